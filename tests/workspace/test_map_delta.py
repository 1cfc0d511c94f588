"""A Delta robot (3-R(SS)²) mapped at constant height against its independent closed form (truth.Delta).

The model: three arms turning about horizontal axes (the inputs), each carrying a parallelogram of two
bars with spherical ends to the platform, so the platform only translates; the map holds the height of
its reference point P and frees P.x, P.y.  Truth: the closed-form arm angles (inverse problem), and the
type-2 locus where the forward Jacobian of the three leg constraints ``|C_i − B_i|² = l_b²`` in P is
singular, ``det[d_1; d_2; d_3] = 0`` (d_i the bar directions), written from the geometry in truth.py.
The working mode has the third leg's knee turned inward, which puts a type-2 curve inside the box.
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from tests.workspace import truth as T

DELTA = T.Delta()
KNEE = (1, 1, -1)
Z = -2.2
BOX = (-1.4, 1.4)
N = 15
ON_LOCUS = 1e-9


def _polyline_distance(p, poly) -> float:
    a, b = poly[:-1], poly[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))


@pytest.fixture(scope="module")
def delta_map():
    mech = symkin.Mechanism.from_dict(DELTA.model(np.array([0.0, 0.0, Z]), KNEE))
    axis = f"{BOX[0]!r}:{BOX[1]!r}"
    return symkin.workspace_map(mech, x=f"velocity:P.x={axis}", y=f"velocity:P.y={axis}", n=N,
                                hold=["velocity:P.z"])


def _det(xy) -> float:
    return DELTA.type2_det([xy[0], xy[1], Z], KNEE)


def test_truth_delta_model_closes_and_its_determinant_vanishes_on_coplanar_bars():
    p = np.array([0.2, -0.1, Z])
    nodes = DELTA.nodes(p, KNEE)
    for k in (1, 2, 3):
        for s in "ab":
            assert np.linalg.norm(nodes[f"C{k}{s}"] - nodes[f"B{k}{s}"]) == pytest.approx(DELTA.bar, abs=1e-12)
        arm = nodes[f"B{k}a"] - nodes[f"A{k}"]
        assert abs(arm @ (nodes[f"A{k}b"] - nodes[f"A{k}"])) == pytest.approx(0.5 * DELTA.width, abs=1e-12)
    d = DELTA.bar_directions(p, KNEE)
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
    # a finite-difference forward Jacobian of the leg constraints in P (arms locked) has the same determinant sign
    theta = DELTA.angles(p, KNEE)
    b = DELTA.elbows(theta)
    u, _ = DELTA.frames()

    def legs(pp):
        return np.array([np.sum((pp + DELTA.platform * u[i] - b[i]) ** 2) for i in range(3)])

    h = 1e-6
    jac = np.column_stack([(legs(p + h * e) - legs(p - h * e)) / (2 * h) for e in np.eye(3)])
    assert np.sign(np.linalg.det(jac)) == np.sign(DELTA.type2_det(p, KNEE))


@pytest.mark.slow
def test_delta_assembles_where_every_leg_reaches(delta_map):
    m = delta_map.modes[0]
    X, Y = np.meshgrid(delta_map.xs, delta_map.ys)
    reach = np.array([[np.all(np.isfinite(DELTA.angles([x, y, Z], KNEE))) for x, y in zip(rx, ry)]
                      for rx, ry in zip(X, Y)])
    assert 0.3 < reach.mean() < 0.95
    # the legs' reach margin decides; grid points within rounding of a leg's limit are not judged
    clear = np.array([[abs(DELTA.reach_margin([x, y, Z])) > 1e-9 for x, y in zip(rx, ry)] for rx, ry in zip(X, Y)])
    assert clear.mean() > 0.9
    assert np.array_equal(m.assembled[clear], reach[clear])


@pytest.mark.slow
def test_delta_grid_signs_follow_the_forward_jacobian_determinant(delta_map):
    m = delta_map.modes[0]
    ok = np.asarray(m.assembled, bool)
    agree = []
    for j, y in enumerate(delta_map.ys):
        for i, x in enumerate(delta_map.xs):
            if ok[j, i] and abs(m.dkp_input[j, i]) > 1e-9:
                agree.append(np.sign(_det((x, y))) == np.sign(m.dkp_input[j, i]))
    assert len(agree) > 50
    assert all(agree) or not any(agree)
    assert 0 < np.sum(m.dkp_input[ok] > 0) < np.sum(ok)  # the slice crosses the type-2 locus


@pytest.mark.slow
def test_delta_traced_type2_points_have_coplanar_bars(delta_map):
    curves = [np.asarray(c.points) for c in delta_map.curves if c.kind == "DKP-input"]
    pts = np.concatenate(curves)
    assert len(pts) > 20
    assert max(abs(_det(q)) for q in pts) < ON_LOCUS
    # a translation singularity, not a turn of the platform (the parallelograms' moments stay independent)
    assert min(abs(DELTA.rotation_det([q[0], q[1], Z], KNEE)) for q in pts) > 1e-3


@pytest.mark.slow
def test_delta_every_type2_point_on_the_grid_lines_is_near_a_traced_curve(delta_map):
    m = delta_map.modes[0]
    xs, ys = delta_map.xs, delta_map.ys
    step = xs[1] - xs[0]
    curves = [np.asarray(c.points) for c in delta_map.curves if c.kind == "DKP-input"]
    roots = []
    for j in range(len(ys)):
        for i in range(len(xs) - 1):
            a, b = (xs[i], ys[j]), (xs[i + 1], ys[j])
            if m.assembled[j, i] and m.assembled[j, i + 1] and _det(a) * _det(b) < 0:
                roots.append((T.bisect_root(lambda x: _det((x, ys[j])), xs[i], xs[i + 1]), ys[j]))
    for i in range(len(xs)):
        for j in range(len(ys) - 1):
            a, b = (xs[i], ys[j]), (xs[i], ys[j + 1])
            if m.assembled[j, i] and m.assembled[j + 1, i] and _det(a) * _det(b) < 0:
                roots.append((xs[i], T.bisect_root(lambda y: _det((xs[i], y)), ys[j], ys[j + 1])))
    assert len(roots) >= 4
    for r in roots:
        assert min(_polyline_distance(np.array(r), c) for c in curves) < 0.05 * step, r


@pytest.mark.slow
def test_delta_traced_boundary_is_the_legs_reach_limit(delta_map):
    """The mode's workspace boundary (no sign change on the grid: a fold between assembled and unassembled
    neighbours) traced as DKP-output curves: every traced point on a leg's reach limit (truth.Delta's
    reach margin min_i (1 − |K_i/ρ_i|) = 0, arm and bar in one line) to 1e-9; every reach-limit point on a
    grid line between assembled and unassembled neighbours near a traced curve; and the core classifies a
    traced point (its configuration from the closed form) as DKP-output, L = F = 3 (no IM)."""
    m = delta_map.modes[0]
    curves = [np.asarray(c.points) for c in delta_map.curves if c.kind == "DKP-output"]
    assert len(curves) >= 1
    pts = np.concatenate(curves)
    assert len(pts) > 30
    margins = np.array([DELTA.reach_margin([x, y, Z]) for x, y in pts])
    assert np.abs(margins).max() < ON_LOCUS
    xs, ys = delta_map.xs, delta_map.ys
    step = xs[1] - xs[0]
    limits = []
    for j in range(len(ys)):
        for i in range(len(xs) - 1):
            if m.assembled[j, i] != m.assembled[j, i + 1]:
                limits.append((T.bisect_root(lambda x: DELTA.reach_margin([x, ys[j], Z]), xs[i], xs[i + 1]), ys[j]))
    for i in range(len(xs)):
        for j in range(len(ys) - 1):
            if m.assembled[j, i] != m.assembled[j + 1, i]:
                limits.append((xs[i], T.bisect_root(lambda y: DELTA.reach_margin([xs[i], y, Z]), ys[j], ys[j + 1])))
    assert len(limits) >= 20
    for r in limits:
        assert min(_polyline_distance(np.array(r), c) for c in curves) < 0.05 * step, r
    # a traced point where the closed form assembles (margin >= 0), classified by the core
    k = int(np.argmin(np.where(margins >= 0, margins, np.inf)))
    mech = symkin.Mechanism.from_dict(DELTA.model(np.array([pts[k][0], pts[k][1], Z]), KNEE))
    res = symkin.analyze(mech)
    assert (res.types, res.dof, res.mobility) == (("DKP-output",), 3, 3)
