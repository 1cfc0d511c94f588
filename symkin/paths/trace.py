"""Trace a mechanism along its input, locate singular configurations and classify them.

:func:`trace` is the mechanism layer over the curve toolkit: it builds the position problem
(:class:`~symkin.paths.system.MechanismCurve`), the event types from the indicators and the
stop rules, and calls the one tracer (:func:`symkin.curves.tracer.trace_curve`), which
continues the curve with pseudo-arclength steps, evaluates every test at each accepted
point and locates every event to machine precision (:mod:`symkin.curves.locate`); then it
classifies the events.  The event types:

* ``DKP-input`` — sign change of ``det[J_S; P̂_in] / sqrt(det(J_S J_Sᵀ))`` (J_S: the
  evaluators' independent geometric rows, P̂_in: unit input rows), which equals
  ``± det(P̂_in V)`` for an orthonormal motion-space basis V: a turning point of the input
  when F = 1;
* ``DKP-output`` — the same with the output rows (or, when the outputs are not F
  scalars, a near-zero minimum of the smallest restricted output singular value);
* ``bifurcation`` — sign change of ``det[J_H; tᵀ]``, the augmented Jacobian of the
  continuation: a simple branch point (IM);
* ``IM`` — a near-zero minimum of ``σ_{F+1}`` (the square root of the paper's IM indicator,
  which touches zero without changing sign; ``J`` is dimensionless), for tangent branch points;
  IM events are moved onto their branch point by the one singular-point locator
  (:func:`symkin.curves.locate.locate_singular_point`: exact derivatives, deflation);
* ``LIM:<link>`` (F = 1) — a link stops while the mechanism moves: sign change of its
  angular rate about its fixed pivot or axis along the tangent, or a near-zero minimum of
  its free nodes' speed (:func:`~symkin.analysis.indicators.link_rate`,
  :func:`~symkin.analysis.indicators.link_speed`); an event of kind LIM, merged into a DKP
  event at the same configuration (kinds in the order IM, DKP-input, DKP-output, LIM);
* ``end`` — the input reaches the requested value.

The row subsets of the signed DKP and bifurcation tests (``J_S``, the rows kept of ``J_H``)
are chosen anew where they lose rank relative to all the rows (redundant rows: the Bennett
loop), their sign carried across the change (``Tolerances.row_switch``): a sign change is a
zero of the test, never a change of rows.

The DKP and IM tests, and the indicators recorded at every point, are values of the one
definition in :mod:`symkin.analysis.indicators`, on the rows of the mechanism's evaluators
(so ``ev.batch`` and :func:`symkin.analyze` give the same numbers at the same
configurations).  Minimum tests accept an event below ``Tolerances.event_threshold``;
every located event is classified as :func:`symkin.analyze` classifies it, with the same
tolerances (:func:`classify_event`: from the curve's own rows where they are the core's),
and bifurcations get the second-order branch analysis of :mod:`symkin.paths.branching`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Callable

import casadi as ca
import numpy as np

from symkin.analysis import indicators
from symkin.analysis.classification import Analysis, analyze, classify, platform_twist
from symkin.analysis.motion_space import ConfigurationRows
from symkin.curves.events import ArclengthLimit, Closed, EventType, ParameterReached, SingularEvent
from symkin.curves.locate import polish
from symkin.curves.stepper import CurvePoint, Settings, correct, point_at, tangent
from symkin.curves.tracer import TracedPoint, trace_curve
from symkin.errors import SymkinError
from symkin.kinds import Kind, describe
from symkin.model.mechanism import Mechanism
from symkin.model.labels import driving_labels
from symkin.numeric.coordinates import InputCoordinate, parse_input_label
from symkin.numeric.linalg import independent_rows
from symkin.paths.branching import Bifurcation, branch_directions
from symkin.paths.system import MechanismCurve, make_curve
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["PathPoint", "PathEvent", "Path", "trace", "follow_branch", "relative_angle", "absolute_angle",
           "CoordinateValues", "classify_event", "curve_rows", "curve_rows_cover"]

#: kinds in merging order: an event located by several tests takes the first of their kinds
KIND_PRIORITY = (Kind.IM, Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.LIM)
#: the arclength limit of a path by default (units of the model's length scale): ~10 full turns of a
#: crank of unit length, far beyond any one loop of the catalogue's mechanisms
MAX_ARCLENGTH = 60.0
#: a model configuration whose closure residual (units of the length scale) exceeds this is projected
#: onto the closure before the path starts (coordinates typed with ~10 significant digits close to it)
START_CLOSURE = 1e-9


# ---------------------------------------------------------------------- the angle convention
def relative_angle(value: float) -> float:
    """An angle measured from the model's configuration, wrapped to (−π, π] (radians).

    Every command, JSON, CSV and plot gives an angle coordinate twice: *relative* to the
    model, in (−180°, 180°], and *absolute* (a planar link's direction, first node → second
    node, from +x), in [0°, 360°).

    >>> relative_angle(math.radians(306.0809543)) == math.radians(306.0809543) - 2 * math.pi
    True
    >>> relative_angle(-math.pi) == math.pi
    True
    """
    r = math.remainder(value, 2 * math.pi)
    return math.pi if r == -math.pi else r


def absolute_angle(value: float | None) -> float | None:
    """An absolute angle wrapped to [0, 2π) (radians); None stays None (see :func:`relative_angle`).

    >>> round(math.degrees(absolute_angle(math.radians(-144.9666511))), 7)
    215.0333489
    """
    if value is None:
        return None
    a = value % (2 * math.pi)
    return 0.0 if a >= 2 * math.pi else a


class CoordinateValues:
    """Coordinates (the model's outputs by default) at any configuration: relative and absolute.

    Parameters
    ----------
    mech : Mechanism
        The mechanism; values are measured from its configuration.
    labels : sequence of str, optional
        Coordinate labels (as ``symkin path --input`` takes them); default the model's
        scalar outputs (twists and the like, which no one coordinate measures, are left out).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> m = get("fourbar_appendix")
    >>> v = CoordinateValues(m)(np.array([c for _, c in m.nodes]), unit="deg")
    >>> v["rotation:rocker"]["relative"], round(v["rotation:rocker"]["absolute"], 6)
    (0.0, 85.601295)
    """

    def __init__(self, mech: Mechanism, labels=None):
        import casadi as ca

        coords = ([InputCoordinate.of(c) for c in driving_labels(mech, mech.outputs)] if labels is None
                  else [parse_input_label(mech, label) for label in labels])
        x = ca.SX.sym("x", len(mech.nodes) * mech.dim)
        x0 = np.array([p for _, p in mech.nodes], float)
        self.mech, self.coordinates = mech, tuple(coords)
        self._f = ca.Function("values", [x], [ca.vertcat(*[c.expression(mech, x, x0) for c in coords])]) \
            if coords else None

    @property
    def labels(self) -> tuple[str, ...]:
        return tuple(c.label for c in self.coordinates)

    def __call__(self, configuration, unit: str = "rad") -> dict:
        """``{label: {"relative": r, "absolute": a}}`` at ``configuration`` ((n, dim) array or node dict).

        Angles in ``unit`` by the convention of :func:`relative_angle` (``absolute`` None for a
        spatial rotation); lengths in model units, ``absolute`` the node's coordinate for
        ``velocity:N.x`` (as a map's axes take it), None for a slide.
        """
        if isinstance(configuration, dict):
            configuration = [configuration[n] for n in self.mech.node_names]
        x = np.asarray(configuration, float).reshape(len(self.mech.nodes), self.mech.dim)
        if self._f is None:
            return {}
        values = np.asarray(self._f(x.ravel()), float).ravel()
        out = {}
        for c, v in zip(self.coordinates, values):
            if c.kind == "angle":
                conv = 180.0 / math.pi if unit == "deg" else 1.0
                a = absolute_angle(c.absolute(self.mech, x))
                out[c.label] = {"relative": relative_angle(float(v)) * conv,
                                "absolute": None if a is None else a * conv}
            else:
                out[c.label] = {"relative": float(v), "absolute": _node_coordinate(self.mech, c, x)}
        return out


def _node_coordinate(mech: Mechanism, c: InputCoordinate, x: np.ndarray) -> float | None:
    """The absolute value of a node's coordinate label (``velocity:P.x`` → x of P, as a map's axes); else None."""
    if c.parameter.kind != "velocity":
        return None
    return float(x[mech.node_index()[c.parameter.target[0]], c.axis])  # axis: velocity:P.y and velocity: P alike


@dataclass(frozen=True)
class PathPoint:
    """One accepted point: driving input (radians / model units), arclength, coordinates, indicators.

    ``input`` is the input along the path, measured from the model's configuration and
    continuous (a crank turned once ends at 2π); ``absolute`` (a planar rotation) is in
    [0, 2π).  :meth:`Path.values` gives them in the unit the path was traced in, with the
    input relative to the model wrapped to (−180°, 180°] (:func:`relative_angle`).
    """

    input: float
    s: float
    coordinates: np.ndarray = field(repr=False)
    indicators: dict = field(repr=False)
    absolute: float | None = None


@dataclass(frozen=True)
class PathEvent:
    """A located singular configuration (or the path's end) and its full analysis.

    ``input``, ``absolute`` as for :class:`PathPoint` (radians for angles, whatever unit the
    path was traced in: :meth:`Path.values` converts).
    """

    kind: str
    input: float
    s: float
    coordinates: np.ndarray = field(repr=False)
    analysis: Analysis | None = field(repr=False)
    value: float
    evaluations: int
    absolute: float | None = None
    bifurcation: Bifurcation | None = field(default=None, repr=False)
    y: np.ndarray | None = field(default=None, repr=False, compare=False)
    t: np.ndarray | None = field(default=None, repr=False, compare=False)
    tests: tuple[str, ...] = ()

    @property
    def kinds(self) -> tuple[str, ...]:
        """Every event kind that located this configuration, ``kind`` first.

        ``tests`` names the test functions (``bifurcation`` and ``IM`` both locate IM
        events); a configuration found by several of them (the flattened Peaucellier–Lipkin
        inversor is a turning point of its crank and a branch point) is one event.
        """
        if self.kind == Kind.END:
            return (Kind.END,)
        return tuple(dict.fromkeys((self.kind,) + tuple(_kind(t) for t in self.tests)))

    @property
    def reason(self) -> str | None:
        """Why a LIM event's configuration is singular, in words (None for other kinds).

        >>> from symkin.analysis.classification import analyze
        >>> from symkin.model.catalogue import get
        >>> a = analyze(get("fourbar_dead_centre"))
        >>> PathEvent(Kind.LIM, 0.0, 0.0, None, a, 0.0, 0).reason
        'link impossible motion (LIM): rocker cannot move'
        """
        if self.kind != Kind.LIM or self.analysis is None:
            return None
        return f"{describe(Kind.LIM)}: {', '.join(self.analysis.locked_links)} cannot move"

    @property
    def confirmed(self) -> bool | None:
        """Whether the classifier at the located configuration finds the singularity of ``kind``.

        False flags an event whose test function vanishes but whose configuration the
        classifier, at its tolerance, does not call singular in that way (e.g. a point located
        only to ~1e-6 on a degenerate family of singular configurations); None for "end".
        """
        if self.analysis is None or self.kind == Kind.END:
            return None
        return self.kind in self.analysis.types


@dataclass(frozen=True)
class Path:
    """Result of :func:`trace`.

    ``stop_reason`` is ``"reached"`` (the input reached its target), ``"closed"`` (a full loop
    back to the start), ``"unreachable"`` (a full loop back to the start on which the input
    turns back short of its target: ``turning_input`` / ``turning_absolute`` say where, and
    ``message`` too), ``"max_arclength"``, ``"max_steps"`` (the continuation's budget of
    ``Settings.max_steps`` accepted steps ran out first; ``message`` names the count and how to
    raise it) or ``"stuck"`` (the step size collapsed; ``message`` says where).  Angles are kept in radians; :meth:`to_dict` converts.
    """

    mechanism: Mechanism = field(repr=False)
    drive: str
    kind: str  # "angle" or "length"
    points: tuple[PathPoint, ...] = field(repr=False)
    events: tuple[PathEvent, ...]
    stop_reason: str
    message: str
    residual_evaluations: int
    node_names: tuple[str, ...] = field(repr=False, default=())
    curve: MechanismCurve | None = field(default=None, repr=False, compare=False)
    turning_input: float | None = None
    turning_absolute: float | None = None
    unit: str = "rad"

    def singular_events(self) -> tuple[PathEvent, ...]:
        return tuple(e for e in self.events if e.kind != Kind.END)

    def values(self, item: PathPoint | PathEvent, unit: str | None = None) -> dict:
        """The input of a point or event in ``unit`` (default: the unit the path was traced in).

        Returns
        -------
        dict
            ``{"input": along the path (continuous, from the model's configuration),
            "relative": the same wrapped to (−180°, 180°], "absolute": in [0°, 360°) or None}``
            for an angle input (degrees or radians); for a length input the three are
            ``input``, ``input`` and None, in model units.

        Examples
        --------
        >>> from symkin.model.catalogue import get
        >>> p = trace(get("fourbar_appendix"), stop=360, unit="deg")
        >>> {k: round(v, 4) for k, v in p.values(p.singular_events()[-1]).items()}
        {'input': 306.081, 'relative': -53.919, 'absolute': 23.5521}
        """
        unit = self.unit if unit is None else unit
        if self.kind != "angle":
            return {"input": item.input, "relative": item.input, "absolute": None}
        conv = 180.0 / math.pi if unit == "deg" else 1.0
        a = absolute_angle(item.absolute)
        return {"input": item.input * conv, "relative": relative_angle(item.input) * conv,
                "absolute": None if a is None else a * conv}

    def outputs(self, item: PathPoint | PathEvent, unit: str | None = None) -> dict:
        """The model's outputs at a point or event: ``{label: {"relative": r, "absolute": a}}``.

        Angles in ``unit`` (default: the path's) by the convention of :func:`relative_angle`.
        """
        return _coordinate_values(self.mechanism)(item.coordinates, self.unit if unit is None else unit)

    def to_dict(self, unit: str | None = None) -> dict:
        """JSON-ready: ``points`` and ``events`` with inputs in ``unit`` (``"deg"`` or ``"rad"``).

        ``unit`` defaults to the unit the path was traced in.  Each point and event has
        ``input`` (along the path), ``relative`` (wrapped to (−180°, 180°]) and ``absolute``
        (in [0°, 360°)), and ``outputs``: the model's outputs (see :meth:`outputs`).
        """
        unit = self.unit if unit is None else unit
        conv = (180.0 / math.pi) if (unit == "deg" and self.kind == "angle") else 1.0

        def cfg(c):
            return {n: [float(v) for v in row] for n, row in zip(self.node_names, c)}

        def num(v):
            return None if v is None else float(v) * conv

        def at(p):
            return {**self.values(p, unit), "s": p.s, "outputs": self.outputs(p, unit)}

        points = [{**at(p), "configuration": cfg(p.coordinates), "indicators": dict(p.indicators)}
                  for p in self.points]
        events = []
        for e in self.events:
            a = e.analysis
            item = {**at(e), "kind": e.kind,
                    "types": list(a.types) if a else [], "locked_links": list(a.locked_links) if a else [],
                    "dof": a.dof if a else None, "configuration": cfg(e.coordinates),
                    "tests": list(e.tests), "kinds": list(e.kinds), "confirmed": e.confirmed, "test_value": e.value,
                    "evaluations": e.evaluations}
            if a is not None:
                item["analysis"] = a.to_dict()
            if e.bifurcation is not None:
                item["branches"] = {"status": e.bifurcation.status, "message": e.bifurcation.message,
                                    "directions": [list(map(float, d)) for d in e.bifurcation.directions]}
            events.append(item)
        return {"mechanism": self.mechanism.name, "input": self.drive, "unit": unit if self.kind == "angle" else
                "model length", "stop_reason": self.stop_reason, "message": self.message,
                "turning": None if self.turning_input is None else
                {"input": num(self.turning_input), "relative": None if self.turning_input is None else
                 num(relative_angle(self.turning_input) if self.kind == "angle" else self.turning_input),
                 "absolute": num(absolute_angle(self.turning_absolute))},
                "residual_evaluations": self.residual_evaluations, "points": points, "events": events}


# ---------------------------------------------------------------------- helpers
class _Counting:
    """Wraps a curve problem and counts residual evaluations (for the benchmark)."""

    def __init__(self, problem):
        self.problem, self.count = problem, 0
        fast = problem.fast_corrector
        self.fast_start = fast.steps if fast is not None else 0

    @property
    def total(self) -> int:
        """Residual evaluations, including the generated corrector's Newton steps."""
        fast = self.problem.fast_corrector
        return self.count + (fast.steps - self.fast_start if fast is not None else 0)

    @property
    def fast_corrector(self):
        return self.problem.fast_corrector

    def residual(self, y):
        self.count += 1
        return self.problem.residual(y)

    def residual_and_jacobian(self, y):
        self.count += 1
        return self.problem.residual_and_jacobian(y)

    def jacobian(self, y):
        return self.problem.jacobian(y)

    def second_derivative(self, y, v):
        return self.problem.second_derivative(y, v)

    @property
    def casadi_function(self):
        """The curve's CasADi ``y ↦ (H, J)`` (exact derivatives for the singular-point locator)."""
        return self.problem.casadi_function


class _PointIndicators:
    """The indicators of :mod:`symkin.analysis.indicators` at points of a curve, once per point.

    Rows come from the mechanism's evaluators (:meth:`MechanismCurve.rows`); ``J_S`` are
    the evaluators' independent rows (chosen at ``y0`` by the same rule when the
    evaluators have none), so the values equal those of ``ev.batch`` and
    :func:`symkin.analyze` at the same configuration, up to the sign carried across a
    change of ``J_S``: where ``J_S`` loses rank relative to the whole ``J`` (its least
    singular value below ``tolerances.row_switch`` times ``σ_{nf−F}`` of ``J``, which
    happens only with redundant rows: the Bennett loop), it is chosen anew at that point
    (:func:`~symkin.analysis.indicators.basis_rows`, :class:`_RowSubset`) and the signed DKP values keep their
    sign there (``J_S`` and the new rows span the same row space: the values differ by
    the sign of their orientations, :func:`~symkin.analysis.indicators.basis_orientation`),
    so that they change sign only through zero.
    """

    def __init__(self, curve: MechanismCurve, y0: np.ndarray, tolerances: Tolerances):
        self.curve, self.tolerances = curve, tolerances
        self.f = curve.mech.mobility_value
        ev = curve.evaluators
        rows = ev.basis_rows or indicators.basis_rows(curve.rows(y0)[0], self.f, tolerances)
        self.js = None if rows is None else _RowSubset(
            rows, lambda jf: indicators.basis_rows(jf, self.f, tolerances),
            lambda m, r, v: indicators.basis_orientation(m[list(r)], v), tolerances)
        self._y: np.ndarray | None = None
        self._values: dict = {}

    def __call__(self, y: np.ndarray) -> dict:
        if self._y is not None and np.array_equal(self._y, y):
            return self._values
        f = self.f
        jf, pin, pout = self.curve.rows(y)
        nf = jf.shape[1]
        if jf.shape[0]:
            _, s, vt = np.linalg.svd(jf, full_matrices=True)
        else:
            s, vt = np.zeros(0), np.eye(nf)
        s_full = np.zeros(nf)
        s_full[: s.size] = s
        ascending = np.sort(s_full)
        values = {"im_indicator": float(indicators.im_indicator(s_full, f)) if f < nf else None,
                  "im_sigma": float(ascending[f]) if f < nf else math.inf}
        v = vt[nf - f:].T  # the F directions least constrained: the motion space where L = F
        js = None
        if self.js is not None:
            self.js.update(jf, v, s)
            js = jf[list(self.js.rows)]
        for key, p in (("input", pin), ("output", pout)):
            k = p.shape[0]
            if k == 0:
                continue
            p_hat = indicators.unit_rows(p)[0]
            sv = indicators.restricted_singular_values(p_hat, v)
            sign = self.js.sign if (k == f and js is not None) else 1.0
            values[f"dkp_{key}"] = sign * float(indicators.dkp_value(p_hat, sv, f, js))
            values[f"sigma_{key}"] = float(sv[min(f, k) - 1]) if sv.size else 0.0  # the deciding one
        self._y, self._values = np.array(y, copy=True), values
        return values


class _RowSubset:
    """The rows a signed test keeps along a curve (``J_S``; the rows of ``J_H``), and the sign carried.

    Where their least singular value falls below ``tolerances.row_switch`` times ``σ_count`` of
    the whole matrix (``count`` the number of rows kept; not next to a rank drop of the whole:
    ``σ_count`` at most ``near_branch · σ_max``), ``choose(matrix)`` gives them anew and
    :attr:`sign` is multiplied by the product of the old and new rows' ``orientation(matrix,
    rows, context)`` — taken where the old rows were last well-conditioned if the new ones are
    too there, else here (a continuation step may pass the old rows' own rank loss, where their
    sign flips) — so that the test changes sign only through zero.  Nothing changes where the
    rows are all of them (no other choice) or an orientation is zero.
    """

    def __init__(self, rows, choose, orientation, tolerances: Tolerances):
        self.rows, self.choose, self.orientation, self.tolerances = tuple(rows), choose, orientation, tolerances
        self.sign = 1.0
        self._good = None  # (matrix, context, σ_count) where the rows were last well-conditioned

    def update(self, m: np.ndarray, context, s: np.ndarray | None = None) -> None:
        """Check (and change) the rows at the matrix ``m`` here; ``s`` its singular values, descending."""
        count, tol = len(self.rows), self.tolerances
        if count in (0, m.shape[0]):
            return
        s = np.linalg.svd(m, compute_uv=False) if s is None else s
        if s.size < count or s[count - 1] <= tol.near_branch * s[0]:
            return
        whole = s[count - 1]
        if np.linalg.svd(m[list(self.rows)], compute_uv=False)[-1] >= tol.row_switch * whole:
            self._good = (m, context, whole)
            return
        rows = self.choose(m)
        if rows is None or len(rows) != count or tuple(rows) == self.rows:
            return
        at_m, at_c, at_whole = self._good if self._good is not None else (m, context, whole)
        if np.linalg.svd(at_m[list(rows)], compute_uv=False)[-1] < tol.row_switch * at_whole:
            at_m, at_c = m, context
        before, after = self.orientation(at_m, self.rows, at_c), self.orientation(at_m, rows, at_c)
        if before != 0.0 and after != 0.0:
            self.sign *= math.copysign(1.0, before) * math.copysign(1.0, after)
            self.rows, self._good = tuple(rows), None


def _bifurcation_det(m: np.ndarray, rows, t: np.ndarray) -> float:
    return float(np.linalg.det(np.vstack([m[list(rows)], t[None, :]])))


class _BranchTest:
    """The bifurcation test ``det[J_H[rows]; tᵀ]`` (``n − 1`` independent rows of the augmented Jacobian).

    The rows are chosen at ``y0`` (:func:`~symkin.numeric.linalg.independent_rows`) and anew
    where they lose rank, the sign carried (:class:`_RowSubset`, as ``J_S`` of the DKP values).
    """

    def __init__(self, curve: MechanismCurve, y0: np.ndarray, tolerances: Tolerances):
        jh = curve.jacobian(y0)
        count = jh.shape[1] - 1
        self.curve, self.count = curve, count
        self.rows = _RowSubset(independent_rows(jh, tolerances.rank, count),
                               lambda m: independent_rows(m, tolerances.rank, count), _bifurcation_det, tolerances)

    def __call__(self, y, t) -> float:
        jh = self.curve.jacobian(y)
        if len(self.rows.rows) == self.count:
            self.rows.update(jh, t)
        return self.rows.sign * _bifurcation_det(jh, self.rows.rows, t)


@dataclass(frozen=True)
class _Value:
    """Test function ``(y, t) -> point(y)[key]``: a value of the indicators' definition."""

    point: _PointIndicators
    key: str

    def __call__(self, y, t) -> float:
        return self.point(y)[self.key]


@dataclass(frozen=True)
class _LinkMotion:
    """The LIM test of one link at a point of the curve, along its tangent (:mod:`symkin.analysis.indicators`).

    ``link_rate`` of the free node ``node`` about the fixed node ``pivot`` (planar) or the
    axis ``pivot → axis_to`` (spatial) when the link has one; else ``link_speed`` of its free
    nodes ``nodes``.  Positions in units of the length scale, velocities ``dy/ds = t``.
    """

    curve: MechanismCurve
    nodes: tuple[int, ...]
    pivot: int | None = None
    axis_to: int | None = None

    def __call__(self, y, t) -> float:
        c = self.curve
        shape = c.x0.shape
        x = c.x_of(y) / c.scale
        flat = np.zeros(x.size)
        flat[c.free] = t
        v = flat.reshape(shape)
        if self.pivot is None:
            return float(indicators.link_speed(v[list(self.nodes)]))
        axis = None
        if self.axis_to is not None:
            axis = x[self.axis_to] - x[self.pivot]
            axis = axis / np.linalg.norm(axis)
        node = self.nodes[0]
        return float(indicators.link_rate(x[node] - x[self.pivot], v[node], axis))


def _link_motions(curve: MechanismCurve) -> dict[str, tuple[_LinkMotion, bool]]:
    """Per moving link of a 1-DOF mechanism: its LIM test and whether it is signed (a fixed pivot or axis)."""
    mech = curve.mech
    index = mech.node_index()
    fixed = set(mech.fixed)
    x0 = curve.x0
    out = {}
    for link in mech.moving_links:
        nodes = mech.link_nodes(link)
        pins = [index[n] for n in nodes if n in fixed]
        free = [index[n] for n in nodes if n not in fixed]
        if not free:
            continue
        pivot = axis_to = None
        if mech.dim == 2 and len(pins) == 1:
            pivot = pins[0]
        elif mech.dim == 3 and len(pins) >= 2 and np.linalg.norm(x0[pins[1]] - x0[pins[0]]) > 0:
            pivot, axis_to = pins[0], pins[1]
        elif pins:
            continue  # a planar link held by two pins, or a spherical pivot: no turning test
        if pivot is None:
            out[link] = (_LinkMotion(curve, tuple(free)), False)
            continue
        a = x0[pins[1]] - x0[pivot] if axis_to is not None else None
        a = None if a is None else a / np.linalg.norm(a)

        def reach(k, a=a):
            r = x0[k] - x0[pivot]
            return float(np.linalg.norm(r if a is None else r - (r @ a) * a))
        out[link] = (_LinkMotion(curve, (max(free, key=reach),), pivot, axis_to), True)
    return out


def event_types(curve: MechanismCurve, y0: np.ndarray, tolerances: Tolerances = DEFAULT) -> list[EventType]:
    """Signed DKP / bifurcation determinants and the IM minimum test (see module docstring).

    The DKP and IM tests are values of :mod:`symkin.analysis.indicators` (signed
    ``dkp_value`` for F parameter rows, else the deciding restricted singular value;
    ``σ_{F+1}`` of the dimensionless ``J``, whose largest singular value is of order 1);
    minimum tests accept an event below ``tolerances.event_threshold``.  A DKP event
    located where ``σ_{F+1}`` is below ``tolerances.near_branch`` is relocated as the IM
    minimum in its bracket (its determinant is ill-conditioned next to a branch point); IM
    events are moved onto their branch point (:class:`~symkin.curves.events.SingularEvent`).
    """
    f = curve.mech.mobility_value
    point = _PointIndicators(curve, y0, tolerances)
    _, pin, pout = curve.rows(y0)
    accept = tolerances.event_threshold
    im = SingularEvent(str(Kind.IM), _Value(point, "im_sigma"), signed=False, threshold=accept, kind=Kind.IM)
    near = {"near": im, "near_threshold": tolerances.near_branch}
    tests = []
    if pin.shape[0] == f and f > 0:
        tests.append(EventType(str(Kind.DKP_INPUT), _Value(point, "dkp_input"), kind=Kind.DKP_INPUT, **near))
    if pout.shape[0] == f and f > 0:
        tests.append(EventType(str(Kind.DKP_OUTPUT), _Value(point, "dkp_output"), kind=Kind.DKP_OUTPUT, **near))
    elif pout.shape[0] > 0:
        tests.append(EventType(str(Kind.DKP_OUTPUT), _Value(point, "sigma_output"), signed=False, threshold=accept,
                               kind=Kind.DKP_OUTPUT, **near))

    tests.append(SingularEvent(str(Kind.BRANCH_POINT), _BranchTest(curve, y0, tolerances), kind=Kind.IM,
                               any_root=True))
    tests.append(im)
    if f == 1:
        for link, (motion, signed) in _link_motions(curve).items():
            # flat below the event threshold, at both ends of a bracket: on a branch along which the link
            # stays locked (the double butterfly's LIM branch) its rate is rounding noise, and where the
            # curve enters such a branch the link stops for good: neither is an isolated stop
            tests.append(EventType(f"{Kind.LIM}:{link}", motion, signed=signed, threshold=accept, kind=Kind.LIM,
                                   flat=accept, isolated=True, **near))
    return tests


def _indicators(tests: list[EventType], y, t) -> dict:
    """Recorded at every path point: the indicators' definition (``DKP-*`` as :func:`~symkin.analysis.indicators.dkp_value`)."""
    point = next(tf.f.point for tf in tests if isinstance(tf.f, _Value))
    vals = point(y)
    out = {"im_indicator": vals["im_indicator"], "im_sigma": vals["im_sigma"],
           str(Kind.BRANCH_POINT): next(tf.f(y, t) for tf in tests if tf.name == Kind.BRANCH_POINT)}
    for k, key in ((Kind.DKP_INPUT, "dkp_input"), (Kind.DKP_OUTPUT, "dkp_output")):
        if any(tf.name == k for tf in tests):
            out[str(k)] = vals[key]
    return out


def _coordinate_values(mech: Mechanism) -> CoordinateValues:
    """The model's outputs as :class:`CoordinateValues`, built once per mechanism."""
    cached = _VALUES.get(mech)
    if cached is None:
        cached = _VALUES[mech] = CoordinateValues(mech)
        while len(_VALUES) > 16:
            _VALUES.pop(next(iter(_VALUES)))
    return cached


_VALUES: dict[Mechanism, CoordinateValues] = {}


def _unwrap(value: float, reference: float, kind: str) -> float:
    if kind != "angle":
        return value
    return reference + math.remainder(value - reference, 2 * math.pi)


# ---------------------------------------------------------------------- main entry points
def trace(mech: Mechanism, input: str | dict[str, float] | None = None, start: float = 0.0, stop: float = 2 * math.pi,
          unit: str = "rad", max_arclength: float | None = None, settings: Settings | None = None,
          progress: Callable[[float], None] | None = None, branch_analysis: bool = True,
          steps: int | None = None, tol: float | Tolerances | None = None) -> Path:
    """Move ``mech`` by its input from ``start`` to ``stop`` and locate every singular configuration.

    Parameters
    ----------
    mech : Mechanism
        At its model configuration (input value 0 there).
    input : str or dict, optional
        Label of the driving input (``rotation:crank``, ``slide:piston``, ...); default the
        model's first input.  With F > 1 the model's other inputs are held at their values.
        A mapping ``{label: rate}`` moves several inputs along a straight segment in input
        space, ``inputs = λ · rate``; ``start``/``stop`` are then values of ``λ``.
    start, stop : float
        Input values measured from the model's configuration, in ``unit``.
    unit : {"rad", "deg"}
        Unit of ``start``/``stop`` for angle inputs (ignored for lengths: model units).
    max_arclength : float, optional
        Stop after this arclength in units of the model's length scale (default 60).
    steps : int, optional
        At least this many points over the input range: a step may change the input by at
        most ``|stop − start| / steps`` (the step control may take more, smaller steps).
    progress : callable, optional
        Called with the fraction of the input range covered (for a progress bar).
    tol : float or Tolerances, optional
        The rank tolerance (a float) or all tolerances, as in :func:`symkin.analyze`:
        minimum tests accept an event below ``event · rank`` and every event is
        classified by ``analyze(..., tol=tol)`` (see :class:`~symkin.tolerances.Tolerances`).

    Returns
    -------
    Path
        Points with indicators, located events (each with its :class:`Analysis`), and why
        it stopped.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> p = trace(get("fourbar_appendix"), stop=360, unit="deg")
    >>> p.stop_reason, sorted({str(e.kind) for e in p.singular_events()})
    ('reached', ['DKP-output'])
    """
    if unit not in ("rad", "deg"):
        raise SymkinError(f"unit must be 'rad' or 'deg', got {unit!r}")
    tolerances = Tolerances.of(tol)
    curve = make_curve(mech, input)
    conv = math.pi / 180.0 if (unit == "deg" and curve.drive.kind == "angle") else 1.0
    start, stop = start * conv, stop * conv
    settings = settings or Settings()
    counted = _Counting(curve)
    y0 = curve.y0()
    if np.linalg.norm(curve.residual(y0)) > START_CLOSURE:
        y0, _, _ = correct(counted, y0)
    if start != 0.0:
        y0 = _move_to(counted, curve, y0, start, settings, unit)
    _check_regular_start(curve, y0, drive_label=curve.drive.label, tolerances=tolerances)
    max_change = abs(stop - start) / steps if steps else None
    return _run(counted, curve, y0, start, stop, max_arclength, settings, progress, branch_analysis,
                max_change=max_change, unit=unit, tolerances=tolerances)


def _check_regular_start(curve: MechanismCurve, y0: np.ndarray, drive_label: str,
                         tolerances: Tolerances = DEFAULT) -> None:
    """A path cannot start where its curve branches (the tangent is not defined there).

    The augmented Jacobian ``J_H`` (dimensionless) branches when its second-smallest
    singular value is at most ``tolerances.rank · max(σ_max, 1)``.
    """
    jh = curve.jacobian(y0)
    s = np.linalg.svd(jh, compute_uv=False)
    n = jh.shape[1]
    s_full = np.sort(np.concatenate([s, np.zeros(max(0, n - s.size))]))
    if s_full.size >= 2 and s_full[1] <= tolerances.rank * max(s_full[-1], 1.0):
        a = analyze(curve.mech.with_coordinates(curve.x_of(y0)), tol=tolerances)
        raise SymkinError(
            f"{curve.mech.name}: the start configuration is a branch point of the path driven by "
            f"{drive_label} (types {', '.join(a.types) or 'none'}, L = {a.dof}): the direction of motion "
            "is not defined there. Start from a model file at a nearby regular configuration, or "
            "continue along one branch with symkin.paths.trace.follow_branch.")


def _initial_tangent(curve, y0, direction: float) -> np.ndarray:
    t = tangent(curve, y0)
    rate = curve.drive_rate(y0, t)
    if rate * direction < 0:
        t = -t
    return t


def _move_to(counted, curve, y0, target, settings, unit: str = "rad") -> np.ndarray:
    """Continue from the model's configuration to input value ``target`` (no events recorded)."""
    path = _run(counted, curve, y0, 0.0, target, None, settings, None, False, record=False, unit=unit)
    if path.stop_reason == "unreachable":
        raise SymkinError(f"cannot reach the start value: {path.message}")
    if path.stop_reason != "reached":
        raise SymkinError(f"cannot reach the start value: the input turns back before it ({path.message})")
    return curve.y_of(path.points[-1].coordinates.ravel()[curve.free])


_TEST_KINDS = {Kind.BRANCH_POINT: Kind.IM, Kind.IM: Kind.IM}


def _kind(test_name: str) -> Kind:
    """The kind of event a test locates (``bifurcation`` and ``IM`` both locate IM events, ``LIM:<link>`` LIM events)."""
    return _TEST_KINDS.get(test_name) or Kind(test_name.split(":", 1)[0])


def _run(counted, curve: MechanismCurve, y0, start, stop, max_arclength, settings, progress,
         branch_analysis, record: bool = True, t0: np.ndarray | None = None,
         max_change: float | None = None, unit: str = "rad", tolerances: Tolerances = DEFAULT) -> Path:
    """The mechanism layer over :func:`symkin.curves.tracer.trace_curve`.

    Builds the event types from the indicators (:func:`event_types`), the stop rules
    (input reached, closed on the start, arclength limit), the input as the curve's
    parameter (angles unwrapped from point to point), calls the tracer, and classifies
    every located event with :func:`symkin.analyze`.
    """
    mech = curve.mech
    kind = curve.drive.kind
    scale_in = 1.0 if kind == "angle" else curve.scale
    direction = 1.0 if stop >= start else -1.0
    if t0 is None:
        t0 = _initial_tangent(curve, y0, direction)
    tests = event_types(curve, y0, tolerances) if record else []
    max_s = MAX_ARCLENGTH if max_arclength is None else float(max_arclength)

    def input_of(y, reference):
        return _unwrap(curve.input_value(y), reference, kind)

    points: list[PathPoint] = []

    def on_point(tp: TracedPoint) -> None:
        points.append(_point(curve, tp.point.y, tp.p, tp.point.s, tests, tp.point.t))
        if progress is not None and stop != start:
            progress(min(1.0, max(0.0, (tp.p - start) / (stop - start))))

    def guard(previous, y):
        if max_change is None:
            return True
        before = input_of(previous.y, points[-1].input if points else start)
        return abs(input_of(y, before) - before) <= max_change

    stops = [ParameterReached(stop, direction, input_of, scale_in),
             Closed(y0, t0, 4 * settings.step, 2 * settings.max_step), ArclengthLimit(max_s)]
    traced = trace_curve(counted, y0, t0, events=tests, stops=stops, settings=settings, parameter=input_of,
                         p0=start, guard=guard, on_point=on_point, priority=KIND_PRIORITY, tolerances=tolerances)
    reason, message = traced.stop.reason, traced.stop.message
    if reason == Kind.CLOSED:
        last = traced.stop.point
        turns = round((last.p - start) / (2 * math.pi)) if kind == "angle" else 0
        points.append(_point(curve, y0, start + 2 * math.pi * turns, last.point.s, tests, t0))

    events = []
    for item in traced.events:
        x = curve.x_of(item.y)
        analysis = classify_event(curve, item.y, tolerances)
        bif = (branch_directions(counted, item.y, rank_tol=tolerances.event_threshold)
               if (branch_analysis and item.kind == Kind.IM) else None)
        events.append(PathEvent(item.kind, item.p, item.s, x, analysis, item.value, item.evaluations,
                                absolute_angle(curve.drive.absolute(mech, x)), bif, item.y, item.t, item.tests))
    ev = traced.stop.event
    if ev is not None:
        y_end = polish(counted, ev.y, tolerances.closure, tolerances.rank)
        points.append(_point(curve, y_end, stop, ev.s, tests, ev.t))
        if record:
            events.append(PathEvent(Kind.END, stop, ev.s, curve.x_of(y_end), None, ev.value, ev.evaluations,
                                    absolute_angle(curve.drive.absolute(mech, curve.x_of(y_end))), None, y_end, ev.t,
                                    (str(Kind.END),)))
    turn = _turning(points, events, start, stop, kind) if reason == Kind.CLOSED else None
    if turn is not None:
        reason = "unreachable"
        absolute = "" if turn.absolute is None else f" (absolute {_format_value(turn.absolute, kind, unit)})"
        message = (f"the input cannot reach {_format_value(stop, kind, unit)}: it turns back at "
                   f"{_format_value(turn.input, kind, unit)}{absolute}, and the path closed on its start")
    return Path(mech, curve.drive.label, kind, tuple(points), tuple(events), reason, message, counted.total,
                mech.node_names, curve, None if turn is None else turn.input, None if turn is None else turn.absolute,
                unit)


def curve_rows_cover(curve: MechanismCurve) -> bool:
    """Whether the rows of ``curve``'s evaluators classify as :func:`symkin.analyze` does.

    True for planar models without sliders or degenerate (collinear) bodies: their
    evaluators' constraint and parameter rows are the core's, row for row, to rounding
    (bars, planar rotation rows with the core's choice of node pair reproduced).  Not for
    spatial models (the core's rotation rows of a spatial body, a rod, may pick other
    rows), sliders (the normals of a line are chosen anew by the core), nor degenerate
    bodies (the evaluators fix their frame and normals at the model's configuration, and
    the statics' labels of their rigidity rows depend on them).
    """
    mech = curve.mech
    return (mech.dim == 2 and not mech.sliders
            and not any("rigidity" in owner for owner in curve.evaluators.row_owners))


class _EventRows:
    """One SX Function ``q ↦ [vec J; vec inputs; vec outputs; vec platform]``, called through buffers.

    The evaluators' ``J`` and ``parameters`` in one call through CasADi's buffer interface
    (a plain call and its conversions cost tens of µs, more than the NumPy core's rows).
    """

    def __init__(self, ev):
        q = ca.SX.sym("q", ev.nf)
        blocks = [ev.symbolic_function("J")(q)[0], *ev.symbolic_function("parameters")(q)]
        self.function = ca.Function("event_rows", [q], [ca.vertcat(*(ca.vec(b) for b in blocks))], {"cse": True})
        self.shapes = tuple(b.shape for b in blocks)
        self._q, self._out = np.zeros(ev.nf), np.zeros(self.function.numel_out(0))
        self._buf, self._trig = self.function.buffer()
        self._buf.set_arg(0, memoryview(self._q))
        self._buf.set_res(0, memoryview(self._out))

    def __call__(self, q: np.ndarray) -> list[np.ndarray]:
        """``J`` (m, D), inputs, outputs and platform rows (k, D) at ``q`` (new arrays)."""
        self._q[:] = q
        self._trig()
        out, start = [], 0
        for rows, cols in self.shapes:  # CasADi is column-major
            out.append(self._out[start: start + rows * cols].reshape(cols, rows).T.copy())
            start += rows * cols
        return out


@lru_cache(maxsize=64)
def _event_rows(ev) -> _EventRows:
    """The :class:`_EventRows` of an evaluators object (built once)."""
    return _EventRows(ev)


def curve_rows(curve: MechanismCurve, y: np.ndarray) -> ConfigurationRows:
    """The rows at ``y`` from the curve's evaluators (``J`` and ``parameters`` at ``q = ℓ y``).

    The input and output rows are given for the mechanism's inputs-then-outputs list, the
    platform rows for its twist; the mechanism is the model's (topology and labels), the
    configuration ``curve.x_of(y)``.
    """
    mech = curve.mech
    ev = curve.evaluators
    j, pin, pout, ppf = _event_rows(ev)(curve.q_of(y))
    given = {tuple(mech.io_parameters): (np.vstack([pin, pout]), ev.input_labels + ev.output_labels)}
    if mech.platform is not None:
        given[tuple(platform_twist(mech)[0])] = (ppf, ev.platform_labels)
    return ConfigurationRows(mech, j, np.flatnonzero(ev.free), curve.x_of(y), given)


def classify_event(curve: MechanismCurve, y: np.ndarray, tolerances: Tolerances = DEFAULT) -> Analysis:
    """The :class:`~symkin.analysis.classification.Analysis` of the event at ``y``.

    From the curve's own rows (:func:`curve_rows`, no model rebuilt at the event) where
    :func:`curve_rows_cover` says they are the core's; otherwise ``analyze`` of the
    mechanism at the event's configuration (spatial models, sliders, degenerate bodies).
    The analysis carries the configuration either way (``analysis.motion.xyz``).
    """
    if curve_rows_cover(curve):
        return classify(curve_rows(curve, y), tolerances)
    return analyze(curve.mech.with_coordinates(curve.x_of(y)), tol=tolerances)


def _format_value(value: float, kind: str, unit: str) -> str:
    """An input value for a message: degrees or radians for angles, model units for lengths."""
    if kind != "angle":
        return f"{value:.10g} (model length units)"
    return f"{math.degrees(value):.10g}°" if unit == "deg" else f"{value:.10g} rad"


def _turning(points, events, start: float, stop: float, kind: str):
    """The point (or located event) where the input turns back short of ``stop`` on a closed loop, or None.

    None when the input never moves backwards, when it reaches ``stop`` somewhere on the
    loop, or (angles) when the loop covers a full turn, so that every angle is reached.
    The turning point is the farthest value towards ``stop``: a located DKP-input event
    (a turning point of the input, refined to machine precision) when there is one.
    """
    direction = 1.0 if stop >= start else -1.0
    progress = np.array([(p.input - start) * direction for p in points])
    if progress.size < 3 or not np.any(np.diff(progress) < 0):
        return None
    if kind == "angle" and float(progress.max() - progress.min()) >= 2 * math.pi:
        return None
    candidates = list(points) + [e for e in events if e.kind != Kind.END]
    best = max(candidates, key=lambda c: (c.input - start) * direction)
    if (best.input - start) * direction >= (stop - start) * direction:
        return None
    return best


def _point(curve, y, value, s, tests, t) -> PathPoint:
    x = curve.x_of(y)
    return PathPoint(value, s, x, _indicators(tests, y, t) if tests else {},
                     absolute_angle(curve.drive.absolute(curve.mech, x)))


def follow_branch(path: Path, event: PathEvent | int, branch: int, sign: float = 1.0,
                  stop: float | None = None, unit: str = "rad", max_arclength: float = 20.0,
                  settings: Settings | None = None, tol: float | Tolerances | None = None) -> Path:
    """Continue from a bifurcation event along one of its branches.

    ``branch`` indexes ``event.bifurcation.directions``; ``sign`` picks the half-branch.
    The returned path's first point is the bifurcation point itself (arclength 0).
    ``tol`` is used for the events and their classification, as in :func:`trace`.
    """
    tolerances = Tolerances.of(tol)
    ev = path.events[event] if isinstance(event, int) else event
    if ev.bifurcation is None or ev.bifurcation.status != "simple":
        status = ev.bifurcation.status if ev.bifurcation else "not analysed"
        msg = ev.bifurcation.message if ev.bifurcation else ""
        raise SymkinError(f"no branch switching at this event: {status} {msg}".strip())
    curve = path.curve
    direction = sign * ev.bifurcation.directions[branch]
    settings = settings or Settings()
    counted = _Counting(curve)
    # first step off the bifurcation point along the chosen direction
    base = CurvePoint(ev.y, direction / np.linalg.norm(direction), 0.0)
    y1 = point_at(counted, base, settings.step)
    conv = math.pi / 180.0 if (unit == "deg" and path.kind == "angle") else 1.0
    value1 = curve.input_value(y1)
    target = stop * conv if stop is not None else value1 + (1e9 if curve.drive_rate(y1, direction) >= 0 else -1e9)
    t1 = tangent(counted, y1, direction)
    sub = _run(counted, curve, y1, value1, target, max_arclength, settings, None, True, t0=t1, unit=unit,
               tolerances=tolerances)
    tests = event_types(curve, y1, tolerances)
    first = _point(curve, ev.y, ev.input, 0.0, tests, direction)
    return replace(sub, points=(first,) + sub.points)
