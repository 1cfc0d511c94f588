"""A slider's rate row (the ``slide`` parameter's row) and its prescribed-slide polynomial: one definition each.

``rate_rows`` is evaluated in floats (the numeric core), CasADi SX and sympy: the three agree to
1e-12 at random configurations, in m and in mm.  Independently of the code: on every velocity
that keeps the carrying pair rigid (``ê·ẋ_A = ê·ẋ_C``) the row is the time derivative of the slide
(:meth:`slide`, by central differences), and on a fixed line it is the unit direction.
``slide_polynomial`` vanishes exactly where the slide takes the prescribed value.
"""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
import sympy as sp

from symkin.constraints import SliderMovingLine, slider_constraints
from symkin.constraints.algebra import FLOATS, Casadi, Sympy
from symkin.errors import SymkinError
from tests.constraints.test_backends import (
    MODELS,
    _dense,
    _random_configurations,
    _sx_coordinates,
    _sx_row,
)


def _sliders(mech):
    return [c for c in slider_constraints(mech) if hasattr(c, "slider")]


def _casadi_rows(con, mech, x):
    dim, n = mech.dim, len(mech.nodes)
    sym, X = _sx_coordinates(dim, n)
    out = [np.array(ca.Function("f", [sym], [_sx_row(r, dim, n)])(x.ravel())).ravel()
           for r in con.rate_rows(Casadi(), X, X)]
    return np.array(out)


def _sympy_rows(con, mech, x):
    dim, n = mech.dim, len(mech.nodes)
    syms = [tuple(sp.Symbol(f"c{k}_{a}", real=True) for a in range(dim)) for k in range(n)]
    subs = {syms[k][a]: sp.Float(float(x[k, a]), 30) for k in range(n) for a in range(dim)}
    out = []
    for r in con.rate_rows(Sympy(), syms, [tuple(map(float, c)) for c in x]):
        vec = np.zeros(dim * n)
        for k, coef, v in r.terms:
            for a in range(dim):
                vec[dim * k + a] += float((coef * v[a] / r.scale).xreplace(subs).evalf(30))
        out.append(vec)
    return np.array(out)


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("scale", [1.0, 1000.0])
def test_rate_rows_agree_and_are_the_slide_derivative(name, scale):
    mech = MODELS[name]().moved(scale=scale)
    dim, n = mech.dim, len(mech.nodes)
    rng = np.random.default_rng(5)
    checked = 0
    for con in _sliders(mech):
        if con.kind == "slider_plane":
            with pytest.raises(SymkinError, match="slide"):
                con.rate_rows(FLOATS, [], [])
            continue
        for x in _random_configurations(mech, 2, seed=9):
            X = [tuple(map(float, r)) for r in x]
            rows = np.array([_dense(r, dim, dim * n) for r in con.rate_rows(FLOATS, X, X)])
            assert _casadi_rows(con, mech, x) == pytest.approx(rows, abs=1e-12)
            assert _sympy_rows(con, mech, x) == pytest.approx(rows, abs=1e-12)
            v = rng.standard_normal(x.shape)
            if isinstance(con, SliderMovingLine):  # keep the pair A-C rigid along ê
                e = x[con.c] - x[con.a]
                u = e / np.linalg.norm(e)
                v[con.c] += (v[con.a] - v[con.c]) @ u * u
                x = x.copy()
                x[con.p] = x[con.a] + 0.37 * e  # P on the line: the slide's derivative is the rate
            else:
                assert np.linalg.norm(rows[0]) == pytest.approx(1.0, abs=1e-15)
            rows = np.array([_dense(r, dim, dim * n) for r in con.rate_rows(FLOATS, *[[tuple(r) for r in x]] * 2)])
            h = 1e-6 * mech.length_scale
            up = con.slide(FLOATS, [tuple(r) for r in x + h * v])
            down = con.slide(FLOATS, [tuple(r) for r in x - h * v])
            assert rows @ v.ravel() == pytest.approx([(up - down) / (2 * h)], rel=1e-7, abs=1e-9)
            checked += 1
    assert checked or name == "screw_jack" or name == "ground_screw"


@pytest.mark.parametrize("name", ["slider_crank", "spatial_sliders"])
def test_slide_polynomial_vanishes_at_the_prescribed_slide(name):
    mech = MODELS[name]()
    x0 = np.array([c for _, c in mech.nodes], float)
    for con in _sliders(mech):
        if con.kind == "slider_plane":
            continue
        X0 = [tuple(r) for r in x0]
        s0 = con.slide(FLOATS, X0)
        for value in (0.0, 0.21 * mech.length_scale, -0.4 * mech.length_scale):
            x = x0.copy()  # move P along its line by ``value``, the carriers kept
            d = (x0[con.c] - x0[con.a]) if isinstance(con, SliderMovingLine) else np.array(con.slider.direction)
            x[con.p] = x0[con.p] + value * d / np.linalg.norm(d)
            X = [tuple(r) for r in x]
            assert con.slide(FLOATS, X) - s0 == pytest.approx(value, abs=1e-12 * mech.length_scale)
            assert con.slide_polynomial(X, X0, value) == pytest.approx(0.0, abs=1e-12 * mech.length_scale ** 2)
            assert abs(con.slide_polynomial(X, X0, value + 0.1 * mech.length_scale)) > 1e-3 * mech.length_scale ** 1


@pytest.mark.parametrize("name", list(MODELS))
def test_slide_equation_is_the_slide_in_every_algebra(name):
    """``slide_equation`` (the loci's slide coordinate) is the slide: its numerator over its scale
    equals the projection on the line (numpy, written here) at random configurations, as floats and
    as exact sympy expressions; a slider on a plane has none (a SymkinError naming it)."""
    mech = MODELS[name]()
    n, dim = len(mech.nodes), mech.dim
    for x in _random_configurations(mech, 3, seed=7):
        x = np.asarray(x, float).reshape(n, dim)
        X = [tuple(map(float, r)) for r in x]
        for con in _sliders(mech):
            if con.kind == "slider_plane":
                with pytest.raises(SymkinError, match=con.owner):
                    con.slide_equation(FLOATS, X)
                continue
            s = con.slider
            if isinstance(con, SliderMovingLine):
                e = x[con.c] - x[con.a]
                truth = (x[con.p] - x[con.a]) @ e / np.linalg.norm(e)
            else:
                d = np.array(s.direction, float)
                truth = (x[con.p] - np.array(s.point, float)) @ d / np.linalg.norm(d)
            eq = con.slide_equation(FLOATS, X)
            assert eq.numerator / eq.denominator == pytest.approx(truth, abs=1e-12 * mech.length_scale)
            exact = con.slide_equation(Sympy(), [tuple(sp.Rational(v) for v in r) for r in X])
            assert float(exact.numerator / exact.denominator) == pytest.approx(truth, abs=1e-12 * mech.length_scale)
