"""The four-bar of the paper's appendix (Fig. 17, eqs. A1-A6) and a dead centre of it.

What the paper states, and what is asserted here:

* Eq. (A3): the geometric matrix of a bar i-j is the 4×4 matrix of cos²θ, cosθ sinθ,
  sin²θ of the bar's angle θ.  Each bar's expanded matrix ḡ_e (eq. 2) is compared entry
  by entry with (A3), the angle taken independently with ``math.atan2``, and
  ``Σ ḡ_e = G`` (eq. 3).
* Eq. (A5): the assembled 8×8 matrix in the paper's node order 1 = B, 2 = C, 3 = D, 4 = A,
  bars 1-2 (coupler, θ), 1-4 (crank, φ), 2-3 (rocker, ψ).  As printed, the entries of bar
  2-3 read φ while eq. (A6) reads ψ there.  Only ψ is consistent: A5 with ψ on bar 2-3
  equals our G to rounding, A5 as printed does not (it would require the rocker parallel to
  the crank, ψ ≡ φ mod π), and A6 as printed equals ``geometric_matrix(boundary=True)``.
* The linkage is a 1-DOF mechanism, non-singular in the file's configuration; its velocity
  ratio agrees with the elementary closure of velocities.
* A dead centre of the SAME linkage (crank and coupler aligned): DKP in the output with
  r = 1 (``rotation:rocker = 0``), the rocker in LIM, L = F = 1; checked against the
  elementary result (v_C = 0, ω_coupler/ω_crank = −|AB|/|BC|).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import symkin
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
#: paper node k+1 -> our node name (node 1 = B, 2 = C, 3 = D, 4 = A)
PAPER_NODES = ("B", "C", "D", "A")
#: our link -> (paper's first node, paper's second node) as the bar is named in the appendix
PAPER_BARS = {"coupler": ("B", "C"), "crank": ("B", "A"), "rocker": ("C", "D")}


def angle(p, q) -> float:
    """Angle of the vector p→q, independently of symkin."""
    return math.atan2(q[1] - p[1], q[0] - p[0])


def a3(t: float) -> np.ndarray:
    """Eq. (A3) as printed, for a bar at angle ``t``."""
    c, s = math.cos(t), math.sin(t)
    return np.array([[c * c, c * s, -c * c, -c * s],
                     [c * s, s * s, -c * s, -s * s],
                     [-c * c, -c * s, c * c, c * s],
                     [-c * s, -s * s, c * s, s * s]])


def a5(theta: float, phi: float, q: float) -> np.ndarray:
    """Eq. (A5) transcribed entry by entry; ``q`` is the angle in the entries of bar 2-3.

    As printed those entries read φ, i.e. the printed matrix is ``a5(θ, φ, φ)``; with the
    rocker's angle it is ``a5(θ, φ, ψ)``.
    """
    ct, st = math.cos(theta), math.sin(theta)
    cf, sf = math.cos(phi), math.sin(phi)
    cq, sq = math.cos(q), math.sin(q)
    return np.array([
        [ct * ct + cf * cf, ct * st + cf * sf, -ct * ct, -ct * st, 0, 0, -cf * cf, -cf * sf],
        [ct * st + cf * sf, st * st + sf * sf, -ct * st, -st * st, 0, 0, -cf * sf, -sf * sf],
        [-ct * ct, -ct * st, ct * ct + cq * cq, ct * st + cq * sq, -cq * cq, -cq * sq, 0, 0],
        [-ct * st, -st * st, ct * st + cq * sq, st * st + sq * sq, -cq * sq, -sq * sq, 0, 0],
        [0, 0, -cq * cq, -cq * sq, cq * cq, cq * sq, 0, 0],
        [0, 0, -cq * sq, -sq * sq, cq * sq, sq * sq, 0, 0],
        [-cf * cf, -cf * sf, 0, 0, 0, 0, cf * cf, cf * sf],
        [-cf * sf, -sf * sf, 0, 0, 0, 0, cf * sf, sf * sf]], dtype=float)


def a6(theta: float, phi: float, psi: float) -> np.ndarray:
    """Eq. (A6) transcribed entry by entry (fixed nodes 3, 4 as identity rows and columns)."""
    ct, st = math.cos(theta), math.sin(theta)
    cf, sf = math.cos(phi), math.sin(phi)
    cp, sp = math.cos(psi), math.sin(psi)
    m = np.eye(8)
    m[:4, :4] = [[ct * ct + cf * cf, ct * st + cf * sf, -ct * ct, -ct * st],
                 [ct * st + cf * sf, st * st + sf * sf, -ct * st, -st * st],
                 [-ct * ct, -ct * st, ct * ct + cp * cp, ct * st + cp * sp],
                 [-ct * st, -st * st, ct * st + cp * sp, st * st + sp * sp]]
    return m


def paper_permutation(mech) -> list[int]:
    """Our coordinate indices in the paper's order x1, y1, ..., x4, y4."""
    idx = mech.node_index()
    return [2 * idx[n] + k for n in PAPER_NODES for k in (0, 1)]


def perp(v) -> np.ndarray:
    return np.array([-v[1], v[0]], dtype=float)


def hand_velocities(xyz: dict, omega_crank: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Velocities of B and C by elementary closure: v_B = ω × AB, then v_C from the bars.

    v_C·u_BC = v_B·u_BC (coupler rigid) and v_C·u_DC = 0 (rocker about D).
    """
    a, b, c, d = (np.array(xyz[n], dtype=float) for n in "ABCD")
    v_b = omega_crank * perp(b - a)
    u_bc = (c - b) / np.linalg.norm(c - b)
    u_dc = (c - d) / np.linalg.norm(c - d)
    v_c = np.linalg.solve(np.array([u_bc, u_dc]), np.array([v_b @ u_bc, 0.0]))
    return v_b, v_c


def omegas_from_motion(mech, v: np.ndarray) -> dict[str, float]:
    """Angular velocities of the three moving links from one motion vector (node order)."""
    xyz = {n: np.array(p, dtype=float) for n, p in mech.coordinates().items()}
    idx = mech.node_index()
    vel = {n: v[2 * idx[n]: 2 * idx[n] + 2] for n in idx}
    out = {}
    for link, (i, j) in (("crank", "AB"), ("coupler", "BC"), ("rocker", "DC")):
        r = xyz[j] - xyz[i]
        out[link] = float(perp(r) @ (vel[j] - vel[i]) / (r @ r))
    return out


def check() -> Checklist:
    c = Checklist("fourbar_appendix")
    mech = symkin.read_model(HERE / "fourbar_appendix.toml")
    xyz = mech.coordinates()
    idx = mech.node_index()

    # ---- eq. (A3), element by element, and eq. (3) ------------------------------------------
    rows = constraint_rows(mech)
    g_sum = np.zeros((8, 8))
    for link, (p, q) in PAPER_BARS.items():
        owned = [k for k, o in enumerate(rows.owners) if o.startswith(f"link {link} ")]
        c.equal(f"bar {link}: one constraint row (a bar)", len(owned), 1)
        row = rows.matrix[owned[0]]
        g_e = np.outer(row, row)  # expanded element matrix ḡ_e of eq. (2)
        g_sum += g_e
        cols = [2 * idx[p], 2 * idx[p] + 1, 2 * idx[q], 2 * idx[q] + 1]
        t = angle(xyz[p], xyz[q])
        c.close(f"eq. A3, bar {link} ({p}-{q}, angle {math.degrees(t):.4f}°): max entry error",
                float(np.abs(g_e[np.ix_(cols, cols)] - a3(t)).max()), 0.0, tol=1e-15)
        outside = g_e.copy()
        outside[np.ix_(cols, cols)] = 0.0
        c.equal(f"eq. 2, bar {link}: ḡ_e is zero outside the bar's rows and columns",
                float(np.abs(outside).max()), 0.0)
    g = symkin.geometric_matrix(mech)
    c.close("eq. 3: G = Σ ḡ_e (max entry error)", float(np.abs(g - g_sum).max()), 0.0, tol=1e-15)

    # ---- eqs. (A5) and (A6) in the paper's node order ---------------------------------------
    theta = angle(xyz["B"], xyz["C"])  # bar 1-2, coupler
    phi = angle(xyz["B"], xyz["A"])    # bar 1-4, crank
    psi = angle(xyz["C"], xyz["D"])    # bar 2-3, rocker
    perm = paper_permutation(mech)
    g_paper = g[np.ix_(perm, perm)]
    c.close("eq. A5 with the rocker angle ψ on bar 2-3 equals G (max entry error)",
            float(np.abs(g_paper - a5(theta, phi, psi)).max()), 0.0, tol=1e-15)
    printed_gap = float(np.abs(g_paper - a5(theta, phi, phi)).max())
    c.true("eq. A5 as printed (φ on bar 2-3) differs from G: misprint", printed_gap > 0.1,
           f"max entry difference {printed_gap:.6f}")
    c.true("... it would hold only with the rocker parallel to the crank (ψ ≡ φ mod π)",
           abs(math.sin(psi - phi)) > 0.1, f"|sin(ψ − φ)| = {abs(math.sin(psi - phi)):.6f}")
    g_bc = symkin.geometric_matrix(mech, boundary=True)[np.ix_(perm, perm)]
    c.close("eq. A6 as printed (ψ on bar 2-3) equals geometric_matrix(boundary=True)",
            float(np.abs(g_bc - a6(theta, phi, psi)).max()), 0.0, tol=1e-15)
    c.close("A6's free block equals A5 with ψ on bar 2-3 (A6 is the consistent one)",
            float(np.abs(a6(theta, phi, psi)[:4, :4] - a5(theta, phi, psi)[:4, :4]).max()), 0.0,
            tol=1e-15)
    gap = float(np.abs(a6(theta, phi, psi)[:4, :4] - a5(theta, phi, phi)[:4, :4]).max())
    c.true("A6's free block differs from A5 as printed (entries of node 2: c²θ + c²ψ vs c²θ + c²φ)",
           gap > 0.1, f"max entry difference {gap:.6f}")

    # ---- the generic configuration: 1 DOF, no singularity -----------------------------------
    res = symkin.analyze(mech)
    c.record("generic", res)
    c.equal("generic configuration: DOF L", res.dof, 1)
    c.equal("generic configuration: mobility F", res.mobility, 1)
    c.equal("generic configuration: no singularity", res.types, ())
    c.equal("generic configuration: input rank", res.input_rank, 1)
    c.equal("generic configuration: output rank", res.output_rank, 1)
    c.true("generic configuration: IM indicator λ₂ well above zero", res.im_indicator > 1e-3,
           res.im_indicator)
    _, v_c = hand_velocities(xyz)
    w = omegas_from_motion(mech, res.motion.V[:, 0])
    d_c = np.subtract(xyz["C"], xyz["D"])
    ratio_hand = float(perp(d_c) @ v_c / (d_c @ d_c))  # ω_rocker for ω_crank = 1
    c.close("generic: ω_rocker/ω_crank from the motion space = elementary closure",
            w["rocker"] / w["crank"], ratio_hand, tol=1e-12)

    # ---- the dead centre of the same linkage -------------------------------------------------
    dead = symkin.read_model(HERE / "fourbar_appendix_dead_centre.toml")
    dx = dead.coordinates()
    for link, (p, q) in (("crank", "AB"), ("coupler", "BC"), ("rocker", "DC"), ("ground", "AD")):
        c.close(f"dead centre: |{p}{q}| ({link}) equals the generic file's",
                math.dist(dx[p], dx[q]), math.dist(xyz[p], xyz[q]), tol=1e-15)
    ab, bc = np.subtract(dx["B"], dx["A"]), np.subtract(dx["C"], dx["B"])
    c.close("dead centre: crank and coupler aligned, sin of their angle",
            float(abs(ab[0] * bc[1] - ab[1] * bc[0]) / (np.linalg.norm(ab) * np.linalg.norm(bc))),
            0.0, tol=1e-15)
    c.true("dead centre: aligned the same way (extended, not folded)", float(ab @ bc) > 0)

    dres = symkin.analyze(dead)
    c.record("dead_centre", dres)
    c.equal("dead centre: DOF L = F = 1 (no IM)", (dres.dof, dres.mobility), (1, 1))
    c.equal("dead centre: types", dres.types, ("DKP-output", "LIM"))
    c.equal("dead centre: input rank (the crank still drives)", dres.input_rank, 1)
    c.equal("dead centre: output rank", dres.output_rank, 0)
    c.equal("dead centre: one output relation", len(dres.output_relations), 1)
    rel = dres.output_relations[0].as_dict() if dres.output_relations else {}
    c.equal("dead centre: the relation is on rotation:rocker only (r = 1)", sorted(rel), ["rotation:rocker"])
    c.close("dead centre: relation 1·ω_rocker = 0, coefficient", rel.get("rotation:rocker", math.nan), 1.0)
    c.equal("dead centre: no input relation", dres.input_relations, ())
    c.equal("dead centre: rocker in LIM", dres.locked_links, ("rocker",))
    c.equal("dead centre: locked node (rocker tip)", dres.locked_nodes, ("C",))
    c.equal("dead centre: no uncontrolled motion with the crank locked", dres.uncontrolled_motions, ())
    m_out, _, _ = dres.motion.restrict(dead.outputs)
    c.close("dead centre: |rocker row restricted to the motion space| (the deciding number)",
            float(np.linalg.norm(m_out)), 0.0, tol=1e-14)
    c.true("... while in the generic configuration it is of order one",
           float(np.linalg.norm(res.motion.restrict(mech.outputs)[0])) > 0.1,
           float(np.linalg.norm(res.motion.restrict(mech.outputs)[0])))
    _, hv_c = hand_velocities(dx)
    c.close("dead centre, elementary closure: |v_C| for ω_crank = 1", float(np.linalg.norm(hv_c)), 0.0,
            tol=1e-14)
    dw = omegas_from_motion(dead, dres.motion.V[:, 0])
    a_len, b_len = math.dist(dx["A"], dx["B"]), math.dist(dx["B"], dx["C"])
    c.close("dead centre: ω_coupler/ω_crank = −|AB|/|BC| (coupler turns about C)",
            dw["coupler"] / dw["crank"], -a_len / b_len, tol=1e-12)
    c.close("dead centre: ω_rocker/ω_crank from the motion space", dw["rocker"] / dw["crank"], 0.0,
            tol=1e-14)

    # ---- why no DKP-input dead centre exists for these lengths --------------------------------
    a, b = math.dist(xyz["A"], xyz["B"]), math.dist(xyz["B"], xyz["C"])
    cr, d = math.dist(xyz["D"], xyz["C"]), math.dist(xyz["A"], xyz["D"])
    c.true("Grashof crank-rocker: crank shortest and a + d < b + c",
           a == min(a, b, cr, d) and a + d < b + cr, f"a + d = {a + d:.6f}, b + c = {b + cr:.6f}")
    c.true("coupler-rocker alignment unreachable: |BD| ∈ [d − a, d + a] excludes b + c and |b − c|",
           b + cr > d + a and abs(b - cr) < d - a,
           f"[{d - a:.6f}, {d + a:.6f}] vs {b + cr:.6f}, {abs(b - cr):.6f}")
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
