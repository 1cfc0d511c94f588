"""Type-2 loci of Gough–Stewart platforms at constant orientation and height (issue 17 §5).

``symkin conditions --in velocity:O.x,velocity:O.y --hold velocity:O.z --hold rotation:platform[x|y|z]``
against the 6 × 6 determinant of the legs' Plücker lines, written here independently from the
model's nodes: rows ``(C_k − A_k, A_k × C_k)`` with ``C_k = O + R (C_k⁰ − O⁰)``,
``O = (x, y, z)``.  Mayer St-Onge & Gosselin (IJRR 19(3), 2000): at constant orientation the
locus is a cubic in the position; in a plane of constant height, a cubic for a general 6-6 and a
conic when the base joints lie in a plane parallel to it (checked below on the Plücker
determinant itself, with sympy).  Compared in metres and millimetres; one root of the cubic is
confirmed by the numeric core (``symkin.analyze`` reports DKP-input there).
"""
from __future__ import annotations

import itertools
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.kinds import Kind
from symkin.symbolic.loci import implicit_loci

ROOT = Path(__file__).resolve().parents[2]
GENERAL = ROOT / "examples/gough_stewart_66.toml"
PLANAR = ROOT / "tests/workspace/models/gough_stewart.toml"
HOLDS = ("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[z]")
X, Y = sp.symbols("x_O y_O", real=True)


def _scaled(mech: symkin.Mechanism, scale: float) -> symkin.Mechanism:
    return mech.with_coordinates({n: [scale * v for v in xyz] for n, xyz in mech.nodes})


def _rot_z(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def pluecker_det(mech: symkin.Mechanism, turn_z_deg: float = 0.0) -> sp.Expr:
    """det of the six legs' Plücker lines (C − A, A × C), platform at O = (x, y, z_model), exact."""
    q = {n: [sp.Rational(repr(float(v))) for v in xyz] for n, xyz in mech.nodes}
    o = sp.Matrix([X, Y, q["O"][2]])
    rot = _rot_z(turn_z_deg)
    rows = []
    for k in range(1, 7):
        a = sp.Matrix(q[f"A{k}"])
        d = [q[f"C{k}"][i] - q["O"][i] for i in range(3)]
        if turn_z_deg:
            d = [sp.Rational(repr(float(sum(rot[i][j] * float(d[j]) for j in range(3))))) for i in range(3)]
        c = o + sp.Matrix(d)
        rows.append(list(c - a) + list(a.cross(c)))
    return sp.expand(sp.Matrix(rows).det(method="berkowitz"))


def _normalised(p: sp.Expr) -> dict:
    poly = sp.Poly(p, X, Y)
    lc = max(poly.coeffs(), key=abs)
    return {m: float(c / lc) for m, c in poly.terms()}


def _assert_proportional(a: sp.Expr, b: sp.Expr, rel: float = 1e-9) -> None:
    na, nb = _normalised(a), _normalised(b)
    assert set(na) == set(nb)
    for m in na:
        assert na[m] == pytest.approx(nb[m], rel=rel, abs=rel)


def _type2(mech, holds=HOLDS):
    loci = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=holds, time_limit=120)
    locus = loci[Kind.DKP_INPUT]
    return loci, locus


def test_pluecker_determinant_degrees_cubic_in_general_conic_for_coplanar_base():
    """The literature's degrees, on the independent determinant alone."""
    gen = pluecker_det(symkin.read_model(GENERAL))
    pla = pluecker_det(symkin.read_model(PLANAR))
    assert sp.Poly(gen, X, Y).total_degree() == 3
    assert sp.Poly(pla, X, Y).total_degree() == 2
    assert all(z == 0.0 for n, (_, _, z) in symkin.read_model(PLANAR).nodes if n.startswith("A"))


@pytest.mark.parametrize("scale", [1.0, 1000.0], ids=["m", "mm"])
@pytest.mark.parametrize("path, degree, name", [(GENERAL, 3, "degree-3 curve"), (PLANAR, 2, "conic")],
                         ids=["general", "coplanar-base"])
def test_type2_locus_is_the_pluecker_determinant(path, degree, name, scale):
    mech = _scaled(symkin.read_model(path), scale)
    loci, locus = _type2(mech)
    assert [f.degree for f in locus.factors] == [degree]
    f = locus.factors[0]
    assert f.meaning.startswith(name) and f.exponent == 1
    # every separated factor is a curve without a real point (|C_k - A_k|² at this height)
    assert all(t.trivial for t in locus.trivial)
    truth = pluecker_det(mech)
    assert sp.Poly(truth, X, Y).total_degree() == degree
    _assert_proportional(f.polynomial, truth)
    # the output (the platform's twist) is never locked out; no IM curve on the slice
    assert loci[Kind.DKP_OUTPUT].factors == () and not loci[Kind.DKP_OUTPUT].everywhere
    assert loci[Kind.IM].factors == ()
    # mm against m: the same curve, x and y scaled by 1000
    if scale != 1.0:
        _, base = _type2(symkin.read_model(path))
        _assert_proportional(f.polynomial, base.factors[0].polynomial.xreplace({X: X / scale, Y: Y / scale}))


def test_a_turned_hold_is_the_pluecker_determinant_of_the_turned_platform():
    mech = symkin.read_model(GENERAL)
    holds = ("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[z]=10")
    _, locus = _type2(mech, holds)
    assert [f.degree for f in locus.factors] == [3]
    _assert_proportional(locus.factors[0].polynomial, pluecker_det(mech, 10.0))


def _translated(mech: symkin.Mechanism, x: float, y: float) -> symkin.Mechanism:
    """The platform translated to O = (x, y, z): leg nodes D_k on A_k C_k at their bar's length."""
    p = {n: np.array(v, float) for n, v in mech.nodes}
    shift = np.array([x, y, p["O"][2]]) - p["O"]
    new = dict(p)
    for n in [f"C{k}" for k in range(1, 7)] + ["O"]:
        new[n] = p[n] + shift
    for k in range(1, 7):
        a, c = p[f"A{k}"], new[f"C{k}"]
        length = np.linalg.norm(p[f"D{k}"] - a)
        new[f"D{k}"] = a + length * (c - a) / np.linalg.norm(c - a)
    return mech.with_coordinates({n: list(v) for n, v in new.items()})


def test_a_root_of_the_cubic_is_dkp_input_for_the_numeric_core():
    mech = symkin.read_model(GENERAL)
    _, locus = _type2(mech)
    f = locus.factors[0].polynomial
    x0 = 0.1
    roots = [complex(r) for r in sp.Poly(f.xreplace({X: sp.Rational(1, 10)}), Y).nroots(n=30)]
    real = sorted((r.real for r in roots if abs(r.imag) < 1e-12), key=abs)
    assert real, "a cubic in y has a real root"
    y0 = real[0]
    at = symkin.analyze(_translated(mech, x0, y0))
    assert Kind.DKP_INPUT in at.types and at.input_rank == 5
    away = symkin.analyze(_translated(mech, x0, y0 + 0.05))
    assert Kind.DKP_INPUT not in away.types


def test_cli_prints_the_cubic_and_its_json():
    out = subprocess.run([sys.executable, "-m", "symkin", "conditions", str(GENERAL), "--in",
                          "velocity:O.x,velocity:O.y", *[a for h in HOLDS for a in ("--hold", h)], "--json"],
                         capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert out.returncode == 0, out.stderr
    import json
    data = json.loads(out.stdout)
    (dkp,) = [l for l in data["loci"] if l["kind"] == Kind.DKP_INPUT]
    assert [f["degree"] for f in dkp["factors"]] == [3]
    _assert_proportional(sp.sympify(dkp["factors"][0]["polynomial"], locals={"x_O": X, "y_O": Y}),
                         pluecker_det(symkin.read_model(GENERAL)))


def test_holds_that_do_not_fix_the_whole_orientation_are_an_error():
    mech = symkin.read_model(GENERAL)
    with pytest.raises(symkin.SymkinError, match="all three components"):
        implicit_loci(mech, ("velocity:O.x", "velocity:O.y"),
                      hold=("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "slide:s1"))


# ---------------------------------------------------------------- the Delta at constant height
#
# A Delta (3-R(SS)²) whose numbers are short decimals: arm directions (1, 0), (−0.6, ±0.8) (a
# Pythagorean layout, not 120°), arm angles with Pythagorean (cos, sin), platform at P.  Truth: the
# inverse kinematics by elementary geometry (per leg, both elbow solutions of
# ``|C − B(θ)| = l``, B turning about the arm's axis; 8 working modes) and the type-2 condition
# det[C_i − B_i] = 0 (the three bars parallel to one plane), relative to the bars' lengths.

XP, YP = sp.symbols("x_P y_P", real=True)
DELTA_Z = -2.2


def delta_model(scale: float = 1.0) -> symkin.Mechanism:
    dirs = [(1.0, 0.0), (-0.6, 0.8), (-0.6, -0.8)]
    arm_cs = [(0.6, 0.8), (0.8, 0.6), (0.28, 0.96)]
    base, arm, plat, half = 1.0, 1.0, 0.3, 0.2
    p = (0.1, -0.05, DELTA_Z)
    nodes, links = {"P": p}, {}
    for k, ((ux, uy), (c, s)) in enumerate(zip(dirs, arm_cs), 1):
        tx, ty = -uy, ux
        a = (base * ux, base * uy, 0.0)
        b = (a[0] + arm * c * ux, a[1] + arm * c * uy, -arm * s)
        cc = (p[0] + plat * ux, p[1] + plat * uy, p[2])
        nodes[f"A{k}"], nodes[f"A{k}b"] = a, (a[0] + tx, a[1] + ty, 0.0)
        for sign, tag in ((-1, "a"), (1, "b")):
            nodes[f"B{k}{tag}"] = (b[0] + sign * half * tx, b[1] + sign * half * ty, b[2])
            nodes[f"C{k}{tag}"] = (cc[0] + sign * half * tx, cc[1] + sign * half * ty, cc[2])
            links[f"bar{k}{tag}"] = [f"B{k}{tag}", f"C{k}{tag}"]
        links[f"arm{k}"] = [f"A{k}", f"A{k}b", f"B{k}a", f"B{k}b"]
    links["platform"] = [f"C{k}{t}" for k in (1, 2, 3) for t in "ab"] + ["P"]
    return symkin.Mechanism.from_dict({
        "name": "Delta", "dim": 3, "fixed": [f"A{k}{t}" for k in (1, 2, 3) for t in ("", "b")], "mobility": 3,
        "inputs": [{"rotation": f"arm{k}", "axis": [f"A{k}", f"A{k}b"]} for k in (1, 2, 3)],
        "outputs": [{"velocity": "P"}], "links": links,
        "nodes": {n: [round(v * scale, 12) for v in x] for n, x in nodes.items()}})


def delta_mode_dets(mech: symkin.Mechanism, x: float, y: float, z: float, margins: bool = False):
    """det[C_i − B_i] / Π|C_i − B_i| for the 8 working modes at P = (x, y, z); None where a leg does not reach.

    ``margins``: instead, each leg's ``1 − |γ/ρ|`` (zero where its two elbow solutions meet: the bar
    normal to the elbow's motion, type 1)."""
    q = {n: np.array(v, float) for n, v in mech.nodes}
    shift = np.array([x, y, z]) - q["P"]
    legs = []
    for k in (1, 2, 3):
        a, t = q[f"A{k}"], q[f"A{k}b"] - q[f"A{k}"]
        t = t / np.linalg.norm(t)
        b0, c0 = q[f"B{k}a"], q[f"C{k}a"]
        rr = b0 - a
        par, perp = t * (t @ rr), rr - t * (t @ rr)
        side = np.cross(t, perp)
        c = c0 + shift
        l2 = np.sum((c0 - b0) ** 2)
        w = c - a - par  # |w − cosθ perp − sinθ side|² = l²
        alpha, beta = 2 * (w @ perp), 2 * (w @ side)
        gamma = w @ w + perp @ perp - l2
        rho = math.hypot(alpha, beta)
        if margins:
            legs.append(1.0 - abs(gamma / rho))
            continue
        if abs(gamma) > rho:
            return None
        phi, delta = math.atan2(beta, alpha), math.acos(gamma / rho)
        legs.append([c - (a + par + math.cos(th) * perp + math.sin(th) * side) for th in (phi + delta, phi - delta)])
    if margins:
        return legs
    out = []
    for d1 in legs[0]:
        for d2 in legs[1]:
            for d3 in legs[2]:
                m = np.array([d1, d2, d3])
                out.append(float(np.linalg.det(m) / np.prod(np.linalg.norm(m, axis=1))))
    return out


@pytest.fixture(scope="module")
def delta_locus():
    mech = delta_model()
    loci = implicit_loci(mech, ("velocity:P.x", "velocity:P.y"), hold=("velocity:P.z",), time_limit=120)
    return mech, loci


def _real_roots_y(poly: sp.Expr, x: sp.Rational) -> list[float]:
    p = sp.Poly(sp.expand(poly.xreplace({XP: x})), YP)
    return [float((a + b) / 2) for (a, b), _ in p.intervals(eps=sp.Rational(1, 10 ** 14))]


def test_delta_type2_locus_at_constant_height_is_the_bars_coplanarity_of_some_working_mode(delta_locus):
    mech, loci = delta_locus
    locus = loci[Kind.DKP_INPUT]
    assert len(locus.factors) == 1 and not locus.trivial
    f = locus.factors[0]
    assert f.degree == 48 and f.meaning.startswith("24-circular curve of degree 48")
    checked = off = 0
    for xv in (sp.Rational(-3, 10), sp.Rational(1, 10), sp.Rational(7, 20)):
        ys = _real_roots_y(f.polynomial, xv)
        assert ys
        for y in ys:
            dets = delta_mode_dets(mech, float(xv), y, DELTA_Z)
            if dets is None:
                continue
            checked += 1
            assert min(abs(d) for d in dets) < 1e-8, (float(xv), y, dets)
        for y0, y1 in itertools.pairwise(ys):
            dets = delta_mode_dets(mech, float(xv), 0.5 * (y0 + y1), DELTA_Z)
            if dets is not None and abs(y1 - y0) > 1e-3:
                off += 1
                assert min(abs(d) for d in dets) > 1e-6, (float(xv), 0.5 * (y0 + y1), dets)
    assert checked >= 6 and off >= 3


def mode_sign_changes_on_polynomial(mech, poly, lines, ys, z, h: float, dps: int) -> int:
    """How many sign changes of a working mode's det along the lines ``x = const`` (bisected, by
    geometry) there are; each is asserted to be a sign change of ``poly`` (at ``y0 ± h``, ``dps`` digits)."""
    import mpmath

    f = sp.lambdify((XP, YP), poly, "mpmath")
    found = 0
    for xv in lines:
        vals = [delta_mode_dets(mech, xv, y, z) for y in ys]
        for k in range(len(ys) - 1):
            if vals[k] is None or vals[k + 1] is None:
                continue
            for mode in range(8):
                if vals[k][mode] * vals[k + 1][mode] >= 0:
                    continue
                lo, hi = ys[k], ys[k + 1]
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    v = delta_mode_dets(mech, xv, mid, z)
                    if v is None:
                        break
                    lo, hi = (lo, mid) if v[mode] * vals[k][mode] < 0 else (mid, hi)
                y0 = mpmath.mpf(0.5 * (lo + hi))
                with mpmath.workdps(dps):
                    assert f(mpmath.mpf(xv), y0 - h) * f(mpmath.mpf(xv), y0 + h) < 0, (xv, float(y0), mode)
                found += 1
    return found


def test_delta_type2_locus_contains_every_working_modes_curve(delta_locus):
    """Where a mode's det changes sign along x = const (bisected, by geometry), the polynomial changes sign too."""
    mech, loci = delta_locus
    poly = loci[Kind.DKP_INPUT].factors[0].polynomial
    assert mode_sign_changes_on_polynomial(mech, poly, (-0.3, 0.1, 0.35), np.linspace(-1.2, 1.2, 241), DELTA_Z,
                                           1e-7, 60) >= 8


def test_delta_type2_locus_in_mm_is_the_metre_locus_scaled():
    a = delta_model()
    b = delta_model(1000.0)
    fa = implicit_loci(a, ("velocity:P.x", "velocity:P.y"), hold=("velocity:P.z",),
                       kinds=(Kind.DKP_INPUT,), time_limit=120)[Kind.DKP_INPUT].factors
    fb = implicit_loci(b, ("velocity:P.x", "velocity:P.y"), hold=("velocity:P.z",),
                       kinds=(Kind.DKP_INPUT,), time_limit=120)[Kind.DKP_INPUT].factors
    assert [f.degree for f in fa] == [f.degree for f in fb] == [48]
    pa = sp.Poly(fa[0].polynomial, XP, YP)
    pb = sp.Poly(sp.expand(fb[0].polynomial.xreplace({XP: 1000 * XP, YP: 1000 * YP})), XP, YP)
    assert pa.monoms() == pb.monoms()
    ratio = pb.LC() / pa.LC()
    assert all(cb == ratio * ca for ca, cb in zip(pa.coeffs(), pb.coeffs()))


def test_delta_type1_locus_is_where_a_legs_two_elbows_meet(delta_locus):
    """DKP-output (platform still, an arm turns): one quartic per leg (a section of the torus that the bar's
    end sweeps), zero where that leg's two elbow solutions coincide."""
    mech, loci = delta_locus
    locus = loci[Kind.DKP_OUTPUT]
    assert [f.degree for f in locus.factors] == [4, 4, 4] and not locus.trivial
    assert [f.degree for f in loci[Kind.IM].factors] == [48] and not loci.skipped  # det[w_i x u_i]: the platform turns
    for k, f in enumerate(locus.factors):
        hits = set()
        for xv in (sp.Rational(-3, 10), sp.Rational(1, 10)):
            for y in _real_roots_y(f.polynomial, xv):
                m = delta_mode_dets(mech, float(xv), y, DELTA_Z, margins=True)
                leg = int(np.argmin(np.abs(m)))
                assert abs(m[leg]) < 1e-9, (k, float(xv), y, m)
                hits.add(leg)
        assert len(hits) == 1  # one leg per factor


def test_delta_route_applies_only_to_parallelograms():
    """A bar moved off its parallelogram (the platform could turn): the translating route declines."""
    from symkin.model.labels import parse_label
    from symkin.symbolic.loci import _LOCUS_LABELS
    from symkin.symbolic.pose_loci import translation_slice
    from symkin.tolerances import Tolerances

    good = delta_model()
    nodes = {n: list(v) for n, v in good.nodes}
    nodes["C1b"][2] += 0.01
    bad = good.with_coordinates(nodes)
    for mech, applies in ((good, True), (bad, False)):
        coords = [parse_label(mech, v, "coordinate", _LOCUS_LABELS) for v in ("velocity:P.x", "velocity:P.y")]
        held = parse_label(mech, "velocity:P.z", "coordinate", _LOCUS_LABELS)
        ps = translation_slice(mech, coords, [(held, None)], Tolerances().geometry)
        assert (ps is not None) == applies
        if applies:
            assert [leg.link for leg in ps.legs] == ["arm1", "arm2", "arm3"]
