"""The one Gauss–Newton corrector: on one point, or on a batch of points at once.

Every stage that projects a point onto a set ``F(z) = 0`` (a curve's closure, a map's
square system, a branch-point system, a polynomial system's original equations) calls
:func:`gauss_newton` (one point) or :func:`gauss_newton_batch` (many points, one stacked
linear solve per iteration; the evaluation of the residuals and Jacobians is the caller's
batched function: CasADi ``map`` or generated code, never a Python loop of scalar solves).

Steps are least-squares steps (``lstsq``), so redundant equations (over-constrained
mechanisms, a hyperplane appended to a curve) are harmless; with ``rcond`` the step is the
minimum-norm step on the well-conditioned part of the Jacobian only (singular values above
``rcond`` times the largest), which moves a point onto a family of solutions by the least
amount instead of sliding along it.

Stopping rule, the same everywhere (residual ``‖F‖``, 2-norm or max-norm as asked):

* converged when ``‖F‖ ≤ tol`` and the last step was at most ``√tol`` (quadratic
  convergence), or ``‖F‖ ≤ 1e-3·tol`` (rounding level: next to a singular point Newton
  converges only linearly), or — with ``step_tol`` — the step fell below
  ``step_tol·max(1, ‖z‖)`` (a system whose residual cannot reach ``tol`` in floating point,
  e.g. an augmented branch-point system);
* at the floor: when ``‖F‖ ≤ floor`` (default ``10·tol``) and a step does not reduce it,
  the point is accepted where it is (a near-singular Jacobian at the rounding level);
* failed when a step or residual is not finite, the residual exceeds ``1e6`` (divergence),
  or ``max_iterations`` steps did not converge.  The best point seen is kept.

All quantities are dimensionless: the caller scales ``z`` (e.g. by the model's length
scale) so that the tolerances of :class:`symkin.tolerances.Tolerances` apply.

>>> import numpy as np
>>> circle = lambda z: (np.array([z @ z - 1.0]), 2 * z[None, :])
>>> r = gauss_newton(circle, np.array([1.0, 1.0]))
>>> r.converged, round(float(np.linalg.norm(r.z)), 12)
(True, 1.0)
>>> batch = lambda Z, idx: ((Z * Z).sum(axis=1, keepdims=True) - 1.0, 2 * Z[:, None, :])
>>> b = gauss_newton_batch(batch, np.array([[2.0, 0.0], [0.0, 0.5], [0.0, 0.0]]))
>>> b.converged.tolist(), np.round(b.z[:2], 12).tolist()
([True, True, False], [[1.0, 0.0], [0.0, 1.0]])
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from symkin.errors import NotConvergedError
from symkin.tolerances import DEFAULT

__all__ = ["Correction", "BatchCorrection", "NonFiniteError", "gauss_newton", "gauss_newton_batch",
           "least_squares_step", "real_form", "real_form_batch", "stacked_steps"]

_DIVERGED = 1e6   # a residual above this (dimensionless) has left every solution behind


class NonFiniteError(NotConvergedError):
    """The residual or the Jacobian is not finite (NaN or inf) where the solver evaluates it."""


@dataclass(frozen=True)
class Correction:
    """Result of :func:`gauss_newton`: the point, whether it converged, its residual, the steps taken."""

    z: np.ndarray = field(repr=False)
    converged: bool
    residual: float
    iterations: int
    best_residual: float

    def raise_unless_converged(self, what: str = "Newton") -> "Correction":
        """``self`` when converged, else :class:`NotConvergedError` carrying the point and residuals."""
        if not self.converged:
            raise NotConvergedError(f"{what} did not converge (residual {self.residual:.3g} after "
                                    f"{self.iterations} iterations; smallest {self.best_residual:.3g})",
                                    y=self.z, residual=self.residual, best_residual=self.best_residual,
                                    iterations=self.iterations)
        return self


@dataclass(frozen=True)
class BatchCorrection:
    """Result of :func:`gauss_newton_batch`, one row per point.

    ``z`` (N, n) the points (the last iterate where not converged), ``converged`` (N,) bool,
    ``residual`` (N,) the norm of ``F`` there, ``iterations`` (N,) int, and ``jacobian``
    (N, m, n) the Jacobian of the last evaluation at each converged point (NaN elsewhere)
    when it was asked for.
    """

    z: np.ndarray = field(repr=False)
    converged: np.ndarray = field(repr=False)
    residual: np.ndarray = field(repr=False)
    iterations: np.ndarray = field(repr=False)
    jacobian: np.ndarray | None = field(default=None, repr=False)


def _norm(r: np.ndarray, norm: str) -> float:
    if r.size == 0:
        return 0.0
    return float(np.max(np.abs(r))) if norm == "max" else float(np.linalg.norm(r))


def least_squares_step(jac: np.ndarray, r: np.ndarray, rcond: float | None = None) -> np.ndarray:
    """The Gauss–Newton step ``-J⁺ r`` (minimum norm; on singular values above ``rcond·σ_max`` only, when given).

    Raises :class:`NonFiniteError` when ``J`` or ``r`` is not finite (LAPACK would stop
    with "SVD did not converge").
    """
    if not (np.all(np.isfinite(jac)) and np.all(np.isfinite(r))):
        raise NonFiniteError("a least-squares system is not finite (NaN or inf)")
    return -np.linalg.lstsq(jac, r, rcond=rcond)[0]


def gauss_newton(fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], z0: np.ndarray, *,
                 tol: float = DEFAULT.newton, max_iterations: int = 20, floor: float | None = None,
                 step_tol: float | None = None, rcond: float | None = None, norm: str = "2") -> Correction:
    """Gauss–Newton on ``F(z) = 0`` from ``z0``; ``fun(z) -> (F(z), F'(z))``.

    See the module docstring for the stopping rule.  Never raises for a failure to
    converge: the result says ``converged``; call :meth:`Correction.raise_unless_converged`
    where a failure is an error.
    """
    z = np.array(z0, dtype=float)
    floor = 10 * tol if floor is None else floor
    step = math.inf

    def evaluate(zz):
        r, j = fun(zz)
        r, j = np.asarray(r, float).ravel(), np.asarray(j, float)
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(j))):
            raise NonFiniteError(f"the residual or the Jacobian is not finite (NaN or inf) at z = {zz}", y=zz)
        return r, j.reshape(r.size, z.size)

    try:
        r, j = evaluate(z)
    except NonFiniteError:
        return Correction(z, False, math.inf, 0, math.inf)
    res = _norm(r, norm)
    best_z, best = z, res
    for k in range(max_iterations + 1):
        if (res <= tol and step <= math.sqrt(tol)) or res <= 1e-3 * tol:
            return Correction(z, True, res, k, min(best, res))
        if k == max_iterations or not res <= _DIVERGED:
            break
        try:
            dz = least_squares_step(j, r, rcond)
            z_new = z + dz
            r_new, j_new = evaluate(z_new)
        except NonFiniteError:
            break
        res_new = _norm(r_new, norm)
        if res <= floor and res_new >= res:
            return Correction(z, True, res, k, min(best, res))  # at the rounding floor already
        z, r, j, res, step = z_new, r_new, j_new, res_new, float(np.linalg.norm(dz))
        if res < best:
            best_z, best = z, res
        if step_tol is not None and step <= step_tol * max(1.0, float(np.linalg.norm(z))):
            return Correction(z, True, res, k + 1, best)
    if best < res:
        z, res = best_z, best
    return Correction(z, bool(res <= tol), res, max_iterations, best)


def real_form(fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
              ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """A complex analytic system ``F(x) = 0`` written as a real one of twice the size, for :func:`gauss_newton`.

    ``fun(x) -> (F(x), F'(x))`` with ``x`` complex (n,), ``F`` complex (m,), ``F'`` complex (m, n).
    The real form takes ``z = [Re x, Im x]`` (2n,) and returns ``[Re F, Im F]`` (2m,) and, by the
    Cauchy–Riemann equations, the Jacobian ``[[Re F', −Im F'], [Im F', Re F']]`` (2m, 2n).  Newton on
    the real form is complex Newton; recover ``x = z[:n] + 1j·z[n:]``.

    Examples
    --------
    >>> import numpy as np
    >>> square = lambda x: (x * x + 1.0, np.diag(2 * x))   # x² = −1
    >>> r = gauss_newton(real_form(square), np.array([0.3, 0.8]))
    >>> r.converged, complex(np.round(r.z[0] + 1j * r.z[1], 12))
    (True, 1j)
    """
    def real(z):
        z = np.asarray(z, float)
        n = z.size // 2
        f, j = fun(z[:n] + 1j * z[n:])
        f = np.asarray(f, complex).ravel()
        j = np.asarray(j, complex).reshape(f.size, n)
        return np.concatenate([f.real, f.imag]), np.block([[j.real, -j.imag], [j.imag, j.real]])

    return real


def real_form_batch(fun: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
                    ) -> Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """:func:`real_form` for :func:`gauss_newton_batch`: ``fun(X, index) -> (F (k, m), F' (k, m, n))``, complex.

    Examples
    --------
    >>> import numpy as np
    >>> square = lambda x, idx: (x * x + 1.0, 2 * x[:, :, None])   # x² = −1, one unknown per row
    >>> b = gauss_newton_batch(real_form_batch(square), np.array([[0.3, 0.8], [0.2, -0.9]]))
    >>> b.converged.tolist(), np.round(b.z[:, 1], 12).tolist()
    ([True, True], [1.0, -1.0])
    """
    def real(z, index):
        z = np.asarray(z, float)
        n = z.shape[1] // 2
        f, j = fun(z[:, :n] + 1j * z[:, n:], index)
        f = np.asarray(f, complex).reshape(z.shape[0], -1)
        j = np.asarray(j, complex).reshape(z.shape[0], f.shape[1], n)
        top = np.concatenate([j.real, -j.imag], axis=2)
        bottom = np.concatenate([j.imag, j.real], axis=2)
        return np.concatenate([f.real, f.imag], axis=1), np.concatenate([top, bottom], axis=1)

    return real


def stacked_steps(jac: np.ndarray, r: np.ndarray, rcond: float | None = None) -> np.ndarray:
    """Gauss–Newton steps ``-J_k⁺ r_k`` for stacked systems ``jac`` (N, m, n), ``r`` (N, m).

    Without ``rcond``, square systems are solved at once (``np.linalg.solve`` on the
    stack); where one is singular, or the systems are not square, each step is the
    minimum-norm least-squares step (an exactly singular square problem is a configuration
    on a family of solutions, Fig. 14 of the paper: the minimum-norm step converges onto
    the family).  With ``rcond`` every step is the minimum-norm step on the singular values
    above ``rcond·σ_max`` (stacked pseudo-inverse): for systems that may be rank deficient
    (an over-constrained mechanism's closure).  NaN rows where a system is not finite.
    """
    n_pts, m, n = jac.shape
    out = np.full((n_pts, n), np.nan)
    finite = np.all(np.isfinite(jac), axis=(1, 2)) & np.all(np.isfinite(r), axis=1)
    if rcond is not None:
        if np.any(finite):
            out[finite] = -(np.linalg.pinv(jac[finite], rcond=rcond) @ r[finite][:, :, None])[:, :, 0]
        return out
    if m == n and np.all(finite):
        try:
            return -np.linalg.solve(jac, r[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            pass
    for k in np.flatnonzero(finite):
        try:
            out[k] = -(np.linalg.solve(jac[k], r[k]) if m == n else np.linalg.lstsq(jac[k], r[k], rcond=None)[0])
        except np.linalg.LinAlgError:
            out[k] = -np.linalg.lstsq(jac[k], r[k], rcond=None)[0]
    return out


def gauss_newton_batch(fun: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]], z0: np.ndarray, *,
                       tol: float = DEFAULT.newton, max_iterations: int = 12, diverge_after: int = 3,
                       norm: str = "max", return_jacobian: bool = False,
                       rcond: float | None = None) -> BatchCorrection:
    """Gauss–Newton on many points at once; ``fun(Z, index) -> (F (k, m), F' (k, m, n))``.

    ``Z`` holds the points still iterating and ``index`` their rows in ``z0`` (so that a
    caller with per-point targets picks them).  A point converges when its residual is at
    most ``tol``; it is dropped (not converged) when its step is not finite or, from
    iteration ``diverge_after`` on, its residual grows (Newton diverges: no solution near).
    Steps as :func:`stacked_steps` (``rcond`` for systems that may be rank deficient).
    """
    z = np.array(np.atleast_2d(z0), dtype=float)
    n_pts = z.shape[0]
    converged = np.zeros(n_pts, bool)
    residual = np.full(n_pts, np.inf)
    iterations = np.zeros(n_pts, int)
    active = np.arange(n_pts)
    jac_out = None
    for it in range(max_iterations + 1):
        if active.size == 0:
            break
        r, j = fun(z[active], active)
        r = np.asarray(r, float).reshape(active.size, -1)
        j = np.asarray(j, float).reshape(active.size, r.shape[1], z.shape[1])
        if return_jacobian and jac_out is None:
            jac_out = np.full((n_pts,) + j.shape[1:], np.nan)
        if r.shape[1] == 0:
            err = np.zeros(active.size)
        elif norm == "max":
            err = np.max(np.abs(r), axis=1)
        else:
            err = np.linalg.norm(r, axis=1)
        before = residual[active]
        residual[active] = err
        done = err <= tol
        converged[active[done]] = True
        iterations[active[done]] = it
        if jac_out is not None:
            jac_out[active[done]] = j[done]
        keep = ~done & np.isfinite(err) & ((it < diverge_after) | (err < before))
        active, r, j = active[keep], r[keep], j[keep]
        if active.size == 0 or it == max_iterations:
            break
        step = stacked_steps(j, r, rcond)
        ok = np.all(np.isfinite(step), axis=1)
        z[active[ok]] += step[ok]
        iterations[active] = it + 1
        active = active[ok]
    return BatchCorrection(z, converged, residual, iterations, jac_out)
