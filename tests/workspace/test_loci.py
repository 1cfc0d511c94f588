"""Refinement to exact curves (symkin.workspace.loci) against closed forms of the five-bar."""
from __future__ import annotations

import numpy as np
import pytest

from symkin.model.catalogue import data
from symkin.model.mechanism import Mechanism
from scipy.optimize import brentq
from symkin.workspace.loci import GridData, LocusSystem, refine
from symkin.workspace.system import map_system

L1, L2 = 1.0, 2.0  # catalogue five_bar: |A_i B_i| = 1, |B_i P| = 2
A = np.array([[-1.0, 0.0], [1.0, 0.0]])


def _system(mech, nodes_axes=("P",)):
    return map_system(mech, f"velocity:{nodes_axes[0]}.x", f"velocity:{nodes_axes[0]}.y")


def _ik(p, signs, a=A, l1=L1, l2=L2):
    """Elbows B_i of a five-bar with end-effector p (closed form), or None when a leg does not reach."""
    out = []
    for k in range(2):
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
