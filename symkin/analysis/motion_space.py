"""The motion space of a mechanism at one configuration (paper §IV, eqs. 8-10).

The null space of the reduced geometric matrix is computed from the singular value
decomposition of the dimensionless constraint matrix ``J`` (``G = Jᵀ J``), which is as
accurate as the eigenproblem of eq. (8) but resolves singular values down to machine
precision instead of its square root.  Eigenvalues of ``G`` are ``λ = σ²``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from symkin.analysis import indicators
from symkin.model.mechanism import Mechanism
from symkin.numeric.geometric_matrix import (constraint_rows, coordinate_labels, free_mask,
                                             parameters_matrix, rotation_rows)
from symkin.numeric.linalg import svd_null_space
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["MotionSpace", "motion_space"]


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
    """

    mechanism: Mechanism
    V: np.ndarray
    dof: int
    singular_values: np.ndarray
    threshold: float
    tolerances: Tolerances = field(default=DEFAULT)

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
        return float(indicators.im_indicator(self.singular_values, f))

    def omega(self) -> tuple[np.ndarray, tuple[str, ...]]:
        """Ω of eq. (10): angular-velocity rows of the moving links times V, and labels."""
        mech = self.mechanism
        rows, labels = [], []
        for link in mech.moving_links:
            r = rotation_rows(mech, link)
            rows.append(r @ self.V)
            labels += [f"omega:{link}"] if mech.dim == 2 else [f"omega:{link}.{c}" for c in "xyz"]
        if not rows:
            return np.zeros((0, self.dof)), ()
        return np.vstack(rows), tuple(labels)

    def restrict(self, params) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
        """Parameter rows restricted to the motion space, rows scaled to unit norm.

        Returns ``(M, norms, labels)`` with ``M = P̂ V`` (``P̂`` the rows divided by their
        norms over the free coordinates); relations found on ``M`` become physical
        coefficients by dividing by ``norms``.
        """
        mech = self.mechanism
        p, labels = parameters_matrix(mech, params)
        p_hat, norms = indicators.unit_rows(p, free_mask(mech))
        return p_hat @ self.V, norms, labels

    def node_speeds(self) -> dict[str, float]:
        """Norm of each node's rows of V: zero for a node that cannot move at all."""
        dim = self.mechanism.dim
        return {n: float(np.linalg.norm(self.V[dim * i: dim * i + dim]))
                for i, n in enumerate(self.mechanism.node_names)}


def motion_space(mech: Mechanism, tolerances: Tolerances = DEFAULT) -> MotionSpace:
    """Compute the motion space of ``mech`` at its configuration.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> ms = motion_space(get("fourbar_appendix"))
    >>> ms.dof, ms.V.shape
    (1, (8, 1))
    """
    j = constraint_rows(mech, tolerances).matrix
    free = free_mask(mech)
    jf = j[:, free]
    smax = float(np.linalg.norm(jf, 2)) if jf.size else 0.0
    threshold = tolerances.rank * smax
    s, null, _ = svd_null_space(jf, threshold)
    v = np.zeros((free.size, null.shape[1]))
    v[free] = null
    return MotionSpace(mechanism=mech, V=v, dof=null.shape[1], singular_values=np.sort(s),
                       threshold=threshold, tolerances=tolerances)
