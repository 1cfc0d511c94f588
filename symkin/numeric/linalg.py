"""Rank-revealing linear algebra with explicit, relative tolerances.

All functions are pure and work on NumPy arrays.  ``tol`` is always relative to a
stated reference so that the caller controls scale invariance (see
:mod:`symkin.tolerances`).
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import lapack

from symkin.constraints.algebra import normal_basis  # one definition (the constraints' normals)
from symkin.constraints.body import affine_hull  # one definition (a degenerate body's decision)

__all__ = ["svd_factors", "singular_values", "svd_rank", "svd_null_space", "rank_and_null_space", "left_null_space", "rref",
           "normal_basis", "affine_hull", "independent_rows", "sparse_small_singular", "sparse_dependent_rows",
           "FundamentalStresses"]


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


# ---------------------------------------------------------------------- sparse (large models, issue 19)
def _orthonormal_columns(q: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the span of ``q``'s columns (thin QR; ``q`` of full column rank)."""
    return np.linalg.qr(q)[0] if q.shape[1] else q


def sparse_small_singular(a, tol: float, window: float, dense_below: int = 8,
                          max_vectors: int = 2000) -> tuple[float, np.ndarray, np.ndarray, int]:
    """Rank, the smallest singular values and the right null space of a sparse ``a`` (m, n).

    Returns ``(σ_max, σ_small, null, rank)``: ``σ_small`` ascending (every singular value of
    ``a`` at or below ``window · σ_max``, plus the next one, structural zeros of a wide
    ``a`` included), ``null`` (n, L) orthonormal, ``rank = n − L`` with
    ``L = #{σ <= tol · σ_max}`` — the dense path's decision (:func:`svd_null_space`).

    Method: ``σ_max²`` is the largest eigenvalue of ``G = aᵀa`` (Lanczos, ARPACK); the
    eigenvectors of the smallest eigenvalues of ``G`` come from Lanczos in shift-invert
    mode, with ``G + s I`` (``s = window² · σ_max²``) factorised once by SuperLU in a
    fill-reducing symmetric order; their number grows (doubling) until the largest found
    is above ``window² · σ_max²``.  Eigenvalues of ``G`` are accurate to ``ε · σ_max²``
    only, i.e. ``σ`` to ``√ε · σ_max`` — the size of the default rank tolerance — so they
    decide nothing: the singular values are those of ``a Q`` (``Q`` the orthonormal basis
    of the eigenvectors found, a Rayleigh–Ritz step on ``a`` itself), accurate to
    ``ε · σ_max`` like the dense SVD's.  Every singular value not found is above
    ``window · σ_max``, far above any rank threshold.  Small ``n`` (``<= dense_below``):
    the eigenvectors of ``G`` by a dense ``eigh``, then the same Rayleigh–Ritz step.
    More than ``max_vectors`` singular values below the window raise ``MemoryError``
    (the motion space would be a dense n × L matrix; the caller refuses the model).
    """
    import scipy.sparse as sps
    import scipy.sparse.linalg as spla
    from scipy.linalg import eigh

    a = sps.csr_matrix(a)
    m, n = a.shape
    if n == 0:
        return 0.0, np.zeros(0), np.zeros((0, 0)), 0
    g = (a.T @ a).tocsc()
    if n <= dense_below:
        w, vecs = eigh(g.toarray())
        lmax = float(max(w[-1], 0.0))
        q = vecs[:, : min(n, int(np.count_nonzero(w <= window * window * lmax)) + 1)]
    else:
        # Ritz residual tol^(3/4): the eigenvalue's error is about residual² / gap, far smaller (7e-10 relative
        # at 10,000 nodes, whose top eigenvalues cluster), so the threshold ``tol · σ_max`` moves by less than
        # any margin a decision reports; a tighter residual costs 4× the time there
        lmax = float(spla.eigsh(g, k=1, which="LA", return_eigenvectors=False, tol=tol ** 0.75)[0])
        if lmax <= 0.0:  # no constraint touches a free coordinate
            return 0.0, np.zeros(n), np.eye(n), 0
        shift = window * window * lmax
        lu = spla.splu((g + shift * sps.identity(n, format="csc")).tocsc(), permc_spec="MMD_AT_PLUS_A",
                       diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
        k = min(8, n - 1)
        while True:
            w, vecs = spla.eigsh(g, k=k, sigma=-shift, which="LM", OPinv=op)
            if w.max() > window * window * lmax or k >= n - 1:
                break
            if k >= max_vectors:
                raise MemoryError(f"more than {max_vectors} singular values below {window:g} × the largest")
            k = min(2 * k, n - 1)
        if k >= n - 1 and w.max() <= window * window * lmax:  # all of them: the dense eigenproblem
            w, vecs = eigh(g.toarray())
        q = vecs
    q = _orthonormal_columns(q)
    _, s, vt = np.linalg.svd(np.asarray(a @ q), full_matrices=False) if m else (None, np.zeros(q.shape[1]), np.eye(q.shape[1]))
    s_full = np.zeros(q.shape[1])
    s_full[: s.size] = s  # a Ritz basis wider than a: structural zeros
    if s.size < q.shape[1]:
        vt = np.vstack([vt, _complement_rows(vt, q.shape[1])])
    smax = float(np.sqrt(lmax))
    order = np.argsort(s_full, kind="stable")
    s_asc = s_full[order]
    v = (q @ vt.T)[:, order]
    null_count = int(np.count_nonzero(s_asc <= tol * smax))
    return smax, s_asc, v[:, :null_count].copy(), n - null_count


def _complement_rows(vt: np.ndarray, k: int) -> np.ndarray:
    """Orthonormal rows completing the orthonormal rows ``vt`` to a basis of R^k."""
    full = np.linalg.svd(vt, full_matrices=True)[2] if vt.size else np.eye(k)
    return full[vt.shape[0]:]


#: Gram matrices with more rows than this are factorised in the order of their rows sorted by
#: the elimination order of ``aᵀa`` (minimum degree on the Gram matrix itself fills in too much
#: beyond: 73 s for the 29,000 rows of a 10,000-node planar truss, against 1.4 s)
GRAM_MINIMUM_DEGREE_ROWS = 8000


def sparse_dependent_rows(a, count: int, regularisation: float) -> np.ndarray:
    """Indices of ``count`` rows of the sparse ``a`` that depend on the others (ascending).

    The Gram matrix ``a aᵀ + δ I`` (``δ = regularisation``, rows of ``a`` of order one) is
    factorised ``L D Lᵀ`` by SuperLU with diagonal pivots: ``D_kk − δ`` is the squared
    distance of row k from the rows before it in the factorisation's order (Cholesky is
    Gram–Schmidt), zero for a dependent row.  The ``count`` smallest pivots
    (``count = m − rank``, the rank decided by :func:`sparse_small_singular`) are the
    dependent rows; the caller verifies the stresses they give.  The order: minimum degree
    on the Gram matrix up to :data:`GRAM_MINIMUM_DEGREE_ROWS` rows; beyond, the rows sorted
    by the last of their columns in a minimum-degree elimination order of ``aᵀa`` (rows
    that meet early in the elimination of the coordinates come early).
    """
    import scipy.sparse as sps
    import scipy.sparse.linalg as spla

    a = sps.csr_matrix(a)
    m, n = a.shape
    if count <= 0:
        return np.zeros(0, dtype=int)
    order = np.arange(m)
    spec = "MMD_AT_PLUS_A"
    if m > GRAM_MINIMUM_DEGREE_ROWS and n:
        g = (a.T @ a).tocsc()
        scale = float(abs(g).max()) or 1.0
        pos = spla.splu(g + regularisation * scale * sps.identity(n, format="csc"), permc_spec="MMD_AT_PLUS_A",
                        diag_pivot_thresh=0.0, options={"SymmetricMode": True}).perm_c[a.indices]
        starts = a.indptr[:-1]
        nonempty = np.diff(a.indptr) > 0
        last = np.zeros(m, dtype=np.int64)
        first = np.zeros(m, dtype=np.int64)
        last[nonempty] = np.maximum.reduceat(pos, starts[nonempty])
        first[nonempty] = np.minimum.reduceat(pos, starts[nonempty])
        order = np.lexsort((first, last))
        a = a[order]
        spec = "NATURAL"
    gram = (a @ a.T + regularisation * sps.identity(m, format="csr")).tocsc()
    lu = spla.splu(gram, permc_spec=spec, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    d = np.abs(lu.U.diagonal())
    position = np.argsort(d, kind="stable")[:count]
    return np.sort(order[np.argsort(lu.perm_r)[position]])


class FundamentalStresses:
    """The fundamental left null vectors of the sparse ``a`` (m, n) for its ``dependent`` rows.

    With ``B`` the other rows (``rank`` of them) and ``C`` the columns kept after dropping
    ``L = null.shape[1]`` columns on which the right null space is nonsingular (pivoted QR of
    ``nullᵀ``), ``B[:, C]`` is square and nonsingular, and for each dependent row k,
    ``y = B[:, C]⁻ᵀ a[k, C]ᵀ`` gives ``ω = e_k − Σ y_b e_b`` with ``ωᵀ a = 0`` (row k is
    ``yᵀ B``).  SuperLU factorises ``B[:, C]ᵀ`` once (at construction); :meth:`columns`
    solves for a range of dependent rows, one solve each, keeping only the nonzeros, so
    that a caller computes the stresses it shows (memory linear in their nonzeros).
    """

    def __init__(self, a, dependent: np.ndarray, null: np.ndarray):
        import scipy.sparse as sps
        import scipy.sparse.linalg as spla
        from scipy.linalg import qr
        from scipy.sparse.csgraph import structural_rank

        a = sps.csr_matrix(a)
        self.shape = a.shape
        m, n = a.shape
        keep = np.arange(n)
        if null.shape[1]:
            piv = qr(null.T, pivoting=True, mode="r")[1]
            keep = np.setdiff1d(keep, piv[: null.shape[1]])
        self.dependent = np.asarray(dependent, dtype=int)
        self.basis = np.setdiff1d(np.arange(m), self.dependent)
        self.count = self.dependent.size
        b = a[self.basis][:, keep].T.tocsc()
        # SuperLU may crash (not raise) on a structurally singular matrix: refuse those first
        if self.count and structural_rank(b) < min(b.shape):
            raise RuntimeError("the rows chosen as a basis are structurally singular")
        self._lu = spla.splu(b) if self.count else None
        self._dep = a[self.dependent][:, keep].tocsr()
        self._n = keep.size

    def columns(self, start: int, stop: int, drop: float):
        """Stresses ``start:stop`` as the columns of a sparse (m, stop − start) CSC matrix.

        Entries ``<= drop · max|ω|`` are exact zeros (as :func:`rref` does).
        """
        import scipy.sparse as sps

        rows, vals, ptr = [], [], [0]
        rhs = np.zeros(self._n)
        dep = self._dep
        for r in range(start, min(stop, self.count)):
            lo, hi = dep.indptr[r], dep.indptr[r + 1]
            rhs[:] = 0.0
            rhs[dep.indices[lo:hi]] = dep.data[lo:hi]
            y = self._lu.solve(rhs)
            big = max(float(np.abs(y).max()) if y.size else 0.0, 1.0)
            nz = np.flatnonzero(np.abs(y) > drop * big)
            rows.append(np.concatenate([[self.dependent[r]], self.basis[nz]]))
            vals.append(np.concatenate([[1.0], -y[nz]]))
            ptr.append(ptr[-1] + nz.size + 1)
        if not rows:
            return sps.csc_matrix((self.shape[0], 0))
        out = sps.csc_matrix((np.concatenate(vals), np.concatenate(rows), np.array(ptr)),
                             shape=(self.shape[0], len(rows)))
        out.sort_indices()
        return out
