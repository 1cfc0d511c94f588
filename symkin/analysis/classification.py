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
  V, hence of Ω; §IV-B-3).
* **constraint** — the platform's DOF (rank of its twist rows) exceeds its generic DOF.

Gosselin–Angeles and Zlatanov types are derived from the same subspaces (see
:func:`analyze`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.analysis.motion_space import MotionSpace, motion_space
from symkin.model.mechanism import Mechanism, Parameter
from symkin.numeric.linalg import rref, svd_factors, svd_rank
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["Relation", "Motion", "Analysis", "analyze", "TYPES"]

TYPES = ("IM", "DKP-input", "DKP-output", "LIM", "constraint")


@dataclass(frozen=True)
class Relation:
    """A dependency ``Σ γ_k q_k = 0`` among kinematic parameters (eq. 13), physical units.

    ``coefficients`` pairs each label with its γ (the pivot's γ is 1); ``r`` is the number
    of parameters involved.
    """

    coefficients: tuple[tuple[str, float], ...]

    @property
    def r(self) -> int:
        return len(self.coefficients)

    def as_dict(self) -> dict[str, float]:
        return dict(self.coefficients)

    def __str__(self) -> str:
        terms = []
        for k, (label, c) in enumerate(self.coefficients):
            sign = "-" if c < 0 else "+"
            mag = abs(c)
            coef = "" if math.isclose(mag, 1.0, rel_tol=1e-9) else f"{mag:.6g}·"
            terms.append(f"{'-' if sign == '-' else ''}{coef}{label}" if k == 0 else f" {sign} {coef}{label}")
        return "".join(terms) + " = 0"


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
    """Result of :func:`analyze`; read it, print it with :mod:`symkin.report`, or ``to_dict()``."""

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
    singular_values: tuple[float, ...]
    tolerance: float
    threshold: float
    margin: float | None
    gosselin_angeles: str | None
    zlatanov: tuple[str, ...]
    motion: MotionSpace = field(repr=False, compare=False)

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
            "singular_values": list(self.singular_values),
            "tolerance": self.tolerance, "threshold": self.threshold,
            "margin": self.margin if self.margin is not None and math.isfinite(self.margin) else None,
            "gosselin_angeles": self.gosselin_angeles, "zlatanov": list(self.zlatanov),
        }


# ---------------------------------------------------------------------- helpers
@dataclass(frozen=True)
class _Ranked:
    """One SVD of a restricted parameter matrix ``M`` (k × L): rank, right and left null spaces."""

    rank: int
    null: np.ndarray  # (L, L - rank): β with M β = 0
    left: np.ndarray  # (k, k - rank): γ with γᵀ M = 0


def _ranked(m: np.ndarray, tol: float) -> _Ranked:
    """Rank of ``m`` with the absolute threshold ``tol``, and both null spaces."""
    k, n = m.shape
    if k == 0:
        return _Ranked(0, np.eye(n), np.zeros((0, 0)))
    u, s, vt = svd_factors(m)
    rank = svd_rank(s, tol)
    return _Ranked(rank, vt[rank:].T, u[:, rank:])


def _rank(m: np.ndarray, tol: float) -> int:
    """Rank of a restricted parameter matrix, absolute ``tol``."""
    return _ranked(m, tol).rank


def _relations(ranked: _Ranked, norms: np.ndarray, labels, tol: float) -> tuple[Relation, ...]:
    """Canonical (reduced row echelon) relations among the rows of ``M``, physical units.

    ``ranked.left`` (k × (k − rank), dimensionless) spans the relations; the reduced row
    echelon form over the parameters' order makes them canonical.
    """
    gamma = ranked.left
    if gamma.shape[1] == 0:
        return ()
    r, pivots = rref(gamma.T, max(tol, 1e-12))
    out = []
    for row, p in zip(r, pivots):
        phys = row / norms * norms[p]
        coeffs = tuple((labels[k], float(phys[k])) for k in range(len(labels)) if row[k] != 0.0)
        out.append(Relation(coeffs))
    return tuple(out)


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
def analyze(mech: Mechanism, tol: float | None = None, tolerances: Tolerances = DEFAULT) -> Analysis:
    """Analyse the configuration of ``mech`` (paper Fig. 9).

    Parameters
    ----------
    mech : Mechanism
    tol : float, optional
        Relative rank tolerance (overrides ``tolerances.rank``; see :mod:`symkin.tolerances`).

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
    tolerances = tolerances.with_rank(tol)
    t = tolerances.rank
    ms = motion_space(mech, tolerances)
    f = mech.mobility_value
    L = ms.dof
    types = []
    if L > f:
        types.append("IM")

    # inputs and outputs restricted in one go (rows are independent), then split
    m_io, n_io, lab_io = ms.restrict(tuple(mech.inputs) + tuple(mech.outputs))
    k_in = mech.n_inputs
    m_in, n_in, lab_in = m_io[:k_in], n_io[:k_in], lab_io[:k_in]
    m_out, n_out, lab_out = m_io[k_in:], n_io[k_in:], lab_io[k_in:]
    k_out = m_out.shape[0]
    rk_in, rk_out = _ranked(m_in, t), _ranked(m_out, t)
    r_in, r_out, null_in, null_out = rk_in.rank, rk_out.rank, rk_in.null, rk_out.null
    if k_in and r_in < min(f, k_in):
        types.append("DKP-input")
    if k_out and r_out < min(f, k_out):
        types.append("DKP-output")

    locked_nodes, locked_links = _locked(mech, ms, t)
    if locked_links:
        types.append("LIM")

    platform_dof = generic = None
    pf_rel: tuple[Relation, ...] = ()
    m_pf = None
    if mech.platform is not None:
        twist = (Parameter("twist", (mech.platform,)),)
        if twist == tuple(mech.outputs):  # the usual case: the outputs are the platform's twist
            m_pf, n_pf, lab_pf, rk_pf = m_out, n_out, lab_out, rk_out
        else:
            m_pf, n_pf, lab_pf = ms.restrict(twist)
            rk_pf = _ranked(m_pf, t)
        platform_dof = rk_pf.rank
        pf_rel = _relations(rk_pf, n_pf, lab_pf, t)
        generic = mech.platform_dof if mech.platform_dof is not None else min(f, m_pf.shape[0])
        if platform_dof > generic:
            types.append("constraint")

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
    if "IM" in types:
        zl.append("IIM")
    if "DKP-input" in types:
        zl.append("II")
    if "DKP-output" in types:
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
    type2 = "DKP-input" in types or ro
    type1 = "DKP-output" in types or ri
    ga = "type 3" if (type1 and type2) else "type 2" if type2 else "type 1" if type1 else None

    s = ms.singular_values
    shown = tuple(s[: min(s.size, L + 3)].tolist())
    margin = None
    if ms.threshold > 0:
        above = s[L] / ms.threshold if L < s.size else math.inf
        below = ms.threshold / s[L - 1] if L > 0 and s[L - 1] > ms.threshold * 1e-300 else math.inf
        margin = float(min(above, below))

    return Analysis(
        name=mech.name, dim=mech.dim, dof=L, mobility=f, types=tuple(types),
        input_labels=lab_in, output_labels=lab_out,
        input_rank=r_in if k_in else None, output_rank=r_out if k_out else None,
        input_relations=_relations(rk_in, n_in, lab_in, t),
        output_relations=_relations(rk_out, n_out, lab_out, t),
        locked_links=locked_links, locked_nodes=locked_nodes, uncontrolled_motions=motions,
        platform=mech.platform, platform_dof=platform_dof, platform_dof_generic=generic,
        platform_relations=pf_rel, im_indicator=ms.im_indicator(f), singular_values=shown,
        tolerance=t, threshold=float(ms.threshold), margin=margin,
        gosselin_angeles=ga, zlatanov=tuple(zl), motion=ms)


def _locked(mech: Mechanism, ms: MotionSpace, t: float) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Free nodes that cannot move for any motion, and the moving links all of whose free nodes are such."""
    fixed = set(mech.fixed)
    still = {n for n, s in zip(mech.node_names, ms.node_speed_array().tolist()) if s <= t and n not in fixed}
    if not still:
        return (), ()
    locked_nodes = tuple(n for n in mech.node_names if n in still)
    locked_links = tuple(name for name in mech.moving_links
                         if all(n in still for n in mech.link_nodes(name) if n not in fixed))
    return locked_nodes, locked_links
