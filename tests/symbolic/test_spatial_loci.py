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
GENERAL = ROOT / "tests/solutions/models/gough_stewart_66.toml"
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
