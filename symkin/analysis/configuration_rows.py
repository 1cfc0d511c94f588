"""The rows at one configuration that the motion space and the classification need."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from symkin.model.mechanism import Mechanism

__all__ = ["ConfigurationRows"]


@dataclass(frozen=True, eq=False)
class ConfigurationRows:
    """The rows at one configuration that the motion space and the classification need.

    Attributes
    ----------
    mechanism : Mechanism
        Topology, labels, inputs and outputs; its own coordinates are the configuration
        only when ``xyz`` is None.
    J : ndarray (m, D)
        Dimensionless constraint rows over all coordinates, in the order and with the
        owners of :func:`~symkin.numeric.geometric_matrix.constraint_rows`.
    free_index : ndarray of int
        Indices of the free coordinates among the D.
    xyz : ndarray (n_nodes, dim) or None
        The configuration, when it is not the mechanism's own.
    parameters : dict
        Parameter rows already evaluated at the configuration: ``tuple(params) →
        (rows (k, D), labels)``, physical units, as
        :func:`~symkin.numeric.geometric_matrix.parameters_matrix` gives them; any other
        list is computed from the mechanism at ``xyz``.
    sparse : SparseRows or None
        For a large model (:mod:`symkin.analysis.sparse`): ``J`` is then a
        ``scipy.sparse`` matrix and this the
        :class:`~symkin.numeric.sparse_rows.SparseRows` it comes from (owners, artefacts).
    """

    mechanism: Mechanism
    J: np.ndarray
    free_index: np.ndarray
    xyz: np.ndarray | None = None
    parameters: dict = field(default_factory=dict)
    sparse: object = None
