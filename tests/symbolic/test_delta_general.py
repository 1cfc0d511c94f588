"""The Delta's type-2 locus at constant height for general float data (issue 17 §5).

The 120° Delta of ``tests/workspace/truth.py`` (16-digit cos/sin of 120°, 240°, arm angles from
``arccos``) and an asymmetric Delta written with floats (three arm directions, arm lengths, bar
lengths, platform offsets and arm angles all different) are taken at their face value: the arms'
elimination by values (:func:`symkin.symbolic.pose_loci.eliminate_arms`) gives one curve of
degree 48.  Truth as in ``test_spatial_loci``: the inverse kinematics by elementary geometry, per
leg both elbow solutions (8 working modes) and the type-2 condition det[C_i − B_i] = 0; the
polynomial's real roots on lines x = const are where some mode's det vanishes, the points between
them are not, and every sign change of a mode's det is a sign change of the polynomial.
"""
from __future__ import annotations

import itertools
import math
import random
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.kinds import Kind
from symkin.model.labels import parse_label
from symkin.symbolic.loci import _LOCUS_LABELS, implicit_loci
from symkin.symbolic.model import symbolic_model
from symkin.symbolic.pose_loci import (
    _interpolate_triangle,
    _newton_1d,
    eliminate_arms,
    factor_list,
    pose_condition,
    translation_slice,
)
from symkin.tolerances import Tolerances
from tests.symbolic.test_spatial_loci import delta_mode_dets, mode_sign_changes_on_polynomial

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "workspace"))
from truth import Delta

XP, YP = sp.symbols("x_P y_P", real=True)
Z = -2.2


def delta_120(scale: float = 1.0) -> symkin.Mechanism:
    return symkin.Mechanism.from_dict(Delta().model((0.1, -0.05, Z), scale=scale))


def delta_asymmetric() -> symkin.Mechanism:
    """Arms at 7°, 131°, 244° (base radii 1.03, 0.97, 1.01), arm lengths 0.93, 1.07, 1.01, platform
    offsets 0.29, 0.33, 0.27, parallelogram widths 0.4, 0.35, 0.45, arm angles 37.3°, 52.9°, 44.1°."""
    phis, radii = (7.0, 131.0, 244.0), (1.03, 0.97, 1.01)
    arms, plats, widths = (0.93, 1.07, 1.01), (0.29, 0.33, 0.27), (0.4, 0.35, 0.45)
    thetas = (37.3, 52.9, 44.1)
    p = np.array([0.05, 0.02, Z])
    nodes, links = {"P": p}, {}
    for k, (phi, rad, la, rp, w, th) in enumerate(zip(phis, radii, arms, plats, widths, thetas), 1):
        u = np.array([math.cos(math.radians(phi)), math.sin(math.radians(phi)), 0.0])
        t = np.array([-u[1], u[0], 0.0])
        a = rad * u
        b = a + la * (math.cos(math.radians(th)) * u - math.sin(math.radians(th)) * np.array([0.0, 0.0, 1.0]))
        c = p + rp * u
        nodes[f"A{k}"], nodes[f"A{k}b"] = a, a + t
        for sign, tag in ((-1, "a"), (1, "b")):
            nodes[f"B{k}{tag}"], nodes[f"C{k}{tag}"] = b + sign * 0.5 * w * t, c + sign * 0.5 * w * t
            links[f"bar{k}{tag}"] = [f"B{k}{tag}", f"C{k}{tag}"]
        links[f"arm{k}"] = [f"A{k}", f"A{k}b", f"B{k}a", f"B{k}b"]
    links["platform"] = [f"C{k}{t}" for k in (1, 2, 3) for t in "ab"] + ["P"]
    return symkin.Mechanism.from_dict({
        "name": "asymmetric Delta", "dim": 3, "fixed": [f"A{k}{t}" for k in (1, 2, 3) for t in ("", "b")],
        "mobility": 3, "inputs": [{"rotation": f"arm{k}", "axis": [f"A{k}", f"A{k}b"]} for k in (1, 2, 3)],
        "outputs": [{"velocity": "P"}], "links": links,
        "nodes": {n: [float(v) for v in x] for n, x in nodes.items()}})


def type2(mech: symkin.Mechanism, method: str = "values") -> sp.Expr:
    coords = [parse_label(mech, v, "coordinate", _LOCUS_LABELS) for v in ("velocity:P.x", "velocity:P.y")]
    held = parse_label(mech, "velocity:P.z", "coordinate", _LOCUS_LABELS)
    ps = translation_slice(mech, coords, [(held, None)], Tolerances().geometry)
    assert ps is not None and [leg.link for leg in ps.legs] == ["arm1", "arm2", "arm3"]
    det, contents = pose_condition(symbolic_model(mech, coordinates="nodes"), ps, Kind.DKP_INPUT)
    assert all(c == 1 for c in contents)
    poly, _ = eliminate_arms(det, ps, method=method)
    return poly


@pytest.fixture(scope="module", params=["120", "asymmetric"])
def general(request):
    mech = delta_120() if request.param == "120" else delta_asymmetric()
    return mech, type2(mech), request.param


def _real_roots_y(poly: sp.Expr, x) -> list[float]:
    p = sp.Poly(sp.expand(poly.xreplace({XP: sp.Rational(x)})), YP)
    return [float((a + b) / 2) for (a, b), _ in p.intervals(eps=sp.Rational(1, 10 ** 14))]


def test_general_delta_locus_has_degree_48_and_float_data(general):
    _, poly, _ = general
    p = sp.Poly(poly, XP, YP)
    assert p.total_degree() == 48 and p.degree(XP) == p.degree(YP) == 48
    assert max(len(str(abs(c))) for c in p.coeffs()) > 500  # the 16-digit data, not snapped
    _, fl = factor_list(sp.Poly(poly, XP, YP, domain="QQ"))  # irreducible (certified)
    assert [(f.total_degree(), m) for f, m in fl] == [(48, 1)]


LINES = ("-1.0", "-0.6", "0.1")  # x = const: each crosses type-2 curves of both models inside the workspace


def test_general_delta_roots_are_a_working_modes_coplanar_bars(general):
    """Real roots on x = const: some mode's det[C_i − B_i] vanishes; at the roots of the polynomial
    shifted by 1e-5 in y, and at the midpoints between roots, none does."""
    mech, poly, name = general
    checked = off = shifted = 0
    for xv in LINES:
        ys = _real_roots_y(poly, xv)
        assert ys
        for y in ys:
            dets = delta_mode_dets(mech, float(xv), y, Z)
            if dets is None:
                continue
            checked += 1
            assert min(abs(d) for d in dets) < 1e-8, (xv, y, dets)
            # the roots of the polynomial shifted by ±1e-5 in y: no mode is singular there (the asymmetric
            # Delta; the 120° one's symmetry makes three modes' curves cross x = const within 1e-9 of each
            # other and a fourth touch it, so a point 1e-5 away can be within 1e-9 of singular)
            for moved in (y - 1e-5, y + 1e-5) if name == "asymmetric" else ():
                dets = delta_mode_dets(mech, float(xv), moved, Z)
                if dets is not None:
                    shifted += 1
                    assert min(abs(d) for d in dets) > 1e-9, (xv, moved, dets)
        for y0, y1 in itertools.pairwise(ys):
            dets = delta_mode_dets(mech, float(xv), 0.5 * (y0 + y1), Z)
            if dets is not None and abs(y1 - y0) > 1e-3:
                off += 1
                assert min(abs(d) for d in dets) > 1e-6, (xv, 0.5 * (y0 + y1), dets)
    assert checked >= 6 and off >= 3 and (shifted >= 8 or name != "asymmetric")


def test_general_delta_locus_contains_every_working_modes_curve(general):
    """Each sign change of a mode's det along x = const (bisected, by geometry) is one of the polynomial."""
    mech, poly, _ = general
    assert mode_sign_changes_on_polynomial(mech, poly, tuple(map(float, LINES)), np.linspace(-1.6, 1.6, 161), Z,
                                           1e-9, 1200) >= 8


def test_general_delta_locus_in_mm_is_the_metre_locus_scaled():
    """The model in mm (its floats rounded again: not an exact multiple): the same real roots, x 1000."""
    a, b = type2(delta_120()), type2(delta_120(1000.0))
    for xv in ("-0.3", "0.1"):
        ra = _real_roots_y(a, xv)
        rb = _real_roots_y(b, sp.Rational(xv) * 1000)
        assert len(ra) == len(rb) >= 2
        assert np.allclose(np.array(rb) / 1000.0, ra, rtol=0, atol=1e-9)


def test_values_and_resultants_give_the_same_polynomial():
    """The short-decimal Delta of examples/: the elimination by values is the symbolic one up to a constant."""
    mech = symkin.read_model(ROOT / "examples" / "delta.json")
    a, b = (sp.Poly(type2(mech, m), XP, YP) for m in ("values", "resultants"))
    assert a.total_degree() == 48
    assert (a * b.LC() - b * a.LC()).is_zero


def test_interpolation_helpers_recover_a_polynomial():
    rnd = random.Random(3)
    n = 9
    coeffs = {(i, j): rnd.randint(-10 ** 30, 10 ** 30) for i in range(n + 1) for j in range(n + 1 - i)}
    vals = np.zeros((n + 1, n + 1), dtype=object)
    x0, y0 = -4, 7
    for i in range(n + 1):
        for j in range(n + 1 - i):
            vals[i, j] = sum(c * (x0 + i) ** a * (y0 + j) ** b for (a, b), c in coeffs.items())
    got = _interpolate_triangle(vals, n, x0, y0)
    scale = math.factorial(n) ** 2
    assert got == {m: scale * c for m, c in coeffs.items() if c}
    uni = [rnd.randint(-100, 100) for _ in range(12)]
    assert _newton_1d([sum(c * t ** k for k, c in enumerate(uni)) for t in range(12)]) == uni


@pytest.mark.slow
def test_general_delta_conditions_end_to_end():
    """``implicit_loci`` (as ``symkin conditions --in``) on the 120° Delta: one irreducible curve of
    degree 48 (DKP-input), one quartic per leg (DKP-output), one irreducible curve of degree 48 (IM)."""
    loci = implicit_loci(delta_120(), ("velocity:P.x", "velocity:P.y"), hold=("velocity:P.z",), time_limit=120)
    inp = loci[Kind.DKP_INPUT]
    assert [f.degree for f in inp.factors] == [48] and not inp.trivial
    assert [f.degree for f in loci[Kind.DKP_OUTPUT].factors] == [4, 4, 4]
    assert [f.degree for f in loci[Kind.IM].factors] == [48] and not loci.skipped


# ------------------------------------------------------------ the constraint singularity (IM)


def delta_pose_nodes(mech: symkin.Mechanism, x: float, y: float, z: float, mode: int):
    """The model's nodes with P at (x, y, z) in working mode ``mode`` (bit k: leg k's elbow), by geometry;
    None where a leg does not reach."""
    q = {n: np.array(v, float) for n, v in mech.nodes}
    shift = np.array([x, y, z]) - q["P"]
    nodes = {n: v for n, v in q.items()}
    for n in ("P", "C1a", "C1b", "C2a", "C2b", "C3a", "C3b"):
        nodes[n] = q[n] + shift
    for k in (1, 2, 3):
        a, t = q[f"A{k}"], q[f"A{k}b"] - q[f"A{k}"]
        t = t / np.linalg.norm(t)

        def turned(node, th, a=a, t=t):
            rr = q[node] - a
            par, perp = t * (t @ rr), rr - t * (t @ rr)
            return a + par + math.cos(th) * perp + math.sin(th) * np.cross(t, perp)

        rr = q[f"B{k}a"] - a
        par, perp = t * (t @ rr), rr - t * (t @ rr)
        side = np.cross(t, perp)
        w = nodes[f"C{k}a"] - a - par
        l2 = np.sum((q[f"C{k}a"] - q[f"B{k}a"]) ** 2)
        alpha, beta, gamma = 2 * (w @ perp), 2 * (w @ side), w @ w + perp @ perp - l2
        rho = math.hypot(alpha, beta)
        if abs(gamma) > rho:
            return None
        th = math.atan2(beta, alpha) + (1 if mode >> (3 - k) & 1 == 0 else -1) * math.acos(gamma / rho)
        nodes[f"B{k}a"], nodes[f"B{k}b"] = turned(f"B{k}a", th), turned(f"B{k}b", th)
    return {n: [float(c) for c in v] for n, v in nodes.items()}


def test_constraint_condition_is_where_the_platform_can_turn_im():
    """The IM locus of ``symkin conditions`` (``implicit_loci``) on the asymmetric float Delta, the
    eliminated det[w_i × u_i]: one irreducible curve of degree 48; at its real roots on x = const one
    working mode is IM for the numeric core (4 motions, the platform turns), and at points 1e-3 off the
    roots none is."""
    mech = delta_asymmetric()
    locus = implicit_loci(mech, ("velocity:P.x", "velocity:P.y"), hold=("velocity:P.z",), kinds=(Kind.IM,),
                          time_limit=120)[Kind.IM]
    assert [f.degree for f in locus.factors] == [48] and not locus.trivial
    poly = locus.factors[0].polynomial
    hits = misses = 0
    for xv in ("-1.0", "0.6"):
        for y in _real_roots_y(poly, xv):
            kinds = []
            for mode in range(8):
                nodes = delta_pose_nodes(mech, float(xv), y, Z, mode)
                if nodes is not None:
                    a = symkin.analyze(mech.with_coordinates(nodes))
                    kinds.append((a.dof, Kind.IM in a.types))
            assert (4, True) in kinds, (xv, y, kinds)
            hits += 1
            for moved in (y - 1e-3, y + 1e-3):
                for mode in range(8):
                    nodes = delta_pose_nodes(mech, float(xv), moved, Z, mode)
                    if nodes is not None:
                        a = symkin.analyze(mech.with_coordinates(nodes))
                        assert a.dof == 3 and Kind.IM not in a.types, (xv, moved, mode, a.types)
                        misses += 1
    assert hits >= 4 and misses >= 16


def test_factor_list_agrees_with_sympy():
    """The certified shortcut gives sympy's answer for an irreducible polynomial; a product (not
    certifiable) goes to sympy."""
    from symkin.symbolic.pose_loci import _certified_irreducible

    irreducible = sp.Poly(sp.Rational(3, 7) * (6 * XP ** 4 + 4 * XP ** 2 * YP ** 2 - 2 * YP ** 3 + 8 * XP + 2),
                          XP, YP, domain="QQ")
    product = sp.Poly((XP ** 2 + YP ** 2 - 1) * (XP ** 3 - 2 * YP ** 2 + XP * YP + 5), XP, YP, domain="QQ")
    assert _certified_irreducible(irreducible) and not _certified_irreducible(product)
    for p in (irreducible, product):
        assert factor_list(p) == sp.factor_list(p)
