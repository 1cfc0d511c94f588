"""Factoring polynomials and classifying their factors.

Steps 4-5 of :mod:`symkin.symbolic.conditions`: each block determinant is factored by :func:`factorize`: trial division by a library of
known geometric factors (parallel links, concurrent link lines, minors at a node, squared
lengths), a gcd split when it is linear in some generator, ``factor_list`` on what remains.
:class:`Deriver` classifies the factors as *trivial* (nonzero constants, lengths,
``cos² + sin²``, squared lengths, row scales) or *geometric*, each with a readable form
(:mod:`symkin.symbolic.readable_forms`) and its meaning when recognised.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import sympy as sp
from sympy import QQ
from sympy.polys.rings import ring

from symkin.symbolic.determinants import laplace_det
from symkin.symbolic.polynomials import PolyContext, poly_key, scale_factors
from symkin.symbolic.readable_forms import readable_trig
from symkin.symbolic.results import Factor
from symkin.symbolic.rows import SymRow

__all__ = ["FACTOR_TERMS", "MAX_LINES", "Deriver", "factorize", "merge_factors"]

#: polynomials with more terms than this are not handed to ``factor_list`` (trial division only)
FACTOR_TERMS = 400
#: most link lines whose triples are tried as concurrent-lines factors (nodal coordinates)
MAX_LINES = 15


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

    def __init__(self, ctx: PolyContext):
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
                    self.known.pop(poly_key(ctx.from_expr_symbolic(cross).monic()), None)
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
        for base, owner in scale_factors(sm):  # nonzero wherever the rows are defined
            if base.free_symbols <= set(ctx.gens):
                self._add(ctx.from_expr_symbolic(base), base, f"a factor of the scale of {owner}", True)

    def _add(self, p, readable, meaning, trivial) -> None:
        if not p or p.is_ground:
            return
        m = p.monic()
        k = poly_key(m)
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
                d = laplace_det(self.ctx.R, list(combo), list(node_cols))
                if d and not d.is_ground:
                    for f, _ in _cheap_factors(d):
                        self._add(f, None, "", False)

    def lookup(self, p) -> _Known | None:
        return self.known.get(poly_key(p.monic()))


def _support(p) -> frozenset:
    """Indices of the generators a polynomial uses."""
    return frozenset(i for m in p.itermonoms() for i, e in enumerate(m) if e)


def _cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


# ====================================================================== factoring
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


def factorize(p, library: _Library | None) -> tuple[object, list]:
    """``(constant, [(monic factor, multiplicity), ...])`` of a nonzero polynomial.

    Parameters
    ----------
    p : sympy.polys.rings.PolyElement
        A nonzero polynomial.
    library : _Library or None
        Known factors tried by trial division first (the library of a :class:`Deriver`),
        used only when ``p`` has more than ``FACTOR_TERMS`` terms and is linear in no
        generator; None for none.

    Returns
    -------
    constant : QQ
        The constant factor.
    factors : list of (PolyElement, int)
        Distinct monic factors with their multiplicities: the library's in its order,
        then those of ``factor_list``.
    """
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
    return const, merge_factors(found)


def merge_factors(factors) -> list:
    """Equal factors merged, their multiplicities added.

    Parameters
    ----------
    factors : iterable of (PolyElement, int)
        Monic factors with multiplicities; equal factors may repeat.

    Returns
    -------
    list of (PolyElement, int)
        One pair per distinct factor (the first one met), in order of first appearance.
    """
    merged: dict[tuple, list] = {}
    for f, m in factors:
        k = poly_key(f)
        if k in merged:
            merged[k][1] += m
        else:
            merged[k] = [f, m]
    return [(f, m) for f, m in merged.values()]


# ====================================================================== classification of factors
class Deriver:
    """Shared machinery of one condition: context, library, factor classification.

    Parameters
    ----------
    sm : SymbolicModel
        The model.
    rows : list of SymRow
        The rows of the condition (the model's constraint rows are always included in the ring).

    Attributes
    ----------
    ctx : PolyContext
        The polynomial ring of the rows.
    library : _Library
        Known geometric factors of the model, trial divisors of :func:`factorize`.
    """

    def __init__(self, sm, rows: list[SymRow]):
        self.sm = sm
        self.ctx = PolyContext(sm, list(sm.rows) + [r for r in rows if r not in sm.rows])
        self.library = _Library(self.ctx)
        self._info: dict[tuple, tuple] = {}

    def classify(self, f) -> tuple[sp.Expr, sp.Expr, bool, str, int]:
        """``(expr, readable, trivial, meaning, sign)`` of a monic factor ``f``.

        ``readable`` equals ``expr``; both are negated (``sign = −1``) when that removes a
        leading minus sign from the readable form.
        """
        k = poly_key(f)
        if k in self._info:
            return self._info[k]
        ctx = self.ctx
        expr = ctx.to_expr(f)
        known = self.library.lookup(f)
        meaning = known.meaning if known and known.meaning else ""
        trivial = bool(known.trivial) if known else False
        readable = expr
        if ctx.angles:
            readable, constant = readable_trig(ctx, f)
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

    def set_readable(self, f, readable: sp.Expr) -> None:
        """Replace the readable form of the classified factor ``f`` by an equal, shorter one."""
        k = poly_key(f)
        info = self._info[k]
        self._info[k] = (info[0], readable, info[2], info[3], info[4])

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

