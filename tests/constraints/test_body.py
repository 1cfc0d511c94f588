"""A degenerate body's rows out of its hull: one definition (:class:`symkin.constraints.Body`), three algebras.

The numeric core evaluates the definition in floats (the SVD's normals and least-squares affine
coordinates, decided at the configuration), the CasADi model in SX (normals smooth in the frame,
decided at the model) and the symbolic rows in sympy (polynomial normals, Cramer's rule).  Their
normals differ by a basis of the normal space, so each body's element matrix ``Σ a aᵀ`` is
compared (basis-free), to 1e-12:

* floats, CasADi and sympy at rigid motions of the model (the body stays degenerate; the floats
  decide its hull there), in m and in mm (rows are dimensionless);
* CasADi and sympy at random configurations (off the closure: the rows are defined there too),
  and their closure residuals (the affine coordinates are the model's);
* against elementary geometry: a collinear body's rows annihilate every rigid velocity field and
  give the body no motion normal to its line that is not rigid.
"""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.constraints import Body, body_constraints
from symkin.constraints.algebra import FLOATS, Casadi, Sympy
from symkin.numeric.casadi_model import build
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.symbolic.rows import RowBuilder
from tests.constraints.test_backends import _dense, _sx_coordinates, _sx_row


def _planar_rod():
    """A planar body of four collinear nodes (unequal spacing), held by two cranks and a rocker."""
    return symkin.Mechanism.from_dict({
        "name": "planar rod", "dim": 2, "fixed": ["O1", "O2", "O3"],
        "nodes": {"O1": [0, 0], "O2": [4.0, -0.5], "O3": [2.2, 2.9], "A": [0.4, 1.3], "B": [1.7, 1.3 + 0.65],
                  "C": [2.9, 1.3 + 1.25], "D": [4.3, 1.3 + 1.95]},
        "links": {"crank": ["O1", "A"], "rod": ["A", "B", "C", "D"], "rocker": ["O2", "D"], "tie": ["O3", "C"]}})


def _spatial_rod():
    """A spatial body of three collinear nodes on a generic line."""
    d = np.array([0.6, -0.3, 0.74])
    a = np.array([0.2, 0.5, 0.1])
    return symkin.Mechanism.from_dict({
        "name": "spatial rod", "dim": 3, "fixed": ["O1", "O2", "O3", "O4"],
        "nodes": {"O1": [0, 0, 0], "O2": [3.1, 0.2, -0.4], "O3": [0.5, 2.6, 1.1], "O4": [2.0, -1.7, 2.3],
                  "A": a.tolist(), "B": (a + 1.3 * d).tolist(), "C": (a + 3.1 * d).tolist()},
        "links": {"rod": ["A", "B", "C"], "l1": ["O1", "A"], "l2": ["O2", "C"], "l3": ["O3", "B"], "l4": ["O4", "B"]}})


def _spatial_plate():
    """A spatial body of five coplanar nodes (a generic plane), on legs."""
    rng = np.random.default_rng(4)
    o, e1, e2 = np.array([0.3, 0.2, 1.5]), np.array([1.0, 0.2, 0.3]), np.array([-0.25, 0.9, 0.4])
    pts = {f"P{k}": (o + a * e1 + b * e2).tolist() for k, (a, b) in
           enumerate([(0, 0), (1.7, 0.1), (0.4, 1.3), (1.1, 0.9), (2.1, 1.6)])}
    grounds = {f"G{k}": (np.array(p) + rng.normal(size=3) + [0, 0, -1.5]).tolist() for k, p in enumerate(pts.values())}
    return symkin.Mechanism.from_dict({
        "name": "spatial plate", "dim": 3, "fixed": list(grounds),
        "nodes": {**pts, **grounds}, "links": {"plate": list(pts), **{f"leg{k}": [f"G{k}", f"P{k}"] for k in range(5)}}})


MODELS = {"planar_rod": _planar_rod, "spatial_rod": _spatial_rod, "spatial_plate": _spatial_plate}


def _body(mech) -> Body:
    (body,) = [b for b in body_constraints(mech) if b.hull([c for _, c in mech.nodes]) is not None]
    return body


def _gram(rows, dim: int, n: int) -> np.ndarray:
    a = np.array([_dense(r, dim, dim * n) for r in rows]).reshape(-1, dim * n)
    return a.T @ a


def _casadi(con, mech, x: np.ndarray, x_model: np.ndarray):
    """``Σ a aᵀ`` of the rows and the closure residuals of ``con`` in SX, decided at ``x_model``, evaluated at ``x``."""
    dim, n = mech.dim, len(mech.nodes)
    sym, X = _sx_coordinates(dim, n)
    X0 = [tuple(map(float, r)) for r in x_model]
    rows = [_sx_row(r, dim, n) for r in con.rows(Casadi(), X, X0)]
    eqs = [e.numerator / e.denominator for e in con.equations(Casadi(), X, X0)]
    j, phi = ca.Function("f", [sym], [ca.horzcat(*rows).T, ca.vertcat(*eqs)])(x.ravel())
    j = np.array(j)
    return j.T @ j, np.array(phi).ravel()


def _sympy(con, mech, x: np.ndarray, x_model: np.ndarray):
    dim, n = mech.dim, len(mech.nodes)
    syms = [[sp.Symbol(f"c{k}_{a}", real=True) for a in range(dim)] for k in range(n)]
    X0 = [tuple(map(float, r)) for r in x_model]
    subs = {syms[k][a]: sp.Float(float(x[k, a]), 30) for k in range(n) for a in range(dim)}
    rows = []
    for r in con.rows(Sympy(), [tuple(s) for s in syms], X0):
        vec = np.zeros(dim * n)
        for k, coef, v in r.terms:
            for a in range(dim):
                vec[dim * k + a] += float((coef * v[a] / r.scale).xreplace(subs).evalf(30))
        rows.append(vec)
    eqs = [float((e.numerator / e.denominator).xreplace(subs).evalf(30))
           for e in con.equations(Sympy(), [tuple(s) for s in syms], X0)]
    a = np.array(rows)
    return a.T @ a, np.array(eqs)


def _rigid(mech, seed: int) -> np.ndarray:
    """The model's nodes moved rigidly (a random rotation and translation)."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((mech.dim, mech.dim)))
    q = q * np.sign(np.linalg.det(q))
    x0 = np.array([c for _, c in mech.nodes], float)
    return x0 @ q.T + mech.length_scale * rng.standard_normal(mech.dim)


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("scale", [1.0, 1000.0])
def test_three_algebras_agree_on_rigid_motions(name, scale):
    mech = MODELS[name]().moved(scale=scale)
    body = _body(mech)
    dim, n = mech.dim, len(mech.nodes)
    x0 = np.array([c for _, c in mech.nodes], float)
    for seed in range(3):
        x = _rigid(mech, seed)
        X = [tuple(map(float, r)) for r in x]
        floats = _gram(body.rows(FLOATS, X, X), dim, n)
        assert np.linalg.matrix_rank(floats, tol=1e-9) > 0
        moved = mech.with_coordinates(x)  # the CasADi and sympy forms decide at their model: this one
        cas, phi_c = _casadi(body, moved, x, x)
        sym, phi_s = _sympy(body, moved, x, x)
        assert cas == pytest.approx(floats, abs=1e-12), "casadi"
        assert sym == pytest.approx(floats, abs=1e-12), "sympy"
        assert np.abs(phi_c).max() <= 1e-12 * mech.length_scale
        assert np.abs(phi_s).max() <= 1e-12 * mech.length_scale
    # mm vs m: the same dimensionless rows
    unit = MODELS[name]()
    X = [tuple(map(float, r)) for r in x0 / scale]
    Xs = [tuple(map(float, r)) for r in x0]
    assert _gram(body.rows(FLOATS, Xs, Xs), dim, n) == pytest.approx(_gram(_body(unit).rows(FLOATS, X, X), dim, n),
                                                                     abs=1e-12)


@pytest.mark.parametrize("name", list(MODELS))
def test_casadi_and_sympy_agree_off_the_closure(name):
    """At random configurations (the body no longer degenerate, the decision the model's): rows and residuals."""
    mech = MODELS[name]()
    body = _body(mech)
    x0 = np.array([c for _, c in mech.nodes], float)
    rng = np.random.default_rng(2)
    for _ in range(3):
        x = x0 + 0.05 * mech.length_scale * rng.standard_normal(x0.shape)
        cas, phi_c = _casadi(body, mech, x, x0)
        sym, phi_s = _sympy(body, mech, x, x0)
        assert cas == pytest.approx(sym, abs=1e-12)
        assert np.abs(phi_c).max() > 1e-6 * mech.length_scale  # off the closure the residuals are not zero
        # one residual per (node, normal): per node, the normals span the same space (3D lines: other bases)
        k = len(phi_c) // (len(body.idx) - body.hull([tuple(c) for c in x0]).h - 1)
        for start in range(0, len(phi_c), k):
            assert np.linalg.norm(phi_c[start:start + k]) == pytest.approx(np.linalg.norm(phi_s[start:start + k]),
                                                                          abs=1e-12 * mech.length_scale)


@pytest.mark.parametrize("name", list(MODELS))
def test_backends_assemble_the_definition(name):
    """The core's rows out of the hull are the floats' definition; the CasADi model's and the symbolic
    rows' element matrices equal them at the model."""
    mech = MODELS[name]()
    body = _body(mech)
    dim, n = mech.dim, len(mech.nodes)
    X = [tuple(map(float, c)) for _, c in mech.nodes]
    expect = np.array([_dense(r, dim, dim * n) for r in body.rows(FLOATS, X, X)])
    core = constraint_rows(mech)
    mine = [k for k, o in enumerate(core.owners) if o == body.owner]
    assert core.matrix[mine].tobytes() == expect.tobytes()
    cm = build(mech)
    j = np.array(ca.Function("J", [cm.q], [cm.J])(cm.q0()))
    assert [cm.owners[k] for k in mine] == [body.owner] * len(mine)
    assert j[mine].T @ j[mine] == pytest.approx(expect.T @ expect, abs=1e-12)
    rb = RowBuilder(mech)
    values = dict(rb.values)
    got = np.zeros((len(mine), dim * n))
    for row, r in zip(got, [r for r in rb.rows if r.owner == body.owner]):
        scale = float(r.scale.xreplace(values))
        for col, e in r.entries(dim).items():
            row[col] = float(e.xreplace(values)) / scale
    assert got.T @ got == pytest.approx(expect.T @ expect, abs=1e-12)


def test_collinear_rows_are_exactly_the_non_rigid_normal_motions():
    """Planar rod A-B-C-D: the rows vanish on every rigid velocity field of the rod (translation,
    rotation about any point) and, with its bars, leave exactly the rod's 3 rigid motions."""
    mech = _planar_rod()
    body = _body(mech)
    X = [tuple(map(float, c)) for _, c in mech.nodes]
    n = len(mech.nodes)
    rows = np.array([_dense(r, 2, 2 * n) for r in body.rows(FLOATS, X, X)])
    assert rows.shape[0] == 2  # two nodes off the frame, one normal each
    idx = [mech.node_index()[k] for k in body.names]
    for v_lin, omega, centre in (([1.0, 0.0], 0.0, [0, 0]), ([0.0, 1.0], 0.0, [0, 0]), ([0.0, 0.0], 1.0, [3.0, -2.0])):
        v = np.zeros(2 * n)
        for k in idx:
            r = np.array(X[k]) - centre
            v[2 * k: 2 * k + 2] = np.array(v_lin) + omega * np.array([-r[1], r[0]])
        assert np.abs(rows @ v).max() <= 1e-14
    bars = constraint_rows(mech).matrix
    cols = [2 * k + a for k in idx for a in range(2)]
    rod = np.vstack([bars[[i for i, o in enumerate(constraint_rows(mech).owners) if o.startswith("link rod (")]][:, cols],
                     rows[:, cols]])
    assert len(cols) - np.linalg.matrix_rank(rod, tol=1e-10) == 3
