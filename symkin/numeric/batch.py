"""Batch evaluation of the evaluators over N configurations, with the core's decisions.

No Python loop runs per configuration: Functions are evaluated by ``Function.map`` in
chunks through CasADi's buffer interface (zero-copy NumPy views), and the exact path uses
NumPy's stacked SVD.

Decisions (IM, DKP-input, DKP-output) are those of :func:`symkin.analyze`, reached by
one of three paths (``BatchResult.path``), with the margin ``s = max(1e-12, 1e4·tol²)``
(a factor 100 on singular values):

0. **kernel** — the generated indicator kernel (:mod:`symkin.numeric.evaluators`) decides
   alone when the decision is certain: ``im`` certified by Sturm counts and
   ``im > s·trace`` (then ``σ_{F+1} > tol·σ_max`` with room to spare: ``L = F``), and both
   DKP lower bounds ``> s`` (then every singular value of the restricted rows exceeds
   ``tol``: no DKP).
1. **motion-space ranks** — no IM for certain but a DKP bound is small: the ranks of the
   unit parameter rows restricted to the generated orthonormal motion-space basis,
   with the core's absolute tolerance ``tol`` (when no constraint row is redundant).
2. **SVD** — everything else (near IM, or the kernel could not certify its value) is
   recomputed as the core does: SVD of the reduced ``J``, threshold ``tol·σ_max``, the
   motion space from it, ranks of the restricted unit rows.

So the decisions agree with the core's except where a singular value is within rounding
error of its threshold, where no two computations need agree.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from symkin.errors import NotConvergedError, SymkinError
from symkin.tolerances import DEFAULT

__all__ = ["BatchResult", "batch", "map_function", "project", "single", "exact_indicators"]

_CHUNK = 4096


@dataclass(frozen=True, eq=False)
class BatchResult:
    """Indicators and decisions at N configurations (arrays of length N).

    Attributes
    ----------
    im_indicator : ndarray
        ``λ_{F+1}`` of the reduced G (eq. 8; NaN when ``F >= nf``).
    dof : ndarray of int
        Instantaneous DOF ``L``.
    im : ndarray of bool
        Increased mobility, ``L > F``.
    dkp_input, dkp_output : ndarray
        DKP indicators (see :mod:`symkin.numeric.evaluators`); NaN at IM configurations
        and when there are no such parameters.
    is_dkp_input, is_dkp_output : ndarray of bool
        The core's DKP decisions.
    path : ndarray of int8
        How each configuration was decided: 0 by the generated kernel alone (certainly
        no IM, no DKP), 1 kernel for IM and the ranks of the restricted parameter rows on
        the generated motion-space basis for DKP, 2 the SVD path (near IM).
    tol : float
        Relative rank tolerance used.
    """

    im_indicator: np.ndarray
    dof: np.ndarray
    im: np.ndarray
    dkp_input: np.ndarray
    dkp_output: np.ndarray
    is_dkp_input: np.ndarray
    is_dkp_output: np.ndarray
    path: np.ndarray
    tol: float

    def __len__(self) -> int:
        return int(self.dof.size)

    def types(self, k: int) -> tuple[str, ...]:
        """The IM / DKP types of configuration ``k``, in :func:`symkin.analyze`'s order."""
        out = []
        if self.im[k]:
            out.append("IM")
        if self.is_dkp_input[k]:
            out.append("DKP-input")
        if self.is_dkp_output[k]:
            out.append("DKP-output")
        return tuple(out)

    @property
    def exact(self) -> np.ndarray:
        """Configurations not decided by the kernel alone (``path > 0``)."""
        return self.path > 0

    @property
    def singular(self) -> np.ndarray:
        """IM or DKP at each configuration."""
        return self.im | self.is_dkp_input | self.is_dkp_output


# ---------------------------------------------------------------------- mapping
def _chunk_size(n: int) -> int:
    return min(_CHUNK, 1 << max(0, (n - 1).bit_length()))


def _configurations(ev, configurations) -> np.ndarray:
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
    q = _configurations(ev, configurations)
    n = q.shape[0]
    f = ev.functions[name]
    outs = []
    for i in range(f.n_out()):
        r, c = f.size_out(i)
        outs.append(np.empty((n, c, r)))
    start = 0
    block = ev.functions.get(f"{name}_batch")
    if block is not None and n >= block.size_in(0)[1]:
        # whole blocks through the generated loop (no CasADi Map layer)
        size = block.size_in(0)[1]
        buf, trig = _buffer(ev, f"{name}_batch")
        start = (n // size) * size
        for s0 in range(0, start, size):
            buf.set_arg(0, memoryview(q[s0: s0 + size]))
            for i, o in enumerate(outs):
                buf.set_res(i, memoryview(o[s0: s0 + size]))
            trig()
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
    pad_q = pad_out = None
    for start in range(0, n, size):
        stop = min(start + size, n)
        if stop - start == size:
            qa, ra = q[start:stop], [o[start:stop] for o in outs]
        else:  # last partial chunk: pad
            pad_q = np.zeros((size, q.shape[1]))
            pad_q[: stop - start] = q[start:stop]
            pad_q[stop - start:] = q[start]
            pad_out = [np.empty((size,) + o.shape[1:]) for o in outs]
            qa, ra = pad_q, pad_out
        buf.set_arg(0, memoryview(qa))
        if pvec is not None:
            buf.set_arg(1, memoryview(pvec))
        for i, o in enumerate(ra):
            buf.set_res(i, memoryview(o))
        trig()
        if pad_out is not None and ra is pad_out:
            for o, po in zip(outs, pad_out):
                o[start:stop] = po[: stop - start]


# ---------------------------------------------------------------------- exact paths
def _unit_parameter_rows(ev, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Input and output rows over the free coordinates, scaled to unit norm (core's ``restrict``)."""
    n = q.shape[0]
    fp = ev.functions["parameters"]
    prm = map_function(ev, "parameters", q)
    free = ev.free
    out = []
    for i, key in enumerate(("inputs", "outputs")):
        pf = prm[key].reshape((n,) + fp.size_out(i))[:, :, free]
        norms = np.linalg.norm(pf, axis=2) if pf.size else np.zeros(pf.shape[:2])
        out.append(pf / np.where(norms > 0, norms, 1.0)[:, :, None])
    return out[0], out[1]


def _dkp_ranks(pk: np.ndarray, v: np.ndarray, tol: float, f: int) -> tuple[np.ndarray, np.ndarray]:
    """The core's DKP test: rank of ``P̂ V`` (absolute ``tol``) below ``min(F, k)``; and its σ."""
    n, k = pk.shape[0], pk.shape[1]
    if v.shape[2] == 0:
        return np.zeros(n, bool) if k == 0 else np.full(n, 0 < min(f, k)), np.zeros((n, 0))
    sv = np.linalg.svd(pk @ v, compute_uv=False)
    return np.count_nonzero(sv > tol, axis=1) < min(f, k), sv


def exact_indicators(ev, configurations, tol: float | None = None) -> dict[str, np.ndarray]:
    """Indicators and decisions computed as the core computes them (stacked SVD).

    Mirrors :func:`symkin.analysis.motion_space.motion_space` (SVD of the reduced ``J``,
    threshold ``tol·σ_max``, null space from the SVD) and the rank tests of
    :func:`symkin.analyze` for IM, DKP-input and DKP-output.
    """
    tol = DEFAULT.rank if tol is None else float(tol)
    q = _configurations(ev, configurations)
    n = q.shape[0]
    f = ev.mobility
    nf = ev.nf
    fj = ev.functions["J"]
    jf = map_function(ev, "J", q)["J_free"].reshape((n,) + fj.size_out(1))
    p_in, p_out = _unit_parameter_rows(ev, q)
    k_in, k_out = p_in.shape[1], p_out.shape[1]
    m = jf.shape[1]
    out = {key: np.full(n, np.nan) for key in ("im_indicator", "dkp_input", "dkp_output")}
    out.update(dof=np.zeros(n, dtype=int), im=np.zeros(n, bool),
               is_dkp_input=np.zeros(n, bool), is_dkp_output=np.zeros(n, bool))
    if nf == 0:
        return out
    if m == 0:
        s_full = np.zeros((n, nf))
        vt = np.broadcast_to(np.eye(nf), (n, nf, nf))
        thr = np.zeros(n)
    else:
        _, s, vt = np.linalg.svd(jf, full_matrices=True)
        thr = tol * s[:, 0]
        s_full = np.zeros((n, nf))
        s_full[:, : s.shape[1]] = s
    rank = np.count_nonzero(s_full > thr[:, None], axis=1)
    dof = nf - rank
    out["dof"] = dof
    out["im"] = dof > f
    if f < nf:
        out["im_indicator"] = np.sort(s_full, axis=1)[:, f] ** 2
    basis = list(ev.basis_rows)
    for L in np.unique(dof):
        sel = np.flatnonzero(dof == L)
        v = vt[sel][:, nf - L:, :].transpose(0, 2, 1)  # (s, nf, L): the null space
        for key, pk, k in (("input", p_in, k_in), ("output", p_out, k_out)):
            if k == 0:
                continue
            flags, sv = _dkp_ranks(pk[sel], v, tol, f)
            out[f"is_dkp_{key}"][sel] = flags
            if L != f:
                continue
            if ev.fast and k == f:
                js = jf[sel][:, basis, :]
                vol = np.sqrt(np.linalg.det(js @ js.transpose(0, 2, 1)))
                out[f"dkp_{key}"][sel] = np.linalg.det(np.concatenate([js, pk[sel]], axis=1)) / vol
            else:
                out[f"dkp_{key}"][sel] = np.prod(sv[:, : min(k, L)], axis=1)
    return out


def motion_ranks(ev, configurations, tol: float | None = None) -> dict[str, np.ndarray]:
    """DKP decisions at configurations known to have ``L = F`` (kernel-certified, no IM).

    The motion space comes from the generated QR (Function ``motion``), orthonormal to
    rounding like the core's; the ranks of the restricted unit rows are the core's test.
    Valid only when no constraint row is redundant (``basis_rows == effective_rows``).
    """
    tol = DEFAULT.rank if tol is None else float(tol)
    q = _configurations(ev, configurations)
    n = q.shape[0]
    v = map_function(ev, "motion", q)["V"].reshape((n,) + ev.functions["motion"].size_out(0))
    p_in, p_out = _unit_parameter_rows(ev, q)
    out = {}
    for key, pk in (("input", p_in), ("output", p_out)):
        out[f"is_dkp_{key}"] = _dkp_ranks(pk, v, tol, ev.mobility)[0] if pk.shape[1] else np.zeros(n, bool)
    return out


# ---------------------------------------------------------------------- batch and single
def _indicator_matrix(values: dict) -> np.ndarray:
    from symkin.numeric.evaluators import INDICATOR_NAMES

    return np.column_stack([values[k].reshape(-1) for k in INDICATOR_NAMES])


def _safe_margin(tol: float) -> float:
    return max(1e-12, 1e4 * tol * tol)


def _paths(ev, ind: np.ndarray, tol: float) -> np.ndarray:
    """0: the kernel decides alone; 1: no IM for sure, DKP by the motion-space ranks; 2: SVD path."""
    s = _safe_margin(tol)
    k_in, k_out = len(ev.input_labels), len(ev.output_labels)
    with np.errstate(invalid="ignore"):
        no_im = (ind[:, 1] == 1.0) & (ind[:, 0] > s * ind[:, 2])
        no_dkp = np.ones(ind.shape[0], bool)
        if k_in:
            no_dkp &= ind[:, 4] > s
        if k_out:
            no_dkp &= ind[:, 6] > s
    path = np.full(ind.shape[0], 2, dtype=np.int8)
    if len(ev.basis_rows) == len(ev.effective_rows):
        path[no_im] = 1
    path[no_im & no_dkp] = 0
    return path


def batch(ev, configurations, tol: float | None = None, exact: bool = False) -> BatchResult:
    """Indicators and IM / DKP decisions at N configurations (rows of ``configurations``).

    Parameters
    ----------
    ev : Evaluators
    configurations : array (N, nf)
        Free coordinates, in the order of ``ev.q_labels``.
    tol : float, optional
        Relative rank tolerance (default ``Tolerances().rank``), as in :func:`symkin.analyze`.
    exact : bool
        Decide every configuration by the SVD path (for checks; slower).

    Examples
    --------
    >>> from symkin.numeric.evaluators import evaluators
    >>> from symkin.model.catalogue import get
    >>> ev = evaluators(get("fourbar_appendix"))
    >>> res = ev.batch([ev.q0, ev.q0])
    >>> res.dof.tolist(), res.im.tolist(), res.path.tolist()
    ([1, 1], [False, False], [0, 0])
    """
    tol = DEFAULT.rank if tol is None else float(tol)
    q = _configurations(ev, configurations)
    n = q.shape[0]
    f = ev.mobility
    k_in, k_out = len(ev.input_labels), len(ev.output_labels)
    if ev.fast and not exact:
        ind = _indicator_matrix(map_function(ev, "indicators", q))
        path = _paths(ev, ind, tol)
        im_ind = ind[:, 0].copy()
        d_in = ind[:, 3].copy()
        d_out = ind[:, 5].copy()
    else:
        path = np.full(n, 2, dtype=np.int8)
        im_ind, d_in, d_out = (np.full(n, np.nan) for _ in range(3))
    dof = np.full(n, f, dtype=int)
    im = np.zeros(n, bool)
    is_in = np.zeros(n, bool)
    is_out = np.zeros(n, bool)
    redo = np.flatnonzero(path == 1)
    if redo.size:
        mr = motion_ranks(ev, q[redo], tol)
        is_in[redo] = mr["is_dkp_input"]
        is_out[redo] = mr["is_dkp_output"]
    redo = np.flatnonzero(path == 2)
    if redo.size:
        ex = exact_indicators(ev, q[redo], tol)
        im_ind[redo] = ex["im_indicator"]
        dof[redo] = ex["dof"]
        im[redo] = ex["im"]
        d_in[redo] = ex["dkp_input"]
        d_out[redo] = ex["dkp_output"]
        is_in[redo] = ex["is_dkp_input"]
        is_out[redo] = ex["is_dkp_output"]
    if not k_in:
        d_in[:] = np.nan
    if not k_out:
        d_out[:] = np.nan
    return BatchResult(im_indicator=im_ind, dof=dof, im=im, dkp_input=d_in, dkp_output=d_out,
                       is_dkp_input=is_in, is_dkp_output=is_out, path=path, tol=tol)


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


def single(ev, q, tol: float | None = None) -> dict[str, Any]:
    """Indicators and decisions at one configuration (see :meth:`Evaluators.indicators_at`).

    The same three paths as :func:`batch`; ``path`` says which one decided.
    """
    tol = DEFAULT.rank if tol is None else float(tol)
    k_in, k_out = len(ev.input_labels), len(ev.output_labels)
    path = 2
    if ev.fast:
        r = fast_caller(ev)(q)
        s = _safe_margin(tol)
        if r[1] == 1.0 and r[0] > s * r[2] and (not k_in or r[4] > s) and (not k_out or r[6] > s):
            return {"im_indicator": float(r[0]), "dof": ev.mobility, "im": False,
                    "dkp_input": float(r[3]) if k_in else math.nan,
                    "dkp_output": float(r[5]) if k_out else math.nan,
                    "is_dkp_input": False, "is_dkp_output": False, "path": 0}
        path = int(_paths(ev, r[None, :], tol)[0])
        if path < 2:
            flags = {"is_dkp_input": False, "is_dkp_output": False}
            if path == 1:
                mr = motion_ranks(ev, np.asarray(q, dtype=float)[None, :], tol)
                flags = {key: bool(v[0]) for key, v in mr.items()}
            return {"im_indicator": float(r[0]), "dof": ev.mobility, "im": False,
                    "dkp_input": float(r[3]) if k_in else math.nan,
                    "dkp_output": float(r[5]) if k_out else math.nan, **flags, "path": path}
    ex = exact_indicators(ev, np.asarray(q, dtype=float)[None, :], tol)
    return {"im_indicator": float(ex["im_indicator"][0]), "dof": int(ex["dof"][0]),
            "im": bool(ex["im"][0]), "dkp_input": float(ex["dkp_input"][0]),
            "dkp_output": float(ex["dkp_output"][0]), "is_dkp_input": bool(ex["is_dkp_input"][0]),
            "is_dkp_output": bool(ex["is_dkp_output"][0]), "path": path}


# ---------------------------------------------------------------------- projection
def project(ev, configurations, p=None, tol: float = 1e-12, max_iter: int = 25) -> np.ndarray:
    """Newton projection of configurations onto ``phi(q, p) = 0`` (minimum-norm steps).

    Converged when ``max |phi| <= tol · length_scale``.  Returns an array like the input.
    """
    q = _configurations(ev, configurations).copy()
    scale = ev.mech.length_scale
    active = np.arange(q.shape[0])
    for _ in range(max_iter + 1):
        if active.size == 0:
            break
        res = map_function(ev, "closure_jacobian", q[active], p)
        phi = res["phi"].reshape(active.size, -1)
        jac = res["dphi_dq"].reshape((active.size,) + ev.functions["closure_jacobian"].size_out(1))
        err = np.max(np.abs(phi), axis=1) if phi.size else np.zeros(active.size)
        done = err <= tol * scale
        active_next = active[~done]
        if active_next.size == 0:
            active = active_next
            break
        phi, jac = phi[~done], jac[~done]
        step = np.linalg.pinv(jac, rcond=1e-12) @ phi[:, :, None]
        q[active_next] -= step[:, :, 0]
        active = active_next
    if active.size:
        res = map_function(ev, "closure", q[active], p)["phi"]
        raise NotConvergedError(f"{active.size} configuration(s) did not close within {max_iter} "
                                "Newton steps", indices=active.tolist(),
                                residual=float(np.max(np.abs(res))))
    return q if np.ndim(configurations) == 2 else q[0]
