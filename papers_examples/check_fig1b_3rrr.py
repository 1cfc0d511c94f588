"""Fig. 1(b), eq. (7): a 3-RRR platform in a DKP-input configuration with r = 2 < F.

The paper states that in the configuration of Fig. 1(b) the angular velocities of links 1
and 2 (with fixed R pairs) obey ω1 − ω2 = 0 (eq. 7): eq. (5) with r = 2 < F = 3, the
coefficient of ω3 being null (§IV-B-1).

The model (fig1b_3rrr.toml) has distal links 1 and 2 on one line ℓ and the ground pivots
A1, A2 at the same distance from ℓ on the same side.  Asserted here: the construction;
L = F = 3 and the classification; input rank 2; the single relation, exactly
{crank1: 1, crank2: −1} with no ω3 term, from symkin and from an independent computation
(γ_i = w_i (a_i × d_i), and the closed form γ_i ∝ (a_i × u)); the deciding singular value;
and the uncontrolled motion, a rotation of the platform about the intersection of ℓ with
distal line 3 while the elbows stay at rest.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

import symkin
from symkin.reproduce import Checklist

sys.path.insert(0, str(Path(__file__).resolve().parent))
from planar_rrr_geometry import LEGS, cross, hand_gamma, rotation_about  # noqa: E402

HERE = Path(__file__).resolve().parent


def line_intersection(p, u, q, v) -> np.ndarray:
    """Intersection of the lines p + s u and q + t v."""
    s, _ = np.linalg.solve(np.array([u, -np.asarray(v)]).T, np.subtract(q, p))
    return np.asarray(p, dtype=float) + s * np.asarray(u, dtype=float)


def check() -> Checklist:
    c = Checklist("fig1b_3rrr")
    mech = symkin.read_model(HERE / "fig1b_3rrr.toml")
    xyz = {n: np.array(p, dtype=float) for n, p in mech.coordinates().items()}

    # ---- the construction ------------------------------------------------------------------
    u = (xyz["B2"] - xyz["B1"]) / np.linalg.norm(xyz["B2"] - xyz["B1"])
    off = max(abs(cross(u, xyz[n] - xyz["B1"])) for n in ("C1", "C2"))
    c.equal("distal links 1 and 2 on one line ℓ (largest distance of C1, C2 from B1-B2)", off, 0.0)
    dist_a = [cross(u, xyz[f"A{k}"] - xyz["B1"]) for k in (1, 2)]
    c.equal("A1 and A2 at the same signed distance from ℓ", dist_a[0], dist_a[1])
    lengths = (math.dist(xyz["A1"], xyz["B1"]), math.dist(xyz["A2"], xyz["B2"]))
    c.true("the two cranks differ (lengths)", abs(lengths[0] - lengths[1]) > 0.1, lengths)

    # ---- the analysis ----------------------------------------------------------------------
    res = symkin.analyze(mech)
    c.record("analysis", res)
    c.equal("instantaneous DOF L", res.dof, 3)
    c.equal("mobility F", res.mobility, 3)
    c.equal("classification: DKP in the input only (no IM, no LIM)", res.types, ("DKP-input",))
    c.equal("input rank (eq. 12)", res.input_rank, 2)
    c.equal("output rank (platform twist)", res.output_rank, 3)
    c.equal("no locked link", res.locked_links, ())
    c.equal("one input relation", len(res.input_relations), 1)
    rel = res.input_relations[0] if res.input_relations else None
    coef = rel.as_dict() if rel else {}
    c.equal("eq. 7 relates two inputs, r = 2 < F (no ω3 term)", sorted(coef),
            ["rotation:crank1", "rotation:crank2"])
    c.close("eq. 7: coefficient of rotation:crank1", coef.get("rotation:crank1", math.nan), 1.0)
    c.close("eq. 7: coefficient of rotation:crank2", coef.get("rotation:crank2", math.nan), -1.0)

    # ---- independent: γ from equilibrium weights, and the closed form (a_i × u) -------------
    gamma, s_min = hand_gamma(xyz)
    c.close("equilibrium of distal lines 1, 2 exists (σ_min/σ_max)", s_min, 0.0, tol=1e-15)
    for k, expected in zip(LEGS, (1.0, -1.0, 0.0)):
        c.close(f"hand γ_{k} (normalised)", float(gamma[k - 1]), expected, tol=1e-12)
    closed = [cross(xyz[f"B{k}"] - xyz[f"A{k}"], u) for k in (1, 2)]
    c.close("closed form γ2/γ1 = −(a_2 × u)/(a_1 × u)", -closed[1] / closed[0], -1.0, tol=1e-15)

    # ---- the deciding number ---------------------------------------------------------------
    m_in, _, _ = res.motion.restrict(mech.inputs)
    s_in = np.linalg.svd(m_in, compute_uv=False)
    c.close("smallest singular value of the input rows restricted to V", float(s_in[-1]), 0.0, tol=1e-14)
    c.true("... and the next one is of order one", float(s_in[-2]) > 0.1, float(s_in[-2]))

    # ---- uncontrolled motion: platform turns about ℓ ∩ (distal line 3) ----------------------
    centre = line_intersection(xyz["B1"], u, xyz["B3"], xyz["C3"] - xyz["B3"])
    c.close("ℓ meets distal line 3 at x = −2/3", float(centre[0]), -2.0 / 3.0, tol=1e-15)
    c.equal("one uncontrolled motion with the inputs locked", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        mo = res.uncontrolled_motions[0]
        c.equal("it moves the platform (and the outputs)", (mo.moves_platform, mo.moves_outputs), (True, True))
        omega, resid, others = rotation_about(mo, xyz, centre, ("C1", "C2", "C3"))
        c.close("it is a rotation of the platform about ℓ ∩ distal line 3: fit residual", resid, 0.0,
                tol=1e-12)
        c.true("... with non-zero angular velocity", abs(omega) > 0.1, omega)
        c.close("... while the elbows B1, B2, B3 stay at rest (largest speed)", others, 0.0, tol=1e-12)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
