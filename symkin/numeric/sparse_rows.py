"""The constraint rows of a large model as a ``scipy.sparse`` matrix (issue 19).

The rows are those of :mod:`symkin.numeric.geometric_matrix`, built by its own functions:

* a bar (a link of two nodes) and a *simplex* body (at most ``dim + 1`` nodes spanning
  their hull: its pair rows are independent) give the bar rows of eq. A3 / A4, ``+u`` at
  node i and ``−u`` at node j, with the unit vectors of ``geometric_matrix._unit_vectors``;
* a slider gives the rows of ``geometric_matrix._slider_rows`` (a few dense rows,
  converted);
* any other rigid body of k nodes gives **O(k) rows** instead of the k(k − 1)/2 pair rows
  of the paper's form: the pair rows of a frame of ``h + 1`` affinely independent nodes
  (``constraints.body.affine_frame``, ``h`` the dimension of the body's hull) and, for every
  other node m, the ``dim`` rows ``ẋ_m − Σ c_k ẋ_k = 0`` with ``c`` the affine coordinates of
  m on the frame (a rigid velocity field is affine, so this is exact; the same affine
  coordinates as the rigidity rows of ``constraints.body.Body``).  These rows
  are independent (each non-frame node's rows have the identity on its own coordinates),
  ``h(h + 1)/2 + dim·(k − h − 1)`` of them: ``2k − 3`` for a planar body, ``3k − 6`` for a
  spatial body spanning space or a plane, ``3k − 5`` for a rod in space — the rank of the
  pair rows, so the motion space is the same.

The paper's pairwise form stays the dense default for small models
(:func:`~symkin.numeric.geometric_matrix.constraint_rows`).  The two forms have the same
motion space; their self-stresses differ only by stresses *inside* one body, which the
statics excludes as modelling artefacts (:mod:`symkin.analysis.statics`), so the reported
counts agree: the O(k) rows have no internal stress except where fixed nodes make some of
them dependent, and :func:`sparse_constraint_rows` reports those rows (``internal``) for
the statics to set aside.
"""
from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sps

from symkin.errors import ModelError, Problem
from symkin.model.mechanism import AXES, Mechanism
from symkin.constraints import slider_constraints
from symkin.constraints.body import affine_frame
from symkin.numeric.geometric_matrix import _slider_rows, _unit_vectors
from symkin.numeric.linalg import affine_hull, left_null_space
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["SparseRows", "sparse_constraint_rows", "pairwise_row_count", "shared_body_pairs",
           "pivoted_dependent_rows", "LOCAL_PATCH_ROWS", "LocalStresses", "local_stress"]

#: rows of the largest patch on which :func:`local_stress` looks for a local self-stress (a dense
#: SVD of at most this many rows; a planar truss's stress is found on ~30 rows, a spatial one's on ~150)
LOCAL_PATCH_ROWS = 200


@dataclass(frozen=True, eq=False)
class SparseRows:
    """Sparse constraint rows ``J`` (rows × all coordinates, CSR), their owners and labels.

    Attributes
    ----------
    matrix : scipy.sparse.csr_matrix (m, D)
        Dimensionless rows over all nodal velocity components: the pair rows link by link
        (a large-form body's: its frame's), then the large-form bodies' affine rows, then the
        sliders' rows.
    owners : tuple of str
        The owner of each row, as :func:`~symkin.numeric.geometric_matrix.constraint_rows`
        names them (``link coupler (B-C)``, ``slider s1``); a body's affine row is owned by
        ``link <body> (affine <node>.<axis>)``.
    free_index : ndarray of int
        The free coordinates among the D (node-major, as ``geometric_matrix.plan``).
    internal : ndarray of int
        Rows dependent on other rows of their own body once the fixed coordinates are
        removed (a body with fixed nodes): modelling artefacts, left out of the statics.
    """

    matrix: sps.csr_matrix
    owners: tuple[str, ...]
    free_index: np.ndarray
    internal: np.ndarray


def pairwise_row_count(mech: Mechanism) -> int:
    """Number of rows of the paper's pairwise form (k(k − 1)/2 per link of k nodes, plus sliders)."""
    rows = sum(len(ns) * (len(ns) - 1) // 2 for _, ns in mech.links)
    return rows + sum(1 if s.kind == "plane" else mech.dim - 1 for s in mech.sliders)


def shared_body_pairs(mech: Mechanism) -> list[tuple[str, str]]:
    """Pairs of bodies (links of 3+ nodes) sharing two or more nodes (the first three found).

    Two bodies sharing a node pair both keep its distance: in the pairwise form the second
    copy of the pair's row is an artefact the statics removes (:mod:`symkin.analysis.statics`);
    in the O(k) form the two bodies' rows carry that stress without a row of its own, so such
    models stay on the dense path (unless both are simplices, whose pair rows are the same).
    """
    bodies_of: dict[str, list[str]] = {}
    for name, ns in mech.links:
        if len(ns) >= 3:
            for n in ns:
                bodies_of.setdefault(n, []).append(name)
    seen, out = set(), []
    for name, ns in mech.links:
        if len(ns) < 3:
            continue
        shared: dict[str, int] = {}
        for n in ns:
            for other in bodies_of[n]:
                if other != name:
                    shared[other] = shared.get(other, 0) + 1
        for other, count in shared.items():
            key = tuple(sorted((name, other)))
            if count >= 2 and key not in seen:
                seen.add(key)
                out.append(key)
                if len(out) >= 3:
                    return out
    return out


def sparse_constraint_rows(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> SparseRows:
    """The constraint rows of ``mech`` in the sparse, O(size) form (see the module docstring).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> from symkin.numeric.geometric_matrix import constraint_rows
    >>> m = get("fourbar_appendix")
    >>> rows = sparse_constraint_rows(m)
    >>> bool((rows.matrix.toarray() == constraint_rows(m).matrix).all())
    True
    """
    dim = mech.dim
    names = mech.node_names
    index = {n: i for i, n in enumerate(names)}
    ncoord = dim * len(names)
    fixed = set(mech.fixed)
    free = np.array([n not in fixed for n in names for _ in range(dim)], dtype=bool)
    pts = [c for _, c in mech.nodes]
    xyz = np.array(pts, dtype=float).reshape(len(pts), dim)

    # ---- every pair row (bars, simplex bodies, the frames of the other bodies)
    pairs, pair_owner = [], []
    pieces = []  # per O(k)-form body: (name, node names, node positions, frame, first and end pair rows)
    internal_groups = []  # (rows, frame nodes) of each O(k)-form body with fixed nodes
    for name, ns in mech.links:
        idx = [index[n] for n in ns]
        if len(idx) == 2:
            pairs.append((idx[0], idx[1]))
            pair_owner.append(f"link {name} ({ns[0]}-{ns[1]})")
            continue
        body = xyz[idx]
        h, _, _ = affine_hull(body, tolerances.geometry)
        if len(idx) <= dim + 1 and h == len(idx) - 1:  # a simplex: its pair rows are independent
            for a in range(len(idx)):
                for b in range(a + 1, len(idx)):
                    pairs.append((idx[a], idx[b]))
                    pair_owner.append(f"link {name} ({ns[a]}-{ns[b]})")
            continue
        frame = affine_frame(body, h)
        start = len(pairs)
        for a in range(len(frame)):
            for b in range(a + 1, len(frame)):
                pairs.append((idx[frame[a]], idx[frame[b]]))
                pair_owner.append(f"link {name} ({ns[frame[a]]}-{ns[frame[b]]})")
        pieces.append((name, ns, idx, frame, start, len(pairs)))

    try:
        vals = _unit_vectors(SimpleNamespace(dim=dim, bar_pairs=pairs), pts)
    except ZeroDivisionError:
        at = [o for (i, j), o in zip(pairs, pair_owner) if tuple(pts[i]) == tuple(pts[j])]
        raise ModelError([Problem(o, "its two nodes coincide (a bar of zero length)") for o in at]) from None
    npair = len(pairs)
    bi = np.array([p[0] for p in pairs], dtype=np.int64)
    bj = np.array([p[1] for p in pairs], dtype=np.int64)
    u = np.array(vals, dtype=float).reshape(npair, dim)
    comps = np.arange(dim)
    rows_i = np.repeat(np.arange(npair), dim)
    r_list = [rows_i, rows_i]
    c_list = [(dim * bi[:, None] + comps).ravel(), (dim * bj[:, None] + comps).ravel()]
    v_list = [u.ravel(), -u.ravel()]
    owners = list(pair_owner)

    # ---- affine rows of each large-form body: ẋ_m − Σ c_k ẋ_k = 0, one row per axis
    nrow = npair
    internal = []
    for name, ns, idx, frame, start, end in pieces:
        others = [m for m in range(len(idx)) if m not in set(frame)]
        if others:
            weights = _affine_weights(xyz[idx], frame, others)
            node_of = np.array([idx[m] for m in others])
            frame_nodes = np.array([idx[k] for k in frame])
            k = len(others)
            row_ids = nrow + np.arange(k * dim).reshape(k, dim)  # row of node m, axis a
            # +1 at (m, a)
            r_list.append(row_ids.ravel())
            c_list.append((dim * node_of[:, None] + comps).ravel())
            v_list.append(np.ones(k * dim))
            # −w_f at (frame node f, a)
            nf = len(frame)
            r_list.append(np.repeat(row_ids[:, :, None], nf, axis=2).ravel())
            c_list.append((dim * frame_nodes[None, None, :] + comps[None, :, None]).repeat(k, axis=0).ravel())
            v_list.append(-np.repeat(weights[:, None, :], dim, axis=1).ravel())
            owners += [f"link {name} (affine {ns[m]}.{AXES[a]})" for m in others for a in range(dim)]
            body_rows = np.concatenate([np.arange(start, end), row_ids.ravel()])
            nrow += k * dim
        else:
            body_rows = np.arange(start, end)
        if any(n in fixed for n in ns):
            internal_groups.append((body_rows, [idx[k] for k in frame]))

    matrix = sps.csr_matrix((np.concatenate(v_list), (np.concatenate(r_list), np.concatenate(c_list))),
                            shape=(nrow, ncoord))
    if slider_constraints(mech):  # the constraints after the links, as the dense rows give them
        sl, sl_owners = _slider_rows(mech, _SliderPlan(dim, ncoord, index), pts)
        matrix = sps.vstack([matrix, sps.csr_matrix(np.array(sl))], format="csr")
        owners += sl_owners
    free_index = np.flatnonzero(free)
    for rows, frame_nodes in internal_groups:
        internal += _dependent_in_body(matrix, rows, frame_nodes, free, dim, tolerances)
    return SparseRows(matrix=matrix, owners=tuple(owners), free_index=free_index,
                      internal=np.array(sorted(internal), dtype=int))


def _affine_weights(body: np.ndarray, frame: list[int], others: list[int]) -> np.ndarray:
    """Affine coordinates (len(others), len(frame)) of the ``others`` nodes of a body on its ``frame``.

    Row m holds the weights on ``frame[0], frame[1], …`` (they sum to 1); least squares on
    the frame's edges, as ``constraints.body.Body`` computes them (here for all nodes at once).
    """
    base = body[frame[0]]
    edges = np.array([body[k] - base for k in frame[1:]]).T.reshape(body.shape[1], len(frame) - 1)
    coef = np.linalg.lstsq(edges, (body[others] - base).T, rcond=None)[0].T if edges.size \
        else np.zeros((len(others), 0))
    return np.hstack([1.0 - coef.sum(axis=1, keepdims=True), coef])


def _SliderPlan(dim: int, ncoord: int, index: dict) -> SimpleNamespace:
    """What ``geometric_matrix._slider_rows`` reads of a plan: dimension, coordinate count, node index."""
    return SimpleNamespace(dim=dim, ncoord=ncoord, index=index)


def _dependent_in_body(matrix, rows: np.ndarray, frame_nodes: list[int], free: np.ndarray, dim: int,
                       tolerances: Tolerances) -> list[int]:
    """Rows of one body (with fixed nodes) that depend on its other rows over the free coordinates.

    A non-frame free node's rows have the identity on its own coordinates, which no other
    row of the body touches: they are independent.  The other rows (the frame's pair rows,
    the affine rows of fixed non-frame nodes) live on the frame nodes' free coordinates
    (at most ``dim·(dim + 1)`` columns): a pivoted QR there
    (:func:`~symkin.numeric.linalg.independent_rows`) keeps an independent set; the rest
    are returned.
    """
    from symkin.numeric.linalg import independent_rows

    cols = np.array([dim * f + a for f in frame_nodes for a in range(dim)])
    cols = cols[free[cols]]
    sub = matrix[rows]
    free_cols = np.flatnonzero(free)
    other = np.setdiff1d(free_cols, cols)
    touches_other = np.asarray(abs(sub[:, other]).sum(axis=1)).ravel() > 0 if other.size else \
        np.zeros(len(rows), bool)
    on_frame = np.asarray(abs(sub[:, cols]).sum(axis=1)).ravel() > 0 if cols.size else np.zeros(len(rows), bool)
    cand = np.flatnonzero(~touches_other & on_frame)
    if cand.size == 0:
        return []
    block = sub[cand][:, cols].toarray()
    keep = set(independent_rows(block, tolerances.rank))
    return [int(rows[c]) for k, c in enumerate(cand) if k not in keep]


def pivoted_dependent_rows(a, guess: np.ndarray, null: np.ndarray) -> np.ndarray:
    """Rows of the sparse ``a`` (m, n) that depend on the others, chosen by partial pivoting (ascending).

    The rank-revealing repair of a first choice ``guess`` of dependent rows (as many as
    ``a`` has dependent rows: ``m − rank``) whose other rows are independent but may be
    ill-conditioned.  ``L = null.shape[1]`` columns on which the right null space ``null``
    (n, L) is nonsingular are dropped (pivoted QR of ``nullᵀ``), leaving ``A`` (m, r) of full
    column rank ``r = rank``.  SuperLU factorises the square ``M = [A | E]`` (``E``: the
    identity columns of the guessed rows; ``M`` is nonsingular iff the rows outside
    ``guess`` are independent), its columns in the order given (``A``'s in a minimum-degree
    order of ``AᵀA``, then ``E``'s: no etree post-order in symmetric mode) with **partial
    pivoting** (``diag_pivot_thresh = 1``): each of ``A``'s columns takes as pivot the row of
    largest magnitude left, so the ``r`` rows pivoted on ``A``'s columns are those of
    Gaussian elimination with partial pivoting on ``A`` — the guess does not enter their
    choice — and the rows pivoted on ``E``'s columns are the dependent ones returned.  The
    multipliers are at most 1, so the basis rows are well-conditioned as far as partial
    pivoting reveals rank; the caller verifies the stresses they give.

    Raises
    ------
    RuntimeError
        From SuperLU, when the rows outside ``guess`` are singular (``M`` is).
    """
    import scipy.sparse.linalg as spla
    from scipy.linalg import qr

    a = sps.csr_matrix(a)
    m, n = a.shape
    guess = np.asarray(guess, dtype=int)
    keep = np.arange(n)
    if null.shape[1]:
        keep = np.setdiff1d(keep, qr(null.T, pivoting=True, mode="r")[1][: null.shape[1]])
    ak = a[:, keep].tocsc()
    r = keep.size
    if r + guess.size != m:
        raise ValueError(f"{guess.size} dependent rows guessed for {m} rows of rank {r}")
    if r:
        g = (ak.T @ ak).tocsc()
        shift = float(abs(g).max()) * np.finfo(float).eps
        order = np.argsort(spla.splu(g + shift * sps.identity(r, format="csc"), permc_spec="MMD_AT_PLUS_A",
                                     diag_pivot_thresh=0.0, options={"SymmetricMode": True}).perm_c)
        ak = ak[:, order]
    e = sps.csc_matrix((np.ones(guess.size), (guess, np.arange(guess.size))), shape=(m, guess.size))
    lu = spla.splu(sps.hstack([ak, e], format="csc"), permc_spec="NATURAL", diag_pivot_thresh=1.0,
                   options={"SymmetricMode": True})
    if not np.array_equal(lu.perm_c, np.arange(m)):  # SuperLU kept the columns' order (no post-order)
        raise RuntimeError("SuperLU reordered the columns")
    return np.flatnonzero(lu.perm_r >= r)


def _gather(indptr: np.ndarray, indices: np.ndarray, sel: np.ndarray) -> np.ndarray:
    """The indices of the compressed rows (or columns) ``sel`` of a CSR (CSC) structure, concatenated."""
    starts, lens = indptr[sel], indptr[sel + 1] - indptr[sel]
    if not lens.sum():
        return np.zeros(0, dtype=indices.dtype)
    offset = np.repeat(starts - (np.cumsum(lens) - lens), lens)
    return indices[offset + np.arange(int(lens.sum()))]


class LocalStresses:
    """Local self-stresses of a sparse ``a`` (m, n) for an ordered list of its dependent rows.

    For the ``k``-th dependent row ``d_k`` the **allowed** rows are all rows but the later
    dependent rows ``d_j`` (``j > k``).  :meth:`stress` grows closed patches around ``d_k``
    in the row–column graph of ``a`` (columns within ``r`` steps of ``d_k``'s, and the allowed
    rows all of whose columns are among them; ``r = 0, 1, 2, …`` while the patch has at most
    ``max_rows`` rows) and returns the first stress found: a left null vector of the patch
    (a dense SVD; singular values ``<= threshold`` count as zero) with ``w_{d_k} = 1``, of
    least norm.  A vector supported on a patch that is null on the patch's columns is null
    on all of ``a``'s (the patch's rows touch no other column), so it is a self-stress of
    ``a``; it is zero on the later dependent rows, so the stresses of ``d_1 … d_m`` have a
    unit lower-triangular matrix of entries on those rows: they are independent.

    Parameters
    ----------
    a : sparse (m, n)
    dependent : ndarray of int
        The dependent rows, in the order that defines the allowed rows.
    threshold : float
        Absolute singular-value threshold (the rank test's ``rank · σ_max`` of ``a``).
    floor : float
        Least norm of the ``d_k`` entries of an orthonormal null basis (the stress's norm is
        at most ``1 / floor``; :attr:`symkin.tolerances.Tolerances.sparse_local`).
    drop : float
        Entries ``<= drop · max|w|`` are exact zeros.
    """

    def __init__(self, a, dependent: np.ndarray, threshold: float, floor: float, drop: float,
                 max_rows: int = LOCAL_PATCH_ROWS):
        a = sps.csr_matrix(a)
        a.sort_indices()
        self._csr, self._csc = a, a.tocsc()
        self._csc.sort_indices()
        self.dependent = np.asarray(dependent, dtype=int)
        self._position = np.full(a.shape[0], -1, dtype=np.int64)
        self._position[self.dependent] = np.arange(self.dependent.size)
        self._threshold, self._floor, self._drop, self._max_rows = threshold, floor, drop, max_rows

    def stress(self, k: int, max_rows: int | None = None) -> tuple[np.ndarray, np.ndarray] | None:
        """The local stress of the ``k``-th dependent row as (rows ascending, values), or None.

        ``max_rows`` (default: the one given at construction) bounds the patch's rows.
        """
        max_rows = self._max_rows if max_rows is None else max_rows
        a, at = self._csr, self._csc
        d = int(self.dependent[k])
        cols = np.unique(_gather(a.indptr, a.indices, np.array([d])))
        incol = np.zeros(a.shape[1], dtype=bool)
        previous = 0
        while True:
            incol[cols] = True
            cand = np.unique(_gather(at.indptr, at.indices, cols))
            cand = cand[self._position[cand] <= k]  # allowed: not a later dependent row
            lens = a.indptr[cand + 1] - a.indptr[cand]
            inside = np.add.reduceat(incol[_gather(a.indptr, a.indices, cand)].astype(np.int64),
                                     np.concatenate([[0], np.cumsum(lens)[:-1]])) == lens if cand.size else cand
            patch = cand[inside] if cand.size else cand
            if patch.size > max_rows:
                return None
            if patch.size > previous:
                found = self._on(patch, cols, d)
                if found is not None:
                    return found
            previous = patch.size
            grown = np.unique(_gather(a.indptr, a.indices, cand))
            if grown.size == cols.size:  # the component is exhausted
                return None
            cols = grown

    def _on(self, patch: np.ndarray, cols: np.ndarray, d: int):
        block = self._csr[patch][:, cols].toarray()
        null = left_null_space(block, self._threshold)
        if not null.shape[1]:
            return None
        at = int(np.searchsorted(patch, d))
        c = null[at]
        size = float(np.linalg.norm(c))
        if size < self._floor:
            return None
        w = null @ (c / size ** 2)
        w[at] = 1.0
        keep = np.flatnonzero(np.abs(w) > self._drop * np.abs(w).max())
        return patch[keep], w[keep]


def local_stress(a, dependent: np.ndarray, k: int, threshold: float, floor: float, drop: float,
                 max_rows: int = LOCAL_PATCH_ROWS):
    """The local self-stress of the ``k``-th of the ``dependent`` rows of ``a`` (see :class:`LocalStresses`).

    Examples
    --------
    Four rows on two coordinates, rows 2 and 3 dependent: the stress of row 2 may not use
    row 3 (a later dependent row), so it is ``e_2 − e_0 − e_1``.

    >>> a = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 1.0]])
    >>> rows, w = local_stress(a, np.array([2, 3]), 0, 1e-8, 1e-4, 1e-12)
    >>> rows.tolist(), np.round(w, 12).tolist()
    ([0, 1, 2], [-1.0, -1.0, 1.0])
    """
    return LocalStresses(a, dependent, threshold, floor, drop, max_rows).stress(k)
