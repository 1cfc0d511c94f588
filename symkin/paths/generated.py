"""A generated corrector for continuation: one Newton step and the new tangent, in C.

For a curve problem whose augmented system ``[J_H; tᵀ]`` is square (closure rows that are
not redundant: ``m + F − 1 = n − 1``), one CasADi Function computes, from ``(y, t, y_pred)``:

* ``y_next = y − A⁻¹ r`` with ``A = [J_H(y); tᵀ]``, ``r = [H(y); t·(y − y_pred)]`` (a
  pseudo-arclength Newton step), ``‖r‖`` and ``‖y_next − y‖``;
* ``t_next = A⁻¹ e_n / ‖A⁻¹ e_n‖``: the tangent at ``y`` oriented along ``t``.

The symbolic factorisation is generated once as straight-line code; the function is
compiled to C through the one artefact cache of :mod:`symkin.numeric.codegen`
(:func:`~symkin.numeric.codegen.cached_library`: keyed by the model's content hash, the
path's inputs, the CasADi version, the generating sources, compiler and flags; written
atomically) and called through CasADi's buffer interface, which removes the per-call
overhead of a plain ``Function`` call.  Without a C compiler the in-process Function is
used (same numbers, slower).  Over-constrained systems (non-square ``A``) keep the
least-squares corrector of :mod:`symkin.curves.stepper`.

Redundant equations (over-constrained mechanisms, bodies with more nodes than a frame)
are handled by keeping ``n − 1`` independent rows chosen at the start (QR with column
pivoting, :func:`symkin.numeric.linalg.independent_rows`); the other rows are consistent with them on the closure manifold.  Should the
kept rows lose rank later on the path, the continuation falls back to the least-squares
corrector for that step.
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

from symkin.errors import NotConvergedError
from symkin.numeric.codegen import (DEFAULT_FLAGS, CompilerError, artefact_key, cache_directory, cached_library,
                                    find_compiler)
from symkin.numeric.linalg import independent_rows
from symkin.tolerances import DEFAULT

__all__ = ["GeneratedCorrector", "generated_corrector"]


class GeneratedCorrector:
    """Buffer-interface caller of the corrector Function (see the module docstring)."""

    def __init__(self, function: ca.Function, compiled: bool):
        self.function = function
        self.compiled = compiled
        n = function.numel_in(0)
        self.n = n
        self._y, self._t, self._p = np.zeros(n), np.zeros(n), np.zeros(n)
        self._y_next, self._res, self._step, self._t_next = np.zeros(n), np.zeros(1), np.zeros(1), np.zeros(n)
        self._buf, self._trig = function.buffer()
        for k, arr in enumerate((self._y, self._t, self._p)):
            self._buf.set_arg(k, memoryview(arr))
        for k, arr in enumerate((self._y_next, self._res, self._step, self._t_next)):
            self._buf.set_res(k, memoryview(arr))
        self.steps = 0

    def step(self, y: np.ndarray, t: np.ndarray, y_pred: np.ndarray):
        """One Newton step: ``(y_next, ‖r(y)‖, ‖Δy‖, t_next at y)`` (arrays are reused: copy them)."""
        self._y[:] = y
        self._t[:] = t
        self._p[:] = y_pred
        self._trig()
        self.steps += 1
        return self._y_next, float(self._res[0]), float(self._step[0]), self._t_next

    def correct(self, y_pred: np.ndarray, t: np.ndarray, tol: float, max_iterations: int):
        """Newton from ``y_pred`` on the hyperplane through it normal to ``t``.

        Returns ``(y, iterations, tangent at y)``; raises :class:`NotConvergedError`.
        The loop touches only the buffers: ``t`` and ``y_pred`` are set once, ``y`` is
        overwritten by each step's result.
        """
        self._t[:] = t
        self._p[:] = y_pred
        self._y[:] = y_pred
        step = math.inf
        sqrt_tol, floor = math.sqrt(tol), 1e-3 * tol
        trig, res_buf, step_buf = self._trig, self._res, self._step
        for k in range(max_iterations + 1):
            trig()
            res = res_buf[0]
            if (res <= tol and step <= sqrt_tol) or res <= floor:
                self.steps += k + 1
                if not np.all(np.isfinite(self._t_next)):
                    break
                return self._y.copy(), k, self._t_next.copy()
            if not res < 1e6:  # also catches NaN
                break
            step = step_buf[0]
            self._y[:] = self._y_next
        self.steps += max_iterations + 1
        raise NotConvergedError("generated corrector did not converge", y=self._y.copy())


_CACHE: dict[str, GeneratedCorrector | None] = {}


def _rows_to_keep(curve) -> list[int] | None:
    """All rows of H for a square system; for redundant rows, n − 1 well-conditioned independent ones at the start."""
    j0 = curve.jacobian(curve.y0())
    m, n = j0.shape
    if m + 1 == n:
        return list(range(m))
    if m + 1 < n:
        return None
    keep = independent_rows(j0, DEFAULT.rank, n - 1)
    if len(keep) < n - 1:
        return None  # fewer than n − 1 independent rows at the start: no square system
    return list(keep)


def _build_function(curve) -> ca.Function | None:
    n = curve.y0().size
    keep = _rows_to_keep(curve)
    if keep is None:
        return None
    y, t, p = ca.SX.sym("y", n), ca.SX.sym("t", n), ca.SX.sym("y_pred", n)
    h, j = curve._hj(y)
    h, j = h[keep], j[keep, :]
    a = ca.vertcat(j, t.T)
    r = ca.vertcat(h, ca.dot(t, y - p))
    e = ca.DM.zeros(n, 1)
    e[n - 1] = 1.0
    sol = ca.solve(a, ca.horzcat(r, e))
    dy, z = sol[:, 0], sol[:, 1]
    return ca.Function("corrector", [y, t, p], [y - dy, ca.norm_2(r), ca.norm_2(dy), z / ca.norm_2(z)],
                       ["y", "t", "y_pred"], ["y_next", "residual", "step", "t_next"])


def _key(curve, compiler: str, flags) -> str:
    """The corrector's cache key (:func:`symkin.numeric.codegen.artefact_key`).

    Keyed also by the source of ``paths/system.py`` (the curve problem it is generated from), named by its
    path: importing that module here would close an import circle (it imports this one).
    """
    parts = [curve.mech.content_hash(), curve.drive.label, *(c.label for c in curve.held),
             *(repr(v) for v in curve.held_values), "corrector-v2"]
    return artefact_key(parts, compiler, flags, sources=(Path(__file__), Path(__file__).with_name("system.py")))


def generated_corrector(curve, compile: bool = True) -> GeneratedCorrector | None:
    """The generated corrector of ``curve`` (None when its augmented system is not square).

    With ``compile`` (default) the C code is built once per model and path definition and
    cached under the symkin cache directory (``SYMKIN_CACHE``); if the compiler is missing or
    fails, a warning says so and the in-process Function is used.
    """
    compiler = find_compiler()
    key = _key(curve, compiler, DEFAULT_FLAGS) + ("c" if compile else "vm")
    if key in _CACHE:
        return _CACHE[key]
    f = _build_function(curve)
    if f is None:
        _CACHE[key] = None
        return None
    result = GeneratedCorrector(f, compiled=False)
    if compile:
        try:
            result = GeneratedCorrector(_compiled(f, key[:-1], compiler), compiled=True)
        except (CompilerError, OSError, RuntimeError) as exc:  # no compiler, unwritable cache, bad library
            warnings.warn(f"symkin: generated corrector not compiled ({exc}); using the in-process "
                          "CasADi function", stacklevel=2)
    _CACHE[key] = result
    return result


def _compiled(f: ca.Function, key: str, compiler: str) -> ca.Function:
    stem = f"corrector_{key}"

    def write_sources(tmp: Path) -> Path:
        cg = ca.CodeGenerator(f"{stem}.c", {"with_header": False})
        cg.add(f)
        cg.generate(str(tmp) + "/")
        return tmp / f"{stem}.c"

    return cached_library(cache_directory() / "paths", stem, write_sources, ["corrector"], compiler,
                          DEFAULT_FLAGS)["corrector"]
