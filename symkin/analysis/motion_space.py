"""The motion space of a mechanism at one configuration (paper §IV, eqs. 8-10).

The null space of the reduced geometric matrix is computed from the singular value
decomposition of the dimensionless constraint matrix ``J`` (``G = Jᵀ J``), which is as
accurate as the eigenproblem of eq. (8) but resolves singular values down to machine
precision instead of its square root.  Eigenvalues of ``G`` are ``λ = σ²``.

One SVD ``J_r = U Σ Vᵀ`` of the reduced (free-coordinate) constraint matrix gives
everything: the singular values, the threshold ``tol · σ_max``, the motion space (the
right singular vectors beyond the rank) and, kept on the result as :attr:`MotionSpace.U`,
the left singular vectors, whose columns beyond the rank span the left null space of
``J_r`` (self-stresses).  Parameter rows restricted to the motion space are computed once
per parameter list (:meth:`MotionSpace.restrict`).

The SVD takes rows, not a model: :class:`ConfigurationRows` holds the constraint rows
at one configuration (all coordinates), the free coordinates and, optionally, parameter
rows already evaluated there.  :func:`model_rows` builds them from the model as the
NumPy core does; :func:`motion_space_of` is the computation, and
:func:`motion_space` is the two together.  The paths stage builds the rows from the
curve's CasADi evaluators at an event instead (:mod:`symkin.paths.trace`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from symkin.analysis import indicators, sparse
from symkin.analysis.configuration_rows import ConfigurationRows
from symkin.model.mechanism import Mechanism
from symkin.numeric.geometric_matrix import (constraint_rows, coordinate_labels, parameters_matrix, plan,
                                             rotation_rows)
from symkin.numeric.linalg import svd_factors, svd_rank
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["ConfigurationRows", "MotionSpace", "model_rows", "rows_for", "motion_space", "motion_space_of"]


def model_rows(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> ConfigurationRows:
    """The rows of ``mech`` at its own configuration, from the NumPy core.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> rows = model_rows(get("fourbar_appendix"))
    >>> rows.J.shape, rows.free_index.tolist()
    ((3, 8), [2, 3, 4, 5])
    """
    return ConfigurationRows(mech, constraint_rows(mech, tolerances).matrix, plan(mech.topology).free_index)


def rows_for(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> ConfigurationRows:
    """The rows :func:`symkin.analyze` and :func:`motion_space` use: sparse for a large model.

    The size switch is :func:`symkin.analysis.sparse.is_large`; a model too large for the
    dense path that the sparse path cannot take is refused
    (:func:`~symkin.analysis.sparse.check_dense_size`).
    """
    if sparse.is_large(mech):
        return sparse.sparse_rows(mech, tolerances)
    sparse.check_dense_size(mech)
    return model_rows(mech, tolerances)


@dataclass(frozen=True, eq=False)
class MotionSpace:
    """Basis of the feasible motions at one configuration.

    Attributes
    ----------
    V : ndarray (D, L)
        Orthonormal basis of the motion space over *all* nodal velocity components
        (eq. 9); rows of fixed coordinates are zero.
    dof : int
        Instantaneous DOF ``L`` (number of zero eigenvalues of the reduced G).
    singular_values : ndarray
        Singular values of the reduced constraint matrix, ascending, including the
        structural zeros (``sqrt`` of the eigenvalues of the reduced G).
    threshold : float
        ``tol · σ_max``: singular values at or below it count as zero.
    rank : int
        Rank of the reduced constraint matrix ``J_r`` (rows × free coordinates).
    J : ndarray (m, n_free)
        The reduced, dimensionless constraint matrix (rows as
        :func:`~symkin.numeric.geometric_matrix.constraint_rows`).
    U : ndarray (m, m)
        Left singular vectors of ``J_r``, by descending singular value: ``U[:, rank:]`` is an
        orthonormal basis of the left null space ``{y : yᵀ J_r = 0}`` (self-stresses).
    V_free : ndarray (n_free, L)
        The rows of ``V`` of the free coordinates (``V`` without its zero rows).
    given : dict
        Parameter rows evaluated with the constraint rows (:attr:`ConfigurationRows.parameters`).
    sparse : SparseRows or None
        Set for a large model (:mod:`symkin.analysis.sparse`): ``J`` is then a
        ``scipy.sparse`` matrix, ``U`` is None, and ``singular_values`` holds only the
        smallest singular values (those at or below ``sparse_window · σ_max`` and the next).

    The configuration is :attr:`xyz`: the mechanism's own coordinates, or those of the
    :class:`ConfigurationRows` the space was computed from.
    """

    mechanism: Mechanism
    V: np.ndarray
    dof: int
    singular_values: np.ndarray
    threshold: float
    tolerances: Tolerances = field(default=DEFAULT)
    rank: int = 0
    J: np.ndarray | None = field(default=None, repr=False)
    U: np.ndarray | None = field(default=None, repr=False)
    V_free: np.ndarray | None = field(default=None, repr=False)
    sparse: object = field(default=None, repr=False)
    _restricted: dict = field(default_factory=dict, repr=False)
    given: dict = field(default_factory=dict, repr=False)

    @classmethod
    def _of(cls, **fields) -> "MotionSpace":
        """``MotionSpace(**fields)`` with every field given, without the frozen ``__init__`` (faster)."""
        obj = object.__new__(cls)
        obj.__dict__.update(fields)
        return obj

    @cached_property
    def xyz(self) -> np.ndarray:
        """The configuration's coordinates, (n_nodes, dim)."""
        return np.array([c for _, c in self.mechanism.nodes], dtype=float)

    @cached_property
    def effective_rows(self) -> np.ndarray:
        """Indices of the rows of ``J`` that touch a free coordinate (not a bar between fixed nodes)."""
        if self.J is None:
            return np.zeros(0, int)
        if self.sparse is not None:
            return np.flatnonzero(np.diff(self.J.indptr))  # CSR without explicit zeros
        return np.flatnonzero(self.J.any(axis=1))

    @property
    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of the reduced geometric matrix, ascending (eq. 8)."""
        return self.singular_values ** 2

    @property
    def coordinate_labels(self) -> tuple[str, ...]:
        return coordinate_labels(self.mechanism)

    def im_indicator(self, mobility: int | None = None) -> float | None:
        """The first eigenvalue of G above the F generic zeros: ``λ_{F+1}`` (§IV-A).

        It vanishes at increased-mobility configurations.  Fixed coordinates are not in
        the reduced matrix, so their unit diagonal (eq. A6) never shows up here.
        """
        f = self.mechanism.mobility_value if mobility is None else mobility
        if f >= self.singular_values.size:
            return None
        return float(indicators.im_indicator(self.singular_values, f, ascending=True))

    def omega(self) -> tuple[np.ndarray, tuple[str, ...]]:
        """Ω of eq. (10): angular-velocity rows of the moving links times V, and labels."""
        mech = self.mechanism
        rows, labels = [], []
        for link in mech.moving_links:
            r = rotation_rows(mech, link, self.xyz)
            rows.append(r @ self.V)
            labels += [f"omega:{link}"] if mech.dim == 2 else [f"omega:{link}.{c}" for c in "xyz"]
        if not rows:
            return np.zeros((0, self.dof)), ()
        return np.vstack(rows), tuple(labels)

    def restrict(self, params) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
        """Parameter rows restricted to the motion space, rows scaled to unit norm.

        Returns ``(M, norms, labels)`` with ``M = P̂ V`` (``P̂`` the rows divided by their
        norms over the free coordinates); relations found on ``M`` become physical
        coefficients by dividing by ``norms``.  Computed once per parameter list; the
        arrays returned are read-only.
        """
        key = params if isinstance(params, tuple) else tuple(params)
        got = self._restricted.get(key)
        if got is None:
            got = self._restricted[key] = self._restrict(key)
        return got

    def unit_rows(self, params) -> np.ndarray:
        """``P̂`` over the free coordinates: the unit parameter rows that :meth:`restrict` projects."""
        key = params if isinstance(params, tuple) else tuple(params)
        self.restrict(key)
        return self._restricted[("unit", key)]

    def _restrict(self, params: tuple) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
        mech = self.mechanism
        got = self.given.get(params)
        # a large model's free coordinates without its plan (whose pair rows grow as k² for a body of k nodes)
        free_index = self.sparse.free_index if self.sparse is not None else None
        if got is None and not params and free_index is not None:
            got = (np.zeros((0, self.V.shape[0])), ())
        p, labels = got if got is not None else parameters_matrix(mech, params, self.__dict__.get("xyz"))
        if free_index is None:
            free_index = plan(mech.topology).free_index
        hat_free, norms = indicators.unit_rows(p.take(free_index, axis=1))
        v_free = self.V_free if self.V_free is not None else self.V[free_index]
        m = hat_free @ v_free
        for a in (m, norms, hat_free):
            a.setflags(write=False)
        self._restricted[("unit", params)] = hat_free
        return m, norms, labels

    def node_speed_array(self) -> np.ndarray:
        """Norm of each node's rows of V, in node order (see :meth:`node_speeds`)."""
        n, dim = len(self.mechanism.nodes), self.mechanism.dim
        block = self.V.reshape(n, dim * self.V.shape[1])
        return np.sqrt(np.einsum("ij,ij->i", block, block))

    def node_speeds(self) -> dict[str, float]:
        """Norm of each node's rows of V: zero for a node that cannot move at all."""
        return dict(zip(self.mechanism.node_names, self.node_speed_array().tolist()))


def motion_space(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> MotionSpace:
    """Compute the motion space of ``mech`` at its configuration.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> ms = motion_space(get("fourbar_appendix"))
    >>> ms.dof, ms.V.shape
    (1, (8, 1))
    >>> ms.rank, ms.J.shape, ms.U.shape  # 3 bars, 4 free coordinates: no self-stress
    (3, (3, 4), (3, 3))
    """
    return motion_space_of(rows_for(mech, tolerances), tolerances)


def motion_space_of(rows: ConfigurationRows, tolerances: Tolerances = DEFAULT) -> MotionSpace:
    """The motion space from the rows at a configuration (the computation of :func:`motion_space`).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> motion_space_of(model_rows(get("fourbar_appendix"))).dof
    1
    """
    mech = rows.mechanism
    if rows.sparse is not None:
        return MotionSpace._of(mechanism=mech, tolerances=tolerances, _restricted={}, given=rows.parameters,
                               **sparse.sparse_motion_fields(rows, tolerances),
                               **({} if rows.xyz is None else {"xyz": rows.xyz}))
    free_index = rows.free_index
    jf = rows.J.take(free_index, axis=1)
    u, s, vt = svd_factors(jf)
    threshold = tolerances.rank * (float(s[0]) if s.size else 0.0)
    rank = svd_rank(s, threshold)
    v_free = vt[rank:].T
    v = np.zeros((rows.J.shape[1], v_free.shape[1]))
    v[free_index] = v_free  # zero rows for the fixed coordinates
    singular = np.zeros(jf.shape[1])  # ascending, with the structural zeros of a wide J_r first
    singular[jf.shape[1] - s.size:] = s[::-1]
    return MotionSpace._of(mechanism=mech, V=v, dof=v.shape[1], singular_values=singular,
                           threshold=threshold, tolerances=tolerances, rank=rank, J=jf, U=u, V_free=v_free,
                           sparse=None, _restricted={}, given=rows.parameters,
                           **({} if rows.xyz is None else {"xyz": rows.xyz}))
