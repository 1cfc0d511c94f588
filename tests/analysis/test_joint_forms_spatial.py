"""Spatial mechanisms written by their joints analyse as their node forms (issue 16, "checks that assert").

* Delta 3-R(SS)² (node form: ``tests/workspace/truth.Delta``): R to ground, four S per leg; at a
  regular pose and on its type-2 locus (the bar directions coplanar, truth's determinant bisected
  to zero) and on its reach limit (an arm and its bars in one plane, truth's reach margin zero).
* 3-RPS (Lee & Shah 1988; node and joint forms in ``tests/model/joint_forms.py``): R to ground
  with the axis tangent to the base circle, P along the leg, S at the platform.  DOF 3 by
  Grübler–Kutzbach (8 links, 3 R, 3 P, 3 S: 6 (8 − 1 − 9) + 3 + 3 + 9 = 3) at a regular pose;
  type 2 where the six wrench lines that hold the platform with the legs locked (the leg lines
  and, through each platform joint, the line along its R axis) are dependent: a 6×6 Plücker
  determinant, bisected to zero over the platform's tilt.

Same DOF, types, ranks, platform DOF and relation coefficients in both forms (``_same``).
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from tests.analysis.test_joint_forms import _same
from tests.model import joint_forms as jf
from tests.workspace import truth as T

DELTA = T.Delta()
KNEE = (1, 1, -1)
Z = -2.2


def _delta(p) -> tuple[symkin.Mechanism, symkin.Mechanism]:
    node = symkin.Mechanism.from_dict(DELTA.model(np.asarray(p, float), KNEE))
    return node, symkin.Mechanism.from_dict(jf.delta(node.coordinates()))


def test_delta_regular_pose():
    p = [0.1, -0.2, Z]
    assert abs(DELTA.type2_det(p, KNEE)) > 1e-2 and DELTA.reach_margin(p) > 1e-2
    node, joint = _delta(p)
    a = symkin.analyze(node)
    assert (a.dof, a.types, a.input_rank, a.output_rank) == (3, (), 3, 3)
    _same(node, joint)


def test_delta_on_its_type_2_locus():
    """On the x axis of the slice z = −2.2 the determinant of the bar directions changes sign (the
    map's type-2 curve, tests/workspace/test_map_delta.py): bisected to zero, both forms DKP-input."""
    xs = np.linspace(-1.4, 1.4, 57)
    f = [DELTA.type2_det([x, 0.0, Z], KNEE) if DELTA.reach_margin([x, 0.0, Z]) > 0 else np.nan for x in xs]
    k = next(i for i in range(len(xs) - 1) if f[i] * f[i + 1] < 0)
    x = T.bisect_root(lambda v: DELTA.type2_det([v, 0.0, Z], KNEE), xs[k], xs[k + 1])
    p = [x, 0.0, Z]
    assert abs(DELTA.type2_det(p, KNEE)) < 1e-12
    node, joint = _delta(p)
    a = symkin.analyze(node)
    assert (a.dof, a.types, a.input_rank, a.output_rank) == (3, ("DKP-input",), 2, 3)
    _same(node, joint)


def test_delta_on_its_reach_limit():
    """Leg 1 stretched (arm and bars in one line: the platform joint at la + lb from the arm's axis
    point): the arm can move with the platform held, DKP-output.  Built exactly: arm 1 at θ = 2.3, the platform where its
    bars continue the arm; legs 2 and 3 by the closed form."""
    u, t = DELTA.frames()
    ez = np.array([0.0, 0.0, 1.0])
    theta = 2.3
    arm = np.cos(theta) * u[0] - np.sin(theta) * ez
    p = (DELTA.radius - DELTA.platform) * u[0] + (DELTA.arm + DELTA.bar) * arm
    assert abs(DELTA.reach_margin(p)) < 1e-12 and np.all(np.isfinite(DELTA.angles(p, KNEE)[1:]))
    data = DELTA.model(p, KNEE)
    b = DELTA.radius * u[0] + DELTA.arm * arm
    data["nodes"]["B1a"], data["nodes"]["B1b"] = list(b - 0.5 * DELTA.width * t[0]), list(b + 0.5 * DELTA.width * t[0])
    node = symkin.Mechanism.from_dict(data)
    joint = symkin.Mechanism.from_dict(jf.delta(node.coordinates()))
    a = symkin.analyze(node)
    assert (a.dof, a.types, a.input_rank, a.output_rank) == (3, ("DKP-output",), 3, 2)
    _same(node, joint)


# ----------------------------------------------------------------------------------- 3-RPS
def _rps(nodes: dict) -> tuple[symkin.Mechanism, symkin.Mechanism]:
    return symkin.Mechanism.from_dict(jf.rps_3_node(nodes)), symkin.Mechanism.from_dict(jf.rps_3(nodes))


def _wrench_det(nodes: dict) -> float:
    """det of the six unit Plücker lines that hold the platform with the legs locked: per leg the line
    A_k C_k and the line through C_k along the R axis u_k (the leg cannot push C_k out of its plane)."""
    rows = []
    for k, (a, u, _) in enumerate(jf.rps_frames(), 1):
        c = np.asarray(nodes[f"C{k}"], float)
        d = c - np.asarray(a, float)
        for v in (d / np.linalg.norm(d), np.asarray(u, float)):
            rows.append(np.r_[v, np.cross(c, v)])
    return float(np.linalg.det(np.array(rows)))


def test_rps_pose_keeps_each_platform_joint_in_its_leg_plane():
    nodes = jf.rps_3_nodes(2.0, 0.2, -0.1)
    for k, (a, u, c) in enumerate(jf.rps_frames(), 1):
        assert (np.asarray(nodes[f"C{k}"]) - a) @ u == pytest.approx(0.0, abs=1e-14)
    plat = np.array([nodes[f"C{k}"] for k in (1, 2, 3)]) - np.asarray(nodes["O"])
    ref = np.array([c for *_, c in jf.rps_frames()])
    assert np.allclose(plat @ plat.T, ref @ ref.T, atol=1e-13)  # a rigid platform


def test_rps_regular_pose_dof_by_grubler_and_joint_form():
    nodes = jf.rps_3_nodes(2.0, 0.2, -0.1)
    assert abs(_wrench_det(nodes)) > 1.0
    node, joint = _rps(nodes)
    a = symkin.analyze(node)
    assert (a.dof, a.types, a.input_rank, a.output_rank, a.platform_dof) == (3, (), 3, 3, 3)
    _same(node, joint)


def test_rps_type_2_where_the_wrench_lines_are_dependent():
    """Height 2, no tilt about y: the determinant changes sign between tilts −0.8 and −0.6 about x."""
    tilt = T.bisect_root(lambda t: _wrench_det(jf.rps_3_nodes(2.0, t, 0.0)), -0.8, -0.6)
    nodes = jf.rps_3_nodes(2.0, tilt, 0.0)
    assert abs(_wrench_det(nodes)) < 1e-10
    node, joint = _rps(nodes)
    a = symkin.analyze(node)
    assert "DKP-input" in a.types and (a.dof, a.input_rank) == (3, 2)
    _same(node, joint)
