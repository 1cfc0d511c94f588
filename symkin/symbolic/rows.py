"""Symbolic constraint rows and kinematic-parameter rows (paper eqs. 1-4, A1-A4).

The numeric core (:mod:`symkin.numeric.geometric_matrix`) writes every constraint as one
dimensionless row ``a`` over the nodal velocity components and assembles
``G = Σ a aᵀ`` (eqs. 2-3).  This module writes *the same rows* with symbols.  A row is
stored as polynomial node blocks divided by a nonzero ``scale``::

    a = (Σ_k  Σ_t coef_t · vec_t  placed at node k) / scale

so that a condition can be derived from the polynomial part alone, the scales being
trivial (nonzero) factors: lengths, areas, norms of fixed directions.

Two sets of configuration variables (``coordinates``):

* ``"nodes"``: the node coordinates ``x_B, y_B (, z_B)``; a bar i-j is
  ``(+Δ at i, −Δ at j) / l`` with ``Δ = x_j − x_i`` (eq. A4 in space; A3 in the plane);
  the fixed nodes of a model with a non-polynomial constraint enter as their numbers (:func:`known_nodes`);
* ``"angles"`` (planar): one angle ``theta_<link>`` per link (first node → second node);
  a bar is ``(+e(α) at i, −e(α) at j)`` with ``e(α) = (cos α, sin α)`` (eq. A3), and a
  pair of a body of 3+ nodes has ``α = theta_<body> + beta_<body>_<i>_<j>`` (fixed internal
  geometry).

Design parameters (lengths, internal angles ``beta``) are always symbols here; the model
(:mod:`symkin.symbolic.model`) substitutes their values unless design symbols were asked for.
Structural decisions (which nodes of a body are degenerate, the frame of a degenerate body,
the node pair that measures a planar link's rotation) are taken at the model's
configuration exactly as the numeric core takes them.  In node coordinates every constraint
row (bars, degenerate bodies, sliders, helical pairs) and a slide's rate row are the
definitions of :mod:`symkin.constraints` evaluated in sympy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from symkin.constraints import (Body, SliderMovingLine, body_constraints, constraints_of, slider_constraint,
                                slider_constraints)
from symkin.constraints.algebra import Sympy
from symkin.errors import SymkinError
from symkin.model.joints import GROUND
from symkin.model.mechanism import AXES, Mechanism, Parameter
from symkin.numeric.linalg import affine_hull
from symkin.symbolic.symbols import (angle_symbol, coordinate_symbol, exact, exact_angle,
                                     length_symbol, offset_symbol, slide_symbol)
from symkin.tolerances import DEFAULT

__all__ = ["SymRow", "RowBuilder", "COORDINATES", "known_nodes"]

COORDINATES = ("nodes", "angles")

Vec = tuple  # tuple of sympy expressions, one per axis


@dataclass(frozen=True)
class SymRow:
    """One constraint or parameter row: ``(Σ coef·vec at each node) / scale``.

    Attributes
    ----------
    owner : str
        What the row expresses, e.g. ``"link coupler (B-C)"``, ``"slider s"`` or a
        parameter label such as ``"rotation:crank"``.
    element : str
        The element whose geometric matrix (eq. 1-2) the row belongs to, e.g. ``"coupler"``.
    blocks : tuple
        ``((node index, ((coef, vec), ...)), ...)``: polynomial blocks.
    scale : sympy.Expr
        Nonzero divisor that makes the row dimensionless (or gives it physical units).
    """

    owner: str
    element: str
    blocks: tuple
    scale: sp.Expr

    def block_vectors(self) -> dict[int, tuple[sp.Expr, ...]]:
        """Node index → the (unscaled) block as one vector ``Σ coef·vec``."""
        out = {}
        for node, terms in self.blocks:
            dim = len(terms[0][1])
            out[node] = tuple(sp.Add(*[c * v[a] for c, v in terms]) for a in range(dim))
        return out

    def entries(self, dim: int) -> dict[int, sp.Expr]:
        """Column index → unscaled entry (columns ordered x_A, y_A, x_B, ...)."""
        out = {}
        for node, vec in self.block_vectors().items():
            for a, e in enumerate(vec):
                if e != 0:
                    out[dim * node + a] = e
        return out


def _cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Vec, b: Vec) -> sp.Expr:
    return sp.Add(*[p * q for p, q in zip(a, b)])


def _perp(a: Vec) -> Vec:
    return (-a[1], a[0])


def _unit(k: int, dim: int) -> Vec:
    return tuple(sp.Integer(1 if a == k else 0) for a in range(dim))


def _least_aligned_axis(vec: np.ndarray) -> int:
    """The coordinate axis least aligned with ``vec`` (as :func:`numeric.linalg.normal_basis`)."""
    return int(np.argmin(np.abs(vec / np.linalg.norm(vec))))


def _combine(rows: list[SymRow], weights: list[sp.Expr], owner: str, element: str,
             extra_scale: sp.Expr = sp.Integer(1)) -> SymRow:
    """``Σ w_k row_k / extra_scale`` as one row over a common scale."""
    scales: list[sp.Expr] = []
    for r in rows:
        if not any(r.scale == s for s in scales):
            scales.append(r.scale)
    common = sp.Mul(*scales)
    merged: dict[int, list] = {}
    for r, w in zip(rows, weights):
        if w == 0:
            continue
        factor = w * sp.Mul(*[s for s in scales if s != r.scale]) if len(scales) > 1 else w
        for node, terms in r.blocks:
            merged.setdefault(node, []).extend((factor * c, v) for c, v in terms)
    blocks = tuple((n, tuple(t)) for n, t in sorted(merged.items()))
    return SymRow(owner, element, blocks, common * extra_scale)


def known_nodes(mech: Mechanism) -> frozenset:
    """The nodes whose coordinates enter the symbolic rows as numbers instead of symbols.

    The fixed nodes of a model with a constraint whose position equation is not polynomial
    (:attr:`symkin.constraints.base.Constraint.polynomial` false).  Such a row can be written
    over a common scale of high degree in fixed nodes (10 for the pair of the screw jack, turning
    about a fixed axis: tests/symbolic/test_helical_conditions.py); with them as symbols an entry expands to 65,000
    terms of degree 11 in 16 symbols and no condition is derived, with their values (the
    exact numbers of :func:`~symkin.symbolic.symbols.exact`) its conditions take a second.  Fixed nodes never move, so the conditions are the same functions
    of the configuration.  Every other model keeps a symbol per node, fixed ones included,
    so that its conditions are unchanged (and stay comparable with the polynomial closure
    of :mod:`symkin.symbolic.loci`, which takes the pivots snapped).

    Parameters
    ----------
    mech : Mechanism
        The model.

    Returns
    -------
    frozenset of str
        Names of the nodes given by their values (empty for a model of polynomial constraints).
    """
    if all(c.polynomial for c in constraints_of(mech)):
        return frozenset()
    return frozenset(mech.fixed)


class RowBuilder:
    """Builds the symbolic rows of one mechanism in one set of coordinates.

    After construction: ``config_symbols`` (configuration variables, in a fixed order),
    ``design_symbols`` (lengths and internal angles), ``values`` (every symbol → its value
    at the model's configuration) and ``design_exact`` (design symbol → exact value, or
    closed form in the node coordinates for nodal lengths).
    """

    def __init__(self, mech: Mechanism, coordinates: str = "nodes", tolerances=DEFAULT):
        if coordinates not in COORDINATES:
            raise SymkinError(f"coordinates must be one of {', '.join(COORDINATES)}, got {coordinates!r}")
        if coordinates == "angles" and mech.dim != 2:
            raise SymkinError("angle coordinates are defined for planar models only "
                              f"({mech.name!r} is spatial); use coordinates='nodes'")
        if coordinates == "angles" and mech.extras:  # the pair kinds' own rows are over node coordinates
            raise SymkinError("angle coordinates express links and sliders only; the constraints of "
                              f"{', '.join(sorted({type(r).key for r in mech.extras}))} need coordinates='nodes'")
        self.mech = mech
        self.mode = coordinates
        self.dim = mech.dim
        self.tol = tolerances
        self.index = mech.node_index()
        self.x = np.array([xyz for _, xyz in mech.nodes], dtype=float)
        self.config_symbols: list[sp.Symbol] = []
        self.design_symbols: list[sp.Symbol] = []
        self.values: dict[sp.Symbol, float] = {}
        self.design_exact: dict[sp.Symbol, sp.Expr] = {}
        self.angle_like: list[sp.Symbol] = []  # symbols that appear inside cos/sin
        self._links = dict(mech.links)
        self.known = known_nodes(mech) if self.mode == "nodes" else frozenset()
        if self.mode == "nodes":
            self.coord = {}
            for n in mech.node_names:
                if n in self.known:  # a fixed node given by its numbers (known_nodes)
                    self.coord[n] = tuple(exact(v) for v in self.x[self.index[n]])
                    continue
                syms = tuple(coordinate_symbol(AXES[a], n) for a in range(self.dim))
                self.coord[n] = syms
                for a, s in enumerate(syms):
                    self._add_config(s, self.x[self.index[n], a])
        else:
            for name in mech.link_names:
                ns = self._links[name]
                d = self._delta_num(ns[0], ns[1])
                s = angle_symbol(name)
                self._add_config(s, math.atan2(d[1], d[0]))
                self.angle_like.append(s)
            for con in slider_constraints(mech):
                if isinstance(con, SliderMovingLine):
                    sl = con.slider
                    a, c = sl.line
                    e = self._delta_num(a, c)
                    t = float(np.dot(self._delta_num(a, sl.node), e) / np.linalg.norm(e))
                    self._add_config(slide_symbol(sl.id), t)
        self.rows = self._constraint_rows()

    # ------------------------------------------------------------------ symbols
    def _add_config(self, s: sp.Symbol, value: float) -> None:
        self.config_symbols.append(s)
        self.values[s] = float(value)

    def _add_design(self, s: sp.Symbol, value: float, exact_value: sp.Expr) -> sp.Symbol:
        if s not in self.values:
            self.design_symbols.append(s)
            self.values[s] = float(value)
            self.design_exact[s] = exact_value
        return s

    def _delta_num(self, i: str, j: str) -> np.ndarray:
        return self.x[self.index[j]] - self.x[self.index[i]]

    def _delta_sym(self, i: str, j: str) -> Vec:
        return tuple(b - a for a, b in zip(self.coord[i], self.coord[j]))

    def _ordered(self, link: str, i: str, j: str) -> tuple[str, str, bool]:
        ns = self._links[link]
        return (i, j, False) if ns.index(i) < ns.index(j) else (j, i, True)

    def length(self, link: str, i: str, j: str) -> sp.Symbol:
        """Length symbol of the pair i-j of ``link`` (registered as a design symbol)."""
        a, b, _ = self._ordered(link, i, j)
        ns = self._links[link]
        s = length_symbol(link) if (a, b) == (ns[0], ns[1]) else length_symbol(link, a, b)
        value = float(np.linalg.norm(self._delta_num(a, b)))
        if self.mode == "nodes":
            closed = sp.sqrt(_dot(self._delta_sym(a, b), self._delta_sym(a, b)))
        else:
            closed = exact(value)
        return self._add_design(s, value, closed)

    def angle(self, link: str, i: str, j: str) -> sp.Expr:
        """Angles mode: the direction angle of i → j, ``theta_<link> + offset``."""
        ns = self._links[link]
        theta = angle_symbol(link)
        a, b, flipped = self._ordered(link, i, j)
        d0 = self._delta_num(ns[0], ns[1])
        d = self._delta_num(a, b)
        off = math.atan2(d0[0] * d[1] - d0[1] * d[0], float(np.dot(d0, d)))
        quarter = off / (math.pi / 2)
        if abs(quarter - round(quarter)) < 1e-12:
            offset = sp.Integer(int(round(quarter))) * sp.pi / 2
        else:
            offset = self._add_design(offset_symbol(link, a, b), off, exact_angle(off))
            if offset not in self.angle_like:
                self.angle_like.append(offset)
        return theta + offset + (sp.pi if flipped else 0)

    def direction(self, link: str, i: str, j: str) -> tuple[Vec, sp.Expr]:
        """``(vec, norm)`` with ``vec / norm`` the unit vector i → j of a pair of ``link``."""
        if self.mode == "nodes":
            return self._delta_sym(i, j), self.length(link, i, j)
        alpha = self.angle(link, i, j)
        return (sp.cos(alpha), sp.sin(alpha)), sp.Integer(1)

    def register_all(self) -> None:
        """Register (with values) the length and internal angle of every node pair of every link,
        whether the rows use them or not (so another model's symbols all get values)."""
        for name, ns in self.mech.links:
            for a in range(len(ns)):
                for b in range(a + 1, len(ns)):
                    self.length(name, ns[a], ns[b])
                    if self.mode == "angles":
                        self.angle(name, ns[a], ns[b])

    # ------------------------------------------------------------------ constraint rows
    def _constraint_rows(self) -> list[SymRow]:
        """The rows of :func:`symkin.constraints.constraints_of` in sympy (node coordinates).

        Angle coordinates are another set of variables (a link's angle, a slider's slide):
        their bars and moving-line sliders are written here over those (:meth:`_angle_rows`).
        """
        if self.mode == "angles":
            return self._angle_rows()
        alg = self._algebra()
        X, X0 = self._positions()
        rows: list[SymRow] = []
        for con in constraints_of(self.mech):
            extra = {"tol": self.tol.geometry} if isinstance(con, Body) else {}
            rows += [self._sym_row(r, con.owner, con.element) for r in con.rows(alg, X, X0, **extra)]
        return rows

    def _algebra(self) -> Sympy:
        """The sympy algebra of the definitions: exact numbers, a design symbol per rigid pair's length."""
        return Sympy(const_hook=lambda v, what="": exact(v),
                     length_hook=lambda link, a, b, d: self.length(link, a, b))

    def _positions(self) -> tuple[list, list]:
        """``(X, X0)``: the nodes' coordinate symbols (None in angle coordinates, which have none: a
        fixed line's rate row needs only its direction) and their model values (floats)."""
        X = [self.coord[n] for n in self.mech.node_names] if self.mode == "nodes" else [None] * len(self.x)
        return X, [tuple(map(float, c)) for c in self.x]

    @staticmethod
    def _sym_row(r, owner: str, element: str) -> SymRow:
        """A definition's :class:`~symkin.constraints.Row` as a :class:`SymRow` (terms grouped by node)."""
        merged: dict[int, list] = {}
        for node, coef, vec in r.terms:
            merged.setdefault(node, []).append((coef, tuple(vec)))
        return SymRow(owner, element, tuple((n, tuple(t)) for n, t in sorted(merged.items())), r.scale)

    def _angle_rows(self) -> list[SymRow]:
        rows: list[SymRow] = []
        for name, ns in self.mech.links:
            for a in range(len(ns)):
                for b in range(a + 1, len(ns)):
                    vec, norm = self.direction(name, ns[a], ns[b])
                    i, j = self.index[ns[a]], self.index[ns[b]]
                    rows.append(SymRow(f"link {name} ({ns[a]}-{ns[b]})", name,
                                       ((i, ((sp.Integer(1), vec),)), (j, ((sp.Integer(-1), vec),))), norm))
            if len(ns) >= 3:
                rows += self._body_extra_rows(name, ns)
        for s in self.mech.sliders:
            rows += self._slider_rows(s)
        return rows

    def _body_extra_rows(self, name: str, ns: tuple[str, ...]) -> list[SymRow]:
        """Angle coordinates: a degenerate (collinear) planar body's rows over its angle (node
        coordinates: :class:`~symkin.constraints.Body`), with its decision (hull, frame)."""
        body = next(b for b in body_constraints(self.mech) if b.link == name)
        hull = body.hull(self.x, self.tol.geometry)
        if hull is None:
            return []
        f0, f1 = (ns[k] for k in hull.frame)
        owner = body.owner
        alpha = self.angle(name, f0, f1)
        normal = (-sp.sin(alpha), sp.cos(alpha))
        e = self._delta_num(f0, f1)
        rows = []
        for m in (n for n in ns if n not in (f0, f1)):
            t = exact(float(np.dot(self._delta_num(f0, m), e) / np.dot(e, e)))
            rows.append(self._weighted_row(owner, name, normal, sp.Integer(1), {m: 1, f0: -(1 - t), f1: -t}))
        return rows

    def _weighted_row(self, owner, element, vec, scale, weights: dict[str, sp.Expr]) -> SymRow:
        blocks = tuple((self.index[n], ((sp.sympify(w), vec),)) for n, w in weights.items())
        return SymRow(owner, element, tuple(sorted(blocks, key=lambda b: b[0])), scale)

    def _normals(self, e: Vec, e_num: np.ndarray, length: sp.Expr | None = None) -> list[tuple[Vec, sp.Expr]]:
        """Normals of direction ``e`` with their norms: ``perp(e)`` in the plane; in space
        ``e × a`` and ``e × (e × a)`` with ``a`` the axis least aligned with ``e`` at the
        model's configuration, so that ``Σ n nᵀ / |n|² = I − ê êᵀ`` exactly.  ``length`` is
        ``|e|`` when it has a symbol."""
        norm_e = length if length is not None else sp.sqrt(_dot(e, e))
        if self.dim == 2:
            return [(_perp(e), norm_e)]
        axis = _unit(_least_aligned_axis(e_num), 3)
        n1 = _cross(e, axis)
        n2 = _cross(e, n1)
        norm1 = sp.sqrt(sp.expand(_dot(n1, n1)))
        return [(n1, norm1), (n2, norm_e * norm1)]

    def _slider_rows(self, s) -> list[SymRow]:
        """A slider's rows in angle coordinates (the planar sliders; node coordinates: the registry)."""
        p = s.node
        owner = f"slider {s.id}"
        if s.line is None:  # a fixed line (a planar model has no planes)
            raw = tuple(exact(v) for v in s.direction)
            return [self._weighted_row(owner, owner, n, norm, {p: 1})
                    for n, norm in self._normals(raw, np.array(s.direction, dtype=float))]
        a, c = s.line
        ll = self.length(s.link, a, c)
        alpha = self.angle(s.link, a, c)
        n = (-sp.sin(alpha), sp.cos(alpha))
        sv = slide_symbol(s.id)
        return [self._weighted_row(owner, owner, n, ll, {p: ll, a: -(ll - sv), c: -sv})]

    # ------------------------------------------------------------------ parameter rows
    def rotation_rows(self, link: str, label: str) -> list[SymRow]:
        """Angular velocity of ``link``: one row (planar) or three (ωx, ωy, ωz)."""
        ns = self._links[link]
        if self.dim == 2:
            dists = [np.linalg.norm(self._delta_num(ns[0], n)) for n in ns]
            i, j = ns[0], ns[int(np.argmax(dists))]
            vec, norm = self.direction(link, i, j)
            if self.mode == "nodes":
                n, scale = _perp(vec), norm ** 2
            else:
                n, scale = _perp(vec), self.length(link, i, j)
            return [self._weighted_row(label, link, n, scale, {j: 1, i: -1})]
        pts = np.array([self.x[self.index[n]] for n in ns])
        h, _, _ = affine_hull(pts, DEFAULT.geometry)
        i = ns[0]
        if h < 2:  # a rod: the angular velocity normal to its axis, from its last node
            k = ns[-1]
            r = self._delta_sym(i, k)
            ll = self.length(link, i, k)
            skew = ((0, -r[2], r[1]), (r[2], 0, -r[0]), (-r[1], r[0], 0))
            return [self._weighted_row(f"{label}.{AXES[c]}", link, tuple(sp.sympify(v) for v in skew[c]),
                                       ll ** 2, {k: 1, i: -1}) for c in range(3)]
        # a body: ω from two edges r1, r2 (best conditioned pair at the model's configuration).
        # With n = r1 × r2 and d_k = v_k − v_i = ω × r_k, decomposing a vector a on the basis
        # (n, r1 × n, r2 × n) gives  a·ω = [(a·n)(r2·d1) − (a·r2)(n·d1) + (a·r1)(n·d2)] / |n|²;
        # with a = e_c this is the row of ω_c.  It is exact on every rigid motion of the body.
        others = ns[1:]
        best, pair = -1.0, None
        for a in range(len(others)):
            for b in range(a + 1, len(others)):
                area = np.linalg.norm(np.cross(self._delta_num(i, others[a]), self._delta_num(i, others[b])))
                if area > best:
                    best, pair = area, (others[a], others[b])
        k1, k2 = pair
        r1, r2 = self._delta_sym(i, k1), self._delta_sym(i, k2)
        n = _cross(r1, r2)
        scale = _dot(n, n)
        rows = []
        for c in range(3):
            blocks = {k1: [(n[c], r2), (-r2[c], n)], k2: [(r1[c], n)],
                      i: [(-n[c], r2), (r2[c], n), (-r1[c], n)]}
            blocks = {nd: [(cf, v) for cf, v in t if cf != 0] for nd, t in blocks.items()}
            rows.append(SymRow(f"{label}.{AXES[c]}", link,
                               tuple(sorted(((self.index[nd], tuple(t)) for nd, t in blocks.items() if t),
                                            key=lambda b: b[0])), scale))
        return rows

    def _link_rotation(self, link: str, label: str) -> list[SymRow]:
        """:meth:`rotation_rows`; zero rows for the fixed frame of a joint model (``ground``, no such link)."""
        if link == GROUND and link not in self._links:
            return [SymRow(f"{label}.{AXES[c]}", link, (), sp.Integer(1)) for c in range(1 if self.dim == 2 else 3)]
        return self.rotation_rows(link, label)

    def _axis(self, axis) -> tuple:
        """A spatial rotation's axis vector (not normalised): two nodes' difference or the vector."""
        if isinstance(axis[0], str):
            return self._delta_sym(axis[0], axis[1])
        return tuple(exact(v) for v in axis)

    def parameter_rows(self, param: Parameter) -> list[SymRow]:
        """Rows of one kinematic parameter, in the numeric core's units and row order."""
        labels = param.labels(self.dim)
        kind = param.kind
        dim = self.dim
        if kind == "rotation":
            rows = self.rotation_rows(param.target[0], labels[0])
            if dim == 2:
                return [SymRow(labels[0], r.element, r.blocks, r.scale) for r in rows]
            vec = self._axis(param.axis)
            return [_combine(rows, list(vec), labels[0], param.target[0],
                             extra_scale=sp.sqrt(_dot(vec, vec)))]
        if kind == "joint":  # the second link's rotation minus the first's (spatial: about the axis)
            r1 = self._link_rotation(param.target[0], "a")
            r2 = self._link_rotation(param.target[1], "b")
            element = f"joint {param.target[0]}-{param.target[1]}"
            if dim == 2:
                return [_combine([b, a], [sp.Integer(1), sp.Integer(-1)], lab, element)
                        for a, b, lab in zip(r1, r2, labels)]
            vec = list(self._axis(param.axis))
            return [_combine(r2 + r1, vec + [-v for v in vec], labels[0], element,
                             extra_scale=sp.sqrt(_dot(vec, vec)))]
        if kind == "twist":
            link = param.target[0]
            first = self.index[self._links[link][0]]
            vel = [SymRow(labels[c], link, ((first, ((sp.Integer(1), _unit(c, dim)),)),), sp.Integer(1))
                   for c in range(dim)]
            rot = self.rotation_rows(link, "w")
            return vel + [SymRow(lab, r.element, r.blocks, r.scale) for r, lab in zip(rot, labels[dim:])]
        if kind == "velocity":
            node = self.index[param.target[0]]
            comps = [AXES.index(param.component)] if param.component else range(dim)
            return [SymRow(lab, param.target[0], ((node, ((sp.Integer(1), _unit(c, dim)),)),), sp.Integer(1))
                    for c, lab in zip(comps, labels)]
        if kind == "slide":
            con = slider_constraint(self.mech, param.target[0])
            if self.mode == "angles" and isinstance(con, SliderMovingLine):  # over the link's angle and the slide
                s = con.slider
                p, (a, c) = s.node, s.line
                ll = self.length(s.link, a, c)
                alpha = self.angle(s.link, a, c)
                u = (sp.cos(alpha), sp.sin(alpha))
                sv = slide_symbol(s.id)
                return [self._weighted_row(labels[0], s.id, u, ll, {p: ll, a: -(ll - sv), c: -sv})]
            # the slider's rate row, as its definition states it (symkin.constraints)
            return [self._sym_row(r, labels[0], con.slider.id) for r in con.rate_rows(self._algebra(), *self._positions())]
        raise SymkinError(f"unknown parameter kind {kind!r}")
