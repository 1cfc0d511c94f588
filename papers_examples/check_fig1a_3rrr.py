"""Fig. 1(a), eq. (6): a 3-RRR platform in a DKP-input configuration with r = F = 3.

The paper states that in the configuration of Fig. 1(a) the three links with fixed R pairs
(the inputs) obey ω1 + ω2 + ω3 = 0 (eq. 6), an instance of eq. (5) with r = F: a DKP in
the input (§III-B-1), found as the rank deficiency of the input rows of Ω (eqs. 12-13),
with an uncontrolled motion when the inputs are locked (eq. 14).

The model (fig1a_3rrr.toml) is 3-fold symmetric with the distal lines concurrent at the
platform centre O.  Asserted here: the construction (concurrency, symmetric lengths);
L = F = 3 (no IM) and the classification; input rank 2; the single relation, exactly
{crank1: 1, crank2: 1, crank3: 1}, both from symkin and from an independent computation
γ_i = w_i (a_i × d_i) with w the equilibrium weights of forces along the distal lines;
the deciding singular value; and the uncontrolled motion, a rotation of the platform
about O with the cranks at rest.
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


def check() -> Checklist:
    c = Checklist("fig1a_3rrr")
    mech = symkin.read_model(HERE / "fig1a_3rrr.toml")
    xyz = mech.coordinates()
    origin = np.zeros(2)

    # ---- the construction ------------------------------------------------------------------
    for k in LEGS:
        b_, c_ = np.array(xyz[f"B{k}"]), np.array(xyz[f"C{k}"])
        d = c_ - b_
        c.close(f"distal line {k} passes through O (distance)", abs(cross(d, origin - b_)) / np.linalg.norm(d),
                0.0, tol=1e-15)
        c.close(f"leg {k}: crank length 2", math.dist(xyz[f"A{k}"], xyz[f"B{k}"]), 2.0, tol=1e-15)
        c.close(f"leg {k}: distal length 2", math.dist(xyz[f"B{k}"], xyz[f"C{k}"]), 2.0, tol=1e-15)
        c.close(f"leg {k}: platform joint at radius 1", math.dist(xyz[f"C{k}"], origin), 1.0, tol=1e-15)

    # ---- the analysis ----------------------------------------------------------------------
    res = symkin.analyze(mech)
    c.record("analysis", res)
    c.equal("instantaneous DOF L", res.dof, 3)
    c.equal("mobility F", res.mobility, 3)
    c.equal("classification: DKP in the input only (no IM, no LIM)", res.types, ("DKP-input",))
    c.equal("input rank (eq. 12)", res.input_rank, 2)
    c.equal("output rank (platform twist)", res.output_rank, 3)
    c.equal("platform DOF", res.platform_dof, 3)
    c.equal("no locked link", res.locked_links, ())
    c.equal("one input relation (eq. 13)", len(res.input_relations), 1)
    rel = res.input_relations[0] if res.input_relations else None
    coef = rel.as_dict() if rel else {}
    c.equal("eq. 6 relates the three inputs: r = F = 3", rel.r if rel else 0, 3)
    for k in LEGS:
        c.close(f"eq. 6: coefficient of rotation:crank{k}", coef.get(f"rotation:crank{k}", math.nan), 1.0)

    # ---- independent: γ_i = w_i (a_i × d_i) -----------------------------------------------
    gamma, s_min = hand_gamma(xyz)
    c.close("equilibrium of the distal-line forces exists (σ_min/σ_max of their matrix)", s_min, 0.0,
            tol=1e-15)
    for k in LEGS:
        c.close(f"hand γ_{k} (normalised) = 1", float(gamma[k - 1]), 1.0, tol=1e-12)
        c.close(f"symkin's γ_{k} = hand γ_{k}", coef.get(f"rotation:crank{k}", math.nan),
                float(gamma[k - 1]), tol=1e-12)

    # ---- the deciding number: smallest singular value of the input rows (eq. 12) ------------
    m_in, _, _ = res.motion.restrict(mech.inputs)
    s_in = np.linalg.svd(m_in, compute_uv=False)
    c.close("smallest singular value of the input rows restricted to V", float(s_in[-1]), 0.0, tol=1e-14)
    c.true("... and the next one is of order one", float(s_in[-2]) > 0.1, float(s_in[-2]))

    # ---- the uncontrolled motion with the inputs locked (eq. 14) ---------------------------
    c.equal("one uncontrolled motion with the inputs locked", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        mo = res.uncontrolled_motions[0]
        c.equal("it moves the platform (and the outputs)", (mo.moves_platform, mo.moves_outputs), (True, True))
        omega, resid, others = rotation_about(mo, xyz, origin, ("C1", "C2", "C3"))
        c.close("it is a rotation of the platform about O: fit residual", resid, 0.0, tol=1e-12)
        c.true("... with non-zero angular velocity", abs(omega) > 0.1, omega)
        c.close("... while the elbows B1, B2, B3 stay at rest (largest speed)", others, 0.0, tol=1e-12)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
