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
* Independent rows (the rows ``J_S`` that the motion space and the signed DKP values are
  built from, the rows a square corrector keeps) are chosen by QR with column pivoting;
  the rank counts the diagonal entries ``|R_kk| > rank · |R_00|``
  (:func:`symkin.numeric.linalg.independent_rows`).
* Events along a path (:func:`symkin.trace`) are accepted with thresholds that are
  multiples of ``rank`` (see :attr:`Tolerances.event`), and then classified by
  :func:`symkin.analyze` with the same ``rank``.
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
    event : float
        Ratio of the path-event threshold to ``rank``: a located minimum of the IM test
        ``σ_{F+1}`` of the dimensionless ``J`` (or of an unsigned DKP test) is an event when it is at most
        ``event · rank`` (default ``10``, i.e. ``1e-7``).  A minimum located along a path
        by Brent's method on a Newton-projected curve is accurate to a few ``1e-9`` only,
        so the event threshold sits one decade above the classifier's; the classifier
        (:func:`symkin.analyze`, same ``rank``) then says whether the event is confirmed.
    near_branch : float
        A sign change of a DKP test located where ``σ_{F+1}`` (dimensionless ``J``) is below
        ``near_branch`` is refined as a branch point (IM) instead (default ``1e-5``: two
        decades above the event threshold, where a DKP root next to a branch point is
        no longer separated from it at the continuation's step size).
    newton : float
        Residual (dimensionless: the closure in units of the length scale, or a system the
        caller scaled so) at which the Gauss–Newton corrector of :mod:`symkin.curves`
        has converged, together with a last step below its square root (default ``1e-12``:
        about 1e4 roundings of an O(1) residual, so that a well-conditioned point reaches
        it in one or two quadratic steps and a point next to a singularity, where Newton
        converges only linearly, still does).
    closure : float
        Residual to which a *located* point (an event, a singular configuration) is
        polished onto the closure before it is classified (default ``1e-13``: one decade
        below ``newton``, at the rounding level of a length-scale-normalised closure).
    locate : float
        Relative step below which the singular-point locator of :mod:`symkin.curves`
        (branch points, rank drops, deflated systems whose residual cannot reach ``newton``
        in floating point) stops (default ``1e-14``: a few roundings of ``‖z‖``).
    pinv : float
        Relative cutoff of the minimum-norm least-squares steps on systems that may be rank
        deficient (the closure of an over-constrained mechanism, whose redundant rows make
        its Jacobian singular): singular values below ``pinv · σ_max`` are treated as zero
        (default ``1e-12``: a rank deficiency at the rounding level of an O(1) Jacobian).
    flat : float
        Along a traced curve, a signed test below this at both ends of a step is identically
        zero there, with no isolated root to locate (the curve runs along such a configuration,
        e.g. a locked input link); default ``1e-9``, two decades below the event threshold.
    root : float
        A located sign change must bring its test below this fraction of its bracket's values,
        else the sign changed through a jump, not a zero (default ``1e-6``).
    sign_change_xtol : float
        Brent's tolerance on the dimensionless projection of a sign change along a curve
        (default ``1e-14``: a few roundings of a coordinate of order 1).
    minimum_xtol : float
        Brent's tolerance on the projection of a minimum (default ``1e-13``: a minimum is flat,
        its place is determined to about the square root of the test's rounding only).
    deflate_singular : float
        The singular-point locator deflates its system where the smallest singular value of
        the system's Jacobian is below this fraction of the largest (default ``1e-7``: above the
        ~1e-8 relative rounding of a point Newton reached there).
    branch_step : float
        Steps at which the half-branch search around a vertex stops (Newton on the reduced
        unknown, Brent on the angle; default ``1e-15``: a few roundings).
    sparse_window : float
        Large models (:mod:`symkin.analysis.sparse`): every singular value of the constraint
        matrix at or below ``sparse_window · σ_max`` is computed accurately (Lanczos in
        shift-invert mode on ``G = JᵀJ``, then a Rayleigh–Ritz step on ``J``) and compared with
        the ``rank`` threshold; those above it are not computed.  Default ``1e-4``: four decades
        above the default rank threshold (no rank decision depends on a value not computed),
        and below the smallest nonzero singular value of ordinary trusses of 10,000 nodes
        (about ``1/N`` for N nodes along a side), so that few vectors are computed.
    sparse_gram : float
        Large models: the Gram matrix ``J Jᵀ + δ I`` whose ``L D Lᵀ`` pivots pick the dependent
        rows (the pivots of the rows that depend on rows before them are ``≈ δ``, the others
        the squared distance of a row from the rows before it, rows of unit norm); default
        ``1e-15``, at the rounding of an O(1) Gram matrix, so that an independent row a
        distance above ~1e-6 from the others is never taken for a dependent one.  The choice
        is verified: each self-stress it gives must pass the ``rank`` test.
    sparse_local : float
        Large models: a patch of rows around a dependent row ``d``
        (:func:`symkin.numeric.sparse_rows.local_stress`) gives a local self-stress when the
        ``d`` entries of an orthonormal basis of the patch's left null space have a norm of at
        least ``sparse_local``; the stress (``w_d = 1``, least norm) then has a norm of at
        most ``1 / sparse_local``.  Default ``1e-4``: well-conditioned stresses (the
        fundamental stresses are accepted up to a norm of ``1 / rank``), a larger patch
        is tried otherwise.
    kernel_margin : float
        Factor on singular values by which the generated indicator kernel must clear the
        rank threshold to decide a configuration alone (:mod:`symkin.analysis.batch`,
        default ``100``: well beyond the kernel's rounding, so kernel and SVD never
        disagree on a configuration the kernel decides).
    row_switch : float
        Along a traced curve (:func:`symkin.trace`), a subset of rows that a signed test keeps
        (``J_S`` of the DKP values, the rows of the bifurcation determinant) is chosen anew
        where its least singular value falls below ``row_switch`` times the least nonzero
        singular value of the whole set (a mechanism with redundant rows: a fixed subset
        loses rank where the whole set does not), the test's sign carried across the switch
        (default ``0.1``: a subset chosen by pivoted QR starts well above it; the signs of the
        two subsets are compared where the old one was last above it, since a continuation
        step may pass the old subset's own rank loss, where its sign flips).
    """

    rank: float = 1e-8
    geometry: float = 1e-6
    same_configuration: float = 1e-6
    event: float = 10.0
    near_branch: float = 1e-5
    kernel_margin: float = 100.0
    sparse_window: float = 1e-4
    sparse_gram: float = 1e-15
    sparse_local: float = 1e-4
    newton: float = 1e-12
    closure: float = 1e-13
    locate: float = 1e-14
    pinv: float = 1e-12
    flat: float = 1e-9
    root: float = 1e-6
    sign_change_xtol: float = 1e-14
    minimum_xtol: float = 1e-13
    deflate_singular: float = 1e-7
    branch_step: float = 1e-15
    row_switch: float = 0.1

    @property
    def event_threshold(self) -> float:
        """``event · rank``: relative threshold of the path's minimum tests (see ``event``)."""
        return self.event * self.rank

    @classmethod
    def of(cls, tol: "float | Tolerances | None") -> "Tolerances":
        """The tolerances meant by ``tol``: a :class:`Tolerances`, a rank tolerance, or None (defaults).

        >>> Tolerances.of(1e-6).rank, Tolerances.of(None).rank
        (1e-06, 1e-08)
        """
        if isinstance(tol, Tolerances):
            return tol
        if isinstance(tol, bool) or not (tol is None or isinstance(tol, (int, float))):
            raise TypeError(f"tol must be a float (the rank tolerance) or a Tolerances, got {tol!r}")
        return DEFAULT.with_rank(tol)

    def with_rank(self, rank: float | None) -> "Tolerances":
        """Return a copy whose rank tolerance is ``rank`` (unchanged when ``None``)."""
        if rank is None:
            return self
        if not (0.0 < float(rank) < 1.0):
            raise ValueError(f"tolerance must be between 0 and 1, got {rank!r}")
        return replace(self, rank=float(rank))


#: the default tolerances (every field at its documented default)
DEFAULT = Tolerances()
