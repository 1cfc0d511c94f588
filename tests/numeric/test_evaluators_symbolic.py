"""Symbolic (sympy), numeric (core) and CasADi values agree (issue 3, requirement 5).

At the model's configuration and at random configurations on the closure manifold of
every catalogue mechanism (the symbolic rows divide by the model's link lengths, so they
are the core's unit rows where the links keep their lengths).
"""
from __future__ import annotations

import zlib

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.model.catalogue import get, names
from symkin.numeric import geometric_matrix as gm
from symkin.analysis.batch import evaluators

symbolic = pytest.importorskip("symkin.symbolic")


def _rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape, (a.shape, b.shape)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300)) if b.size else 0.0


@pytest.mark.parametrize("name", names())
def test_symbolic_numeric_and_casadi_agree(name):
    mech = get(name)
    ev = evaluators(mech)
    sm = symbolic.symbolic_model(mech, coordinates="nodes")
    labels = sm.coordinate_labels
    index = [labels.index(s.name) for s in sm.config_symbols]
    matrices = [sm.reduced_G, sm.G, sm.J]
    planar = mech.dim == 2
    if planar:
        matrices += [sm.parameter_rows(mech.inputs)[0], sm.parameter_rows(mech.outputs)[0]]
    f = sp.lambdify(sm.config_symbols, matrices, "numpy")
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    q = ev.project(ev.q0 + 0.05 * mech.length_scale * rng.standard_normal((10, ev.nf)), tol=1e-14)
    q = np.vstack([ev.q0, q])
    worst = 0.0
    for k in range(q.shape[0]):
        xyz = ev.coordinates(q[k]).ravel()
        sym = [np.array(m, dtype=float) for m in f(*xyz[index])]
        mk = ev.mechanism_at(q[k])
        cas_g = ev("G", q[k])
        cas_p = ev("parameters", q[k])
        core = [gm.geometric_matrix(mk, reduced=True), gm.geometric_matrix(mk)]
        for s, c, x in zip(sym[:2], core, (cas_g["G"], cas_g["G_full"])):
            worst = max(worst, _rel(s, c), _rel(x, c), _rel(s, x))
        # constraint rows: G = JᵀJ on both sides (row signs of degenerate bodies are free)
        worst = max(worst, _rel(sym[2].T @ sym[2], ev("J", q[k])["J"].T @ ev("J", q[k])["J"]))
        if planar:
            for s, x, params in ((sym[3], cas_p["inputs"], mk.inputs), (sym[4], cas_p["outputs"], mk.outputs)):
                c = gm.parameters_matrix(mk, params)[0]
                worst = max(worst, _rel(s.reshape(c.shape), c), _rel(x, c))
    assert worst <= 1e-12, f"{name}: {worst:.3e}"
    assert len(sm.row_owners) == len(ev.row_owners)
    assert set(sm.row_owners) == set(ev.row_owners)


def test_symbolic_im_condition_vanishes_where_the_kernel_says_im():
    """The flattened four-bar: the symbolic IM condition and the CasADi IM indicator are zero."""
    mech = get("fourbar_flat")
    sm = symbolic.symbolic_model(mech, coordinates="nodes")
    ev = evaluators(mech)
    res = ev.batch(ev.q0)
    assert res.im[0] and res.im_indicator[0] <= 1e-30
    if not hasattr(sm, "im_condition"):
        pytest.skip("symbolic IM condition not available")
    cond = sm.im_condition()
    expr = getattr(cond, "expression", None)
    if expr is None:
        pytest.skip("the IM condition has no single expression to evaluate")
    value = sm.evaluate(expr)
    assert abs(value) <= 1e-12
    generic = get("fourbar_appendix")
    sm2 = symbolic.symbolic_model(generic, coordinates="nodes")
    assert symkin.analyze(generic).dof == 1
    assert abs(sm2.evaluate(getattr(sm2.im_condition(), "expression"))) > 1e-6
