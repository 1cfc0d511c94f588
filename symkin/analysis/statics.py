"""Statics, the dual of the motion space: self-stresses and redundant constraints.

The motion space (paper §IV, eqs. 8-10) is the right null space of the reduced
constraint matrix ``J`` (free coordinates only; ``G = Jᵀ J``, eq. 3).  Its left null
space holds the **self-stresses**: row weights ``ω`` with ``ωᵀ J = 0``, forces in the
constraints that balance at every free node with no load applied.  Each independent
self-stress is one **redundant constraint** — the paper's method "facilitates the choice
of actuators and redundant devices" (§I); a parallelogram with a third parallel crank or
a Bennett linkage carries them in every configuration, a structure at a special
geometry (collinear bars) gains one.

Bar rows are unit vectors (+u at node i, −u at node j, ``u`` from i to j), so the weight
of a bar row is the bar's axial force, tension positive, up to the common factor of the
stress.

What is *not* a redundant constraint of the mechanism, and is excluded:

* rows that touch no free coordinate (a bar between two fixed nodes, a ground link):
  they carry the ground's own forces;
* stresses supported inside a single rigid body: a planar body of n ≥ 4 nodes is
  modelled by its n(n−1)/2 pair rows of rank 2n − 3 (spatial: 3n − 6), a degenerate
  (collinear / coplanar) body by pair rows plus rigidity rows; a body is rigid whatever
  rows model it, so these stresses are modelling artefacts;
* the second copy of a node pair shared by two bodies (two spatial bodies sharing two
  nodes form a revolute pair, README "Pairs"; both bodies keep the pair's distance):
  the stress "one copy against the other" is an artefact of the same kind.

The reported stresses span the part of the left null space orthogonal to these
artefacts; the count is ``m − rank(J) − (artefacts)`` with ``m`` the rows touching a
free coordinate.  The rank is the motion space's own decision, ``rank(J) = n_free − L``
(threshold ``tol · σ_max``, :mod:`symkin.tolerances`), so statics and kinematics never
disagree and the count is scale invariant; when ``m = n_free − L`` there is no stress and
nothing more is computed.

Constraint labels (one per row): a bar link → its name (``coupler``); a pair inside a
body → ``body[N1-N2]``; the rigidity rows of a degenerate body → ``body:rigidity[k]``
(k = 1, 2, … in the body's row order); on the sparse path of a large model
(:mod:`symkin.analysis.sparse`), the affine row of node N along axis a of a body in its
O(k) form → ``body:affine[N.a]`` (frame dependent); a slider → ``slider:<id>`` (``slider:<id>[k]``
when it has several rows: a line in space).

Canonical form: the stresses are put in reduced row echelon form over the rows in the
core's order (links, then sliders), except that the rows whose weight depends on the
frame (rigidity rows, the rows of a slider on a line in space: :func:`frame_dependent`)
come last, so that pivots fall on bars whenever they can.  The coefficients of
frame-independent rows then do not change under a rigid motion or a change of units;
those of frame-dependent rows may change sign or mix (they are forces along normals that
symkin chose).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symkin.analysis.constraint_labels import PAIR_OWNER, RIGIDITY_OWNER, constraint_labels
from symkin.analysis.motion_space import MotionSpace, motion_space
from symkin.analysis.relations import Relation, canonical_relations
from symkin.model.mechanism import Mechanism
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.numeric.linalg import left_null_space
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["Statics", "self_stresses", "constraint_labels", "frame_dependent"]

@dataclass(frozen=True)
class Statics:
    """Result of :func:`self_stresses`.

    Attributes
    ----------
    redundant_constraints : int
        Number of independent self-stresses (modelling artefacts excluded).
    self_stresses : tuple of Relation
        One per independent self-stress, ``{constraint label: coefficient}``, canonical
        (reduced row echelon over the rows' order, pivot 1, exact zeros).  For a large
        model (:mod:`symkin.analysis.sparse`): the fundamental stresses of its dependent
        rows (coefficient 1 on the dependent row), a sequence computed when read.
    artefacts : int
        Number of excluded stresses internal to the rows that model rigid bodies.
    warning : str or None
        Why the self-stresses of a large model are not listed (their number is exact):
        the sparse path found no well-conditioned basis of rows and the dense left null
        space would not fit (:mod:`symkin.analysis.sparse`); None otherwise.
    """

    redundant_constraints: int
    self_stresses: tuple[Relation, ...]
    artefacts: int
    warning: str | None = None


def frame_dependent(label: str) -> bool:
    """Whether a constraint row's weight depends on the frame (a normal chosen by symkin).

    A degenerate body's rigidity rows and the two rows of a slider on a line in space use
    normals that symkin picks (any orthonormal basis of the normal space would do), so
    their coefficients turn with the frame; bars, body pairs and one-row sliders do not.

    >>> frame_dependent("coupler[B-C]"), frame_dependent("platform:rigidity[1]"), frame_dependent("slider:s[2]")
    (False, True, True)
    """
    return ":rigidity[" in label or ":affine[" in label or (label.startswith("slider:") and label.endswith("]"))


def _artefact_vectors(mech: Mechanism, owners, jr: np.ndarray, threshold: float) -> np.ndarray:
    """Stresses (columns, over the rows of ``jr``) internal to the rows modelling bodies.

    Only links of 3+ nodes are bodies: a bar is one constraint, and two bars (or a bar and
    a body) on the same node pair are a real redundancy.
    """
    size = {name: len(ns) for name, ns in mech.links}
    bodies: dict[str, list[int]] = {}
    pairs: dict[frozenset, list[int]] = {}
    degenerate = set()
    for r, o in enumerate(owners):
        if (m := PAIR_OWNER.match(o)) and size[m["link"]] >= 3:
            bodies.setdefault(m["link"], []).append(r)
            pairs.setdefault(frozenset((m["a"], m["b"])), []).append(r)
        elif m := RIGIDITY_OWNER.match(o):
            bodies.setdefault(m["link"], []).append(r)
            degenerate.add(m["link"])
    cols = []
    for name, rows in bodies.items():
        # a simplex (n ≤ dim + 1 nodes spanning their hull: no rigidity rows) has independent
        # pair rows, also once some of its nodes are fixed: no internal stress to look for
        if len(rows) < 2 or (size[name] <= mech.dim + 1 and name not in degenerate):
            continue
        inside = left_null_space(jr[rows], threshold)
        for c in range(inside.shape[1]):
            v = np.zeros(jr.shape[0])
            v[rows] = inside[:, c]
            cols.append(v)
    for group in pairs.values():
        for r in group[1:]:  # a bar row does not depend on the pair's order: the copies are equal
            v = np.zeros(jr.shape[0])
            v[group[0]], v[r] = 1.0, -1.0
            cols.append(v / np.sqrt(2.0))
    return np.array(cols).T.reshape(jr.shape[0], len(cols))


def _orthonormal_range(a: np.ndarray, tol: float) -> np.ndarray:
    """Orthonormal basis (columns) of the range of ``a``; relative threshold ``tol``."""
    if a.shape[1] == 0:
        return a
    u, s, _ = np.linalg.svd(a, full_matrices=False)
    return u[:, : int(np.count_nonzero(s > tol * s[0]))]


def self_stresses(mech: Mechanism, tolerances: Tolerances = DEFAULT,
                  motion: MotionSpace | None = None) -> Statics:
    """Self-stresses and redundant constraints of ``mech`` at its configuration.

    Parameters
    ----------
    mech : Mechanism
    tolerances : Tolerances
        The rank threshold is ``tolerances.rank · σ_max`` of the reduced ``J``, the motion
        space's (see the module docstring for what is excluded and why).
    motion : MotionSpace, optional
        The motion space already computed for ``mech`` (its threshold is reused).

    Returns
    -------
    Statics

    Examples
    --------
    A parallelogram four-bar with a third parallel crank carries one self-stress; the
    crank forces balance the coupler (sum and moment of three parallel forces):

    >>> from symkin.model.catalogue import get
    >>> st = self_stresses(get("double_parallelogram"))
    >>> force = st.self_stresses[0].as_dict()
    >>> st.redundant_constraints, [round(force[c], 9) for c in ("crank", "middle", "rocker")]
    (1, [1.0, 3.0, -4.0])
    """
    ms = motion if motion is not None else motion_space(mech, tolerances)
    if ms.sparse is not None:
        return _sparse_statics(mech, ms, tolerances)
    jf = ms.J  # the reduced constraint rows the motion space was computed from
    touching = ms.effective_rows
    rank = ms.rank  # the motion space's own rank decision
    count = touching.size - rank
    if count <= 0:  # the common case: no stress at all, nothing more to compute
        return Statics(0, (), 0)
    rows = constraint_rows(mech, tolerances)  # for the owners of the rows
    jr = jf[touching]
    owners = tuple(rows.owners[r] for r in touching)
    labels = constraint_labels(mech, rows.owners)
    labels = tuple(labels[r] for r in touching)
    u = np.linalg.svd(jr, full_matrices=True)[0]
    stresses = u[:, rank:]  # left null space: the last m − rank left singular vectors
    artefacts = _orthonormal_range(_artefact_vectors(mech, owners, jr, ms.threshold), tolerances.rank)
    if artefacts.shape[1]:
        keep = max(count - artefacts.shape[1], 0)
        rest = stresses - artefacts @ (artefacts.T @ stresses)  # orthogonal to the artefacts
        stresses = np.linalg.svd(rest, full_matrices=False)[0][:, :keep]
    order = sorted(range(len(labels)), key=lambda r: frame_dependent(labels[r]))  # stable
    relations = canonical_relations(stresses[order], [labels[r] for r in order], tolerances.rank)
    return Statics(redundant_constraints=stresses.shape[1], self_stresses=relations,
                   artefacts=count - stresses.shape[1])


def _sparse_statics(mech: Mechanism, ms: MotionSpace, tolerances: Tolerances) -> Statics:
    """:func:`self_stresses` of a large model: fundamental stresses, computed when read (:mod:`symkin.analysis.sparse`)."""
    from symkin.analysis.sparse import sparse_stresses

    stresses, artefacts = sparse_stresses(mech, ms, tolerances)
    warning = None if not stresses.unlisted else \
        f"the {stresses.count} self-stresses are counted but not listed: {stresses.unlisted}"
    return Statics(redundant_constraints=stresses.count, self_stresses=stresses, artefacts=artefacts,
                   warning=warning)
