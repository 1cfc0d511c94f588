"""The square DKP system: its determinant is the velocity equation's with the parameter row appended."""
from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from symkin.model import catalogue
from symkin.numeric.coordinates import input_coordinates
from symkin.paths.trace import trace
from symkin.solutions.dkp_system import block_triangular, dkp_system, rate_row


def full_determinant(mech, c, system):
    """det[∂Φ/∂u; p(u)] in the full free coordinates (every closure equation, no elimination), numerically."""
    u = list(system.closure.unknowns)
    eqs = [e for _, e in system.closure.equations]
    jac = sp.lambdify([u], sp.Matrix(eqs).jacobian(u), "numpy")
    row = sp.lambdify([u], rate_row(mech, c), "numpy")
    return lambda x: float(np.linalg.det(np.vstack([np.array(jac(x), float), np.array(row(x), float)])))


@pytest.mark.parametrize("name", ["fourbar_appendix", "watt_sixbar"])
def test_determinant_equals_the_full_velocity_equation_up_to_a_constant(name):
    m = catalogue.get(name)
    for c in input_coordinates(m) + input_coordinates(m, m.outputs):
        s = dkp_system(m, c)
        d = sp.lambdify([list(s.unknowns)], s.equations[-1], "numpy")
        full = full_determinant(m, c, s)
        rng = np.random.default_rng(3)
        ratios = []
        for _ in range(4):
            v = rng.standard_normal(len(s.unknowns))
            ratios.append(full(s.closure.recover(v)) / float(d(v)))
        assert np.allclose(ratios, ratios[0], rtol=1e-8) and abs(ratios[0]) > 1e-12


def test_watt_sixbar_determinant_splits_by_loops():
    m = catalogue.get("watt_sixbar")
    s = dkp_system(m, input_coordinates(m)[0])
    assert len(s.factors) == 3 and s.degree == 6
    assert sum(2 ** len(s.curve) * sp.Poly(f, *s.unknowns).total_degree() for f in s.factors) == 192


def test_block_triangular_of_a_triangular_pattern():
    x = sp.Symbol("x")
    rows = [[x, 0, 0], [1, x, 1], [2, 1, x]]
    blocks = sorted((sorted(r), sorted(c)) for r, c in block_triangular(rows))
    assert blocks == [([0], [0]), ([1, 2], [1, 2])]


def test_determinant_vanishes_at_the_traced_dkp_output_configurations():
    m = catalogue.get("fourbar_appendix")
    out = input_coordinates(m, m.outputs)[0]
    s = dkp_system(m, out)
    d = sp.lambdify([list(s.unknowns)], s.equations[-1], "numpy")
    path = trace(m, stop=2 * math.pi)
    events = [e for e in path.singular_events() if e.kind == "DKP-output"]
    assert len(events) == 2
    index = [list(s.closure.unknowns).index(v) for v in s.unknowns]
    scale = s.closure.scale
    for e in events:
        q = np.concatenate([e.coordinates[m.node_index()[n]] for n in m.free_nodes])
        u = (q - np.tile(s.closure.center, len(m.free_nodes))) / scale
        v = u[index]
        assert abs(float(d(v))) <= 1e-10


def test_a_block_constant_on_the_curve_is_not_solved():
    """The crank's own block of a four-bar, 2 |B − A|² / ℓ² in B's coordinates, is never zero on the curve: left out."""
    from symkin.solutions.homotopy import total_degree

    m = catalogue.get("fourbar_appendix")
    s = dkp_system(m, input_coordinates(m)[0])
    assert len(s.factors) == 2 and len(s.constant) == 1
    (k,) = s.constant
    assert {str(x) for x in k.free_symbols} == {"u_x_B", "u_y_B"}
    b = np.array(m.coordinates()["B"]) - np.array(m.coordinates()["A"])
    center, scale = s.closure.center, s.closure.scale
    at = {sp.Symbol("u_x_B"): (m.coordinates()["B"][0] - center[0]) / scale,
          sp.Symbol("u_y_B"): (m.coordinates()["B"][1] - center[1]) / scale}
    assert abs(abs(float(k.subs(at))) - 2 * float(b @ b) / scale**2) <= 1e-12
    (system,) = s.systems()
    assert total_degree(list(system), list(s.unknowns)) == 16
