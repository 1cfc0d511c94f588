"""Readable forms of polynomial factors (step 5 of :mod:`symkin.symbolic.conditions`).

In angle coordinates a factor is a polynomial in ``cos θ, sin θ`` of each angle;
:func:`readable_trig` writes it as the shortest of its finite Fourier series in the angles
(with ``cos 2u = 1 − 2 sin² u`` or ``2 cos² u − 1`` where that helps, :func:`fourier_terms`).
A block's node-by-node Laplace expansion is a sum of products of ``sin(α − β)``
(:func:`node_expansion`); a Gram matrix has ``cos(α − β)`` entries (:func:`block_dot`,
:func:`angle_form`), its determinant shortened by ``cos² u = 1 − sin² u``
(:func:`square_rewrites`).  Hand-made forms are checked at random points
(:func:`relative_sign`, :func:`agree`).
"""
from __future__ import annotations

import itertools
import math
from functools import lru_cache

import sympy as sp
from sympy import QQ

from symkin.symbolic.polynomials import PolyContext
from symkin.symbolic.rows import SymRow

__all__ = ["FOURIER_WORK", "agree", "angle_form", "block_dot", "fourier_terms", "node_expansion",
           "readable_trig", "relative_sign", "square_rewrites"]

#: most monomial expansions spent on the Fourier form of one factor
FOURIER_WORK = 20000


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


def fourier_terms(ctx: PolyContext, p) -> dict:
    """``{(k-vector, other monomial): (re, im)}``: the trig polynomial as Σ c_k e^{i k·a}.

    Parameters
    ----------
    ctx : PolyContext
        The ring of ``p`` (its angles and their ``cos``/``sin`` generators).
    p : sympy.polys.rings.PolyElement
        A polynomial in the ``cos``/``sin`` generators and the other symbols.

    Returns
    -------
    dict
        ``(k, other) → (re, im)``: the complex coefficient of ``e^{i k·a}`` times the
        monomial ``other`` (exponents of ``ctx.other``); zero coefficients left out.
    """
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


def _fourier_expr(ctx: PolyContext, terms: dict, rewrite: dict | None = None) -> sp.Expr:
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


def readable_trig(ctx: PolyContext, p) -> tuple[sp.Expr, bool]:
    """Shortest equal trig form of ``p`` and whether it is free of the angles.

    Candidates: the Fourier series, and the same with each even cosine term rewritten
    through ``cos 2u = 1 − 2 sin²u`` or ``2 cos²u − 1`` (all combinations when there are
    at most 6 such terms), e.g. ``1 − cos(2u)/2 − cos(2v)/2 → sin²u + sin²v``.

    Parameters
    ----------
    ctx : PolyContext
        The ring of ``p``.
    p : sympy.polys.rings.PolyElement
        A polynomial in the ``cos``/``sin`` generators (above ``FOURIER_WORK`` monomial
        expansions it is returned as it is, in ``cos``/``sin`` of the angles).

    Returns
    -------
    readable : sympy.Expr
        The shortest form (design substituted).
    constant : bool
        True when it does not depend on the angles.
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


# ====================================================================== squares of cos and sin
def square_rewrites(expr: sp.Expr) -> sp.Expr:
    """Shortest of ``expr`` with some ``cos²u`` written ``1 − sin²u`` (or ``sin²u`` as ``1 − cos²u``).

    Parameters
    ----------
    expr : sympy.Expr
        An expression in ``cos``/``sin`` of some arguments.

    Returns
    -------
    sympy.Expr
        The shortest candidate (by operation count, then length), expanded; every subset of
        the squared ``cos``/``sin`` is tried when there are at most 8 of them.
    """
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


# ====================================================================== unit vectors
def angle_form(vec) -> tuple[sp.Expr, sp.Expr] | None:
    """``(amplitude, angle)`` with ``vec = amplitude · (cos angle, sin angle)``, when visible.

    Parameters
    ----------
    vec : tuple of sympy.Expr
        A planar vector ``(x, y)``.

    Returns
    -------
    tuple of sympy.Expr or None
        ``(amplitude, angle)``, or None when the vector is zero or not of that form.
    """
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


def block_dot(t1, t2) -> sp.Expr:
    """Dot product of two rows' blocks at one node, as ``Σ c c' r r' cos(α − β)``.

    Parameters
    ----------
    t1, t2 : sequence of (sympy.Expr, tuple)
        The terms ``(coefficient, planar vector)`` of each row at the node
        (:attr:`SymRow.blocks <symkin.symbolic.rows.SymRow.blocks>`).

    Returns
    -------
    sympy.Expr
        The dot product; a pair of vectors not visibly ``r · (cos α, sin α)``
        (:func:`angle_form`) contributes its ``trigsimp``-ed dot product.
    """
    out = []
    for c1, v1 in t1:
        for c2, v2 in t2:
            f1, f2 = angle_form(v1), angle_form(v2)
            if f1 is not None and f2 is not None:
                out.append(c1 * c2 * f1[0] * f2[0] * sp.cos(f1[1] - f2[1]))
            else:
                out.append(c1 * c2 * sp.trigsimp(sp.expand(v1[0] * v2[0] + v1[1] * v2[1])))
    return sp.Add(*out)


def node_expansion(rows: list[SymRow], nodes: list[int]) -> sp.Expr | None:
    """Determinant of the rows over the nodes' coordinates by the generalised Laplace
    expansion along each node's two columns: every 2×2 minor of unit vectors is
    ``sin(β − α)``, so the result is a sum of products of sines (planar angles only).

    Parameters
    ----------
    rows : list of SymRow
        Square: two rows per node.
    nodes : list of int
        Indices of the nodes whose two coordinates are the columns, in column order.

    Returns
    -------
    sympy.Expr or None
        The determinant, or None when some entry is not visibly ``c · (cos α, sin α)``.
    """
    blocks = [dict(r.blocks) for r in rows]
    forms = []
    for b in blocks:
        fb = {}
        for n, terms in b.items():
            fl = []
            for c, v in terms:
                af = angle_form(v)
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


# ====================================================================== guards on hand-made forms
def relative_sign(ctx: PolyContext, p, expr: sp.Expr, trials: int = 3) -> int:
    """``+1`` / ``−1`` when the polynomial ``p`` (in cos/sin generators) equals ``±expr`` at
    random angles, ``0`` otherwise (a guard on hand-made readable forms).

    Parameters
    ----------
    ctx : PolyContext
        The ring of ``p``.
    p : sympy.polys.rings.PolyElement
        The polynomial.
    expr : sympy.Expr
        The candidate form, in the angles and the other symbols of ``ctx``.
    trials : int
        Random points tried (fixed seed).

    Returns
    -------
    int
        ``1``, ``-1`` or ``0``.
    """
    import random

    rnd = random.Random(12345)
    sign = 0
    for _ in range(trials):
        vals = {a: rnd.uniform(-3, 3) for a in ctx.angles}
        vals.update({s: rnd.uniform(0.5, 2) for s in ctx.other})
        point = []
        for g in ctx.gens:
            f = ctx.back.get(g)
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


def agree(sm, a: sp.Expr, b: sp.Expr, trials: int = 2) -> bool:
    """``a`` and ``b`` agree at random values of the model's symbols (a guard on rewritten forms).

    Parameters
    ----------
    sm : SymbolicModel
        The model the expressions belong to.
    a, b : sympy.Expr
        The expressions; positive symbols are drawn in ``[0.5, 2]``, others in ``[-3, 3]``.
    trials : int
        Random points tried (fixed seed).

    Returns
    -------
    bool
        True when they agree to ``1e-9`` at every point; False also when they cannot be
        evaluated (too big, or singular there).
    """
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
