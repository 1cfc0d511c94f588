"""The position problem as a polynomial system in the nodal coordinates of the free nodes.

Built from the model data alone (no per-mechanism equations).  Coordinates are made
dimensionless, ``x = c + L·u`` (``c`` the centroid of the model's nodes, ``L`` its length
scale, :attr:`symkin.Mechanism.length_scale`), so the system, its tolerances and its
solution count do not depend on the unit of length.

Equations (``d`` a difference of node positions, all in ``u``):

* a **rigid body** of ``k`` nodes (a link): planar, one distance between two frame nodes
  ``|x_1 − x_0|² = l²`` and, for every other node, its affine coordinates in the frame,
  ``x_m = x_0 + α e + β J e`` (``e = x_1 − x_0``, ``J`` the quarter turn): ``2k − 3``
  equations of which only one is quadratic.  Spatial, three distances between three frame
  nodes and ``x_m = x_0 + α e_1 + β e_2 + γ e_1 × e_2`` (``3k − 6``; quadratic when ``γ ≠ 0``);
  collinear bodies use one distance and ``x_m = x_0 + α e``;
* a **slider** on a fixed line or plane: ``n · (x − p) = 0`` for the normals ``n`` (linear); on
  the moving line through nodes A, C: ``(x − x_A) × (x_C − x_A) = 0`` (bilinear);
* a **prescribed value** (an input coordinate of :mod:`symkin.numeric.coordinates`, measured
  from the model's configuration): a node coordinate (linear); a planar link angle θ —
  ``(x_j − x_i) · (−sin θ, cos θ) = 0`` (linear) with the half-line filter
  ``(x_j − x_i) · (cos θ, sin θ) > 0``; a planar joint angle (bilinear, with its half-line
  filter); a spatial rotation about a fixed axis (linear in the node farthest from the
  axis, with its half-line filter); a slide on a fixed line (linear) or on a moving line
  (``(x − x_A) · (x_C − x_A) = s·|AC|``, bilinear).

The reduced system given to the homotopy keeps the number of paths down: a prescribed planar
link angle (or planar joint angle, or rotation about a fixed axis of a link that holds the
axis) becomes linear once the link's fixed length is used, ``x_j − x_i = l (cos θ, sin θ)``;
every linear equation is substituted; and so is every combination of the quadratic equations
free of quadratic terms (the difference of two circles about one node), until none is left
(:func:`_reduce`).  One more reduction concerns prismatic legs: a free node D that
appears only in a two-node link [A, D] pivoted at a fixed node A and as the line of one
moving-line slider of node C whose slide ``ρ`` is prescribed, is determined by C
(``D = A + l (C − A) / ρ``); its three equations are replaced by ``|x_C − x_A|² = ρ²``.
The original equations are kept: every solution is checked against them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from symkin.constraints import SliderMovingLine, bar_constraint, body_constraint, polynomial_constraints, slider_constraint, slider_constraints
from symkin.constraints.algebra import Sympy
from symkin.errors import SymkinError
from symkin.model.joints import GROUND
from symkin.model.mechanism import AXES, Mechanism
from symkin.numeric.coordinates import InputCoordinate, axis_angle_setup, measuring_pair, parse_input_label
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["PolynomialSystem", "SystemBuilder", "ValueEquations", "closure_system", "configuration", "position_system",
           "prescribed_coordinates", "recover_jacobian", "value_equations"]


@dataclass(frozen=True, eq=False)
class PolynomialSystem:
    """The position problem in dimensionless free coordinates ``u`` (``x = center + scale·u``).

    Attributes
    ----------
    unknowns : tuple of sympy.Symbol
        ``u_<axis>_<node>`` for every free node, in :attr:`Mechanism.free_nodes` order.
    equations : tuple of (str, sympy.Expr)
        The original equations with their owners (``link:crank``, ``slider:S``, ``value:<label>``).
    filters : tuple of (str, sympy.Expr)
        Half-line conditions ``expr > 0`` a real solution must satisfy.
    reduced : tuple of sympy.Expr
        The equations left after the reduction of prismatic legs and the substitution of
        every linear equation, in the symbols ``solve_for``.
    solve_for : tuple of sympy.Symbol
        The unknowns left for the homotopy.
    recover : callable
        ``recover(v)`` → the full vector ``u`` (numpy, real or complex) from values of ``solve_for``.
    """

    mechanism: Mechanism
    center: np.ndarray
    scale: float
    unknowns: tuple
    equations: tuple
    filters: tuple
    reduced: tuple
    solve_for: tuple
    recover: object = field(repr=False)

    @property
    def overconstrained(self) -> bool:
        """More reduced equations than unknowns (squared up before the homotopy)."""
        return len(self.reduced) > len(self.solve_for)

    def coordinates(self, u: np.ndarray) -> dict[str, list[float]]:
        """Node name → coordinates (model units) of every node at the dimensionless free vector ``u``."""
        return configuration(self.mechanism, self.center, self.scale, u)


def configuration(mech: Mechanism, center, scale: float, u: np.ndarray) -> dict[str, list[float]]:
    """Node name → coordinates (model units) of every node of ``mech`` at the dimensionless free vector ``u``
    (``x = center + scale·u``)."""
    out = {n: list(map(float, x)) for n, x in mech.nodes}
    dim = mech.dim
    for k, n in enumerate(mech.free_nodes):
        out[n] = [float(center[a] + scale * u[k * dim + a]) for a in range(dim)]
    return out


def _symbols(mech: Mechanism):
    return [sp.Symbol(f"u_{AXES[a]}_{n}") for n in mech.free_nodes for a in range(mech.dim)]


def prescribed_coordinates(mech: Mechanism, values: dict, unit: str = "rad") -> list[tuple[InputCoordinate, float]]:
    """The input coordinates named by ``values`` and their values (angles in radians).

    Raises :class:`SymkinError` for an unknown label, a bad unit, or a number of values other
    than the mobility F (too few: the solutions form curves, not points; too many: the
    problem is overdetermined).
    """
    if unit not in ("rad", "deg"):
        raise SymkinError(f"unit must be 'rad' or 'deg', got {unit!r}")
    out = []
    for label, v in values.items():
        c = parse_input_label(mech, label)
        try:
            value = float(v)
        except (TypeError, ValueError):
            raise SymkinError(f"{label}: the value {v!r} is not a number") from None
        if not math.isfinite(value):
            raise SymkinError(f"{label}: the value {v!r} is not finite")
        out.append((c, value * (math.pi / 180.0 if unit == "deg" and c.kind == "angle" else 1.0)))
    f = mech.mobility_value
    names = ", ".join(values) or "none"
    if len(out) < f:
        raise SymkinError(f"{mech.name}: F = {f} but {len(out)} value(s) given ({names}): the solutions are not "
                          f"isolated points; prescribe {f - len(out)} more (e.g. the model's inputs "
                          f"{', '.join(c.label for c in _inputs(mech))})")
    if len(out) > f:
        raise SymkinError(f"{mech.name}: F = {f} but {len(out)} values given ({names}): too many values, "
                          f"the position problem is overdetermined; prescribe exactly {f}")
    labels = [c.label for c, _ in out]
    if len(set(labels)) < len(labels):
        raise SymkinError(f"{mech.name}: a value is given twice ({names})")
    return out


def _inputs(mech):
    from symkin.numeric.coordinates import input_coordinates

    try:
        return input_coordinates(mech)
    except SymkinError:
        return ()


class SystemBuilder:
    """The dimensionless polynomial equations of a model, gathered one owner (link, slider, value) at a time.

    Positions are ``u = (x − c) / L`` (``c`` the centroid of the model's nodes, ``L`` its length
    scale): symbols for the free nodes (:meth:`node`), numbers for the fixed ones, so that the
    equations and every row built from them (:func:`symkin.solutions.dkp_system.rate_row`) do not
    depend on the unit of length.

    Parameters
    ----------
    mech : Mechanism
        The model, at its configuration (the fixed nodes' positions are taken from it).
    tol : Tolerances
        ``rank`` decides the linear eliminations, ``geometry`` the consistency checks.
    """

    def __init__(self, mech: Mechanism, tol: Tolerances):
        polynomial_constraints(mech, "the polynomial position system (modes, singularities, solve)")
        self.mech = mech
        self.tol = tol
        self.dim = mech.dim
        xyz = np.array([c for _, c in mech.nodes], float)
        self.center = xyz.mean(axis=0)
        self.scale = float(mech.length_scale)
        self.x0 = {n: np.array(c, float) for n, c in mech.nodes}
        self.u = _symbols(mech)
        free = mech.free_nodes
        self.index = {n: k for k, n in enumerate(free)}
        self.equations: list[tuple[str, sp.Expr]] = []
        self.filters: list[tuple[str, sp.Expr]] = []

    def node(self, n: str):
        """Dimensionless position of node ``n``: symbols for a free node, numbers for a fixed one."""
        if n in self.index:
            k = self.index[n]
            return sp.Matrix(self.u[k * self.dim:(k + 1) * self.dim])
        return sp.Matrix([float(v) for v in (self.x0[n] - self.center) / self.scale])

    def model(self, n: str) -> np.ndarray:
        return (self.x0[n] - self.center) / self.scale

    def add(self, owner: str, expr) -> None:
        expr = sp.expand(expr)
        if not expr.free_symbols:  # between fixed nodes: holds in the model, nothing to solve
            return
        self.equations.append((owner, expr))


def _dot(a, b):
    return sum(a[i] * b[i] for i in range(len(a)))


def _frame(points: list[np.ndarray], geometry: float) -> tuple[list[int], int]:
    """Indices of frame nodes (farthest pair, then farthest from their line) and the body's rank."""
    k = len(points)
    pairs = [(np.linalg.norm(points[i] - points[j]), i, j) for i in range(k) for j in range(i + 1, k)]
    d, i, j = max(pairs)
    if d <= geometry:
        return [i], 0
    e = (points[j] - points[i]) / d
    off = [(np.linalg.norm((points[m] - points[i]) - ((points[m] - points[i]) @ e) * e), m)
           for m in range(k) if m not in (i, j)]
    if not off or max(off)[0] <= geometry * max(d, 1.0):
        return [i, j], 1
    return [i, j, max(off)[1]], 2


def _bodies(b: SystemBuilder) -> None:
    mech, dim = b.mech, b.dim
    fixed = set(mech.fixed)
    geometry = b.tol.geometry
    for name, ns in mech.links:
        if all(n in fixed for n in ns):
            continue
        owner = f"link:{name}"
        pts = [b.model(n) for n in ns]
        frame, rank = _frame(pts, geometry)
        if rank == 0:
            raise SymkinError(f"{mech.name}: link {name} has all its nodes at one point")
        if dim == 2 and rank == 2:
            frame = frame[:2]
        for a in range(len(frame)):
            for c in range(a + 1, len(frame)):  # |x_q − x_p|² − L²: the Bar's equation, L² in u
                p, q = ns[frame[a]], ns[frame[c]]
                square = float(np.sum((pts[frame[c]] - pts[frame[a]]) ** 2))
                b.add(owner, _distance(b, name, p, q, square))
        e_model = [pts[f] - pts[frame[0]] for f in frame[1:]]
        if dim == 2 and len(e_model) == 1 and rank >= 1:
            e_model.append(np.array([-e_model[0][1], e_model[0][0]]))
        elif dim == 3 and len(e_model) == 2:
            e_model.append(np.cross(e_model[0], e_model[1]))
        basis = np.column_stack(e_model)
        for m, n in enumerate(ns):
            if m in frame:
                continue
            body = body_constraint(b.mech, name)  # x_m = x_f0 + Σ c_k b_k: the body's frame equations
            X = {k: tuple(b.node(nn)) for k, nn in zip(body.idx, ns)}
            coef = np.linalg.lstsq(basis, pts[m] - pts[frame[0]], rcond=None)[0]
            for r in body.frame_equations(X, [body.idx[f] for f in frame], body.idx[m], [float(w) for w in coef]):
                b.add(owner, r)


def _distance(b: SystemBuilder, link: str, p: str, q: str, square) -> sp.Expr:
    """``|x_q − x_p|² − square`` in ``u``: the position equation of the :class:`~symkin.constraints.Bar`
    of the pair (:meth:`~symkin.constraints.Bar.polynomial`), ``L² = square`` (dimensionless or exact)."""
    bar = bar_constraint(b.mech, link, p, q)
    X = {bar.i: tuple(b.node(p)), bar.j: tuple(b.node(q))}  # d = x_q − x_p (the equation is symmetric in the pair)
    return bar.polynomial(Sympy(squared_hook=lambda *_: square), X, {bar.i: None, bar.j: None})


def _sliders(b: SystemBuilder, skip: set) -> None:
    """The sliders' polynomial equations (their definitions in :mod:`symkin.constraints`), in ``u``.

    An equation with a constant denominator (a fixed line or plane) is divided by it: its
    normals are then unit vectors, as the dimensionless system's other equations.
    """
    mech = b.mech
    alg = Sympy(point_hook=lambda v, what: tuple(float(c) for c in (np.asarray(v, float) - b.center) / b.scale),
                direction_hook=lambda v, what: tuple(float(c) for c in v))
    X = [tuple(b.node(n)) for n in mech.node_names]
    X0 = [tuple(map(float, c)) for _, c in mech.nodes]
    for con in slider_constraints(mech):
        if con.slider.id in skip:
            continue
        owner = f"slider:{con.slider.id}"
        for eq in con.equations(alg, X, X0):
            den = eq.denominator
            constant = not getattr(den, "free_symbols", ())
            b.add(owner, eq.numerator / float(den) if constant else eq.numerator)


def _link_vector(b: SystemBuilder, link: str):
    """A planar link's measuring vector (unknowns) and its model value; +x for the fixed frame of a joint model."""
    if link == GROUND and link not in b.mech.link_names:
        return sp.Matrix([1.0, 0.0]), np.array([1.0, 0.0])
    i, j = measuring_pair(b.mech, link)
    names = b.mech.node_names
    return b.node(names[j]) - b.node(names[i]), b.model(names[j]) - b.model(names[i])


def _rotate(v, angle: float):
    c, s = math.cos(angle), math.sin(angle)
    return sp.Matrix([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _values(b: SystemBuilder, prescribed, skip: set, reduce: bool = False) -> None:
    mech, dim = b.mech, b.dim
    names = mech.node_names
    for c, value in prescribed:
        if c.label in skip:
            continue
        owner = f"value:{c.label}"
        p = c.parameter
        if p.kind == "rotation" and dim == 2:
            i, j = measuring_pair(mech, p.target[0])
            d = b.node(names[j]) - b.node(names[i])
            d0 = b.model(names[j]) - b.model(names[i])
            phi = math.atan2(d0[1], d0[0]) + value
            if reduce:  # |x_j − x_i| is fixed in the link: the half-line is one point
                length = float(np.linalg.norm(d0))
                b.add(owner, d[0] - length * math.cos(phi))
                b.add(owner, d[1] - length * math.sin(phi))
                continue
            b.add(owner, -math.sin(phi) * d[0] + math.cos(phi) * d[1])
            b.filters.append((owner, math.cos(phi) * d[0] + math.sin(phi) * d[1]))
        elif p.kind == "joint" and dim == 2:
            (d1, m1), (d2, m2) = (_link_vector(b, link) for link in p.target)
            psi = math.atan2(m2[1], m2[0]) - math.atan2(m1[1], m1[0]) + value
            r = _rotate(d1, psi)
            if reduce:  # both lengths are fixed: d2 = (l2 / l1) R(ψ) d1
                ratio = float(np.linalg.norm(m2) / np.linalg.norm(m1))
                for comp in d2 - ratio * r:
                    b.add(owner, comp)
                continue
            b.add(owner, r[0] * d2[1] - r[1] * d2[0])
            b.filters.append((owner, _dot(r, d2)))
        elif p.kind == "rotation":
            axis, origin, k = axis_angle_setup(mech, p)
            o = (origin - b.center) / b.scale
            r0 = b.model(names[k]) - o
            r0 = r0 - (r0 @ axis) * axis
            turned = math.cos(value) * r0 + math.sin(value) * np.cross(axis, r0)
            normal = np.cross(axis, turned)
            r = b.node(names[k]) - sp.Matrix(o)
            link_fixed = set(mech.link_nodes(p.target[0])) & set(mech.fixed)
            if reduce and isinstance(p.axis[0], str) and set(p.axis) <= link_fixed:
                # the link turns about its fixed axis: the node's position is known, x = o + (r0·a) a + R r0⊥
                along = float((b.model(names[k]) - o) @ axis)
                for comp, target in zip(r, along * axis + turned):
                    b.add(owner, comp - float(target))
                continue
            b.add(owner, _dot([float(v) for v in normal], r))
            b.filters.append((owner, _dot([float(v) for v in turned], r)))
        elif p.kind == "velocity":
            axis = AXES.index(p.component) if p.component else c.component
            n = p.target[0]
            b.add(owner, b.node(n)[axis] - float(b.model(n)[axis]) - value / b.scale)
        elif p.kind == "slide":  # the slider's definition states its prescribed slide (in u)
            con = slider_constraint(mech, p.target[0])
            X = {k: tuple(b.node(n)) for k, n in enumerate(names) if k in con.nodes()}
            X0 = {k: b.model(n) for k, n in enumerate(names) if k in con.nodes()}
            b.add(owner, con.slide_polynomial(X, X0, value / b.scale))
        else:
            raise SymkinError(f"{c.label}: a {p.kind} value cannot be prescribed to solve the position problem")


def _legs(b: SystemBuilder, prescribed) -> list[tuple]:
    """Prismatic legs to reduce (see the module docstring): (slider, bar, D, A, C, ρ, l, label)."""
    mech = b.mech
    fixed = set(mech.fixed)
    slides = {c.parameter.target[0]: (c, v) for c, v in prescribed if c.parameter.kind == "slide"}
    out = []
    for con in slider_constraints(mech):
        if not isinstance(con, SliderMovingLine):
            continue
        s = con.slider
        hit = slides.get(s.id) or slides.get(s.node)
        if hit is None or mech.slider(hit[0].parameter.target[0]).id != s.id:
            continue
        ns = mech.link_nodes(s.link)
        if len(ns) != 2 or set(ns) != set(s.line):
            continue
        a, d = (ns[0], ns[1]) if ns[0] in fixed else (ns[1], ns[0])
        if a not in fixed or d in fixed or s.node in (a, d):
            continue
        in_links = [name for name, nn in mech.links if d in nn]
        others = [t for t in mech.sliders if t.id != s.id and (t.node == d or (t.line and d in t.line))]
        values_on_d = [c for c, _ in prescribed if c.parameter.kind != "slide"
                       and (d in c.parameter.target or any(t in in_links for t in c.parameter.target))]
        if in_links != [s.link] or others or values_on_d:
            continue
        c_label, value = hit
        u0 = b.model(s.line[1]) - b.model(s.line[0])
        along0 = float((b.model(s.node) - b.model(s.line[0])) @ u0 / np.linalg.norm(u0))
        rho = along0 + value / b.scale
        if s.line[0] != a:  # the slide is measured from the line's first node
            continue
        if abs(rho) <= b.tol.geometry:
            continue
        out.append((s, s.link, d, a, s.node, rho, float(np.linalg.norm(u0)), c_label.label))
    return out


def position_system(mech: Mechanism, values: dict, unit: str = "rad", tol: Tolerances = DEFAULT
                    ) -> PolynomialSystem:
    """The polynomial position problem of ``mech`` with the input coordinates ``values`` prescribed.

    See the module docstring for the equations.  ``values`` maps input labels
    (:func:`symkin.numeric.coordinates.parse_input_label`) to values measured from the model's
    configuration (angles in ``unit``, lengths in model units); exactly F of them.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> s = position_system(get("fourbar_appendix"), {"rotation:crank": 30}, unit="deg")
    >>> len(s.equations), len(s.unknowns), len(s.reduced), len(s.solve_for)
    (4, 4, 1, 1)
    """
    tol = Tolerances.of(tol)
    prescribed = prescribed_coordinates(mech, values, unit)
    b = SystemBuilder(mech, tol)
    _bodies(b)
    _sliders(b, set())
    _values(b, prescribed, set())
    original = list(b.equations)
    filters = list(b.filters)

    # the reduced system: prismatic legs, then linear substitution
    owned, keep_u, legs = _leg_reduced(b, mech, prescribed)
    reduced = [e for _, e in owned]

    pivots, solution, left, nonlinear = _reduce(reduced, keep_u, tol, mech.name)
    nonlinear = [e for e in nonlinear if e.free_symbols]
    if len(nonlinear) < len(left):
        raise SymkinError(f"{mech.name}: with the values {', '.join(values)} the position problem keeps "
                          f"{len(left) - len(nonlinear)} free parameter(s) (more unknowns than equations): "
                          "its solutions are not isolated; prescribe other values")

    linear = _linear_recovery(b.u, left, pivots, solution)

    def recover(v):
        v = np.asarray(v)
        return _place_bars(b, mech, legs, linear(v), v.dtype)

    return PolynomialSystem(mech, b.center, b.scale, tuple(b.u), tuple(original), tuple(filters),
                            tuple(nonlinear), tuple(left), recover)


def original_equations(mech: Mechanism, values: dict, unit: str = "rad", tol: Tolerances = DEFAULT):
    """``(unknowns, equations, filters, center, scale)`` of :func:`position_system` without its reduction (fast)."""
    b = SystemBuilder(mech, Tolerances.of(tol))
    _bodies(b)
    _sliders(b, set())
    _values(b, prescribed_coordinates(mech, values, unit), set())
    return tuple(b.u), tuple(b.equations), tuple(b.filters), b.center, b.scale


def _leg_reduced(b: SystemBuilder, mech: Mechanism, prescribed, reduce_values: bool = True, fixed: bool = True):
    """The equations with the prismatic legs reduced (module docstring), the unknowns kept, the legs.

    The equations come in the order: bodies and sliders (they do not depend on the values), then
    the values', then the legs'; with ``fixed=False`` the first group is left out.
    """
    legs = _legs(b, prescribed)
    b.equations, b.filters = [], []
    skip_links = {leg[1] for leg in legs}
    skip_sliders = {leg[0].id for leg in legs}
    skip_values = {leg[7] for leg in legs}
    if fixed:
        keep = [(nm, ns) for nm, ns in mech.links if nm not in skip_links]
        b.mech = replace(mech, links=tuple(keep))
        _bodies(b)
        b.mech = mech
        _sliders(b, skip_sliders)
    _values(b, prescribed, skip_values, reduce=reduce_values)
    owned = list(b.equations)
    for leg in legs:
        r = b.node(leg[4]) - b.node(leg[3])
        owned.append((f"leg:{leg[1]}", sp.expand(_dot(r, r) - leg[5] ** 2)))
    removed = set()
    for leg in legs:
        k = list(mech.free_nodes).index(leg[2])
        removed |= set(b.u[k * b.dim:(k + 1) * b.dim])
    return owned, [s for s in b.u if s not in removed], legs


def leg_reduced_equations(mech: Mechanism, values: dict, unit: str = "rad", tol: Tolerances = DEFAULT):
    """``(kept, equations, recover)``: :func:`position_system`'s equations after the reduction of prismatic legs only.

    ``kept`` the indices of the unknowns left (into :attr:`PolynomialSystem.unknowns`),
    ``equations`` ``(owner, expr)`` in them, ``recover(v)`` the full ``u`` from their values.
    The prescribed angles keep their original equations (a link angle is not made linear with
    the link's length: with cos θ and sin θ as independent parameters the system would be
    inconsistent off the circle).
    """
    tol = Tolerances.of(tol)
    prescribed = prescribed_coordinates(mech, values, unit)
    b = SystemBuilder(mech, tol)
    owned, keep_u, legs = _leg_reduced(b, mech, prescribed, reduce_values=False)
    kept = [b.u.index(s) for s in keep_u]
    recover = _leg_recovery(b, mech, legs, kept)

    return kept, tuple(owned), recover


def _leg_recovery(b, mech: Mechanism, legs, kept: list):
    """``recover(v)``: the full ``u`` from the kept unknowns' values ``v``, the reduced legs' bars placed."""
    def recover(v):
        v = np.asarray(v)
        u = np.zeros(len(b.u), dtype=v.dtype)
        u[kept] = v
        return _place_bars(b, mech, legs, u, v.dtype)

    return recover


@dataclass(frozen=True, eq=False)
class ValueEquations:
    """The equations of a position problem that depend on the prescribed values (a later query, issue 17).

    :func:`original_equations` gives the bodies' and sliders' equations first and the values'
    last; :func:`leg_reduced_equations` the bodies' and sliders' (of the links and sliders that
    are not a reduced leg), then the values', then the legs'.  The first group does not depend
    on the values: a query that has it from an earlier one (:mod:`symkin.solutions.query`)
    builds only these.

    Attributes
    ----------
    unknowns : tuple of sympy.Symbol
        As :attr:`PolynomialSystem.unknowns`.
    center, scale
        ``x = center + scale·u``.
    original : tuple of (str, sympy.Expr)
        The value equations that end :func:`original_equations`' list.
    filters : tuple of (str, sympy.Expr)
        Its filters (every filter is a value's).
    reduced : tuple of (str, sympy.Expr)
        The value and leg equations that end :func:`leg_reduced_equations`' list.
    kept : tuple of int
        As :func:`leg_reduced_equations`' ``kept``.
    legs : tuple of str
        ``"<slider>:<link>"`` of each reduced leg (which bodies and sliders the first group leaves out).
    recover : callable
        As :func:`leg_reduced_equations`' ``recover``.
    """

    unknowns: tuple
    center: np.ndarray
    scale: float
    original: tuple
    filters: tuple
    reduced: tuple
    kept: tuple
    legs: tuple
    recover: object = field(repr=False)


def value_equations(mech: Mechanism, values: dict, unit: str = "rad", tol: Tolerances = DEFAULT) -> ValueEquations:
    """The equations of :func:`original_equations` and :func:`leg_reduced_equations` that depend on the values
    (:class:`ValueEquations`): the same expressions as theirs, made by the same code."""
    tol = Tolerances.of(tol)
    prescribed = prescribed_coordinates(mech, values, unit)
    b = SystemBuilder(mech, tol)
    _values(b, prescribed, set())
    original, filters = tuple(b.equations), tuple(b.filters)
    owned, keep_u, legs = _leg_reduced(b, mech, prescribed, reduce_values=False, fixed=False)
    kept = [b.u.index(s) for s in keep_u]
    recover = _leg_recovery(b, mech, legs, kept)

    return ValueEquations(tuple(b.u), b.center, b.scale, original, filters, tuple(owned), tuple(kept),
                          tuple(f"{leg[0].id}:{leg[1]}" for leg in legs), recover)


def _place_bars(b: SystemBuilder, mech: Mechanism, legs, u: np.ndarray, dtype) -> np.ndarray:
    """``u`` with each reduced leg's bar node placed, ``D = A + l (C − A) / ρ`` (module docstring)."""
    free = list(mech.free_nodes)
    for leg in legs:
        kd, a, c, rho, length = free.index(leg[2]), leg[3], leg[4], leg[5], leg[6]
        xa = np.asarray(b.model(a), dtype=dtype) if a not in b.index else \
            u[b.index[a] * b.dim:(b.index[a] + 1) * b.dim]
        xc = u[b.index[c] * b.dim:(b.index[c] + 1) * b.dim]
        u[kd * b.dim:(kd + 1) * b.dim] = xa + (length / rho) * (xc - xa)
    return u


def _reduce(equations, unknowns, tol: Tolerances, name: str):
    """Substitute every linear equation, then every linear combination free of quadratic terms, until none is left.

    The quadratic equations' degree-2 coefficients form a matrix ``Q`` (equations × monomials);
    with its SVD ``Q = U S Vᵀ`` the combinations ``Uᵀ f`` whose singular value is below
    ``tol.rank · σ_max`` are linear (e.g. the difference of two circles about one node);
    they are substituted in turn.  ``Uᵀ`` is orthogonal, so the system is equivalent.
    Returns the eliminated unknowns, their expressions, the unknowns left and the equations left.
    """
    pivots, solution = [], {}
    left = list(unknowns)
    eqs = list(equations)
    while True:
        eqs = [sp.expand(e.subs(solution)) if solution else e for e in eqs]
        constants = [e for e in eqs if not e.free_symbols]
        if any(abs(complex(e)) > tol.geometry for e in constants):
            raise SymkinError(f"{name}: the prescribed values contradict the model's constraints "
                              "(a constraint between fixed quantities fails): no configuration")
        eqs = [e for e in eqs if e.free_symbols]
        degree = [sp.Poly(e, *left).total_degree() for e in eqs]
        linear = [e for e, d in zip(eqs, degree) if d <= 1]
        quadratic = [e for e, d in zip(eqs, degree) if d == 2]
        higher = [e for e, d in zip(eqs, degree) if d > 2]
        if not linear and len(quadratic) > 1:
            linear, quadratic = _linear_combinations(quadratic, left, tol)
        if not linear:
            return pivots, solution, left, quadratic + higher
        piv, sol = _eliminate_linear(linear, left, tol)
        if not piv:
            return pivots, solution, left, quadratic + higher
        solution = {s: sp.expand(v.subs(sol)) for s, v in solution.items()}
        solution.update(sol)
        pivots += piv
        left = [s for s in left if s not in piv]
        eqs = quadratic + higher


def _linear_combinations(quadratic, unknowns, tol: Tolerances):
    polys = [sp.Poly(e, *unknowns) for e in quadratic]
    monomials = sorted({m for p in polys for m in p.monoms() if sum(m) == 2})
    q = np.array([[float(p.coeff_monomial(m)) for m in monomials] for p in polys])
    u, s, _ = np.linalg.svd(q)
    rank = int(np.sum(s > tol.rank * s[0])) if s.size and s[0] > 0 else 0
    if rank == len(polys):
        return [], quadratic
    size = max(abs(float(c)) for p in polys for c in p.coeffs())
    combos, linear = [], []
    for k in range(u.shape[1]):
        e = sp.expand(sum(float(u[i, k]) * quadratic[i] for i in range(len(quadratic))))
        if k < rank:
            combos.append(e)
            continue
        # drop the rounding left in the quadratic terms; a combination with nothing left beyond
        # rounding is a redundant equation (e.g. the third component of a cross product in space)
        p = sp.Poly(e, *unknowns)
        terms = [(m, c) for m, c in p.terms() if sum(m) <= 1 and abs(float(c)) > tol.rank * size]
        if terms:
            linear.append(sum((c * sp.prod([v ** d for v, d in zip(unknowns, m)]) for m, c in terms),
                              sp.Integer(0)))
    return linear, combos


def _eliminate_linear(linear, unknowns, tol: Tolerances):
    """Solve the linear equations for some unknowns (QR with column pivoting, relative rank test)."""
    from scipy.linalg import qr

    if not linear:
        return [], {}
    a = np.array([[float(e.coeff(s)) for s in unknowns] for e in linear])
    rhs = -np.array([float(e.subs({s: 0 for s in unknowns})) for e in linear])
    _, r, perm = qr(a, pivoting=True, mode="economic")
    diag = np.abs(np.diag(r))
    rank = int(np.sum(diag > tol.rank * max(diag[0], 1e-300))) if diag.size else 0
    piv = [unknowns[i] for i in perm[:rank]]
    rest = [unknowns[i] for i in perm[rank:]]
    # least-squares residual of the linear equations tells whether they are consistent
    sol, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    if np.max(np.abs(a @ sol - rhs)) > tol.geometry * max(1.0, np.max(np.abs(rhs))):
        raise SymkinError("the prescribed values contradict the model's linear constraints (sliders, "
                          "rigid bodies): no configuration")
    ap = a[:, perm[:rank]]
    ar = a[:, perm[rank:]]
    # u_p = ap⁺ (rhs − ar u_r)
    pinv = np.linalg.pinv(ap)
    const = pinv @ rhs
    coef = -pinv @ ar
    solution = {}
    for k, s in enumerate(piv):
        solution[s] = float(const[k]) + sum((float(coef[k, j]) * t for j, t in enumerate(rest)), sp.Integer(0))
    return piv, solution


def closure_system(mech: Mechanism, tol: Tolerances = DEFAULT) -> PolynomialSystem:
    """The closure equations of ``mech`` alone (no prescribed value), reduced as :func:`position_system` does.

    The solution set is the configuration space (a curve for a 1-DOF mechanism): ``reduced``
    has fewer equations than ``solve_for`` has unknowns.  Every linear equation (and every
    combination of the quadratics free of quadratic terms) is substituted, so the free
    coordinates are an affine function of ``solve_for``: ``recover(v) = u₀ + N v``, whose
    constant Jacobian ``N = ∂u/∂v`` :func:`recover_jacobian` gives.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> s = closure_system(get("watt_sixbar"))
    >>> len(s.equations), len(s.unknowns), len(s.reduced), len(s.solve_for)
    (7, 8, 5, 6)
    """
    tol = Tolerances.of(tol)
    b = SystemBuilder(mech, tol)
    _bodies(b)
    _sliders(b, set())
    original = list(b.equations)
    pivots, solution, left, nonlinear = _reduce([e for _, e in original], list(b.u), tol, mech.name)
    nonlinear = [e for e in nonlinear if e.free_symbols]
    recover = _linear_recovery(b.u, left, pivots, solution)
    recover.expressions = {s: solution.get(s, s) for s in b.u}
    return PolynomialSystem(mech, b.center, b.scale, tuple(b.u), tuple(original), (),
                            tuple(nonlinear), tuple(left), recover)


def _linear_recovery(unknowns, left, pivots, solution):
    """``v ↦ u``: the kept unknowns ``left`` are ``v``, the eliminated ``pivots`` their linear solution."""
    lin_f = sp.lambdify([left], [solution[s] for s in pivots], "numpy") if pivots else None
    full_index = {s: i for i, s in enumerate(unknowns)}

    def recover(v):
        v = np.asarray(v)
        u = np.zeros(len(unknowns), dtype=v.dtype)
        for s, val in zip(left, v):
            u[full_index[s]] = val
        if lin_f is not None:
            for s, val in zip(pivots, lin_f(list(v))):
                u[full_index[s]] = val
        return u

    return recover


def recover_jacobian(system: PolynomialSystem) -> np.ndarray:
    """``N = ∂u/∂v`` of :func:`closure_system`'s affine ``recover`` (unknowns × solve_for)."""
    exprs = system.recover.expressions
    return np.array([[float(sp.diff(exprs[s], v)) for v in system.solve_for] for s in system.unknowns])
