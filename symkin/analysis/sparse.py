"""Large models: the motion space and the self-stresses from sparse rows (issue 19).

The dense path (:mod:`symkin.analysis.motion_space`, :mod:`symkin.analysis.statics`) takes
one full SVD of the constraint matrix in the paper's pairwise form: exact and simple, but
cubic in the model's size.  A model above the **size switch** (:func:`is_large`: more than
:data:`LARGE_COORDINATES` free coordinates, or more than :data:`LARGE_ROWS` rows in the
pairwise form) takes this path instead:

* the rows are :func:`symkin.numeric.sparse_rows.sparse_constraint_rows` (the same bar and
  slider rows; a rigid body of k nodes in O(k) rows);
* the rank, the singular values near zero and the motion space come from
  :func:`symkin.numeric.linalg.sparse_small_singular` (Lanczos on ``JᵀJ`` in shift-invert
  mode, then a Rayleigh–Ritz step on ``J``): the rank is decided, as on the dense path, by
  ``σ <= rank · σ_max`` on singular values of ``J`` accurate to rounding;
* the self-stresses are the **fundamental** stresses of the dependent rows
  (:class:`~symkin.numeric.linalg.FundamentalStresses`): one per dependent row ``k``,
  with coefficient 1 on row k, each checked (``‖Jᵀω‖ <= rank · σ_max · ‖ω‖``, the rank
  test, and ``‖ω‖ <= 1 / rank``), computed when read (:class:`SparseStresses`).  The
  dependent rows are first chosen by the pivots of an LDLᵀ of ``J Jᵀ + δI``
  (:func:`symkin.numeric.linalg.sparse_dependent_rows`: cheap, and its stresses stay as
  local as the structure lets them, but it is not rank-revealing); where a stress of that
  choice fails its checks, by Gaussian elimination with partial pivoting on ``J``
  (:func:`symkin.numeric.sparse_rows.pivoted_dependent_rows`), whose stresses are
  well-conditioned but reach many rows (about half of them in a spatial truss): that repair
  is made only where such a listing fits :data:`symkin.model.validation.DENSE_ANALYSIS_BYTES`,
  then the dense left null space if it fits, else the stresses are counted (exactly) and not
  listed, with a warning.  They span the same space as the dense path's canonical (reduced
  row echelon) stresses, but are not that canonical basis: the echelon form of thousands of
  stresses is dense.
* the stresses listed are **local** where possible
  (:class:`~symkin.numeric.sparse_rows.LocalStresses`): for the k-th dependent row, a left
  null vector of a small patch of rows around it (a dense SVD of at most
  :data:`~symkin.numeric.sparse_rows.LOCAL_PATCH_ROWS` rows) with 1 on that row and 0 on the
  later dependent rows; where no patch gives one, its fundamental stress (also 0 there).
  Their entries on the dependent rows form a unit lower-triangular matrix, so they are a
  basis whatever the rows' conditioning; their number of bars is bounded by the patch's
  (a triangulated planar grid: a median of 19 bars at 992 nodes, 39 at 2,970, where the LDLᵀ
  orders the rows otherwise), not by the model's.  The first
  dependent rows have the least freedom (the first one's stress is its fundamental stress),
  so a choice of rows that fails its checks there still takes the repair above.

The count of self-stresses is the dense path's: rows touching a free coordinate, minus the
rank, minus the modelling artefacts (here: the rows of a body made dependent on its own
rows by fixed nodes, and the second copy of a node pair shared by two simplex bodies).
On this path the signed DKP values (:func:`symkin.analysis.indicators.dkp_value`) of a
mechanism are given unsigned: their sign is relative to the independent rows ``J_S``,
which a pivoted QR of the whole ``J`` would choose.

A model that this path cannot take — two bodies, one of more than ``dim + 1`` nodes,
sharing two nodes (the stress of the shared pair has no row of its own in the O(k) form) —
goes to the dense path if its size allows (:data:`symkin.model.validation.DENSE_ANALYSIS_BYTES`),
else it is refused with its size and the limit.
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sps
from scipy.linalg import qr
from scipy.sparse.linalg import ArpackNoConvergence

from symkin.analysis.configuration_rows import ConfigurationRows
from symkin.analysis.constraint_labels import PAIR_OWNER, constraint_labels
from symkin.analysis.relations import Relation
from symkin.errors import ModelError, Problem, SymkinError
from symkin.model.mechanism import Mechanism
from symkin.model.validation import dense_size_problem
from symkin.numeric.linalg import (FundamentalStresses, left_null_space, sparse_dependent_rows,
                                   sparse_small_singular, svd_null_space)
from symkin.numeric.sparse_rows import (LOCAL_PATCH_ROWS, LocalStresses, pairwise_row_count, pivoted_dependent_rows,
                                       shared_body_pairs, sparse_constraint_rows)
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["LARGE_COORDINATES", "LARGE_ROWS", "MAX_MOTIONS", "is_large", "check_dense_size", "sparse_rows",
           "sparse_motion_fields", "sparse_stresses", "SparseStresses"]

#: free coordinates above which :func:`symkin.analyze` takes the sparse path (a dense SVD of
#: 400 × 600 takes ~0.1 s; the sparse path is faster above ~300 coordinates and its cost is
#: about linear, the dense one cubic)
LARGE_COORDINATES = 400
#: rows of the paper's pairwise form above which the sparse path is taken (a body of 64+ nodes)
LARGE_ROWS = 2000
#: singular values below the window (:attr:`Tolerances.sparse_window`) beyond which a large
#: model is refused: its motion space would be a dense (coordinates × motions) matrix
MAX_MOTIONS = 2000
#: self-stresses computed at a time when a large model's are read (:class:`SparseStresses`):
#: 8 first (a report shows 5), then as many as already computed, up to this many
CHUNK = 256
#: bytes of one listed entry (a bar's label and force in a Python tuple), to estimate a listing's size
LISTED_ENTRY_BYTES = 120
#: whether the stresses listed are local ones where found (:class:`~symkin.numeric.sparse_rows.LocalStresses`)
LOCAL = True
#: rows of the largest patch tried for a dependent row whose fundamental stress fails its checks
RETRY_PATCH_ROWS = 800
#: stresses computed and checked when a choice of dependent rows is made (:class:`SparseStresses`)
_FIRST = 8


def _free_count(mech: Mechanism) -> int:
    return mech.dim * (len(mech.nodes) - len(set(mech.fixed)))


def _not_sparse(mech: Mechanism) -> str | None:
    """Why the sparse path cannot take ``mech`` (None when it can)."""
    shared = [(a, b) for a, b in shared_body_pairs(mech)
              if max(len(mech.link_nodes(a)), len(mech.link_nodes(b))) > mech.dim + 1]
    if shared:
        a, b = shared[0]
        return f"links {a} and {b} share two or more nodes, which the sparse path does not take"
    return None


_ROUTES: dict = {}


def _route(mech: Mechanism) -> tuple[bool, Problem | None]:
    """``(sparse?, problem of the dense path)`` of ``mech``'s topology (computed once per topology)."""
    got = _ROUTES.get(mech.topology)
    if got is None:
        rows, cols = pairwise_row_count(mech), _free_count(mech)
        large = rows > LARGE_ROWS or cols > LARGE_COORDINATES
        why = _not_sparse(mech) if large or dense_size_problem(rows, cols, "") is not None else None
        problem = None if large and why is None else \
            dense_size_problem(rows, cols, why or "the sparse path is for larger models")
        if len(_ROUTES) > 256:
            _ROUTES.clear()
        got = _ROUTES[mech.topology] = (large and why is None, problem)
    return got


def is_large(mech: Mechanism) -> bool:
    """Whether :func:`symkin.analyze` takes the sparse path for ``mech`` (the size switch).

    >>> from symkin.model.catalogue import get
    >>> is_large(get("fourbar_appendix"))
    False
    """
    return _route(mech)[0]


def check_dense_size(mech: Mechanism) -> None:
    """Raise :class:`~symkin.errors.ModelError` when the dense analysis of ``mech`` would not fit."""
    problem = _route(mech)[1]
    if problem is not None:
        raise ModelError([problem])


def sparse_rows(mech: Mechanism, tolerances: Tolerances = DEFAULT):
    """The :class:`~symkin.analysis.motion_space.ConfigurationRows` of ``mech`` with sparse rows."""

    rows = sparse_constraint_rows(mech, tolerances)
    return ConfigurationRows(mech, rows.matrix, rows.free_index, sparse=rows)


def sparse_motion_fields(rows, tolerances: Tolerances) -> dict:
    """The fields of a :class:`~symkin.analysis.motion_space.MotionSpace` from sparse ``rows``."""
    jf = sps.csr_matrix(rows.J)[:, rows.free_index].tocsr()
    jf.eliminate_zeros()
    try:
        try:
            smax, s_small, v_free, rank = sparse_small_singular(jf, tolerances.rank, tolerances.sparse_window,
                                                                max_vectors=MAX_MOTIONS)
        except (ArpackNoConvergence, RuntimeError):  # Lanczos or SuperLU failed: the dense SVD, if it fits
            problem = dense_size_problem(jf.shape[0], jf.shape[1], "the sparse rank decision did not converge")
            if problem is not None:
                raise ModelError([problem]) from None
            dense = jf.toarray()
            top = float(np.linalg.norm(dense, 2)) if dense.size else 0.0
            s_all, v_free, rank = svd_null_space(dense, tolerances.rank * top)
            smax, s_small = top, np.sort(s_all)
    except MemoryError:
        raise ModelError([Problem("model", f"more than {MAX_MOTIONS} singular values of its {jf.shape[0]} × "
                                           f"{jf.shape[1]} constraint matrix are near zero (below "
                                           f"{tolerances.sparse_window:g} × the largest): a motion space "
                                           f"that large is beyond the limit of {MAX_MOTIONS} motions")]) from None
    threshold = tolerances.rank * smax
    v = np.zeros((rows.J.shape[1], v_free.shape[1]))
    v[rows.free_index] = v_free
    return dict(V=v, dof=v.shape[1], singular_values=s_small, threshold=threshold, rank=rank, J=jf, U=None,
                V_free=v_free, sparse=rows.sparse)


def _shared_simplex_pairs(owners, touching: np.ndarray, sizes: dict) -> dict[int, list[int]]:
    """First row → its other copies, for each node pair shared by simplex bodies (links of 3+ nodes).

    The copies after the first are artefacts (:mod:`symkin.analysis.statics`): the stresses
    are computed without them, then the force of the pair is shared equally by its copies —
    the representative the dense path gives (its stresses are orthogonal to the difference
    of two copies).
    """

    first: dict[frozenset, int] = {}
    out: dict[int, list[int]] = {}
    for r in touching.tolist():
        m = PAIR_OWNER.match(owners[r])
        if m and sizes.get(m["link"], 2) >= 3:
            key = frozenset((m["a"], m["b"]))
            if key in first:
                out.setdefault(first[key], []).append(r)
            else:
                first[key] = r
    return out


class SparseStresses(Sequence):
    """The self-stresses of a large model: a sequence of :class:`~symkin.analysis.relations.Relation`.

    Its length (the number of independent self-stresses) is known at once; the stresses are
    computed when read, in chunks of up to :data:`CHUNK` (one sparse solve each, checked by the rank
    test), so that a report showing a few of them does not pay for thousands.  Reading all
    of them (``--json``, ``tuple(...)``) computes all.  Equal to a tuple of the same
    relations; pickles as that tuple.
    """

    def __init__(self, mech: Mechanism, ms, tolerances: Tolerances, used: np.ndarray, copies: dict,
                 labels: tuple, count: int):
        self._ju = ms.J[used]
        self._used, self._copies, self._labels = used, copies, labels
        self._tol = tolerances
        self._smax = ms.threshold / tolerances.rank if tolerances.rank > 0 else 1.0
        self._count = count
        self._done: list[Relation] = []
        self._fundamental = None
        self._dependent = None  # the dependent rows of the current choice (of J[used])
        self._null = ms.V_free
        self.unlisted: str | None = None  # why the stresses are not listed (their count still is)
        #: how the dependent rows were chosen: "LDLT" (the Gram matrix's pivots), "pivoted" (Gaussian
        #: elimination with partial pivoting, when the first choice failed its checks), "dense" (the
        #: dense left null space), or "unlisted" (the stresses are counted only: see ``unlisted``)
        self.choice: str | None = None
        self._guess = None
        self._raw: list[tuple[np.ndarray, np.ndarray]] = []  # the stresses read, as (rows of J[used], values)
        self._order = np.arange(count)  # the fundamental stresses listed after those kept from a former choice
        self._local = self._local_of = None
        self._jt = self._ju.T.tocsr().tocsc() if count > 0 else None  # Jᵀ by columns (rows of J): the checks
        #: stresses read that are local (:class:`~symkin.numeric.sparse_rows.LocalStresses`), and those that
        #: are the fundamental stresses of their dependent rows (no local one found within the patch limit)
        self.local = 0
        self.fallback = 0
        self.is_local: list[bool] = []  # per stress read: local (True) or fundamental (False)
        if count > 0:
            self._choose()

    def _choose(self) -> None:
        """The dependent rows: the LDLᵀ choice, else its partial-pivoting repair, else the dense path.

        Each choice is kept if its first stresses pass their checks (:meth:`_take`).  A later
        stress that fails (:meth:`_more`) moves to the next choice; the stresses already read
        stay, first, and the new choice gives the others: those of its fundamental stresses
        that complete them to a basis (:meth:`_exchange`).
        """
        if self.choice is None:
            try:
                self._guess = sparse_dependent_rows(self._ju, self._count, self._tol.sparse_gram)
                # built when a stress needs it (no local one): the local stresses need only the rows
                self._fundamental, self._dependent = None, self._guess
                self.choice = "LDLT"
                self._order = np.arange(self._count)
                if self._take(0, _FIRST):  # the first few at once: a poor choice of rows shows here, at analysis time
                    return
            except RuntimeError:  # SuperLU: the rows chosen are singular
                pass
        if self.choice in (None, "LDLT") and self._guess is not None:
            self.choice = "pivoted"
            if self._too_large_to_list(len(self._done)):
                return
            try:
                rows = pivoted_dependent_rows(self._ju, self._guess, self._null)
                self._fundamental = FundamentalStresses(self._ju, rows, self._null)
                self._dependent = rows
                h = len(self._done)
                if self._exchange() and self._take(h, h + _FIRST):
                    self._check_listing_size(h)
                    return
            except RuntimeError:
                pass
        self._fundamental = None
        self.choice = "dense"
        if self._done:
            raise SymkinError("the self-stresses cannot be listed: the rows chosen as a basis fail the rank "
                              "test after some stresses were read")
        self._dense()

    def _too_large_to_list(self, h: int) -> bool:
        """Whether a listing of stresses reaching half the rows would exceed the limit (then not listed).

        Checked before the partial-pivoting repair, whose factorisation is costly: its
        fundamental stresses reach about half the rows on the spatial trusses measured (47–49 %
        at 1,000–1,728 nodes, ``benchmarks/bench_large.py``).
        """
        m = self._ju.shape[0]
        need = self._count * (m / 2) * LISTED_ENTRY_BYTES
        from symkin.model import validation

        if need <= validation.DENSE_ANALYSIS_BYTES:
            return False
        message = (f"the first choice of dependent rows fails the rank test, and the stresses of the "
                   f"partial-pivoting choice (about {m // 2} bars each) would take about {need / 1024 ** 3:.1f} GiB "
                   f"to list, above the limit of {validation.DENSE_ANALYSIS_BYTES / 1024 ** 3:g} GiB")
        if h:
            raise SymkinError(f"the self-stresses cannot be listed: {message}")
        self.unlisted, self._done, self._raw, self._fundamental = message, [], [], None
        self.is_local, self.local, self.fallback = [], 0, 0
        self.choice = "unlisted"
        return True

    def _check_listing_size(self, h: int) -> None:
        """Refuse to list stresses whose listing would exceed the dense limit (estimated from those computed).

        A fundamental stress of the partial-pivoting choice may reach many rows (in a spatial
        truss, about half of them): the listing then grows as (count × rows), beyond
        :data:`symkin.model.validation.DENSE_ANALYSIS_BYTES` at a few thousand nodes.
        """
        from symkin.model import validation

        entries = sum(rows.size for rows, _ in self._raw[h:]) / max(len(self._raw) - h, 1)
        need = entries * self._count * LISTED_ENTRY_BYTES
        if need > validation.DENSE_ANALYSIS_BYTES:
            message = (f"listing them would take about {need / 1024 ** 3:.1f} GiB (about {entries:.0f} bars each, "
                       f"the rows chosen by partial pivoting), above the limit of "
                       f"{validation.DENSE_ANALYSIS_BYTES / 1024 ** 3:g} GiB")
            if h:
                raise SymkinError(f"the self-stresses cannot be listed: {message}")
            self.unlisted, self._done, self._raw = message, [], []
            self.is_local, self.local, self.fallback = [], 0, 0

    def _exchange(self) -> bool:
        """Keep the stresses read (``h`` of them) and drop ``h`` of the new fundamental stresses.

        A stress's coordinates in the new fundamental basis are its entries on the new
        dependent rows; the ``h`` columns of the ``h × count`` matrix of those coordinates
        chosen by a pivoted QR are the new stresses the old ones replace (the exchange lemma:
        the result is a basis when the pivots are nonzero at the rank tolerance).
        """
        h = len(self._done)
        self._order = np.arange(self._count)
        if not h:
            return True
        dependent = self._dependent
        coords = np.zeros((h, self._count))
        for i, (rows, coef) in enumerate(self._raw):
            at = np.searchsorted(dependent, rows)
            hit = (at < dependent.size) & (dependent[np.minimum(at, dependent.size - 1)] == rows)
            coords[i, at[hit]] = coef[hit]
        r, piv = qr(coords, pivoting=True, mode="r")
        d = np.abs(np.diag(r))
        if d.size < h or d.min() <= self._tol.rank * d.max():
            return False
        self._order = np.setdiff1d(self._order, piv[:h])
        return True

    @property
    def count(self) -> int:
        """The number of independent self-stresses (exact, also when they are not listed)."""
        return self._count

    def __len__(self) -> int:
        return 0 if self.unlisted else self._count

    def __getitem__(self, i):
        n = len(self)
        if isinstance(i, slice):
            return tuple(self[k] for k in range(*i.indices(n)))
        if i < 0:
            i += n
        if not 0 <= i < n:
            raise IndexError(i)
        while len(self._done) <= i:
            self._more()
        return self._done[i]

    def __iter__(self):
        for k in range(len(self)):
            yield self[k]

    def __eq__(self, other) -> bool:
        try:
            return len(other) == len(self) and all(a == b for a, b in zip(self, other))
        except TypeError:
            return NotImplemented

    def __hash__(self) -> int:
        return hash(tuple(self))

    def __reduce__(self):
        return tuple, (tuple(self),)

    def __repr__(self) -> str:
        return f"SparseStresses({self._count} self-stresses, {len(self._done)} computed)"

    def _more(self) -> None:
        start = len(self._done)
        if not self._take(start, start + min(CHUNK, max(8, start))):  # the next choice, from the start
            self._choose()
            if self.unlisted:
                raise SymkinError(f"the self-stresses cannot be listed: {self.unlisted}")

    def _take(self, start: int, stop: int) -> bool:
        """Compute and keep stresses ``start:stop`` if each passes its checks (else keep none).

        A stress is the local one of its dependent row where a patch of at most
        :data:`~symkin.numeric.sparse_rows.LOCAL_PATCH_ROWS` rows gives one, else its
        fundamental stress, else (that one failing its checks: a poor choice of rows) the local
        one of a patch of up to :data:`RETRY_PATCH_ROWS` rows; else the choice fails.
        """
        # entries below rank^1.5 (1e-12 by default) of a stress's largest are rounding of the solve: exact zeros
        h = self._count - self._order.size  # stresses kept from a former choice, listed first
        index = self._order[start - h: stop - h]
        use_local = h == 0 and LOCAL
        found = self._locals(index) if use_local else {}
        rest = np.array([k for k in index.tolist() if k not in found], dtype=int)
        if rest.size:
            try:
                if self._fundamental is None:
                    self._fundamental = FundamentalStresses(self._ju, self._dependent, self._null)
                parts = np.split(rest, np.flatnonzero(np.diff(rest) != 1) + 1)
                fund = sps.hstack([self._fundamental.columns(int(p[0]), int(p[-1]) + 1, self._tol.rank ** 1.5)
                                   for p in parts], format="csc")
                ok = self._passes(fund)
            except RuntimeError:  # SuperLU: the rows left are singular
                fund, ok = None, np.zeros(rest.size, dtype=bool)
            bad = rest[~ok]
            if bad.size and not use_local:
                return False
            retry = self._locals(bad, RETRY_PATCH_ROWS) if bad.size else {}
            if len(retry) < bad.size:
                return False
            fallback = {k: (fund.indices[fund.indptr[c]: fund.indptr[c + 1]], fund.data[fund.indptr[c]: fund.indptr[c + 1]])
                        for c, k in enumerate(rest.tolist()) if ok[c]}
        else:
            retry, fallback = {}, {}
        for k in index.tolist():
            rows, coef = found.get(k) or retry.get(k) or fallback[k]
            self._raw.append((rows.copy(), coef.copy()))
            self._add(self._used[rows], coef)
            self.is_local.append(k not in fallback)
        self.local += index.size - len(fallback)
        self.fallback += len(fallback)
        return True

    def _passes(self, w) -> np.ndarray:
        """Which columns of ``w`` pass the checks of a stress.

        A stress passes the rank test (relative to its norm), and its 1 on its own dependent
        row stays above the rank tolerance of its norm (else the stresses are not independent
        at the threshold: the rows chosen as a basis are dependent there).
        """
        residual = abs(self._ju.T @ w).max(axis=0).toarray().ravel()
        norms = np.sqrt(np.asarray(w.multiply(w).sum(axis=0)).ravel())
        return (residual <= self._tol.rank * self._smax * norms) & (norms * self._tol.rank <= 1.0)

    def _locals(self, index: np.ndarray, max_rows: int = LOCAL_PATCH_ROWS) -> dict:
        """Local stresses (:class:`~symkin.numeric.sparse_rows.LocalStresses`) of the dependent rows
        ``index``, those found and passing the rank test on the whole ``J``: position → (rows, values)."""
        if self._local is None or self._local_of is not self._dependent:
            self._local_of = self._dependent
            self._local = LocalStresses(self._ju, self._dependent, self._tol.rank * self._smax,
                                        self._tol.sparse_local, self._tol.rank ** 1.5)
        out = {}
        for k in index.tolist():
            got = self._local.stress(k, max_rows)
            if got is None:
                continue
            rows, w = got
            residual = np.abs(self._jt[:, rows] @ w).max(initial=0.0)
            if residual <= self._tol.rank * self._smax * float(np.linalg.norm(w)):
                out[k] = got
        return out

    def _add(self, rows: np.ndarray, coef: np.ndarray) -> None:
        if self._copies:
            rows, coef = _share_copies(rows, coef, self._copies)
        labels = self._labels
        self._done.append(Relation(tuple(zip([labels[r] for r in rows.tolist()], coef.tolist()))))

    def _dense(self) -> None:
        """All stresses from the dense left null space (when the sparse choice of rows failed)."""
        problem = dense_size_problem(self._ju.shape[0], self._ju.shape[1], "the rows the sparse path chose "
                                     "as a basis are not one at the rank threshold")
        if problem is not None:
            self.unlisted = problem.message
            return
        basis = left_null_space(self._ju.toarray(), self._tol.rank * self._smax)[:, : self._count]
        self._done, self._raw, self.is_local, self.local, self.fallback = [], [], [], 0, 0
        for c in range(basis.shape[1]):
            col = basis[:, c]
            keep = np.flatnonzero(np.abs(col) > self._tol.rank * np.abs(col).max())
            self._add(self._used[keep], col[keep] / col[keep[0]])
        self._count = len(self._done)


def sparse_stresses(mech: Mechanism, ms, tolerances: Tolerances) -> tuple[SparseStresses, int]:
    """The self-stresses (:class:`SparseStresses`) of a sparse motion space ``ms`` and the artefacts' count."""

    info = ms.sparse
    touching = ms.effective_rows
    sizes = {name: len(ns) for name, ns in mech.links}
    copies = _shared_simplex_pairs(info.owners, touching, sizes)
    internal = set(info.internal.tolist()) | {r for rs in copies.values() for r in rs}
    used = np.array([r for r in touching.tolist() if r not in internal], dtype=int)
    artefacts = touching.size - used.size
    count = max(used.size - ms.rank, 0)
    return SparseStresses(mech, ms, tolerances, used, copies, constraint_labels(mech, info.owners), count), artefacts


def _share_copies(rows: np.ndarray, coef: np.ndarray, copies: dict) -> tuple[np.ndarray, np.ndarray]:
    """The force on a pair's first row shared equally by all its copies (see :func:`_shared_simplex_pairs`)."""
    out_rows, out_coef = [], []
    for r, c in zip(rows.tolist(), coef.tolist()):
        group = [r] + copies.get(r, [])
        out_rows += group
        out_coef += [c / len(group)] * len(group)
    order = np.argsort(out_rows)
    return np.array(out_rows)[order], np.array(out_coef)[order]
