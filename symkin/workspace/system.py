"""The position problem of a singularity map: two axis coordinates and the held ones fix the mechanism.

A map (paper §VI, Figs. 14-16) sweeps two position-level coordinates, the *axes*, over a
box; with mobility ``F > 2`` the ``F − 2`` *held* coordinates are fixed at values (default:
the model's).  At a grid point ``(x, y)`` the configuration ``q`` (the ``nf`` free nodal
coordinates, in the order of ``symkin.evaluators(mech).q_labels``) solves the square system

.. math::  S(q; x, y, h) = [\\,Φ_S(q)/ℓ;\\; (c(q) − h)/s_c;\\; (a(q) − (x, y))/s_a\\,] = 0

with ``Φ_S`` the ``nf − F`` independent rows of the evaluators' closure (the same closure
paths use; rows ``basis_rows`` of the evaluators, chosen once), ``c`` the held coordinates,
``a`` the two axis coordinates, ``ℓ`` the model's length scale and ``s = ℓ`` for lengths,
``1`` for angles: every row is dimensionless, so a model in millimetres and in metres
solves the same system.  ``nf`` unknowns, ``(nf − F) + (F − 2) + 2 = nf`` equations.

Coordinates (labels as :func:`symkin.numeric.coordinates.parse_input_label` takes them) are
**absolute**, in internal units (model lengths, radians):

* ``velocity:P.x`` — the node's coordinate;
* ``rotation:L`` (planar) — the direction of link L's first node → second node from +x,
  continuous on ``(θ₀ − π, θ₀ + π]`` around its model value ``θ₀``;
* ``slide:S`` — the slider node's position along its line from the line's point (fixed
  line) or from the line's first node (moving line);
* anything else a path accepts (joint angles, spatial rotations about a fixed axis) —
  measured from the model's configuration.

User-facing values (axis ranges, hold values, the map's axes) are in the map's ``unit``
for angles (``"deg"`` by default, or ``"rad"``) and model units for lengths;
:meth:`MapSystem.to_internal` / :meth:`MapSystem.to_user` convert.

API for the other workspace modules (``grid``, ``loci``, ``maps``)
-----------------------------------------------------------------
``system = map_system(mech, x, y, hold=(), unit="deg", tolerances=None)`` → :class:`MapSystem`.
``hold`` is a sequence of labels or ``(label, value)`` pairs (value in the user unit; None:
the model's).  Errors (:class:`symkin.errors.SymkinError`): a label naming nothing, the same
coordinate twice, F < 2, a number of holds that does not square the problem (the message
names what is missing), axes + holds that do not fix the mechanism.

CasADi Functions in ``system.functions`` (all take column vectors; ``N`` configurations
through ``Function.map`` or :meth:`MapSystem.evaluate`):

``square``       ``(q[nf], target[F])`` → ``S[nf]``, ``dS_dq[nf×nf]``; ``target = [x, y, h…]``
                 in internal units (:meth:`MapSystem.targets` builds it).
``constraints``  ``(q[nf], h[F−2])`` → ``C[nf−2]``, ``dC_dq[(nf−2)×nf]``: closure and holds, the
                 axes free — the 2-D solution surface on which ``loci`` traces a curve by adding
                 one test function (closure + test function = 0).
``axes``         ``q`` → ``a[2]``, ``da_dq[2×nf]`` (internal units).
``holds``        ``q`` → ``c[F−2]`` (internal units).

Methods: :meth:`~MapSystem.solve` (batched Newton, ``(q_start[N,nf], xy[N,2]) → (q, converged,
residual, iterations)``), :meth:`~MapSystem.axis_values` (``q[N,nf] → [N,2]``),
:meth:`~MapSystem.evaluate` (any Function above at N points), :attr:`~MapSystem.q0`.
Indicators at solved configurations come from ``system.evaluators.batch(q)`` (the one
analysis core); nothing here decides a singularity.

Examples
--------
>>> from symkin.model.catalogue import get
>>> s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
>>> s.nf, s.mobility, [a.label for a in s.axes], s.axis_values(s.q0[None]).tolist()
(6, 2, ['velocity:P.x', 'velocity:P.y'], [[0.0, 2.0]])
>>> q, ok, res, _ = s.solve(s.q0[None], [[0.3, 2.2]])
>>> ok.tolist(), s.axis_values(q).round(12).tolist()
([True], [[0.3, 2.2]])
>>> bool(abs(s.evaluators("closure", q[0])["phi"]).max() < 1e-12)
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np

from symkin.analysis.batch import Evaluators, evaluators_for
from symkin.constraints import slider_constraint
from symkin.constraints.algebra import FLOATS
from symkin.errors import SymkinError
from symkin.model.labels import parse_hold, parse_holds, parse_orientation_label  # parse_hold re-exported
from symkin.model.mechanism import AXES, Mechanism
from symkin.numeric.linalg import independent_rows
from symkin.numeric.coordinates import InputCoordinate, accepted_input_labels, parse_input_label
from symkin.curves.corrector import gauss_newton_batch
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["MapCoordinate", "MapSystem", "map_system", "turned", "window_note", "parse_hold", "UNITS", "NEWTON_TOL", "NEWTON_ITER"]

#: angle units a map accepts, with their factor to radians
UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
#: Newton converges when the dimensionless residual ``max |S|`` is at most this (lengths / ℓ)
NEWTON_TOL = 1e-11
#: Newton iterations before a grid point counts as not reached
NEWTON_ITER = 12
#: from this iteration on, a Newton iterate whose residual grows is given up (it diverges)
DIVERGE_AFTER = 3
#: largest number of points per mapped call
_CHUNK = 2048


@dataclass(frozen=True)
class MapCoordinate:
    """One absolute coordinate of a map (an axis or a held coordinate).

    ``coordinate`` is the path coordinate it is built on (relative to the model's
    configuration); ``offset`` its absolute value there, so that the absolute value is
    ``offset + coordinate`` (internal units: model lengths, radians).  ``kind`` is
    ``"angle"`` or ``"length"``.
    """

    label: str
    kind: str
    coordinate: InputCoordinate
    offset: float

    def expression(self, mech: Mechanism, x, x0: np.ndarray):
        """CasADi expression of the absolute value; ``x`` all nodal coordinates (column)."""
        return self.offset + self.coordinate.expression(mech, x, x0)

    def scale(self, length_scale: float) -> float:
        """What the residual row of this coordinate is divided by (``ℓ`` for lengths, 1 for angles)."""
        return length_scale if self.kind == "length" else 1.0


def _offset(mech: Mechanism, c: InputCoordinate, x0: np.ndarray) -> float:
    """Absolute value of ``c`` at the model's configuration (0 for relative-only coordinates)."""
    p = c.parameter
    if p.kind == "rotation" and mech.dim == 2:
        return float(c.absolute(mech, x0))
    if p.kind == "velocity":
        i = mech.node_index()[p.target[0]]
        axis = AXES.index(p.component) if p.component else c.component
        return float(x0[i, axis])
    if p.kind == "slide":  # the slide of its definition (symkin.constraints)
        return float(slider_constraint(mech, p.target[0]).slide(FLOATS, [tuple(map(float, r)) for r in x0]))
    return 0.0


#: below this ``1 − cos θ`` the factor θ / sin θ of the rotation vector is its series (error ~1e-16)
_SERIES_BELOW = 1e-5


@dataclass(frozen=True)
class OrientationComponent:
    """``rotation:<link>[x|y|z]`` of a spatial rigid link: a component of its rotation vector.

    The rotation vector ``θ·n`` of ``R = F(x) F(x₀)ᵀ``, the rotation that takes the link from
    its orientation in the model to its orientation at ``x`` (components in the fixed frame,
    an angle: ``--unit``), with ``F`` the orthonormal frame of three of its nodes (the first,
    the farthest from it, and the farthest from their line).  Holding the three components
    (default: the model's values, 0) holds the link's orientation: a spatial map slice at
    constant orientation, e.g. ``--hold rotation:platform[x] --hold rotation:platform[y]
    --hold rotation:platform[z] --hold velocity:O.z``.  ``θ·n = vee(R − Rᵀ)/2 · θ/sin θ``
    (``cos θ = (tr R − 1)/2``) is smooth for ``θ < π``, including ``θ = 0``.
    """

    label: str
    link: str
    axis: int
    nodes: tuple[int, int, int]
    kind: str = "angle"

    @staticmethod
    def _frame(pts):
        p0, p1, p2 = pts
        e1 = p1 - p0
        e1 = e1 / ca.norm_2(e1)
        e3 = ca.cross(e1, p2 - p0)
        e3 = e3 / ca.norm_2(e3)
        return ca.horzcat(e1, ca.cross(e3, e1), e3)

    def expression(self, mech: Mechanism, x, x0: np.ndarray):
        d = mech.dim
        f = self._frame([x[k * d:(k + 1) * d] for k in self.nodes])
        f0 = self._frame([ca.DM(np.asarray(x0, float).reshape(-1, d)[k]) for k in self.nodes])
        r = ca.mtimes(f, f0.T)
        v = ca.vertcat(r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]) / 2  # sin θ · n
        u = 1 - (r[0, 0] + r[1, 1] + r[2, 2] - 1) / 2  # 1 − cos θ
        series = u < _SERIES_BELOW
        c = 1 - ca.if_else(series, 2 * _SERIES_BELOW, u)  # the exact branch away from θ = 0 (finite derivative)
        exact = ca.acos(c) / ca.sqrt(1 - c * c)
        factor = ca.if_else(series, 1 + u / 3 + 2 * u * u / 15, exact)  # θ / sin θ
        return v[self.axis] * factor


def _orientation_component(mech: Mechanism, label: str) -> OrientationComponent | None:
    """``rotation:<link>[x|y|z]`` of a spatial moving link (read by :func:`symkin.model.labels.parse_orientation_label`,
    the one definition ``conditions`` uses too), else None."""
    o = parse_orientation_label(mech, label)
    if o is None:
        return None
    idx = mech.node_index()
    return OrientationComponent(o.label, o.link, o.axis, tuple(idx[n] for n in o.nodes))


def map_coordinate(mech: Mechanism, label: str) -> MapCoordinate:
    """The absolute map coordinate named ``label``; a :class:`SymkinError` listing what is accepted.

    Besides the labels of :func:`symkin.numeric.coordinates.parse_input_label`, a spatial
    link's orientation component ``rotation:<link>[x|y|z]`` (:class:`OrientationComponent`,
    relative to the model's orientation).
    """
    o = _orientation_component(mech, label)
    if o is not None:
        return MapCoordinate(o.label, o.kind, o, 0.0)
    c = parse_input_label(mech, label)
    x0 = np.array([v for _, v in mech.nodes], dtype=float)
    return MapCoordinate(c.label, c.kind, c, _offset(mech, c, x0))


def turned(c: MapCoordinate, centre: float) -> MapCoordinate:
    """``c`` measured on the model's branch of angles shifted by the whole turns that centre it on ``centre``.

    An angle's absolute value is ``offset + coordinate`` with the coordinate in (−π, π] about the
    model (:class:`MapCoordinate`); the offset moves by ``2π·k``, ``k`` the whole number of turns
    nearest to ``(centre − offset) / 2π`` (halves rounded up), so that a map window and the
    same window shifted by a turn are measured on branches one turn apart: angle windows are
    taken modulo 360°.  Lengths and a spatial link's orientation components (not periodic)
    are returned as they are.  ``centre`` in radians.

    >>> from symkin.model.catalogue import get
    >>> c = map_coordinate(get("five_bar"), "rotation:crank1")
    >>> round(math.degrees(turned(c, math.radians(540)).offset - c.offset), 9)
    360.0
    """
    if c.kind != "angle" or isinstance(c.coordinate, OrientationComponent) or not math.isfinite(centre):
        return c
    k = math.floor((centre - c.offset) / (2 * math.pi) + 0.5)
    return replace(c, offset=c.offset + 2 * math.pi * k) if k else c


def window_note(c: MapCoordinate, lo: float, hi: float, unit: str = "deg") -> str | None:
    """A sentence when the window ``[lo, hi]`` (``unit``) of an angle axis reaches past its branch, else None.

    The branch is ``(offset − π, offset + π]`` (:func:`turned`): the part of the window outside it
    cannot assemble on this map (the same configurations are one turn away, inside the branch).
    """
    if c.kind != "angle" or isinstance(c.coordinate, OrientationComponent):
        return None
    f = UNITS[unit]
    b_lo, b_hi = (c.offset - math.pi) / f, (c.offset + math.pi) / f
    tol = DEFAULT.geometry * (abs(b_lo) + abs(b_hi))
    if lo >= b_lo - tol and hi <= b_hi + tol:
        return None
    why = "is wider than a turn" if hi - lo > 2 * math.pi / f else "is not within one turn of it"
    return (f"{c.label}: angles are taken modulo a turn, measured on ({b_lo:.6g}, {b_hi:.6g}] {unit} (the model's "
            f"branch shifted by whole turns to the window); the window {lo:.6g}:{hi:.6g} {why}, and its part "
            "outside that range cannot assemble on this map")


def _holds_needed_text(mech: Mechanism, used: set[str]) -> str:
    a = accepted_input_labels(mech)
    candidates = [lab for lab in a["inputs"] + a["outputs"] if lab not in used]
    return f" (e.g. {', '.join(candidates)})" if candidates else ""


@dataclass(eq=False)
class MapSystem:
    """The square position problem of a map (see the module docstring for the API).

    Build it with :func:`map_system`.  Attributes: ``mech``, ``evaluators`` (shared,
    :func:`symkin.analysis.batch.evaluators_for`), ``axes`` (two :class:`MapCoordinate`),
    ``holds`` (``F − 2`` of them), ``hold_values`` (internal units), ``unit``, ``rows`` (the
    closure rows kept, indices into the evaluators' ``phi``), ``functions`` (CasADi).
    """

    mech: Mechanism
    axes: tuple[MapCoordinate, MapCoordinate]
    holds: tuple[MapCoordinate, ...]
    hold_values: np.ndarray
    unit: str = "deg"
    tolerances: Tolerances = DEFAULT
    evaluators: Evaluators = field(init=False, repr=False)
    rows: tuple[int, ...] = field(init=False)
    functions: dict = field(init=False, repr=False)
    #: the model's length scale (``mech.length_scale``, computed once)
    ell: float = field(init=False, repr=False)
    #: internal units per dimensionless unit of each axis (``ℓ`` for a length, 1 for an angle)
    axis_scale: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        self.evaluators = evaluators_for(self.mech)
        ev = self.evaluators
        m = ev.model
        scale = self.mech.length_scale
        self.ell = float(scale)
        self.axis_scale = np.array([c.scale(scale) for c in self.axes], float)
        self._shapes: dict = {}
        f, nf = ev.mobility, ev.nf
        q = ca.SX.sym("q", nf)
        x = ca.substitute(m.x, m.q, q)
        phi = ca.substitute(m.closure, m.q, q)
        if m.p.numel():
            phi = ca.substitute(phi, m.p, ca.DM(m.p0))
        self.rows = self._closure_rows(phi, q, nf - f)
        phi_s = phi[list(self.rows)] / scale if self.rows else ca.SX(0, 1)
        x0 = np.array([c for _, c in self.mech.nodes], dtype=float)
        a = ca.vertcat(*[c.expression(self.mech, x, x0) for c in self.axes])
        c = ca.vertcat(*[c.expression(self.mech, x, x0) for c in self.holds]) if self.holds else ca.SX(0, 1)
        sa = ca.DM([k.scale(scale) for k in self.axes])
        sc = ca.DM([k.scale(scale) for k in self.holds]) if self.holds else ca.DM(0, 1)
        target = ca.SX.sym("target", f)
        h = ca.SX.sym("h", len(self.holds))
        held = (c - target[2:]) / sc if self.holds else ca.SX(0, 1)
        s = ca.vertcat(phi_s, held, (a - target[:2]) / sa)
        cons = ca.vertcat(phi_s, (c - h) / sc if self.holds else ca.SX(0, 1))
        d = ca.densify  # dense outputs: the buffer interface writes every entry
        self.functions = {
            "square": ca.Function("map_square", [q, target], [d(s), d(ca.jacobian(s, q))], ["q", "target"],
                                  ["S", "dS_dq"]),
            "constraints": ca.Function("map_constraints", [q, h], [d(cons), d(ca.jacobian(cons, q))], ["q", "h"],
                                       ["C", "dC_dq"]),
            "axes": ca.Function("map_axes", [q], [d(a), d(ca.jacobian(a, q))], ["q"], ["a", "da_dq"]),
            "holds": ca.Function("map_holds", [q], [d(c)], ["q"], ["c"]),
        }
        self._maps: dict = {}
        self._check_independent()

    # ------------------------------------------------------------------ set-up
    def _closure_rows(self, phi, q, count: int) -> tuple[int, ...]:
        """The evaluators' independent rows ``J_S``, else rows chosen here at the model's configuration."""
        ev = self.evaluators
        if count <= 0:
            return ()
        if ev.basis_rows and len(ev.basis_rows) == count:
            return tuple(ev.basis_rows)
        jac = np.array(ca.Function("j", [q], [ca.jacobian(phi, q)])(ev.q0))
        rows = independent_rows(jac, self.tolerances.rank, count)
        if len(rows) < count:
            raise SymkinError(f"{self.mech.name}: the closure has rank {len(rows)} at the model's configuration, "
                              f"not nf - F = {count}; a map needs the generic mobility")
        return rows

    def _check_independent(self) -> None:
        """Axes and holds must fix the mechanism: ``dS/dq`` regular at the model's configuration or near it."""
        q0 = self.q0
        t0 = self.targets(self.axis_values(q0[None])[0][None])[0]
        if self._regular(q0, t0):
            return
        rng = np.random.default_rng(0)
        q1 = q0 + 1e-2 * self.mech.length_scale * rng.standard_normal(q0.size)
        try:
            q1 = self.evaluators.project(q1)
        except SymkinError:
            q1 = None
        if q1 is not None and self._regular(q1, self.targets(self.axis_values(q1[None]))[0]):
            return
        names = ", ".join(c.label for c in self.axes + self.holds)
        raise SymkinError(f"{self.mech.name}: the axes and holds ({names}) do not fix the mechanism: they are "
                          "not independent coordinates of its configuration (the position problem is singular)")

    def _regular(self, q: np.ndarray, target: np.ndarray) -> bool:
        jac = np.array(self.functions["square"](q, target)[1])
        rows = independent_rows(jac, self.tolerances.rank)
        return len(rows) == self.nf

    # ------------------------------------------------------------------ sizes and units
    @property
    def nf(self) -> int:
        return self.evaluators.nf

    @property
    def mobility(self) -> int:
        return self.evaluators.mobility

    @property
    def q0(self) -> np.ndarray:
        """Free coordinates of the model's configuration."""
        return np.asarray(self.evaluators.q0, dtype=float).ravel()

    @property
    def labels(self) -> tuple[str, str]:
        return self.axes[0].label, self.axes[1].label

    def _factors(self, coords) -> np.ndarray:
        return np.array([UNITS[self.unit] if c.kind == "angle" else 1.0 for c in coords])

    def to_internal(self, values, which: str = "axes") -> np.ndarray:
        """User-unit values of the axes (``which="axes"``, last axis of size 2) or holds → internal units."""
        coords = self.axes if which == "axes" else self.holds
        return np.asarray(values, dtype=float) * self._factors(coords)

    def to_user(self, values, which: str = "axes") -> np.ndarray:
        """Internal values (radians, model lengths) → the user's unit (inverse of :meth:`to_internal`)."""
        coords = self.axes if which == "axes" else self.holds
        return np.asarray(values, dtype=float) / self._factors(coords)

    def targets(self, xy) -> np.ndarray:
        """``[x, y, h…]`` rows (N, F) for axis values ``xy`` (N, 2), internal units."""
        xy = np.atleast_2d(np.asarray(xy, dtype=float))
        return np.hstack([xy, np.broadcast_to(self.hold_values, (xy.shape[0], len(self.holds)))])

    # ------------------------------------------------------------------ batched evaluation
    def evaluate(self, name: str, *args) -> list[np.ndarray]:
        """Function ``name`` at N points: ``args`` are (N, size) arrays (or one shared 1-D vector).

        Returns the outputs as arrays of shape ``(N, rows)`` (vectors) or ``(N, rows, cols)``.
        Evaluated by ``Function.map`` over chunks of a power-of-two size through CasADi's
        buffer interface (no Python loop per point, no conversion to ``DM``).
        """
        f = self.functions[name]
        shapes = self._shapes.get(name)
        if shapes is None:  # the Function's sizes, asked of CasADi once
            shapes = self._shapes[name] = ([f.numel_in(k) for k in range(f.n_in())],
                                           [f.size_out(i) for i in range(f.n_out())])
        numel_in, size_out = shapes
        n = max(np.shape(a)[0] if np.ndim(a) == 2 else 1 for a in args)
        ins = []
        for k, a in enumerate(args):
            a = np.asarray(a, dtype=float).reshape(-1, numel_in[k])
            ins.append(a if a.shape[0] == n and a.flags.c_contiguous else
                       np.ascontiguousarray(np.broadcast_to(a, (n, numel_in[k]))))
        outs = [np.empty((n,) + so[::-1]) for so in size_out]
        size = min(_CHUNK, 1 << max(0, (n - 1).bit_length()))
        hit = self._maps.get((name, size))
        if hit is None:
            fm = f if size == 1 else f.map(f"{f.name()}_map{size}", "serial", size, [], [])
            hit = (fm,) + tuple(fm.buffer())
            self._maps[(name, size)] = hit
        _, buf, trig = hit
        for start in range(0, n, size):
            stop = min(start + size, n)
            if stop - start == size:
                part_in = [a[start:stop] for a in ins]
                part_out = [o[start:stop] for o in outs]
            else:  # the last chunk, padded with its first point
                part_in = [np.ascontiguousarray(np.concatenate([a[start:stop], np.repeat(a[start:start + 1],
                                                                                          size - stop + start, 0)]))
                           for a in ins]
                part_out = [np.empty((size,) + o.shape[1:]) for o in outs]
            for k, a in enumerate(part_in):
                buf.set_arg(k, memoryview(a))
            for k, o in enumerate(part_out):
                buf.set_res(k, memoryview(o))
            trig()
            if stop - start != size:
                for o, po in zip(outs, part_out):
                    o[start:stop] = po[: stop - start]
        result = []
        for o, (r, c) in zip(outs, size_out):
            result.append(o.reshape(n, r) if c == 1 else o.transpose(0, 2, 1))
        return result

    def axis_values(self, q) -> np.ndarray:
        """Axis values (N, 2) of configurations ``q`` (N, nf), internal units."""
        return self.evaluate("axes", np.atleast_2d(q))[0]

    def solve(self, q_start, xy, tol: float = NEWTON_TOL, max_iter: int = NEWTON_ITER,
              return_jacobian: bool = False):
        """Batched Newton on :math:`S(q; x, y, h) = 0` from ``q_start`` (N, nf) to axis values ``xy`` (N, 2).

        Parameters
        ----------
        q_start : array (N, nf)
            Starting configurations (a neighbouring solved grid point, or a predictor).
        xy : array (N, 2)
            Axis values, internal units (radians, model lengths).
        tol : float
            Converged when the dimensionless residual ``max |S| <= tol``.
        max_iter : int
            Newton iterations at most; a point not converged by then, whose step is not
            finite (singular position problem) or whose residual grows from iteration
            :data:`DIVERGE_AFTER` on, is reported as not converged.

        return_jacobian : bool
            Also return ``∂S/∂q`` (N, nf, nf) at the solved configurations (NaN where not
            converged): the Jacobian of the last residual evaluation (it does not depend on
            the targets), so a tangent there needs no further evaluation.

        Returns
        -------
        q : (N, nf) solved configurations (the last iterate where not converged),
        converged : (N,) bool, residual : (N,) ``max |S|``, iterations : (N,) int
        (and the Jacobian, with ``return_jacobian``).
        """
        q = np.array(np.atleast_2d(q_start), dtype=float)
        t = self.targets(xy)
        n = q.shape[0]
        if t.shape[0] != n:
            raise ValueError("one row of xy per starting configuration")
        out = gauss_newton_batch(lambda z, rows: self.evaluate("square", z, t[rows]), q, tol=tol,
                                 max_iterations=max_iter, diverge_after=DIVERGE_AFTER, norm="max",
                                 return_jacobian=return_jacobian)
        if return_jacobian:
            jac = out.jacobian if out.jacobian is not None else np.full((n, self.nf, self.nf), np.nan)
            return out.z, out.converged, out.residual, out.iterations, jac
        return out.z, out.converged, out.residual, out.iterations


def map_system(mech: Mechanism, x: str, y: str, hold=(), unit: str = "deg",
               tolerances: Tolerances | float | None = None, windows=None) -> MapSystem:
    """The position problem of a map of ``mech`` over axes ``x`` and ``y`` (labels).

    Parameters
    ----------
    mech : Mechanism
    x, y : str
        Axis labels (``velocity:P.x``, ``rotation:L``, ``slide:S``, or any label
        ``symkin path --input`` takes).
    hold : sequence of str or (str, float | None)
        The ``F − 2`` held coordinates: labels (held at the model's value), ``"LABEL=VALUE"``
        strings, or ``(label, value)`` pairs, values in ``unit`` for angles.
    unit : ``"deg"`` or ``"rad"``
        Unit of angle values given by the user (axes ranges, hold values).
    tolerances : Tolerances or float, optional
        The rank tolerance used for the independence checks.
    windows : ((float, float), (float, float)), optional
        The axes' ranges (``unit`` for angles).  An angle axis (and an angle held at a value)
        is measured on the model's branch shifted by whole turns to the window's centre
        (:func:`turned`): angle windows are taken modulo 360°, the map of ``360:720`` is
        the map of ``0:360`` shifted.  Without it, the model's branch.

    Raises
    ------
    SymkinError
        Unknown label, a coordinate named twice, F < 2, holds that do not square the
        problem (the message says how many and suggests labels), or axes and holds that
        do not fix the mechanism.
    """
    if unit not in UNITS:
        raise SymkinError(f"unknown angle unit {unit!r}; use one of {', '.join(UNITS)}")
    tol = Tolerances.of(tolerances)
    f = mech.mobility_value
    if f < 2:
        raise SymkinError(f"{mech.name}: mobility F = {f}; a map needs F >= 2 (two axis coordinates), "
                          "use symkin path for F = 1")
    axes = (map_coordinate(mech, x), map_coordinate(mech, y))
    pairs = parse_holds(hold)
    holds = tuple(map_coordinate(mech, label) for label, _ in pairs)
    seen: dict[str, str] = {}
    for c in axes + holds:
        if c.label in seen:
            raise SymkinError(f"{c.label} is named twice (as axis or hold); each coordinate can be fixed once")
        seen[c.label] = c.label
    need = f - 2
    if len(holds) != need:
        used = {c.label for c in axes + holds}
        if len(holds) < need:
            raise SymkinError(f"{mech.name}: F = {f}, so 2 axes need {need} held coordinate(s) to make the "
                              f"position problem square; {len(holds)} given: add {need - len(holds)} "
                              f"--hold LABEL[=VALUE]{_holds_needed_text(mech, used)}")
        raise SymkinError(f"{mech.name}: F = {f}, so 2 axes need {need} held coordinate(s); {len(holds)} given "
                          f"({', '.join(c.label for c in holds)}): the position problem is over-determined")
    if windows is not None:
        axes = tuple(turned(c, 0.5 * (float(lo) + float(hi)) * (UNITS[unit] if c.kind == "angle" else 1.0))
                     for c, (lo, hi) in zip(axes, windows))
    values = []
    for k, (c, (_, v)) in enumerate(zip(holds, pairs)):
        if v is None:
            values.append(c.offset)  # the model's value
        else:
            values.append(v * (UNITS[unit] if c.kind == "angle" else 1.0))
            holds = holds[:k] + (turned(c, values[-1]),) + holds[k + 1:]
    return MapSystem(mech, axes, holds, np.array(values, dtype=float), unit=unit, tolerances=tol)
