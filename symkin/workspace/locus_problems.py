"""The problems refinement solves on a map's locus: the map's position problem as SX (:class:`LocusSystem`) and the
CasADi Functions evaluated on it in ``y = q/ℓ`` (:class:`LocusProblems`), wrapped as counted curve problems.

See :mod:`symkin.workspace.loci` for the contract and the algorithm.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from symkin.analysis.batch import Evaluators
from symkin.curves.corrector import gauss_newton, gauss_newton_batch
from symkin.errors import NotConvergedError, SymkinError
from symkin.kinds import Kind
from symkin.numeric.evaluators import INDICATOR_NAMES
from symkin.numeric.sx_linalg import givens_qr
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["KINDS", "OTHER_KIND", "LOCUS_NEWTON_TOL", "POLISH_STEP", "POLISH_ITERATIONS", "SQUARE_ITERATIONS", "LocusSystem", "LocusProblems",
           "CountedFunction", "CurveFunction", "EvaluationCounter"]

#: curve kinds and the indicator output that defines each
KINDS = {Kind.DKP_INPUT: "dkp_input", Kind.DKP_OUTPUT: "dkp_output"}
#: the other DKP kind of each
OTHER_KIND = {Kind.DKP_INPUT: Kind.DKP_OUTPUT, Kind.DKP_OUTPUT: Kind.DKP_INPUT}
#: Gauss–Newton tolerance of located points (residual, dimensionless)
LOCUS_NEWTON_TOL = 1e-12
#: relative step at which a located point counts as polished (the issue's 1e-10)
POLISH_STEP = 1e-10
#: Gauss–Newton iterations of a located point on its extended system (crossing, fold, double zero, box edge)
POLISH_ITERATIONS = 30
#: Newton iterations of the square problem at one axis point (one point or a batch)
SQUARE_ITERATIONS = 25
#: largest number of points per mapped CasADi call of a batch
_BLOCK = 1024
#: relative displacement at which a 0/0 derivative of the indicator kernel is re-evaluated
_JACOBIAN_BUMP = 1e-12


# ---------------------------------------------------------------------- inputs
@dataclass(eq=False)
class LocusSystem:
    """The map's position problem as SX expressions (see the module docstring)."""

    evaluators: Evaluators
    q: ca.SX
    constraints: ca.SX
    axes: ca.SX
    axis_scale: tuple[float, float]

    @property
    def scale(self) -> float:
        return float(self.evaluators.mech.length_scale)

    @property
    def nf(self) -> int:
        return int(self.q.numel())

    @classmethod
    def of(cls, system: Any) -> "LocusSystem":
        """The locus problem of a map position problem (a :class:`symkin.workspace.system.MapSystem`).

        ``constraints`` are the system's ``constraints`` Function (closure rows ``Φ_S/ℓ`` and
        the held coordinates at ``hold_values``), ``axes`` its ``axes`` Function converted to
        the user's unit (:meth:`MapSystem.to_user`: model lengths, degrees or radians), and
        ``axis_scale`` is ``ℓ`` for a length axis and one radian in the user's unit for an
        angle.  A :class:`LocusSystem` is returned as it is.

        >>> from symkin.model.catalogue import get
        >>> from symkin.workspace.system import map_system
        >>> mech = get("rrr_3")
        >>> ls = LocusSystem.of(map_system(mech, "velocity:C1.x", "rotation:platform", hold=["velocity:C1.y"]))
        >>> ls.nf, ls.constraints.numel(), ls.axis_scale[0] == mech.length_scale, round(ls.axis_scale[1], 4)
        (12, 10, True, 57.2958)
        """
        if isinstance(system, LocusSystem):
            return system
        try:
            fn, ev = system.functions, system.evaluators
            q = ca.SX.sym("q", ev.nf)
            cons = fn["constraints"](q, ca.DM(np.asarray(system.hold_values, float)))[0]
            factors = np.asarray(system.to_user(np.ones(2)), float)  # user units per internal unit
            axes = fn["axes"](q)[0] * ca.DM(factors)
            ell = float(ev.mech.length_scale)
            scale = tuple(ell if c.kind == "length" else float(f) for c, f in zip(system.axes, factors))
        except (AttributeError, KeyError, TypeError) as exc:
            raise SymkinError(f"refinement needs a map position problem (symkin.workspace.system.MapSystem), "
                              f"got {type(system).__name__} ({exc})") from None
        return cls(ev, q, cons, axes, scale)



# ---------------------------------------------------------------------- CasADi problems
class _NumericCall:
    """A CasADi SX Function called on NumPy arrays through its buffer interface (no ``DM`` in or out).

    The numbers are those of the plain call (the same generated evaluation); a symbolic
    argument (SX / MX, when another Function is built on this one) goes to the Function
    itself.  Outputs are NumPy arrays of shape ``(rows,)`` (a column) or ``(rows, cols)``.
    """

    def __init__(self, fn: ca.Function):
        ins = fn.sx_in()
        self.fn = fn
        self._dense = ca.Function(fn.name(), ins, [ca.densify(o) for o in fn.call(ins)])
        self._sizes_in = [self._dense.numel_in(k) for k in range(self._dense.n_in())]
        self._sizes_out = [self._dense.size_out(k) for k in range(self._dense.n_out())]
        self._buf, self._trig = self._dense.buffer()
        self._maps: dict = {}

    def many(self, *args) -> list[np.ndarray]:
        """The Function at N points: each argument (N, size) or one vector shared by all.

        Outputs (N, rows) for columns, (N, rows, cols) else.  ``Function.map`` over blocks of
        a power-of-two size (at most :data:`_BLOCK`, the last one padded with its first
        point) through the buffer interface: one CasADi call per block, no loop per point.
        """
        n = max((np.shape(a)[0] for a in args if np.ndim(a) == 2), default=1)
        ins = [np.ascontiguousarray(np.broadcast_to(np.asarray(a, float).reshape(-1, size), (n, size)))
               for a, size in zip(args, self._sizes_in)]
        outs = [np.empty((n, c, r)) for r, c in self._sizes_out]
        size = min(_BLOCK, 1 << max(0, (n - 1).bit_length()))
        if size not in self._maps:
            fm = self._dense.map(f"{self.fn.name()}_map{size}", "serial", size, [], [])
            self._maps[size] = fm.buffer()
        buf, trig = self._maps[size]
        for start in range(0, n, size):
            stop = min(start + size, n)
            pad = size - (stop - start)
            part_in = [np.ascontiguousarray(np.concatenate([a[start:stop]] + [a[start:start + 1]] * pad)) if pad
                       else a[start:stop] for a in ins]
            part_out = [np.empty((size,) + o.shape[1:]) for o in outs] if pad else [o[start:stop] for o in outs]
            for k, a in enumerate(part_in):
                buf.set_arg(k, memoryview(a))
            for k, o in enumerate(part_out):
                buf.set_res(k, memoryview(o))
            trig()
            if pad:
                for o, po in zip(outs, part_out):
                    o[start:stop] = po[:stop - start]
        return [o[:, 0, :] if c == 1 else o.transpose(0, 2, 1) for o, (r, c) in zip(outs, self._sizes_out)]

    def name(self) -> str:
        return self.fn.name()

    def __call__(self, *args):
        if any(isinstance(a, (ca.MX, ca.SX)) for a in args):
            return self.fn(*args)
        ins = [np.ascontiguousarray(np.asarray(a, float).ravel()) for a in args]
        for k, (a, size) in enumerate(zip(ins, self._sizes_in)):
            if a.size != size:
                raise ValueError(f"{self.fn.name()}: argument {k} has {a.size} entries, not {size}")
            self._buf.set_arg(k, memoryview(a))
        outs = [np.empty(c * r) for r, c in self._sizes_out]
        for k, o in enumerate(outs):
            self._buf.set_res(k, memoryview(o))
        self._trig()
        return [o if c == 1 else o.reshape(c, r).T for o, (r, c) in zip(outs, self._sizes_out)]


def _null_space(a: np.ndarray) -> np.ndarray:
    """An orthonormal basis (columns) of the null space of ``a`` (as :func:`scipy.linalg.null_space`: SVD,
    singular values above ``max(a.shape) · eps · σ_max`` count)."""
    _, sv, vh = np.linalg.svd(a, full_matrices=True)
    cut = max(a.shape) * np.finfo(float).eps * (sv.max() if sv.size else 0.0)
    return vh[int(np.sum(sv > cut)):].T


class _OnFirstUse(dict):
    """``{key: make(key)}``, each value made on its first look-up."""

    def __init__(self, make):
        super().__init__()
        self._make = make

    def __missing__(self, key):
        value = self[key] = self._make(key)
        return value


class EvaluationCounter:
    """Calls of the residual/Jacobian Functions (one count per evaluation)."""

    n = 0


class LocusProblems:
    """The CasADi Functions refinement evaluates, in ``y = q/ℓ`` and dimensionless axes ``A = a/axis_scale``."""

    def __init__(self, system: LocusSystem, tolerances: Tolerances = DEFAULT):
        self.system = system
        ev = system.evaluators
        if not ev.fast:
            raise SymkinError(f"{ev.mech.name}: the DKP test functions need the indicator kernel "
                              "(nf - F independent constraint rows); refinement is not available")
        self.scale = system.scale
        self.counter = EvaluationCounter()
        q = system.q
        y = ca.SX.sym("y", system.nf)
        qy = self.scale * y
        ind = ev.symbolic_function("indicators")(q)
        named = dict(zip(INDICATOR_NAMES, ind))
        g = ca.substitute(system.constraints, q, qy)
        ax = ca.substitute(system.axes / ca.DM(np.array(system.axis_scale)), q, qy)
        tests = {k: ca.substitute(named[v], q, qy) for k, v in KINDS.items()}
        rel_im = ca.sqrt(ca.fmax(ca.substitute(named["im"] / named["trace"], q, qy), 0))
        # the entry pairs of the kernel's Givens QR of J_Sᵀ (the same rows, the same rotations): where
        # both entries of a pair vanish the QR is not differentiable (see :meth:`degenerate`)
        js = ca.substitute(ev.symbolic_function("J")(q)[1], q, qy)[list(ev.basis_rows), :]
        pairs: list = []
        givens_qr([[js[j, i] for j in range(js.shape[0])] for i in range(js.shape[1])], js.shape[0], pairs)
        pv = ca.vertcat(*[ca.vertcat(a, b) for a, b in pairs]) if pairs else ca.SX(0, 1)
        # the pairs' values, and (built per tangent dimension on first use) their derivatives along the
        # directions of a basis (forward mode: not the whole Jacobian)
        self._pair_values = _NumericCall(ca.Function("givens_pairs", [y], [pv]))
        self._pv, self._y = pv, y
        self._pairs_along: dict = {}
        self._rank = float(Tolerances.of(tolerances).rank)
        self.n_constraints = int(g.numel())
        self._axes = _NumericCall(ca.Function("axes", [y], [ax, ca.jacobian(ax, y)]))
        self._tests = _NumericCall(ca.Function("tests", [y], [tests[Kind.DKP_INPUT], tests[Kind.DKP_OUTPUT], rel_im]))
        self._constraints = _NumericCall(ca.Function("constraints", [y], [g, ca.jacobian(g, y)]))
        target = ca.SX.sym("target", 2)
        sq = ca.vertcat(g, ax - target)
        self._square = _NumericCall(ca.Function("square", [y, target], [sq, ca.jacobian(sq, y)]))
        s = ca.SX.sym("s")
        a0, d = ca.SX.sym("a0", 2), ca.SX.sym("d", 2)
        z = ca.vertcat(y, s)

        def curve(k):
            t = tests[k]
            return _NumericCall(ca.Function(f"locus_{KINDS[k]}", [y], [ca.vertcat(g, t), ca.jacobian(ca.vertcat(g, t), y)]))

        def extended(k):
            e = ca.vertcat(g, ax - (a0 + s * d), tests[k])
            return _NumericCall(ca.Function(f"extended_{KINDS[k]}", [z, a0, d], [e, ca.jacobian(e, z)]))

        # each kind's locus Functions (the Jacobian of its test through the whole indicator kernel: seconds
        # on a large model) are built when that kind is refined: a map with DKP-input curves only never
        # builds the DKP-output ones (issue 16: the 6-UPS joint form's map)
        self._curve, self._extended = _OnFirstUse(curve), _OnFirstUse(extended)

        self._slopes: dict = {}
        self._g, self._rank_drop = g, None

    def _slope_functions(self, kind: str):
        """``∂T/∂n`` on the solution surface, ``n`` a direction of the dimensionless axes (built on first use).

        ``G(y; n) = ∇_y T · w``, ``w`` the surface direction with ``∂A/∂y · w = n`` (the square
        problem's Jacobian solved for ``(0, n)``); the curve Function ``(y, n) ↦ ((Φ/ℓ, holds, G),
        ∂/∂y)`` and the extended one ``(z = (y, s), a0, d, n) ↦ ((Φ/ℓ, holds, A − (a0 + s·d), G), ∂/∂z)``.
        Second derivatives of ``T`` come from CasADi's AD of the indicator kernel (MX graph).
        """
        if kind in self._slopes:
            return self._slopes[kind]
        nf, nc = self.system.nf, self.n_constraints
        z = ca.MX.sym("z", nf + 1)
        y, s = z[:nf], z[nf]
        n, a0, d = ca.MX.sym("n", 2), ca.MX.sym("a0", 2), ca.MX.sym("d", 2)
        r, jr = self._curve[kind](y)
        g, grad_t = r[:nc], jr[nc, :]
        jsq = self._square(y, ca.MX.zeros(2))[1]
        rhs = ca.vertcat(ca.MX.zeros(nc, 1), n)
        w = ca.solve(jsq, rhs) if nc + 2 == nf else ca.solve(ca.mtimes(jsq.T, jsq), ca.mtimes(jsq.T, rhs))
        slope = ca.mtimes(grad_t, w)
        h = ca.vertcat(g, slope)
        ax = self._axes(y)[0]
        e = ca.vertcat(g, ax - (a0 + s * d), slope)
        yy = ca.MX.sym("y", nf)
        h_y = ca.substitute(h, z, ca.vertcat(yy, 0))
        curve = ca.Function(f"slope_{KINDS[kind]}", [yy, n], [h_y, ca.jacobian(h_y, yy)])
        ext = ca.Function(f"slope_extended_{KINDS[kind]}", [z, a0, d, n], [e, ca.jacobian(e, z)])
        value = ca.Function(f"slope_value_{KINDS[kind]}", [yy, n], [ca.substitute(slope, z, ca.vertcat(yy, 0))])
        self._slopes[kind] = (curve, ext, value)
        return self._slopes[kind]

    def slope(self, kind: str, y, n) -> float:
        """``∂T/∂n`` at ``y`` along the dimensionless axis direction ``n`` (see :meth:`_slope_functions`)."""
        self.counter.n += 1
        try:
            return float(self._slope_functions(kind)[2](y, ca.DM(np.asarray(n, float))))
        except RuntimeError as exc:  # CasADi: the square problem's Jacobian is singular at y (a fold, IM)
            raise NotConvergedError(f"∂T/∂n ({kind}) is not defined here: the square problem is singular",
                                    y=np.asarray(y, float).ravel()) from exc

    def slope_curve(self, kind: str, n) -> "CurveFunction":
        """The curve ``(Φ/ℓ, holds, ∂T/∂n) = 0``: through a double zero of ``T`` it follows that locus."""
        return CurveFunction(self._slope_functions(kind)[0], self.counter, (ca.DM(np.asarray(n, float)),),
                      degenerate=self.degenerate)

    def slope_extended(self, kind: str, a0, d) -> "CountedFunction":
        n = np.asarray(d, float) / np.linalg.norm(d)
        return CountedFunction(self._slope_functions(kind)[1], self.counter, (ca.DM(a0), ca.DM(d), ca.DM(n)),
                   degenerate=lambda z: self.degenerate(np.asarray(z, float)[:-1]))

    # numbers
    def axes(self, y) -> np.ndarray:
        return np.array(self._axes(y)[0]).ravel()

    def axes_and_jacobian(self, y):
        """The dimensionless axes ``A(y)`` and ``∂A/∂y`` (CasADi outputs)."""
        return self._axes(y)

    def tests(self, y) -> dict[str, float]:
        a, b, c = (float(v[0]) for v in self._tests(y))
        return {Kind.DKP_INPUT: a, Kind.DKP_OUTPUT: b, "im": c}

    # batches (one mapped CasADi call per block, one batched Gauss–Newton: no loop of scalar solves)
    def tests_many(self, y: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`tests` at the rows of ``y`` (N, nf): arrays (N,)."""
        a, b, c = self._tests.many(np.atleast_2d(y))
        self.counter.n += len(a)
        return {Kind.DKP_INPUT: a[:, 0], Kind.DKP_OUTPUT: b[:, 0], "im": c[:, 0]}

    def extended_many(self, kind: str, z: np.ndarray, a0: np.ndarray, d: np.ndarray) -> list[np.ndarray]:
        """The extended system of :meth:`extended` and its Jacobian at N points ``z = (y, s)`` (N, nf + 1),
        lines ``a0 + s·d`` (N, 2) each: ``[(N, m), (N, m, nf + 1)]``, one mapped call per block."""
        z = np.atleast_2d(np.asarray(z, float))
        self.counter.n += len(z)
        return self._extended[kind].many(z, a0, d)

    def solve_square_many(self, targets: np.ndarray, y0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`solve_square` at N dimensionless axis values (rows of ``targets``) from the rows of ``y0``.

        One :func:`symkin.curves.corrector.gauss_newton_batch` on the mapped square problem
        (the same rows and tolerance as the single solve).  Returns ``(y, converged)``.
        """
        targets = np.atleast_2d(np.asarray(targets, float))

        def fun(z, rows):
            self.counter.n += len(rows)
            return self._square.many(z, targets[rows])

        out = gauss_newton_batch(fun, np.atleast_2d(y0), tol=LOCUS_NEWTON_TOL, max_iterations=SQUARE_ITERATIONS,
                                 norm="2")
        return out.z, out.converged

    def polish_rank_drop_many(self, y0: np.ndarray, iterations: int) -> np.ndarray:
        """Gauss–Newton steps towards a rank drop of the constraints from each row of ``y0`` (N, nf), one batch.

        The system of :func:`symkin.curves.locate.locate_singular_point` with ``drop = 1``:
        ``(Φ_S/ℓ, holds)(y) = 0``, ``C'(y)ᵀ ψ = 0``, ``ψ · ψ⁰ = 1`` in ``(y, ψ)``, ``ψ⁰`` the
        left singular vector of the smallest singular value of ``C'(y0)``, here with the
        exact second derivatives (CasADi) and all starts at once
        (:func:`symkin.curves.corrector.gauss_newton_batch`, at most ``iterations`` steps; a
        start whose residual grows is left where it is).  Returns the configurations reached
        (N, nf): a screen, not a located point (the caller evaluates the IM indicator there).
        """
        y0 = np.atleast_2d(np.asarray(y0, float))
        nf, m = self.system.nf, self.n_constraints
        if self._rank_drop is None:
            y = ca.SX.sym("y", nf)
            psi, psi0 = ca.SX.sym("psi", m), ca.SX.sym("psi0", m)
            g = ca.substitute(self._g, self._y, y)
            w = ca.vertcat(y, psi)
            f = ca.vertcat(g, ca.mtimes(ca.jacobian(g, y).T, psi), ca.dot(psi, psi0) - 1.0)
            self._rank_drop = _NumericCall(ca.Function("rank_drop", [w, psi0], [f, ca.jacobian(f, w)]))
        jac = self._constraints.many(y0)[1]
        u = np.linalg.svd(jac, full_matrices=True)[0]
        psi0 = u[:, :, m - 1]
        w0 = np.hstack([y0, psi0])

        def fun(z, rows):
            self.counter.n += len(rows)
            return self._rank_drop.many(z, psi0[rows])

        out = gauss_newton_batch(fun, w0, tol=LOCUS_NEWTON_TOL, max_iterations=iterations, norm="2")
        return out.z[:, :nf]

    def polish_lim_many(self, link, y0: np.ndarray, iterations: int) -> tuple[np.ndarray, np.ndarray]:
        """Gauss–Newton towards a LIM configuration of the pivoted ``link`` from each row of ``y0`` (N, nf), one batch.

        The system of :mod:`symkin.workspace.lim_points`: ``Φ_S(y)/ℓ = 0`` and
        ``J_S(ℓy)ᵀ ψ + u(y) = 0`` in ``(y, ψ)``, ``J_S`` the core's independent rows and
        ``u = (−r_y, r_x)/|r|`` the unit row of the link's angular rate at its farthest free
        node (``r`` from the pivot; :func:`symkin.analysis.indicators.link_rate`), exact
        derivatives by CasADi: square (``2 nf − F`` rows and unknowns), its roots the link's
        isolated LIM configurations.  The held coordinates are not in it (with them the system
        would be over-determined): a root counts only when it lies on the map's slice, its
        residual of ``(Φ_S/ℓ, holds)`` within ten times Newton's tolerance (always when
        ``F = 2``).  ``ψ`` starts at the least-squares solution at ``y0``.  One
        :func:`symkin.curves.corrector.gauss_newton_batch`, at most ``iterations`` steps.
        Returns ``(y, converged and on the slice)``.
        """
        y0 = np.atleast_2d(np.asarray(y0, float))
        nf = self.system.nf
        ev = self.system.evaluators
        key = ("lim", link.name)
        if key not in self._slopes:
            y = ca.SX.sym("y", nf)
            g = ca.substitute(self._g, self._y, y)[:nf - ev.mobility]  # the closure rows (the holds follow)
            js = ev.symbolic_function("J")(self.scale * y)[1][list(ev.basis_rows), :]
            psi = ca.SX.sym("psi", js.shape[0])
            bx, by = (int(c) for c in link.columns[link.far])
            rx, ry = self.scale * y[bx] - float(link.pivot[0]), self.scale * y[by] - float(link.pivot[1])
            norm = ca.sqrt(rx * rx + ry * ry)
            u = ca.SX.zeros(nf, 1)
            u[bx], u[by] = -ry / norm, rx / norm
            w = ca.vertcat(y, psi)
            f = ca.vertcat(g, ca.mtimes(js.T, psi) + u)
            self._slopes[key] = (_NumericCall(ca.Function(f"lim_{link.name}", [w], [f, ca.jacobian(f, w)])),
                                 js.shape[0])
        fn, ns = self._slopes[key]
        m = nf - ev.mobility
        r, jac = fn.many(np.hstack([y0, np.zeros((len(y0), ns))]))
        a, b = jac[:, m:, nf:], r[:, m:]  # J_Sᵀ and u at ψ = 0
        psi0 = -np.einsum("nij,nj->ni", np.linalg.pinv(a), b)

        def fun(z, rows):
            self.counter.n += len(rows)
            return fn.many(z)

        out = gauss_newton_batch(fun, np.hstack([y0, psi0]), tol=LOCUS_NEWTON_TOL, max_iterations=iterations,
                                 norm="2")
        y, ok = out.z[:, :nf], out.converged.copy()
        if ok.any():
            on_slice = np.linalg.norm(self._constraints.many(y[ok])[0], axis=1) <= 10 * LOCUS_NEWTON_TOL
            ok[np.flatnonzero(ok)[~on_slice]] = False
        return y, ok

    def degenerate(self, y) -> bool:
        """Whether the kernel's derivative at ``y`` is one-sided: a Givens pair ``(a, b) = (0, 0)``
        whose entries do not stay 0 on the solution surface ``(Φ_S/ℓ, holds) = 0`` through ``y``.

        There the radius ``hypot(a, b)`` is not differentiable and the kernel's derivative
        (finite, :func:`symkin.numeric.sx_linalg.root`) is right only along directions that
        keep the pair at zero.  When the pair stays zero along the surface (a bar kept
        parallel to an axis: a slice at constant orientation) it is the right derivative on
        the surface; otherwise (a five-bar's locus crossing its symmetry line) the caller
        takes the Jacobian a rounding step away.  "Stays zero": the pair's gradients along
        an orthonormal basis of the surface's tangent space are at most ``Tolerances.rank``
        (``y`` and the rows are dimensionless).
        """
        v = self._pair_values(y)[0]
        if v.size == 0:
            return False
        both = np.flatnonzero((v[0::2] == 0.0) & (v[1::2] == 0.0))
        if both.size == 0:
            return False
        tangent_space = _null_space(self._constraints(y)[1])
        if tangent_space.shape[1] == 0:
            return False
        rows = np.concatenate([2 * both, 2 * both + 1])
        k = tangent_space.shape[1]
        if k not in self._pairs_along:
            basis = ca.SX.sym("basis", self.system.nf, k)
            self._pairs_along[k] = _NumericCall(ca.Function(f"givens_pairs_along{k}", [self._y, basis],
                                                            [ca.jtimes(self._pv, self._y, basis)]))
        along = self._pairs_along[k](y, tangent_space.T.ravel())[0]  # CasADi reads the basis column by column
        along = along.reshape(-1, k) if along.ndim == 1 else along
        along = along[rows]
        return bool(np.max(np.abs(along), initial=0.0) > self._rank)

    def curve(self, kind: str) -> "CurveFunction":
        return CurveFunction(self._curve[kind], self.counter, degenerate=self.degenerate)

    def constraints(self) -> "CountedFunction":
        """The 2-D solution surface ``(Φ_S/ℓ, holds)(y) = 0`` (axes free)."""
        return CountedFunction(self._constraints, self.counter)

    def solve_square(self, target: np.ndarray, y0: np.ndarray) -> np.ndarray:
        """Free coordinates ``y`` at dimensionless axis values ``target`` (Newton from ``y0``)."""
        square = CountedFunction(self._square, self.counter, (np.asarray(target, float),))
        return gauss_newton(square.residual_and_jacobian, y0, tol=LOCUS_NEWTON_TOL,
                            max_iterations=SQUARE_ITERATIONS).raise_unless_converged("square position problem").z

    def square_singular(self, y: np.ndarray, tol: Tolerances) -> bool:
        """Whether the square position problem is singular at ``y``: ``σ_min ≤ event_threshold · σ_max``.

        Its rows are dimensionless, so the relative test is scale invariant; the threshold
        is the core's path-event threshold (:attr:`Tolerances.event_threshold`).
        """
        jac = self._square(y, np.zeros(2))[1]
        sv = np.linalg.svd(jac, compute_uv=False)
        return bool(sv[-1] <= tol.event_threshold * sv[0])

    def extended(self, kind: str, a0: np.ndarray, d: np.ndarray) -> "CountedFunction":
        return CountedFunction(self._extended[kind], self.counter, (np.asarray(a0, float), np.asarray(d, float)),
                   degenerate=lambda z: self.degenerate(np.asarray(z, float)[:-1]))


class CountedFunction:
    """A CurveProblem-like wrapper of a CasADi Function ``(z, *params) -> (r, J)`` that counts calls."""

    def __init__(self, fn, counter, params=(), degenerate=None):
        self.fn, self.counter, self.params, self.degenerate = fn, counter, params, degenerate

    def residual_and_jacobian(self, z):
        self.counter.n += 1
        try:
            r, j = self.fn(z, *self.params)
        except RuntimeError as exc:  # CasADi: an evaluation failed (a kernel step not defined there)
            raise NotConvergedError(f"{self.fn.name()} could not be evaluated here",
                                    y=np.asarray(z, float).ravel()) from exc
        r, j = np.array(r).ravel(), np.array(j)
        if np.all(np.isfinite(r)) and (not np.all(np.isfinite(j)) or
                                       (self.degenerate is not None and self.degenerate(np.asarray(z, float)))):
            j = self._nearby_jacobian(np.asarray(z, float))
        return r, j

    def _nearby_jacobian(self, z):
        """The Jacobian a rounding step away, where the kernel is not differentiable (see below).

        The indicator kernel's Givens rotations take ``hypot(a, b)`` of two entries of the
        constraint rows; where both vanish exactly (a bar exactly parallel to an axis, e.g.
        on a symmetry line) the value is right and its derivative finite
        (:func:`symkin.numeric.sx_linalg.root`) but one-sided: right only along directions
        that keep the entries zero (a slice at constant orientation), not across them (a
        five-bar's locus through its symmetry line).  The Jacobian at ``z + δ``,
        ``|δ| ~ 1e-12`` relative, is then used (it differs by ~1e-12).
        """
        bump = _JACOBIAN_BUMP * np.maximum(1.0, np.abs(z)) * np.cos(np.arange(z.size) + 0.5)
        for k in range(1, 4):
            j = np.array(self.fn(z + k * bump, *self.params)[1])
            if np.all(np.isfinite(j)):
                return j
        return j

    def residual(self, z):
        return self.residual_and_jacobian(z)[0]

    def jacobian(self, z):
        return self.residual_and_jacobian(z)[1]


class CurveFunction(CountedFunction):
    """The locus ``(Φ/ℓ, holds, T)(y) = 0`` as a :class:`~symkin.curves.stepper.CurveProblem`."""

