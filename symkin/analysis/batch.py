"""IM / DKP decisions at N configurations from the generated evaluators.

:func:`evaluators` (``symkin.evaluators``) returns the CasADi Functions of
:mod:`symkin.numeric.evaluators` as an :class:`Evaluators` whose :meth:`~Evaluators.batch`
and :meth:`~Evaluators.indicators_at` *decide*.  Every indicator and decision is the one
definition of :mod:`symkin.analysis.indicators`; the generated ``indicators`` kernel is
only a fast way to reach the same numbers where the decision is certain.  No Python loop
runs per configuration: Functions are evaluated by :func:`symkin.numeric.mapping.map_function`,
and the exact path uses NumPy's stacked SVD.

Decisions (IM, DKP-input, DKP-output) are those of :func:`symkin.analyze`, reached by
one of three paths (``BatchResult.path``), with the margin
``s = max(1e-12, (tol.kernel_margin · tol.rank)²)`` (a factor ``kernel_margin`` on
singular values; 1e-12 is the relative width of the kernel's Sturm certificate):

0. **kernel** — the generated indicator kernel decides alone when the decision is
   certain: ``im`` certified by Sturm counts and ``im > s·trace`` (then
   ``σ_{F+1} > tol·σ_max`` with room to spare: ``L = F``), and both DKP lower bounds
   ``> s`` (then every singular value of the restricted rows exceeds ``tol``: no DKP).
1. **motion-space ranks** — no IM for certain but a DKP bound is small: the DKP test of
   :func:`~symkin.analysis.indicators.is_dkp` on the generated orthonormal motion-space
   basis (when no constraint row is redundant).
2. **SVD** — everything else (near IM, or the kernel could not certify its value) is
   recomputed as the core does: SVD of the reduced ``J``, threshold ``tol·σ_max``, the
   motion space from it, :mod:`~symkin.analysis.indicators` on it.

So the decisions agree with the core's except where a singular value is within rounding
error of its threshold, where no two computations need agree.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from symkin.analysis import indicators as ind
from symkin.kinds import Kind
from symkin.model.mechanism import Mechanism
from symkin.numeric import evaluators as _numeric
from symkin.numeric.evaluators import INDICATOR_NAMES
from symkin.numeric.mapping import as_configurations, fast_caller, map_function
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["BatchResult", "Evaluators", "evaluators", "evaluators_for", "batch", "single",
           "exact_indicators", "motion_ranks", "fast_caller"]

#: relative width of the kernel's Sturm certificate: the smallest margin that means anything
_CERTIFICATE = 1e-12


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
        DKP values (:func:`symkin.analysis.indicators.dkp_value`); NaN at IM configurations
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
            out.append(Kind.IM)
        if self.is_dkp_input[k]:
            out.append(Kind.DKP_INPUT)
        if self.is_dkp_output[k]:
            out.append(Kind.DKP_OUTPUT)
        return tuple(out)

    @property
    def exact(self) -> np.ndarray:
        """Configurations not decided by the kernel alone (``path > 0``)."""
        return self.path > 0

    @property
    def singular(self) -> np.ndarray:
        """IM or DKP at each configuration."""
        return self.im | self.is_dkp_input | self.is_dkp_output


# ---------------------------------------------------------------------- exact paths
def _unit_parameter_rows(ev, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Input and output rows over the free coordinates, unit norm (:func:`~symkin.analysis.indicators.unit_rows`)."""
    n = q.shape[0]
    fp = ev.functions["parameters"]
    prm = map_function(ev, "parameters", q)
    out = []
    for i, key in enumerate(("inputs", "outputs")):
        pf = prm[key].reshape((n,) + fp.size_out(i))[:, :, ev.free]
        out.append(ind.unit_rows(pf)[0])
    return out[0], out[1]


def _basis_stack(ev, jf: np.ndarray) -> np.ndarray | None:
    """``J_S`` at every configuration (n, nf − F, nf): the evaluators' rows, else chosen here."""
    n, _, nf = jf.shape
    if nf - ev.mobility <= 0:
        return np.zeros((n, 0, nf))
    if ev.basis_rows:
        return jf[:, list(ev.basis_rows), :]
    return None


def exact_indicators(ev, configurations, tol: float | Tolerances | None = None) -> dict[str, np.ndarray]:
    """Indicators and decisions computed as the core computes them (stacked SVD).

    The motion space of :func:`symkin.motion_space` (SVD of the reduced ``J``, threshold
    ``tol·σ_max``, null space from the SVD) and the definitions of
    :mod:`symkin.analysis.indicators` for IM, DKP-input and DKP-output.
    """
    tol = Tolerances.of(tol)
    q = as_configurations(ev, configurations)
    n = q.shape[0]
    f = ev.mobility
    nf = ev.nf
    fj = ev.functions["J"]
    jf = map_function(ev, "J", q)["J_free"].reshape((n,) + fj.size_out(1))
    p_in, p_out = _unit_parameter_rows(ev, q)
    out = {key: np.full(n, np.nan) for key in ("im_indicator", "dkp_input", "dkp_output")}
    out.update(dof=np.zeros(n, dtype=int), im=np.zeros(n, bool),
               is_dkp_input=np.zeros(n, bool), is_dkp_output=np.zeros(n, bool))
    if nf == 0:
        return out
    if jf.shape[1] == 0:
        s_full = np.zeros((n, nf))
        vt = np.broadcast_to(np.eye(nf), (n, nf, nf))
    else:
        _, s, vt = np.linalg.svd(jf, full_matrices=True)
        s_full = np.zeros((n, nf))
        s_full[:, : s.shape[1]] = s
    dof = ind.instantaneous_dof(s_full, ind.rank_threshold(s_full, tol))
    out["dof"] = dof
    out["im"] = ind.is_im(dof, f)
    out["im_indicator"] = ind.im_indicator(s_full, f)
    js_all = _basis_stack(ev, jf)
    for L in np.unique(dof):
        sel = np.flatnonzero(dof == L)
        v = vt[sel][:, nf - L:, :].transpose(0, 2, 1)  # (s, nf, L): the null space
        for key, pk in (("input", p_in), ("output", p_out)):
            k = pk.shape[1]
            if k == 0:
                continue
            sv = ind.restricted_singular_values(pk[sel], v)
            out[f"is_dkp_{key}"][sel] = ind.is_dkp(sv, k, f, tol)
            if L != f:
                continue
            if js_all is not None:
                out[f"dkp_{key}"][sel] = ind.dkp_value(pk[sel], sv, f, js_all[sel])
            else:  # no rows chosen once (declared mobility not generic): choose them here
                for a, c in enumerate(sel):
                    rows = ind.basis_rows(jf[c], f, tol)
                    js = None if rows is None else jf[c][list(rows)]
                    out[f"dkp_{key}"][c] = ind.dkp_value(pk[c], sv[a], f, js)
    return out


def motion_ranks(ev, configurations, tol: float | Tolerances | None = None) -> dict[str, np.ndarray]:
    """DKP decisions at configurations known to have ``L = F`` (kernel-certified, no IM).

    The motion space comes from the generated QR (Function ``motion``), orthonormal to
    rounding like the core's; :func:`~symkin.analysis.indicators.is_dkp` decides.
    Valid only when no constraint row is redundant (``basis_rows == effective_rows``).
    """
    tol = Tolerances.of(tol)
    q = as_configurations(ev, configurations)
    n = q.shape[0]
    v = map_function(ev, "motion", q)["V"].reshape((n,) + ev.functions["motion"].size_out(0))
    p_in, p_out = _unit_parameter_rows(ev, q)
    out = {}
    for key, pk in (("input", p_in), ("output", p_out)):
        sv = ind.restricted_singular_values(pk, v)
        out[f"is_dkp_{key}"] = ind.is_dkp(sv, pk.shape[1], ev.mobility, tol)
    return out


# ---------------------------------------------------------------------- batch and single
def _indicator_matrix(values: dict) -> np.ndarray:
    return np.column_stack([values[k].reshape(-1) for k in INDICATOR_NAMES])


def _safe_margin(tol: Tolerances) -> float:
    return max(_CERTIFICATE, (tol.kernel_margin * tol.rank) ** 2)


def _paths(ev, kern: np.ndarray, tol: Tolerances) -> np.ndarray:
    """0: the kernel decides alone; 1: no IM for sure, DKP by the motion-space ranks; 2: SVD path."""
    s = _safe_margin(tol)
    k_in, k_out = len(ev.input_labels), len(ev.output_labels)
    with np.errstate(invalid="ignore"):
        no_im = (kern[:, 1] == 1.0) & (kern[:, 0] > s * kern[:, 2])
        no_dkp = np.ones(kern.shape[0], bool)
        if k_in:
            no_dkp &= kern[:, 4] > s
        if k_out:
            no_dkp &= kern[:, 6] > s
    path = np.full(kern.shape[0], 2, dtype=np.int8)
    if len(ev.basis_rows) == len(ev.effective_rows):
        path[no_im] = 1
    path[no_im & no_dkp] = 0
    return path


def batch(ev, configurations, tol: float | Tolerances | None = None, exact: bool = False) -> BatchResult:
    """Indicators and IM / DKP decisions at N configurations (rows of ``configurations``).

    Parameters
    ----------
    ev : Evaluators
    configurations : array (N, nf)
        Free coordinates, in the order of ``ev.q_labels``.
    tol : float or Tolerances, optional
        Rank tolerance (default ``Tolerances()``), as in :func:`symkin.analyze`.
    exact : bool
        Decide every configuration by the SVD path (for checks; slower).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> ev = evaluators(get("fourbar_appendix"))
    >>> res = ev.batch([ev.q0, ev.q0])
    >>> res.dof.tolist(), res.im.tolist(), res.path.tolist()
    ([1, 1], [False, False], [0, 0])
    """
    tol = Tolerances.of(tol)
    q = as_configurations(ev, configurations)
    n = q.shape[0]
    f = ev.mobility
    k_in, k_out = len(ev.input_labels), len(ev.output_labels)
    if ev.fast and not exact:
        kern = _indicator_matrix(map_function(ev, "indicators", q))
        path = _paths(ev, kern, tol)
        im_ind = kern[:, 0].copy()
        d_in = kern[:, 3].copy()
        d_out = kern[:, 5].copy()
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
                       is_dkp_input=is_in, is_dkp_output=is_out, path=path, tol=tol.rank)


def single(ev, q, tol: float | Tolerances | None = None) -> dict[str, Any]:
    """Indicators and decisions at one configuration (see :meth:`Evaluators.indicators_at`).

    The same three paths as :func:`batch`; ``path`` says which one decided.
    """
    tol = Tolerances.of(tol)
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




# ---------------------------------------------------------------------- the evaluators, deciding
@dataclass(eq=False)
class Evaluators(_numeric.Evaluators):
    """The CasADi Functions of :class:`symkin.numeric.evaluators.Evaluators`, with decisions.

    Everything of the numeric class (``ev("G", q)``, ``ev.map``, ``ev.project``,
    ``ev.compile()``, ``ev.functions[...]``, ``ev.q0``) plus the IM / DKP decisions of
    :mod:`symkin.analysis.indicators` at one (:meth:`indicators_at`) or many
    (:meth:`batch`) configurations.
    """

    def indicators_at(self, q, tol: float | Tolerances | None = None) -> dict[str, Any]:
        """Indicators and IM / DKP decisions at one configuration (fast single call).

        Uses CasADi's buffer interface (no per-call conversion) and the paths of
        :func:`batch` when the configuration is near a singularity.  Returns a dict with
        ``im_indicator``, ``dof``, ``im``, ``dkp_input``, ``dkp_output``, ``is_dkp_input``,
        ``is_dkp_output`` and ``path`` (0, 1, 2 as in :class:`BatchResult`).
        """
        return single(self, q, tol)

    def batch(self, configurations, tol: float | Tolerances | None = None, exact: bool = False) -> BatchResult:
        """Indicators and decisions over N configurations; see :func:`batch`."""
        return batch(self, configurations, tol=tol, exact=exact)


def evaluators(mech: Mechanism, tolerances: Tolerances = DEFAULT, kernel: bool = True) -> Evaluators:
    """The evaluators of ``mech`` with decisions (``symkin.evaluators``).

    Builds :func:`symkin.numeric.evaluators.evaluators` (see it for the Functions and the
    arguments) and returns them as an :class:`Evaluators`.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> ev = evaluators(get("fourbar_appendix"))
    >>> ev.batch([ev.q0]).types(0), ev.indicators_at(ev.q0)["dof"]
    ((), 1)
    """
    base = _numeric.evaluators(mech, tolerances, kernel=kernel)
    return Evaluators(**{f.name: getattr(base, f.name) for f in fields(base)})


_SHARED: dict[tuple, Evaluators] = {}


def evaluators_for(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> Evaluators:
    """The evaluators of ``mech``, built once per process and model content (shared, do not mutate).

    Paths and maps of one mechanism share them: the CasADi closure and parameter rows
    they are built on are those of :func:`evaluators`.  The indicator kernel is built on
    first use (a path needs only the closure and the rows).
    """
    key = (mech.content_hash(), tolerances)
    ev = _SHARED.get(key)
    if ev is None:
        ev = evaluators(mech, tolerances, kernel=False)
        _SHARED[key] = ev
    return ev
