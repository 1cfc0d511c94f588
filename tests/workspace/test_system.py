"""The map's square position problem: squareness, absolute coordinates, batched Newton, errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.workspace.system import map_system, parse_hold


@pytest.fixture(scope="module")
def five_bar():
    return get("five_bar")


def test_square_system_sizes(five_bar):
    s = map_system(five_bar, "velocity:P.x", "velocity:P.y")
    assert s.nf == 6 and s.mobility == 2 and len(s.rows) == 4 and s.holds == ()
    r, j = s.evaluate("square", s.q0[None], s.targets([[0.0, 2.0]]))
    assert r.shape == (1, 6) and j.shape == (1, 6, 6)
    assert np.max(np.abs(r)) < 1e-14
    assert np.linalg.matrix_rank(j[0]) == 6


def test_absolute_rotation_axes(five_bar):
    # crank1 A1(-1,0) -> B1(-1.6,0.8): atan2(0.8, -0.6); crank2 A2(1,0) -> B2(1.6,0.8): atan2(0.8, 0.6)
    s = map_system(five_bar, "rotation:crank1", "rotation:crank2")
    a = s.axis_values(s.q0[None])[0]
    assert a == pytest.approx([math.atan2(0.8, -0.6), math.atan2(0.8, 0.6)], abs=1e-14)
    assert s.to_user(a) == pytest.approx(np.degrees(a))


def test_newton_lands_on_closure_and_target(five_bar):
    s = map_system(five_bar, "velocity:P.x", "velocity:P.y")
    xy = np.array([[0.3, 2.2], [-0.5, 1.5], [0.0, 2.0]])
    q, ok, res, it = s.solve(np.repeat(s.q0[None], 3, axis=0), xy)
    assert ok.all() and (res < 1e-11).all()
    assert np.allclose(s.axis_values(q), xy, atol=1e-12)
    # independent truth: every bar keeps its model length
    x = np.array([s.evaluators.coordinates(qk) for qk in q])
    names = {n: k for k, (n, _) in enumerate(five_bar.nodes)}
    for a, b in (("A1", "B1"), ("B1", "P"), ("A2", "B2"), ("B2", "P")):
        l0 = np.linalg.norm(np.subtract(dict(five_bar.nodes)[a], dict(five_bar.nodes)[b]))
        assert np.allclose(np.linalg.norm(x[:, names[a]] - x[:, names[b]], axis=1), l0, atol=1e-12)


def test_unreachable_point_is_not_converged(five_bar):
    s = map_system(five_bar, "velocity:P.x", "velocity:P.y")
    # |P - A1| > l1 + l2 = 1 + sqrt(2.6) for P = (5, 5): no configuration
    _, ok, _, _ = s.solve(s.q0[None], [[5.0, 5.0]])
    assert not ok[0]


def test_scale_invariant_residual(five_bar):
    big = five_bar.moved(scale=1000.0)
    s1 = map_system(five_bar, "velocity:P.x", "velocity:P.y")
    s2 = map_system(big, "velocity:P.x", "velocity:P.y")
    q1, ok1, _, it1 = s1.solve(s1.q0[None], [[0.3, 2.2]])
    q2, ok2, _, it2 = s2.solve(s2.q0[None], [[300.0, 2200.0]])
    assert ok1[0] and ok2[0] and it1[0] == it2[0]
    assert np.allclose(q2 / 1000.0, q1, atol=1e-12)


def test_holds_square_the_problem():
    m = get("rrr_3")
    with pytest.raises(SymkinError, match=r"F = 3.*1 held coordinate.*--hold"):
        map_system(m, "velocity:C1.x", "velocity:C1.y")
    with pytest.raises(SymkinError, match="over-determined"):
        map_system(m, "velocity:C1.x", "velocity:C1.y", hold=["rotation:platform", "rotation:crank1"])
    s = map_system(m, "velocity:C1.x", "velocity:C1.y", hold=["rotation:platform=10"])
    assert s.hold_values == pytest.approx([math.radians(10.0)])
    s = map_system(m, "velocity:C1.x", "velocity:C1.y", hold=["rotation:platform"])
    assert s.evaluate("holds", s.q0[None])[0][0] == pytest.approx(s.hold_values)
    c, dc = s.evaluate("constraints", s.q0[None], s.hold_values)
    assert c.shape == (1, s.nf - 2) and dc.shape == (1, s.nf - 2, s.nf) and np.abs(c).max() < 1e-14


def test_bad_labels(five_bar):
    with pytest.raises(SymkinError, match="unknown input 'velocity:Q.x'"):
        map_system(five_bar, "velocity:Q.x", "velocity:P.y")
    with pytest.raises(SymkinError, match="named twice"):
        map_system(five_bar, "velocity:P.x", "velocity:P.x")
    with pytest.raises(SymkinError, match="F >= 2"):
        map_system(get("fourbar_appendix"), "rotation:crank", "rotation:rocker")
    with pytest.raises(SymkinError, match="unit"):
        map_system(five_bar, "velocity:P.x", "velocity:P.y", unit="grad")


def test_dependent_axes_are_refused(five_bar):
    # crank1's angle and B1's x-coordinate fix the same freedom (B1 lies on the crank circle)
    with pytest.raises(SymkinError, match="do not fix the mechanism"):
        map_system(five_bar, "rotation:crank1", "velocity:B1.x")


def test_parse_hold():
    assert parse_hold("slide:s=-1.5") == ("slide:s", -1.5)
    with pytest.raises(SymkinError, match="not a number"):
        parse_hold("rotation:platform=abc")
