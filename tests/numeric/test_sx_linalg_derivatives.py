"""Derivatives of the indicator kernel where an entry pair, a norm or a discriminant vanishes.

A bar exactly parallel to an axis zeroes entries of the constraint rows: a Givens radius
``hypot(a, b) = 0``, a reciprocal of 0, a clamped Laguerre discriminant.  Their derivatives were
``0/0 = NaN`` (curve tracing then stopped in LAPACK); now they are finite, the values unchanged, and
the derivative along every direction that keeps the bar parallel is the true one (checked against
central differences on the closure manifold).
"""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from scipy.linalg import null_space

import symkin
from symkin.numeric.evaluators import INDICATOR_NAMES, evaluators
from symkin.numeric.sx_linalg import givens_qr, root

RPR = Path(__file__).resolve().parents[1] / "workspace" / "models" / "rpr_3.toml"


def test_root_value_is_sqrt_and_derivative_finite_at_zero():
    u = ca.SX.sym("u")
    f = ca.Function("f", [u], [root(u), ca.jacobian(root(u), u), ca.sqrt(u)])
    for v in (0.0, 1e-300, 2.0, 1e300):
        r, d, s = (float(x) for x in f(v))
        assert r == s and np.isfinite(d)
    assert float(f(0.0)[1]) == 0.0


def test_givens_derivative_along_a_direction_that_keeps_the_zeros():
    """QR of a 3×2 array whose first column starts with two zeros: d(r11·r22) along directions
    that keep them zero equals the central difference; before, the derivative was NaN."""
    x = ca.SX.sym("x", 6)
    cols = [[x[0], x[1]], [x[2], x[3]], [x[4], x[5]]]
    a, _ = givens_qr(cols, 2)
    vol = a[0][0] * a[1][1]
    f = ca.Function("f", [x], [vol, ca.jacobian(vol, x)])
    x0 = np.array([0.0, 0.7, 0.0, -0.4, 1.3, 0.2])
    value, jac = f(x0)
    jac = np.array(jac).ravel()
    assert np.all(np.isfinite(jac))
    rng = np.random.default_rng(3)
    for _ in range(5):
        d = rng.standard_normal(6)
        d[[0, 2]] = 0.0  # the two zeros stay zero
        h = 1e-6
        fd = (float(f(x0 + h * d)[0]) - float(f(x0 - h * d)[0])) / (2 * h)
        assert jac @ d == pytest.approx(fd, rel=1e-8, abs=1e-12)
    # the value: |det| of the array's Gram matrix, independently
    m = x0.reshape(3, 2)
    assert abs(float(value)) == pytest.approx(np.sqrt(np.linalg.det(m.T @ m)), rel=1e-14)


@pytest.fixture(scope="module")
def rpr():
    ev = evaluators(symkin.read_model(RPR))
    q = ca.SX.sym("q", ev.nf)
    named = dict(zip(INDICATOR_NAMES, ev.symbolic_function("indicators")(q)))
    return ev, q, named


def _manifold_directions(ev, q0, keep=()):
    """Orthonormal tangent directions of the closure manifold at q0 (that keep x_a - x_b, (a, b) in keep)."""
    jac = np.asarray(ev("closure_jacobian", q0)["dphi_dq"])
    rows = [jac]
    for a, b in keep:
        r = np.zeros(ev.nf)
        r[ev.q_labels.index(a)], r[ev.q_labels.index(b)] = 1.0, -1.0
        rows.append(r[None, :])
    return null_space(np.vstack(rows))


@pytest.mark.parametrize("name,keep", [("im", ()), ("dkp_input", (("x_C3", "x_O"),)),
                                        ("dkp_output", (("x_C3", "x_O"),))])
def test_rpr_indicator_derivatives_at_an_axis_parallel_bar(rpr, name, keep):
    """The 3-RPR model: platform bar O-C3 exactly vertical (its J row has a zero entry)."""
    ev, q, named = rpr
    q0 = np.asarray(ev.q0, float).ravel()
    f = ca.Function("f", [q], [named[name], ca.jacobian(named[name], q)])
    jac = np.array(f(q0)[1]).ravel()
    assert np.all(np.isfinite(jac)), name
    h = 1e-6
    for t in _manifold_directions(ev, q0, keep).T:
        vals = [float(f(np.asarray(ev.project((q0 + s * h * t)[None, :])).ravel())[0]) for s in (1, -1)]
        fd = (vals[0] - vals[1]) / (2 * h)
        assert jac @ t == pytest.approx(fd, rel=1e-6, abs=1e-9), name
