"""Every constraint kind, every backend: the same rows and equations (issue 16, "one definition per pair kind").

Each definition of :mod:`symkin.constraints` is evaluated in floats, in CasADi SX and in
sympy at random configurations (the rows are defined off the closure too) and the three
must agree to 1e-12; then the assembled backends — the numeric core's
``constraint_rows`` (with its vectorised bars), the CasADi model's ``J`` and closure, the
symbolic rows — must agree with the definitions, so that a backend that drifted from its
definition fails here.  Rows are dimensionless: a model in mm and in m gives the same rows,
and a rotated model gives each constraint's element matrix ``Σ a aᵀ`` rotated.
"""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.constraints import Bar, Body, constraints_of
from symkin.constraints.algebra import FLOATS, Casadi, Floats, Sympy
from symkin.model.catalogue import get
from symkin.numeric.casadi_model import build
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.symbolic.rows import RowBuilder

HERE = Path(__file__).parent
KINDS = ("bar", "slider_line", "slider_plane", "slider_moving_line", "helical")


def _spatial_sliders():
    """A spatial model with a slider of every kind: a fixed line, a fixed plane, a moving line."""
    return symkin.Mechanism.from_dict({
        "name": "spatial sliders", "dim": 3, "fixed": ["O", "Q"],
        "nodes": {"O": [0, 0, 0], "A": [0.3, 1.1, 0.2], "B": [1.4, 0.9, 0.7], "C": [2.1, 1.6, 0.4],
                  "Q": [2.5, -0.3, 0.1], "P": [0.85, 1.0, 0.45]},
        "links": {"crank": ["O", "A"], "rod": ["A", "B", "C"], "tie": ["Q", "C"], "pin": ["P", "Q"]},
        "sliders": [{"id": "line", "node": "B", "point": [1.4, 0.9, 0.7], "direction": [0.3, -0.2, 0.9]},
                    {"id": "plane", "node": "C", "point": [2.1, 1.6, 0.4], "normal": [0.1, 0.2, 1.0]},
                    {"id": "moving", "node": "P", "line": ["A", "B"], "link": "rod"}]})


def _ground_screw():
    """A screw turning and advancing in a ground nut (H with ground as its guide), driven by a crank-rod."""
    return symkin.read_model(HERE / "models" / "ground_screw.toml")


MODELS = {
    "slider_crank": lambda: get("slider_crank"),
    "spatial_sliders": _spatial_sliders,
    "screw_jack": lambda: symkin.read_model(HERE / "models" / "screw_jack.toml"),
    "ground_screw": _ground_screw,
}


def _mechs():
    return {name: f() for name, f in MODELS.items()}


@pytest.fixture(scope="module")
def mechs():
    return _mechs()


def _dense(row, dim: int, ncoord: int) -> np.ndarray:
    """A :class:`Row` of floats as a dense vector."""
    out = np.zeros(ncoord)
    for k, coef, vec in row.terms:
        for a in range(dim):
            out[dim * k + a] += float(coef) * float(vec[a]) / float(row.scale)
    return out


def _sx_coordinates(dim: int, n: int):
    """All node coordinates as one SX vector, and per node the tuple of its symbols."""
    sym = ca.SX.sym("x", dim * n)
    return sym, [tuple(sym[dim * k + a] for a in range(dim)) for k in range(n)]


def _sx_row(row, dim: int, n: int):
    """A :class:`Row` of SX terms as one SX column over all coordinates."""
    vec = [ca.SX(0)] * (dim * n)
    for k, coef, v in row.terms:
        for a in range(dim):
            vec[dim * k + a] = vec[dim * k + a] + coef * v[a] / row.scale
    return ca.vertcat(*vec)


def _casadi_values(con, mech, x: np.ndarray):
    """Rows and equation residuals of ``con`` built in SX over all coordinates, evaluated at ``x``."""
    dim, n = mech.dim, len(mech.nodes)
    sym, X = _sx_coordinates(dim, n)
    X0 = [tuple(map(float, r)) for r in x]
    alg = Casadi()
    rows = [_sx_row(r, dim, n) for r in con.rows(alg, X, X0)]
    eqs = [e.numerator / e.denominator for e in con.equations(alg, X, X0)]
    f = ca.Function("f", [sym], [ca.horzcat(*rows).T if rows else ca.SX(0, dim * n),
                                 ca.vertcat(*eqs) if eqs else ca.SX(0, 1)])
    j, phi = f(x.ravel())
    return np.array(j), np.array(phi).ravel()


def _sympy_values(con, mech, x: np.ndarray, x_model: np.ndarray):
    """Rows and residuals of ``con`` in sympy over coordinate symbols, then substituted by ``x``."""
    dim, n = mech.dim, len(mech.nodes)
    syms = [[sp.Symbol(f"c{k}_{a}", real=True) for a in range(dim)] for k in range(n)]
    X = [tuple(s) for s in syms]
    X0 = [tuple(map(float, r)) for r in x_model]
    alg = Sympy()
    subs = {syms[k][a]: sp.Float(float(x[k, a]), 30) for k in range(n) for a in range(dim)}
    rows = []
    for r in con.rows(alg, X, X0):
        vec = np.zeros(dim * n)
        for k, coef, v in r.terms:
            for a in range(dim):
                vec[dim * k + a] += float((coef * v[a] / r.scale).xreplace(subs).evalf(30))
        rows.append(vec)
    eqs = [float((e.numerator / e.denominator).xreplace(subs).evalf(30)) for e in con.equations(alg, X, X0)]
    return np.array(rows).reshape(len(rows), dim * n), np.array(eqs)


def _random_configurations(mech, count: int, seed: int):
    rng = np.random.default_rng(seed)
    x0 = np.array([c for _, c in mech.nodes], float)
    free = np.array([[n not in mech.fixed] for n in mech.node_names], float)  # fixed nodes stay
    return [x0 + 0.05 * mech.length_scale * free * rng.standard_normal(x0.shape) for _ in range(count)]


def test_every_kind_is_covered(mechs):
    kinds = {c.kind for m in mechs.values() for c in constraints_of(m)}
    assert set(KINDS) <= kinds


@pytest.mark.parametrize("name", list(MODELS))
def test_floats_casadi_sympy_agree_at_random_configurations(mechs, name):
    """Rows and equations of every constraint under the three algebras, to 1e-12.

    The model's configuration ``X0`` is taken at the random configuration itself (the exact
    algebra decides the axis of a line's normals there, the others at ``X``), and the
    equations are measured from the model's own configuration (their parameters: lengths,
    offsets, the helix's phase).
    """
    mech = mechs[name]
    dim, n = mech.dim, len(mech.nodes)
    x_model = np.array([c for _, c in mech.nodes], float)
    checked = 0
    for x in _random_configurations(mech, 3, seed=7):
        X = [tuple(map(float, r)) for r in x]
        X0 = [tuple(map(float, r)) for r in x_model]
        for con in constraints_of(mech):
            if isinstance(con, Body):
                continue
            f_rows = np.array([_dense(r, dim, dim * n) for r in con.rows(FLOATS, X, X)])
            f_eqs = np.array([e.numerator / e.denominator for e in con.equations(FLOATS, X, X0)])
            # CasADi decides the normals' axis at x, as the floats do; its closure parameters at the model
            c_rows, _ = _casadi_values(con, mech, x)
            _, c_eqs = _casadi_values(con, mech, x_model)
            s_rows, _ = _sympy_values(con, mech, x, x)
            assert c_rows == pytest.approx(f_rows, abs=1e-12), con.owner
            assert s_rows == pytest.approx(f_rows, abs=1e-12), con.owner
            # equations: the residual at x relative to the model's configuration
            # (sympy decides a line's normals at the model's configuration: so do the floats here)
            sx = np.array([float(v) for v in _sympy_equations(con, mech, x, x_model)])
            f_model = np.array([e.numerator / e.denominator for e in con.equations(_FloatsAtModel(), X, X0)])
            cx = _casadi_equations(con, mech, x, x_model)
            assert cx == pytest.approx(f_eqs, abs=1e-12 * mech.length_scale), con.owner
            assert sx == pytest.approx(f_model, abs=1e-12 * mech.length_scale), con.owner
            assert len(f_rows) == con.size(dim) == len(f_eqs)
            checked += 1
    assert checked >= 3


class _FloatsAtModel(Floats):
    """Floats that take the discrete choice at the model's configuration, as the exact algebra does."""

    def least_aligned(self, e, e0):
        return Floats.least_aligned(self, e0, e0)


def _casadi_equations(con, mech, x, x_model):
    dim, n = mech.dim, len(mech.nodes)
    sym = ca.SX.sym("x", dim * n)
    X = [tuple(sym[dim * k + a] for a in range(dim)) for k in range(n)]
    eqs = [e.numerator / e.denominator for e in con.equations(Casadi(), X, [tuple(r) for r in x_model])]
    return np.array(ca.Function("e", [sym], [ca.vertcat(*eqs)])(x.ravel())).ravel()


def _sympy_equations(con, mech, x, x_model):
    dim, n = mech.dim, len(mech.nodes)
    syms = [[sp.Symbol(f"c{k}_{a}", real=True) for a in range(dim)] for k in range(n)]
    subs = {syms[k][a]: sp.Float(float(x[k, a]), 30) for k in range(n) for a in range(dim)}
    eqs = con.equations(Sympy(), [tuple(s) for s in syms], [tuple(map(float, r)) for r in x_model])
    return [(e.numerator / e.denominator).xreplace(subs).evalf(30) for e in eqs]


@pytest.mark.parametrize("name", list(MODELS))
def test_assembled_backends_are_the_definitions(mechs, name):
    """The numeric core (vectorised bars included), the CasADi model and the symbolic rows
    assemble exactly the registry's rows, in its order, at the model and at random configurations."""
    mech = mechs[name]
    dim, n = mech.dim, len(mech.nodes)
    cm = build(mech)
    jf0 = ca.Function("J", [cm.q, cm.p], [cm.J, cm.closure, ca.jacobian(cm.closure, cm.q)])

    def jf(q):
        return jf0(q, cm.p0)

    free = cm.free
    for x in [np.array([c for _, c in mech.nodes], float)] + _random_configurations(mech, 2, seed=3):
        at = mech.with_coordinates(x)
        X = [tuple(map(float, r)) for r in x]
        expect, owners = [], []
        for con in constraints_of(mech):
            if isinstance(con, Body):
                continue
            for r in con.rows(FLOATS, X, X):
                expect.append(_dense(r, dim, dim * n))
                owners.append(con.owner)
        core = constraint_rows(at)
        body_free = [k for k, o in enumerate(core.owners) if "out of its hull" not in o]
        assert [core.owners[k] for k in body_free] == owners
        assert core.matrix[body_free] == pytest.approx(np.array(expect), abs=1e-12)
        j, phi, dphi = (np.array(v) for v in jf(x.ravel()[free]))
        assert cm.owners == core.owners
        assert j[body_free] == pytest.approx(np.array(expect), abs=1e-12)
    # the closure's gradient is the row at the model's configuration (where it closes)
    j, phi, dphi = (np.array(v) for v in jf(cm.q0()))
    assert np.abs(phi).max() <= 1e-12 * mech.length_scale
    assert dphi == pytest.approx(j[:, free], abs=1e-9)


@pytest.mark.parametrize("name", list(MODELS))
def test_symbolic_rows_are_the_definitions(mechs, name):
    """The symbolic rows (node coordinates, design lengths at the model's values) at the model's configuration."""
    mech = mechs[name]
    rb = RowBuilder(mech)
    values = dict(rb.values)
    core = constraint_rows(mech)
    dim = mech.dim
    assert [r.owner for r in rb.rows] == list(core.owners)
    for r, expect in zip(rb.rows, core.matrix):
        got = np.zeros_like(expect)
        scale = float(r.scale.xreplace(values))
        for col, e in r.entries(dim).items():
            got[col] = float(e.xreplace(values)) / scale
        if "out of its hull" in r.owner:  # the symbolic body rows may pick other normals: compare a aᵀ
            assert np.outer(got, got) == pytest.approx(np.outer(expect, expect), abs=1e-12)
        else:
            assert got == pytest.approx(expect, abs=1e-12), r.owner


def _element_matrices(mech) -> list[np.ndarray]:
    """``Σ a aᵀ`` over the rows of each constraint (basis-free: the paper's element matrices)."""
    x = [tuple(map(float, c)) for _, c in mech.nodes]
    dim, n = mech.dim, len(mech.nodes)
    out = []
    for con in constraints_of(mech):
        if isinstance(con, Body):
            continue
        rows = np.array([_dense(r, dim, dim * n) for r in con.rows(FLOATS, x, x)])
        out.append(rows.T @ rows)
    return out


def _rotation(dim: int, seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((dim, dim)))
    return q * np.sign(np.linalg.det(q))


@pytest.mark.parametrize("name", list(MODELS))
def test_rows_are_scale_and_rotation_invariant(mechs, name):
    """mm vs m: the same rows (dimensionless); rotated: each element matrix turned with the model."""
    mech = mechs[name]
    base = _element_matrices(mech)
    for g, h in zip(base, _element_matrices(mech.moved(scale=1000.0, translation=[5.0] * mech.dim))):
        assert h == pytest.approx(g, abs=1e-12)
    rot = _rotation(mech.dim, 11)
    big = np.kron(np.eye(len(mech.nodes)), rot)
    for g, h in zip(base, _element_matrices(mech.moved(rotation=rot))):
        assert h == pytest.approx(big @ g @ big.T, abs=1e-12)


def test_vectorised_bars_are_the_bar_definition(mechs):
    """The numeric core's bar block (its fast path) is :class:`Bar` evaluated in floats."""
    for mech in mechs.values():
        x = [tuple(map(float, c)) for _, c in mech.nodes]
        dim, n = mech.dim, len(mech.nodes)
        core = constraint_rows(mech)
        bars = [c for c in constraints_of(mech) if isinstance(c, Bar)]
        for con in bars:
            k = core.owners.index(con.owner)
            assert core.matrix[k] == pytest.approx(_dense(con.rows(FLOATS, x, x)[0], dim, dim * n), abs=1e-15)
