"""Branch points located to rounding (deflation at tangent contacts) and the half-branches leaving them.

Independent truth, by elementary geometry:

* the double butterfly's contacts T1, T2 with its LIM branch (``papers_examples/README_paths.md``):
  the wing at rest on the ground triangle, the upper kite turned about P1 = Q1 until C = P2, the
  coupler, the crank and link3 one body about P2 with the crank along P2 → P1 (T1) or P1 → P2 (T2);
  on the LIM branch C stays at P2 and the wing, the upper triangle, link1 and link2 do not move;
* a change-point four-bar (s + l = p + q) flattened on its ground line: two branches crossing
  transversally (the two assembly modes).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin import Mechanism
from symkin.model.model_file import read_model
from symkin.paths.system import make_curve
from symkin.curves.branches import HALF_BRANCH_RADIUS, half_branches
from symkin.curves.locate import locate_singular_point as locate_branch_point
from tests.conftest import EXAMPLES


def _rotate(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _angle(u, w):
    return math.atan2(u[0] * w[1] - u[1] * w[0], u[0] * w[0] + u[1] * w[1])


def contact(mech: Mechanism, sign: float) -> dict:
    """T1 (sign +1: crank along P2 → P1) or T2 (sign −1) of the double butterfly, by elementary geometry."""
    x = {n: np.array(c, float) for n, c in mech.coordinates().items()}
    p1, p2, c0 = x["P1"], x["P2"], x["C"]
    out = dict(x)
    turn = _angle(c0 - p1, p2 - p1)          # the upper kite about P1 until C reaches P2
    out["C"] = p2.copy()
    for n in ("U1", "U2"):
        out[n] = p1 + _rotate(x[n] - p1, turn)
    crank = _angle(x["V1"] - c0, sign * (p1 - p2))   # coupler + crank + link3 about P2
    for n in ("V1", "V2"):
        out[n] = p2 + _rotate(x[n] - c0, crank)
    return out


@pytest.fixture(scope="module")
def butterfly():
    m = read_model(EXAMPLES / "double_butterfly.toml")
    return m, make_curve(m)


def _y(curve, mech, x: dict) -> np.ndarray:
    flat = np.concatenate([x[n] for n in mech.node_names])
    return curve.y_of(flat[curve.free])


@pytest.mark.parametrize("sign", [1.0, -1.0], ids=["T1", "T2"])
def test_tangent_contact_located_to_rounding_by_deflation(butterfly, sign):
    m, curve = butterfly
    exact = _y(curve, m, contact(m, sign))
    assert float(np.max(np.abs(curve.residual(exact)))) <= 1e-14          # the construction closes
    rng = np.random.default_rng(7)
    for _ in range(3):
        start = exact + 1e-5 * rng.standard_normal(exact.size)         # a trace's event is 1e-6..1e-5 off
        bp = locate_branch_point(curve, start)
        assert bp.converged and bp.deflations == 2
        assert float(np.max(np.abs(bp.y - exact))) <= 1e-14
        assert bp.residual <= 1e-15
    # without deflation (Newton on the singular system) the same start stays ~1e-8 off: what deflation buys
    plain = locate_branch_point(curve, start, max_deflations=0)
    assert plain.deflations == 0 and float(np.max(np.abs(plain.y - exact))) > 1e-12


@pytest.mark.parametrize("sign", [1.0, -1.0], ids=["T1", "T2"])
def test_four_half_branches_at_a_tangent_contact_one_pair_on_the_lim_branch(butterfly, sign):
    m, curve = butterfly
    x = contact(m, sign)
    y0 = _y(curve, m, x)
    halves = half_branches(curve, y0)
    assert len(halves) == 4
    idx = {n: k for k, n in enumerate(m.node_names)}
    scale = m.length_scale
    chords = []
    on_lim = []
    for y in halves:
        assert float(np.max(np.abs(curve.residual(y)))) <= 1e-13
        xs = curve.x_of(y)
        assert abs(float(np.linalg.norm(y - y0)) - HALF_BRANCH_RADIUS) <= 1e-3   # the null-plane circle (+ O(ρ²))
        chords.append((y - y0) / np.linalg.norm(y - y0))
        # LIM branch: C stays at P2, the wing and the upper triangle do not move
        c_at_p2 = float(np.linalg.norm(xs[idx["C"]] - x["P2"])) <= 1e-12 * scale
        rest = all(float(np.linalg.norm(xs[idx[n]] - x[n])) <= 1e-12 * scale for n in ("Q1", "Q2", "U1", "U2"))
        assert c_at_p2 == rest
        on_lim.append(c_at_p2)
    assert sum(on_lim) == 2                                   # both halves of the LIM branch ...
    # ... and the other two (the regular loop); the branches are tangent: the halves pair up in two
    # nearly equal directions, opposite to each other
    cos = np.array([[float(a @ b) for b in chords] for a in chords])
    pairs = [(i, j) for i in range(4) for j in range(i + 1, 4) if cos[i, j] > 0.99]
    assert len(pairs) == 2 and all(on_lim[i] != on_lim[j] for i, j in pairs)
    assert all(cos[i, j] < -0.99 for i in range(4) for j in range(4) if (i, j) not in pairs and (j, i) not in pairs
               and i != j)


def fourbar(g, a, b, c, B, C):
    return Mechanism.from_dict({
        "name": "change point", "dim": 2, "fixed": ["A", "D"], "mobility": 1,
        "inputs": [{"rotation": "crank"}],
        "nodes": {"A": [0.0, 0.0], "B": list(B), "C": list(C), "D": [g, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})


def test_simple_branch_point_needs_no_deflation_and_has_two_transversal_branches():
    # g, a, b, c = 4, 1, 3, 2 (1 + 4 = 3 + 2): flat at B = (-1, 0), C = (2, 0); model at a nearby regular pose
    g, a, b, c = 4.0, 1.0, 3.0, 2.0
    phi = math.radians(170.0)
    B = np.array([a * math.cos(phi), a * math.sin(phi)])
    d = np.array([g, 0.0]) - B
    dd = float(np.linalg.norm(d))
    along = (b * b - c * c + dd * dd) / (2 * dd)
    C = B + along * d / dd + math.sqrt(b * b - along * along) * np.array([-d[1], d[0]]) / dd
    m = fourbar(g, a, b, c, B, C)
    curve = make_curve(m)
    flat = curve.y_of(np.array([-1.0, 0.0, 2.0, 0.0]))
    bp = locate_branch_point(curve, flat + 1e-3 * np.array([0.3, -0.2, 0.1, 0.4]))
    assert bp.converged and bp.deflations == 0 and float(np.max(np.abs(bp.y - flat))) <= 1e-14
    halves = half_branches(curve, bp.y)
    assert len(halves) == 4
    chords = [(y - flat) / np.linalg.norm(y - flat) for y in halves]
    # two branches through the flat pose, crossing transversally: two pairs of opposite chords
    cos = np.array([[float(u @ w) for w in chords] for u in chords])
    assert sorted(int(np.sum(cos[i] < -0.99)) for i in range(4)) == [1, 1, 1, 1]
    assert float(np.max(np.abs(cos[np.abs(cos) < 0.99]))) < 0.9
    # the two branches are the assembly modes: B and C on the same side of the ground line, or not
    sides = sorted(int(np.sign(y[1] * y[3])) for y in halves)
    assert sides == [-1, -1, 1, 1]


def test_half_branches_of_a_regular_point_is_none(butterfly):
    m, curve = butterfly
    assert half_branches(curve, curve.y0()) is None
