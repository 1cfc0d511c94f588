"""Fig. 7 and eqs. (16)-(17), the 3-RRP platform written by its joints (``fig7_3rrp_joints.toml``).

The planar P between the platform and each block compiles to two moving-line sliders of the
block on the platform side, as the node file ``fig7_3rrp.toml`` has them by hand.  Asserted: the
compiled sliders lie on the sides of the node file; the analysis equals the node file's (L = 4 > F
= 3: IM, types, ranks, platform DOF 1, statics) and the platform relations are eq. (17),
ẋ_i + (2/3)·ω_z = 0 (i.e. 1.5·ẋ_i + ω_z = 0) and ẏ_i = 0, to 1e-9; the inputs are the joint rates
of the ground pivots (``joint:A1`` ...).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import symkin
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent


def check() -> Checklist:
    c = Checklist("fig7_3rrp_joints")
    joint = symkin.read_model(HERE / "fig7_3rrp_joints.toml")
    node = symkin.read_model(HERE / "fig7_3rrp.toml")
    sides = {1: ("J", "K"), 2: ("K", "I"), 3: ("I", "J")}
    xyz = joint.coordinates()
    for k in (1, 2, 3):
        s = joint.slider(f"P{k}")
        c.equal(f"P{k}: a slider of block{k} on a moving line of the platform", (s.link, s.node), ("platform", f"B{k}"))
    for k, (p, q) in sides.items():
        u = np.subtract(xyz[q], xyz[p])
        off = max(abs(float(u[0] * (xyz[n][1] - xyz[p][1]) - u[1] * (xyz[n][0] - xyz[p][0]))) / float(np.linalg.norm(u))
                  for n in joint.slider(f"P{k}").line + (f"P{k}.end",))
        c.true(f"P{k}: its line points and block node P{k}.end lie on side {p}-{q}", off < 1e-12, off)
    c.equal("inputs are the joint rates of the ground pivots", [p.labels(2)[0] for p in joint.inputs],
            ["joint:A1", "joint:A2", "joint:A3"])
    a, b = symkin.analyze(joint), symkin.analyze(node)
    c.record("Fig. 7 by its joints", a)
    c.equal("L, F, types, ranks and platform DOF as the node file",
            (a.dof, a.mobility, a.types, a.input_rank, a.output_rank, a.platform_dof),
            (b.dof, b.mobility, b.types, b.input_rank, b.output_rank, b.platform_dof))
    c.equal("L = 4 > F = 3 (IM) and platform DOF 1", (a.dof, a.mobility, "IM" in a.types, a.platform_dof),
            (4, 3, True, 1))
    c.equal("redundant constraints as the node file", a.redundant_constraints, b.redundant_constraints)
    rel = [r.as_dict() for r in a.platform_relations]
    c.equal("two platform relations (eq. 17)", len(rel), 2)
    first = next((r for r in rel if "twist:platform.wz" in r), {})
    c.close("eq. (17): ẋ_i + (2/3)·ω_z = 0", first.get("twist:platform.wz", float("nan")), 2.0 / 3.0)
    c.equal("eq. (17): ẏ_i = 0", {"twist:platform.vy": 1.0} in rel, True)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
