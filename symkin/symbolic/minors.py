"""Conditions from the minors of the velocity equation (paper §III-A, §III-B).

With ``J`` the constraint rows over the ``n`` free coordinates and ``P`` the parameter rows:

* a square ``M = [J; P]`` gives the DKP condition ``det M`` (eq. 12, the determinant of
  Gosselin–Angeles): :func:`determinant_condition`;
* otherwise the condition is the sum of the squares of all maximal minors (Cauchy–Binet:
  ``e_r(G_r) = Σ det(J_{R,C})²`` for IM, eq. 8), zero exactly where every one of them
  vanishes, with the factors common to all minors taken out: :func:`sum_of_squares_condition`.

Each minor is evaluated through its block-triangular form, block determinants cached and
factored once (``_MinorEngine``).
"""
from __future__ import annotations

import itertools
import math
import time
from dataclasses import replace

import sympy as sp
from sympy import QQ

from symkin.errors import SymkinError
from symkin.symbolic.determinants import block_determinant, laplace_det
from symkin.symbolic.factors import Deriver, factorize, merge_factors
from symkin.symbolic.gram import gram_form
from symkin.symbolic.polynomials import free_rows, poly_key
from symkin.symbolic.readable_forms import agree, node_expansion, relative_sign
from symkin.symbolic.results import Condition, Factor
from symkin.symbolic.rows import SymRow
from symkin.symbolic.time_limit import check_deadline

__all__ = ["GRAM_ROWS", "MAX_MINORS", "SUM_TERMS", "determinant_condition", "sum_of_squares_condition"]

#: most maximal minors enumerated for a sum-of-squares condition
MAX_MINORS = 20000
#: largest Gram matrix J Jᵀ expanded for the readable form of a sum of squares (angles)
GRAM_ROWS = 14
#: sums of squares of minors expanded (to recognise a trivial sum) up to about this many terms
SUM_TERMS = 2000


def _node_column_groups(sm) -> list[tuple[int, ...]]:
    cols = {c: k for k, c in enumerate(sm.free)}
    groups = []
    for k in range(len(sm.mechanism.nodes)):
        g = tuple(cols[sm.dim * k + a] for a in range(sm.dim) if sm.dim * k + a in cols)
        if len(g) == sm.dim:
            groups.append(g)
    return groups


class _MinorEngine:
    """Determinants of square sub-matrices through their block-triangular form, cached by block."""

    def __init__(self, deriver: Deriver, poly_rows: list[dict], symrows: list[SymRow] | None = None):
        self.d = deriver
        self.rows = poly_rows
        self.symrows = symrows
        self._blocks: dict[tuple, tuple] = {}

    def block(self, rows_idx: tuple, cols: tuple) -> tuple:
        key = (rows_idx, cols)
        if key not in self._blocks:
            R = self.d.ctx.R
            det = laplace_det(R, [self.rows[r] for r in rows_idx], list(cols))
            if not det:
                self._blocks[key] = (0, [])
            else:
                self._blocks[key] = factorize(det, self.d.library)
                if self.d.ctx.angles and self.symrows is not None and 4 <= len(cols) <= 10:
                    self._node_readable(rows_idx, cols, det, *self._blocks[key])
        return self._blocks[key]

    def _node_readable(self, rows_idx, cols, det, const, factored) -> None:
        """Offer the block's node-by-node Laplace expansion (a sum of products of
        ``sin(α − β)``) as the readable form of its one geometric factor."""
        geo = [(f, m) for f, m in factored if not self.d.classify(f)[2]]
        if len(geo) != 1 or geo[0][1] != 1:
            return
        triv = QQ.to_sympy(const)
        gkey = poly_key(geo[0][0])
        for f, m in factored:
            if poly_key(f) != gkey:
                _, rd, _, _, _ = self.d.classify(f)
                if not rd.is_number:
                    return
                triv *= rd ** m
        sm = self.d.sm
        groups: dict[int, list] = {}
        for c in cols:
            node, axis = divmod(sm.free[c], sm.dim)
            groups.setdefault(node, []).append(axis)
        if any(sorted(a) != list(range(sm.dim)) for a in groups.values()):
            return
        expansion = node_expansion([self.symrows[r] for r in rows_idx], list(groups))
        if expansion is None:
            return
        f = geo[0][0]
        _, readable, _, _, sign = self.d.classify(f)
        relative = relative_sign(self.d.ctx, det, expansion)
        if not relative:
            return
        candidate = sm.substitute_design(relative * sign * expansion / triv)
        if (sp.count_ops(candidate), len(str(candidate))) >= (sp.count_ops(readable), len(str(readable))):
            return
        self.d.set_readable(f, candidate)

    def minor(self, rows_idx: tuple, cols: tuple) -> tuple | None:
        """``(constant, [(factor, mult)])`` of the minor, or None when it vanishes identically."""
        check_deadline()
        colpos = {c: k for k, c in enumerate(cols)}
        sub = [{colpos[c]: p for c, p in self.rows[r].items() if c in colpos} for r in rows_idx]
        bt = block_determinant(self.d.ctx.R, sub, len(cols))
        if bt is None:
            return None
        sign, blocks = bt
        const = QQ(sign)
        found: list = []
        for brows, bcols in blocks:
            c, fl = self.block(tuple(rows_idx[i] for i in brows), tuple(cols[j] for j in bcols))
            if c == 0:
                return None
            const *= c
            found += fl
        return const, merge_factors(found)


def determinant_condition(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    """The determinant of a square velocity equation, block-triangularised and factored.

    Parameters
    ----------
    sm : SymbolicModel
        The model.
    kind : str
        ``"IM"``, ``"DKP-input"`` or ``"DKP-output"``.
    labels : tuple of str
        Kinematic parameters involved (DKP).
    rows : list of SymRow
        Rows of the velocity equation (constraint rows, then parameter rows).
        Square over the free coordinates.
    note : str
        What the zero set contains, in words.
    t0 : float
        ``time.perf_counter()`` at the start of the derivation.

    Returns
    -------
    Condition
        Method ``"determinant"``, with the owners of ``rows``.
    """
    cond = _derive_determinant(sm, kind, labels, rows, note, t0)
    return replace(cond, rows=tuple(r.owner for r in rows))


def _derive_determinant(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    deriver = Deriver(sm, rows)
    _, cols = free_rows(sm, rows)
    poly_rows = [deriver.ctx.row(r, cols) for r in rows]
    deriver.library.add_minor_divisors(poly_rows, _node_column_groups(sm))
    engine = _MinorEngine(deriver, poly_rows, rows)
    result = engine.minor(tuple(range(len(rows))), tuple(range(len(cols))))
    if result is None:
        return Condition(kind, labels, "determinant", sp.Integer(0), (), (), sm.coordinates,
                         time.perf_counter() - t0, "the determinant vanishes identically: "
                         "the condition holds at every configuration", sm)
    const, factored = result
    constant, factors = deriver.finish(const, factored, rows, 1)
    return Condition(kind, labels, "determinant", constant, tuple(factors), (), sm.coordinates,
                     time.perf_counter() - t0, note, sm)


def sum_of_squares_condition(sm, kind, labels, rows: list[SymRow], size: int, note: str,
                             t0: float) -> Condition:
    """``Σ det(M_{R,C})²`` over all ``size × size`` minors (Cauchy–Binet), common factors out.

    Parameters
    ----------
    sm, kind, labels, rows, note, t0
        As for :func:`determinant_condition`; ``rows`` need not be square.
    size : int
        Size of the minors (the rank sought).

    Returns
    -------
    Condition
        Method ``"sum of squared maximal minors"``, with the distinct minors and the owners
        of the rows that touch a free coordinate.

    Raises
    ------
    SymkinError
        When there are more than ``MAX_MINORS`` minors to enumerate.
    """
    live = [r for r in rows if free_rows(sm, [r])[0]]
    cond = _derive_sum_of_squares(sm, kind, labels, rows, size, note, t0)
    return replace(cond, rows=tuple(r.owner for r in live))


def _derive_sum_of_squares(sm, kind, labels, rows: list[SymRow], size: int, note: str,
                           t0: float) -> Condition:
    method = "sum of squared maximal minors"
    deriver = Deriver(sm, rows)
    _, cols = free_rows(sm, rows)
    poly_rows = [deriver.ctx.row(r, cols) for r in rows]
    live = [k for k, r in enumerate(poly_rows) if r]
    n = len(cols)

    def trivial_condition(constant, text):
        return Condition(kind, labels, method, sp.Integer(constant), (), (), sm.coordinates,
                         time.perf_counter() - t0, text, sm)

    if size == 0:
        return trivial_condition(1, "no minor to lose: the condition never holds")
    if len(live) < size or n < size:
        return trivial_condition(0, f"fewer than {size} rows: the condition holds at every configuration")
    count = math.comb(len(live), size) * math.comb(n, size)
    if count > MAX_MINORS:
        raise SymkinError(f"{kind}: {count} maximal minors of size {size} to enumerate (limit {MAX_MINORS}); "
                          "this mechanism is too large for the sum-of-squares form")
    deriver.library.add_minor_divisors(poly_rows, _node_column_groups(sm))
    engine = _MinorEngine(deriver, poly_rows, rows)
    same_rows = len(live) == size
    minors = []  # (row subset, constant, [(factor, multiplicity)])
    for rsub in itertools.combinations(live, size):
        for csub in itertools.combinations(range(n), size):
            m = engine.minor(rsub, csub)
            if m is not None:
                minors.append((rsub, m[0], m[1]))
    if not minors:
        return trivial_condition(0, "every maximal minor vanishes identically: "
                                    "the condition holds at every configuration")
    # factors common to every minor come out squared
    counts = [{poly_key(f): e for f, e in fl} for _, _, fl in minors]
    common = {}
    for f, m in minors[0][2]:
        k = poly_key(f)
        mult = min(c.get(k, 0) for c in counts)
        if mult and not deriver.classify(f)[2]:  # trivial common factors stay in the sum
            common[k] = (f, mult)

    def product(const, fl, readable=False):
        out = QQ.to_sympy(const)
        for f, m in fl:
            expr, rd, _, _, sign = deriver.classify(f)
            out *= (sign * (rd if readable else expr)) ** m
        return out

    terms_expr, terms_readable, polys, distinct = [], [], [], {}
    R = deriver.ctx.R
    for rsub, const, fl in minors:
        rest = [(f, m - common.get(poly_key(f), (None, 0))[1]) for f, m in fl]
        rest = [(f, m) for f, m in rest if m]
        weight = sp.Integer(1)
        if not same_rows:
            weight = sp.Mul(*[sm.substitute_design(rows[i].scale) ** -2 for i in rsub])
        terms_expr.append(weight * product(const, rest) ** 2)
        terms_readable.append(weight * product(const, rest, readable=True) ** 2)
        key = tuple(sorted(poly_key(f) for f, _ in fl))
        if key not in distinct:
            distinct[key] = product(1, fl, readable=True)
        p = R(const)
        for f, m in rest:
            p = p * f ** m
        polys.append(p)
    trivial_sum = None
    if same_rows and sum(len(p) ** 2 for p in polys) <= SUM_TERMS:
        # small enough to expand: a sum that cannot vanish (e.g. cos² + sin²) is a trivial factor
        c, fl = factorize(sum((p ** 2 for p in polys), R.zero), deriver.library)
        if all(deriver.classify(f)[2] for f, _ in fl):
            trivial_sum = (c, fl)
    extra: list[Factor] = []
    if trivial_sum is None:
        const, sum_trivial = QQ(1), []
        readable = sp.Add(*terms_readable)
        if same_rows and not common and deriver.ctx.angles and len(live) <= GRAM_ROWS:
            gram = gram_form(sm, [rows[i] for i in live])
            if gram is not None and agree(sm, gram, sp.Add(*terms_expr)):
                readable = min([gram, readable], key=lambda e: (sp.count_ops(e), len(str(e))))
        extra = [Factor(sp.Add(*terms_expr), 1, readable, False, f"sum of squares of {len(minors)} maximal minors")]
    else:
        const, sum_trivial = trivial_sum
    constant, factors = deriver.finish(const, [(f, 2 * m) for f, m in common.values()] + sum_trivial,
                                       [rows[i] for i in live] if same_rows else [], 2)
    # the sum of squares last, after the common factors
    factors = [f for f in factors if not f.trivial] + extra + [f for f in factors if f.trivial]
    return Condition(kind, labels, method, constant, tuple(factors), tuple(distinct.values()),
                     sm.coordinates, time.perf_counter() - t0, note, sm)

