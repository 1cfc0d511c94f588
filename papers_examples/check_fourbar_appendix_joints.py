"""The appendix four-bar written by its joints (``[[joints]]``) is the appendix four-bar.

Asserted: the joints compile to the node file's nodes, fixed nodes and links (a planar R is a
node shared by two links); the analysis equals the node file's (L = F = 1, no singularity,
ranks, the velocity ratio ω_rocker/ω_crank from the elementary velocity closure); at the dead
centre of ``fourbar_appendix_dead_centre.toml`` the joint form is singular in the output with
the relation ``joint:D = 0`` (the rocker at rest, LIM), as the paper's A-matrix analysis says.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import symkin
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent


def omega_ratio(xyz) -> float:
    """ω_rocker/ω_crank from the velocity closure v_B + ω_cp × (C − B) = ω_r × (C − D)."""
    a, b, c, d = (np.array(xyz[n], float) for n in "ABCD")
    perp = lambda v: np.array([-v[1], v[0]])
    # unknowns ω_cp, ω_r with ω_crank = 1: ω_cp perp(C−B) − ω_r perp(C−D) = −perp(B−A)
    m = np.column_stack([perp(c - b), -perp(c - d)])
    return float(np.linalg.solve(m, -perp(b - a))[1])


def check() -> Checklist:
    c = Checklist("fourbar_appendix_joints")
    joint = symkin.read_model(HERE / "fourbar_appendix_joints.toml")
    node = symkin.read_model(HERE / "fourbar_appendix.toml")
    c.equal("the joints compile to the node file's nodes", joint.coordinates(), node.coordinates())
    c.equal("... its fixed nodes", set(joint.fixed), set(node.fixed))
    c.equal("... and its links (as node sets)", {k: frozenset(v) for k, v in joint.links},
            {k: frozenset(v) for k, v in node.links})
    c.equal("labels of the joint rates", (joint.inputs[0].labels(2), joint.outputs[0].labels(2)),
            (("joint:A",), ("joint:D",)))
    a, b = symkin.analyze(joint), symkin.analyze(node)
    c.record("generic", a)
    c.equal("L = F = 1 and no singularity, as the node file",
            (a.dof, a.mobility, a.types, a.input_rank, a.output_rank),
            (b.dof, b.mobility, b.types, b.input_rank, b.output_rank))
    v = a.motion.V[:, 0]
    idx = joint.node_index()
    xyz = joint.coordinates()
    rows = {}
    for name, link, tip in (("crank", "A", "B"), ("rocker", "D", "C")):
        r = np.subtract(xyz[tip], xyz[link])
        vt = v[2 * idx[tip]: 2 * idx[tip] + 2]
        rows[name] = float(np.array([-r[1], r[0]]) @ vt / (r @ r))
    c.close("ω_rocker/ω_crank of the motion space = the velocity closure", rows["rocker"] / rows["crank"],
            omega_ratio(xyz), tol=1e-9)
    dead = symkin.read_model(HERE / "fourbar_appendix_dead_centre.toml")
    at = joint.with_coordinates(dead.coordinates())
    d, e = symkin.analyze(at), symkin.analyze(dead)
    c.record("dead centre", d)
    c.equal("at the dead centre: the node file's types, ranks and locked links",
            (d.types, d.dof, d.input_rank, d.output_rank, d.locked_links),
            (e.types, e.dof, e.input_rank, e.output_rank, e.locked_links))
    c.equal("the output relation joint:D = 0 (the rocker at rest)",
            [r.as_dict() for r in d.output_relations], [{"joint:D": 1.0}])
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
