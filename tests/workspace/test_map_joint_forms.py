"""A mechanism written by its joints maps as its node form (issue 16: "the same map curves").

``symkin.workspace_map`` of the node form and of the joint form (``tests/model/joint_forms.py``)
over the same box: the same number of traced curves of each kind, the same special points, and
the same curves as point sets: every traced point of one form is within a small fraction of the
model's length scale of a traced curve of the same kind of the other (the symmetric, Hausdorff,
distance from points to polylines; the two forms sample the curves at different points, and a
chord between samples leaves the curve by at most ~ step² × curvature).  Five-bar and 3-RPR; the
Gough–Stewart constant-orientation slice of tests/workspace/test_map_truth.py (slow: the 6-UPS
joint form has more than twice the node form's coordinates, and its map kernels take minutes to build).
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from tests.model import joint_forms as jf
from tests.workspace import test_map_truth as MT

#: the largest point-to-curve distance between the forms' curves, over the model's length scale: the
#: chords of the two samplings (steps ~ 0.1 of the length scale, curvature ~ 1) leave the curve by up
#: to ~ 3e-3 (measured: five-bar 0 — the same samples —, 3-RPR 2.5e-3); two different curves of these
#: maps are further apart than a grid cell (> 0.1)
SAME_CURVE = 1e-2


def _kinds(wmap) -> dict:
    out: dict = {}
    for c in wmap.curves:
        out[str(c.kind)] = out.get(str(c.kind), 0) + 1
    return out


def _hausdorff(a, b, kind: str) -> float:
    """Symmetric distance between the traced curves of ``kind`` of maps ``a`` and ``b``."""
    ca = [np.asarray(c.points, float) for c in a.curves if c.kind == kind]
    cb = [np.asarray(c.points, float) for c in b.curves if c.kind == kind]
    one = max(MT._nearest(p, cb) for c in ca for p in c)
    other = max(MT._nearest(p, ca) for c in cb for p in c)
    return max(one, other)


def _compare(node: symkin.Mechanism, joint: symkin.Mechanism, **kw) -> dict:
    a, b = symkin.workspace_map(node, **kw), symkin.workspace_map(joint, **kw)
    kinds = _kinds(a)
    assert kinds and kinds == _kinds(b)
    assert sorted(str(p.kind) for p in a.points) == sorted(str(p.kind) for p in b.points)
    for pa, pb in zip(sorted(a.points, key=lambda p: tuple(p.at)), sorted(b.points, key=lambda p: tuple(p.at))):
        assert np.linalg.norm(np.subtract(pa.at, pb.at)) < SAME_CURVE * node.length_scale
    for kind in kinds:
        gap = _hausdorff(a, b, kind) / node.length_scale
        print(f"{node.name}: {kind} curves {gap:.3g} apart (length scale)")
        assert gap < SAME_CURVE, kind
    assert np.array_equal(np.asarray(a.modes[0].assembled), np.asarray(b.modes[0].assembled))
    return kinds


def test_five_bar_map_by_its_joints():
    node = MT._five_bar(MT.FB, (0.3, 2.4), (1, -1))
    joint = symkin.Mechanism.from_dict(jf.five_bar(node.coordinates()))
    kinds = _compare(node, joint, x="velocity:P.x=-3.0:3.0", y="velocity:P.y=0.2:3.6", n=(25, 15), refine=True)
    assert kinds["DKP-input"] >= 1 and kinds["DKP-output"] >= 1


def test_rpr_map_by_its_joints():
    node = symkin.read_model(jf.MODELS / "rpr_3.toml")
    joint = symkin.Mechanism.from_dict(jf.rpr_3(node.coordinates()))
    kinds = _compare(node, joint, x="velocity:O.x=1.5:4.5", y="velocity:O.y=0.75:3.25", n=(16, 13),
                     hold=("rotation:platform",), refine=True)
    assert kinds == {"DKP-input": 1}


@pytest.mark.slow
def test_gough_stewart_constant_orientation_map_by_its_joints():
    node = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    joint = symkin.Mechanism.from_dict(jf.ups_6(node.coordinates()))
    kinds = _compare(node, joint, x="velocity:O.x=-0.75:1.25", y="velocity:O.y=-1.0:1.0", n=(7, 7),
                     hold=MT.GS_HOLD_ORIENTATION, refine=True)
    assert kinds == {"DKP-input": 1}
