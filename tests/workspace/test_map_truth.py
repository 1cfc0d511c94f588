"""The singularity maps (``symkin.workspace_map``) against the independent truth of truth.py.

For each mechanism and working mode: every traced point of a DKP-input curve is on the closed-form
type-2 locus of its mode, and every point of a DKP-output curve on a type-1 circle, to 1e-9
(dimensionless); every closed-form locus point inside the box (away from its edges and from the
mode's workspace boundary) is near a traced curve of that mode and kind; the assembled grid points
of a mode are the points where the closed-form inverse problem has a solution; and a model in
millimetres gives the same map as in metres.  Skipped, with the reason, until the map engine
exists.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from tests.workspace import truth as T

workspace_map = getattr(symkin, "workspace_map", None)
pytestmark = pytest.mark.skipif(workspace_map is None, reason="needs symkin.workspace_map (issue 8, map engine)")

MODELS = Path(__file__).resolve().parent / "models"
EXAMPLES = Path(__file__).resolve().parents[2] / "papers_examples"

#: a generic five-bar on the catalogue's base: cranks 1.3, distal links 1.8 (the catalogue's own
#: 1 and 2 make its crank circles touch, so its only type-2 locus is touched, not crossed)
FB = T.FiveBar(np.array([[-1.0, 0.0], [1.0, 0.0]]), (1.3, 1.3), (1.8, 1.8))
FB_BOX = ((-3.0, 3.0), (0.2, 3.6))
FB_N = (49, 29)
ON_LOCUS = 1e-9


def _five_bar(fb: T.FiveBar, p, mode, scale: float = 1.0) -> symkin.Mechanism:
    """The catalogue's five-bar topology with geometry ``fb`` at end-effector ``p`` in ``mode``."""
    data = catalogue.data("five_bar")
    b1, b2 = T.five_bar_elbows(fb, np.asarray(p, float), mode)
    nodes = {"A1": fb.a[0], "A2": fb.a[1], "B1": b1, "B2": b2, "P": np.asarray(p, float)}
    data["nodes"] = {k: [float(v) * scale for v in xyz] for k, xyz in nodes.items()}
    data["name"] = f"five-bar, mode {mode}"
    return symkin.Mechanism.from_dict(data)


def _axis(label: str, lo: float, hi: float) -> str:
    return f"{label}={float(lo)!r}:{float(hi)!r}"


def _polyline_distance(p: np.ndarray, poly: np.ndarray) -> float:
    """Distance of point p from the polyline (segments between consecutive points)."""
    if len(poly) == 1:
        return float(np.linalg.norm(p - poly[0]))
    a, b = poly[:-1], poly[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))


def _curves(wmap, kind: str, mode: int) -> list[np.ndarray]:
    return [np.asarray(c.points, float) for c in wmap.curves if c.kind == kind and c.mode == mode]


def _nearest(p, curves) -> float:
    return min((_polyline_distance(p, c) for c in curves), default=np.inf)


# ----------------------------------------------------------------------------------- five-bar
@pytest.fixture(scope="module")
def five_bar_map():
    modes = [(1, -1), (-1, 1), (1, 1), (-1, -1)]
    seed_p = (0.3, 2.4)
    mechs = [_five_bar(FB, seed_p, m) for m in modes]
    (x0, x1), (y0, y1) = FB_BOX
    wmap = workspace_map(mechs[0], x=_axis("velocity:P.x", x0, x1), y=_axis("velocity:P.y", y0, y1), n=FB_N,
                         seeds=mechs[1:], modes="model", refine=True)
    return wmap, modes


@pytest.mark.slow
def test_five_bar_every_mode_is_a_map_mode(five_bar_map):
    wmap, modes = five_bar_map
    assert len(wmap.modes) == len(modes)
    for mm, mode in zip(wmap.modes, modes):
        b = mm.seed_q.reshape(-1, 2)  # free nodes B1, B2, P in the evaluators' order
        assert T.five_bar_mode(FB, {"B1": b[0], "B2": b[1], "P": b[2]}) == mode


@pytest.mark.slow
def test_five_bar_assembled_where_the_closed_form_reaches(five_bar_map):
    wmap, modes = five_bar_map
    X, Y = np.meshgrid(wmap.xs, wmap.ys)
    P = np.stack([X, Y], axis=-1)
    reach = T.five_bar_reachable(FB, P)
    margin = np.min(np.abs(T.five_bar_type1(FB, P)), axis=(-1, -2)) > 1e-9
    assert 0.3 < reach.mean() < 0.95  # the box holds both reachable and unreachable points
    for mm in wmap.modes:
        ok = np.asarray(mm.assembled, bool)
        np.testing.assert_array_equal(ok[margin], reach[margin])
        assert mm.fraction == pytest.approx(reach.mean(), abs=np.mean(~margin) + 1e-12)


def _on_box_edge(pts, box) -> np.ndarray:
    (x0, x1), (y0, y1) = box
    return (np.abs(pts[:, 0] - x0) < 1e-12) | (np.abs(pts[:, 0] - x1) < 1e-12) | \
        (np.abs(pts[:, 1] - y0) < 1e-12) | (np.abs(pts[:, 1] - y1) < 1e-12)


def _type2_check(pts, mode) -> np.ndarray:
    """Per point: on the mode's type-2 locus (1e-9), or at a meeting point with the workspace boundary.

    Where a type-2 curve meets a type-1 circle (a leg stretched or folded) the residual grows like
    the square root of the distance to the circle, so a point located to 1e-14 there shows a
    residual near 1e-7: such points must be on the circle to 1e-12 and have a residual below 1e-6.
    """
    res = np.abs(T.five_bar_type2(FB, pts, mode))
    on_circle = np.min(np.abs(T.five_bar_type1(FB, pts)), axis=(-1, -2)) < 1e-12
    return (res < ON_LOCUS) | (on_circle & (res < 1e-6))


@pytest.mark.slow
def test_five_bar_traced_points_on_the_closed_form_loci(five_bar_map):
    wmap, modes = five_bar_map
    n_in = n_out = 0
    for k, mode in enumerate(modes):
        for pts in _curves(wmap, "DKP-input", k):
            inner = pts[~_on_box_edge(pts, FB_BOX)]
            assert np.all(_type2_check(inner, mode)), f"mode {mode}: DKP-input point off the type-2 locus"
            n_in += len(inner)
        for pts in _curves(wmap, "DKP-output", k):
            res = np.min(np.abs(T.five_bar_type1(FB, pts)), axis=(-1, -2))
            assert np.max(res) < ON_LOCUS, f"mode {mode}: DKP-output point off the type-1 circles"
            n_out += len(pts)
    assert n_in > 50 and n_out > 50


@pytest.mark.slow
def test_five_bar_curve_ends_on_the_box_edge_are_on_the_loci(five_bar_map):
    wmap, modes = five_bar_map
    n_edge = 0
    for k, mode in enumerate(modes):
        for pts in _curves(wmap, "DKP-input", k):
            edge = pts[_on_box_edge(pts, FB_BOX)]
            assert np.all(_type2_check(edge, mode)), (mode, edge)
            n_edge += len(edge)
    assert n_edge >= 4  # the Watt's curves leave the box through its bottom edge


@pytest.mark.slow
def test_five_bar_every_locus_point_in_the_box_is_near_a_traced_curve(five_bar_map):
    wmap, modes = five_bar_map
    (x0, x1), (y0, y1) = FB_BOX
    step = max((x1 - x0) / (FB_N[0] - 1), (y1 - y0) / (FB_N[1] - 1))
    inside = lambda p: (x0 + step < p[0] < x1 - step) and (y0 + step < p[1] < y1 - step)  # noqa: E731
    samples = []
    p, m = T.five_bar_type2_samples(FB, n=720, aligned=True)          # the Watt's curves
    samples += list(zip(p, map(tuple, m)))
    for centre, radius in T.five_bar_coincident_elbow_circles(FB):      # the coincident-elbow circles
        t = np.linspace(0, 2 * np.pi, 360, endpoint=False)
        for q in centre + radius * np.stack([np.cos(t), np.sin(t)], axis=-1):
            for mode in T.MODES_5BAR:
                if all(np.allclose(b, centre, atol=1e-9) for b in T.five_bar_elbows(FB, q, mode)):
                    samples.append((q, mode))
    checked = 0
    worst = 0.0
    for q, mode in samples:
        clear = np.min(np.abs(T.five_bar_type1(FB, q))) * (FB.l1[0] + FB.l2[0]) > step
        if not (inside(q) and clear):
            continue
        d = _nearest(q, _curves(wmap, "DKP-input", modes.index(mode)))
        worst = max(worst, d)
        checked += 1
    assert checked > 100
    assert worst < 0.05 * step, f"a type-2 point {worst:.3g} from every traced curve (grid step {step:.3g})"
    # the type-1 circles: every circle point where the mode assembles on one side
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    ring = np.stack([np.cos(t), np.sin(t)], axis=-1)
    checked = 0
    for i in range(2):
        for radius in (FB.l1[i] + FB.l2[i], abs(FB.l1[i] - FB.l2[i])):
            for q in FB.a[i] + radius * ring:
                other = T.five_bar_type1(FB, q)[1 - i]
                if not inside(q) or np.min(np.abs(other)) * 3.1 < step or not (other[0] < 0 < other[1]):
                    continue
                for k in range(len(modes)):
                    assert _nearest(q, _curves(wmap, "DKP-output", k)) < 0.05 * step
                checked += 1
    assert checked > 50


@pytest.mark.slow
def test_five_bar_map_is_scale_invariant():
    mode = (1, -1)
    (x0, x1), (y0, y1) = FB_BOX
    maps = []
    for s in (1.0, 1000.0):
        mech = _five_bar(FB, (0.3, 2.4), mode, scale=s)
        maps.append(workspace_map(mech, x=_axis("velocity:P.x", x0 * s, x1 * s), y=_axis("velocity:P.y", y0 * s, y1 * s),
                                  n=(25, 15), refine=True))
    m, mm = maps
    np.testing.assert_array_equal(m.modes[0].assembled, mm.modes[0].assembled)
    np.testing.assert_array_equal(m.modes[0].types, mm.modes[0].types)
    for name in ("im_indicator", "dkp_input", "dkp_output"):
        np.testing.assert_allclose(getattr(mm.modes[0], name), getattr(m.modes[0], name), rtol=1e-9, atol=1e-12)
    assert [(c.kind, c.closed, len(c.points)) for c in m.curves] == [(c.kind, c.closed, len(c.points)) for c in mm.curves]
    for c, cc in zip(m.curves, mm.curves):
        np.testing.assert_allclose(np.asarray(cc.points) / 1000.0, c.points, rtol=0, atol=1e-9 * FB.scale)


# ----------------------------------------------------------------------------------- 3-RPR (conic)
RPR_A = np.array([[0.0, 0.0], [6.0, 0.0], [2.0, 5.0]])
RPR_C = np.array([[-1.0, -0.5], [1.25, -0.25], [0.0, 1.0]])
RPR_BOX = ((1.5, 4.5), (0.75, 3.25))


def _rpr_map(refine: bool):
    mech = symkin.read_model(MODELS / "rpr_3.toml")
    (x0, x1), (y0, y1) = RPR_BOX
    return workspace_map(mech, x=_axis("velocity:O.x", x0, x1), y=_axis("velocity:O.y", y0, y1), n=(31, 26),
                         hold=("rotation:platform",), refine=refine)


def test_rpr_grid_signs_follow_the_conic():
    """The DKP-input test function on the grid has the sign of the conic (up to one global sign)."""
    wmap = _rpr_map(refine=False)
    X, Y = np.meshgrid(wmap.xs, wmap.ys)
    conic = T.conic_value(T.rpr_conic(RPR_A, RPR_C, 0.0), np.stack([X, Y], axis=-1))
    din = np.asarray(wmap.modes[0].dkp_input)
    assert np.asarray(wmap.modes[0].assembled).all()  # prismatic legs: no stretch limit in this box
    assert (conic > 0).any() and (conic < 0).any()    # the conic crosses the box
    same = np.sign(din) == np.sign(conic)
    assert same.all() or (~same).all()


@pytest.mark.slow
def test_rpr_traced_type2_points_on_the_conic():
    wmap = _rpr_map(refine=True)
    coef = T.rpr_conic(RPR_A, RPR_C, 0.0)
    pts = np.concatenate(_curves(wmap, "DKP-input", 0) or [np.zeros((0, 2))])
    assert len(pts) > 20
    for q in pts:
        assert T.lines_concurrency(RPR_A, q + RPR_C) < ON_LOCUS
    # every conic point in the box (away from its edges) is near a traced curve
    (x0, x1), (y0, y1) = RPR_BOX
    step = max((x1 - x0) / 30, (y1 - y0) / 25)
    on = T.conic_points(coef, np.linspace(x0 + step, x1 - step, 200))
    on = on[(on[:, 1] > y0 + step) & (on[:, 1] < y1 - step)]
    assert len(on) > 50
    curves = _curves(wmap, "DKP-input", 0)
    assert max(_nearest(q, curves) for q in on) < 0.05 * step


# ----------------------------------------------------------------------------------- 3-RRR
@pytest.fixture(scope="module")
def rrr_map():
    data = catalogue.data("rrr_3")
    ref = np.array(data["nodes"]["C1"])
    rrr = T.RRR3.from_data(data, reference=ref, phi=0.0)  # platform frame at the model's orientation
    mode = (1, 1, -1)  # the catalogue's own mode (−, −, −) has no type-2 point in this slice
    b = T.rrr_elbows(rrr, ref, 0.0, mode)
    for k in range(3):
        data["nodes"][f"B{k + 1}"] = [float(v) for v in b[k]]
    mech = symkin.Mechanism.from_dict(data)
    box = ((ref[0] - 1.5, ref[0] + 1.5), (ref[1] - 1.5, ref[1] + 1.5))
    wmap = workspace_map(mech, x=_axis("velocity:C1.x", *box[0]), y=_axis("velocity:C1.y", *box[1]), n=(31, 31),
                         hold=("rotation:platform",), refine=True)
    return wmap, rrr, mode, box


@pytest.mark.slow
def test_rrr_traced_type2_points_have_concurrent_distal_lines(rrr_map):
    wmap, rrr, mode, _ = rrr_map
    pts = np.concatenate(_curves(wmap, "DKP-input", 0) or [np.zeros((0, 2))])
    assert len(pts) > 20
    assert np.max(np.abs(T.rrr_type2(rrr, pts, 0.0, mode))) < ON_LOCUS
    for q in pts[:: max(1, len(pts) // 50)]:
        assert T.lines_concurrency(T.rrr_elbows(rrr, q, 0.0, mode), rrr.platform(q, 0.0)) < ON_LOCUS
    for pts in _curves(wmap, "DKP-output", 0):
        assert np.max(np.min(np.abs(T.rrr_type1(rrr, pts, 0.0)), axis=(-1, -2))) < ON_LOCUS


@pytest.mark.slow
def test_rrr_every_type2_point_in_the_box_is_near_a_traced_curve(rrr_map):
    wmap, rrr, mode, ((x0, x1), (y0, y1)) = rrr_map
    step = max((x1 - x0) / 30, (y1 - y0) / 30)
    curves = _curves(wmap, "DKP-input", 0)
    checked, worst = 0, 0.0
    for y in np.linspace(y0 + step, y1 - step, 41):
        xs = np.linspace(x0 + step, x1 - step, 241)
        f = T.rrr_type2(rrr, np.column_stack([xs, np.full_like(xs, y)]), 0.0, mode)
        for k in np.nonzero(np.isfinite(f[:-1]) & np.isfinite(f[1:]) & (f[:-1] * f[1:] < 0))[0]:
            x = T.bisect_root(lambda s: float(T.rrr_type2(rrr, np.array([s, y]), 0.0, mode)), xs[k], xs[k + 1])
            q = np.array([x, y])
            # away from the mode's workspace boundary (a leg stretched or folded), where curves end
            if np.min(np.abs(T.rrr_type1(rrr, q, 0.0))) * 4.5 < step:
                continue
            worst = max(worst, _nearest(q, curves))
            checked += 1
    assert checked > 20
    assert worst < 0.05 * step, f"a type-2 point {worst:.3g} from every traced curve (grid step {step:.3g})"


@pytest.mark.slow
def test_rrr_assembled_where_the_closed_form_reaches(rrr_map):
    wmap, rrr, mode, _ = rrr_map
    X, Y = np.meshgrid(wmap.xs, wmap.ys)
    P = np.stack([X, Y], axis=-1)
    reach = T.rrr_reachable(rrr, P, 0.0)
    margin = np.min(np.abs(T.rrr_type1(rrr, P, 0.0)), axis=(-1, -2)) > 1e-9
    ok = np.asarray(wmap.modes[0].assembled, bool)
    # continuation from the seed reaches the seed's connected part of the reachable set
    assert not np.any(ok & ~reach)
    assert np.sum(ok[margin] != reach[margin]) == 0


# ----------------------------------------------------------------------------------- Fig. 14: the IM point
@pytest.mark.slow
def test_fig14_map_reports_the_im_point_at_the_origin():
    """The IM indicator touches zero at the origin, the centre of a cell of the even grid (four equal
    minima at its corners, no configuration kept there): refinement re-solves one from the seed and
    locates the collapsed rhombus, one isolated IM point, IM with a DKP in the output (the core's
    classification of the file's derivation: L = 3 > F = 2, v_Py = 0)."""
    mech = symkin.read_model(EXAMPLES / "fig14_2rr.toml")
    wmap = workspace_map(mech, x="velocity:P.x=-6.5:6.5", y="velocity:P.y=-6.5:6.5", n=52, refine=True)
    ims = [p for p in wmap.points if p.kind == "IM"]
    assert len(ims) == 1, [(p.kind, p.at) for p in wmap.points]
    assert np.hypot(*ims[0].at) < 1e-8, ims[0].at
    assert tuple(ims[0].types) == ("IM", "DKP-output")
    # independently: at P = 0 a collapsed rhombus (B1 = -B2 = l·n) has velocity rows (cranks A-B_i, distal
    # links B_i-P over v_B1, v_B2, v_P) of rank 3, so L = 6 − 3 = 3 > F = 2
    n = np.array([0.6, 0.8])
    rows = np.array([[*n, 0, 0, 0, 0], [0, 0, *n, 0, 0], [*(-n), 0, 0, *n], [0, 0, *n, *(-n)]])
    assert rows.shape[1] - np.linalg.matrix_rank(rows) == 3


# ----------------------------------------------------------------------------------- Gough–Stewart slice
GS_A = T.hexagon(2.0, np.radians(20))
GS_C = T.hexagon(1.0, np.radians(50))
GS_R0 = T.rot3(np.radians(10), 0.0, np.radians(90))
GS_O = np.array([0.75, 0.0, 2.0])
#: a slice of the 6-D workspace: O.x, O.y free; held: the height of O and of the platform joints C1, C3
#: (with O.z they fix the platform's tilt: R = Rz(ψ) R0) and the length of leg 1 (it fixes the turn ψ).
#: (The map engine cannot hold a spatial orientation yet: it holds node coordinates, slides and planar
#: rotations; so the turn about the vertical follows from leg 1, and truth solves it independently.)
GS_HOLD = ("velocity:O.z", "velocity:C1.z", "velocity:C3.z", "slide:s1")
GS_BOX = ((-0.75, 1.25), (-1.0, 1.0))


def _gs_turn(xy, steps: int = 40) -> float | None:
    """ψ with |O + Rz(ψ) R0 c1 − A1| = |C1 − A1| of the model, O = (x, y, 2), continued by Newton along
    the segment from the model's O (ψ = 0) to (x, y): the branch the map continues from its seed."""
    target = np.linalg.norm(GS_O + GS_R0 @ GS_C[0] - GS_A[0])
    arm = GS_R0 @ GS_C[0]

    def f(o, s):
        return float(np.linalg.norm(o + T.rot3(0, 0, s) @ arm - GS_A[0]) - target)

    psi = 0.0
    for t in np.linspace(0.0, 1.0, steps + 1)[1:]:
        o = np.array([GS_O[0] + t * (xy[0] - GS_O[0]), GS_O[1] + t * (xy[1] - GS_O[1]), GS_O[2]])
        for _ in range(30):
            val = f(o, psi)
            if abs(val) < 1e-15 * target:
                break
            slope = (f(o, psi + 1e-7) - f(o, psi - 1e-7)) / 2e-7
            if slope == 0.0:
                return None
            psi -= val / slope
        else:
            return None
    return psi


def _gs_det(xy) -> float:
    psi = _gs_turn(xy)
    assert psi is not None, f"leg 1 cannot keep its length at {xy}"
    return float(T.gough_type2_det(GS_A, GS_C, T.rot3(0, 0, psi) @ GS_R0, GS_O[2], np.asarray(xy, float)))


def _gs_map(refine: bool):
    mech = symkin.read_model(MODELS / "gough_stewart.toml")
    (x0, x1), (y0, y1) = GS_BOX
    return workspace_map(mech, x=_axis("velocity:O.x", x0, x1), y=_axis("velocity:O.y", y0, y1), n=(21, 21),
                         hold=GS_HOLD, refine=refine)


@pytest.mark.slow
def test_gough_stewart_grid_signs_follow_the_plucker_determinant():
    gs_map = _gs_map(refine=False)
    mode = gs_map.modes[0]
    ok = np.asarray(mode.assembled, bool)
    din = np.asarray(mode.dkp_input)
    signs = []
    for j, y in enumerate(gs_map.ys):
        for i, x in enumerate(gs_map.xs):
            if ok[j, i] and abs(din[j, i]) > 1e-9:
                signs.append(np.sign(_gs_det((x, y))) == np.sign(din[j, i]))
    assert len(signs) > 200
    assert all(signs) or not any(signs)
    assert 0 < np.sum(din[ok] > 0) < np.sum(ok)  # the slice crosses the type-2 locus


@pytest.mark.slow
def test_gough_stewart_traced_type2_points_are_singular_poses():
    gs_map = _gs_map(refine=True)
    pts = np.concatenate(_curves(gs_map, "DKP-input", 0) or [np.zeros((0, 2))])
    assert len(pts) > 10
    dets = np.array([_gs_det(q) for q in pts])
    assert np.max(np.abs(dets)) < ON_LOCUS
    for q in pts[:: max(1, len(pts) // 5)]:  # independently: the leg-length Jacobian is singular there
        pose = np.r_[q, GS_O[2], 0.0, 0.0, 0.0]
        rot = T.rot3(0, 0, _gs_turn(q)) @ GS_R0
        c_here = GS_C @ rot.T  # the platform frame turned to the pose: rotations about it from zero
        assert T.gough_jacobian_sigma(GS_A, c_here, pose) < 1e-7


@pytest.mark.slow
def test_fig14_origin_grid_point_is_assembled_and_im():
    """With an odd grid the origin is a grid point: the square position problem is exactly singular there
    (the collapsed rhombus turns freely about A), Newton's minimum-norm steps reach the closure, and the
    point is assembled, the limit configuration of the mode: IM indicator 0 (closed form (3 − |c| −
    √(1 − 2|c| + 5c²))/2 at ρ = 0, c = 1: 0), classified IM; refinement reports the IM point there."""
    from symkin.workspace.grid import TYPE_BITS

    mech = symkin.read_model(EXAMPLES / "fig14_2rr.toml")
    wmap = workspace_map(mech, x="velocity:P.x=-6.5:6.5", y="velocity:P.y=-6.5:6.5", n=53, refine=True)
    mode = wmap.modes[0]
    j = i = 26
    assert wmap.xs[i] == 0.0 and wmap.ys[j] == 0.0
    assert np.asarray(mode.assembled).all()
    assert abs(float(np.asarray(mode.im_indicator)[j, i])) < 1e-12
    assert int(np.asarray(mode.types)[j, i]) & TYPE_BITS["IM"]
    ims = [p for p in wmap.points if p.kind == "IM"]
    assert len(ims) == 1 and np.hypot(*ims[0].at) < 1e-8, [(p.kind, p.at) for p in wmap.points]


# ----------------------------------------------------------------------------------- Gough–Stewart at constant orientation
#: the slice the issue asks for: O.x, O.y free; the platform's orientation (the three components of its
#: rotation vector from the model's orientation) and the height of O held at the model's values
GS_HOLD_ORIENTATION = ("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[z]")


@pytest.mark.slow
def test_gough_stewart_constant_orientation_slice_traces_the_plucker_locus():
    mech = symkin.read_model(MODELS / "gough_stewart.toml")
    (x0, x1), (y0, y1) = GS_BOX
    wmap = workspace_map(mech, x=_axis("velocity:O.x", x0, x1), y=_axis("velocity:O.y", y0, y1), n=(21, 21),
                         hold=GS_HOLD_ORIENTATION, refine=True)
    mode = wmap.modes[0]
    ok = np.asarray(mode.assembled, bool)
    assert ok.all()  # prismatic legs: no stretch limit in this box
    X, Y = np.meshgrid(wmap.xs, wmap.ys)
    det = T.gough_type2_det(GS_A, GS_C, GS_R0, GS_O[2], np.stack([X, Y], axis=-1))
    din = np.asarray(mode.dkp_input)
    sure = np.abs(det) > 1e-9
    same = np.sign(din[sure]) == np.sign(det[sure])
    assert same.all() or (~same).all()
    assert (det > 0).any() and (det < 0).any()  # the slice crosses the type-2 locus
    curves = _curves(wmap, "DKP-input", 0)
    pts = np.concatenate(curves or [np.zeros((0, 2))])
    assert len(pts) > 10
    # every traced point: the six leg Plücker lines are dependent (independent determinant)
    assert np.max(np.abs(T.gough_type2_det(GS_A, GS_C, GS_R0, GS_O[2], pts))) < ON_LOCUS
    # every locus point on rows and columns of the box (away from its edges) is near a traced curve
    step = max((x1 - x0) / 20, (y1 - y0) / 20)
    checked, worst = 0, 0.0
    for axis in (0, 1):
        lo, hi = GS_BOX[axis]
        olo, ohi = GS_BOX[1 - axis]
        for other in np.linspace(olo + step, ohi - step, 15):
            def at(s, o=other, a=axis):
                return np.array([s, o]) if a == 0 else np.array([o, s])
            ss = np.linspace(lo + step, hi - step, 121)
            f = T.gough_type2_det(GS_A, GS_C, GS_R0, GS_O[2], np.array([at(v) for v in ss]))
            for k in np.nonzero(f[:-1] * f[1:] < 0)[0]:
                root = T.bisect_root(lambda v: float(T.gough_type2_det(GS_A, GS_C, GS_R0, GS_O[2], at(v))),
                                     ss[k], ss[k + 1])
                worst = max(worst, _nearest(at(root), curves))
                checked += 1
    assert checked > 5
    assert worst < 0.05 * step, worst


def test_orientation_hold_labels_are_checked():
    mech = symkin.read_model(MODELS / "gough_stewart.toml")
    with pytest.raises(symkin.SymkinError, match="x, y, z"):
        workspace_map(mech, x="velocity:O.x=0:1", y="velocity:O.y=0:1", n=3,
                      hold=("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[w]"))
    with pytest.raises(symkin.SymkinError, match="not a moving link"):
        workspace_map(mech, x="velocity:O.x=0:1", y="velocity:O.y=0:1", n=3,
                      hold=("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:nothing[z]"))


@pytest.mark.slow
def test_orientation_hold_value_is_the_rotation_vector_from_the_model():
    """``rotation:platform[z]=2`` (degrees): every solved configuration has the platform turned by exactly
    Rz(2°) from the model's orientation (its frame from three platform joints, computed here)."""
    from symkin.workspace.grid import continue_mode
    from symkin.workspace.system import map_system

    mech = symkin.read_model(MODELS / "gough_stewart.toml")
    s = map_system(mech, "velocity:O.x", "velocity:O.y",
                   hold=["velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[z]=2"])
    xs = np.linspace(0.5, 1.0, 3)
    g = continue_mode(s, xs, xs, s.q0, keep_configurations=True)
    assert np.asarray(g.assembled).all()
    xyz0 = np.array([c for _, c in mech.nodes], float)
    idx = mech.node_index()
    k = [idx[n] for n in ("C1", "C3", "C5")]

    def frame(p):
        e1 = (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])
        e3 = np.cross(e1, p[2] - p[0])
        e3 /= np.linalg.norm(e3)
        return np.column_stack([e1, np.cross(e3, e1), e3])

    c, sn = np.cos(np.radians(2.0)), np.sin(np.radians(2.0))
    rz = np.array([[c, -sn, 0.0], [sn, c, 0.0], [0.0, 0.0, 1.0]])
    for j in range(3):
        for i in range(3):
            xyz = s.evaluators.coordinates(g.q[j, i])
            rot = frame(xyz[k]) @ frame(xyz0[k]).T
            np.testing.assert_allclose(rot, rz, atol=1e-12)
            assert xyz[idx["O"], 2] == pytest.approx(xyz0[idx["O"], 2], abs=1e-12)
