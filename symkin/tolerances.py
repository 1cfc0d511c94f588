"""Scale-invariant numerical tolerances.

Every numerical decision in symkin (a rank, a zero eigenvalue, a zero row) compares a
*dimensionless* number with a relative tolerance:

* The constraint rows of the geometric matrix are built from unit vectors and affine
  (barycentric) coefficients, so the matrix ``J`` with ``G = Jᵀ J`` is dimensionless.  A
  singular value ``σ`` of ``J`` counts as zero when ``σ <= tol · σ_max`` (an eigenvalue
  ``λ = σ²`` of ``G`` is zero when ``sqrt(λ / λ_max) <= tol``).
* Kinematic-parameter rows are scaled to unit norm before they are restricted to the
  motion space, whose basis is orthonormal; a restricted row or singular value counts as
  zero when it is ``<= tol``.
* Geometric checks on model files (a slider node on its line, a zero-length bar) compare
  distances with ``geometry_tol · length_scale``, where the length scale is the mean
  length of the node pairs inside the links.

Because no decision involves a length in metres or millimetres, a model and the same
model scaled by any factor (or moved rigidly) get the same answer.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

__all__ = ["Tolerances", "DEFAULT"]


@dataclass(frozen=True)
class Tolerances:
    """Relative tolerances used by the analysis.

    Parameters
    ----------
    rank : float
        Relative threshold on singular values (see module docstring).  Default ``1e-8``:
        a configuration typed with 6 significant digits near a singularity has a
        smallest singular value near ``1e-6`` and is reported as non-singular, with the
        margin shown so that the near miss is visible; pass ``--tol 1e-5`` to accept it.
    geometry : float
        Relative threshold for geometric validation of model files (slider on its line,
        coincident nodes), in units of the model's length scale.
    same_configuration : float
        Two configurations located along a path are the same configuration when their free
        nodal coordinates differ by less than this (Euclidean norm of the difference, in
        units of the model's length scale); their events are merged into one.  Located
        events are accurate to ~1e-9 and distinct singular configurations of a path are
        far apart, so ``1e-6`` separates the two cases with a wide margin.
    """

    rank: float = 1e-8
    geometry: float = 1e-6
    same_configuration: float = 1e-6

    def with_rank(self, rank: float | None) -> "Tolerances":
        """Return a copy whose rank tolerance is ``rank`` (unchanged when ``None``)."""
        if rank is None:
            return self
        if not (0.0 < float(rank) < 1.0):
            raise ValueError(f"tolerance must be between 0 and 1, got {rank!r}")
        return replace(self, rank=float(rank))


DEFAULT = Tolerances()
