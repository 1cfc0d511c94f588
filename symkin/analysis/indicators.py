"""The one definition of the singularity indicators and of the IM / DKP decisions.

Every stage that needs an indicator calls these functions: :func:`symkin.analyze`
(one configuration), the batch evaluators (:mod:`symkin.analysis.batch`, N configurations
in stacked arrays) and path tracing (:mod:`symkin.paths.trace`, one point of a path).
Each function takes stacked arrays (any leading axes) so that one definition serves all.
The generated CasADi form of the same quantities (the ``indicators`` Function of
:mod:`symkin.numeric.evaluators`) is kept equal to these by the tests.

With ``J`` the dimensionless constraint rows over the free coordinates (``G = JᵀJ``),
``F`` the mobility, ``V`` an orthonormal basis of the motion space and ``P̂`` kinematic
parameter rows scaled to unit norm (paper §IV):

* **unit parameter rows** — ``P̂ = P / ‖P‖`` over the free coordinates (:func:`unit_rows`);
* **IM indicator** — ``λ_{F+1}``, the first eigenvalue of the reduced G above its F generic
  zeros (§IV-A, Fig. 3), from the singular values of ``J`` (:func:`im_indicator`);
* **IM decision** — ``L > F`` with ``L`` the number of singular values ``<= tol · σ_max``
  (:func:`instantaneous_dof`, :func:`is_im`);
* **DKP decision** — ``rank(P̂ V) < min(F, k)``, singular values of ``P̂ V`` compared with
  the absolute ``tol`` (eqs. 12-13, 16-17; :func:`is_dkp`);
* **DKP value** — for ``k = F`` rows, ``det[J_S; P̂] / sqrt(det(J_S J_Sᵀ)) = ±det(P̂ V)``,
  signed and dimensionless (``J_S`` the ``nf − F`` independent constraint rows chosen by
  :func:`symkin.numeric.linalg.independent_rows`); otherwise the product of the
  ``min(k, F)`` singular values of ``P̂ V`` (:func:`dkp_value`).  Both vanish exactly at
  DKP configurations and are defined only where ``L = F``;
* **LIM test along a motion** — a link's signed angular rate about its fixed pivot or axis
  (:func:`link_rate`) or, for a link without one, the speed of its free nodes
  (:func:`link_speed`): zero where the link stops while the mechanism moves (§IV-B-3).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg.lapack import dgetrf as _dgetrf

from symkin.numeric.linalg import independent_rows
from symkin.tolerances import Tolerances

__all__ = ["unit_rows", "padded_singular_values", "im_indicator", "rank_threshold", "instantaneous_dof",
           "is_im", "restricted_singular_values", "is_dkp", "dkp_value", "basis_orientation", "basis_volume",
           "basis_rows", "link_rate", "link_speed"]


def unit_rows(p: np.ndarray, free: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Parameter rows scaled to unit norm over the free coordinates: ``(P̂, norms)``.

    ``p`` has shape ``(..., k, D)``; the norm of each row is taken over the columns in
    the boolean mask ``free`` (all columns when None).  A zero row is left as it is (its
    returned norm is 1).  Relations found on ``P̂`` become physical coefficients by
    dividing by ``norms``.

    >>> unit_rows(np.array([[3.0, 4.0]]))[0].tolist()
    [[0.6, 0.8]]
    """
    p = np.asarray(p, dtype=float)
    pf = p if free is None else p[..., free]
    norms = np.sqrt((pf * pf).sum(axis=-1))
    safe = norms if norms.all() else np.where(norms > 0, norms, 1.0)
    return p / safe[..., None], safe


def padded_singular_values(j: np.ndarray, nf: int) -> np.ndarray:
    """Singular values of ``j`` (..., m, nf), descending, padded with ``nf − m`` structural zeros."""
    j = np.asarray(j, dtype=float)
    lead = j.shape[:-2]
    out = np.zeros(lead + (nf,))
    if j.shape[-2] and nf:
        s = np.linalg.svd(j, compute_uv=False)
        out[..., : s.shape[-1]] = s
    return out


def im_indicator(singular_values: np.ndarray, mobility: int, ascending: bool = False) -> np.ndarray:
    """``λ_{F+1}``: the (F+1)-th smallest eigenvalue ``σ²`` of the reduced G (§IV-A).

    ``singular_values`` (..., nf) of the reduced ``J`` including the structural zeros, in
    any order (``ascending=True`` says they are sorted already).  NaN when ``F >= nf``.
    It vanishes at increased-mobility configurations.

    >>> float(im_indicator(np.array([2.0, 0.0, 0.5]), 1))
    0.25
    """
    s = np.asarray(singular_values, dtype=float)
    if not ascending:
        s = np.sort(s, axis=-1)
    if mobility >= s.shape[-1]:
        return np.full(s.shape[:-1], np.nan)
    return s[..., mobility] ** 2


def rank_threshold(singular_values: np.ndarray, tol: Tolerances) -> np.ndarray:
    """``tol.rank · σ_max``: singular values of ``J`` at or below it count as zero."""
    s = np.asarray(singular_values, dtype=float)
    return tol.rank * (np.max(s, axis=-1) if s.shape[-1] else np.zeros(s.shape[:-1]))


def instantaneous_dof(singular_values: np.ndarray, threshold) -> np.ndarray:
    """``L``: number of singular values (padded, see :func:`padded_singular_values`) ``<= threshold``."""
    s = np.asarray(singular_values, dtype=float)
    return s.shape[-1] - np.count_nonzero(s > np.asarray(threshold)[..., None], axis=-1)


def is_im(dof, mobility: int):
    """Increased mobility: ``L > F`` (§III, Fig. 9)."""
    return np.asarray(dof) > mobility


def restricted_singular_values(p_hat: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Singular values of ``P̂ V`` (..., min(k, L)), descending: the restricted parameter rows.

    ``p_hat`` (..., k, nf) unit rows over the free coordinates, ``v`` (..., nf, L) an
    orthonormal basis of the motion space.
    """
    m = np.asarray(p_hat, dtype=float) @ np.asarray(v, dtype=float)
    if m.shape[-1] == 0 or m.shape[-2] == 0:
        return np.zeros(m.shape[:-2] + (0,))
    return np.linalg.svd(m, compute_uv=False)


def is_dkp(restricted: np.ndarray, k: int, mobility: int, tol: Tolerances, rank: int | None = None):
    """DKP test: ``rank(P̂ V) < min(F, k)``, singular values compared with ``tol.rank`` (eq. 12, 16).

    ``restricted`` are the singular values from :func:`restricted_singular_values` (the
    rows are unit and V orthonormal, so the absolute threshold is scale invariant).
    False when there are no such parameters (``k = 0``).  ``rank``, for one configuration,
    is that count of ``restricted`` above ``tol.rank`` when the caller has made it.
    """
    if rank is not None:  # one configuration whose singular values above tol.rank are counted already
        return k > 0 and rank < min(mobility, k)
    s = np.asarray(restricted, dtype=float)
    if k == 0:
        return np.zeros(s.shape[:-1], bool)
    return (s > tol.rank).sum(axis=-1) < min(mobility, k)


def dkp_value(p_hat: np.ndarray, restricted: np.ndarray, mobility: int, js: np.ndarray | None = None,
              volume: float | None = None, restricted_matrix: np.ndarray | None = None,
              orientation: float | None = None):
    """The DKP indicator of ``k`` unit parameter rows at a configuration with ``L = F``.

    For ``k = F`` and ``J_S`` given (``nf − F`` independent constraint rows, (..., nf − F, nf)):
    ``det[J_S; P̂] / sqrt(det(J_S J_Sᵀ))``, which equals ``±det(P̂ V)``: signed, changes sign
    through a DKP configuration (a turning point of the input when F = 1).  Otherwise the
    product of the ``min(k, F)`` singular values ``restricted`` of ``P̂ V`` (non-negative).
    NaN when ``k = 0``.  Where ``J_S`` loses rank (IM) the value means nothing; the
    division is floored at the smallest normal float so that it stays finite there.
    ``volume`` (one configuration) is :func:`basis_volume` of ``js`` when the caller has it.

    One configuration with ``restricted_matrix = P̂ V`` and ``orientation`` =
    :func:`basis_orientation` of ``(J_S, V)``: the same value as ``orientation · det(P̂ V)``.
    For an orthonormal ``V`` with ``J_S V = 0``, ``[J_S; P̂] [W V] = [[J_S W, 0], [P̂ W, P̂ V]]``
    (``[W V]`` orthogonal), so ``det[J_S; P̂] = det[J_S; Vᵀ] · det(P̂ V)`` and
    ``|det[J_S; Vᵀ]| = sqrt(det(J_S J_Sᵀ))``: one factorisation of ``[J_S; Vᵀ]`` serves the
    inputs and the outputs (a test keeps both forms equal).

    Examples
    --------
    The four-bar of the appendix, output rows (rocker DC): ``±det(P̂ V)`` from a plain
    SVD equals the signed determinant.

    >>> from symkin.model.catalogue import get
    >>> from symkin.analysis.motion_space import motion_space
    >>> from symkin.numeric.geometric_matrix import constraint_rows, free_mask, parameters_matrix
    >>> mech = get("fourbar_appendix")
    >>> ms, free = motion_space(mech), free_mask(mech)
    >>> p_hat = unit_rows(parameters_matrix(mech, mech.outputs)[0][:, free])[0]
    >>> jf = constraint_rows(mech).matrix[:, free]
    >>> js = jf[list(basis_rows(jf, 1, Tolerances()))]
    >>> v = ms.V[free]
    >>> d = dkp_value(p_hat, restricted_singular_values(p_hat, v), 1, js)
    >>> bool(abs(abs(d) - abs(np.linalg.det(p_hat @ v))) < 1e-14)
    True
    """
    p_hat = np.asarray(p_hat, dtype=float)
    k = p_hat.shape[-2]
    lead = p_hat.shape[:-2]
    if k == 0:
        return np.full(lead, np.nan)
    if k == mobility and orientation is not None and restricted_matrix is not None:
        return orientation * _det(restricted_matrix)
    if k == mobility and js is not None and js.shape[-2] + k == p_hat.shape[-1]:
        js = np.asarray(js, dtype=float)
        if p_hat.ndim == 2 and js.ndim == 2:  # one configuration: LAPACK's LU directly (no gufunc overhead)
            return _det(np.concatenate((js, p_hat))) / (basis_volume(js) if volume is None else volume)
        gram = np.linalg.det(js @ np.swapaxes(js, -1, -2)) if js.shape[-2] else np.ones(lead)
        vol = np.sqrt(np.maximum(gram, TINY))  # J_S rank-deficient only at IM
        if js.ndim < p_hat.ndim:  # one J_S for a stack of parameter rows
            js = np.broadcast_to(js, lead + js.shape[-2:])
        return np.linalg.det(np.concatenate([js, p_hat], axis=-2)) / vol
    s = np.asarray(restricted, dtype=float)
    return np.prod(s[..., : min(k, mobility)], axis=-1)


def _det(a: np.ndarray) -> float:
    """Determinant of one square matrix: cofactors up to 3 × 3, else LAPACK's LU (``dgetrf``)."""
    n = a.shape[0]
    if n == 0:
        return 1.0
    if n <= 3:  # cofactors in plain floats: cheaper than a LAPACK call for the restricted matrices
        m = a.tolist()
        if n == 1:
            return m[0][0]
        if n == 2:
            return m[0][0] * m[1][1] - m[0][1] * m[1][0]
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    lu, piv, info = _dgetrf(a)
    if info < 0:  # bad input: let NumPy say what is wrong
        return float(np.linalg.det(a))
    swaps = int(np.count_nonzero(piv != _ORDER[: piv.size])) if piv.size <= _ORDER.size else \
        int(np.count_nonzero(piv != np.arange(piv.size)))
    return math.prod(lu.diagonal().tolist()) * (-1.0 if swaps % 2 else 1.0)


#: LAPACK's pivot indices when no row is exchanged
_ORDER = np.arange(64, dtype=np.int32)
#: the smallest normal float: the floor of a J_S volume (J_S loses rank only at IM)
TINY = float(np.finfo(float).tiny)


def basis_orientation(js: np.ndarray, v: np.ndarray) -> float:
    """``sign det[J_S; Vᵀ]`` (±1) of one ``J_S`` (nf − F, nf) and an orthonormal basis ``V`` (nf, F) of its null space.

    The orientation of ``V`` relative to the rows ``J_S``: with it the signed DKP value is
    ``orientation · det(P̂ V)`` (see :func:`dkp_value`).
    """
    return -1.0 if _det(np.concatenate((js, v.T))) < 0 else 1.0


def basis_volume(js: np.ndarray) -> float:
    """``sqrt(det(J_S J_Sᵀ))`` of one ``J_S``, floored at the smallest normal float (IM)."""
    if js.shape[0] == 0:
        return 1.0
    return float(np.sqrt(max(_det(js @ js.T), TINY)))


def basis_rows(jf: np.ndarray, mobility: int, tol: Tolerances, rank: int | None = None,
               nonzero: np.ndarray | None = None) -> tuple[int, ...] | None:
    """The ``nf − F`` independent constraint rows ``J_S`` of ``jf`` (m, nf), or None.

    :func:`symkin.numeric.linalg.independent_rows` (the rule the evaluators apply once, at a
    generic configuration; here it is applied at the configuration of ``jf``: where every
    effective row is needed, as in most mechanisms, both give all of them); None when
    ``jf`` has fewer than ``nf − F`` independent rows here (an IM configuration).  A caller
    that knows ``rank(jf)`` passes it (and, if it has them, the indices of the nonzero
    rows): when it is ``nf − F`` and exactly that many rows are nonzero, they are the rows
    (what the pivoted QR would choose), with no factorisation.
    """
    count = jf.shape[1] - mobility
    if count <= 0:
        return ()
    if rank == count:
        nonzero = np.flatnonzero(jf.any(axis=1)) if nonzero is None else nonzero
        if nonzero.size == count:
            return tuple(nonzero.tolist())
    rows = independent_rows(jf, tol.rank, count)
    return rows if len(rows) == count else None


def link_rate(r: np.ndarray, v: np.ndarray, axis: np.ndarray | None = None) -> np.ndarray:
    """Signed rate at which a link turns about a fixed point (planar) or a fixed axis (spatial): the LIM test.

    ``r`` (..., dim) is a free node of the link relative to its fixed node (a point of the
    fixed ``axis``, a unit vector, in space), ``v`` (..., dim) that node's velocity along
    the motion: the link's angular rate is ``(r × v) / |r|²`` (planar) or
    ``((r⊥ × v) · a) / |r⊥|²`` with ``r⊥ = r − (r·a) a`` (spatial).  With positions in units
    of the length scale and velocities per unit (dimensionless) arclength it is
    dimensionless: a model and the same model scaled give the same value.  It changes sign
    where the link stops and turns back (§IV-B-3: a link impossible motion, LIM, when the
    mechanism moves on), so a path locates it as a sign change; use the node farthest from
    the pivot (largest ``|r|``, or ``|r⊥|``) for the best-conditioned value.

    >>> float(link_rate(np.array([2.0, 0.0]), np.array([0.0, 1.0])))
    0.5
    >>> float(link_rate(np.array([1.0, 0.0, 5.0]), np.array([0.0, -3.0, 0.0]), np.array([0.0, 0.0, 1.0])))
    -3.0
    """
    r, v = np.asarray(r, float), np.asarray(v, float)
    if axis is None:
        return (r[..., 0] * v[..., 1] - r[..., 1] * v[..., 0]) / (r * r).sum(axis=-1)
    a = np.asarray(axis, float)
    perp = r - (r @ a)[..., None] * a
    return (np.cross(perp, v) @ a) / (perp * perp).sum(axis=-1)


def link_speed(v: np.ndarray) -> np.ndarray:
    """Speed of a link along the motion: the norm of its free nodes' velocities ``v`` (..., k, dim).

    The LIM test of a link with no fixed pivot or axis (a coupler, a link on a spherical
    joint): non-negative, zero where the link stops, so a path locates it as a minimum below
    the event threshold.  Dimensionless as :func:`link_rate`.

    >>> float(link_speed(np.array([[3.0, 0.0], [0.0, 4.0]])))
    5.0
    """
    v = np.asarray(v, float)
    return np.sqrt((v * v).sum(axis=(-2, -1)))
