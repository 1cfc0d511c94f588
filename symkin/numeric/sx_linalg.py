"""Straight-line linear algebra in CasADi ``SX`` for the generated indicator kernel.

Every function here builds an expression graph with no data-dependent control flow
(decisions are ``if_else`` selections), so the result can be wrapped in a
``casadi.Function``, mapped over configurations and generated as C.  Matrices are
passed as SX matrices or as Python lists of SX scalars; structural zeros
(``SX.is_zero()``) are skipped, so the sparsity of the constraint rows of the geometric
matrix (Altuzarra et al. 2004, eq. 1-4) is used without being declared.

Contents
--------
:func:`givens_qr`
    QR by Givens rotations (the motion space, eq. 9, and the DKP values, eq. 12, 16).
:func:`householder_tridiagonal`
    Orthogonal reduction of a symmetric matrix to tridiagonal form.
:func:`charpoly`, :func:`sturm_count`
    ``det(T - xI)`` with two derivatives, and the number of eigenvalues of a tridiagonal
    ``T`` below ``x`` (Sturm sequence = inertia of the LDLᵀ factorisation of ``T - xI``).
:func:`laguerre_steps`
    Laguerre iterations for the real roots of ``det(T - xI)``.
:func:`eigenvalue_above`, :func:`smallest_eigenvalue`
    Certified eigenvalue ``λ_{r0+1}`` (IM indicator ``λ_{F+1}`` of the reduced G, §IV-A),
    with structural zero eigenvalues divided out, and the leaner kernel for ``r0 = 0``.
:func:`det`
    Determinant, closed forms up to 3×3.

Examples
--------
The smallest eigenvalue of a 3×3 symmetric matrix, with its certificate:

>>> import casadi as ca, numpy as np
>>> a = ca.SX.sym("a", 3, 3)
>>> sym = (a + a.T) / 2
>>> diag, off = householder_tridiagonal(sym)
>>> lam, ok = smallest_eigenvalue(diag, off)
>>> f = ca.Function("lmin", [a], [lam, ok])
>>> m = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
>>> value, cert = (float(v) for v in f(m))
>>> bool(abs(value - np.linalg.eigvalsh(m)[0]) <= 1e-14), cert
(True, 1.0)
"""
from __future__ import annotations

from typing import Any, Sequence

import casadi as ca
import numpy as np

__all__ = ["givens_qr", "householder_tridiagonal", "charpoly", "sturm_count", "laguerre_steps",
           "eigenvalue_above", "smallest_eigenvalue", "det", "reciprocal", "root", "CERTIFICATE_WIDTH"]

#: relative accuracy a certificate proves: |λ - value| <= CERTIFICATE_WIDTH·|value|
CERTIFICATE_WIDTH = 1e-12
#: iterations of :func:`eigenvalue_above`: Laguerre with multiplicity-2 trial steps, then plain
PHASES = (4, 3)
#: evaluations of the characteristic polynomial in :func:`smallest_eigenvalue`
ITERATIONS = 6
#: rounding allowed for the reduction to tridiagonal form, in units of ``ε·tr(A)``
ROUNDING = 1.0
_EPS = float(np.finfo(float).eps)


def _zero(x) -> bool:
    return isinstance(x, ca.SX) and x.is_zero()


def root(u):
    """``sqrt(u)`` of a sum of squares ``u >= 0``, with derivative 0 (not 0/0) where ``u == 0``.

    The value is the value of ``sqrt(u)``, bit for bit (``sqrt(0) = 0``).  Where ``u``
    vanishes the derivative of ``sqrt`` is ``du / (2·0) = 0/0 = NaN`` (and a selection
    around it does not help: its derivative is ``0 · NaN``); here the inner selection
    takes the square root of 1 instead, so the derivative is ``0 · du = 0``.  The norm of
    a vector at zero has no derivative; 0 is a subgradient, and it is the derivative along
    every direction in which ``u`` stays 0 (a bar that stays parallel to an axis, e.g. on
    a map slice at constant orientation), where the rest of the computation is smooth.
    CasADi's simplification ``sqrt(u)² = u`` still applies, so later values are unchanged.

    >>> import casadi as ca
    >>> x = ca.SX.sym("x", 2)
    >>> f = ca.Function("f", [x], [ca.jacobian(root(ca.sumsqr(x)), x)])
    >>> f([0.0, 0.0]).full().tolist(), f([3.0, 4.0]).full().tolist()
    ([[0.0, 0.0]], [[0.6, 0.8]])
    """
    nonzero = u != 0
    return ca.if_else(nonzero, ca.sqrt(ca.if_else(nonzero, u, 1)), 0)


def reciprocal(y, at_zero=ca.inf):
    """``1 / y`` as one reciprocal that CasADi keeps (``at_zero`` where ``y == 0``).

    CasADi rewrites ``a * (1 / y)`` as ``a / y``; a selection keeps the reciprocal, so
    several quotients by ``y`` cost one division and multiplications.  The division is
    of 1 where ``y == 0``: the derivative of ``1 / y`` there (``-inf · 0 = NaN``, which a
    selection does not remove: its derivative is ``0 · NaN``) stays finite.
    """
    zero = y == 0
    return ca.if_else(zero, at_zero, 1 / ca.if_else(zero, 1, y))


# ---------------------------------------------------------------------- QR
def givens_qr(cols: list[list[Any]], m: int, pairs: list | None = None) -> tuple[list[list[Any]], list[tuple]]:
    """QR by Givens rotations of the first ``m`` columns of an (n × c) SX array.

    Parameters
    ----------
    cols : list of list of SX
        ``cols[i][j]`` is entry (i, j) (a row-major nested list; not modified).
    m : int
        Columns to triangularise (``m <= n``); the other columns are transformed along.
    pairs : list, optional
        When given, ``(a_kk, a_ik)`` of every rotation is appended to it (the entries whose
        radius is taken: where both vanish the QR is not differentiable, see :func:`root`).

    Returns
    -------
    a : list of list of SX
        ``Qᵀ`` applied to the array: ``R`` (upper triangular, non-negative diagonal) in the
        top ``m`` rows of the first ``m`` columns, zeros below it.
    rotations : list of tuple
        ``(k, i, c, s)`` in the order applied: rows ``k, i`` become ``c·a_k + s·a_i`` and
        ``c·a_i - s·a_k``.  Every rotation has determinant +1, so ``det Q = 1``.

    Notes
    -----
    Rotations skip structural zeros, so the sparsity of the constraint rows is used.  The
    new diagonal entry is set to the rotation's radius ``r = hypot(a_kk, a_ik)`` (the
    value ``c·a_kk + s·a_ik`` has in exact arithmetic): the square roots of a column then
    follow one another without a division in between, and one reciprocal serves ``c`` and
    ``s``.  Two zero entries give the identity rotation.
    """
    n, width = len(cols), len(cols[0]) if cols else 0
    # the rows as SX row vectors: a rotation updates two of them with whole-vector operations
    # (entry by entry the operations of a scalar loop; a pair of zeros gives the zero it was)
    rows = [ca.horzcat(*[ca.SX(x) for x in row]) if width else ca.SX(1, 0) for row in cols]
    rotations = []
    for k in range(m):
        for i in range(k + 1, n):
            b = rows[i][0, k]
            if _zero(b):
                continue
            top = rows[k][0, k]
            if pairs is not None:
                pairs.append((top, b))
            r = root(top * top + b * b)  # finite derivative where both entries vanish
            zero = r == 0  # both entries zero: the identity rotation
            inv = reciprocal(r, 1)
            c = (top + zero) * inv
            s = b * inv
            rotations.append((k, i, c, s))
            tk, ti = rows[k][0, k + 1:], rows[i][0, k + 1:]
            rows[k] = ca.horzcat(rows[k][0, :k], r, c * tk + s * ti)
            rows[i] = ca.horzcat(rows[i][0, :k], ca.SX(0), c * ti - s * tk)
    a = [[row[0, j] for j in range(width)] for row in rows]
    return a, rotations


# ---------------------------------------------------------------------- tridiagonal form
def householder_tridiagonal(sym: ca.SX) -> tuple[list[Any], list[Any]]:
    """Householder reduction of a symmetric SX matrix to tridiagonal form ``T = Hᵀ A H``.

    Parameters
    ----------
    sym : SX (n × n)
        Symmetric (only its lower triangle is read after the first step).

    Returns
    -------
    diag, off : list of SX
        The ``n`` diagonal and ``n - 1`` sub-diagonal entries of ``T`` (same eigenvalues).

    Notes
    -----
    Sums (norms, matrix-vector and inner products) are pairwise (:func:`_pairwise_sum`):
    the same operations as a running sum, half the dependency depth in the generated C.
    """
    n = sym.shape[0]
    m = ca.densify(sym)  # the trailing block still to reduce: rows and columns k..n-1
    diag, off = [], []
    for k in range(n - 2):
        x = [m[i, 0] for i in range(1, n - k)]
        diag.append(m[0, 0])
        nx = ca.sqrt(_pairwise_sum([xi * xi for xi in x]))
        s = ca.if_else(x[0] < 0, -1, 1)
        alpha = -s * nx
        v = [x[0] - alpha] + x[1:]
        vv = _pairwise_sum([vi * vi for vi in v])
        # a zero column (vv == 0, v = 0) needs no reflection: dividing by 1 there gives the same
        # values (every update is a product with v = 0) and a finite derivative (2 / 1e-300 has
        # the derivative -2e300 / 1e-300 = -inf, times 0: NaN)
        beta = 2 / ca.fmax(ca.if_else(vv == 0, 1, vv), 1e-300)
        block = m[1:, 1:]
        size = n - k - 1
        vc = ca.vertcat(*v)
        # p = β·A v, each entry a pairwise sum over its row (the products a_rt·v_t, whole matrices at once)
        p = [beta * t for t in _row_pairwise_sums(block * ca.repmat(vc.T, size, 1))]
        kk = beta / 2 * _pairwise_sum([v[r] * p[r] for r in range(size)])
        w = [p[r] - kk * v[r] for r in range(size)]
        wc = ca.vertcat(*w)
        # the rank-2 update a_rt − v_r w_t − w_r v_t of the upper triangle, mirrored to the lower one
        upd = block - ca.mtimes(vc, wc.T) - ca.mtimes(wc, vc.T)
        m = ca.densify(ca.triu(upd) + ca.triu(upd, False).T)
        off.append(alpha)
    diag += [m[i, i] for i in range(m.shape[0])]
    off += [m[i + 1, i] for i in range(m.shape[0] - 1)]
    return diag, off


def _row_pairwise_sums(prod: ca.SX) -> list:
    """:func:`_pairwise_sum` of every row of the SX matrix ``prod``, as whole-matrix operations.

    The constant zeros are dropped (:func:`casadi.sparsify`), each row's terms moved to its
    first columns in column order, and the columns then added in pairs ``(0, 1), (2, 3), …``
    level by level: a structural zero pads a row's odd term, and ``x + 0`` is ``x`` itself,
    so every row gets the tree (and the values) of :func:`_pairwise_sum` of its terms.
    """
    size = prod.shape[0]
    sparse = ca.sparsify(prod)
    rows, cols = sparse.sparsity().get_triplet()
    order = sorted(range(len(rows)), key=lambda e: (rows[e], cols[e]))
    rank, seen = [0] * len(rows), {}
    for e in order:
        rank[e] = seen.get(rows[e], 0)
        seen[rows[e]] = rank[e] + 1
    width = max(seen.values(), default=0)
    if width == 0:
        return [ca.SX(0) for _ in range(size)]
    perm = sorted(range(len(rows)), key=lambda e: (rank[e], rows[e]))  # column-major order of the packed matrix
    packed = ca.SX(ca.Sparsity.triplet(size, width, [rows[e] for e in perm], [rank[e] for e in perm]),
                   sparse.nz[perm])
    while width > 1:
        even = packed[:, list(range(0, width, 2))]
        odd = packed[:, list(range(1, width, 2))]
        if odd.shape[1] < even.shape[1]:
            odd = ca.horzcat(odd, ca.SX(size, 1))
        packed, width = even + odd, even.shape[1]
    dense = ca.densify(packed)
    return [dense[r, 0] for r in range(size)]


def _pairwise_sum(terms: list):
    """Sum of SX terms as a balanced tree (structural zeros dropped)."""
    terms = [t for t in terms if not _zero(t)]
    if not terms:
        return ca.SX(0)
    while len(terms) > 1:
        terms = [terms[i] + terms[i + 1] if i + 1 < len(terms) else terms[i] for i in range(0, len(terms), 2)]
    return terms[0]


# ---------------------------------------------------------------------- characteristic polynomial
def charpoly(diag: Sequence, off2: Sequence, x) -> tuple[Any, Any, Any]:
    """``p(x) = det(T - xI)`` of a symmetric tridiagonal ``T`` and its first two derivatives.

    ``diag`` holds the diagonal of ``T``, ``off2`` the squares of its off-diagonal; the
    three-term recurrence of the leading minors is differentiated twice.
    """
    p0, p1 = ca.SX(1), diag[0] - x
    d0, d1 = ca.SX(0), ca.SX(-1)
    s0, s1 = ca.SX(0), ca.SX(0)
    for i in range(1, len(diag)):
        t = diag[i] - x
        p2 = t * p1 - off2[i - 1] * p0
        d2 = t * d1 - p1 - off2[i - 1] * d0
        s2 = t * s1 - 2 * d1 - off2[i - 1] * s0
        p0, p1, d0, d1, s0, s1 = p1, p2, d1, d2, s1, s2
    return p1, d1, s1


def _charpoly_count(diag, off2, x):
    """:func:`charpoly` and :func:`sturm_count` at the same ``x`` from one recurrence."""
    p0, p1 = ca.SX(1), diag[0] - x
    d0, d1 = ca.SX(0), ca.SX(-1)
    s0, s1 = ca.SX(0), ca.SX(0)
    count = p1 < 0
    for i in range(1, len(diag)):
        t = diag[i] - x
        p2 = t * p1 - off2[i - 1] * p0
        d2 = t * d1 - p1 - off2[i - 1] * d0
        s2 = t * s1 - 2 * d1 - off2[i - 1] * s0
        count = count + (p2 * p1 < 0)
        p0, p1, d0, d1, s0, s1 = p1, p2, d1, d2, s1, s2
    return p1, d1, s1, count


def sturm_count(diag: Sequence, off2: Sequence, x):
    """Number of eigenvalues of the tridiagonal ``T`` below ``x`` (an SX integer value).

    The sign changes of the leading minors of ``T - xI`` (a Sturm sequence) are the
    negative pivots of its LDLᵀ factorisation: by Sylvester's law of inertia, the number
    of eigenvalues below ``x``.
    """
    p0, p1 = ca.SX(1), diag[0] - x
    count = (p1 < 0)
    for i in range(1, len(diag)):
        p2 = (diag[i] - x) * p1 - off2[i - 1] * p0
        count = count + (p2 * p1 < 0)
        p0, p1 = p1, p2
    return count


def _finite_or(value, fallback):
    """``value`` where finite, else ``fallback`` (``|v| < inf`` is false for inf and NaN)."""
    return ca.if_else(ca.fabs(value) < ca.inf, value, fallback)


def _laguerre(n, x, g, spread, mult, direction):
    """One Laguerre step from ``x`` for a root of multiplicity ``mult`` (``spread = n·h - g²``)."""
    disc = root(ca.fmax((n / mult - 1) * spread, 0))  # finite derivative where clamped
    return _finite_or(x - n / (g - direction * disc), x)  # not finite: stay


def laguerre_steps(diag: Sequence, off2: Sequence, x, mults=(1,), direction=+1, zeros: int = 0) -> list:
    """Laguerre steps for the roots of ``det(T - xI) / x^zeros`` from ``x``, one per multiplicity.

    ``zeros`` known zero roots are divided out (deflated).  ``direction`` is +1 (the step
    to the right) or -1 (to the left), or an SX ±1.  A step that is not finite (``x`` on a
    root) leaves ``x`` unchanged.  For a polynomial with real roots a step of multiplicity
    1 never passes the nearest root in its direction.
    """
    n = len(diag) - zeros
    p, dp, ddp = charpoly(diag, off2, x)
    g = dp / p
    h = g * g - ddp / p
    if zeros:
        g = g - zeros / x
        h = h - zeros / (x * x)
    spread = n * h - g * g
    return [_laguerre(n, x, g, spread, mult, direction) for mult in mults]


# ---------------------------------------------------------------------- eigenvalues
def eigenvalue_above(diag: Sequence, off: Sequence, r0: int, phases: tuple[int, int] = PHASES,
                     width: float = CERTIFICATE_WIDTH) -> tuple[Any, Any]:
    """Eigenvalue ``λ_{r0+1}`` (ascending) of a symmetric tridiagonal matrix, and a 0/1 certificate.

    The ``r0`` smallest eigenvalues are the structural zeros of ``J_e J_eᵀ`` (redundant
    constraint rows); they are divided out of the characteristic polynomial, and
    ``r0 = 0`` asks for the smallest.  Laguerre's iteration from a point between
    ``λ_{r0}`` and ``λ_{r0+1}`` converges monotonically to ``λ_{r0+1}`` and never
    passes it.  Trial steps for a double root (clusters are common: the legs of a
    symmetric mechanism give near-double eigenvalues) are accepted when a Sturm count
    shows they stay below ``λ_{r0+1}``, and otherwise kept as an upper bound when exactly
    one more eigenvalue lies below them; that bound is then refined by left Laguerre
    steps, which converge to the root just below it.

    Returns
    -------
    value : SX
    certified : SX (0 or 1)
        1 when Sturm counts prove that the start lay below ``λ_{r0+1}`` (for ``r0 > 0``)
        and that ``λ_{r0+1}`` lies within a relative ``width`` of ``value``: no more than
        ``r0`` eigenvalues below ``value·(1 - width/2)``, at least ``r0 + 1`` below
        ``value·(1 + width/2)``, the other half of the width covering the rounding of the
        reduction to tridiagonal form (see ``_certificate``).
    """
    n = len(diag)
    off2 = [b * b for b in off]
    trace = sum(diag[1:], diag[0])
    if n == 1:
        return diag[0], ca.SX(1)
    phase1, phase2 = phases
    lo = (-1e-12 if r0 == 0 else 1e-6) * ca.fabs(trace)
    start_ok = sturm_count(diag, off2, lo) == r0
    up = ca.SX(ca.inf)
    have = ca.SX(0)
    for _ in range(phase1):
        r1, r2 = laguerre_steps(diag, off2, lo, (1, 2), +1, r0)
        count = sturm_count(diag, off2, r2)
        inside = ca.logic_and(count == r0 + 1, r2 < up)
        up = ca.if_else(inside, r2, up)
        have = ca.logic_or(have, count == r0 + 1)
        lo = ca.if_else(count == r0, ca.fmax(r1, r2), r1)
    # refine the upper bound from above when there is one, else the lower bound from below
    est = ca.if_else(have, up, lo)
    direction = ca.if_else(have, -1, 1)
    for _ in range(phase2):
        est = laguerre_steps(diag, off2, est, (1,), direction, r0)[0]
    ok = _certificate(diag, off2, est, r0, width, trace)
    if r0:
        ok = ca.logic_and(ok, start_ok)
    return est, ok


def _certificate(diag, off2, est, r0: int, width: float, trace):
    """1 when ``λ_{r0+1}`` of the matrix reduced to ``T`` lies within a relative ``width`` of ``est``.

    Sturm counts prove that ``λ_{r0+1}(T)`` lies within half of that interval
    (``est·(1 ± width/2)``); the other half must cover the rounding of the reduction to
    ``T`` (forming ``J_e J_eᵀ`` and the Householder steps, a backward error of order
    ``ε‖A‖``), allowed for as ``ROUNDING·ε·tr(A)`` (``tr A ≥ ‖A‖₂`` for the PSD
    ``A``).  So nothing is certified when the eigenvalue is too small, relative to the
    matrix, for double precision to resolve it to ``width`` (near increased mobility).
    """
    half = 0.5 * width * ca.fabs(est)
    counts = ca.logic_and(sturm_count(diag, off2, est - half) == r0,
                          sturm_count(diag, off2, est + half) >= r0 + 1)
    return ca.logic_and(counts, ROUNDING * _EPS * ca.fabs(trace) <= half)


def smallest_eigenvalue(diag: Sequence, off: Sequence, iterations: int = ITERATIONS,
                        width: float = CERTIFICATE_WIDTH) -> tuple[Any, Any]:
    """Smallest eigenvalue of a symmetric tridiagonal matrix, and a 0/1 certificate.

    The kernel of the common case ``r0 = 0`` (no redundant constraint row): the IM
    indicator ``λ_{F+1}`` of the reduced G is the smallest eigenvalue of ``J_e J_eᵀ``.

    Each of ``iterations`` evaluations of the characteristic polynomial at a point ``x``
    also yields the Sturm count at ``x`` (the signs of the same leading minors), which
    decides the next point:

    * no eigenvalue below ``x``: ``x`` is a lower bound; the plain Laguerre step to the
      right (which never passes ``λ_1``) is kept as a safe lower bound, and the next point
      is the step for a double root (clusters: the legs of a symmetric mechanism give
      near-double eigenvalues), which may pass ``λ_1``;
    * exactly one below: ``x`` is an upper bound isolating ``λ_1``; the next point is the
      Laguerre step to the left, which converges to ``λ_1`` from above;
    * more than one: the trial passed ``λ_2``; the next point is the safe lower bound.

    Compared with :func:`eigenvalue_above` (``r0 = 0``), no separate Sturm count follows
    each trial step.

    Returns
    -------
    value : SX
    certified : SX (0 or 1)
        1 when Sturm counts prove that ``λ_1`` lies within a relative ``width`` of
        ``value`` (the certificate of :func:`eigenvalue_above`): no eigenvalue below
        ``value·(1 - width/2)``, at least one below ``value·(1 + width/2)``, and the
        rounding of the reduction to tridiagonal form within the other half.
    """
    n = len(diag)
    if n == 1:
        return diag[0], ca.SX(1)
    off2 = [b * b for b in off]
    trace = sum(diag[1:], diag[0])
    x = -1e-12 * ca.fabs(trace)  # below λ_1 >= 0 (and below its rounding error)
    safe = x
    for _ in range(iterations):
        p, dp, ddp, count = _charpoly_count(diag, off2, x)
        inv = reciprocal(p)
        g = dp * inv
        spread = n * (g * g - ddp * inv) - g * g
        disc1 = root(ca.fmax((n - 1) * spread, 0))
        disc2 = root(ca.fmax((n / 2 - 1) * spread, 0))
        below = count == 0
        # no eigenvalue below x: the plain step right (safe) and the double-root trial;
        # exactly one: the plain step left; more: back to the safe point
        right1 = _finite_or(x - n / (g - disc1), x)
        trial = _finite_or(x - n / ca.if_else(below, g - disc2, g + disc1), x)
        x = ca.if_else(below, ca.fmax(right1, trial), ca.if_else(count == 1, trial, safe))
        safe = ca.if_else(below, right1, safe)
    return x, _certificate(diag, off2, x, 0, width, trace)


# ---------------------------------------------------------------------- determinant
def det(m: ca.SX) -> ca.SX:
    """Determinant of a square SX matrix: closed forms up to 3×3 (cofactors), else ``casadi.det``."""
    n = m.shape[0]
    if n == 0:
        return ca.SX(1)
    if n == 1:
        return m[0, 0]
    if n == 2:
        return m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    if n == 3:
        return (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
                - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
                + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]))
    return ca.det(m)
