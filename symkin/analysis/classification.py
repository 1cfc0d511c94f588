"""Classification of one configuration (paper §III-V, the algorithm of Fig. 9).

With F the full-cycle mobility, L the instantaneous DOF and ranks taken of the
parameter rows restricted to the motion space (unit-norm rows, orthonormal basis, so
every rank is scale invariant):

* **IM** — ``L > F``; the uncontrolled motions are the motions left with every input
  locked (eq. 11/14).
* **DKP-input** — ``rank(inputs) < min(F, n_in)``; relations (eq. 13) from the left null
  space, in reduced row echelon form over the parameters' order.
* **DKP-output** — ``rank(outputs) < min(F, n_out)`` (eqs. 16-17).
* **LIM** — a non-ground link whose free nodes cannot move for any motion (zero rows of
  V, hence of Ω; §IV-B-3), evaluated only when the mechanism has mobility to lose
  (``F ≥ 1`` and ``L > 0``).  A structure (``F = 0``) is singular only when it has a flex
  (``L > 0``: IM); its motionless links and nodes are still listed in ``locked_links`` /
  ``locked_nodes`` (every link of a rigid structure), as data, not as a singularity.
* **constraint** — the platform's DOF (rank of its twist rows) exceeds its generic DOF.

Gosselin–Angeles and Zlatanov types are derived from the same subspaces (see
:func:`analyze`).  Every analysis also reports the self-stresses and redundant constraints
(:mod:`symkin.analysis.statics`) and warnings about odd models
(:mod:`symkin.model.diagnostics`).

:func:`classify` is the computation: it takes the rows at a configuration
(:class:`~symkin.analysis.motion_space.ConfigurationRows`: constraint rows, free
coordinates, parameter rows already evaluated, the mechanism for topology and labels).
:func:`analyze` builds those rows from the model (:func:`~symkin.analysis.motion_space.rows_for`: sparse for a large model)
and calls it; the paths stage builds them from the curve's evaluators at an event.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from symkin.analysis import indicators
from symkin.analysis.motion_space import ConfigurationRows, MotionSpace, motion_space_of, rows_for
from symkin.analysis.relations import Relation, canonical_relations
from symkin.analysis.statics import self_stresses
from symkin.model.diagnostics import mobility_warning, topology_warnings
from symkin.model.mechanism import Mechanism, Parameter, ParameterList
from symkin.numeric.linalg import rref, singular_values, svd_factors, svd_rank
from symkin.kinds import TYPES, Kind
from symkin.tolerances import Tolerances

__all__ = ["Relation", "Motion", "Analysis", "analyze", "classify", "platform_twist", "TYPES"]



@dataclass(frozen=True)
class Motion:
    """One uncontrolled motion (inputs locked), as nodal velocities of the free nodes."""

    velocities: tuple[tuple[str, tuple[float, ...]], ...]
    moves_outputs: bool | None
    moves_platform: bool | None

    def as_dict(self) -> dict:
        return {"velocities": {n: list(v) for n, v in self.velocities},
                "moves_outputs": self.moves_outputs, "moves_platform": self.moves_platform}


@dataclass(frozen=True)
class Analysis:
    """Result of :func:`analyze`; read it, print it with :mod:`symkin.report`, or ``to_dict()``.

    Besides the classification: ``redundant_constraints`` and ``self_stresses`` (the statics
    of the configuration, :func:`symkin.analysis.statics.self_stresses`) and ``warnings``
    (sentences about an odd but legal model, :mod:`symkin.model.diagnostics`; empty when
    nothing is odd).
    """

    name: str
    dim: int
    dof: int
    mobility: int
    types: tuple[str, ...]
    input_labels: tuple[str, ...]
    output_labels: tuple[str, ...]
    input_rank: int | None
    output_rank: int | None
    input_relations: tuple[Relation, ...]
    output_relations: tuple[Relation, ...]
    locked_links: tuple[str, ...]
    locked_nodes: tuple[str, ...]
    uncontrolled_motions: tuple[Motion, ...]
    platform: str | None
    platform_dof: int | None
    platform_dof_generic: int | None
    platform_relations: tuple[Relation, ...]
    im_indicator: float | None
    dkp_input: float | None
    dkp_output: float | None
    singular_values: tuple[float, ...]
    tolerance: float
    threshold: float
    margin: float | None
    gosselin_angeles: str | None
    zlatanov: tuple[str, ...]
    motion: MotionSpace = field(repr=False, compare=False)
    redundant_constraints: int = 0
    self_stresses: tuple[Relation, ...] = ()
    warnings: tuple[str, ...] = ()
    #: every decision made, as ``(name, deciding value, threshold, margin)``: ``rank`` (the
    #: constraint matrix), ``IM`` (its (F+1)-th smallest singular value), ``DKP-input`` and
    #: ``DKP-output`` (the min(F, k)-th singular value of the restricted rows, eq. 12, 16);
    #: the margin is how many times the value is above (or below) the threshold
    decisions: tuple[tuple[str, float, float, float], ...] = ()

    @classmethod
    def _of(cls, **fields) -> "Analysis":
        """``Analysis(**fields)`` with every field given, without the frozen ``__init__``.

        A frozen dataclass sets each of its ~30 fields through ``object.__setattr__``,
        which is a tenth of an analysis; :func:`analyze` fills the instance's dictionary
        at once instead.  The result is the same object (equality, ``replace``, frozen).
        """
        obj = object.__new__(cls)
        obj.__dict__.update(fields)
        return obj

    @property
    def structure(self) -> bool:
        """``True`` for a structure (full-cycle mobility F = 0): rigid, or flexible when L > 0."""
        return self.mobility == 0

    @property
    def singular(self) -> bool:
        return bool(self.types)

    def has(self, kind: str) -> bool:
        return kind in self.types

    def to_dict(self) -> dict:
        """JSON-ready dictionary (the ``--json`` report)."""
        def rels(rs):
            return [r.as_dict() for r in rs]

        return {
            "name": self.name, "dim": self.dim, "dof": self.dof, "mobility": self.mobility,
            "singular": self.singular, "types": list(self.types),
            "input_labels": list(self.input_labels), "output_labels": list(self.output_labels),
            "input_rank": self.input_rank, "output_rank": self.output_rank,
            "platform": self.platform, "platform_dof": self.platform_dof,
            "platform_dof_generic": self.platform_dof_generic,
            "locked_links": list(self.locked_links), "locked_nodes": list(self.locked_nodes),
            "input_relations": rels(self.input_relations),
            "input_relations_r": [r.r for r in self.input_relations],
            "output_relations": rels(self.output_relations),
            "output_relations_r": [r.r for r in self.output_relations],
            "platform_relations": rels(self.platform_relations),
            "uncontrolled_motions": [m.as_dict() for m in self.uncontrolled_motions],
            "im_indicator": self.im_indicator,
            "dkp_input": self.dkp_input, "dkp_output": self.dkp_output,
            "singular_values": list(self.singular_values),
            "tolerance": self.tolerance, "threshold": self.threshold,
            "margin": self.margin if self.margin is not None and math.isfinite(self.margin) else None,
            "gosselin_angeles": self.gosselin_angeles, "zlatanov": list(self.zlatanov),
            "redundant_constraints": self.redundant_constraints,
            "self_stresses": rels(self.self_stresses),
            "warnings": list(self.warnings),
            "decisions": [{"decision": n, "value": v, "threshold": th,
                           "margin": m if math.isfinite(m) else None} for n, v, th, m in self.decisions],
        }


# ---------------------------------------------------------------------- helpers
class _Ranked(NamedTuple):
    """One SVD of a restricted parameter matrix ``M`` (k × L): rank, right and left null spaces."""

    rank: int
    null: np.ndarray  # (L, L - rank): β with M β = 0
    left: np.ndarray  # (k, k - rank): γ with γᵀ M = 0
    s: np.ndarray  # its singular values, descending (those of P̂ V: the DKP test's)


def _ranked(m: np.ndarray, tol: float) -> _Ranked:
    """Rank of ``m`` with the absolute threshold ``tol``, and both null spaces.

    The singular values come first; the singular vectors only when a null space is not
    empty (the generic square case needs none).
    """
    k, n = m.shape
    if k == 0:
        return _Ranked(0, np.eye(n), np.zeros((0, 0)), np.zeros(0))
    s = singular_values(m)
    rank = svd_rank(s, tol)
    if rank == k == n:
        return _Ranked(rank, np.zeros((n, 0)), np.zeros((k, 0)), s)
    u, _, vt = svd_factors(m)  # the rank stays the one decided on ``s``
    return _Ranked(rank, vt[rank:].T, u[:, rank:], s)


def _rank(m: np.ndarray, tol: float) -> int:
    """Rank of a restricted parameter matrix, absolute ``tol``."""
    return _ranked(m, tol).rank


def _relations(ranked: _Ranked, norms: np.ndarray, labels, tol: float) -> tuple[Relation, ...]:
    """Canonical (reduced row echelon) relations among the rows of ``M``, physical units.

    ``ranked.left`` (k × (k − rank), dimensionless) spans the relations (eq. 13, 17).
    """
    if ranked.left.shape[1] == 0:
        return ()
    return canonical_relations(ranked.left, labels, tol, norms)


def _canonical_motions(b: np.ndarray, tol: float) -> np.ndarray:
    """A canonical basis (columns) of span(b): reduced row echelon, each scaled to max |v| = 1."""
    if b.shape[1] == 0:
        return b
    r, _ = rref(b.T, max(tol, 1e-12))
    r = r / np.max(np.abs(r), axis=1, keepdims=True)
    return r.T


def _motion(mech: Mechanism, vec: np.ndarray, moves_out, moves_pf) -> Motion:
    dim = mech.dim
    fixed = set(mech.fixed)
    vel = tuple((n, tuple(float(v) for v in vec[dim * i: dim * i + dim]))
                for i, n in enumerate(mech.node_names) if n not in fixed)
    return Motion(vel, moves_out, moves_pf)


# ---------------------------------------------------------------------- main
def _dkp_values(mech: Mechanism, ms: MotionSpace, tolerances: Tolerances, p_hat: np.ndarray,
                singular: tuple[np.ndarray, np.ndarray], restricted: np.ndarray) -> tuple[float | None, float | None]:
    """Signed DKP values of the inputs and outputs (:func:`symkin.analysis.indicators.dkp_value`).

    ``p_hat`` are the unit input rows then output rows over the free coordinates,
    ``restricted`` their restrictions ``P̂ V`` and ``singular`` the singular values of those.  Defined where
    ``L = F``; None elsewhere and when there are no such parameters.  ``J_S`` is chosen by
    the evaluators' rule (:func:`symkin.analysis.indicators.basis_rows`) at this
    configuration: where no constraint row is redundant (every catalogue mechanism) that
    is every effective row, the evaluators' choice, and the values equal theirs.  With
    redundant rows the magnitude ``|det(P̂ V)|`` is the same for any choice; the sign is
    relative to the rows chosen and may differ from the evaluators'.
    """
    f = mech.mobility_value
    if ms.dof != f:
        return None, None
    k_in = mech.n_inputs
    if not p_hat.shape[0]:
        return None, None
    # a large model (sparse rows): the unsigned values, no J_S
    rows = None if ms.sparse is not None else \
        indicators.basis_rows(ms.J, f, tolerances, rank=ms.rank, nonzero=ms.effective_rows)
    sides = ((p_hat[:k_in], singular[0], restricted[:k_in]), (p_hat[k_in:], singular[1], restricted[k_in:]))
    if rows is None:
        return tuple(float(indicators.dkp_value(hat, sv, f)) if hat.shape[0] else None for hat, sv, _ in sides)
    js = ms.J if len(rows) == ms.J.shape[0] else ms.J[list(rows)]
    orientation = indicators.basis_orientation(js, ms.V_free) if f in (k_in, p_hat.shape[0] - k_in) else None
    return tuple(float(indicators.dkp_value(hat, sv, f, js, restricted_matrix=m, orientation=orientation))
                 if hat.shape[0] else None for hat, sv, m in sides)


def analyze(mech: Mechanism, tol: float | Tolerances | None = None) -> Analysis:
    """Analyse the configuration of ``mech`` (paper Fig. 9).

    Parameters
    ----------
    mech : Mechanism
    tol : float or Tolerances, optional
        The relative rank tolerance (a float), or all the tolerances (a
        :class:`~symkin.tolerances.Tolerances`); default ``Tolerances()`` (see
        :mod:`symkin.tolerances`).

    Notes
    -----
    Gosselin–Angeles and Zlatanov types, as §III relates them to IM and DKP:

    * Zlatanov **IIM** = IM; **II** = DKP-input; **IO** = DKP-output; **RO** when a motion
      with the inputs locked moves the outputs; **RI** when a motion with the outputs
      locked moves the inputs; **RPM** when a motion moves neither (each beyond what an
      under-actuated or under-sensed generic configuration already has).
    * Gosselin–Angeles **type 2** (direct kinematics) = DKP-input or RO; **type 1**
      (inverse kinematics) = DKP-output or RI; **type 3** when both hold.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> a = analyze(get("fourbar_appendix"))
    >>> a.dof, a.types
    (1, ())
    """
    tolerances = Tolerances.of(tol)
    return classify(rows_for(mech, tolerances), tolerances)


def classify(rows: ConfigurationRows, tol: float | Tolerances | None = None) -> Analysis:
    """Classify the configuration whose rows are ``rows`` (the computation of :func:`analyze`).

    ``rows.mechanism`` gives the topology, the labels, the inputs, outputs and platform;
    every number comes from ``rows`` (the constraint rows, and the parameter rows it
    carries or, for the others, the mechanism's rows at ``rows.xyz``).  The self-stresses'
    constraint labels are those of the mechanism's own configuration, the same at any
    configuration of a model without degenerate bodies or sliders (whose rows the paths
    stage does not take from its evaluators).

    Examples
    --------
    >>> from symkin.analysis.motion_space import model_rows
    >>> from symkin.model.catalogue import get
    >>> classify(model_rows(get("fourbar_dead_centre"))).types
    ('DKP-output', 'LIM')
    """
    tolerances = Tolerances.of(tol)
    t = tolerances.rank
    mech = rows.mechanism
    ms = motion_space_of(rows, tolerances)
    f = mech.mobility_value
    L = ms.dof
    types = []
    if indicators.is_im(L, f):
        types.append(Kind.IM)

    # inputs and outputs restricted in one go (rows are independent), then split
    io = mech.io_parameters
    m_io, n_io, lab_io = ms.restrict(io)
    k_in = mech.n_inputs
    m_in, n_in, lab_in = m_io[:k_in], n_io[:k_in], lab_io[:k_in]
    m_out, n_out, lab_out = m_io[k_in:], n_io[k_in:], lab_io[k_in:]
    k_out = m_out.shape[0]
    rk_in, rk_out = _ranked(m_in, t), _ranked(m_out, t)
    r_in, r_out, null_in, null_out = rk_in.rank, rk_out.rank, rk_in.null, rk_out.null
    if indicators.is_dkp(rk_in.s, k_in, f, tolerances, rank=rk_in.rank):
        types.append(Kind.DKP_INPUT)
    if indicators.is_dkp(rk_out.s, k_out, f, tolerances, rank=rk_out.rank):
        types.append(Kind.DKP_OUTPUT)

    locked_nodes, locked_links = _locked(mech, ms, t)
    if locked_links and f >= 1 and L > 0:  # LIM needs mobility to lose (issue 7 §1)
        types.append(Kind.LIM)

    platform_dof = generic = None
    pf_rel: tuple[Relation, ...] = ()
    m_pf = None
    if mech.platform is not None:
        twist, is_outputs = platform_twist(mech)
        if is_outputs:  # the usual case: the outputs are the platform's twist
            m_pf, n_pf, lab_pf, rk_pf = m_out, n_out, lab_out, rk_out
        else:
            m_pf, n_pf, lab_pf = ms.restrict(twist)
            rk_pf = _ranked(m_pf, t)
        platform_dof = rk_pf.rank
        pf_rel = _relations(rk_pf, n_pf, lab_pf, t)
        generic = mech.platform_dof if mech.platform_dof is not None else min(f, m_pf.shape[0])
        if platform_dof > generic:
            types.append(Kind.CONSTRAINT)

    # uncontrolled motions: inputs locked (eq. 11, 14), canonical basis
    motions: tuple[Motion, ...] = ()
    if k_in and null_in.shape[1]:
        basis = _canonical_motions(ms.V @ null_in, t)
        beta = ms.V.T @ basis  # coordinates of each motion in the orthonormal basis
        motions = tuple(
            _motion(mech, basis[:, c],
                    bool(np.linalg.norm(m_out @ beta[:, c]) > t) if k_out else None,
                    bool(np.linalg.norm(m_pf @ beta[:, c]) > t) if m_pf is not None else None)
            for c in range(basis.shape[1]))

    zl = []
    if Kind.IM in types:
        zl.append("IIM")
    if Kind.DKP_INPUT in types:
        zl.append("II")
    if Kind.DKP_OUTPUT in types:
        zl.append("IO")
    ro = ri = False
    if k_in and k_out:
        ro = _rank(m_out @ null_in, t) > max(0, f - k_in) if null_in.shape[1] else False
        ri = _rank(m_in @ null_out, t) > max(0, f - k_out) if null_out.shape[1] else False
        # rank([M_in; M_out]) >= max(r_in, r_out) (interlacing): its SVD only when it can matter
        rpm_bound = max(0, f - k_in - k_out)
        rpm = L - max(r_in, r_out) > rpm_bound and \
            L - _rank(np.vstack([m_in, m_out]), t) > rpm_bound
        zl += [name for name, on in (("RI", ri), ("RO", ro), ("RPM", rpm)) if on]
    type2 = Kind.DKP_INPUT in types or ro
    type1 = Kind.DKP_OUTPUT in types or ri
    ga = "type 3" if (type1 and type2) else "type 2" if type2 else "type 1" if type1 else None

    dkp_in, dkp_out = _dkp_values(mech, ms, tolerances, ms.unit_rows(io), (rk_in.s, rk_out.s), m_io)
    s = ms.singular_values
    shown = tuple(s[: min(s.size, L + 3)].tolist())
    margin = None
    if ms.threshold > 0:
        above = s[L] / ms.threshold if L < s.size else math.inf
        below = ms.threshold / s[L - 1] if L > 0 and s[L - 1] > ms.threshold * 1e-300 else math.inf
        margin = float(min(above, below))

    decisions = []
    if margin is not None:
        decisions.append(("rank", float(s[L]) if L < s.size else 0.0, float(ms.threshold), margin))
        if f < s.size and ms.threshold > 0:
            decisions.append((Kind.IM, float(s[f]), float(ms.threshold), _margin(float(s[f]), float(ms.threshold))))
    for name, ranked, k in ((Kind.DKP_INPUT, rk_in, k_in), (Kind.DKP_OUTPUT, rk_out, k_out)):
        m = min(f, k)
        if k and m > 0 and t > 0:
            value = float(ranked.s[m - 1]) if m <= ranked.s.size else 0.0
            decisions.append((str(name), value, float(t), _margin(value, float(t))))

    statics = self_stresses(mech, tolerances, ms)
    warnings = topology_warnings(mech)
    if (w := mobility_warning(mech, L)) is not None:
        warnings += (w,)
    if statics.warning is not None:
        warnings += (statics.warning,)

    return Analysis._of(
        name=mech.name, dim=mech.dim, dof=L, mobility=f, types=tuple(types),
        input_labels=lab_in, output_labels=lab_out,
        input_rank=r_in if k_in else None, output_rank=r_out if k_out else None,
        input_relations=_relations(rk_in, n_in, lab_in, t),
        output_relations=_relations(rk_out, n_out, lab_out, t),
        locked_links=locked_links, locked_nodes=locked_nodes, uncontrolled_motions=motions,
        platform=mech.platform, platform_dof=platform_dof, platform_dof_generic=generic,
        platform_relations=pf_rel, im_indicator=ms.im_indicator(f), dkp_input=dkp_in, dkp_output=dkp_out,
        singular_values=shown,
        tolerance=t, threshold=float(ms.threshold), margin=margin,
        gosselin_angeles=ga, zlatanov=tuple(zl), motion=ms,
        redundant_constraints=statics.redundant_constraints, self_stresses=statics.self_stresses,
        warnings=warnings, decisions=tuple(decisions))


def _margin(value: float, threshold: float) -> float:
    """How many times ``value`` is above ``threshold``, or below it (∞ for an exact zero)."""
    if value > threshold:
        return value / threshold
    return threshold / value if value > 0 else math.inf


_TWISTS: dict = {}


def platform_twist(mech: Mechanism) -> tuple[ParameterList, bool]:
    """The platform's twist as a parameter list, and whether it is the outputs (once per topology).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> twist, is_outputs = platform_twist(get("rrr_3"))
    >>> twist[0].kind, is_outputs
    ('twist', True)
    """
    got = _TWISTS.get(mech.topology)
    if got is None:
        twist = ParameterList((Parameter("twist", (mech.platform,)),))
        if len(_TWISTS) > 256:
            _TWISTS.clear()
        got = _TWISTS[mech.topology] = (twist, twist == tuple(mech.outputs))
    return got


def _locked(mech: Mechanism, ms: MotionSpace, t: float) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Free nodes that cannot move for any motion, and the moving links all of whose free nodes are such."""
    vf = ms.V_free  # rows of the free coordinates, node by node (a node is fixed as a whole)
    block = vf.reshape(vf.shape[0] // mech.dim, -1)
    if not (np.sqrt((block * block).sum(axis=1)) <= t).any():
        return (), ()  # the common case: every free node can move
    fixed = set(mech.fixed)
    still = {n for n, s in zip(mech.node_names, ms.node_speed_array().tolist()) if s <= t and n not in fixed}
    locked_nodes = tuple(n for n in mech.node_names if n in still)
    locked_links = tuple(name for name in mech.moving_links
                         if all(n in still for n in mech.link_nodes(name) if n not in fixed))
    return locked_nodes, locked_links
