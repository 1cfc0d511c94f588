"""Fig. 7 and eqs. (16)-(17): a 3-RRP planar platform in IM whose platform keeps one DOF.

The paper (§IV-B-2) states that in the configuration of Fig. 7 the 3-RRP platform has an
instantaneous DOF of four (F = 3: IM), that choosing the velocity of the upper node i and
the platform's angular velocity as output parameters gives eq. (16),

    {ẋ_i, ẏ_i, ω_z} = [[0, 0, 0, 1], [0, 0, 0, 0], [0, 0, 0, −1.5]] {β},

whose dependencies are eq. (17), 1.5·ẋ_i + ω_z = 0 and ẏ_i = 0, so the platform has only
one DOF, and that only eigenvector 4 of the motion space involves the platform.

The model (fig7_3rrp.toml) has every crank perpendicular to its prismatic line and the
three crank lines concurrent at P, 2/3 below node I.  Asserted here: the construction;
L = 4 > F = 3 with the deciding singular values; the classification; platform DOF 1 and
the two relations of eq. (17) (coefficients to 1e-9); eq. (16) itself, in a basis of the
motion space where the first three vectors leave the platform at rest; the motion space
equal to the span of four motions built by hand (three leg self-motions, one platform
rotation about P); and the uncontrolled motion with the inputs locked.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import symkin
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
#: leg k slides on the platform side (first node, second node)
SIDES = {1: ("J", "K"), 2: ("K", "I"), 3: ("I", "J")}
PAPER_EQ16 = np.array([[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, -1.5]])


def cross(u, v) -> float:
    """z component of the planar cross product."""
    return float(u[0] * v[1] - u[1] * v[0])


def perp(v) -> np.ndarray:
    return np.array([-v[1], v[0]], dtype=float)


def unit(v) -> np.ndarray:
    return np.asarray(v, dtype=float) / np.linalg.norm(v)


def platform_rows(mech, V: np.ndarray) -> np.ndarray:
    """Rows ẋ_I, ẏ_I, ω_z of eq. (16) over the motion-space basis V, by elementary kinematics."""
    idx = mech.node_index()
    xyz = mech.coordinates()
    vi = V[2 * idx["I"]: 2 * idx["I"] + 2]
    vj = V[2 * idx["J"]: 2 * idx["J"] + 2]
    r = np.subtract(xyz["J"], xyz["I"])
    omega = perp(r) @ (vj - vi) / (r @ r)
    return np.vstack([vi, omega[None, :]])


def hand_motions(mech, centre) -> np.ndarray:
    """Four motions (columns, all nodal velocity components) built from the construction.

    Columns 1-3: block k slides along its side, its crank turning, everything else at rest.
    Column 4: the platform turns about ``centre`` with unit angular velocity, the cranks at
    rest and each block turning with the platform about its node B_k.
    """
    idx = mech.node_index()
    xyz = {n: np.array(p, dtype=float) for n, p in mech.coordinates().items()}
    cols = np.zeros((2 * len(idx), 4))

    def put(col, node, v):
        cols[2 * idx[node]: 2 * idx[node] + 2, col] = v

    for k, (p, q) in SIDES.items():
        u = unit(xyz[q] - xyz[p])
        put(k - 1, f"B{k}", u)
        put(k - 1, f"E{k}", u)
        put(3, f"E{k}", perp(xyz[f"E{k}"] - xyz[f"B{k}"]))
    for n in ("I", "J", "K"):
        put(3, n, perp(xyz[n] - centre))
    return cols


def check() -> Checklist:
    c = Checklist("fig7_3rrp")
    mech = symkin.read_model(HERE / "fig7_3rrp.toml")
    xyz = {n: np.array(p, dtype=float) for n, p in mech.coordinates().items()}
    centre = np.zeros(2)  # P, the concurrency point of the crank lines

    # ---- the construction ------------------------------------------------------------------
    for k, (p, q) in SIDES.items():
        u = unit(xyz[q] - xyz[p])
        a = xyz[f"B{k}"] - xyz[f"A{k}"]
        c.close(f"leg {k}: crank perpendicular to its prismatic line (cos of angle)",
                abs(float(u @ a)) / np.linalg.norm(a), 0.0, tol=1e-15)
        c.close(f"leg {k}: crank line passes through P (distance)",
                abs(cross(unit(a), centre - xyz[f"B{k}"])), 0.0, tol=1e-15)
        for n in (f"B{k}", f"E{k}"):
            c.close(f"leg {k}: {n} on side {p}-{q} (distance)", abs(cross(u, xyz[n] - xyz[p])), 0.0, tol=1e-15)
    c.equal("node I directly above P", float(xyz["I"][0] - centre[0]), 0.0)
    c.close("1/|IP| = 1.5 (per length unit)", 1.0 / float(xyz["I"][1] - centre[1]), 1.5, tol=1e-15)

    # ---- the analysis: IM with L = 4 ------------------------------------------------------
    res = symkin.analyze(mech)
    c.record("analysis", res)
    c.equal("instantaneous DOF L = 4", res.dof, 4)
    c.equal("mobility F = 3", res.mobility, 3)
    c.equal("classification: IM, with a DKP in the output", res.types, ("IM", "DKP-output"))
    s = res.motion.singular_values
    c.close("4th smallest singular value of J (a zero: L = 4)", float(s[3]), 0.0, tol=1e-14)
    c.true("5th is of order one (L is not 5)", float(s[4]) > 0.1, float(s[4]))
    c.close("IM indicator λ_{F+1} (eq. 8)", res.im_indicator, 0.0, tol=1e-28)
    c.equal("input rank 3: the inputs stay independent", res.input_rank, 3)
    c.equal("no locked link", res.locked_links, ())

    # ---- eq. (17): the platform's DOF and relations ----------------------------------------
    c.equal("platform DOF (rank of the twist rows)", res.platform_dof, 1)
    c.equal("output rank", res.output_rank, 1)
    for which, rels in (("output", res.output_relations), ("platform", res.platform_relations)):
        got = [r.as_dict() for r in rels]
        c.equal(f"eq. 17 ({which} relations): labels",
                [sorted(r) for r in got],
                [["twist:platform.vx", "twist:platform.wz"], ["twist:platform.vy"]])
        if len(got) == 2:
            c.close(f"eq. 17 ({which}): coefficient of ẋ_i", got[0].get("twist:platform.vx", math.nan), 1.0)
            c.close(f"eq. 17 ({which}): coefficient of ω_z = 1/1.5",
                    got[0].get("twist:platform.wz", math.nan), 1.0 / 1.5)
            c.close(f"eq. 17 ({which}): in the paper's form 1.5·ẋ_i + ω_z = 0, the 1.5",
                    1.0 / got[0].get("twist:platform.wz", math.nan), 1.5)
            c.close(f"eq. 17 ({which}): ẏ_i = 0, coefficient", got[1].get("twist:platform.vy", math.nan), 1.0)

    # ---- eq. (16) in a basis of the motion space whose first three vectors leave the platform at rest
    V = res.motion.V
    m = platform_rows(mech, V)
    _, sm, vt = np.linalg.svd(m)
    c.close("platform rows over V: second singular value (rank 1)", float(sm[1] / sm[0]), 0.0, tol=1e-14)
    if m.shape[1] == PAPER_EQ16.shape[1]:
        basis = np.column_stack([vt[1:].T, vt[0]])  # β-space: null space of the platform rows, then the rest
        m16 = m @ basis
        m16[:, 3] /= m16[0, 3]  # scale eigenvector 4 so that ẋ_i = 1, as printed
        c.close("eq. 16 reproduced in that basis (largest entry error)", float(np.abs(m16 - PAPER_EQ16).max()),
                0.0, tol=1e-12)
    else:
        c.true("eq. 16 reproduced in that basis", False, f"the motion space has {m.shape[1]} vectors, not 4")

    # ---- the motion space against four motions built by hand -------------------------------
    hand = hand_motions(mech, centre)
    resid = max(float(np.linalg.norm(h - V @ (V.T @ h)) / np.linalg.norm(h)) for h in hand.T)
    c.close("hand-built motions lie in the motion space (largest relative residual)", resid, 0.0, tol=1e-14)
    normed = hand / np.linalg.norm(hand, axis=0)
    s_hand = np.linalg.svd(normed, compute_uv=False)
    c.true("... and are independent, so they span it (σ_min of the normalised set)", float(s_hand[-1]) > 0.1,
           float(s_hand[-1]))
    hand_rows = platform_rows(mech, hand)
    c.close("only the 4th hand-built motion moves the platform (largest platform term of 1-3)",
            float(np.abs(hand_rows[:, :3]).max()), 0.0, tol=1e-15)
    c.close("... and for it ω_z/ẋ_i = −1.5", float(hand_rows[2, 3] / hand_rows[0, 3]), -1.5, tol=1e-15)

    # ---- uncontrolled motion with the inputs locked (eq. 11) -------------------------------
    c.equal("one uncontrolled motion with the inputs locked (L − F)", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        mo = res.uncontrolled_motions[0]
        c.equal("it moves the platform", mo.moves_platform, True)
        vel = {n: np.array(v) for n, v in mo.velocities}
        idx = mech.node_index()
        vec = np.zeros(2 * len(idx))
        for n, v in vel.items():
            vec[2 * idx[n]: 2 * idx[n] + 2] = v
        omega = float(hand[:, 3] @ vec / (hand[:, 3] @ hand[:, 3]))
        c.close("it is the platform's rotation about P (relative residual from the hand-built motion)",
                float(np.linalg.norm(vec - omega * hand[:, 3]) / np.linalg.norm(vec)), 0.0, tol=1e-12)
        c.close("... with the elbows B1, B2, B3 at rest (largest speed)",
                max(float(np.linalg.norm(vel[f"B{k}"])) for k in SIDES), 0.0, tol=1e-14)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
