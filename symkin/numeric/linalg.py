"""Rank-revealing linear algebra with explicit, relative tolerances.

All functions are pure and work on NumPy arrays.  ``tol`` is always relative to a
stated reference so that the caller controls scale invariance (see
:mod:`symkin.tolerances`).
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import lapack

from symkin.constraints.algebra import normal_basis  # one definition (the constraints' normals)

__all__ = ["svd_factors", "singular_values", "svd_rank", "svd_null_space", "rank_and_null_space", "left_null_space", "rref",
           "normal_basis", "affine_hull", "independent_rows"]


def svd_factors(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Full SVD ``a = U diag(s) Vt``: ``U`` (m, m), ``s`` (min(m, n),) descending, ``Vt`` (n, n).

    LAPACK's ``dgesdd`` called directly (NumPy's ``svd`` calls the same routine through a
    thicker wrapper, which costs more than the factorisation for the small matrices of a
    mechanism); empty matrices give identities and no singular values.
    """
    m, n = a.shape
    if m == 0 or n == 0:
        return np.eye(m), np.zeros(0), np.eye(n)
    u, s, vt, info = lapack.dgesdd(a)
    if info != 0:  # not converged (or bad input): NumPy's own driver raises a clear error
        return np.linalg.svd(a, full_matrices=True)
    return u, s, vt


def singular_values(a: np.ndarray) -> np.ndarray:
    """Singular values of ``a``, descending (LAPACK's ``dgesdd`` without vectors, as :func:`svd_factors`)."""
    if a.shape[0] == 0 or a.shape[1] == 0:
        return np.zeros(0)
    _, s, _, info = lapack.dgesdd(a, compute_uv=0)
    if info != 0:
        return np.linalg.svd(a, compute_uv=False)
    return s


def svd_rank(s: np.ndarray, threshold: float) -> int:
    """Number of singular values strictly above ``threshold``."""
    return int(np.count_nonzero(s > threshold))


def svd_null_space(a: np.ndarray, threshold: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Singular values (padded with structural zeros, descending), null-space basis, rank.

    ``a`` is (m, n).  Singular values ``<= threshold`` count as zero.  The returned
    singular values have length ``n``: when ``m < n`` the ``n - m`` structural zeros
    are appended, so that ``len(s) - rank`` is the nullity.
    """
    m, n = a.shape
    if n == 0:
        return np.zeros(0), np.zeros((0, 0)), 0
    if m == 0:
        return np.zeros(n), np.eye(n), 0
    _, s, vt = svd_factors(a)
    s_full = np.zeros(n)
    s_full[: s.size] = s
    rank = svd_rank(s, threshold)
    return s_full, vt[rank:].T.copy(), rank


def rank_and_null_space(a: np.ndarray, tol: float) -> tuple[int, np.ndarray, np.ndarray]:
    """Rank, right null space and singular values of ``a`` with an *absolute* threshold ``tol``."""
    s, null, rank = svd_null_space(a, tol)
    return rank, null, s


def left_null_space(a: np.ndarray, tol: float) -> np.ndarray:
    """Orthonormal basis (columns) of ``{y : yᵀ a = 0}`` with absolute threshold ``tol``."""
    if a.shape[0] == 0:
        return np.zeros((0, 0))
    _, null, _ = svd_null_space(a.T, tol)
    return null


def rref(a: np.ndarray, tol: float) -> tuple[np.ndarray, list[int]]:
    """Reduced row echelon form and pivot columns; entries ``<= tol·max|a|`` are zero.

    Gauss-Jordan elimination with partial pivoting.  For a basis of a subspace the
    result is canonical: it depends on the subspace only, not on the basis given.
    """
    r = np.array(a, dtype=float, copy=True)
    if r.size == 0:
        return r, []
    eps = tol * max(float(np.max(np.abs(r))), np.finfo(float).tiny)
    rows, cols = r.shape
    pivots: list[int] = []
    row = 0
    for col in range(cols):
        if row >= rows:
            break
        best = row + int(np.argmax(np.abs(r[row:, col])))
        if abs(r[best, col]) <= eps:
            r[row:, col] = 0.0
            continue
        r[[row, best]] = r[[best, row]]
        r[row] /= r[row, col]
        for other in range(rows):
            if other != row:
                r[other] -= r[other, col] * r[row]
        pivots.append(col)
        row += 1
    r[np.abs(r) <= eps] = 0.0
    return r[: len(pivots)], pivots


def affine_hull(points: np.ndarray, tol: float) -> tuple[int, np.ndarray, np.ndarray]:
    """Dimension ``h`` of the affine hull of ``points`` (k, d), its directions and normals.

    Directions (h, d) and normals (d-h, d) are orthonormal rows; ``tol`` is relative to
    the spread of the points.
    """
    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=True)
    scale = s[0] if s.size and s[0] > 0 else 1.0
    h = int(np.count_nonzero(s > tol * scale))
    return h, vt[:h], vt[h:]


def independent_rows(a: np.ndarray, tol: float, count: int | None = None) -> tuple[int, ...]:
    """Indices (ascending) of well-conditioned independent rows of ``a``, at most ``count`` of them.

    QR with column pivoting of ``aᵀ``: the rank is the number of ``|R_kk| > tol · |R_00|``
    (relative, so scale invariant), and the rows are the first ``min(rank, count)``
    pivots.  This is the one choice of the independent constraint rows ``J_S`` (made once
    by the evaluators at a generic configuration, and by :func:`symkin.analyze` at its
    configuration) and of the rows that the path's square corrector and bifurcation test
    keep.  ``len(result)`` is the rank of ``a`` when ``count`` is None.

    >>> independent_rows(np.array([[1.0, 0.0], [2.0, 0.0], [0.0, 3.0]]), 1e-8)
    (1, 2)
    """
    from scipy.linalg import qr

    a = np.asarray(a, dtype=float)
    if a.size == 0:
        return ()
    _, r, piv = qr(a.T, pivoting=True, mode="economic")
    d = np.abs(np.diag(r))
    rank = int(np.count_nonzero(d > tol * d[0])) if d.size and d[0] > 0 else 0
    take = rank if count is None else min(rank, count)
    return tuple(sorted(int(k) for k in piv[:take]))
