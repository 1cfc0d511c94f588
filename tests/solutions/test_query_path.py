"""The faster later query of ``symkin modes`` (issue 17) gives the same answers as the slow one.

Two shortcuts of :mod:`symkin.solutions.solve_all` are checked against what they replace: the
checks' Jacobian built equation by equation from polynomials (against sympy's
``Matrix.jacobian``), and the labelling of the real solutions by the batch's exact path
(:func:`symkin.analysis.batch.exact_indicators`) when the evaluators' batch kernel is not built
(against the batch kernel's signs and types), the value-free equations read back from the
artefact cache (against freshly made ones), and a later query that reads its plan back
(:mod:`symkin.solutions.query`: only the value equations made) against the same query made from all its
equations, bit for bit.  Speed is shown in ``benchmarks/bench_solve_all.py --only query``.
"""
from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from symkin.model import catalogue
from symkin.model.model_file import read_model
from symkin.solutions.system import original_equations
from symkin.tolerances import Tolerances

solve_all_module = importlib.import_module("symkin.solutions.solve_all")
GS66 = Path(__file__).resolve().parents[2] / "examples" / "gough_stewart_66.toml"


@pytest.mark.parametrize("mech, values, unit", [
    (read_model(GS66), {f"slide:s{k}": 0.01 * k for k in range(1, 7)}, "rad"),
    (catalogue.get("rrr_3"), {"velocity:C1.x": 0.05, "velocity:C1.y": -0.05, "rotation:platform": 5}, "deg"),
    (catalogue.get("fourbar_appendix"), {"rotation:crank": 30}, "deg"),
], ids=["gough-stewart-66", "3-RRR", "four-bar"])
def test_jacobian_by_polynomials_is_sympys(mech, values, unit):
    u, eqs, _, _, _ = original_equations(mech, values, unit, Tolerances())
    exprs = [e for _, e in eqs]
    ours = solve_all_module._jacobian(exprs, list(u))
    theirs = sp.Matrix(exprs).jacobian(list(u))
    rng = np.random.default_rng(3)
    f1, f2 = sp.lambdify([u], ours, "numpy"), sp.lambdify([u], theirs, "numpy")
    for _ in range(3):
        x = rng.standard_normal(len(u)) + 1j * rng.standard_normal(len(u))
        a, b = np.array(f1(x), complex), np.array(f2(x), complex)
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(b)))


@pytest.mark.parametrize("mech, values, unit", [
    (catalogue.get("fourbar_dead_centre"), {"rotation:crank": 0}, "deg"),
    (catalogue.get("five_bar"), {"velocity:P.x": 0.1, "velocity:P.y": -0.2}, "rad"),
    (catalogue.get("rrr_3"), {"velocity:C1.x": 0.05, "velocity:C1.y": -0.05, "rotation:platform": 5}, "deg"),
    (read_model(GS66), {f"slide:s{k}": v for k, v in zip(range(1, 7), (0.08, -0.05, 0.03, 0.1, -0.07, 0.02))},
     "rad"),
], ids=["dead-centre", "five-bar", "3-RRR", "gough-stewart-66"])
def test_labels_without_the_kernel_are_the_batch_kernels(mech, values, unit, monkeypatch, tmp_path):
    """The same signs and IM / DKP types whether the real solutions are labelled by the batch kernel
    or, before it is built, by the batch's exact path (one with a dead centre; the 6-6's two
    solutions have opposite DKP-input signs)."""
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    method = "parameter" if mech.dim == 3 else "total-degree"
    monkeypatch.setattr(solve_all_module, "_kernel_ready", lambda ev: False)   # the exact path
    by_exact = solve_all_module.solve_all(mech, values, unit=unit, method=method)
    monkeypatch.setattr(solve_all_module, "_kernel_ready", lambda ev: True)    # the batch kernel
    by_kernel = solve_all_module.solve_all(mech, values, unit=unit, method=method)
    assert len(by_kernel.solutions) == len(by_exact.solutions) > 0

    def flat(s):
        return np.concatenate([s.configuration[n] for n in mech.free_nodes])

    for a in by_kernel.solutions:
        gaps = [np.max(np.abs(flat(a) - flat(b))) for b in by_exact.solutions]
        b = by_exact.solutions[int(np.argmin(gaps))]
        assert min(gaps) <= 1e-9 * mech.length_scale
        assert a.types == b.types and a.signs == b.signs
    if "dead centre" in mech.name:
        assert sorted(s.types for s in by_exact.solutions) == [(), ("DKP-output",)]
    if mech.dim == 3:
        assert sorted(s.signs["dkp_input"] for s in by_exact.solutions) == [-1, 1]


def test_cached_equations_are_the_fresh_ones(tmp_path, monkeypatch):
    """The value-free equations of a query are read back from the artefact cache at the next
    query (a new value, the same file) and evaluate as the freshly made ones, Jacobian too."""
    from symkin.solutions.system import PolynomialSystem

    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    mech = read_model(GS66)
    rng = np.random.default_rng(5)
    for k, shift in enumerate((0.01, -0.03)):
        values = {f"slide:s{i}": shift * i for i in range(1, 7)}
        u, eqs, filters, center, scale = original_equations(mech, values, "rad", Tolerances())
        system = PolynomialSystem(mech, center, scale, tuple(u), tuple(eqs), tuple(filters), (), (), None)
        cached = solve_all_module._compiled_equations(system, cache=True)
        files = list((tmp_path / "query-checks").glob("*.py"))
        assert len(files) == 1  # one file for both queries: the value equations are not in it
        fresh = solve_all_module._lambdified([e for _, e in eqs], list(u))
        for _ in range(2):
            x = rng.standard_normal(len(u)) + 1j * rng.standard_normal(len(u))
            for a, b in zip(cached, fresh):
                va, vb = np.array(a(x), complex), np.array(b(x), complex).reshape(np.shape(a(x)))
                assert np.max(np.abs(va - vb)) <= 1e-12 * max(1.0, np.max(np.abs(vb)))


@pytest.mark.parametrize("path, first, later, unit", [
    ("examples/rpr_3.toml", {"slide:s1": 0.1, "slide:s2": -0.2, "slide:s3": 0.05},
     {"slide:s1": 0.3, "slide:s2": 0.2, "slide:s3": -0.1}, "rad"),
    ("examples/fivebar.toml", {"velocity:P.x": 0.1, "velocity:P.y": -0.2},
     {"velocity:P.x": -0.05, "velocity:P.y": 0.1}, "rad"),
    ("papers_examples/fourbar_appendix.toml", {"rotation:crank": 30}, {"rotation:crank": -75}, "deg"),
], ids=["3-RPR-slides", "five-bar-point", "four-bar-angle"])
def test_planned_query_is_the_full_one_bit_for_bit(path, first, later, unit, tmp_path, monkeypatch):
    """A later query that reads the value-free equations back (symkin.solutions.query) gives the same
    numbers, bit for bit, as the same query made from all its equations: configurations, residuals,
    counts and labels (the output of ``symkin modes`` prints rounding-level digits)."""
    from symkin.solutions import query

    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    mech = read_model(Path(__file__).resolve().parents[2] / path)
    solve_all_module.solve_all(mech, first, unit=unit, method="parameter")  # start solutions and the plan
    assert list((tmp_path / "query-plans").glob("*.npz")) and list((tmp_path / "query-checks").glob("*.py"))
    full_calls = []
    real_full = solve_all_module._full_query
    monkeypatch.setattr(solve_all_module, "_full_query", lambda *a, **k: full_calls.append(1) or real_full(*a, **k))
    planned = solve_all_module.solve_all(mech, later, unit=unit, method="parameter")
    assert not full_calls  # read back: only the value equations were made
    for f in (tmp_path / "query-plans").glob("*.npz"):
        f.unlink()
    full = solve_all_module.solve_all(mech, later, unit=unit, method="parameter")
    assert full_calls == [1]
    assert planned.method == full.method == "parameter" and len(planned.solutions) > 0
    for key in ("complex", "near_real", "at_infinity", "filtered", "rejected", "unverified", "paths", "failed",
                "unknowns", "equations"):
        assert getattr(planned, key) == getattr(full, key), key
    assert len(planned.solutions) == len(full.solutions)
    for a, b in zip(planned.solutions, full.solutions):
        assert a.configuration == b.configuration  # exact floats
        assert (a.residual, a.closure, a.signs, a.types, a.multiplicity) == \
            (b.residual, b.closure, b.signs, b.types, b.multiplicity)
    assert query.plan_file(mech, list(later), Tolerances()).exists()  # made again by the full query


def test_plan_that_does_not_fit_is_not_used(tmp_path, monkeypatch):
    """A plan whose owners differ from the query's value equations (here: doctored) is not used: the
    query is made from all its equations, with the same answer."""
    from symkin.solutions import query

    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    mech = read_model(Path(__file__).resolve().parents[2] / "examples" / "rpr_3.toml")
    values = {"slide:s1": 0.1, "slide:s2": -0.2, "slide:s3": 0.05}
    before = solve_all_module.solve_all(mech, values, method="parameter")
    path = query.plan_file(mech, list(values), Tolerances())
    plan = query.load_plan(path)
    query.save_plan(path, query.QueryPlan(plan.fixed_rows, plan.reduced_owners[::-1], plan.legs, plan.kept,
                                          plan.base, plan.original_owners))
    full_calls = []
    real_full = solve_all_module._full_query
    monkeypatch.setattr(solve_all_module, "_full_query", lambda *a, **k: full_calls.append(1) or real_full(*a, **k))
    after = solve_all_module.solve_all(mech, values, method="parameter")
    assert full_calls == [1]
    assert [s.configuration for s in after.solutions] == [s.configuration for s in before.solutions]
