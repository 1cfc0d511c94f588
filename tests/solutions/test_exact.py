"""The exact square DKP systems (msolve, the optional extra symkin[exact]) against the homotopy and geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from symkin import SymkinError
from symkin.model import catalogue
from symkin.numeric.coordinates import input_coordinates
from symkin.solutions import exact
from symkin.solutions.exact import _parse, exact_dkp_system, msolve_executable, real_solutions

needs_msolve = pytest.mark.skipif(msolve_executable() is None, reason="msolve is the optional extra symkin[exact] "
                                  "(pip install -e '.[exact]')")


def test_parse_the_three_kinds_of_answer():
    assert _parse("[-1]:", 2) == []
    with pytest.raises(SymkinError, match="not zero-dimensional"):
        _parse("[1, 2, -1, []]:", 2)
    (mid, width), = _parse("[0, [1,\n[[[3 / 2^1, 7 / 2^2], [1, 1]]]\n]]:", 2)
    assert mid.tolist() == [1.625, 1.0] and width == 0.25


def test_without_msolve_the_error_names_the_extra(monkeypatch):
    monkeypatch.setattr(exact, "msolve_executable", lambda: None)
    x = sp.Symbol("x")
    with pytest.raises(SymkinError, match=r"symkin\[exact\]|\.\[exact\]"):
        real_solutions([x**2 - 2], [x])


def test_unsupported_mechanisms_say_why():
    m = catalogue.get("rssr")
    with pytest.raises(SymkinError, match="planar mechanisms of revolute pairs"):
        exact_dkp_system(m, input_coordinates(m)[0])


@needs_msolve
def test_a_circle_and_a_line():
    x, y = sp.symbols("x y")
    sols = sorted(float(v[0]) for v, _ in real_solutions([x**2 + y**2 - 4, x - y], [x, y]))
    assert np.allclose(sols, [-math.sqrt(2), math.sqrt(2)], atol=1e-15)


@needs_msolve
@pytest.mark.parametrize("name", ["fourbar_appendix", "watt_sixbar"])
def test_exact_roots_equal_the_homotopy_roots(name):
    """The exact system's real solutions are the Bertini cross-check's, configuration by configuration."""
    pytest.importorskip("bertini", reason="the homotopy is the optional extra symkin[global]")
    from symkin.solutions.circuits import _real_roots
    from symkin.solutions.dkp_system import dkp_system
    from symkin.tolerances import DEFAULT

    m = catalogue.get(name)
    c = input_coordinates(m)[0]
    s = exact_dkp_system(m, c)
    assert s.constant == 1  # the crank's own block, 2 |B − A|², is a constant on the curve
    got = [s.place(v) for eqs in s.systems() for v, w in real_solutions(list(eqs), s.unknowns)]
    ref, _ = _real_roots(dkp_system(m, c), DEFAULT)
    assert len(got) == len(ref)
    free = m.free_nodes
    for r in ref:
        q = np.concatenate([r[n] for n in free])
        assert min(float(np.max(np.abs(np.concatenate([g[n] for n in free]) - q))) for g in got) <= 1e-9
