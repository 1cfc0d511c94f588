"""Evaluation of the evaluators' Functions over N configurations (numbers, no decisions).

No Python loop runs per configuration: Functions are evaluated by ``Function.map`` in
chunks through CasADi's buffer interface (zero-copy NumPy views), or through the
generated ``*_batch`` loops.  The decisions built on these numbers (IM, DKP) belong to
the analysis stage: :mod:`symkin.analysis.batch`.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from symkin.curves.corrector import gauss_newton_batch
from symkin.errors import NotConvergedError, SymkinError
from symkin.tolerances import DEFAULT

__all__ = ["map_function", "project", "fast_caller", "as_configurations"]

_CHUNK = 4096
#: a last partial block of a generated ``*_batch`` loop is padded when it holds at least
#: 1/_PAD_SHARE of the block (the generated loop at 0.5 µs per configuration, against
#: about 3 µs in CasADi's in-process Map layer for the 3-RRR's indicator kernel)
_PAD_SHARE = 8


# ---------------------------------------------------------------------- mapping
def _chunk_size(n: int) -> int:
    return min(_CHUNK, 1 << max(0, (n - 1).bit_length()))


def as_configurations(ev, configurations) -> np.ndarray:
    """``configurations`` as a C-contiguous (N, nf) array; a clear error for a wrong shape."""
    q = np.asarray(configurations, dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != ev.nf:
        raise SymkinError(f"configurations must be an (N, {ev.nf}) array of free coordinates "
                          f"({', '.join(ev.q_labels)}), got shape {np.shape(configurations)}")
    return np.ascontiguousarray(q)


def _mapped(ev, name: str, size: int):
    """Cached ``(map Function, buffer, trigger)`` of Function ``name`` for ``size`` configurations."""
    key = ("map", name, size, id(ev.functions[name]))
    hit = ev._cache.get(key)
    if hit is None:
        f = ev.functions[name]
        reduce_in = [1] if f.n_in() == 2 else []
        fm = f if size == 1 else f.map(f"{name}_map{size}", "serial", size, reduce_in, [])
        buf, trig = fm.buffer()
        hit = (f, fm, buf, trig)
        ev._cache[key] = hit
    return hit


def map_function(ev, name: str, configurations, p=None) -> dict[str, np.ndarray]:
    """Evaluate Function ``name`` of ``ev`` at every row of ``configurations``.

    Returns a dict, by output name, of arrays of shape ``(N, rows, cols)`` (``(N, rows)``
    for column outputs).  ``p`` (closure parameters, shared by all) defaults to ``ev.p0``.
    """
    q = as_configurations(ev, configurations)
    n = q.shape[0]
    f = ev.functions[name]
    outs = []
    for i in range(f.n_out()):
        r, c = f.size_out(i)
        outs.append(np.empty((n, c, r)))
    start = 0
    block = ev.functions.get(f"{name}_batch")
    size = block.size_in(0)[1] if block is not None else 0
    if block is not None and (n >= size or (ev.compiled and n >= size // _PAD_SHARE)):
        # whole blocks through the generated loop (no CasADi Map layer); in generated code a
        # last block of at least 1/_PAD_SHARE of the size is padded (cheaper than the Map layer)
        buf, trig = _buffer(ev, f"{name}_batch")
        start = _run_blocks(buf, trig, q, outs, size, pad=ev.compiled and n % size >= size // _PAD_SHARE)
    if start < n:
        _evaluate(ev, name, q[start:], [o[start:] for o in outs], p)
    result = {}
    for i, o in enumerate(outs):
        r, c = f.size_out(i)
        arr = o.transpose(0, 2, 1)
        result[f.name_out(i)] = arr[:, :, 0] if c == 1 else arr
    return result


def _buffer(ev, name: str):
    key = ("buffer", name, id(ev.functions[name]))
    hit = ev._cache.get(key)
    if hit is None:
        hit = ev.functions[name].buffer()
        ev._cache[key] = hit
    return hit


def _evaluate(ev, name: str, q: np.ndarray, outs: list, p) -> None:
    """Evaluate ``name`` at the rows of ``q`` into ``outs`` (arrays (n, cols, rows))."""
    n = q.shape[0]
    f = ev.functions[name]
    size = _chunk_size(n)
    _, _, buf, trig = _mapped(ev, name, size)
    pvec = None
    if f.n_in() == 2:
        pvec = np.ascontiguousarray(ev.p0 if p is None else np.asarray(p, dtype=float).ravel())
        if pvec.size != f.numel_in(1):
            raise SymkinError(f"p must have {f.numel_in(1)} entries ({', '.join(ev.p_labels)})")
    _run_blocks(buf, trig, q, outs, size, pvec, pad=True)


def _run_blocks(buf, trig, q: np.ndarray, outs: list, size: int, pvec=None, pad: bool = False) -> int:
    """Run a ``size``-configuration Function buffer over the rows of ``q`` into ``outs``; rows done.

    Whole blocks are views of ``q`` and ``outs``; with ``pad`` a last partial block is run
    padded with copies of its first row (and only its own rows are kept).
    """
    n = q.shape[0]
    if pvec is not None:
        buf.set_arg(1, memoryview(pvec))
    full = (n // size) * size
    for start in range(0, full + (size if pad and full < n else 0), size):
        stop = min(start + size, n)
        if stop - start == size:
            qa, ra = q[start:stop], [o[start:stop] for o in outs]
        else:
            qa = np.empty((size, q.shape[1]))
            qa[: stop - start] = q[start:stop]
            qa[stop - start:] = q[start]
            ra = [np.empty((size,) + o.shape[1:]) for o in outs]
        buf.set_arg(0, memoryview(qa))
        for i, o in enumerate(ra):
            buf.set_res(i, memoryview(o))
        trig()
        if stop - start < size:
            for o, po in zip(outs, ra):
                o[start:stop] = po[: stop - start]
    return n if pad else full


class _Single:
    """Buffer-interface caller of ``indicators`` for one configuration at a time."""

    def __init__(self, f: ca.Function):
        self.q = np.zeros(f.numel_in(0))
        self.r = np.zeros(f.n_out())
        self.buf, self.trig = f.buffer()
        self.buf.set_arg(0, memoryview(self.q))
        for i in range(f.n_out()):
            self.buf.set_res(i, memoryview(self.r[i: i + 1]))

    def __call__(self, q) -> np.ndarray:
        self.q[:] = q
        self.trig()
        return self.r


def fast_caller(ev):
    """A function ``q -> ndarray`` of the 7 indicator values (no decisions), minimal overhead.

    The returned array is reused by the next call; copy it to keep it.
    """
    key = ("single", id(ev.functions["indicators"]))
    caller = ev._cache.get(key)
    if caller is None:
        caller = _Single(ev.functions["indicators"])
        ev._cache[key] = caller
    return caller


# ---------------------------------------------------------------------- projection
def project(ev, configurations, p=None, tol: float = DEFAULT.newton, max_iter: int = 25) -> np.ndarray:
    """Newton projection of configurations onto ``phi(q, p) = 0`` (minimum-norm steps).

    One batched Gauss–Newton (:func:`symkin.curves.corrector.gauss_newton_batch`) on the
    closure: converged when ``max |phi| <= tol · ℓ`` (``ℓ`` the model's length scale).  Returns an array like the input.
    """
    q = as_configurations(ev, configurations).copy()
    scale = ev.mech.length_scale
    shape = ev.functions["closure_jacobian"].size_out(1)

    def closure(qq, index):  # in model units; the tolerance below carries the length scale
        res = map_function(ev, "closure_jacobian", qq, p)
        return res["phi"].reshape(qq.shape[0], -1), res["dphi_dq"].reshape((qq.shape[0],) + shape)

    fit = gauss_newton_batch(closure, q, tol=tol * scale, max_iterations=max_iter, diverge_after=max_iter + 1,
                             rcond=DEFAULT.pinv)
    q = fit.z
    if not np.all(fit.converged):
        bad = np.flatnonzero(~fit.converged)
        raise NotConvergedError(f"{bad.size} configuration(s) did not close within {max_iter} "
                                "Newton steps", indices=bad.tolist(),
                                residual=float(np.max(fit.residual[bad])))
    return q if np.ndim(configurations) == 2 else q[0]
