"""Refinement to exact curves (symkin.workspace.loci) against closed forms of the five-bar."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from symkin.model.catalogue import data, get
from symkin.model.mechanism import Mechanism
from scipy.optimize import brentq
from symkin.workspace.loci import GridData, refine
from symkin.workspace.system import map_system

L1, L2 = 1.0, 2.0  # catalogue five_bar: |A_i B_i| = 1, |B_i P| = 2
A = np.array([[-1.0, 0.0], [1.0, 0.0]])


def _system(mech, nodes_axes=("P",)):
    return map_system(mech, f"velocity:{nodes_axes[0]}.x", f"velocity:{nodes_axes[0]}.y")


def _ik(p, signs, a=A, l1=L1, l2=L2):
    """Elbows B_i of RR legs from A_i to p (closed form), or None when a leg does not reach."""
    out = []
    for k in range(len(signs)):
        d = p - a[k]
        r = np.linalg.norm(d)
        if not abs(l1 - l2) < r < l1 + l2:
            return None
        along = (l1 * l1 - l2 * l2 + r * r) / (2 * r)
        h = np.sqrt(max(l1 * l1 - along * along, 0.0))
        u = d / r
        n = np.array([-u[1], u[0]])
        out.append(a[k] + along * u + signs[k] * h * n)
    return out


def _grid(ev, xs, ys, signs, a=A, l1=L1, l2=L2):
    """Grid of one working mode from the closed-form inverse kinematics; indicators from the batch evaluators."""
    nx, ny = len(xs), len(ys)
    q = np.full((ny, nx, ev.nf), np.nan)
    asm = np.zeros((ny, nx), bool)
    order = ev.q_labels  # x_B1, y_B1, x_B2, y_B2, x_P, y_P
    for j, y in enumerate(ys):
        for i, x in enumerate(xs):
            b = _ik(np.array([x, y]), signs, a, l1, l2)
            if b is None:
                continue
            vals = {"x_B1": b[0][0], "y_B1": b[0][1], "x_B2": b[1][0], "y_B2": b[1][1], "x_P": x, "y_P": y}
            q[j, i] = [vals[k] for k in order]
            asm[j, i] = True
    res = ev.batch(q[asm])
    arrays = {}
    for key in ("dkp_input", "dkp_output", "im_indicator"):
        full = np.full((ny, nx), np.nan)
        full[asm] = getattr(res, key)
        arrays[key] = full
    return GridData(np.asarray(xs), np.asarray(ys), asm, q=q, **arrays)


def _nodes(ev, qs, name):
    return np.column_stack([qs[:, ev.q_labels.index(f"x_{name}")], qs[:, ev.q_labels.index(f"y_{name}")]])


XS, YS = np.linspace(-3.5, 3.5, 36), np.linspace(0.2, 4.4, 22)
CELL = 0.2
MODES = [(1, -1), (-1, 1), (1, 1), (-1, -1)]
#: a generic five-bar on the catalogue's base (the catalogue's l1 = 1, l2 = 2 with |A1A2| = 2 puts the
#: coincident elbows on the base line, where the type-2 test function touches zero without changing sign)
G1, G2 = 1.3, 1.8


def _five_bar(l1=G1, l2=G2, scale=1.0):
    d = data("five_bar")
    p = np.array([0.3, 2.1])
    b = _ik(p, (1, -1), A, l1, l2)
    d["nodes"].update(B1=list(b[0]), B2=list(b[1]), P=list(p))
    for k, v in d["nodes"].items():
        d["nodes"][k] = [scale * c for c in v]
    return Mechanism.from_dict(d)


def _refined(mech, signs, scale=1.0, l1=G1, l2=G2):
    sys_ = _system(mech)
    grid = _grid(sys_.evaluators, scale * XS, scale * YS, signs, scale * A, scale * l1, scale * l2)
    return (sys_, grid) + tuple(refine(sys_, grid, mode=str(signs)))


@pytest.fixture(scope="module", params=MODES, ids=[str(m) for m in MODES])
def fivebar_map(request):
    return request.param, _refined(_five_bar(), request.param)


def _polyline_distance(p, poly, closed):
    pts = np.vstack([poly, poly[:1]]) if closed else poly
    a, b = pts[:-1], pts[1:]
    ab = b - a
    u = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(p - (a + u[:, None] * ab), axis=1)))


def _near_any(p, curves):
    return min(_polyline_distance(p, c.points, c.closed) for c in curves)


def test_type1_curves_lie_on_the_circles(fivebar_map):
    """DKP-output curves of a workspace map: |P − A_i| = l1 ± l2 at every traced point (to 1e-9)."""
    _, (sys_, grid, curves, points, stats) = fivebar_map
    out = [c for c in curves if c.kind == "DKP-output"]
    assert len(out) >= 4  # two outer and two inner circles cross the box in every mode
    radii = np.array([G1 + G2, abs(G1 - G2)])
    for c in out:
        d = np.linalg.norm(c.points[:, None, :] - A[None, :, :], axis=2)  # (N, 2)
        err = np.abs(d[:, :, None] - radii[None, None, :])  # (N, leg, radius)
        # one circle for the whole curve
        leg, r = np.unravel_index(np.argmin(err.max(axis=0)), (2, 2))
        assert err[:, leg, r].max() <= 1e-9, (c.ends, err[:, leg, r].max())
        # the configuration closes and its P is the reported point
        ev = sys_.evaluators
        assert np.allclose(_nodes(ev, c.configurations, "P"), c.points, atol=1e-12)


def test_type2_curves_align_the_distal_links(fivebar_map):
    """DKP-input curves: B1, P, B2 collinear at every traced point, elementary cross product (to 1e-9)."""
    _, (sys_, grid, curves, points, stats) = fivebar_map
    ev = sys_.evaluators
    for c in (c for c in curves if c.kind == "DKP-input"):
        b1, b2, p = (_nodes(ev, c.configurations, n) for n in ("B1", "B2", "P"))
        u, v = b1 - p, b2 - p
        cross = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        assert np.abs(cross).max() <= 1e-9
        for k, bk in enumerate((b1, b2)):
            assert np.abs(np.linalg.norm(bk - A[k], axis=1) - G1).max() <= 1e-9 * G2
            assert np.abs(np.linalg.norm(bk - p, axis=1) - G2).max() <= 1e-9 * G2
        assert np.allclose(p, c.points, atol=1e-12)


def _type2_samples(signs, n=281):
    """Points of the mode's type-2 locus from the closed form: sign changes of (B1−P)×(B2−P) along fine rows."""
    def cross(x, y):
        b = _ik(np.array([x, y]), signs, A, G1, G2)
        if b is None:
            return np.nan
        u, v = b[0] - np.array([x, y]), b[1] - np.array([x, y])
        return u[0] * v[1] - u[1] * v[0]

    out = []
    for y in np.linspace(YS[0], YS[-1], 43)[1:-1]:
        xs = np.linspace(XS[0], XS[-1], n)
        c = np.array([cross(x, y) for x in xs])
        for k in np.flatnonzero(np.sign(c[:-1]) * np.sign(c[1:]) < 0):
            out.append([brentq(lambda x: cross(x, y), xs[k], xs[k + 1], xtol=1e-12), y])
    return np.array(out)


def _type1_samples(signs):
    """Points of the circles |P − A_i| = l1 ± l2 in the box where the other leg reaches (away from its ends)."""
    out = []
    for k in range(2):
        for r in (G1 + G2, abs(G1 - G2)):
            for t in np.linspace(0, np.pi, 721):
                p = A[k] + r * np.array([np.cos(t), np.sin(t)])
                if not (XS[0] < p[0] < XS[-1] and YS[0] < p[1] < YS[-1]):
                    continue
                other = np.linalg.norm(p - A[1 - k])
                if abs(G1 - G2) + 0.05 < other < G1 + G2 - 0.05:
                    out.append(p)
    return np.array(out)


def test_every_closed_form_locus_point_is_near_a_traced_curve(fivebar_map):
    signs, (sys_, grid, curves, points, stats) = fivebar_map
    for kind, samples in (("DKP-output", _type1_samples(signs)), ("DKP-input", _type2_samples(signs))):
        traced = [c for c in curves if c.kind == kind]
        if len(samples) == 0:
            continue
        assert traced, kind
        far = [p for p in samples if _near_any(p, traced) > 2 * CELL]
        assert not far, (kind, len(far), far[:3])


def test_curves_are_not_traced_twice(fivebar_map):
    """Deduplication: no two curves of one kind share a point."""
    _, (sys_, grid, curves, points, stats) = fivebar_map
    for a in range(len(curves)):
        for b in range(a + 1, len(curves)):
            if curves[a].kind != curves[b].kind:
                continue
            mid = curves[b].points[len(curves[b].points) // 2]
            assert _near_any(mid, [curves[a]]) > 1e-6
    assert stats.duplicates > 0 and stats.located + stats.seeded == len(curves)
    assert all(len(c.points) >= 2 for c in curves)


@pytest.mark.slow
def test_scale_invariance_mm_and_m():
    """The same mechanism in millimetres gives the same curves, scaled by 1000."""
    m = _refined(_five_bar(), (-1, 1))
    mm = _refined(_five_bar(scale=1000.0), (-1, 1), scale=1000.0)
    ca_, cb = m[2], mm[2]
    assert sorted((c.kind, c.closed, c.ends) for c in ca_) == sorted((c.kind, c.closed, c.ends) for c in cb)
    for c in cb:
        same = [d for d in ca_ if d.kind == c.kind]
        assert max(_near_any(p / 1000.0, same) for p in c.points) <= 1e-9


# ---------------------------------------------------------------------- 3-RRR at constant orientation
R_BASE, R_PF, R1, R2, PHI = 4.0, 1.0, 2.0, 2.5, 0.1  # catalogue rrr_3 (platform angle 0.1)
ANG = [2 * np.pi * k / 3 + np.pi / 2 for k in range(3)]
A3 = np.array([[R_BASE * np.cos(a), R_BASE * np.sin(a)] for a in ANG])
OFF = np.array([[R_PF * np.cos(a + PHI), R_PF * np.sin(a + PHI)] for a in ANG])
X3, Y3 = np.linspace(-3.0, 3.0, 31), np.linspace(-2.5, 3.5, 31)
CELL3 = 0.2
#: a working mode whose workspace contains type-2 loci at this orientation (the model's, (1, 1, 1), has none)
MODE3 = (1, 1, -1)


def _rrr_nodes(c1, signs):
    """Elbows B_k and platform joints C_k of the 3-RRR with C1 at ``c1`` and the model's orientation."""
    c = c1 + OFF - OFF[0]
    out = []
    for k in range(3):
        b = _ik(c[k], (signs[k],), A3[k:k + 1], R1, R2)
        if b is None:
            return None
        out.append(b[0])
    return np.array(out), c


def _rrr_grid(ev, signs):
    nx, ny = len(X3), len(Y3)
    q = np.full((ny, nx, ev.nf), np.nan)
    asm = np.zeros((ny, nx), bool)
    for j, y in enumerate(Y3):
        for i, x in enumerate(X3):
            r = _rrr_nodes(np.array([x, y]), signs)
            if r is None:
                continue
            b, c = r
            vals = {}
            for k in range(3):
                vals.update({f"x_B{k + 1}": b[k, 0], f"y_B{k + 1}": b[k, 1], f"x_C{k + 1}": c[k, 0],
                             f"y_C{k + 1}": c[k, 1]})
            q[j, i] = [vals[lab] for lab in ev.q_labels]
            asm[j, i] = True
    res = ev.batch(q[asm])
    arrays = {}
    for key in ("dkp_input", "dkp_output", "im_indicator"):
        full = np.full((ny, nx), np.nan)
        full[asm] = getattr(res, key)
        arrays[key] = full
    return GridData(X3, Y3, asm, q=q, **arrays)


def _plucker_det(b, c):
    """det of the planar Plücker coordinates (d_x, d_y, m) of the three distal lines B_k C_k, normalised."""
    d = c - b
    m = b[..., 0] * d[..., 1] - b[..., 1] * d[..., 0]
    rows = np.stack([d[..., 0], d[..., 1], m / R_BASE], axis=-1)
    return np.linalg.det(rows) / np.prod(np.linalg.norm(rows, axis=-1), axis=-1)


@pytest.fixture(scope="module")
def rrr_map():
    mech = get("rrr_3")
    sys_ = map_system(mech, "velocity:C1.x", "velocity:C1.y", hold=["rotation:platform"])
    grid = _rrr_grid(sys_.evaluators, MODE3)
    return (sys_, grid) + tuple(refine(sys_, grid, mode=str(MODE3)))


@pytest.mark.slow
def test_rrr_constant_orientation_loci(rrr_map):
    """3-RRR, platform orientation held: type-2 where the distal lines are concurrent (Plücker det = 0), type-1
    where a leg is stretched or folded; every traced point to 1e-9, every closed-form type-2 point near a curve."""
    sys_, grid, curves, points, stats = rrr_map
    ev = sys_.evaluators
    inp = [c for c in curves if c.kind == "DKP-input"]
    out = [c for c in curves if c.kind == "DKP-output"]
    assert inp and out
    for c in curves:
        b = np.stack([_nodes(ev, c.configurations, f"B{k}") for k in (1, 2, 3)], axis=1)
        cc = np.stack([_nodes(ev, c.configurations, f"C{k}") for k in (1, 2, 3)], axis=1)
        # closure and the held orientation, from the configuration
        assert np.abs(np.linalg.norm(b - A3[None], axis=2) - R1).max() <= 1e-9 * R1
        assert np.abs(np.linalg.norm(cc - b, axis=2) - R2).max() <= 1e-9 * R1
        assert np.abs(cc - cc[:, :1] - (OFF - OFF[0])[None]).max() <= 1e-9
        if c.kind == "DKP-input":
            assert np.abs(_plucker_det(b, cc)).max() <= 1e-9
        else:
            reach = np.linalg.norm(cc - A3[None], axis=2)  # (N, leg)
            err = np.min(np.abs(reach[:, :, None] - np.array([R1 + R2, R2 - R1])[None, None]), axis=(1, 2))
            assert err.max() <= 1e-9 * R1
    # closed-form type-2 points (sign changes of the Plücker determinant along fine rows)
    samples = []
    for y in np.linspace(Y3[0], Y3[-1], 31)[1:-1]:
        xs = np.linspace(X3[0], X3[-1], 201)
        vals = []
        for x in xs:
            r = _rrr_nodes(np.array([x, y]), MODE3)
            vals.append(np.nan if r is None else _plucker_det(*r))
        vals = np.array(vals)
        for k in np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0):
            f = lambda x: _plucker_det(*_rrr_nodes(np.array([x, y]), MODE3))
            samples.append([brentq(f, xs[k], xs[k + 1], xtol=1e-12), y])
    assert samples
    far = [p for p in samples if _near_any(np.array(p), inp) > 2 * CELL3]
    assert not far, far[:3]


# ---------------------------------------------------------------------- an IM point where two loci meet
@pytest.mark.slow
def test_im_point_where_two_fold_curves_meet():
    """l1 = 2.2, l2 = 1.2 on the catalogue's base: the inner circles |P − A_i| = 1 touch at the origin, where all four
    bars are collinear (B1 = (1.2, 0), B2 = (−1.2, 0)) and the y velocities of B1, B2, P are free: L = 3 > F (IM).

    The traced fold circles end there (the DKP test functions are not defined at IM); the end is refined to the
    origin to 1e-9 and the core classifies it IM.
    """
    d = data("five_bar")
    p = np.array([0.3, 1.9])
    b = _ik(p, (1, -1), A, 2.2, 1.2)
    d["nodes"].update(B1=list(b[0]), B2=list(b[1]), P=list(p))
    mech = Mechanism.from_dict(d)
    sys_ = map_system(mech, "velocity:P.x", "velocity:P.y")
    xs, ys = np.linspace(-2.03, 2.01, 21), np.linspace(-1.49, 1.53, 16)
    grid = _grid(sys_.evaluators, xs, ys, (1, -1), A, 2.2, 1.2)
    curves, points, stats = refine(sys_, grid, mode="elbows")
    im = [pt for pt in points if pt.kind == "IM"]
    assert len(im) == 1, [pt.to_dict() for pt in points]
    assert np.linalg.norm(im[0].at) <= 1e-9 and "IM" in im[0].types
    b1, b2 = (_nodes(sys_.evaluators, im[0].configuration[None], n)[0] for n in ("B1", "B2"))
    assert np.allclose(b1, [1.2, 0.0], atol=1e-9) and np.allclose(b2, [-1.2, 0.0], atol=1e-9)
    # the two inner circles, each traced from the IM point round to it again
    inner = [c for c in curves if c.kind == "DKP-output"]
    assert len(inner) == 2 and all(c.ends == ("IM", "IM") for c in inner)
    for c, centre in zip(sorted(inner, key=lambda c: c.points[:, 0].mean()), A):
        assert np.abs(np.linalg.norm(c.points - centre, axis=1) - 1.0).max() <= 1e-9


@pytest.mark.slow
def test_rotation_invariance():
    """The five-bar turned by 90° (box turned with it): the same curves (kinds, ends) on the turned loci."""
    rot = np.array([[0.0, -1.0], [1.0, 0.0]])
    mech = _five_bar().moved(rotation=rot.tolist())
    sys_ = _system(mech)
    a_rot = A @ rot.T
    xs, ys = -YS[::-1], XS  # (x, y) -> (-y, x) maps the grid onto itself
    grid = _grid(sys_.evaluators, xs, ys, (-1, 1), a_rot, G1, G2)
    curves, points, stats = refine(sys_, grid, mode="turned")
    ref = _refined(_five_bar(), (-1, 1))[2]
    key = lambda cs: sorted((c.kind, c.closed, tuple(sorted(c.ends))) for c in cs)  # noqa: E731
    assert key(curves) == key(ref)
    ev = sys_.evaluators
    for c in curves:
        back = c.points @ rot  # turned back
        if c.kind == "DKP-output":
            d = np.linalg.norm(back[:, None, :] - A[None], axis=2)
            err = np.abs(d[:, :, None] - np.array([G1 + G2, abs(G1 - G2)])[None, None]).min(axis=(1, 2))
            assert err.max() <= 1e-9
        else:
            b1, b2, p = (_nodes(ev, c.configurations, n) for n in ("B1", "B2", "P"))
            u, v = b1 - p, b2 - p
            cross = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
            assert np.abs(cross).max() <= 1e-9
    # every curve of the reference run, turned, lies near a curve of the turned run
    for c in ref:
        same = [d for d in curves if d.kind == c.kind]
        assert max(_near_any(p, same) for p in c.points @ rot.T) <= 2 * CELL


def test_im_candidates_are_strict_interior_minima():
    from symkin.workspace.im_points import im_candidates

    im = np.ones((5, 6))
    im[2, 3] = 0.1   # interior strict minimum: a candidate
    im[0, 1] = 0.01  # on the edge of the grid: no 3 × 3 neighbourhood
    im[3, 1] = 0.2   # its neighbour (2, 0)... is not assembled: skipped
    asm = np.ones((5, 6), bool)
    asm[2, 0] = False
    grid = GridData(np.arange(6.0), np.arange(5.0), asm, im, im, im_indicator=im)
    assert im_candidates(grid) == [(2, 3)]


# ----------------------------------------------------------------------------------- IM minima through the quadtree
FIG14 = Path(__file__).resolve().parents[2] / "papers_examples" / "fig14_2rr.toml"


@pytest.mark.parametrize("k", [1.0, 1000.0])  # model units, and the same model in millimetres
def test_fig14_im_point_between_coarse_grid_points_found_through_the_quadtree(k):
    """Fig. 14's 2RR (l = 5, coaxial pivots): a coarse 6 × 6 grid whose nodes miss the origin (the nearest,
    the IM indicator's grid minimum, is (-1, 0.1), |P| = 1.005): it is too far for the rank-drop
    refinement to reach the collapsed rhombus from it.  Subdividing the cells around the minimum (the IM
    indicator as the quadtree's T) starts it from the finest cell instead: the IM point at the origin to
    1e-9, IM with a DKP in the output, and (by the core) L = 3 > F = 2 there with the collapsed rhombus
    B1 = −B2, |B_i| = 5 (the model file's derivation); the same in millimetres."""
    import symkin
    from symkin.workspace.grid import continue_mode

    mech = symkin.read_model(FIG14).moved(scale=k)
    s = map_system(mech, "velocity:P.x", "velocity:P.y")
    xs, ys = k * np.linspace(-6.0, 6.5, 6), k * np.linspace(-1.5, 6.5, 6)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    assert g.assembled.all()
    # the nearest grid node is (-1, 0.1), |P| = 1.005 (a fifth of the link): the grid does not resolve it
    X, Y = np.meshgrid(xs, ys)
    assert np.hypot(X, Y).min() > 1.0 * k
    grid = GridData(xs, ys, g.assembled, g.dkp_input, g.dkp_output, g.im_indicator, q=g.q, seed=s.q0)
    curves, points, stats = refine(s, grid)
    im = [pt for pt in points if pt.kind == "IM"]
    assert len(im) == 1, [pt.to_dict() for pt in points]
    assert np.linalg.norm(im[0].at) <= 1e-9 * k
    assert tuple(im[0].types) == ("IM", "DKP-output")
    assert stats.subdivided > 0 and stats.failed == 0
    ev = s.evaluators
    b1, b2, p = (_nodes(ev, im[0].configuration[None], n)[0] for n in ("B1", "B2", "P"))
    assert np.allclose(b1, -b2, atol=1e-9 * k) and abs(np.linalg.norm(b1) - 5.0 * k) <= 1e-9 * k
    res = symkin.analyze(mech.with_coordinates({"B1": b1, "B2": b2, "P": p}))
    assert (res.dof, res.mobility, res.types) == (3, 2, ("IM", "DKP-output"))


def test_fig14_slope_at_the_collapsed_rhombus_is_not_converged_and_refine_completes():
    """At the IM configuration (P = A = 0, B1 = −B2 = (0, 5)) the square position problem is singular, so
    ∂T/∂n (a solve with its Jacobian) is not defined: a NotConvergedError that the dip refinement skips,
    not CasADi's RuntimeError.  The coarse 5 × 5 grid below has a dip of DKP-output next to the origin whose
    double-zero search reaches that configuration; refinement completes and subdivides the dip."""
    import symkin
    from symkin.errors import NotConvergedError
    from symkin.workspace.grid import continue_mode
    from symkin.workspace.locus_problems import LocusProblems, LocusSystem

    mech = symkin.read_model(FIG14)
    s = map_system(mech, "velocity:P.x", "velocity:P.y")
    pb = LocusProblems(LocusSystem.of(s))
    ev = s.evaluators
    q = {"x_B1": 0.0, "y_B1": 5.0, "x_B2": 0.0, "y_B2": -5.0, "x_P": 0.0, "y_P": 0.0}
    y = np.array([q[k] for k in ev.q_labels]) / pb.scale
    with pytest.raises(NotConvergedError):
        pb.slope("DKP-output", y, np.array([1.0, 0.0]))
    xs, ys = np.linspace(-6.0, 5.5, 5), np.linspace(-1.5, 6.5, 5)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    grid = GridData(xs, ys, g.assembled, g.dkp_input, g.dkp_output, g.im_indicator, q=g.q, seed=s.q0)
    curves, points, stats = refine(s, grid)
    assert stats.dips == 1 and stats.subdivided > 0
    assert all("IM" in pt.types and np.linalg.norm(pt.at) <= 1e-9 for pt in points if pt.kind == "IM")
