"""Gram determinants ``det(M Mᵀ)`` of the velocity equation's rows (paper §III-A, eq. 8).

For rows that should be independent (as many as the rank sought), ``det(M Mᵀ)`` is the sum
of the squares of all maximal minors (Cauchy–Binet) in one determinant.  In angle
coordinates its entries are dot products of unit vectors, ``cos(α − β)``.
:func:`gram_form` gives the readable form of a sum of squares; :func:`gram_condition`
derives the IM condition of a large mechanism as one Gram determinant, block-triangularised.
"""
from __future__ import annotations

import time
from dataclasses import replace

import sympy as sp
from sympy import QQ
from sympy.polys.polyerrors import CoercionFailed
from sympy.polys.rings import ring

from symkin.symbolic.determinants import block_determinant, laplace_det
from symkin.symbolic.factors import factorize
from symkin.symbolic.readable_forms import block_dot, square_rewrites
from symkin.symbolic.results import Condition, Factor
from symkin.symbolic.rows import SymRow

__all__ = ["GRAM_TERMS", "gram_condition", "gram_form"]

#: Gram determinants with more terms than this are not offered as readable forms
GRAM_TERMS = 3000


def _gram_matrix(sm, rows: list[SymRow]):
    """The Gram matrix ``P Pᵀ`` of the polynomial rows over the free coordinates, as sparse
    polynomial rows; in angle coordinates its entries are written ``Σ c c' cos(α − β)`` and
    each distinct ``cos``/``sin`` becomes a generator.  Returns ``(ring, rows, back)``."""
    free = set(sm.free)
    dim = sm.dim
    entries = [[sp.Integer(0)] * len(rows) for _ in rows]
    if sm.coordinates == "angles":
        blocks = [{n: t for n, t in r.blocks if dim * n in free} for r in rows]
        for i in range(len(rows)):
            for j in range(i, len(rows)):
                shared = set(blocks[i]) & set(blocks[j])
                e = sp.Add(*[block_dot(blocks[i][n], blocks[j][n]) for n in shared]) if shared else sp.Integer(0)
                entries[i][j] = entries[j][i] = e
    else:
        rowentries = [{c: e for c, e in r.entries(dim).items() if c in free} for r in rows]
        for i in range(len(rows)):
            for j in range(i, len(rows)):
                e = sp.Add(*[rowentries[i][c] * rowentries[j][c] for c in rowentries[i] if c in rowentries[j]])
                entries[i][j] = entries[j][i] = e
    atoms = sorted({a for row in entries for e in row for a in e.atoms(sp.cos, sp.sin)}, key=sp.default_sort_key)
    dummies = [sp.Dummy() for _ in atoms]
    forward = dict(zip(atoms, dummies))
    symbols = sorted({s for row in entries for e in row for s in e.xreplace(forward).free_symbols} - set(dummies),
                     key=lambda s: s.name)
    gens = dummies + symbols or [sp.Dummy("one")]
    R, *_ = ring(gens, QQ)
    prows = [{j: R.from_expr(sp.expand(e.xreplace(forward))) for j, e in enumerate(row) if e != 0}
             for row in entries]
    return R, prows, dict(zip(dummies, atoms))


def gram_form(sm, rows: list[SymRow]) -> sp.Expr | None:
    """``det(P Pᵀ)`` of the polynomial rows in angle coordinates, its entries written as
    ``cos(α − β)`` (dot products of unit vectors), with ``cos²u = 1 − sin²u`` or
    ``sin²u = 1 − cos²u`` where that shortens it: e.g. ``sin²(φ−θ) + sin²(ψ−θ)``.

    Parameters
    ----------
    sm : SymbolicModel
        The model (angle coordinates).
    rows : list of SymRow
        The rows, as many as the rank sought.

    Returns
    -------
    sympy.Expr or None
        The readable Gram determinant, or None when it has more than ``GRAM_TERMS`` terms
        or a coefficient outside ``QQ``.
    """
    try:
        R, prows, back = _gram_matrix(sm, rows)
    except (ValueError, CoercionFailed):  # a coefficient outside QQ (should not happen): no Gram form
        return None
    det = laplace_det(R, prows, list(range(len(rows))))
    if len(det) > GRAM_TERMS:
        return None
    return sm.substitute_design(square_rewrites(det.as_expr().xreplace(back)))


def gram_condition(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    """``det(M Mᵀ)`` of rows that should be independent (as many as the rank sought): the
    sum of squares of all maximal minors in one determinant, block-triangularised.

    Parameters
    ----------
    sm, kind, labels, note, t0
        As for :func:`~symkin.symbolic.minors.determinant_condition`.
    rows : list of SymRow
        Independent rows over the free coordinates, as many as the rank sought.

    Returns
    -------
    Condition
        Method ``"Gram determinant"``, with the owners of ``rows``.
    """
    return replace(_derive_gram(sm, kind, labels, rows, note, t0), rows=tuple(r.owner for r in rows))


def _derive_gram(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    R, prows, back = _gram_matrix(sm, rows)
    bt = block_determinant(R, prows, len(prows))
    method = "Gram determinant"
    if bt is None:
        return Condition(kind, labels, method, sp.Integer(0), (), (), sm.coordinates, time.perf_counter() - t0,
                         "the Gram determinant vanishes identically: the condition holds everywhere", sm)
    sign, blocks = bt
    const = QQ(sign)
    geometric, trivial = [], sp.Integer(1)
    for brows, bcols in blocks:
        det = laplace_det(R, [prows[i] for i in brows], list(bcols))
        if not det:
            return Condition(kind, labels, method, sp.Integer(0), (), (), sm.coordinates,
                             time.perf_counter() - t0, "the Gram determinant vanishes identically", sm)
        c, fl = factorize(det, None)
        const *= c
        for f, m in fl:
            expr = sm.substitute_design(f.as_expr().xreplace(back))
            if expr.is_number or (expr.free_symbols and all(x.is_positive for x in expr.free_symbols)
                                  and f.is_monomial):
                trivial *= expr ** m
                continue
            readable = square_rewrites(expr) if len(f) <= 400 else expr
            if readable.is_number and readable != 0:
                trivial *= readable ** m
                continue
            geometric.append(Factor(expr, m, readable, False, "sum of squares (Gram determinant)"))
    for r in rows:
        trivial *= sm.substitute_design(r.scale) ** -2
    coeff, rest = trivial.as_coeff_Mul()
    constant = QQ.to_sympy(const) * coeff
    factors = list(geometric)
    for base, e in rest.as_powers_dict().items():
        if base.is_number:
            constant *= base ** e
        elif e:
            factors.append(Factor(base, e, base, True, "nonzero"))
    return Condition(kind, labels, method, constant, tuple(factors), (), sm.coordinates,
                     time.perf_counter() - t0, note, sm)

