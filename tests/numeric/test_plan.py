"""The per-topology fast paths of :mod:`symkin.numeric.geometric_matrix` against their plain definitions."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import (_certainly_full_hull, constraint_rows, parameter_rows,
                                             parameters_matrix, plan)
from symkin.numeric.linalg import affine_hull
from symkin.tolerances import DEFAULT

EXAMPLES = Path(__file__).resolve().parents[2] / "papers_examples"


def _models():
    yield from (catalogue.get(n) for n in catalogue.names())
    yield from (symkin.read_model(p) for p in sorted(EXAMPLES.glob("*.toml")))


@pytest.mark.parametrize("dim,k", [(2, 3), (2, 5), (3, 3), (3, 4), (3, 6)])
def test_full_hull_shortcut_never_contradicts_affine_hull(dim, k):
    """Whenever the cheap bound says "full", the SVD of affine_hull says so too (also near degeneracy)."""
    rng = np.random.default_rng(dim * 10 + k)
    tol = DEFAULT.geometry
    said_full = 0
    for flat in [0.0, 1e-9, 1e-7, 1e-6, 3e-6, 1e-5, 1e-4, 1e-3, 1e-1, 1.0]:
        for _ in range(40):
            pts = rng.standard_normal((k, dim)) * 10 ** rng.uniform(-3, 3)
            pts[:, -1] *= flat  # squeeze towards a line (2D) / plane (3D)
            if dim == 3 and k == 3:
                pts[2] = pts[0] + (pts[1] - pts[0]) * rng.uniform(-2, 2) + flat * rng.standard_normal(3)
            h, _, _ = affine_hull(pts, tol)
            if _certainly_full_hull(pts.tolist(), tol):
                said_full += 1
                assert h == min(dim, k - 1), (flat, pts)
    assert said_full > 40  # and it does take the shortcut for well-spread bodies


def test_planar_parameter_program_equals_the_stacked_rows():
    """parameters_matrix's cached program gives parameter_rows stacked, at several configurations."""
    for mech in _models():
        if mech.dim != 2:
            continue
        ev = symkin.evaluators(mech)
        rng = np.random.default_rng(0)
        qs = [ev.q0] + list(ev.q0 + 0.02 * mech.length_scale * rng.standard_normal((3, ev.nf)))
        params = list(mech.inputs) + list(mech.outputs)
        if mech.platform is not None:
            params.append(symkin.Parameter("twist", (mech.platform,)))
        if not params:  # a structure
            continue
        for q in qs:
            m = mech.with_coordinates(ev.coordinates(q))
            p, labels = parameters_matrix(m, params)
            want = np.vstack([parameter_rows(m, prm) for prm in params])
            np.testing.assert_allclose(p, want, rtol=1e-13, atol=1e-13 * np.abs(want).max())
            assert labels == tuple(lab for prm in params for lab in prm.labels(2))


def test_constraint_rows_match_bar_by_bar_unit_vectors():
    """Every bar row is +u at its first node and −u at its second (eq. A3/A4), nothing else."""
    for mech in _models():
        rows = constraint_rows(mech)
        pl = plan(mech.topology)
        x = np.array([c for _, c in mech.nodes])
        dim = mech.dim
        bars = [k for k, o in enumerate(rows.owners) if o.startswith("link") and "hull" not in o]
        assert len(bars) == pl.bar_i.size
        for k, i, j in zip(bars, pl.bar_i, pl.bar_j):
            u = (x[j] - x[i]) / np.linalg.norm(x[j] - x[i])
            want = np.zeros(rows.matrix.shape[1])
            want[dim * i: dim * i + dim], want[dim * j: dim * j + dim] = u, -u
            np.testing.assert_allclose(rows.matrix[k], want, atol=1e-15)


def test_with_coordinates_shares_the_topology_and_checks_the_coordinates():
    m = catalogue.get("fourbar_appendix")
    moved = m.with_coordinates({"B": (0.1, 1.0)})
    assert moved.topology is m.topology and moved.coordinates()["B"] == (0.1, 1.0)
    assert moved == m.with_coordinates(np.array([c for _, c in moved.nodes]))
    with pytest.raises(symkin.ModelError, match="nodes.B: coordinates must have 2 components"):
        m.with_coordinates({"B": (0.1, 1.0, 2.0)})
    with pytest.raises(symkin.ModelError, match="nodes.C: coordinates must be finite"):
        m.with_coordinates({"C": (np.inf, 1.0)})
    with pytest.raises(symkin.ModelError, match="nodes.Q: no such node"):
        m.with_coordinates({"Q": (0.0, 1.0)})
    with pytest.raises(symkin.ModelError, match="3 coordinate rows given for the 4 nodes"):
        m.with_coordinates(np.zeros((3, 2)))
    with pytest.raises(symkin.ModelError, match="nodes.A: coordinates must be numbers"):
        m.with_coordinates({"A": ("a", 0.0)})


def test_coincident_bar_nodes_name_the_bar():
    m = catalogue.get("fourbar_appendix")
    at_a = m.with_coordinates({"B": m.coordinates()["A"]})
    with pytest.raises(symkin.ModelError, match=r"link crank \(A-B\): its two nodes coincide"):
        symkin.analyze(at_a)


def test_with_coordinates_from_float_arrays_checks_finiteness():
    m = catalogue.get("fourbar_appendix")
    xyz = np.array([c for _, c in m.nodes], dtype=np.float32)
    assert m.with_coordinates(xyz).nodes == m.with_coordinates(xyz.tolist()).nodes
    xyz[2, 1] = np.nan
    with pytest.raises(symkin.ModelError, match="nodes.C: coordinates must be finite"):
        m.with_coordinates(xyz)
