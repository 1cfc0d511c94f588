"""Dips of |T|, the quadtree around them and double zeros (symkin.workspace.quadtree, loci) against closed forms."""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from symkin.workspace import quadtree
from tests.workspace import truth as T

#: the catalogue five-bar: cranks 1, distal links 2, pivots (∓1, 0): its crank circles touch at the origin,
#: so with both elbows there P turns on the circle |P| = 2, a double zero of the DKP-input test function
FB0 = T.FiveBar.from_data(catalogue.data("five_bar"))
BOX0 = ((-3.5, 3.5), (0.2, 4.4))
#: the working mode whose elbows can coincide at the origin on that circle (truth.elbow's sign convention)
MODE0 = (1, -1)


def _catalogue_five_bar(p, mode) -> symkin.Mechanism:
    data = catalogue.data("five_bar")
    b1, b2 = T.five_bar_elbows(FB0, np.asarray(p, float), mode)
    nodes = {"A1": FB0.a[0], "A2": FB0.a[1], "B1": b1, "B2": b2, "P": np.asarray(p, float)}
    data["nodes"] = {k: [float(v) for v in xyz] for k, xyz in nodes.items()}
    return symkin.Mechanism.from_dict(data)


def _polyline_distance(p, poly) -> float:
    a, b = poly[:-1], poly[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))


# ----------------------------------------------------------------------------------- dips
def test_dips_flag_a_double_zero_and_two_close_roots_not_a_valley_or_a_sign_change():
    x = np.linspace(-1.0, 1.0, 9)
    h = x[1] - x[0]
    rows = np.array([(x - 0.3 * h) ** 2,                  # double zero between grid points
                     (x - 0.1 * h) * (x - 0.4 * h) + 0.0,  # two roots in one cell: all nodes positive
                     x ** 2 + 4 * h * h,                  # a valley far from zero: no dip
                     x - 0.5 * h])                        # a simple root: a sign change, no dip
    got = np.array([quadtree.dip_mask(r[None], np.ones((1, r.size), bool))[0] for r in rows])  # along x only
    assert got[0].sum() == 1 and got[1].sum() == 1
    assert not got[2].any() and not got[3].any()
    assert np.all(rows[1][np.isfinite(rows[1])] > 0)  # the two close roots show no sign change on the grid


# ----------------------------------------------------------------------------------- quadtree
def _synthetic(f):
    """``solve``, ``value`` for :func:`quadtree.subdivide` whose "configuration" is the axis point itself."""
    def solve(a, y0):
        return np.array(a, float), np.ones(len(a), bool)

    def value(y):
        return np.array([f(np.asarray(row, float)) for row in y])
    return solve, value


@pytest.mark.parametrize("curve", ["small circle", "two close lines"])
def test_quadtree_finds_a_curve_narrower_than_a_cell_that_the_grid_misses(curve):
    cell = np.array([1.0, 1.0])
    centre = np.array([0.37, -0.22])  # inside the cell [0, 1] × [-1, 0] of the grid node (0, 0)
    if curve == "small circle":
        radius = 0.15                  # the whole curve inside one cell, away from its corners

        def f(a):
            return float(np.sum((a - centre) ** 2) - radius ** 2)

        def on_curve(a):
            return abs(np.linalg.norm(a - centre) - radius)
    else:
        x0, x1 = 0.2, 0.55             # the band x0 < x < x1 crosses every grid line between two grid points

        def f(a):
            return float((a[0] - x0) * (a[0] - x1))

        def on_curve(a):
            return min(abs(a[0] - x0), abs(a[0] - x1))
    lo, hi = np.array([-5.0, -5.0]), np.array([5.0, 5.0])
    grid = [f(np.array([i, j], float)) for i in (-1, 0, 1) for j in (-1, 0, 1)]
    assert all(v > 0 for v in grid)  # no sign change on the grid: it misses the curve
    a0 = np.zeros(2)
    # without subdivision (depth 0) the cells around the dip show nothing to locate
    flat = quadtree.subdivide(*_synthetic(f), a0, a0, f(a0), cell, lo, hi, depth=0)
    assert flat.crossings == []
    deep = quadtree.subdivide(*_synthetic(f), a0, a0, f(a0), cell, lo, hi)
    fine = cell / 2 ** quadtree.DEPTH
    assert len(deep.crossings) >= 4
    for a_a, y_a, a_b, y_b in deep.crossings:
        assert f(a_a) * f(a_b) < 0                                    # a bracket of the curve
        assert np.linalg.norm(a_b - a_a) == pytest.approx(fine[0])    # on a finest edge
        assert min(on_curve(a_a), on_curve(a_b)) <= fine[0]
    assert deep.samples < 200  # adaptive: far fewer than the 17 × 17 points of a full subdivision


# ----------------------------------------------------------------------------------- double zeros on a map
@pytest.fixture(scope="module")
def double_zero_map():
    mech = _catalogue_five_bar((0.3, 2.4), MODE0)
    return symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=21)


def test_truth_the_coincident_elbow_circle_is_a_double_zero():
    (centre, radius), = {(tuple(c), r) for c, r in T.five_bar_coincident_elbow_circles(FB0)}
    assert np.allclose(centre, 0.0, atol=1e-15) and radius == 2.0
    r = np.array([1.9, 1.95, 2.0 - 1e-4, 2.0 + 1e-4, 2.05, 2.1])
    phi = 1.2
    t2 = T.five_bar_type2(FB0, np.stack([r * np.cos(phi), r * np.sin(phi)], -1), MODE0)
    assert np.all(t2 > 0)  # one sign on both sides of the circle
    assert t2[3] / t2[5] == pytest.approx((1e-4 / 0.1) ** 2, rel=0.1)  # quadratic in the distance
    assert abs(T.five_bar_type2(FB0, 2.0 * np.array([np.cos(phi), np.sin(phi)]), MODE0)) < 1e-15


@pytest.mark.slow
def test_double_zero_circle_is_traced_on_the_closed_form(double_zero_map):
    wmap = double_zero_map
    curves = [np.asarray(c.points) for c in wmap.curves if c.kind == "DKP-input"]
    assert len(curves) == 1
    pts = curves[0]
    assert len(pts) > 15
    # every traced point on the circle |P| = 2 (dimensionless: over the length 2) and of type 2 in its mode
    assert np.max(np.abs(np.hypot(*pts.T) - 2.0)) / 2.0 < 1e-9
    assert np.max(np.abs(T.five_bar_type2(FB0, pts, MODE0))) < 1e-9
    # the curve runs from box edge to box edge (y = 0.2 on both sides of the circle)
    assert np.allclose(sorted([pts[0, 1], pts[-1, 1]]), [0.2, 0.2], atol=1e-12)
    assert pts[0, 0] * pts[-1, 0] < 0
    # every circle point in the box is near the traced curve
    step = max(7.0 / 20, 4.2 / 20)
    t = np.linspace(0.0, np.pi, 721)
    circle = 2.0 * np.stack([np.cos(t), np.sin(t)], -1)
    circle = circle[circle[:, 1] > BOX0[1][0]]
    worst = max(_polyline_distance(q, pts) for q in circle)
    assert worst < 0.05 * step
    assert wmap.counts()["0"]["DKP-input"] == 1


@pytest.mark.slow
def test_double_zero_is_found_on_a_coarse_grid_by_the_quadtree(monkeypatch):
    """A 9 × 9 grid (cells of 0.875 × 0.525 against a circle of radius 2): the subdivided cells find the
    circle; without subdivision (depth 0: the grid's own cells) it is missed."""
    mech = _catalogue_five_bar((0.3, 2.4), MODE0)
    wmap = symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=9)
    pts = np.concatenate([c.points for c in wmap.curves if c.kind == "DKP-input"])
    assert np.max(np.abs(np.hypot(*pts.T) - 2.0)) < 1e-9
    # the whole arc above y = 0.2: from angle asin(0.1) to π − asin(0.1)
    assert np.ptp(np.arctan2(pts[:, 1], pts[:, 0])) > 0.99 * (np.pi - 2 * np.arcsin(0.1))
    monkeypatch.setattr(quadtree, "DEPTH", 0)
    flat = symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=9)
    assert not [c for c in flat.curves if c.kind == "DKP-input"]
