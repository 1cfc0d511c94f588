"""The square polynomial system "closure + DKP test function = 0" of a 1-DOF mechanism.

In the dimensionless nodal coordinates of :func:`~symkin.solutions.system.closure_system`
the configuration curve is ``R(v) = 0`` (``k`` equations, ``k + 1`` unknowns, every linear
equation substituted: ``u = u₀ + N v``).  The velocity equation is ``(∂R/∂v) v̇ = 0``; a
parameter (the input or the output coordinate) has the rate ``p(u) · N v̇`` up to a factor
that is nonzero and constant on the curve (a link length, :func:`rate_row`).  Appending its
row gives the square matrix of the velocity equation with the parameter row, and

    D(v) = det [ ∂R/∂v ; p(u(v)) N ]

vanishes exactly where the parameter's rate is zero along the curve (a DKP configuration of
that parameter when F = 1, paper §III: the parameter cannot be given an arbitrary rate) or
where ``∂R/∂v`` loses rank (an IM configuration, a branch point of the curve).  It is the
determinant of the velocity equation in the full nodal coordinates with the parameter row
appended, up to a nonzero constant factor (the linear rows of the eliminated equations).
``R = 0, D = 0`` is square (``k + 1`` equations): its isolated real solutions are every
DKP and IM configuration of the mechanism, which :func:`symkin.singularities` compares
with those located along the traced circuits.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from sympy.polys.domains import RR
from sympy.polys.rings import ring

from symkin.curves.corrector import gauss_newton
from symkin.constraints import SliderLine, slider_constraint
from symkin.errors import SymkinError
from symkin.model.joints import GROUND
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate, axis_angle_setup, measuring_pair
from symkin.solutions.system import PolynomialSystem, SystemBuilder, closure_system, recover_jacobian
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["DkpSystem", "block_triangular", "determinant", "dkp_system", "polish", "rate_row"]

#: :func:`polish` aims at this largest residual of a square system in dimensionless coordinates (the
#: rounding level of O(1) polynomials: a real root is polished to the last digits before it is compared)
POLISH_TARGET = 1e-15
#: :func:`polish` stops when a step falls below this relative to ``max(1, ‖v‖)`` (rounding of ``v``)
POLISH_STEP = 1e-16
#: largest residual (max-norm, times ``max(1, scale²)``) of a curve point projected by :func:`constant_on_curve`
#: (one decade below :attr:`Tolerances.newton`: the factor is compared to relative 1e-9 there)
CURVE_POINT = 1e-13


@dataclass(frozen=True, eq=False)
class DkpSystem:
    """``closure + D = 0`` for one parameter (see the module docstring).

    ``curve`` are the closure's reduced equations in ``unknowns`` (= ``closure.solve_for``);
    ``factors`` the determinants of the diagonal blocks of the block-triangular form of
    ``[∂R/∂v; p N]`` (its Dulmage–Mendelsohn decomposition: ``D = ± ∏ factors``, so that a
    Watt six-bar's ``D`` splits into one factor per loop and the homotopy tracks far fewer
    paths); :meth:`systems` the square systems ``curve + [factor]``.  ``degree`` is the total
    degree of ``D``.  ``squared`` tells that the closure had redundant equations, squared up
    by random combinations before ``D`` was formed (its extra roots are filtered by the caller).
    ``constant`` are the factors that take one value on the curve (e.g. a crank's block,
    ``2 |V1 − P2|²``: never zero there), which :meth:`systems` leaves out.
    """

    closure: PolynomialSystem
    coordinate: InputCoordinate
    curve: tuple
    factors: tuple
    unknowns: tuple
    degree: int
    squared: bool
    constant: tuple = ()

    @property
    def equations(self) -> tuple:
        """``curve`` followed by the product of the factors (``D`` up to its sign)."""
        return self.curve + (sp.expand(sp.prod(self.factors)),)

    def systems(self) -> list[tuple]:
        """One square system ``curve + (factor,)`` per factor that is not a constant on the curve."""
        return [self.curve + (f,) for f in self.factors if not any(f is k for k in self.constant)]


def rate_row(mech: Mechanism, c: InputCoordinate, tol: Tolerances = DEFAULT) -> list:
    """A polynomial row ``p(u)`` over the free coordinates with ``ċ = p(u) · u̇ / κ``, ``κ`` constant on the closure.

    Planar rotation of a link (pair ``i → j``, ``d = x_j − x_i``): ``d × ḋ`` (``κ = |d|²``); a
    planar joint angle: ``|d₁|² (d₂ × ḋ₂) − |d₂|² (d₁ × ḋ₁)``; a rotation about a fixed axis
    ``a`` (body node ``k``, ``r = x_k − o``): ``a · (r × ṙ)``; a node's coordinate or a slide on a
    fixed line: the constant unit row.  A slide on a moving line is not supported (its rate
    involves ``1/|x_C − x_A|``, not constant in general).
    """
    b = SystemBuilder(mech, tol)
    names = mech.node_names
    dots = {n: sp.Matrix(sp.symbols(f"w_{n}_0:{mech.dim}")) for n in mech.free_nodes}

    def vel(n):
        return dots[n] if n in dots else sp.zeros(mech.dim, 1)

    def turn(link):
        if link == GROUND and link not in mech.link_names:  # the fixed frame of a joint model
            return sp.Integer(0), 1.0
        i, j = measuring_pair(mech, link)
        d, dd = b.node(names[j]) - b.node(names[i]), vel(names[j]) - vel(names[i])
        m = b.model(names[j]) - b.model(names[i])
        return d[0] * dd[1] - d[1] * dd[0], float(m @ m)

    p = c.parameter
    if p.kind == "rotation" and mech.dim == 2:
        form = turn(p.target[0])[0]
    elif p.kind == "joint" and mech.dim == 2:
        (w1, k1), (w2, k2) = turn(p.target[0]), turn(p.target[1])
        form = k1 * w2 - k2 * w1
    elif p.kind == "rotation":
        axis, origin, k = axis_angle_setup(mech, p)
        r = b.node(names[k]) - sp.Matrix((origin - b.center) / b.scale)
        form = sp.Matrix([float(a) for a in axis]).dot(r.cross(vel(names[k])))
    elif p.kind == "velocity":
        form = vel(p.target[0])[c.component if not p.component else "xyz".index(p.component)]
    elif p.kind == "slide" and isinstance(slider_constraint(mech, p.target[0]), SliderLine):
        s = mech.slider(p.target[0])
        d = np.array(s.direction, float)
        form = sum(float(w) * e for w, e in zip(d / np.linalg.norm(d), vel(s.node)))
    else:
        raise SymkinError(f"{c.label}: the square DKP system is not available for a {p.kind} on a moving line")
    form = sp.expand(form)
    return [sp.expand(form.coeff(w)) for n in mech.free_nodes for w in dots[n]]


def determinant(rows: list[list], gens: list, domain=RR):
    """``det`` of a square matrix of polynomials by Laplace expansion over column subsets (memoised).

    The rows of ``∂R/∂v`` are sparse (a bar involves at most two nodes): the expansion is
    ``2ⁿ`` sub-determinants at most, in sympy's sparse polynomial ring over ``domain``.

    Parameters
    ----------
    rows : list of list
        The square matrix, row by row: sympy expressions (or numbers) polynomial in ``gens``.
    gens : list of sympy.Symbol
        The polynomial ring's generators.
    domain : sympy domain
        ``RR`` (floats, the default) or ``QQ`` (exact rationals, :mod:`symkin.solutions.exact`).

    Returns
    -------
    sympy.Expr
        The determinant, expanded, in ``gens``.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> determinant([[x, 1], [y, x]], [x, y])
    1.0*x**2 - 1.0*y
    """
    return _determinant_poly(rows, gens, domain).as_expr()


def _determinant_poly(rows: list[list], gens: list, domain=RR):
    """:func:`determinant` as an element of sympy's sparse polynomial ring over ``gens`` (expanded, no zero terms)."""
    n = len(rows)
    r, *_ = ring(list(gens), domain)  # the generators themselves (no renaming of the entries or of the result)
    polys = [[r(0) if e == 0 else r.from_expr(sp.sympify(e)) for e in row] for row in rows]
    memo: dict[int, object] = {}

    def rec(k: int, used: int):
        if k == n:
            return r.one
        if used in memo:
            return memo[used]
        total = r.zero
        free = [j for j in range(n) if not used >> j & 1]
        for pos, j in enumerate(free):
            if polys[k][j]:
                term = polys[k][j] * rec(k + 1, used | 1 << j)
                total = total + term if pos % 2 == 0 else total - term
        memo[used] = total
        return total

    return rec(0, 0)


def dkp_system(mech: Mechanism, c: InputCoordinate, tol: float | Tolerances | None = None,
               closure: PolynomialSystem | None = None, seed: int = 0) -> DkpSystem:
    """The square system ``R(v) = 0, det[∂R/∂v; p N] = 0`` of parameter ``c`` (module docstring).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> from symkin.numeric.coordinates import input_coordinates
    >>> m = get("fourbar_appendix")
    >>> s = dkp_system(m, input_coordinates(m)[0])
    >>> len(s.equations), len(s.unknowns), s.degree
    (4, 4, 4)
    """
    from symkin.solutions.homotopy import square_up

    tol = Tolerances.of(tol)
    if mech.mobility_value != 1:
        raise SymkinError(f"{mech.name}: the DKP system needs a 1-DOF mechanism (F = {mech.mobility_value})")
    closure = closure or closure_system(mech, tol)
    v = list(closure.solve_for)
    eqs = list(closure.reduced)
    squared = len(eqs) > len(v) - 1
    if squared:
        eqs = square_up(eqs, len(v) - 1, seed=seed)
    if len(eqs) < len(v) - 1:
        raise SymkinError(f"{mech.name}: the closure leaves {len(v) - len(eqs)} free parameters, not a curve "
                          "(the mechanism moves with more than one degree of freedom)")
    n = recover_jacobian(closure)
    u_of_v = closure.recover.expressions
    row_u = rate_row(mech, c, tol)
    sub = {s: e for s, e in u_of_v.items() if s not in v}
    row_v = [sp.expand(sum((float(n[i, j]) * row_u[i].xreplace(sub) for i in range(len(row_u)) if n[i, j] != 0),
                           sp.Integer(0))) for j in range(len(v))]
    jac = [list(row) for row in _jacobian(tuple(eqs), tuple(v))] if eqs else []
    factors, terms = [], []
    for block in block_triangular(jac + [row_v]):
        rows = [[(jac + [row_v])[i][j] for j in block[1]] for i in block[0]]
        det = _determinant_poly(rows, v)  # expanded: its expression needs no sp.expand
        if not det:
            raise SymkinError(f"{mech.name}: the DKP test function of {c.label} is identically zero on the "
                              "configuration space (a structurally singular velocity equation)")
        if not det.is_ground:
            factors.append(det.as_expr())
            terms.append((np.array(list(det.itermonoms()), float), np.array([float(k) for k in det.itercoeffs()])))
    # a block that is a constant on the curve (a crank's own 2|V1 − P2|², a rocker's) never vanishes there:
    # its square system has no real solution, only paths to track
    constant = tuple(f_ for f_, t_ in zip(factors, terms) if _constant_on_curve(f_, eqs, v, closure, t_))
    if factors and len(constant) == len(factors):
        raise SymkinError(f"{mech.name}: the DKP test function of {c.label} is constant on the configuration "
                          "space (the parameter is never singular): no square system")
    if not factors:
        raise SymkinError(f"{mech.name}: the DKP test function of {c.label} is constant on the configuration "
                          "space (the parameter is never singular): no square system")
    degree = sum(int(e.sum(axis=1).max()) for e, _ in terms)
    return DkpSystem(closure, c, tuple(eqs), tuple(factors), tuple(v), degree, squared, constant)


def _jacobian(eqs: tuple, v: tuple) -> tuple:
    """``∂eqs/∂v`` row by row, memoised (the DKP systems of one closure share it: input, output, every LIM)."""
    key = (eqs, v)
    if key not in _JACOBIANS:
        if len(_JACOBIANS) >= 8:
            _JACOBIANS.pop(next(iter(_JACOBIANS)))
        _JACOBIANS[key] = tuple(tuple(row) for row in sp.Matrix(eqs).jacobian(v).tolist())
    return _JACOBIANS[key]


_JACOBIANS: dict = {}
_CURVES: dict = {}


def _curve_functions(eqs: tuple, v: tuple):
    """The closure's residuals and Jacobian as numpy functions of ``v``, memoised like :func:`_jacobian`."""
    key = (eqs, v)
    if key not in _CURVES:
        if len(_CURVES) >= 8:
            _CURVES.pop(next(iter(_CURVES)))
        r = sp.lambdify([list(v)], list(eqs), "numpy")
        jac = sp.lambdify([list(v)], sp.Matrix(_jacobian(eqs, v)), "numpy")
        _CURVES[key] = (lambda z: np.array(r(z), float).ravel(),
                        lambda z: np.array(jac(z), float).reshape(len(eqs), len(v)))
    return _CURVES[key]


def _terms(factor, v: list):
    """``(exponents, coefficients)`` of an expanded polynomial ``factor`` in ``v`` (arrays), or ``None``.

    Read from its terms (a sum of number × powers of ``v``); ``None`` when a term is anything else.
    """
    index = {s: k for k, s in enumerate(v)}
    exps, coeffs = [], []
    for term in sp.Add.make_args(factor):
        c, m = term.as_coeff_Mul()
        if not c.is_Number:
            return None
        e = [0] * len(v)
        for b, p in m.as_powers_dict().items():
            if b == 1:
                continue
            if b not in index or not (p.is_Integer and p >= 0):
                return None
            e[index[b]] += int(p)
        exps.append(e)
        coeffs.append(float(c))
    return np.array(exps, float).reshape(len(exps), len(v)), np.array(coeffs, float)


def _constant_on_curve(factor, eqs: list, v: list, closure: PolynomialSystem, terms=None, points: int = 4) -> bool:
    """Whether ``factor`` takes one value at the model's configuration and at ``points`` other curve points."""
    mech = closure.mechanism
    x = np.concatenate([np.asarray(dict(mech.nodes)[n], float) for n in mech.free_nodes])
    u0 = (x - np.tile(closure.center, len(mech.free_nodes))) / closure.scale
    index = {s_: k for k, s_ in enumerate(closure.unknowns)}
    return constant_on_curve(factor, eqs, v, np.array([u0[index[s_]] for s_ in v]), 1.0, points, terms=terms)


def constant_on_curve(factor, eqs: list, v: list, v0: np.ndarray, scale: float = 1.0, points: int = 4,
                      terms=None) -> bool:
    """Whether the polynomial ``factor`` is one number on the curve ``eqs = 0`` near ``v0`` (a curve point).

    It is evaluated at ``v0`` and at ``points`` other curve points: Gauss–Newton projections onto
    ``eqs = 0`` of random perturbations (0.2 ``scale``, fixed seed) of ``v0``; a factor that varies
    on the curve differs there (relative 1e-9).  Points where the projection fails are not used;
    fewer than two usable points: not constant (the factor is kept).  ``terms``, the factor's
    ``(exponents, coefficients)`` when the caller has them, spares reading them from ``factor``.
    """
    if not eqs:
        return False
    if terms is None:
        terms = _terms(factor, list(v))
    if terms is None:  # not a sum of number × powers: sympy reads it
        poly = sp.Poly(factor, *v)
        terms = np.array(poly.monoms(), float), np.array([float(c_) for c_ in poly.coeffs()])
    exps, coeffs = terms

    def f(y):  # the factor's terms at once (a degree-6 factor has thousands: lambdify is slow to build)
        return float(coeffs @ np.prod(np.power(y[None, :], exps), axis=1))

    r, jac = _curve_functions(tuple(eqs), tuple(v))
    closes = CURVE_POINT * max(1.0, scale * scale)

    def project(y):
        c = gauss_newton(lambda z: (r(z), jac(z)), y, tol=closes, floor=closes, max_iterations=40, norm="max")
        return c.z if c.converged else None

    base = project(np.asarray(v0, float).copy())
    if base is None:
        return False
    f0 = f(base)
    rng = np.random.default_rng(0)
    used = 0
    for _ in range(3 * points):
        y = project(base + 0.2 * scale * rng.standard_normal(len(v)))
        if y is None or float(np.linalg.norm(y - base)) < 1e-3 * scale:
            continue
        if abs(f(y) - f0) > 1e-9 * max(1.0, abs(f0)):
            return False
        used += 1
        if used == points:
            break
    return used >= 2


def block_triangular(rows: list[list]) -> list[tuple[list[int], list[int]]]:
    """Diagonal blocks ``(rows, columns)`` of the block-triangular form of a square sparse matrix.

    A perfect matching of rows to columns (:func:`scipy.sparse.csgraph.maximum_bipartite_matching`)
    and the strongly connected components of the row graph it induces (Dulmage–Mendelsohn):
    the determinant is, up to its sign, the product of the blocks' determinants.  A
    structurally singular matrix (no perfect matching) is one block.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

    n = len(rows)
    pattern = csr_matrix(np.array([[1 if e != 0 else 0 for e in r] for r in rows], dtype=np.int8))
    match = maximum_bipartite_matching(pattern, perm_type="column")
    if np.any(match < 0):
        return [(list(range(n)), list(range(n)))]
    row_of = {int(match[i]): i for i in range(n)}
    graph = np.zeros((n, n), dtype=np.int8)
    for i in range(n):
        for j in range(n):
            if rows[i][j] != 0:
                graph[i, row_of[j]] = 1
    count, label = connected_components(csr_matrix(graph), directed=True, connection="strong")
    blocks = []
    for k in range(count):
        ri = [i for i in range(n) if label[i] == k]
        blocks.append((ri, [int(match[i]) for i in ri]))
    return blocks


def polish(equations: tuple, unknowns: tuple, v: np.ndarray, max_iterations: int = 40) -> tuple[np.ndarray, float]:
    """Gauss–Newton on the square system ``equations = 0`` from ``v``; returns the point and its largest residual.

    The one corrector, :func:`symkin.curves.corrector.gauss_newton`, in the max-norm, to
    :data:`POLISH_TARGET` or a step below :data:`POLISH_STEP` (the best point seen when it does
    not get there), without stopping early at a floor.

    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> p, res = polish((x * x + y * y - 1, x - y), (x, y), np.array([1.0, 0.5]))
    >>> [round(float(c), 12) for c in p], res < 1e-15
    ([0.707106781187, 0.707106781187], True)
    """
    f, j = _compiled(equations, unknowns)
    # floor=0: no acceptance at a floor; at a singular root (an IM point, where the residual is the
    # square of the distance) it goes on converging linearly to the target or the last step, as polished roots must
    c = gauss_newton(lambda z: (f(z), j(z)), np.asarray(v, float), tol=POLISH_TARGET, floor=0.0,
                     max_iterations=max_iterations, step_tol=POLISH_STEP, norm="max")
    return c.z, c.residual


def _compiled(equations: tuple, unknowns: tuple):
    u = list(unknowns)
    f = sp.lambdify([u], list(equations), "numpy")
    jj = sp.lambdify([u], sp.Matrix(equations).jacobian(u), "numpy")
    return (lambda x: np.array(f(x), float).ravel(),
            lambda x: np.array(jj(x), float).reshape(len(u), len(u)))
