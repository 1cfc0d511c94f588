"""Fig. 2: a 3-RRR platform where the right grounded link is motionless (LIM, DKP with r = 1).

The paper (§III-B-3) gives Fig. 2 as an example of link impossible motion: an equation of
type (5) with r = 1 makes an input null whatever the inputs given, and "the link with fixed
R pair on the right is motionless"; §IV-B-3 detects it as null rows of V and Ω.

The model (fig2_3rrr_lim.toml) has legs 2 and 3 stretched with their lines meeting at C1,
the platform joint of leg 1.  Asserted here: the construction; L = F = 3 (no IM); the
classification; crank1 and distal1 locked (null rows of V at B1 and C1, null row of Ω for
both links); the input relation rotation:crank1 = 0 (r = 1), also from an independent
computation of γ_i = w_i (a_i × d_i); the platform reduced to a rotation about C1
(platform DOF 1, relations v_C1 = 0); and the uncontrolled motion with the inputs locked.
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
    c = Checklist("fig2_3rrr_lim")
    mech = symkin.read_model(HERE / "fig2_3rrr_lim.toml")
    xyz = {n: np.array(p, dtype=float) for n, p in mech.coordinates().items()}

    # ---- the construction ------------------------------------------------------------------
    for k in (2, 3):
        a_, d = xyz[f"B{k}"] - xyz[f"A{k}"], xyz[f"C{k}"] - xyz[f"B{k}"]
        c.equal(f"leg {k} stretched: a_{k} × d_{k} = 0", cross(a_, d), 0.0)
        c.true(f"leg {k} stretched, not folded: a_{k}·d_{k} > 0", float(a_ @ d) > 0, float(a_ @ d))
        c.equal(f"line of leg {k} passes through C1", cross(d, xyz["C1"] - xyz[f"B{k}"]), 0.0)
    a1, d1 = xyz["B1"] - xyz["A1"], xyz["C1"] - xyz["B1"]
    c.equal("leg 1 is not stretched: a_1 × d_1", cross(a1, d1), 5.0)
    c.true("leg 1 is on the right (largest x of the ground pivots)",
           xyz["A1"][0] > max(xyz["A2"][0], xyz["A3"][0]), float(xyz["A1"][0]))

    # ---- the analysis ----------------------------------------------------------------------
    res = symkin.analyze(mech)
    c.record("analysis", res)
    c.equal("instantaneous DOF L = F = 3: no increased mobility", (res.dof, res.mobility), (3, 3))
    c.equal("classification", res.types, ("DKP-input", "DKP-output", "LIM"))
    c.true("crank1 (the right grounded link) is motionless", "crank1" in res.locked_links, res.locked_links)
    c.equal("locked links: crank1 and distal1", res.locked_links, ("crank1", "distal1"))
    c.equal("nodes at rest: B1 and C1", res.locked_nodes, ("B1", "C1"))
    speeds = res.motion.node_speeds()
    c.close("null rows of V at B1 and C1 (largest row norm)", max(speeds["B1"], speeds["C1"]), 0.0, tol=1e-14)
    omega_rows, omega_labels = res.motion.omega()
    for link in ("crank1", "distal1"):
        row = omega_rows[omega_labels.index(f"omega:{link}")]
        c.close(f"null row of Ω for {link}", float(np.linalg.norm(row)), 0.0, tol=1e-14)
    c.true("the platform is not locked", "platform" not in res.locked_links, res.locked_links)

    c.equal("input rank", res.input_rank, 2)
    c.equal("one input relation", len(res.input_relations), 1)
    coef = res.input_relations[0].as_dict() if res.input_relations else {}
    c.equal("relation on rotation:crank1 only (r = 1)", sorted(coef), ["rotation:crank1"])
    c.close("relation 1·ω1 = 0, coefficient", coef.get("rotation:crank1", math.nan), 1.0)
    gamma, s_min = hand_gamma(xyz)
    c.close("the three distal lines are concurrent (σ_min/σ_max of their matrix)", s_min, 0.0, tol=1e-15)
    for k, expected in zip(LEGS, (1.0, 0.0, 0.0)):
        c.close(f"hand γ_{k} (normalised)", float(gamma[k - 1]), expected, tol=1e-12)

    # ---- what the platform can do ----------------------------------------------------------
    c.equal("platform DOF (rotation about C1 only)", res.platform_dof, 1)
    c.equal("output rank", res.output_rank, 1)
    out = [r.as_dict() for r in res.output_relations]
    c.equal("output relations are v_C1 = 0 (twist of the platform at its first node C1)",
            [sorted(r) for r in out], [["twist:platform.vx"], ["twist:platform.vy"]])
    c.true("... with unit coefficients", all(math.isclose(v, 1.0, rel_tol=1e-9) for r in out for v in r.values()),
           out)

    # ---- uncontrolled motion with the inputs locked ------------------------------------------
    c.equal("one uncontrolled motion with the inputs locked", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        mo = res.uncontrolled_motions[0]
        c.equal("it moves the platform", mo.moves_platform, True)
        omega, resid, others = rotation_about(mo, xyz, xyz["C1"], ("C2", "C3"))
        c.close("it is a rotation of the platform about C1: fit residual", resid, 0.0, tol=1e-12)
        c.true("... with non-zero angular velocity", abs(omega) > 0.1, omega)
        c.close("... while B1, C1, B2, B3 stay at rest (largest speed)", others, 0.0, tol=1e-12)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
