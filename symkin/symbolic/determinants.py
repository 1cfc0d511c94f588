"""Determinants of square matrices of sparse polynomial rows.

Steps 2-3 of :mod:`symkin.symbolic.conditions`, so that no determinant of a large
symbolic matrix is ever expanded: :func:`block_determinant` permutes a square matrix to
block-triangular form (a maximum matching, then strongly connected components), whose
determinant is the product of the diagonal blocks' ones — for the 3-RRR the inputs split
off each leg and leave the platform block — and :func:`laplace_det` expands one block along
its columns with memoised minors (fraction free, sparse), or by Bareiss elimination above
``LAPLACE_ROWS`` rows.
"""
from __future__ import annotations

from symkin.symbolic.time_limit import check_deadline

__all__ = ["LAPLACE_ROWS", "block_determinant", "laplace_det"]

#: diagonal blocks larger than this use Bareiss elimination instead of the memoised expansion
LAPLACE_ROWS = 40


def _perm_sign(perm: list[int]) -> int:
    seen, sign = [False] * len(perm), 1
    for i in range(len(perm)):
        if seen[i]:
            continue
        j, length = i, 0
        while not seen[j]:
            seen[j] = True
            j = perm[j]
            length += 1
        if length % 2 == 0:
            sign = -sign
    return sign


def _matching(rows: list[dict]) -> dict[int, int] | None:
    """Perfect matching row → column of a square structure, or None (structurally singular)."""
    col_of_row: dict[int, int] = {}
    row_of_col: dict[int, int] = {}

    def augment(r, seen) -> bool:
        for c in rows[r]:
            if c in seen:
                continue
            seen.add(c)
            if c not in row_of_col or augment(row_of_col[c], seen):
                row_of_col[c] = r
                col_of_row[r] = c
                return True
        return False

    for r in sorted(range(len(rows)), key=lambda r: len(rows[r])):
        if not augment(r, set()):
            return None
    return col_of_row


def _strong_components(n: int, edges: list[list[int]]) -> list[list[int]]:
    """Tarjan's strongly connected components (emitted in reverse topological order)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    for v in range(n):
        if v not in index:
            visit(v)
    return out


def laplace_det(R, rows: list[dict], cols: list[int]):
    """Determinant of the square sub-matrix (rows × cols, in the given orders), expanded
    along columns with memoised minors; polynomial arithmetic only.

    Parameters
    ----------
    R : sympy.polys.rings.PolyRing
        The ring of the entries.
    rows : list of dict
        Sparse rows ``{column: polynomial}``.
    cols : list of int
        The columns of the sub-matrix, as many as ``rows``.

    Returns
    -------
    sympy.polys.rings.PolyElement
        The determinant (Bareiss elimination above ``LAPLACE_ROWS`` rows).
    """
    n = len(rows)
    if n == 0:
        return R.one
    if n == 1:
        return rows[0].get(cols[0], R.zero)
    if n == 2:
        return rows[0].get(cols[0], R.zero) * rows[1].get(cols[1], R.zero) - \
            rows[0].get(cols[1], R.zero) * rows[1].get(cols[0], R.zero)
    if n > LAPLACE_ROWS:  # memoised expansion may need 2^n minors: fraction-free Bareiss instead
        from sympy.polys.matrices import DomainMatrix

        K = R.to_domain()
        dense = [[r.get(c, R.zero) for c in cols] for r in rows]
        return DomainMatrix(dense, (n, n), K).det()
    # expand sparse columns first (the sign of the column permutation is applied at the end)
    order = sorted(range(n), key=lambda k: sum(1 for r in rows if cols[k] in r))
    sign = _perm_sign(order)
    ordered = [cols[k] for k in order]
    memo: dict[int, object] = {}

    def rec(k: int, used: int):
        if k == n:
            return R.one
        if used in memo:
            return memo[used]
        check_deadline()
        total = R.zero
        c = ordered[k]
        position = 0
        for r in range(n):
            if used >> r & 1:
                continue
            e = rows[r].get(c)
            if e:
                sub = rec(k + 1, used | (1 << r))
                if sub:
                    total = total + e * sub if position % 2 == 0 else total - e * sub
            position += 1
        memo[used] = total
        return total

    d = rec(0, 0)
    return d if sign > 0 else -d


def block_determinant(R, rows: list[dict], ncols: int):
    """``(sign, blocks)`` with ``det = sign · Π det(block)``; ``None`` if structurally singular.

    ``rows`` are ``{column: polynomial}`` dictionaries of a square matrix.  Each block is
    ``(row indices, column indices)``: a diagonal block of the block-triangular form.
    """
    n = len(rows)
    if n != ncols:
        raise ValueError("matrix is not square")
    match = _matching(rows)
    if match is None:
        return None
    row_of_col = {c: r for r, c in match.items()}
    edges = [[row_of_col[c] for c in rows[r] if c != match[r]] for r in range(n)]
    comps = _strong_components(n, edges)
    row_perm = [r for comp in comps for r in comp]
    col_perm = [match[r] for r in row_perm]
    sign = _perm_sign(row_perm) * _perm_sign(col_perm)
    blocks = [(tuple(comp), tuple(match[r] for r in comp)) for comp in comps]
    return sign, blocks

