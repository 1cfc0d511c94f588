"""A generated corrector for continuation: one Newton step and the new tangent, in C.

For a curve problem whose augmented system ``[J_H; tᵀ]`` is square (closure rows that are
not redundant: ``m + F − 1 = n − 1``), one CasADi Function computes, from ``(y, t, y_pred)``:

* ``y_next = y − A⁻¹ r`` with ``A = [J_H(y); tᵀ]``, ``r = [H(y); t·(y − y_pred)]`` (a
  pseudo-arclength Newton step), ``‖r‖`` and ``‖y_next − y‖``;
* ``t_next = A⁻¹ e_n / ‖A⁻¹ e_n‖``: the tangent at ``y`` oriented along ``t``.

The symbolic factorisation is generated once as straight-line code; the function is
compiled to C (cached on disk, keyed by the model's content hash, the path's inputs and the
CasADi version) and called through CasADi's buffer interface, which removes the per-call
overhead of a plain ``Function`` call.  Without a C compiler the in-process Function is
used (same numbers, slower).  Over-constrained systems (non-square ``A``) keep the
least-squares corrector of :mod:`symkin.paths.continuation`.
"""
from __future__ import annotations

import hashlib
import math
import warnings

import casadi as ca
import numpy as np

from symkin.errors import NotConvergedError

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
        """
        y = np.array(y_pred, float)
        step = math.inf
        for k in range(max_iterations + 1):
            y_next, res, step_next, t_new = self.step(y, t, y_pred)
            if (res <= tol and step <= math.sqrt(tol)) or res <= 1e-3 * tol:
                if not np.all(np.isfinite(t_new)):
                    break
                return y, k, t_new.copy()
            if not np.all(np.isfinite(y_next)) or res > 1e6:
                break
            y, step = y_next.copy(), step_next
        raise NotConvergedError("generated corrector did not converge", y=y)


_CACHE: dict[str, GeneratedCorrector | None] = {}


def _build_function(curve) -> ca.Function | None:
    n = curve.y0().size
    y, t, p = ca.SX.sym("y", n), ca.SX.sym("t", n), ca.SX.sym("y_pred", n)
    h, j = curve._hj(y)
    if j.shape[0] + 1 != n:
        return None
    a = ca.vertcat(j, t.T)
    r = ca.vertcat(h, ca.dot(t, y - p))
    e = ca.DM.zeros(n, 1)
    e[n - 1] = 1.0
    sol = ca.solve(a, ca.horzcat(r, e))
    dy, z = sol[:, 0], sol[:, 1]
    return ca.Function("corrector", [y, t, p], [y - dy, ca.norm_2(r), ca.norm_2(dy), z / ca.norm_2(z)],
                       ["y", "t", "y_pred"], ["y_next", "residual", "step", "t_next"])


def _key(curve) -> str:
    parts = [curve.mech.content_hash(), curve.drive.label, *(c.label for c in curve.held),
             *(repr(v) for v in curve.held_values), ca.__version__, "corrector-v1"]
    return hashlib.sha256("|".join(parts).encode()).hexdigest()[:24]


def generated_corrector(curve, compile: bool = True) -> GeneratedCorrector | None:
    """The generated corrector of ``curve`` (None when its augmented system is not square).

    With ``compile`` (default) the C code is built once per model and path definition and
    cached under the symkin cache directory (``SYMKIN_CACHE``); if the compiler is missing or
    fails, a warning says so and the in-process Function is used.
    """
    key = _key(curve) + ("c" if compile else "vm")
    if key in _CACHE:
        return _CACHE[key]
    f = _build_function(curve)
    if f is None:
        _CACHE[key] = None
        return None
    result = GeneratedCorrector(f, compiled=False)
    if compile:
        try:
            result = GeneratedCorrector(_compiled(f, key), compiled=True)
        except Exception as exc:  # noqa: BLE001 - any build problem falls back to the in-process function
            warnings.warn(f"symkin: generated corrector not compiled ({exc}); using the in-process "
                          "CasADi function", stacklevel=2)
    _CACHE[key] = result
    return result


def _compiled(f: ca.Function, key: str) -> ca.Function:
    from symkin.numeric.codegen import build_library, cache_directory, load_library

    directory = cache_directory() / "paths"
    directory.mkdir(parents=True, exist_ok=True)
    stem = f"corrector_{key}"
    so_path = directory / f"{stem}.so"
    if not so_path.exists():
        cg = ca.CodeGenerator(f"{stem}.c", {"with_header": False})
        cg.add(f)
        cg.generate(str(directory) + "/")
        build_library(directory / f"{stem}.c", so_path)
    return load_library(so_path, ["corrector"])["corrector"]
