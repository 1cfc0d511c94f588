"""The independent truth of the maps (tests/workspace/truth.py), each function on its own.

Points are built to be on a locus (from elementary constructions: a crank angle and circle
intersections, a bisection root checked by an independent test, a known singular pose) or off it,
and the truth functions must say so.  The last tests check that the model files of
tests/workspace/models encode the geometry truth.py assumes (one analysis each).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from tests.workspace import truth as T

MODELS = Path(__file__).resolve().parent / "models"
RNG = np.random.default_rng(8)

#: the catalogue's five-bar (l1 = 1, l2 = 2, pivots at ±1) and a generic one (unequal everything)
FIVE = T.FiveBar.from_data(catalogue.data("five_bar"))
GENERIC = T.FiveBar(np.array([[-1.0, 0.0], [1.2, 0.1]]), (1.3, 1.1), (1.8, 2.1))
EQUAL_GENERIC = T.FiveBar(np.array([[-1.0, 0.0], [1.0, 0.0]]), (1.3, 1.3), (1.8, 1.8))


# ----------------------------------------------------------------------------------- five-bar
def test_five_bar_geometry_from_the_catalogue():
    assert FIVE.l1 == pytest.approx((1.0, 1.0), abs=1e-15)
    assert FIVE.l2 == pytest.approx((2.0, 2.0), abs=1e-15)
    np.testing.assert_array_equal(FIVE.a, [[-1.0, 0.0], [1.0, 0.0]])
    nodes = catalogue.data("five_bar")["nodes"]
    mode = T.five_bar_mode(FIVE, nodes)
    b1, b2 = T.five_bar_elbows(FIVE, nodes["P"], mode)
    np.testing.assert_allclose(b1, nodes["B1"], atol=1e-14)
    np.testing.assert_allclose(b2, nodes["B2"], atol=1e-14)


@pytest.mark.parametrize("fb", [FIVE, GENERIC], ids=["catalogue", "generic"])
def test_elbows_have_the_link_lengths_and_the_mode_sign(fb):
    p = RNG.uniform(-3, 3, (400, 2))
    ok = T.five_bar_reachable(fb, p)
    assert 50 < ok.sum() < 400  # both reachable and unreachable points drawn
    for mode in T.MODES_5BAR:
        bs = T.five_bar_elbows(fb, p, mode)
        for i, b in enumerate(bs):
            reach = _leg_reaches(fb, p, i)
            assert np.all(np.isfinite(b[reach])) and not np.any(np.isfinite(b[~reach]))
            np.testing.assert_allclose(np.linalg.norm(b[ok] - fb.a[i], axis=-1), fb.l1[i], rtol=1e-12)
            np.testing.assert_allclose(np.linalg.norm(p[ok] - b[ok], axis=-1), fb.l2[i], rtol=1e-12)
            assert np.all(np.sign(T.cross2(b[ok] - fb.a[i], p[ok] - b[ok])) == mode[i])


def _leg_reaches(fb, p, i):
    r = np.linalg.norm(p - fb.a[i], axis=-1)
    return (r >= abs(fb.l1[i] - fb.l2[i])) & (r <= fb.l1[i] + fb.l2[i])


@pytest.mark.parametrize("fb", [FIVE, GENERIC], ids=["catalogue", "generic"])
def test_type1_circles_and_reachability(fb):
    t = np.linspace(0, 2 * np.pi, 50)
    ring = np.stack([np.cos(t), np.sin(t)], axis=-1)
    for i in range(2):
        for k, radius in enumerate((fb.l1[i] + fb.l2[i], abs(fb.l1[i] - fb.l2[i]))):
            on = fb.a[i] + radius * ring
            np.testing.assert_allclose(T.five_bar_type1(fb, on)[:, i, k], 0.0, atol=1e-15)
            out = fb.a[i] + (radius * (1 + 1e-6) + 1e-6 * (k == 1 and radius == 0)) * ring
            assert np.all(np.abs(T.five_bar_type1(fb, out)[:, i, k]) > 1e-8)
            # on the stretched / folded circle the two elbows of leg i coincide (the mode boundary)
            bp = T.elbow(fb.a[i], on, fb.l1[i], fb.l2[i], 1)
            bm = T.elbow(fb.a[i], on, fb.l1[i], fb.l2[i], -1)
            ok = np.isfinite(bp).all(axis=-1)
            np.testing.assert_allclose(bp[ok], bm[ok], atol=1e-6 * fb.scale)
    # outside the outer circle of leg 1: unreachable; just inside it, reachable if leg 2 reaches
    far = fb.a[0] + (fb.l1[0] + fb.l2[0]) * (1 + 1e-9) * ring
    assert not T.five_bar_reachable(fb, far).any()


def test_five_bar_aligned_type2_samples_are_on_the_locus():
    # the catalogue's five-bar has none: |B1 − A2| ≤ 3 < l2 + l2 − l1 (its type-2 locus is the
    # coincident-elbow circle |P| = 2, below)
    assert len(T.five_bar_type2_samples(FIVE, aligned=True)[0]) == 0
    for fb in (GENERIC, EQUAL_GENERIC):
        p, modes = T.five_bar_type2_samples(fb, aligned=True)
        assert len(p) > 100
        for mode in T.MODES_5BAR:
            sel = np.all(modes == mode, axis=1)
            if not sel.any():
                continue
            res = T.five_bar_type2(fb, p[sel], mode)
            np.testing.assert_allclose(res, 0.0, atol=1e-12)
            # off the locus: the same points moved normal to the distal links, by 1e-4 length units
            b1, b2 = T.five_bar_elbows(fb, p[sel], mode)
            d = (b2 - b1) / np.linalg.norm(b2 - b1, axis=-1)[:, None]
            off = p[sel] + 1e-4 * np.stack([-d[:, 1], d[:, 0]], axis=-1)
            res_off = T.five_bar_type2(fb, off, mode)
            fine = np.isfinite(res_off)
            assert np.all(np.abs(res_off[fine]) > 1e-7)


def test_five_bar_type2_changes_sign_across_the_locus():
    p, modes = T.five_bar_type2_samples(GENERIC, n=90)
    for q, mode in zip(p, modes):
        b1, b2 = T.five_bar_elbows(GENERIC, q, mode)
        d = (b2 - b1) / np.linalg.norm(b2 - b1)
        n = np.array([-d[1], d[0]])
        lo, hi = (T.five_bar_type2(GENERIC, q + s * 1e-5 * n, mode) for s in (-1, 1))
        if np.isfinite(lo) and np.isfinite(hi):
            assert lo * hi < 0


def test_five_bar_folded_type2_samples_with_unequal_distal_links():
    p, modes = T.five_bar_type2_samples(GENERIC, aligned=False)
    assert len(p) > 50
    for q, mode in zip(p, modes):
        b1, b2 = T.five_bar_elbows(GENERIC, q, tuple(mode))
        assert abs(T.cross2(q - b1, q - b2)) < 1e-12
        # folded: both elbows on the same side of P
        assert np.dot(q - b1, q - b2) > 0


def test_watt_curve_midpoints_with_equal_distal_links():
    p, modes = T.five_bar_type2_samples(EQUAL_GENERIC, aligned=True)
    for q, mode in zip(p, modes):
        b1, b2 = T.five_bar_elbows(EQUAL_GENERIC, q, tuple(mode))
        np.testing.assert_allclose(q, (b1 + b2) / 2, atol=1e-12)         # P is the midpoint of B1B2
        assert abs(np.linalg.norm(b2 - b1) - 2 * 1.8) < 1e-12            # |B1B2| = 2 l2
    np.testing.assert_allclose(T.watt_curve_residual(EQUAL_GENERIC, p), 0.0, atol=1e-12)
    # the centre of the base, far from the curve, is not on it
    assert T.watt_curve_residual(EQUAL_GENERIC, np.array([0.0, 2.0])) > 1e-2


def test_coincident_elbow_circles():
    circles = T.five_bar_coincident_elbow_circles(EQUAL_GENERIC)
    assert len(circles) == 2
    for centre, radius in circles:
        for i in range(2):
            assert abs(np.linalg.norm(centre - EQUAL_GENERIC.a[i]) - 1.3) < 1e-14
        assert radius == 1.8
        t = np.linspace(0.05, 2 * np.pi - 0.05, 37)
        on = centre + radius * np.stack([np.cos(t), np.sin(t)], axis=-1)
        for q in on:
            # some working mode has both elbows at the centre, and its type-2 residual vanishes there
            found = [m for m in T.MODES_5BAR
                     if all(np.allclose(b, centre, atol=1e-9) for b in T.five_bar_elbows(EQUAL_GENERIC, q, m))]
            assert found
            assert all(abs(T.five_bar_type2(EQUAL_GENERIC, q, m)) < 1e-12 for m in found)
    # unequal distal links: no such circle
    assert T.five_bar_coincident_elbow_circles(GENERIC) == []
    # the catalogue's crank circles touch at the origin: one (double) centre
    cat = T.five_bar_coincident_elbow_circles(FIVE)
    assert all(np.allclose(c, [0.0, 0.0], atol=1e-7) for c, _ in cat)


# ----------------------------------------------------------------------------------- 3-RPR
A_RPR = np.array([[0.0, 0.0], [6.0, 0.0], [2.0, 5.0]])
C_RPR = np.array([[-1.0, -0.5], [1.25, -0.25], [0.0, 1.0]])


@pytest.mark.parametrize("phi", [0.0, 0.4, -1.1])
def test_rpr_conic_equals_the_determinant(phi):
    coef = T.rpr_conic(A_RPR, C_RPR, phi)
    p = RNG.uniform(-5, 10, (200, 2))
    det = T.rpr_type2_det(A_RPR, C_RPR, phi, p)
    np.testing.assert_allclose(T.conic_value(coef, p), det, rtol=1e-10, atol=1e-10 * np.abs(det).max())
    assert np.any(coef[:3] != 0)  # a genuine conic, not a line


@pytest.mark.parametrize("phi", [0.0, 0.4, -1.1])
def test_rpr_conic_points_have_concurrent_legs(phi):
    coef = T.rpr_conic(A_RPR, C_RPR, phi)
    pts = T.conic_points(coef, np.linspace(-4, 10, 57))
    assert len(pts) > 10
    c_world = C_RPR @ T.rot2(phi).T
    # the conic also passes through the three points where a leg has zero length (C_i = A_i: a zero
    # row of the line matrix); there the line is undefined, so those points are left out
    legs = np.linalg.norm(pts[:, None, :] + c_world - A_RPR, axis=-1).min(axis=1)
    for p0 in A_RPR - c_world:
        assert abs(T.conic_value(T.rpr_conic(A_RPR, C_RPR, phi), p0)) < 1e-9
    pts = pts[legs > 0.05]
    for q in pts:
        # independent: intersect leg lines 1 and 2, measure the distance of line 3
        assert T.lines_concurrency(A_RPR, q + c_world) < 1e-9
    off = pts + np.array([0.0, 1e-3])
    conc = [T.lines_concurrency(A_RPR, q + c_world) for q in off]
    assert min(conc) > 1e-8


def test_rpr_conic_vanishes_for_a_platform_congruent_to_the_base():
    """Platform congruent and parallel to the base (c_i = A_i − centroid): every leg has the direction
    p − centroid, the three lines are parallel (concurrent at infinity) for every p: det ≡ 0."""
    a = A_RPR
    c = a - a.mean(axis=0)
    coef = T.rpr_conic(a, c, 0.0)
    for q in RNG.uniform(-3, 3, (10, 2)):
        assert abs(T.conic_value(coef, q)) < 1e-9 * (1 + np.abs(coef).max())


# ----------------------------------------------------------------------------------- 3-RRR
RRR = T.RRR3.from_data(catalogue.data("rrr_3"), reference=(0.0, 0.0), phi=0.1)


def test_rrr_geometry_and_mode_of_the_catalogue():
    nodes = catalogue.data("rrr_3")["nodes"]
    np.testing.assert_allclose(RRR.l1, 2.0, rtol=1e-12)
    np.testing.assert_allclose(RRR.l2, 2.5, rtol=1e-12)
    mode = T.rrr_mode(RRR, nodes)
    b = T.rrr_elbows(RRR, np.zeros(2), 0.1, mode)
    np.testing.assert_allclose(b, [nodes[f"B{k}"] for k in (1, 2, 3)], atol=1e-12)
    assert abs(T.rrr_type2(RRR, np.zeros(2), 0.1, mode)) > 1e-3  # the catalogue's pose is regular


def test_rrr_type2_vanishes_at_the_concurrent_pose_of_fig1a():
    from tests.conftest import EXAMPLES

    data = symkin.read_model(EXAMPLES / "fig1a_3rrr.toml").to_dict()
    r = T.RRR3.from_data(data)
    mode = T.rrr_mode(r, data["nodes"])
    assert abs(T.rrr_type2(r, np.zeros(2), 0.0, mode)) < 1e-14
    assert abs(T.rrr_type2(r, np.array([0.05, 0.0]), 0.0, mode)) > 1e-4


def test_rrr_type2_roots_have_concurrent_distal_lines():
    # the catalogue's own mode (elbow signs −, −, −) has no type-2 point in this slice; this one has
    mode = (1, 1, -1)
    found = 0
    for y in np.linspace(-1.5, 1.5, 13):
        xs = np.linspace(-3.0, 3.0, 121)
        f = T.rrr_type2(RRR, np.column_stack([xs, np.full_like(xs, y)]), 0.1, mode)
        for k in np.nonzero(np.isfinite(f[:-1]) & np.isfinite(f[1:]) & (f[:-1] * f[1:] < 0))[0]:
            x = T.bisect_root(lambda s: float(T.rrr_type2(RRR, np.array([s, y]), 0.1, mode)), xs[k], xs[k + 1])
            p = np.array([x, y])
            b = T.rrr_elbows(RRR, p, 0.1, mode)
            c = RRR.platform(p, 0.1)
            assert T.lines_concurrency(b, c) < 1e-9
            found += 1
    assert found >= 3
    # and away from the roots the lines are not concurrent
    p = np.zeros(2)
    assert abs(T.rrr_type2(RRR, p, 0.1, mode)) > 1e-2
    assert T.lines_concurrency(T.rrr_elbows(RRR, p, 0.1, mode), RRR.platform(p, 0.1)) > 1e-3


def test_rrr_type1_circles():
    t = np.linspace(0, 2 * np.pi, 30)
    for k in range(3):
        radius = RRR.l1[k] + RRR.l2[k]
        c_on = RRR.a[k] + radius * np.stack([np.cos(t), np.sin(t)], axis=-1)
        p = c_on - RRR.c_local[k] @ T.rot2(0.3).T
        np.testing.assert_allclose(T.rrr_type1(RRR, p, 0.3)[:, k, 0], 0.0, atol=1e-14)
    assert T.rrr_reachable(RRR, np.zeros(2), 0.1)
    assert not T.rrr_reachable(RRR, np.array([20.0, 0.0]), 0.1)


# ----------------------------------------------------------------------------------- Gough–Stewart
A_GS = T.hexagon(2.0, np.radians(20))
C_GS = T.hexagon(1.0, np.radians(50))


def test_gough_stewart_regular_pose():
    pose = np.array([0.1, -0.2, 2.0, 0.05, -0.1, 0.3])
    det = T.gough_type2_det(A_GS, C_GS, T.rot3(*pose[3:]), pose[2], pose[:2])
    assert abs(det) > 1e-2
    assert T.gough_jacobian_sigma(A_GS, C_GS, pose) > 1e-2


def test_gough_stewart_fichter_singularity():
    """Turned 90° about the vertical, this 6-6 platform is singular at every position of the slice."""
    rot = T.rot3(0.0, 0.0, np.pi / 2)
    xy = RNG.uniform(-1, 1, (20, 2))
    np.testing.assert_allclose(T.gough_type2_det(A_GS, C_GS, rot, 2.0, xy), 0.0, atol=1e-14)
    for q in xy[:5]:
        assert T.gough_jacobian_sigma(A_GS, C_GS, np.r_[q, 2.0, 0.0, 0.0, np.pi / 2]) < 1e-8


def test_gough_stewart_slice_roots_are_singular_poses():
    rot_angles = (np.radians(10), 0.0, np.radians(90))
    rot = T.rot3(*rot_angles)
    found = 0
    for x in np.linspace(-1.2, 1.2, 7):
        f = lambda s: float(T.gough_type2_det(A_GS, C_GS, rot, 2.0, np.array([x, s])))  # noqa: E731
        assert f(-1.5) * f(1.5) < 0
        y = T.bisect_root(f, -1.5, 1.5)
        pose = np.r_[x, y, 2.0, rot_angles]
        assert T.gough_jacobian_sigma(A_GS, C_GS, pose) < 1e-7
        assert T.gough_jacobian_sigma(A_GS, C_GS, pose + np.r_[0, 0.3, 0, 0, 0, 0]) > 1e-4
        found += 1
    assert found == 7


# ----------------------------------------------------------------------------------- the model files
def test_rpr_model_file_encodes_the_truth_geometry():
    mech = symkin.read_model(MODELS / "rpr_3.toml")
    xyz = {k: np.array(v) for k, v in mech.coordinates().items()}
    np.testing.assert_array_equal([xyz[f"A{k}"] for k in (1, 2, 3)], A_RPR)
    np.testing.assert_allclose([xyz[f"C{k}"] - xyz["O"] for k in (1, 2, 3)], C_RPR, atol=1e-15)
    # on the conic: move the platform (orientation 0) to a conic point; the core finds a DKP in the input
    coef = T.rpr_conic(A_RPR, C_RPR, 0.0)
    q = T.conic_points(coef, [2.0])[1]  # (2, 7/6); the other root, (2, 4), puts C3 on A3
    assert T.lines_concurrency(A_RPR, q + C_RPR) < 1e-12
    moved = {f"C{k}": q + C_RPR[k - 1] for k in (1, 2, 3)} | {"O": q}
    moved |= {f"D{k}": (A_RPR[k - 1] + moved[f"C{k}"]) / 2 for k in (1, 2, 3)}
    res = symkin.analyze(mech.with_coordinates(moved))
    assert "DKP-input" in res.types and res.input_rank == 2
    assert symkin.analyze(mech).types == ()


def test_gough_stewart_model_file_encodes_the_truth_geometry():
    mech = symkin.read_model(MODELS / "gough_stewart.toml")
    xyz = {k: np.array(v) for k, v in mech.coordinates().items()}
    rot = T.rot3(np.radians(10), 0.0, np.radians(90))
    np.testing.assert_allclose([xyz[f"A{k}"] for k in range(1, 7)], A_GS, atol=1e-15)
    np.testing.assert_allclose([xyz[f"C{k}"] for k in range(1, 7)], T.gough_platform(C_GS, rot, xyz["O"]),
                               atol=1e-15)
    assert symkin.analyze(mech).types == ()
