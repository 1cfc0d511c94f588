"""Singularity conditions derived from the symbolic velocity equation (paper §III-IV, §VI).

With ``J`` the constraint rows over the ``n`` free coordinates (``G_r = Jᵀ J``), ``F`` the
full-cycle mobility and ``r = n − F``:

* **IM** (§III-A): ``L > F`` ⇔ ``rank J < r`` ⇔ the coefficient of ``λ^F`` in
  ``det(λI − G_r)`` vanishes.  That coefficient is ``(−1)^r e_r(G_r)`` and, by Cauchy–Binet,
  ``e_r(G_r) = Σ det(J_{R,C})²`` over all ``r × r`` minors: the condition is a sum of
  squares, zero exactly where every maximal minor of the velocity equation vanishes.
* **DKP-input / DKP-output** (§III-B, eq. 12): with the ``k`` parameter rows ``P``
  appended, ``M = [J; P]``, the parameters lose independence on the motion space (or the
  mobility rises) exactly where ``rank M < r + min(F, k)``; when ``M`` is square that is
  ``det M = 0`` (the determinant of Gosselin–Angeles), otherwise all maximal minors vanish.

How it is computed (no determinant of a large symbolic matrix is ever expanded):

1. every row is a polynomial row divided by a nonzero scale (:mod:`symkin.symbolic.rows`);
   the scales are trivial factors and leave the polynomial part (in angle coordinates the
   polynomials are in ``cos θ, sin θ`` of each angle, used as independent generators);
2. a square matrix is permuted to block-triangular form (maximum matching, then strongly
   connected components); its determinant is the product of the diagonal blocks' ones —
   for the 3-RRR the inputs split off each leg and leave the platform block;
3. each block's determinant is expanded along columns with memoised minors (fraction free,
   sparse) in sympy's sparse polynomial ring (Bareiss elimination above 40 rows);
4. each block determinant is factored: trial division by a library of known geometric
   factors (parallel links, concurrent link lines, minors at a node, squared lengths), a
   gcd split when it is linear in some generator, ``factor_list`` on what remains;
5. factors are classified: *trivial* (nonzero constants, lengths, ``cos² + sin²``, squared
   lengths, row scales) or *geometric*; each geometric factor gets a readable form — in
   angle coordinates the shortest of its finite Fourier series in the angles (with
   ``cos 2u = 1 − 2 sin² u`` where that helps) and the node-by-node Laplace expansion of its
   block (a sum of products of ``sin(α − β)``); in nodal coordinates the cross product or
   the determinant of line coordinates it was recognised as.  A sum of squares (IM) reads
   best as ``det(J Jᵀ)`` with ``cos(α − β)`` entries, which is tried too.

Every readable form is checked to equal its factor (by construction or at random points).
"""
from __future__ import annotations

import contextvars
import itertools
import math
import time
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np
import sympy as sp
from sympy import QQ
from sympy.polys.polyerrors import CoercionFailed
from sympy.polys.rings import ring

from symkin.errors import SymkinError
from symkin.tolerances import DEFAULT
from symkin.symbolic.rows import SymRow

__all__ = ["Factor", "Condition", "DerivationTimeout", "im_condition", "dkp_condition", "MAX_MINORS",
           "FACTOR_TERMS"]

#: most maximal minors enumerated for a sum-of-squares condition
MAX_MINORS = 20000
#: polynomials with more terms than this are not handed to ``factor_list`` (trial division only)
FACTOR_TERMS = 400
#: largest Gram matrix J Jᵀ expanded for the readable form of a sum of squares (angles)
GRAM_ROWS = 14
#: diagonal blocks larger than this use Bareiss elimination instead of the memoised expansion
LAPLACE_ROWS = 40
#: sums of squares of minors expanded (to recognise a trivial sum) up to about this many terms
SUM_TERMS = 2000
#: most monomial expansions spent on the Fourier form of one factor
FOURIER_WORK = 20000
#: Gram determinants with more terms than this are not offered as readable forms
GRAM_TERMS = 3000
#: IM conditions with more maximal minors than this are derived as one Gram determinant
DIRECT_MINORS = 5000
#: most link lines whose triples are tried as concurrent-lines factors (nodal coordinates)
MAX_LINES = 15


_DEADLINE: contextvars.ContextVar = contextvars.ContextVar("symkin_symbolic_deadline", default=None)


class DerivationTimeout(SymkinError):
    """A derivation ran past its time limit (``time_limit=`` of the condition functions)."""


def _check_deadline() -> None:
    deadline = _DEADLINE.get()
    if deadline is not None and time.perf_counter() > deadline[0]:
        raise DerivationTimeout(f"{deadline[1]}: not derived within the time limit of {deadline[2]:g} s "
                                "(this mechanism is large for an exact symbolic derivation)")


# ====================================================================== results
@dataclass(frozen=True)
class Factor:
    """One factor of a condition.

    Attributes
    ----------
    expr : sympy.Expr
        The factor as derived (design parameters substituted unless kept symbolic).
    exponent : int
        Its multiplicity; negative for the scales of the rows (denominators).
    readable : sympy.Expr
        An equal expression that is easier to read, e.g. ``sin(theta_coupler - theta_rocker)``.
    trivial : bool
        True for factors that cannot vanish: nonzero constants, lengths, ``cos² + sin²``,
        squared lengths, row scales.
    meaning : str
        What the factor says, when recognised, e.g. ``"coupler ∥ rocker"``.
    """

    expr: sp.Expr
    exponent: int
    readable: sp.Expr
    trivial: bool
    meaning: str = ""

    def __str__(self) -> str:
        power = "" if self.exponent == 1 else f"**({sp.sstr(self.exponent)})"
        tail = f"   [{self.meaning}]" if self.meaning else ""
        return f"({sp.sstr(self.readable)}){power}{tail}"


@dataclass(frozen=True, eq=False)
class Condition:
    """A singularity condition: the configurations where ``expression`` vanishes.

    Attributes
    ----------
    kind : str
        ``"IM"``, ``"DKP-input"`` or ``"DKP-output"``.
    labels : tuple of str
        Kinematic parameters involved (DKP), e.g. ``("rotation:crank",)``.
    method : str
        ``"determinant"`` (square velocity equation) or ``"sum of squared maximal minors"``.
    constant : sympy.Expr
        Nonzero numeric factor (0 when the condition holds everywhere).
    factors : tuple of Factor
        Trivial and geometric factors; ``expression = constant · Π expr**exponent``.
    minors : tuple of sympy.Expr
        For sums of squares: the distinct nonzero maximal minors, factored (readable forms).
        The condition holds exactly where all of them vanish.
    coordinates : str
        ``"nodes"`` or ``"angles"``.
    seconds : float
        Time the derivation took.
    note : str
        What the zero set contains, in words.
    rows : tuple of str
        Owners of the rows of the velocity equation it was derived from, in order
        (constraint rows as :attr:`SymbolicModel.row_owners`, then parameter labels).
    """

    kind: str
    labels: tuple[str, ...]
    method: str
    constant: sp.Expr
    factors: tuple[Factor, ...]
    minors: tuple[sp.Expr, ...]
    coordinates: str
    seconds: float
    note: str
    model: object = field(repr=False, default=None)
    rows: tuple[str, ...] = ()

    # ---------------------------------------------------------------- views
    @property
    def expression(self) -> sp.Expr:
        """The raw scalar as derived: ``constant · Π factor**exponent``."""
        return self.constant * sp.Mul(*[f.expr ** f.exponent for f in self.factors])

    @property
    def trivial_factors(self) -> tuple[Factor, ...]:
        return tuple(f for f in self.factors if f.trivial)

    @property
    def geometric_factors(self) -> tuple[Factor, ...]:
        return tuple(f for f in self.factors if not f.trivial)

    @property
    def identically_zero(self) -> bool:
        """True when the condition holds at every configuration."""
        return self.constant == 0

    @property
    def never(self) -> bool:
        """True when no configuration satisfies it (no geometric factor)."""
        return self.constant != 0 and not self.geometric_factors

    @property
    def readable(self) -> sp.Expr:
        """Product of the readable geometric factors: the condition is ``readable = 0``."""
        if self.identically_zero:
            return sp.Integer(0)
        return sp.Mul(*[f.readable ** f.exponent for f in self.geometric_factors])

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(sorted(self.expression.free_symbols, key=lambda s: s.name))

    def evaluate(self, values: dict | None = None) -> float:
        """Value of ``expression`` at ``values`` (default: the model's configuration).

        ``values`` maps symbols or their names to numbers (see
        :meth:`SymbolicModel.values_at <symkin.symbolic.model.SymbolicModel.values_at>`).
        """
        return self.model.evaluate(self.expression, values)

    def evaluate_readable(self, values: dict | None = None) -> float:
        """Value of ``readable`` (the geometric factors only) at ``values``."""
        return self.model.evaluate(self.readable, values)

    def evaluate_factors(self, values: dict | None = None) -> list[float]:
        """Values of the geometric factors' readable forms at ``values``."""
        return [self.model.evaluate(f.readable, values) for f in self.geometric_factors]

    def lambdify(self, readable: bool = True):
        """A NumPy function of the model's symbols (in ``model.symbols`` order plus any design
        symbols), vectorised over arrays: handy for plotting a condition over a grid.

        Returns ``(function, symbols)``.
        """
        expr = self.readable if readable else self.expression
        expr = expr.replace(lambda e: isinstance(e, sp.Determinant), lambda e: e.doit())
        expr = self.model.substitute_design(expr)
        syms = list(self.model.symbols)
        return sp.lambdify(syms, expr, modules="numpy"), tuple(syms)

    # ---------------------------------------------------------------- rendering
    def _heading(self) -> str:
        what = {"IM": "IM (L > F)", "DKP-input": "DKP-input", "DKP-output": "DKP-output"}[self.kind]
        if self.labels:
            what += f" [{', '.join(self.labels)}]"
        return what

    def __str__(self) -> str:
        lines = [f"{self._heading()} — {self.method}, derived in {self.seconds:.3g} s"]
        geo = self.geometric_factors
        if self.identically_zero:
            lines.append("  holds at every configuration (the expression is identically 0)")
        elif self.never:
            lines.append("  holds at no configuration (no geometric factor)")
        else:
            if len(geo) > 1:
                lines.append("  holds where any of these factors vanishes:")
            for f in geo:
                power = f"  (power {f.exponent})" if f.exponent != 1 else ""
                tail = f"   [{f.meaning}]" if f.meaning else ""
                lines.append(f"  {sp.sstr(f.readable)} = 0{power}{tail}")
        triv = self.trivial_factors
        if self.constant not in (0, 1) or triv:
            parts = [sp.sstr(self.constant)] if self.constant not in (0, 1) else []
            parts += [f"({sp.sstr(f.readable)})**({sp.sstr(f.exponent)})" if f.exponent != 1
                      else f"({sp.sstr(f.readable)})" for f in triv]
            lines.append(f"  trivial factors (never zero): {' * '.join(parts)}")
        if self.minors:
            lines.append(f"  equivalently: all {len(self.minors)} distinct maximal minors vanish")
        if self.note:
            lines.append(f"  note: {self.note}")
        return "\n".join(lines)

    def latex(self) -> str:
        """LaTeX of the condition: ``readable = 0`` and the trivial factors separated."""
        head = {"IM": r"\mathrm{IM}", "DKP-input": r"\mathrm{DKP}_{\mathrm{in}}",
                "DKP-output": r"\mathrm{DKP}_{\mathrm{out}}"}[self.kind]
        if self.identically_zero:
            return head + r":\; 0 = 0"
        if self.never:
            return head + r":\; \text{never}"
        body = r" \cdot ".join(
            (rf"\left({sp.latex(f.readable)}\right)^{{{f.exponent}}}" if f.exponent != 1
             else (sp.latex(f.readable) if len(self.geometric_factors) == 1
                   else rf"\left({sp.latex(f.readable)}\right)"))
            for f in self.geometric_factors)
        out = head + r":\; " + body + " = 0"
        triv = sp.Mul(*[f.readable ** f.exponent for f in self.trivial_factors]) * self.constant
        if triv != 1:
            out += r"\quad\left(\text{trivial factor } " + sp.latex(triv) + r"\right)"
        return out

    def as_dict(self) -> dict:
        """JSON-ready summary (strings)."""
        return {"kind": self.kind, "labels": list(self.labels), "method": self.method,
                "coordinates": self.coordinates, "seconds": self.seconds,
                "identically_zero": self.identically_zero, "never": self.never,
                "readable": sp.sstr(self.readable), "expression": sp.sstr(self.expression),
                "geometric_factors": [{"readable": sp.sstr(f.readable), "exponent": f.exponent,
                                       "meaning": f.meaning} for f in self.geometric_factors],
                "trivial_factors": [{"readable": sp.sstr(f.readable), "exponent": f.exponent,
                                     "meaning": f.meaning} for f in self.trivial_factors],
                "constant": sp.sstr(self.constant), "minors": [sp.sstr(m) for m in self.minors],
                "note": self.note}


# ====================================================================== polynomial context
def _key(p) -> tuple:
    """Hashable key of a monic polynomial."""
    return tuple(sorted(p.terms()))


class _Context:
    """Polynomial ring of one symbolic model: rows as sparse polynomials, back to sympy.

    In angle coordinates each angle ``a`` becomes two generators ``cos a`` and ``sin a``
    (plain dummies); the relation ``cos² + sin² = 1`` is used only when reading factors
    (Fourier form), never during elimination, so every step is exact polynomial algebra.
    """

    def __init__(self, sm, rows: list[SymRow]):
        self.sm = sm
        self.angles = list(sm._builder.angle_like) if sm.coordinates == "angles" else []
        self.trig = {a: (sp.Dummy(f"c_{a.name}"), sp.Dummy(f"s_{a.name}")) for a in self.angles}
        self._to_gen = {}
        for a, (c, s) in self.trig.items():
            self._to_gen[sp.cos(a)] = c
            self._to_gen[sp.sin(a)] = s
        self._back = {c: sp.cos(a) for a, (c, s) in self.trig.items()}
        self._back.update({s: sp.sin(a) for a, (c, s) in self.trig.items()})
        converted = {}
        others: set = set()
        for row in rows:
            for e in row.entries(sm.dim).values():
                if e not in converted:
                    converted[e] = self._prepare(e)
                    others |= converted[e].free_symbols
        trig_gens = [g for a in self.angles for g in self.trig[a]]
        others -= set(trig_gens)
        self.other = sorted(others, key=lambda s: s.name)
        self.gens = trig_gens + self.other
        if not self.gens:
            self.gens = [sp.Dummy("one")]
        self.R, *_ = ring(self.gens, QQ)
        self._cache = {e: self.R.from_expr(v) for e, v in converted.items()}
        self.trig_index = {a: (self.gens.index(self.trig[a][0]), self.gens.index(self.trig[a][1]))
                           for a in self.angles}
        self.other_index = [self.gens.index(s) for s in self.other]

    def _prepare(self, e: sp.Expr) -> sp.Expr:
        if self.trig:
            e = sp.expand_trig(e).xreplace(self._to_gen)
        return sp.expand(e)

    def poly(self, e: sp.Expr):
        if e not in self._cache:
            self._cache[e] = self.R.from_expr(self._prepare(e))
        return self._cache[e]

    def row(self, row: SymRow, cols: dict[int, int]) -> dict[int, object]:
        """Row as ``{position of column: polynomial}`` over the chosen columns."""
        out = {}
        for col, e in row.entries(self.sm.dim).items():
            if col in cols:
                p = self.poly(e)
                if p:
                    out[cols[col]] = p
        return out

    def to_expr(self, p) -> sp.Expr:
        """Polynomial → sympy expression in the model's symbols (design substituted)."""
        return self.sm.substitute_design(p.as_expr().xreplace(self._back))

    def from_expr_symbolic(self, e: sp.Expr):
        return self.R.from_expr(self._prepare(e))


# ====================================================================== block-triangular determinant
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


def _laplace_det(R, rows: list[dict], cols: list[int]):
    """Determinant of the square sub-matrix (rows × cols, in the given orders), expanded
    along columns with memoised minors; polynomial arithmetic only."""
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
        _check_deadline()
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


# ====================================================================== Fourier form (angles)
@lru_cache(maxsize=None)
def _trig_monomial(p: int, q: int) -> tuple:
    """``cos^p · sin^q`` as ``((k, re, im), ...)``: coefficients of ``e^{ik·a}``."""
    acc: dict[int, list] = {}
    for j in range(p + 1):
        for m in range(q + 1):
            k = (p - 2 * j) + (q - 2 * m)
            coef = math.comb(p, j) * math.comb(q, m) * (-1) ** m
            acc[k] = acc.get(k, 0) + coef
    # divide by 2^p (2i)^q = 2^(p+q) i^q  →  multiply by (-i)^q / 2^(p+q)
    unit = [(1, 0), (0, -1), (-1, 0), (0, 1)][q % 4]
    den = 2 ** (p + q)
    return tuple((k, QQ(v * unit[0], den), QQ(v * unit[1], den)) for k, v in acc.items() if v)


def fourier_terms(ctx: _Context, p) -> dict:
    """``{(k-vector, other monomial): (re, im)}``: the trig polynomial as Σ c_k e^{i k·a}."""
    na = len(ctx.angles)
    acc: dict = {}
    for monom, coeff in p.terms():
        partial = {(0,) * na: (coeff, QQ(0))}
        for ai, a in enumerate(ctx.angles):
            ic, is_ = ctx.trig_index[a]
            pc, ps = monom[ic], monom[is_]
            if pc == 0 and ps == 0:
                continue
            new: dict = {}
            for kv, (re, im) in partial.items():
                for k, r2, i2 in _trig_monomial(pc, ps):
                    key = kv[:ai] + (kv[ai] + k,) + kv[ai + 1:]
                    nr, ni = re * r2 - im * i2, re * i2 + im * r2
                    old = new.get(key)
                    new[key] = (nr, ni) if old is None else (old[0] + nr, old[1] + ni)
            partial = new
        other = tuple(monom[j] for j in ctx.other_index)
        for kv, (re, im) in partial.items():
            key = (kv, other)
            old = acc.get(key)
            acc[key] = (re, im) if old is None else (old[0] + re, old[1] + im)
    return {k: v for k, v in acc.items() if v[0] or v[1]}


def _canonical(kv: tuple) -> tuple[tuple, int]:
    for k in kv:
        if k:
            return (kv, 1) if k > 0 else (tuple(-x for x in kv), -1)
    return kv, 1


def _fourier_expr(ctx: _Context, terms: dict, rewrite: dict | None = None) -> sp.Expr:
    """Real form ``Σ A cos(k·a) + B sin(k·a)`` of Fourier ``terms``.

    ``rewrite`` maps a canonical ``(k, other)`` key with even ``k`` to ``"sin2"`` or
    ``"cos2"``: that term's ``cos(2u)`` is written ``1 − 2 sin²u`` or ``2 cos²u − 1``.
    """
    rewrite = rewrite or {}
    out = []
    done = set()
    for (kv, other) in terms:
        ck, _ = _canonical(kv)
        if (ck, other) in done:
            continue
        done.add((ck, other))
        c = terms.get((ck, other), (QQ(0), QQ(0)))
        mono = sp.Mul(*[s ** e for s, e in zip(ctx.other, other)])
        if not any(ck):
            out.append(QQ.to_sympy(c[0]) * mono)
            continue
        arg = sp.Add(*[k * a for k, a in zip(ck, ctx.angles)])
        a_coef, b_coef = 2 * c[0], -2 * c[1]
        if a_coef:
            how = rewrite.get((ck, other))
            if how:
                half = sp.Add(*[(k // 2) * a for k, a in zip(ck, ctx.angles)])
                cos2 = 1 - 2 * sp.sin(half) ** 2 if how == "sin2" else 2 * sp.cos(half) ** 2 - 1
                out.append(sp.expand(QQ.to_sympy(a_coef) * cos2 * mono))
            else:
                out.append(QQ.to_sympy(a_coef) * sp.cos(arg) * mono)
        if b_coef:
            out.append(QQ.to_sympy(b_coef) * sp.sin(arg) * mono)
    return sp.Add(*out)


def _readable_trig(ctx: _Context, p) -> tuple[sp.Expr, bool]:
    """Shortest equal trig form of ``p`` and whether it is free of the angles.

    Candidates: the Fourier series, and the same with each even cosine term rewritten
    through ``cos 2u = 1 − 2 sin²u`` or ``2 cos²u − 1`` (all combinations when there are
    at most 6 such terms), e.g. ``1 − cos(2u)/2 − cos(2v)/2 → sin²u + sin²v``.
    """
    work = sum(math.prod(m[ic] + m[is_] + 1 for ic, is_ in ctx.trig_index.values()) for m in p.itermonoms())
    if work > FOURIER_WORK:  # too big to expand into a Fourier series: keep the polynomial
        return ctx.to_expr(p), False
    terms = fourier_terms(ctx, p)
    if not terms:
        return sp.Integer(0), True
    constant = all(not any(kv) for kv, _ in terms)
    even = []
    for kv, other in terms:
        ck, _ = _canonical(kv)
        if any(ck) and all(k % 2 == 0 for k in ck) and (ck, other) not in even and terms.get((ck, other), (0, 0))[0]:
            even.append((ck, other))
    candidates = [_fourier_expr(ctx, terms)]
    if even:
        if len(even) <= 6:
            for choice in itertools.product(("sin2", "cos2"), repeat=len(even)):
                candidates.append(_fourier_expr(ctx, terms, dict(zip(even, choice))))
        else:
            for how in ("sin2", "cos2"):
                candidates.append(_fourier_expr(ctx, terms, {k: how for k in even}))
    best = min(candidates, key=lambda e: (sp.count_ops(e), len(str(e))))
    return ctx.sm.substitute_design(best), constant


# ====================================================================== library of known factors
@dataclass
class _Known:
    readable: sp.Expr | None  # equal to the polynomial the entry was made from
    meaning: str
    trivial: bool
    lc: object = 1            # leading coefficient of that polynomial


def _pair_name(link: str, ns: tuple, i: str, j: str) -> str:
    return link if len(ns) == 2 else f"{link} ({i}-{j})"


class _Library:
    """Polynomials with a known geometric meaning, keyed by their monic form."""

    def __init__(self, ctx: _Context):
        self.ctx = ctx
        self.known: dict[tuple, _Known] = {}
        self.divisors: list = []
        self.support: dict[int, frozenset] = {}
        self.degree: dict[int, int] = {}
        sm = ctx.sm
        b = sm._builder
        pairs = []
        for link, ns in sm.mechanism.links:
            for a in range(len(ns)):
                for c in range(a + 1, len(ns)):
                    pairs.append((link, ns, ns[a], ns[c]))
        if sm.coordinates == "angles":
            dirs = []
            for link, ns, i, j in pairs:
                alpha = b.angle(link, i, j)
                dirs.append((alpha, _pair_name(link, ns, i, j)))
            for (a1, n1), (a2, n2) in itertools.combinations(dirs, 2):
                p = ctx.from_expr_symbolic(sp.sin(a2 - a1))
                self._add(p, sp.sin(a2 - a1), f"{n1} ∥ {n2}", False)
        elif sm.dim == 2:
            vecs = []
            for link, ns, i, j in pairs:
                d = b._delta_sym(i, j)
                name = _pair_name(link, ns, i, j)
                vecs.append((d, b.coord[i], name, link))
                sq = d[0] ** 2 + d[1] ** 2
                self._add(ctx.from_expr_symbolic(sq), sm.substitute_design(b.length(link, i, j)) ** 2,
                          f"squared length of {name}", True)
            for (d1, _, n1, l1), (d2, _, n2, l2) in itertools.combinations(vecs, 2):
                cross = d1[0] * d2[1] - d1[1] * d2[0]
                self._add(ctx.from_expr_symbolic(cross), cross, f"{n1} ∥ {n2}", False)
            for link, ns in sm.mechanism.links:  # three nodes of one body in line
                for trio in itertools.combinations(ns, 3):
                    d1, d2 = b._delta_sym(trio[0], trio[1]), b._delta_sym(trio[0], trio[2])
                    cross = d1[0] * d2[1] - d1[1] * d2[0]
                    self.known.pop(_key(ctx.from_expr_symbolic(cross).monic()), None)
                    self._add(ctx.from_expr_symbolic(cross), cross,
                              f"nodes {', '.join(trio)} of {link} in line", False)
            if len(vecs) <= MAX_LINES:
                for trio in itertools.combinations(vecs, 3):
                    if len({t[3] for t in trio}) < 3:
                        continue
                    lines = [[d[0], d[1], p[0] * d[1] - p[1] * d[0]] for d, p, _, _ in trio]
                    det = sp.Matrix(lines).det(method="berkowitz")
                    p = ctx.from_expr_symbolic(det)
                    if p:
                        self._add(p, sp.Determinant(sp.ImmutableMatrix(lines)),
                                  f"lines of {', '.join(t[2] for t in trio)} concurrent (or parallel)", False)
        else:
            for link, ns, i, j in pairs:
                d = b._delta_sym(i, j)
                sq = sp.Add(*[v ** 2 for v in d])
                self._add(ctx.from_expr_symbolic(sq), sm.substitute_design(b.length(link, i, j)) ** 2,
                          f"squared length of {_pair_name(link, ns, i, j)}", True)
            for link, ns in sm.mechanism.links:
                for i in ns:
                    for j, k in itertools.combinations([n for n in ns if n != i], 2):
                        nv = _cross3(b._delta_sym(i, j), b._delta_sym(i, k))
                        sq = sp.Add(*[v ** 2 for v in nv])
                        p = ctx.from_expr_symbolic(sq)
                        if p:
                            self._add(p, sq, f"squared area of {link} ({i}, {j}, {k})", True)

    def _add(self, p, readable, meaning, trivial) -> None:
        if not p or p.is_ground:
            return
        m = p.monic()
        k = _key(m)
        if k not in self.known:
            self.known[k] = _Known(readable, meaning, trivial, p.LC)
            self.divisors.append(m)
            self.support[id(m)] = _support(m)
            self.degree[id(m)] = max(sum(e) for e in m.itermonoms())

    def add_minor_divisors(self, rows: list[dict], row_blocks: list) -> None:
        """Node-block minors of the rows (``dim`` rows touching one node) as trial divisors."""
        sm = self.ctx.sm
        dim = sm.dim
        for node_cols in row_blocks:
            touching = [r for r in rows if any(c in r for c in node_cols)
                        and sum(len(r.get(c, ())) for c in node_cols) <= 12]  # small entries only
            if len(touching) < dim or len(touching) > 8:
                continue
            for combo in itertools.combinations(touching, dim):
                d = _laplace_det(self.ctx.R, list(combo), list(node_cols))
                if d and not d.is_ground:
                    for f, _ in _cheap_factors(d):
                        self._add(f, None, "", False)

    def lookup(self, p) -> _Known | None:
        return self.known.get(_key(p.monic()))


def _support(p) -> frozenset:
    """Indices of the generators a polynomial uses."""
    return frozenset(i for m in p.itermonoms() for i, e in enumerate(m) if e)


def _cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _factor_list(p):
    """``p.factor_list()``, with a shortcut: when ``p = a·x + b`` is linear in a generator
    ``x``, ``p = gcd(a, b) · (p / gcd(a, b))`` and the second factor is irreducible, so only
    the gcd (which does not involve ``x``) is left to factor.  Determinants of velocity
    equations are multilinear in many generators, which makes this the common case."""
    R = p.ring
    if p.is_ground:
        return p.LC, []
    for i in range(R.ngens):
        if p.degree(i) == 1:
            x = R.gens[i]
            g = p.coeff_wrt(x, 1).gcd(p.coeff_wrt(x, 0))
            if g.is_ground:
                return QQ(1), [(p, 1)]
            h = p.exquo(g)
            c, fl = _factor_list(g)
            return c, fl + [(h, 1)]
    if len(p) > FACTOR_TERMS:  # too big for dense factoring: one factor (maybe reducible)
        return QQ(1), [(p, 1)]
    return _factor_list_dense(p)


def _factor_list_dense(p):
    """``p.factor_list()`` in the ring of the generators ``p`` actually uses (sympy's dense
    multivariate factoring slows down with every unused generator)."""
    R = p.ring
    used = [i for i in range(R.ngens) if any(m[i] for m in p.itermonoms())]
    if len(used) == R.ngens or not used:
        return p.factor_list()
    small, *_ = ring([R.symbols[i] for i in used], R.domain)
    c, fl = p.set_ring(small).factor_list()
    return c, [(f.set_ring(R), m) for f, m in fl]


def _cheap_factors(p) -> list:
    """Factors of a small polynomial (``factor_list``), or the polynomial itself."""
    if len(p) <= 60:
        _, fl = _factor_list(p)
        return [(f, m) for f, m in fl if not f.is_ground]
    return [(p, 1)]


def _factorize(p, library: _Library | None) -> tuple[object, list]:
    """``(constant, [(monic factor, multiplicity), ...])`` of a nonzero polynomial."""
    const = p.LC
    q = p.monic()
    found: list = []
    if not q.is_ground and (len(q) <= FACTOR_TERMS or any(q.degree(i) == 1 for i in range(q.ring.ngens))):
        library = None  # factor_list (with its gcd shortcut) finds every factor: no trial division
    if library is not None and not q.is_ground:
        support = _support(q)
        degree = max(sum(m) for m in q.itermonoms())
        for d in library.divisors:
            if q.is_ground:
                break
            if not library.support[id(d)] <= support or library.degree[id(d)] > degree:
                continue
            mult = 0
            while True:
                quot, rem = q.div([d])
                if rem:
                    break
                q = quot[0]
                mult += 1
            if mult:
                found.append((d, mult))
    if not q.is_ground:
        const *= q.LC
        q = q.monic()
        if len(q) <= FACTOR_TERMS or any(q.degree(i) == 1 for i in range(q.ring.ngens)):
            c, fl = _factor_list(q)
            const *= c
            for f, m in fl:
                if not f.is_ground:
                    lc = f.LC
                    const *= lc ** m
                    found.append((f.monic(), m))
        else:
            found.append((q, 1))
    # merge equal factors
    merged: dict[tuple, list] = {}
    for f, m in found:
        k = _key(f)
        if k in merged:
            merged[k][1] += m
        else:
            merged[k] = [f, m]
    return const, [(f, m) for f, m in merged.values()]


# ====================================================================== classification of factors
class _Deriver:
    """Shared machinery of one condition: context, library, factor classification."""

    def __init__(self, sm, rows: list[SymRow]):
        self.sm = sm
        self.ctx = _Context(sm, list(sm.rows) + [r for r in rows if r not in sm.rows])
        self.library = _Library(self.ctx)
        self._info: dict[tuple, tuple] = {}

    def classify(self, f) -> tuple[sp.Expr, sp.Expr, bool, str, int]:
        """``(expr, readable, trivial, meaning, sign)`` of a monic factor ``f``.

        ``readable`` equals ``expr``; both are negated (``sign = −1``) when that removes a
        leading minus sign from the readable form.
        """
        k = _key(f)
        if k in self._info:
            return self._info[k]
        ctx = self.ctx
        expr = ctx.to_expr(f)
        known = self.library.lookup(f)
        meaning = known.meaning if known and known.meaning else ""
        trivial = bool(known.trivial) if known else False
        readable = expr
        if ctx.angles:
            readable, constant = _readable_trig(ctx, f)
            if constant and readable.free_symbols <= self._positive_symbols():
                trivial = True
                meaning = meaning or "nonzero (cos² + sin² = 1)"
        elif known is not None and known.readable is not None:
            # the known form is lc times the monic factor
            readable = self.sm.substitute_design(known.readable)
            if known.lc != 1:
                readable = readable / QQ.to_sympy(known.lc)
        if not trivial and readable.is_number and readable != 0:
            trivial, meaning = True, meaning or "nonzero constant"
        if not trivial and f.is_monomial and all(self.ctx.gens[i] in self._positive_symbols()
                                                 for i, e in enumerate(f.LM) if e):
            trivial, meaning = True, meaning or "product of lengths"
        sign = 1
        if not trivial and readable.could_extract_minus_sign():
            readable, expr, sign = -readable, -expr, -1
        out = (expr, readable, trivial, meaning, sign)
        self._info[k] = out
        return out

    def _positive_symbols(self) -> set:
        return {s for s in self.ctx.other if s.is_positive}

    def _trivial_meanings(self) -> dict:
        b = self.sm._builder
        out = {}
        for link, ns in self.sm.mechanism.links:
            for i, j in itertools.combinations(ns, 2):
                name = _pair_name(link, ns, i, j)
                length = self.sm.substitute_design(b.length(link, i, j))
                if length.is_Pow and length.exp == sp.Rational(1, 2):
                    out[length.base] = f"squared length of {name}"
                else:
                    out[length] = f"length of {name}"
        return out

    def finish(self, const, factored: list, scale_rows: list[SymRow], scale_power: int,
               extra: list[Factor] | None = None) -> tuple[sp.Expr, list[Factor]]:
        """Constant and Factor objects: geometric factors kept apart, trivial ones (with the
        row scales to the power ``−scale_power``) merged by base."""
        constant = QQ.to_sympy(const)
        geometric, trivial = [], sp.Integer(1)
        for f, m in factored:
            expr, readable, triv, meaning, sign = self.classify(f)
            constant *= sign ** m
            if triv:
                trivial *= readable ** m
            else:
                geometric.append(Factor(expr, m, readable, False, meaning))
        for r in scale_rows:
            trivial *= self.sm.substitute_design(r.scale) ** (-scale_power)
        coeff, rest = trivial.as_coeff_Mul()
        constant *= coeff
        meanings = self._trivial_meanings()
        out = list(extra or []) + geometric
        for base, e in rest.as_powers_dict().items():
            if e == 0:
                continue
            if base.is_number:
                constant *= base ** e
                continue
            out.append(Factor(base, e, base, True, meanings.get(base, "nonzero")))
        return constant, out


# ====================================================================== conditions
def _free_rows(sm, rows: list[SymRow]) -> tuple[list[SymRow], dict[int, int]]:
    cols = {c: k for k, c in enumerate(sm.free)}
    keep = [r for r in rows if any(c in cols and e != 0 for c, e in r.entries(sm.dim).items())]
    return keep, cols


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

    def __init__(self, deriver: _Deriver, poly_rows: list[dict], symrows: list[SymRow] | None = None):
        self.d = deriver
        self.rows = poly_rows
        self.symrows = symrows
        self._blocks: dict[tuple, tuple] = {}

    def block(self, rows_idx: tuple, cols: tuple) -> tuple:
        key = (rows_idx, cols)
        if key not in self._blocks:
            R = self.d.ctx.R
            det = _laplace_det(R, [self.rows[r] for r in rows_idx], list(cols))
            if not det:
                self._blocks[key] = (0, [])
            else:
                self._blocks[key] = _factorize(det, self.d.library)
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
        gkey = _key(geo[0][0])
        for f, m in factored:
            if _key(f) != gkey:
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
        expansion = _node_expansion([self.symrows[r] for r in rows_idx], list(groups))
        if expansion is None:
            return
        f = geo[0][0]
        _, readable, _, _, sign = self.d.classify(f)
        relative = _relative_sign(self.d.ctx, det, expansion)
        if not relative:
            return
        candidate = sm.substitute_design(relative * sign * expansion / triv)
        if (sp.count_ops(candidate), len(str(candidate))) >= (sp.count_ops(readable), len(str(readable))):
            return
        info = self.d._info[_key(f)]
        self.d._info[_key(f)] = (info[0], candidate, info[2], info[3], info[4])

    def minor(self, rows_idx: tuple, cols: tuple) -> tuple | None:
        """``(constant, [(factor, mult)])`` of the minor, or None when it vanishes identically."""
        _check_deadline()
        colpos = {c: k for k, c in enumerate(cols)}
        sub = [{colpos[c]: p for c, p in self.rows[r].items() if c in colpos} for r in rows_idx]
        bt = block_determinant(self.d.ctx.R, sub, len(cols))
        if bt is None:
            return None
        sign, blocks = bt
        const = QQ(sign)
        factors: dict[tuple, list] = {}
        for brows, bcols in blocks:
            c, fl = self.block(tuple(rows_idx[i] for i in brows), tuple(cols[j] for j in bcols))
            if c == 0:
                return None
            const *= c
            for f, m in fl:
                k = _key(f)
                if k in factors:
                    factors[k][1] += m
                else:
                    factors[k] = [f, m]
        return const, [(f, m) for f, m in factors.values()]


def _determinant_condition(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    cond = _derive_determinant(sm, kind, labels, rows, note, t0)
    return replace(cond, rows=tuple(r.owner for r in rows))


def _derive_determinant(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    deriver = _Deriver(sm, rows)
    _, cols = _free_rows(sm, rows)
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


def _sum_of_squares_condition(sm, kind, labels, rows: list[SymRow], size: int, note: str,
                              t0: float) -> Condition:
    """``Σ det(M_{R,C})²`` over all ``size × size`` minors (Cauchy–Binet), common factors out."""
    live = [r for r in rows if _free_rows(sm, [r])[0]]
    cond = _derive_sum_of_squares(sm, kind, labels, rows, size, note, t0)
    return replace(cond, rows=tuple(r.owner for r in live))


def _derive_sum_of_squares(sm, kind, labels, rows: list[SymRow], size: int, note: str,
                               t0: float) -> Condition:
    method = "sum of squared maximal minors"
    deriver = _Deriver(sm, rows)
    _, cols = _free_rows(sm, rows)
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
    counts = [{_key(f): e for f, e in fl} for _, _, fl in minors]
    common = {}
    for f, m in minors[0][2]:
        k = _key(f)
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
        rest = [(f, m - common.get(_key(f), (None, 0))[1]) for f, m in fl]
        rest = [(f, m) for f, m in rest if m]
        weight = sp.Integer(1)
        if not same_rows:
            weight = sp.Mul(*[sm.substitute_design(rows[i].scale) ** -2 for i in rsub])
        terms_expr.append(weight * product(const, rest) ** 2)
        terms_readable.append(weight * product(const, rest, readable=True) ** 2)
        key = tuple(sorted(_key(f) for f, _ in fl))
        if key not in distinct:
            distinct[key] = product(1, fl, readable=True)
        p = R(const)
        for f, m in rest:
            p = p * f ** m
        polys.append(p)
    trivial_sum = None
    if same_rows and sum(len(p) ** 2 for p in polys) <= SUM_TERMS:
        # small enough to expand: a sum that cannot vanish (e.g. cos² + sin²) is a trivial factor
        c, fl = _factorize(sum((p ** 2 for p in polys), R.zero), deriver.library)
        if all(deriver.classify(f)[2] for f, _ in fl):
            trivial_sum = (c, fl)
    extra: list[Factor] = []
    if trivial_sum is None:
        const, sum_trivial = QQ(1), []
        readable = sp.Add(*terms_readable)
        if same_rows and not common and deriver.ctx.angles and len(live) <= GRAM_ROWS:
            gram = _gram_form(sm, [rows[i] for i in live])
            if gram is not None and _agree(sm, gram, sp.Add(*terms_expr)):
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


def _node_expansion(rows: list[SymRow], nodes: list[int]) -> sp.Expr | None:
    """Determinant of the rows over the nodes' coordinates by the generalised Laplace
    expansion along each node's two columns: every 2×2 minor of unit vectors is
    ``sin(β − α)``, so the result is a sum of products of sines (planar angles only)."""
    blocks = [dict(r.blocks) for r in rows]
    forms = []
    for b in blocks:
        fb = {}
        for n, terms in b.items():
            fl = []
            for c, v in terms:
                af = _angle_form(v)
                if af is None:
                    return None
                fl.append((c * af[0], af[1]))
            fb[n] = fl
        forms.append(fb)
    n_rows = len(rows)
    memo: dict[tuple, sp.Expr] = {}

    def rec(k: int, used: int) -> sp.Expr:
        if k == len(nodes):
            return sp.Integer(1)
        if (k, used) in memo:
            return memo[(k, used)]
        node = nodes[k]
        free = [r for r in range(n_rows) if not used >> r & 1]
        total = []
        for a in range(len(free)):
            ra = free[a]
            if node not in forms[ra]:
                continue
            for b in range(a + 1, len(free)):
                rb = free[b]
                if node not in forms[rb]:
                    continue
                minor = sp.Add(*[c1 * c2 * sp.sin(t2 - t1) for c1, t1 in forms[ra][node]
                                 for c2, t2 in forms[rb][node]])
                if minor == 0:
                    continue
                sub = rec(k + 1, used | (1 << ra) | (1 << rb))
                if sub == 0:
                    continue
                sign = -1 if (a + b + 1) % 2 else 1
                total.append(sign * minor * sub)
        out = sp.Add(*total)
        memo[(k, used)] = out
        return out

    return rec(0, 0)


def _relative_sign(ctx: _Context, p, expr: sp.Expr, trials: int = 3) -> int:
    """``+1`` / ``−1`` when the polynomial ``p`` (in cos/sin generators) equals ``±expr`` at
    random angles, ``0`` otherwise (a guard on hand-made readable forms)."""
    import random

    rnd = random.Random(12345)
    sign = 0
    for _ in range(trials):
        vals = {a: rnd.uniform(-3, 3) for a in ctx.angles}
        vals.update({s: rnd.uniform(0.5, 2) for s in ctx.other})
        point = []
        for g in ctx.gens:
            f = ctx._back.get(g)
            if f is None:
                point.append(vals.get(g, 1.0))
            else:
                point.append(math.cos(vals[f.args[0]]) if isinstance(f, sp.cos) else math.sin(vals[f.args[0]]))
        pv = float(sum(float(c) * math.prod(x ** e for x, e in zip(point, m)) for m, c in p.terms()))
        ev = float(expr.xreplace({k: sp.Float(v) for k, v in vals.items()}).evalf())
        scale = max(abs(pv), abs(ev), 1e-300)
        if abs(pv - ev) <= 1e-9 * scale:
            s = 1
        elif abs(pv + ev) <= 1e-9 * scale:
            s = -1
        else:
            return 0
        if sign and s != sign:
            return 0
        sign = s
    return sign


def _agree(sm, a: sp.Expr, b: sp.Expr, trials: int = 2) -> bool:
    """``a`` and ``b`` agree at random values of the model's symbols (a guard on rewritten forms)."""
    import random

    rnd = random.Random(271828)
    syms = sorted(a.free_symbols | b.free_symbols, key=lambda s: s.name)
    try:
        fa = sp.lambdify(syms, a, modules="math", cse=True)
        fb = sp.lambdify(syms, b, modules="math", cse=True)
        for _ in range(trials):
            point = [rnd.uniform(0.5, 2.0) if s.is_positive else rnd.uniform(-3.0, 3.0) for s in syms]
            va, vb = float(fa(*point)), float(fb(*point))
            if not math.isclose(va, vb, rel_tol=1e-9, abs_tol=1e-12 * max(1.0, abs(vb))):
                return False
    except (RecursionError, MemoryError, OverflowError, ValueError, ZeroDivisionError):
        return False  # too big or singular to check: do not use the rewritten form
    return True


def _angle_form(vec) -> tuple[sp.Expr, sp.Expr] | None:
    """``(amplitude, angle)`` with ``vec = amplitude · (cos angle, sin angle)``, when visible."""
    x, y = vec
    if x.is_number and y.is_number:
        if x == 0 and y == 0:
            return None
        return sp.sqrt(x ** 2 + y ** 2), sp.atan2(y, x)
    cx, fx = x.as_coeff_Mul()
    cy, fy = y.as_coeff_Mul()
    if isinstance(fx, sp.cos) and isinstance(fy, sp.sin) and fx.args == fy.args and cx == cy:
        return cx, fx.args[0]
    if isinstance(fx, sp.sin) and isinstance(fy, sp.cos) and fx.args == fy.args and cx == -cy:
        return cy, fx.args[0] + sp.pi / 2
    return None


def _block_dot(t1, t2) -> sp.Expr:
    out = []
    for c1, v1 in t1:
        for c2, v2 in t2:
            f1, f2 = _angle_form(v1), _angle_form(v2)
            if f1 is not None and f2 is not None:
                out.append(c1 * c2 * f1[0] * f2[0] * sp.cos(f1[1] - f2[1]))
            else:
                out.append(c1 * c2 * sp.trigsimp(sp.expand(v1[0] * v2[0] + v1[1] * v2[1])))
    return sp.Add(*out)


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
                e = sp.Add(*[_block_dot(blocks[i][n], blocks[j][n]) for n in shared]) if shared else sp.Integer(0)
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


def _square_rewrites(expr: sp.Expr) -> sp.Expr:
    """Shortest of ``expr`` with some ``cos²u`` written ``1 − sin²u`` (or ``sin²u`` as ``1 − cos²u``)."""
    expr = sp.expand(expr)
    squared = sorted({x.base for x in expr.atoms(sp.Pow)
                      if isinstance(x.base, (sp.cos, sp.sin)) and x.exp.is_even and x.exp > 0},
                     key=sp.default_sort_key)

    def swap(e, which):
        def other(base):
            return sp.sin(base.args[0]) if isinstance(base, sp.cos) else sp.cos(base.args[0])
        return sp.expand(e.replace(lambda x: x.is_Pow and x.base in which and x.exp.is_even and x.exp > 0,
                                   lambda x: (1 - other(x.base) ** 2) ** (x.exp // 2)))

    if len(squared) <= 8:
        choices = [set(c) for k in range(len(squared) + 1) for c in itertools.combinations(squared, k)]
    else:
        choices = [set(), {b for b in squared if isinstance(b, sp.cos)}, {b for b in squared if isinstance(b, sp.sin)}]
    candidates = [swap(expr, c) if c else expr for c in choices]
    return min(candidates, key=lambda e: (sp.count_ops(e), len(str(e))))


def _gram_form(sm, rows: list[SymRow]) -> sp.Expr | None:
    """``det(P Pᵀ)`` of the polynomial rows in angle coordinates, its entries written as
    ``cos(α − β)`` (dot products of unit vectors), with ``cos²u = 1 − sin²u`` or
    ``sin²u = 1 − cos²u`` where that shortens it: e.g. ``sin²(φ−θ) + sin²(ψ−θ)``."""
    try:
        R, prows, back = _gram_matrix(sm, rows)
    except (ValueError, CoercionFailed):  # a coefficient outside QQ (should not happen): no Gram form
        return None
    det = _laplace_det(R, prows, list(range(len(rows))))
    if len(det) > GRAM_TERMS:
        return None
    return sm.substitute_design(_square_rewrites(det.as_expr().xreplace(back)))


def _gram_condition(sm, kind, labels, rows: list[SymRow], note: str, t0: float) -> Condition:
    """``det(M Mᵀ)`` of rows that should be independent (as many as the rank sought): the
    sum of squares of all maximal minors in one determinant, block-triangularised."""
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
        det = _laplace_det(R, [prows[i] for i in brows], list(bcols))
        if not det:
            return Condition(kind, labels, method, sp.Integer(0), (), (), sm.coordinates,
                             time.perf_counter() - t0, "the Gram determinant vanishes identically", sm)
        c, fl = _factorize(det, None)
        const *= c
        for f, m in fl:
            expr = sm.substitute_design(f.as_expr().xreplace(back))
            if expr.is_number or (expr.free_symbols and all(x.is_positive for x in expr.free_symbols)
                                  and f.is_monomial):
                trivial *= expr ** m
                continue
            readable = _square_rewrites(expr) if len(f) <= 400 else expr
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


def _independent_rows(sm, rows: list[SymRow]) -> list[SymRow]:
    """Drop constraint rows that depend on others at *every* configuration.

    Links are taken in model order.  A link enforces the distances of all its node pairs;
    its rows are kept greedily (numerically, at the model's configuration) when they add
    rank to its rows kept so far together with the pair rows of node pairs an earlier
    link already enforces.  Both dependencies persist: a body keeps its shape (so a subset
    spanning its rows here spans them everywhere), and a node pair shared by two bodies (a
    revolute pair in space, a bar inside a body) is the same row in both.  The velocity
    equation keeps its solutions, and its maximal minors their common zeros.
    """
    from symkin.numeric.geometric_matrix import constraint_rows

    numeric = constraint_rows(sm.mechanism).matrix
    if numeric.shape[0] != len(sm.rows):
        return rows
    mech = sm.mechanism
    dim = sm.dim
    index = {id(r): k for k, r in enumerate(sm.rows)}
    node = mech.node_index()
    xyz = [np.array(p, dtype=float) for _, p in mech.nodes]
    ncoord = numeric.shape[1]

    def pair_row(a: str, b: str) -> np.ndarray:
        u = xyz[node[b]] - xyz[node[a]]
        u = u / np.linalg.norm(u)
        row = np.zeros(ncoord)
        row[dim * node[a]: dim * node[a] + dim] = u
        row[dim * node[b]: dim * node[b] + dim] = -u
        return row

    def rank(m: np.ndarray) -> int:
        if m.shape[0] == 0:
            return 0
        sv = np.linalg.svd(m, compute_uv=False)
        return int(np.count_nonzero(sv > DEFAULT.rank * max(sv[0], 1e-300)))

    free = np.array([c in set(sm.free) for c in range(ncoord)])
    mine = {id(r) for r in rows}
    enforced: set = set()
    dropped = set()
    for link, ns in mech.links:
        group = [r for r in sm.rows if r.element == link and id(r) in mine]
        shared = [pair_row(a, b) for a, b in itertools.combinations(ns, 2) if frozenset((a, b)) in enforced]
        basis = np.array(shared).reshape(-1, ncoord)[:, free]
        base_rank = rank(basis)
        for r in group:
            trial = np.vstack([basis, numeric[index[id(r)]][free]])
            if rank(trial) > base_rank:
                basis, base_rank = trial, base_rank + 1
            else:
                dropped.add(id(r))
        enforced |= {frozenset(pair) for pair in itertools.combinations(ns, 2)}
    return [r for r in rows if id(r) not in dropped]


def _with_limit(kind: str, time_limit: float | None, fn):
    if time_limit is None:
        return fn()
    token = _DEADLINE.set((time.perf_counter() + float(time_limit), kind, float(time_limit)))
    try:
        return fn()
    finally:
        _DEADLINE.reset(token)


def im_condition(sm, time_limit: float | None = None) -> Condition:
    """The IM condition of a :class:`~symkin.symbolic.model.SymbolicModel` (§III-A, eq. 8).

    Returns ``e_r(G_r)``, the coefficient of ``λ^F`` of ``det(λI − G_r)`` up to the sign
    ``(−1)^r`` (``r = n − F``), as the sum of the squares of the maximal minors of the
    velocity equation (Cauchy–Binet), with the geometric factors common to all minors
    taken out and the row scales separated as trivial factors.  ``Condition.minors`` lists
    the distinct minors: ``L > F`` exactly where all of them vanish.  In angle coordinates
    the readable form is ``det(J Jᵀ)`` written with ``cos(α − β)`` entries and
    ``cos² = 1 − sin²`` where that is shorter.

    Large mechanisms (more than ``DIRECT_MINORS`` minors): the rows of each rigid body are
    first reduced to an independent subset (same solutions, same zero set), then the
    condition is ``det(J Jᵀ)`` of the reduced rows, one Gram determinant; its value is then
    the coefficient of the reduced equation's matrix, not of ``G``'s (the note says so).
    """
    return _with_limit("IM", time_limit, lambda: _im_condition(sm))


def _im_condition(sm) -> Condition:
    t0 = time.perf_counter()
    mech = sm.mechanism
    f = mech.mobility_value
    n = len(sm.free)
    r = max(n - f, 0)
    note = (f"e_{r}(G) = Σ (maximal minors)², the coefficient of λ^{f} of det(λI − G) up to the sign "
            f"(-1)^{r}; zero exactly where L > F = {f}")
    rows, _ = _free_rows(sm, list(sm.rows))
    if len(rows) >= r > 0 and math.comb(len(rows), r) * math.comb(n, r) > DIRECT_MINORS:
        reduced = _independent_rows(sm, rows)
        if len(reduced) == r:
            note = (f"det(J Jᵀ) of the velocity equation with each body reduced to independent rows "
                    f"({len(rows) - len(reduced)} dropped); zero exactly where L > F = {f}, but its value is "
                    f"not G's coefficient when rows were dropped")
            if math.comb(n, r) <= DIRECT_MINORS:
                return _sum_of_squares_condition(sm, "IM", (), reduced, r, note, t0)
            return _gram_condition(sm, "IM", (), reduced, note, t0)
    return _sum_of_squares_condition(sm, "IM", (), list(sm.rows), r, note, t0)


def dkp_condition(sm, which: str = "input", time_limit: float | None = None) -> Condition:
    """DKP condition of the inputs or the outputs (§III-B, eqs. 12-16).

    With the parameter rows ``P`` appended to the velocity equation, ``M = [J; P]``: the
    condition is ``det M`` when ``M`` is square, otherwise the sum of squares of its
    ``r + min(F, k)`` minors.  Its zero set is where a motion is left with the parameters
    locked (DKP) and also contains the IM configurations.
    """
    if which not in ("input", "output"):
        raise SymkinError(f"which must be 'input' or 'output', got {which!r}")
    return _with_limit(f"DKP-{which}", time_limit, lambda: _dkp_condition(sm, which))


def _dkp_condition(sm, which: str) -> Condition:
    t0 = time.perf_counter()
    mech = sm.mechanism
    params = mech.inputs if which == "input" else mech.outputs
    if not params:
        raise SymkinError(f"the model {mech.name!r} declares no {which}s")
    prow = sm._parameter_symrows(params)
    labels = tuple(r.owner for r in prow)
    f = mech.mobility_value
    n = len(sm.free)
    r = max(n - f, 0)
    kept, _ = _free_rows(sm, list(sm.rows))
    if len(kept) > r:  # redundant rows of rigid bodies: an equivalent, square equation
        kept = _independent_rows(sm, kept)
    k = len(prow)
    size = r + min(f, k)
    rows = kept + prow
    kind = "DKP-input" if which == "input" else "DKP-output"
    locked = "inputs" if which == "input" else "outputs"
    if k <= f:
        note = (f"zero where some motion is left with the {locked} locked: DKP-{which} configurations, "
                "and also every IM configuration")
    else:
        note = (f"zero where the {k} {which} rows restricted to the motion space have rank below "
                f"min(L, {k}): DKP-{which} configurations, and IM ones where the {locked} do not fix every motion")
    if len(kept) == r and len(rows) == n == size:
        return _determinant_condition(sm, kind, labels, rows, note, t0)
    return _sum_of_squares_condition(sm, kind, labels, rows, size, note, t0)
