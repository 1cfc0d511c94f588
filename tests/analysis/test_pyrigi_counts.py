"""PyRigi's counts, unchanged (issue 19): self-stresses and infinitesimal motions on 90 bar frameworks.

PyRigi 1.3 (``pyrigi``, in the ``test`` extra; skipped cleanly without it) is independent
truth: its ``Framework.stresses`` and ``Framework.inf_flexes(include_trivial=True)``
(numerical) give the number of self-stresses and of infinitesimal motions (trivial ones
included: the frameworks are not pinned, as symkin's DOF of an unpinned model counts them).
Both of symkin's paths — the dense one (the paper's pairwise rows, one SVD) and the
sparse one of large models (:mod:`symkin.analysis.sparse`) — must give PyRigi's numbers, in
metres and in millimetres (the coordinates × 1000).

The frameworks:

* PyRigi's ``frameworkDB`` (its own realisations), planar and spatial;
* PyRigi's ``graphDB`` graphs, realised in the plane and in space at seeded random
  coordinates (three decimals: generic);
* the bar frameworks of ``tests/analysis/test_statics.py``, and the catalogue's and the test
  models' bar-only models (links of two nodes, no sliders), unpinned.
"""
from __future__ import annotations

import glob
import zlib
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.analysis import sparse
from symkin.analysis.classification import classify
from symkin.analysis.motion_space import model_rows
from symkin.model import catalogue
from symkin.tolerances import DEFAULT

ROOT = Path(__file__).resolve().parents[2]


def _db_cases():
    """PyRigi's ``frameworkDB``: (constructor, arguments); K_n and C_n in space only for n <= 4 (PyRigi's limit)."""
    cases = [("Complete", (n,), {"dim": d}) for n in range(3, 8) for d in (2, 3) if d == 2 or n <= 4]
    cases += [("Cycle", (n,), {"dim": d}) for n in (4, 5, 6) for d in (2, 3) if d == 2 or n <= 4]
    cases += [("Wheel", (n,), {}) for n in (4, 5, 6, 7)] + [("Frustum", (n,), {}) for n in (3, 4, 5)]
    cases += [("CompleteBipartite", (a, b), {}) for a, b in ((3, 3), (3, 4), (4, 4))]
    cases += [(name, (), {}) for name in ("Square", "Diamond", "K33plusEdge", "ThreePrism", "ThreePrismPlusEdge",
                                          "Cube", "Octahedron", "Icosahedron", "Dodecahedron", "SecondOrderRigid",
                                          "CnSymmetricFourRegular", "CnSymmetricWithFixedVertex")]
    return cases


#: PyRigi's ``graphDB`` graphs realised at random coordinates, each in the plane and in space
_GRAPHS = [("Complete", (n,)) for n in (5, 6, 8)] + [("CompleteMinusOne", (n,)) for n in (5, 6, 7)] + \
    [("CompleteBipartite", ab) for ab in ((3, 3), (3, 4), (4, 4), (4, 6))] + \
    [("Wheel", (6,)), ("Cycle", (6,)), ("Path", (5,)), ("Grid", (3, 4)), ("CubeWithDiagonal", ()),
     ("DoubleBanana", ()), ("K66MinusPerfectMatching", ()), ("ThreeConnectedR3Circuit", ()),
     ("Dodecahedral", ()), ("Icosahedral", ()), ("Octahedral", ()), ("DiamondWithZeroExtension", ()),
     ("ThreePrismPlusTriangleOnSide", ()), ("K33plusEdge", ()), ("ThreePrism", ())]


def _cases():
    """(id, source, ...): everything is built lazily in the test (PyRigi may be absent)."""
    out = [(f"db-{n}{a}{k.get('dim', '')}", "db", (n, a, k)) for n, a, k in _db_cases()]
    out += [(f"graph-{n}{a}-{d}d", "graph", (n, a, d)) for n, a in _GRAPHS for d in (2, 3)]
    from tests.analysis.test_statics import FRAMEWORKS

    out += [(f"statics-{name}", "statics", (name,)) for name in FRAMEWORKS]
    models = [(name, lambda name=name: catalogue.get(name)) for name in catalogue.names()]
    models += [(Path(p).name, lambda p=p: symkin.read_model(p))
               for p in sorted(glob.glob(str(ROOT / "tests/**/models/*.toml"), recursive=True))]
    for name, load in models:
        try:
            mech = load()
        except Exception:  # noqa: BLE001 — a model the reader refuses is not a framework here
            continue
        if mech.links and all(len(ns) == 2 for _, ns in mech.links) and not getattr(mech, "sliders", ()):
            out.append((f"model-{name}", "model", (mech,)))
    return out


CASES = _cases()


def test_at_least_68_frameworks():
    assert len(CASES) >= 68


def _framework(source, args):
    """(points {name: coordinates}, bars [(a, b)], dim) of one case."""
    if source == "db":
        import pyrigi.frameworkDB as db

        name, a, k = args
        fw = getattr(db, name)(*a, **k)
        pts = {f"V{v}": [float(c) for c in p] for v, p in fw.realization(as_points=True, numerical=True).items()}
        return pts, [(f"V{a}", f"V{b}") for a, b in fw.graph.edges], len(next(iter(pts.values())))
    if source == "graph":
        import pyrigi.graphDB as gdb

        name, a, dim = args
        graph = getattr(gdb, name)(*a)
        rng = np.random.default_rng(zlib.crc32(f"{name}{a}{dim}".encode()))  # seeded by the case
        pts = {f"V{v}": np.round(rng.uniform(-5, 5, dim), 3).tolist() for v in graph.nodes}
        return pts, [(f"V{a}", f"V{b}") for a, b in graph.edges], dim
    if source == "statics":
        from tests.analysis.test_statics import FRAMEWORKS

        nodes, bars = FRAMEWORKS[args[0]]
        return {n: list(map(float, x)) for n, x in nodes.items()}, [(b[0], b[1]) for b in bars], 2
    mech = args[0]
    return {n: list(map(float, x)) for n, x in mech.nodes}, [tuple(ns) for _, ns in mech.links], mech.dim


def _pyrigi_counts(points, bars):
    from pyrigi import Framework, Graph

    graph = Graph(bars)
    graph.add_nodes_from(points)
    fw = Framework(graph, points)
    return len(fw.stresses(numerical=True)), len(fw.inf_flexes(include_trivial=True, numerical=True))


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_stress_and_motion_counts_equal_pyrigi_s_in_m_and_in_mm(case):
    pytest.importorskip("pyrigi")
    _, source, args = case
    points, bars, dim = _framework(source, args)
    stresses, motions = _pyrigi_counts(points, bars)
    for scale in (1.0, 1000.0):  # metres, millimetres
        mech = symkin.Mechanism.from_dict({
            "dim": dim, "mobility": 0, "nodes": {n: [scale * c for c in x] for n, x in points.items()},
            "links": {f"e{k}": list(b) for k, b in enumerate(bars)}})
        for rows in (model_rows(mech), sparse.sparse_rows(mech)):
            a = classify(rows, DEFAULT)
            assert (a.redundant_constraints, len(tuple(a.self_stresses)), a.dof) == (stresses, stresses, motions), \
                f"scale {scale}, {'sparse' if rows.sparse is not None else 'dense'} path"
