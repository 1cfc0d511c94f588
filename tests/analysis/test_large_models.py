"""Large models (issue 19): the sparse path against closed forms, the dense path and itself scaled.

The frameworks come from the generators of ``benchmarks/bench_large.py`` (the benchmark's
own); the cases here have about 300 nodes (above the size switch, fast), the 10,000-node
case is the benchmark's only.
"""
from __future__ import annotations

import glob
import importlib.util
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.analysis import sparse
from symkin.analysis.classification import classify
from symkin.analysis.motion_space import model_rows
from symkin.errors import ModelError
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.numeric.sparse_rows import sparse_constraint_rows
from symkin.report import LISTED, SUMMARISED, render_text
from symkin.tolerances import DEFAULT

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("bench_large", ROOT / "benchmarks" / "bench_large.py")
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def _models():
    out = [(name, catalogue.get(name)) for name in catalogue.names()]
    out += [(Path(p).name, symkin.read_model(p)) for p in sorted(glob.glob(str(ROOT / "tests/**/models/*.toml"),
                                                                            recursive=True))]
    return out


def _span_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance of an orthonormal basis of span(a) from span(b) (inf when the dimensions differ)."""
    if a.shape[1] != b.shape[1]:
        return math.inf
    if a.shape[1] == 0:
        return 0.0
    qa, qb = np.linalg.qr(a)[0], np.linalg.qr(b)[0]
    return float(np.abs(qa - qb @ (qb.T @ qa)).max())


def _stress_matrix(relations, labels) -> np.ndarray:
    index = {label: k for k, label in enumerate(labels)}
    out = np.zeros((len(labels), len(relations)))
    for c, rel in enumerate(relations):
        for label, v in rel.coefficients:
            out[index[label], c] = v
    return out


def _both(mech):
    return classify(model_rows(mech), DEFAULT), classify(sparse.sparse_rows(mech), DEFAULT)


# ---------------------------------------------------------------------- the two paths agree
@pytest.mark.parametrize("name,mech", _models(), ids=[n for n, _ in _models()])
def test_sparse_path_equals_dense_path_on_every_catalogue_and_test_model(name, mech):
    d, s = _both(mech)
    assert (s.dof, s.motion.rank, s.redundant_constraints, s.types) == \
        (d.dof, d.motion.rank, d.redundant_constraints, d.types)
    assert _span_distance(d.motion.V, s.motion.V) <= 1e-10
    labels = sorted({label for a in (d, s) for r in a.self_stresses for label, _ in r.coefficients})
    assert _span_distance(_stress_matrix(d.self_stresses, labels), _stress_matrix(s.self_stresses, labels)) <= 1e-10
    assert s.input_rank == d.input_rank and s.output_rank == d.output_rank


@pytest.mark.parametrize("name", catalogue.names())
def test_sparse_rows_are_the_dense_rows_where_no_body_takes_the_o_k_form(name):
    mech = catalogue.get(name)
    big = [ln for ln, ns in mech.links if len(ns) > mech.dim + 1]
    rows = sparse_constraint_rows(mech)
    if big:
        pytest.skip(f"{name}: body {big[0]} takes the O(k) form")
    dense = constraint_rows(mech)
    assert rows.owners == dense.owners
    assert np.array_equal(rows.matrix.toarray(), dense.matrix)


def _body_model(dim, points, fixed, extra_links=None):
    nodes = {f"P{k}": list(p) for k, p in enumerate(points)}
    links = {"body": list(nodes)}
    links.update(extra_links or {})
    return symkin.Mechanism.from_dict({"dim": dim, "mobility": 0, "fixed": fixed, "nodes": nodes, "links": links})


BODIES = {
    # a planar body of 7 nodes pinned at one node and barred at another: 1 flex → 0, a stress in the bar pair
    "planar body": _body_model(2, [(0, 0), (2, 0), (3, 1), (1, 2), (0, 3), (2.5, 2.5), (1, 1)], ["P0"],
                               {"b1": ["P1", "P6"]}),
    "planar body, three fixed nodes": _body_model(2, [(0, 0), (2, 0), (3, 1), (1, 2), (0, 3), (1, 1)],
                                                  ["P0", "P1", "P4"]),
    "collinear body": _body_model(2, [(0, 0), (1, 0), (2.5, 0), (4, 0), (5, 0)], ["P0"]),
    "spatial body": _body_model(3, [(0, 0, 0), (2, 0, 0), (0, 2, 0), (0, 0, 2), (1, 1, 1), (2, 2, 0.5),
                                    (0.5, 2, 2), (1, 0, 1.5)], ["P0", "P1"]),
    "coplanar spatial body": _body_model(3, [(0, 0, 0), (2, 0, 0), (0, 2, 0), (1, 1, 0), (2, 2, 0), (3, 1, 0)],
                                         ["P0", "P1", "P2"]),
    "spatial rod": _body_model(3, [(0, 0, 0), (1, 1, 1), (2, 2, 2), (3, 3, 3)], ["P0"]),
}


@pytest.mark.parametrize("name", list(BODIES))
def test_o_k_body_rows_give_the_pairwise_form_s_motion_space_and_stress_count(name):
    """A body of k nodes in 2k − 3 / 3k − 6 rows: the same flexes and the same number of
    self-stresses as the k(k − 1)/2 pair rows, whose internal stresses are artefacts."""
    mech = BODIES[name]
    d, s = _both(mech)
    assert (s.dof, s.motion.rank, s.redundant_constraints, s.types) == \
        (d.dof, d.motion.rank, d.redundant_constraints, d.types)
    assert _span_distance(d.motion.V, s.motion.V) <= 1e-10
    k = len(mech.nodes)
    rows = sparse_constraint_rows(mech).matrix.shape[0]
    hull = np.linalg.matrix_rank(np.array([c for _, c in mech.nodes]) - mech.nodes[0][1])
    expected = {(2, 2): 2 * k - 3, (2, 1): 2 * k - 3, (3, 3): 3 * k - 6, (3, 2): 3 * k - 6, (3, 1): 3 * k - 5}
    assert rows - (len(mech.links) - 1) == expected[(mech.dim, hull)]


def test_body_rows_of_a_body_pinned_at_two_nodes_flex_about_their_axis():
    """Closed form: a rigid body in space held at two nodes turns about their line (1 flex)."""
    a = symkin.analyze(symkin.Mechanism.from_dict(bench.rigid_body(1000, dim=3)))
    assert (a.dof, a.types, a.redundant_constraints) == (1, ("IM",), 0)
    v = a.motion.V[:, 0].reshape(-1, 3)
    assert np.abs(v[:, 0]).max() <= 1e-9 and np.abs(v[:, 1]).max() <= 1e-9  # z only: about the x axis Z0-Z1


# ---------------------------------------------------------------------- closed forms
def _strip(n_nodes, extra=0, **kw):
    """A triangulated strip of 2 × n/2 nodes: 2n − 3 bars, statically determinate when pinned."""
    return symkin.Mechanism.from_dict(bench.planar_truss(n_nodes // 2, 2, extra=extra, **kw))


def test_a_statically_determinate_truss_has_no_flex_and_no_self_stress():
    mech = _strip(300)
    assert sparse.is_large(mech)
    assert len(mech.links) == 2 * 300 - 3
    a = symkin.analyze(mech)
    assert (a.dof, a.types, a.redundant_constraints, len(a.self_stresses)) == (0, (), 0, 0)
    assert a.motion.sparse is not None
    assert "statically determinate" in render_text(a)


@pytest.mark.parametrize("extra", [1, 7, 40])
def test_each_added_bar_adds_one_self_stress_on_its_cell(extra):
    mech = _strip(300, extra=extra)
    a = symkin.analyze(mech)
    assert (a.dof, a.redundant_constraints, len(a.self_stresses)) == (0, extra, extra)
    # a braced cell (4 sides, 2 diagonals) is a K4: its one stress is on those 6 bars (elementary geometry),
    # 5 of them for the first cell, whose bottom bar joins the two fixed nodes (it is not a constraint then)
    sizes = sorted(r.r for r in a.self_stresses)
    assert sizes in ([6] * extra, [5] + [6] * (extra - 1))


def test_grid_truss_self_stress_count_and_equilibrium():
    """A triangulated nx × ny grid pinned at one bar: (nx − 2)(ny − 2) self-stresses (a wheel round
    every interior node); each stress balances at every free node (checked from the coordinates)."""
    data = bench.planar_truss(15, 20)
    mech = symkin.Mechanism.from_dict(data)
    a = symkin.analyze(mech)
    assert (a.dof, a.redundant_constraints) == (0, 13 * 18)
    free = set(data["nodes"]) - set(data["fixed"])
    for rel in a.self_stresses:
        force = {n: np.zeros(2) for n in free}
        for bar, w in rel.coefficients:
            i, j = data["links"][bar]
            u = np.subtract(data["nodes"][j], data["nodes"][i])
            u = u / np.linalg.norm(u)
            if i in force:
                force[i] += w * u
            if j in force:
                force[j] -= w * u
        assert max(np.abs(f).max() for f in force.values()) <= 1e-9 * max(abs(w) for _, w in rel.coefficients)


def test_spatial_truss_counts():
    """Freudenthal grid of 5 × 5 × 4 nodes pinned at a triangle (generic: moved by up to 10 %): rigid
    (a shellable tetrahedral complex), so its self-stresses are the rows beyond the rank 3n − 9."""
    data = bench.spatial_truss(5, 5, 4)
    mech = symkin.Mechanism.from_dict(data)
    d, s = _both(mech)
    n, bars = len(data["nodes"]), len(data["links"])
    assert d.dof == s.dof == 0
    # bars between two fixed nodes touch no free coordinate; the others have rank 3n − 9 (3n − 6, 3 pinned)
    grounded = sum(1 for a, b in data["links"].values() if {a, b} <= set(data["fixed"]))
    assert grounded == 2
    assert s.redundant_constraints == d.redundant_constraints == (bars - grounded) - (3 * n - 9)
    # the same stresses (the dense canonical form rounds its entries at 1e-8 of the largest)
    labels = sorted({label for a in (d, s) for r in a.self_stresses for label, _ in r.coefficients})
    assert _span_distance(_stress_matrix(d.self_stresses, labels), _stress_matrix(s.self_stresses, labels)) <= 1e-8


# ---------------------------------------------------------------------- invariance
@pytest.mark.parametrize("spacing,angle", [(1000.0, 0.0), (1.0, 0.7), (0.001, 2.2)])
def test_large_case_is_scale_and_rotation_invariant(spacing, angle):
    base = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20, extra=5)))
    moved = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20, extra=5, spacing=spacing,
                                                                         angle=angle)))
    assert (moved.dof, moved.redundant_constraints, moved.types) == (base.dof, base.redundant_constraints, base.types)
    assert moved.singular_values[0] == pytest.approx(base.singular_values[0], rel=1e-9)
    labels = sorted({label for a in (base, moved) for r in a.self_stresses for label, _ in r.coefficients})
    assert _span_distance(_stress_matrix(base.self_stresses, labels),
                          _stress_matrix(moved.self_stresses, labels)) <= 1e-9


# ---------------------------------------------------------------------- reports
def test_text_report_summarises_and_json_lists_every_stress():
    a = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20)))
    text = render_text(a)
    assert "234 redundant constraints" in text
    assert f"the first {SUMMARISED} are shown" in text
    assert text.count("  self-stress ") == SUMMARISED and 234 > LISTED
    d = json.loads(json.dumps(a.to_dict()))
    assert d["redundant_constraints"] == len(d["self_stresses"]) == 234
    assert all(rel for rel in d["self_stresses"])


# ---------------------------------------------------------------------- the fuzz case and refusals
def test_a_rigid_body_of_1000_nodes_analyses_through_the_command_line(tmp_path):
    path = tmp_path / "body.json"
    path.write_text(json.dumps(bench.rigid_body(1000)))
    proc = subprocess.run([sys.executable, "-m", "symkin", "analyze", "--json", str(path)],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout)
    assert (out["dof"], out["redundant_constraints"], out["types"]) == (0, 0, [])


def test_a_model_too_large_for_the_dense_path_is_refused_with_its_size(tmp_path):
    """Two bodies of 700 nodes sharing two nodes (not taken by the sparse path): refused, exit 2."""
    nodes = {f"A{k}": [float(k % 37), float(k // 37)] for k in range(700)}
    nodes.update({f"B{k}": [100.0 + k % 37, float(k // 37)] for k in range(698)})
    data = {"dim": 2, "mobility": 0, "fixed": ["A0", "A1"], "nodes": nodes,
            "links": {"left": [f"A{k}" for k in range(700)],
                      "right": ["A698", "A699"] + [f"B{k}" for k in range(698)]}}
    with pytest.raises(ModelError) as err:
        symkin.analyze(symkin.Mechanism.from_dict(data))
    message = str(err.value)
    assert "GiB" in message and "limit of 2 GiB" in message and "left and right share" in message
    path = tmp_path / "two.json"
    path.write_text(json.dumps(data))
    proc = subprocess.run([sys.executable, "-m", "symkin", "analyze", str(path)], capture_output=True, text=True,
                          cwd=ROOT)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and "limit of 2 GiB" in proc.stderr


def _bad_choice(a, count, regularisation):
    """A wrong choice of dependent rows: the first ``count`` (the grid's lower part); the rows left are
    not a basis, so SuperLU or the checks of the stresses reject the choice."""
    return np.arange(count)


def _no_repair(a, guess, null):
    raise RuntimeError("no partial-pivoting repair in this test")


def test_a_poor_choice_of_rows_falls_back_to_the_dense_stresses(monkeypatch):
    data = bench.planar_truss(15, 20)
    mech = symkin.Mechanism.from_dict(data)
    d = classify(model_rows(mech), DEFAULT)
    monkeypatch.setattr(sparse, "sparse_dependent_rows", _bad_choice)
    monkeypatch.setattr(sparse, "pivoted_dependent_rows", _no_repair)
    a = symkin.analyze(mech)
    assert a.redundant_constraints == len(a.self_stresses) == 234 and not a.warnings
    assert a.self_stresses.choice == "dense"
    labels = sorted({label for x in (a, d) for r in x.self_stresses for label, _ in r.coefficients})
    assert _span_distance(_stress_matrix(d.self_stresses, labels), _stress_matrix(a.self_stresses, labels)) <= 1e-8


def test_stresses_are_counted_not_listed_when_the_dense_fallback_does_not_fit(monkeypatch):
    import symkin.model.validation as validation

    mech = symkin.Mechanism.from_dict(bench.planar_truss(15, 20))
    monkeypatch.setattr(sparse, "sparse_dependent_rows", _bad_choice)
    monkeypatch.setattr(sparse, "pivoted_dependent_rows", _no_repair)
    monkeypatch.setattr(validation, "DENSE_ANALYSIS_BYTES", 1000)
    a = symkin.analyze(mech)
    assert (a.dof, a.redundant_constraints, len(a.self_stresses)) == (0, 234, 0)
    assert any("234 self-stresses are counted but not listed" in w for w in a.warnings)
    # the repair is not even tried: a listing of stresses reaching half the rows would not fit the limit
    assert a.self_stresses.choice == "unlisted" and any("above the limit of" in w for w in a.warnings)
    assert "234 redundant constraints (self-stresses counted, not listed: see the warning)." in render_text(a)
    assert json.loads(json.dumps(a.to_dict()))["redundant_constraints"] == 234


def test_partial_pivoting_repairs_an_ill_conditioned_choice_of_rows():
    """Rows 0, 1, 2 nearly dependent (row 0 = row 1 + row 2 + 1e-11): a guess keeping them all as the
    basis is nonsingular but has condition ~1e11; the repaired basis is well-conditioned, and the
    rows it sets aside are as many as guessed."""
    from symkin.numeric.sparse_rows import pivoted_dependent_rows

    rng = np.random.default_rng(3)
    a = rng.standard_normal((12, 5))
    a[0] = a[1] + a[2] + 1e-11 * rng.standard_normal(5)
    guess = np.arange(5, 12)
    assert np.linalg.cond(a[:5]) > 1e9
    dependent = pivoted_dependent_rows(a, guess, np.zeros((5, 0)))
    basis = np.setdiff1d(np.arange(12), dependent)
    assert dependent.size == 7 and np.linalg.cond(a[basis]) < 1e3
    # with a right null space: the column it makes dependent is dropped (rank 4 of 5 columns)
    b = np.hstack([a[:, :4], a[:, :1] + a[:, 1:2]])
    null = np.linalg.svd(b)[2][-1:].T
    dependent = pivoted_dependent_rows(b, np.arange(4, 12), null)
    basis = np.setdiff1d(np.arange(12), dependent)
    assert dependent.size == 8 and np.linalg.matrix_rank(b[basis]) == 4


def test_a_spatial_truss_whose_ldlt_choice_fails_is_listed_by_partial_pivoting():
    """A Freudenthal grid of 9 × 9 × 9 nodes (seed 1): the LDLᵀ pivots of its Gram matrix choose rows
    whose stresses fail the rank test after the first ones; the partial-pivoting choice lists all
    (bars − 2) − (3n − 9) of them (closed form, rigid), each in equilibrium at every free node (the
    equilibrium matrix built here from the coordinates), independent (rank of the listed stresses)."""
    data = bench.spatial_truss(9, 9, 9)
    mech = symkin.Mechanism.from_dict(data)
    a = symkin.analyze(mech)
    assert a.motion.sparse is not None and a.dof == 0
    n, bars = len(data["nodes"]), len(data["links"])
    stresses = tuple(a.self_stresses)
    assert a.self_stresses.choice == "pivoted"
    assert a.redundant_constraints == len(stresses) == (bars - 2) - (3 * n - 9)
    equilibrium, names = _equilibrium(data)
    s = _stress_matrix(stresses, names)
    assert (np.abs(equilibrium @ s).max(axis=0) <= 1e-9 * np.abs(s).max(axis=0)).all()
    assert np.linalg.matrix_rank(s) == len(stresses)


# ---------------------------------------------------------------------- local self-stresses
def _equilibrium(data) -> tuple[np.ndarray, list[str]]:
    """The equilibrium matrix (free coordinates × bars) built here from the node coordinates."""
    dim = data["dim"]
    names = list(data["links"])
    free = {name: k for k, name in enumerate(sorted(set(data["nodes"]) - set(data["fixed"])))}
    out = np.zeros((dim * len(free), len(names)))
    for c, bar in enumerate(names):
        i, j = data["links"][bar]
        u = np.subtract(data["nodes"][j], data["nodes"][i])
        u = u / np.linalg.norm(u)
        for node, sign in ((i, 1.0), (j, -1.0)):
            if node in free:
                out[dim * free[node]: dim * free[node] + dim, c] = sign * u
    return out, names


def _check_listed_stresses(data, a) -> np.ndarray:
    """Count = deficit, each stress in equilibrium (independent computation), rank of the set = count."""
    stresses = tuple(a.self_stresses)
    assert len(stresses) == a.redundant_constraints
    eq, names = _equilibrium(data)
    s = _stress_matrix(stresses, names)
    assert (np.abs(eq @ s).max(axis=0) <= 1e-9 * np.abs(s).max(axis=0)).all()
    assert np.linalg.matrix_rank(s) == len(stresses)
    # the closed form of a rigid framework: bars touching a free node, minus dim · free nodes
    grounded = sum(1 for x, y in data["links"].values() if {x, y} <= set(data["fixed"]))
    assert a.dof == 0 and len(stresses) == len(names) - grounded - eq.shape[0]
    return s


@pytest.mark.parametrize("cells", [150, 400])
def test_local_stresses_of_a_braced_strip_stay_on_their_cell_whatever_its_length(cells):
    """A strip of 2 × cells nodes with 25 cells braced twice: 25 stresses, each on the 6 bars of its
    braced cell (a K4: elementary geometry), 5 where that cell's bottom bar joins the fixed nodes."""
    data = bench.planar_truss(cells, 2, extra=25)
    a = symkin.analyze(symkin.Mechanism.from_dict(data))
    _check_listed_stresses(data, a)
    assert a.self_stresses.is_local == [True] * 25
    assert max(r.r for r in a.self_stresses) <= 6


def test_local_stresses_of_a_grid_have_a_support_independent_of_its_size():
    """Triangulated grids of 15 × 20 and 30 × 30 nodes (+ 20 braced cells): the stresses are local
    (most: a wheel round an interior node is 12 bars, the patches mix two), their support bounded by
    the same constant at both sizes; the few dependent rows without one within the patch limit keep
    their fundamental stress.  The set is a basis (rank), in equilibrium, as many as the deficit."""
    from symkin.numeric.sparse_rows import LOCAL_PATCH_ROWS

    bound = {}
    for nx, ny, extra in [(15, 20, 0), (25, 25, 20)]:
        data = bench.planar_truss(nx, ny, extra=extra)
        a = symkin.analyze(symkin.Mechanism.from_dict(data))
        _check_listed_stresses(data, a)
        flags = a.self_stresses.is_local
        assert sum(flags) >= 0.9 * len(flags)
        sizes = [r.r for r, local in zip(a.self_stresses, flags) if local]
        bound[nx] = (max(sizes), float(np.percentile(sizes, 90)))
    # 90 % of the local stresses on at most 19 bars (two wheels), at both sizes; all within a patch
    assert bound[15][1] <= 19 and bound[25][1] <= 19
    assert max(bound[15][0], bound[25][0]) <= LOCAL_PATCH_ROWS


def test_local_stresses_are_unit_triangular_on_the_dependent_rows():
    """Each listed stress has 1 on its own dependent row and 0 on the later ones (hence independent)."""
    a = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20, extra=5)))
    st = a.self_stresses
    tuple(st)
    dependent = st._dependent
    coords = np.zeros((len(st), dependent.size))
    for i, (rows, coef) in enumerate(st._raw):
        at = {r: c for r, c in zip(rows.tolist(), coef.tolist())}
        coords[i] = [at.get(r, 0.0) for r in dependent.tolist()]
    assert np.array_equal(np.diag(coords), np.ones(len(st)))
    assert not np.triu(coords, 1).any()


def test_local_stresses_are_the_same_in_mm_and_in_m():
    m = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20, extra=5)))
    mm = symkin.analyze(symkin.Mechanism.from_dict(bench.planar_truss(15, 20, extra=5, spacing=1000.0)))
    assert len(tuple(m.self_stresses)) == len(tuple(mm.self_stresses)) == 239
    assert mm.self_stresses.is_local == m.self_stresses.is_local and sum(m.self_stresses.is_local) >= 200
    for x, y in zip(m.self_stresses, mm.self_stresses):
        assert [label for label, _ in x.coefficients] == [label for label, _ in y.coefficients]
        assert np.allclose([v for _, v in x.coefficients], [v for _, v in y.coefficients], rtol=1e-8, atol=1e-10)


def test_local_stresses_of_a_spatial_truss():
    """A Freudenthal grid of 6 × 6 × 5 nodes: (bars − 2) − (3n − 9) stresses (closed form), listed,
    mostly local, in equilibrium, independent; their span is the dense path's."""
    data = bench.spatial_truss(6, 6, 5)
    mech = symkin.Mechanism.from_dict(data)
    a = symkin.analyze(mech)
    assert a.motion.sparse is not None
    s = _check_listed_stresses(data, a)
    flags = a.self_stresses.is_local
    assert sum(flags) >= 0.8 * len(flags)
    assert np.median([r.r for r in a.self_stresses]) <= 150
    d = classify(model_rows(mech), DEFAULT)
    names = list(data["links"])
    # the dense canonical (echelon) form rounds its entries at 1e-8 of its largest, here ~1e3
    assert _span_distance(_stress_matrix(d.self_stresses, names), s) <= 1e-7
