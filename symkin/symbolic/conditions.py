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

This module holds the entry points :func:`im_condition` and :func:`dkp_condition` (and
re-exports :class:`Condition`, :class:`Factor`, :class:`DerivationTimeout`, ``MAX_MINORS``
and ``FACTOR_TERMS``); the steps live in :mod:`symkin.symbolic.polynomials` (1),
:mod:`symkin.symbolic.determinants` (2-3), :mod:`symkin.symbolic.factors` (4-5),
:mod:`symkin.symbolic.readable_forms` (5), :mod:`symkin.symbolic.minors` (determinant and
sum of squares) and :mod:`symkin.symbolic.gram` (Gram determinant); the result types in
:mod:`symkin.symbolic.results`, the time limits in :mod:`symkin.symbolic.time_limit`.
"""
from __future__ import annotations

import itertools
import math
import time

import numpy as np

from symkin.kinds import Kind
from symkin.errors import SymkinError
from symkin.tolerances import DEFAULT
from symkin.symbolic.factors import FACTOR_TERMS
from symkin.symbolic.gram import gram_condition
from symkin.symbolic.minors import MAX_MINORS, determinant_condition, sum_of_squares_condition
from symkin.symbolic.polynomials import free_rows, independent_constant_rows
from symkin.symbolic.results import Condition, Factor
from symkin.symbolic.rows import SymRow
from symkin.symbolic.time_limit import DerivationTimeout, with_time_limit

__all__ = ["Factor", "Condition", "DerivationTimeout", "im_condition", "dkp_condition", "MAX_MINORS",
           "FACTOR_TERMS"]

#: IM conditions with more maximal minors than this are derived as one Gram determinant
DIRECT_MINORS = 5000


def _independent_rows(sm, rows: list[SymRow]) -> list[SymRow]:
    """Drop constraint rows that depend on others at *every* configuration.

    Links are taken in model order.  A link enforces the distances of all its node pairs;
    its rows are kept greedily (numerically, at the model's configuration) when they add
    rank to its rows kept so far together with the pair rows of node pairs an earlier
    link already enforces.  Both dependencies persist: a body keeps its shape (so a subset
    spanning its rows here spans them everywhere), and a node pair shared by two bodies (a
    revolute pair in space, a bar inside a body) is the same row in both.  Constant rows that
    repeat earlier ones go too (:func:`~symkin.symbolic.polynomials.independent_constant_rows`).
    The velocity equation keeps its solutions, and its maximal minors their common zeros.
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
    return independent_constant_rows(sm, [r for r in rows if id(r) not in dropped])


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
    return with_time_limit(Kind.IM, time_limit, lambda: _im_condition(sm))


def _im_condition(sm) -> Condition:
    t0 = time.perf_counter()
    mech = sm.mechanism
    f = mech.mobility_value
    n = len(sm.free)
    r = max(n - f, 0)
    note = (f"e_{r}(G) = Σ (maximal minors)², the coefficient of λ^{f} of det(λI − G) up to the sign "
            f"(-1)^{r}; zero exactly where L > F = {f}")
    rows, _ = free_rows(sm, list(sm.rows))
    if len(rows) >= r > 0 and math.comb(len(rows), r) * math.comb(n, r) > DIRECT_MINORS:
        reduced = _independent_rows(sm, rows)
        if len(reduced) == r:
            note = (f"det(J Jᵀ) of the velocity equation with each body reduced to independent rows "
                    f"({len(rows) - len(reduced)} dropped); zero exactly where L > F = {f}, but its value is "
                    f"not G's coefficient when rows were dropped")
            if math.comb(n, r) <= DIRECT_MINORS:
                return sum_of_squares_condition(sm, Kind.IM, (), reduced, r, note, t0)
            return gram_condition(sm, Kind.IM, (), reduced, note, t0)
        elif (math.comb(len(rows), r) * math.comb(n, r) > MAX_MINORS >= math.comb(len(reduced), r) * math.comb(n, r)
              and len(independent_constant_rows(sm, rows)) < len(rows)):  # e.g. two pairs holding a node on one fixed axis
            note = (f"e_{r} of the reduced equation's G = Σ (maximal minors)², each body reduced to independent rows "
                    f"and repeated constant rows dropped ({len(rows) - len(reduced)}); zero exactly where L > F = {f}")
            return sum_of_squares_condition(sm, Kind.IM, (), reduced, r, note, t0)
    return sum_of_squares_condition(sm, Kind.IM, (), list(sm.rows), r, note, t0)


def dkp_condition(sm, which: str = "input", time_limit: float | None = None) -> Condition:
    """DKP condition of the inputs or the outputs (§III-B, eqs. 12-16).

    With the parameter rows ``P`` appended to the velocity equation, ``M = [J; P]``: the
    condition is ``det M`` when ``M`` is square, otherwise the sum of squares of its
    ``r + min(F, k)`` minors.  Its zero set is where a motion is left with the parameters
    locked (DKP) and also contains the IM configurations.
    """
    if which not in ("input", "output"):
        raise SymkinError(f"which must be 'input' or 'output', got {which!r}")
    return with_time_limit(f"DKP-{which}", time_limit, lambda: _dkp_condition(sm, which))


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
    kept, _ = free_rows(sm, list(sm.rows))
    if len(kept) > r:  # redundant rows of rigid bodies: an equivalent, square equation
        kept = _independent_rows(sm, kept)
    k = len(prow)
    size = r + min(f, k)
    rows = kept + prow
    kind = Kind.DKP_INPUT if which == "input" else Kind.DKP_OUTPUT
    locked = "inputs" if which == "input" else "outputs"
    if k <= f:
        note = (f"zero where some motion is left with the {locked} locked: DKP-{which} configurations, "
                "and also every IM configuration")
    else:
        note = (f"zero where the {k} {which} rows restricted to the motion space have rank below "
                f"min(L, {k}): DKP-{which} configurations, and IM ones where the {locked} do not fix every motion")
    if len(kept) == r and len(rows) == n == size:
        return determinant_condition(sm, kind, labels, rows, note, t0)
    return sum_of_squares_condition(sm, kind, labels, rows, size, note, t0)
