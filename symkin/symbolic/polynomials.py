"""Rows of a symbolic model as sparse polynomials (step 1 of :mod:`symkin.symbolic.conditions`).

Every row of the velocity equation is a polynomial row divided by a nonzero scale
(:mod:`symkin.symbolic.rows`).  :class:`PolyContext` maps the polynomial parts into one
sympy sparse polynomial ring over ``QQ`` — in angle coordinates the polynomials are in
``cos θ, sin θ`` of each angle, used as independent generators — and back to sympy
expressions; :func:`free_rows` keeps the rows that touch the free coordinates,
:func:`independent_constant_rows` drops the constant rows that repeat others everywhere,
:func:`scale_factors` gives the polynomial factors of the row scales (nonzero wherever the
rows are defined) and :func:`poly_key` makes monic polynomials hashable.
"""
from __future__ import annotations

import sympy as sp
from sympy import QQ
from sympy.polys.rings import ring

from symkin.symbolic.rows import SymRow
from symkin.symbolic.time_limit import check_deadline

__all__ = ["PolyContext", "free_rows", "independent_constant_rows", "poly_key", "scale_factors"]


def poly_key(p) -> tuple:
    """Hashable key of a monic polynomial.

    Parameters
    ----------
    p : sympy.polys.rings.PolyElement
        A polynomial, usually monic (equal monic factors get equal keys).

    Returns
    -------
    tuple
        Its terms, sorted.
    """
    return tuple(sorted(p.terms()))


class PolyContext:
    """Polynomial ring of one symbolic model: rows as sparse polynomials, back to sympy.

    In angle coordinates each angle ``a`` becomes two generators ``cos a`` and ``sin a``
    (plain dummies); the relation ``cos² + sin² = 1`` is used only when reading factors
    (Fourier form), never during elimination, so every step is exact polynomial algebra.

    Parameters
    ----------
    sm : SymbolicModel
        The model whose symbols (design substituted unless kept symbolic) make the ring.
    rows : list of SymRow
        Rows whose entries are converted up front; others are converted on demand.

    Attributes
    ----------
    R : sympy.polys.rings.PolyRing
        The ring over ``QQ``: ``cos``/``sin`` generators of each angle first, then the
        other symbols (``other``) by name.
    angles : list of sympy.Symbol
        The angle coordinates (empty in nodal coordinates).
    back : dict
        Each ``cos``/``sin`` generator → ``cos(a)`` / ``sin(a)`` of its angle.
    trig_index, other_index
        Positions of each angle's two generators and of the other symbols in ``gens``.
    """

    def __init__(self, sm, rows: list[SymRow]):
        self.sm = sm
        self.angles = list(sm._builder.angle_like) if sm.coordinates == "angles" else []
        self.trig = {a: (sp.Dummy(f"c_{a.name}"), sp.Dummy(f"s_{a.name}")) for a in self.angles}
        self._to_gen = {}
        for a, (c, s) in self.trig.items():
            self._to_gen[sp.cos(a)] = c
            self._to_gen[sp.sin(a)] = s
        self.back = {c: sp.cos(a) for a, (c, s) in self.trig.items()}
        self.back.update({s: sp.sin(a) for a, (c, s) in self.trig.items()})
        entries = list(dict.fromkeys(e for row in rows for e in row.entries(sm.dim).values()))
        trig_gens = [g for a in self.angles for g in self.trig[a]]
        if self.trig:
            converted = {}
            others: set = set()
            for e in entries:
                check_deadline()
                converted[e] = self._prepare(e)
                others |= converted[e].free_symbols
        else:
            converted, others = self._nodal(entries)
        others -= set(trig_gens)
        self.other = sorted(others, key=lambda s: s.name)
        self.gens = trig_gens + self.other
        if not self.gens:
            self.gens = [sp.Dummy("one")]
        self.R, *_ = ring(self.gens, QQ)
        self._cache = {e: (self.R.from_expr(v) if self.trig else v.set_ring(self.R)) for e, v in converted.items()}
        self.trig_index = {a: (self.gens.index(self.trig[a][0]), self.gens.index(self.trig[a][1]))
                           for a in self.angles}
        self.other_index = [self.gens.index(s) for s in self.other]

    @staticmethod
    def _nodal(entries: list) -> tuple[dict, set]:
        """Nodal entries as polynomials, built by sparse ring arithmetic (``ring.from_expr`` of the
        unexpanded entry; ``sympy.expand`` of an entry of degree 11 in 16 symbols, as a pair kind's
        own row can give, does not finish), with the symbols they use.  The ring is the one of every symbol
        written; the symbols that cancel are left out of the returned set, as an expansion would."""
        candidates = sorted(set().union(*(e.free_symbols for e in entries)), key=lambda s: s.name)
        wide, *_ = ring(candidates or [sp.Dummy("one")], QQ)
        converted = {}
        used: set = set()
        for e in entries:
            check_deadline()
            p = wide.from_expr(e)
            converted[e] = p
            used |= {i for m in p.itermonoms() for i, k in enumerate(m) if k}
        return converted, {candidates[i] for i in used} if candidates else set()

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
        return self.sm.substitute_design(p.as_expr().xreplace(self.back))

    def from_expr_symbolic(self, e: sp.Expr):
        return self.R.from_expr(self._prepare(e))


def free_rows(sm, rows: list[SymRow]) -> tuple[list[SymRow], dict[int, int]]:
    """The rows with a nonzero entry over the model's free coordinates.

    Parameters
    ----------
    sm : SymbolicModel
        The model (its ``free`` columns and ``dim``).
    rows : list of SymRow
        Rows of the velocity equation.

    Returns
    -------
    rows : list of SymRow
        The rows that touch a free coordinate, in order.
    cols : dict
        Free column → its position among the free columns.
    """
    cols = {c: k for k, c in enumerate(sm.free)}
    keep = [r for r in rows if any(c in cols and e != 0 for c, e in r.entries(sm.dim).items())]
    return keep, cols


def _free_entries(sm, row: SymRow) -> dict[int, sp.Expr]:
    free = set(sm.free)
    return {c: e for c, e in row.entries(sm.dim).items() if c in free}


def independent_constant_rows(sm, rows: list[SymRow]) -> list[SymRow]:
    """``rows`` without the constant rows that depend on the constant rows kept before them.

    A row is constant when its entries over the free coordinates hold no configuration
    symbol (a slider on a fixed line, or on a line through two fixed nodes given by their
    numbers: :func:`~symkin.symbolic.rows.known_nodes`).  Constant rows are the same at
    every configuration, so a dependency among them holds everywhere: dropping such a row
    keeps the solutions of the velocity equation and the zero set of its maximal minors at
    every configuration.  The rank is exact (sympy, design symbols substituted unless the
    model keeps them, then generic in them).  Two pairs that hold the same nodes on one fixed
    axis repeat rows (four in the screw jack of tests/symbolic/test_helical_conditions.py).

    Parameters
    ----------
    sm : SymbolicModel
        The model (its free coordinates and configuration symbols).
    rows : list of SymRow
        Rows of the velocity equation, in order.

    Returns
    -------
    list of SymRow
        ``rows`` in order, each dependent constant row left out (all of them when none is).
    """
    config = set(sm.config_symbols)
    cols = {c: k for k, c in enumerate(sm.free)}
    kept: list[list] = []
    dropped: set = set()
    for row in rows:
        entries = _free_entries(sm, row)
        if not entries or any(e.free_symbols & config for e in entries.values()):
            continue
        vec = [sp.Integer(0)] * len(cols)
        for c, e in entries.items():
            vec[cols[c]] = sm.substitute_design(e)
        if kept and sp.Matrix(kept + [vec]).rank() == len(kept):
            dropped.add(id(row))
        else:
            kept.append(vec)
    return [r for r in rows if id(r) not in dropped] if dropped else rows


def scale_factors(sm) -> list[tuple[sp.Expr, str]]:
    """The polynomial factors of the constraint rows' scales that depend on the configuration.

    A row is its polynomial part over a scale that is nonzero wherever the row is defined
    (:mod:`symkin.symbolic.rows`); a factor of a condition equal to a factor of a scale is
    therefore never zero on the mechanism (a pair kind's row written over the squared
    distance of an arm from its axis, say, which is constant as the mechanism moves and
    divides the minors in which the row enters).
    Radicals (the norms of a spatial slider's normals) are left out: they are not
    polynomials, and a normal's norm may vanish away from the model's configuration.

    Parameters
    ----------
    sm : SymbolicModel
        The model.

    Returns
    -------
    list of (sympy.Expr, str)
        Each factor, as the scale writes it (so that it cancels against the scale in a
        readable form), with the owner of the first row whose scale holds it.
    """
    config = set(sm.config_symbols)
    out: list[tuple[sp.Expr, str]] = []
    seen: set = set()
    for row in sm.rows:
        for factor in sp.Mul.make_args(row.scale):
            base, exp = factor.as_base_exp()
            if not (exp.is_Integer and exp > 0) or not base.free_symbols & config:
                continue
            key = sp.expand(base)
            if key.is_polynomial(*key.free_symbols) and key not in seen:
                seen.add(key)
                out.append((base, row.owner))
    return out
