"""Finite input coordinates: the position-level quantities whose rates are kinematic parameters.

A path is driven by *input values* measured from the model's configuration (0 = as in the
file): the angle a link has turned (planar; spatial about a fixed axis), a slider's
displacement along its line, a node's coordinate, or a planar joint angle.  Each is a
CasADi expression of the nodal coordinates; its gradient (by automatic differentiation)
is the parameter row of :func:`symkin.numeric.geometric_matrix.parameter_rows` on the
constraint manifold, which a test checks.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from symkin.constraints import slider_constraint
from symkin.constraints.algebra import FLOATS, Casadi
from symkin.errors import SymkinError
from symkin.model.labels import CoordinateLabel, accepted_labels, parse_label
from symkin.model.labels import driving_labels
from symkin.model.labels import coordinate_labels
from symkin.model.joints import GROUND
from symkin.model.mechanism import AXES, Mechanism, Parameter

__all__ = ["InputCoordinate", "LinearInput", "accepted_input_labels", "input_coordinates", "parse_input_label",
           "segment_inputs"]


@dataclass(frozen=True)
class InputCoordinate(CoordinateLabel):
    """One scalar input coordinate: a finite quantity whose rate is a kinematic parameter.

    ``kind`` is ``"angle"`` (radians) or ``"length"`` (model units); ``label`` as in reports;
    ``component`` picks the axis of a whole-node velocity parameter (the label itself is
    resolved by :func:`symkin.model.labels.parse_label`).  :meth:`expression`
    builds its value as a CasADi expression of all nodal coordinates, measured from the
    model's configuration (angles relative to it, in (−π, π]); gradients come from it by
    automatic differentiation.
    """

    @classmethod
    def of(cls, c: CoordinateLabel) -> "InputCoordinate":
        return cls(c.label, c.kind, c.parameter, c.component)

    def expression(self, mech: Mechanism, x, x0: np.ndarray):
        """CasADi expression of the value; ``x`` is an (n·dim) SX/MX column of all coordinates."""
        return _expression(self, mech, x, x0)

    def absolute(self, mech: Mechanism, x: np.ndarray) -> float | None:
        """Absolute value: for a planar rotation, the direction of the link's first node → second node from +x."""
        if self.parameter.kind == "rotation" and mech.dim == 2:
            idx = mech.node_index()
            ns = mech.link_nodes(self.parameter.target[0])
            d = x[idx[ns[1]]] - x[idx[ns[0]]]
            return math.atan2(d[1], d[0])
        return None


def measuring_pair(mech: Mechanism, link: str) -> tuple[int, int]:
    """The link's first node and the node farthest from it (as for the rotation rows)."""
    idx = mech.node_index()
    ns = mech.link_nodes(link)
    xyz = np.array([c for _, c in mech.nodes])
    first = idx[ns[0]]
    far = max((idx[n] for n in ns), key=lambda k: float(np.linalg.norm(xyz[k] - xyz[first])))
    return first, far


def axis_angle_setup(mech: Mechanism, p: Parameter):
    """Fixed axis unit vector, a point on it, and the body node used to measure the angle."""
    fixed = set(mech.fixed)
    xyz = mech.coordinates()
    if isinstance(p.axis[0], str):
        if not all(n in fixed for n in p.axis):
            raise SymkinError(f"{p.labels(3)[0]}: a spatial rotation input on a path needs a fixed axis "
                              f"(nodes {p.axis[0]} and {p.axis[1]} must be fixed)")
        origin = np.array(xyz[p.axis[0]])
        a = np.subtract(xyz[p.axis[1]], xyz[p.axis[0]])
    else:
        ground = [n for n in mech.link_nodes(p.target[0]) if n in fixed]
        if not ground:
            raise SymkinError(f"{p.labels(3)[0]}: a spatial rotation input on a path needs a link pivoted "
                              "on a fixed axis")
        origin = np.array(xyz[ground[0]])
        a = np.array(p.axis, float)
    a = a / np.linalg.norm(a)
    idx = mech.node_index()
    x = np.array([c for _, c in mech.nodes])
    moving = [idx[n] for n in mech.link_nodes(p.target[0]) if n not in fixed]
    if not moving:
        raise SymkinError(f"{p.labels(3)[0]}: link {p.target[0]} has no moving node")
    radial = [np.linalg.norm(np.cross(a, x[k] - origin)) for k in moving]
    return a, origin, moving[int(np.argmax(radial))]


def relative_pair(mech: Mechanism, link: str, axis) -> tuple[int, int]:
    """Two nodes of ``link`` whose vector is the farthest from the (spatial) ``axis``.

    ``axis``: two node names or a vector.  The vector between them, projected normal to the
    axis, measures the link's angle about it (a spatial joint's angle, :func:`_expression`).
    """
    idx = mech.node_index()
    x = np.array([c for _, c in mech.nodes])
    a = x[idx[axis[1]]] - x[idx[axis[0]]] if isinstance(axis[0], str) else np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    ns = [idx[n] for n in mech.link_nodes(link)]

    def off(i, k):
        d = x[k] - x[i]
        return float(np.linalg.norm(d - (d @ a) * a))

    return max(((i, k) for i in ns for k in ns if i < k), key=lambda ik: off(*ik))


def _joint_angle(mech: Mechanism, p: Parameter, pairs, x: np.ndarray) -> float:
    """The angle of a spatial joint at the coordinates ``x`` (n × 3) by its node ``pairs``."""
    idx = mech.node_index()
    a = x[idx[p.axis[1]]] - x[idx[p.axis[0]]] if isinstance(p.axis[0], str) else np.asarray(p.axis, float)
    a = a / np.linalg.norm(a)
    d = [x[k] - x[i] for i, k in pairs]
    d = [v - (v @ a) * a for v in d]
    return math.atan2(float(np.cross(d[0], d[1]) @ a), float(d[0] @ d[1]))


def _expression(c: InputCoordinate, mech: Mechanism, x, x0: np.ndarray):
    import casadi as ca

    dim = mech.dim
    p = c.parameter

    def node(k):
        return x[dim * k: dim * k + dim]

    def planar_turn(link):
        if link == GROUND and link not in mech.link_names:  # the fixed frame of a joint model
            return 0.0
        i, j = measuring_pair(mech, link)
        d, d0 = node(j) - node(i), x0[j] - x0[i]
        return ca.atan2(d0[0] * d[1] - d0[1] * d[0], d0[0] * d[0] + d0[1] * d[1])

    if p.kind == "rotation" and dim == 2:
        return planar_turn(p.target[0])
    if p.kind == "joint" and dim == 2:
        turn = planar_turn(p.target[1]) - planar_turn(p.target[0])
        return ca.atan2(ca.sin(turn), ca.cos(turn))
    if p.kind == "joint":  # the angle from the first link's vector to the second's, about the axis
        idx = mech.node_index()
        if isinstance(p.axis[0], str):
            a = node(idx[p.axis[1]]) - node(idx[p.axis[0]])
            a = a / ca.norm_2(a)
        else:
            a = ca.DM(np.asarray(p.axis, float) / np.linalg.norm(p.axis))
        pairs = [relative_pair(mech, link, p.axis) for link in p.target]
        d = [node(k) - node(i) for i, k in pairs]
        d = [v - ca.dot(v, a) * a for v in d]
        turn = ca.atan2(ca.dot(ca.cross(d[0], d[1]), a), ca.dot(d[0], d[1])) - _joint_angle(mech, p, pairs, x0)
        return ca.atan2(ca.sin(turn), ca.cos(turn))
    if p.kind == "rotation":
        a, origin, k = axis_angle_setup(mech, p)
        r, r0 = node(k) - origin, x0[k] - origin
        r = r - ca.dot(r, a) * a
        r0 = r0 - (r0 @ a) * a
        return ca.atan2(ca.dot(ca.cross(ca.DM(r0), r), a), ca.dot(ca.DM(r0), r))
    if p.kind == "velocity":
        i = mech.node_index()[p.target[0]]
        axis = AXES.index(p.component) if p.component else c.component
        return x[dim * i + axis] - x0[i, axis]
    if p.kind == "slide":  # the slide of its definition (symkin.constraints), from the model's
        con = slider_constraint(mech, p.target[0])
        n = len(mech.nodes)
        X = [tuple(x[dim * k + a] for a in range(dim)) for k in range(n)]
        X0 = [tuple(map(float, x0[k])) for k in range(n)]
        return con.slide(Casadi(), X) - con.slide(FLOATS, X0)
    raise SymkinError(f"{c.label}: a {p.kind} cannot drive a path; use rotation, slide, velocity "
                      "components or joint inputs")


def input_coordinates(mech: Mechanism, params=None) -> tuple[InputCoordinate, ...]:
    """Scalar input coordinates of ``params`` (default: the model's inputs)."""
    return tuple(InputCoordinate.of(c) for c in coordinate_labels(mech, params))


def _driving(mech: Mechanism, params) -> list[InputCoordinate]:
    """The scalar coordinates of ``params`` that can drive a path (twists and the like are skipped)."""
    return [InputCoordinate.of(c) for c in driving_labels(mech, params)]


#: what :func:`parse_input_label` accepts, by kind: :func:`symkin.model.labels.accepted_labels` itself
accepted_input_labels = accepted_labels


def parse_input_label(mech: Mechanism, label: str) -> InputCoordinate:
    """The input coordinate named ``label`` (``rotation:crank``, ``slide:piston``, ``velocity:P.x`` ...).

    Matches the model's input labels first, then its output labels, then any rotation of a
    moving link (planar), slide of a slider or velocity component of a free node it can
    build (see :func:`accepted_input_labels`); an unknown label raises a
    :class:`SymkinError` that lists what is accepted.  The label is resolved by
    :func:`symkin.model.labels.parse_label` (one definition, shared with the symbolic stage).
    """
    return InputCoordinate.of(parse_label(mech, label))


@dataclass(frozen=True)
class LinearInput:
    """A linear combination ``Σ w_j · value_j`` of input coordinates (a path's drive or a held input).

    With one term of weight 1 it is that coordinate.  For a straight segment in input space
    (direction ``d``) the drive is ``λ = Σ d_j value_j / |d|²``, so the inputs are ``λ·d`` along
    it.  ``kind`` is the terms' common kind (``"angle"`` / ``"length"``), ``"dimensionless"``
    for the held combinations of a segment, or ``"segment"`` when the kinds are mixed.
    """

    label: str
    kind: str
    terms: tuple[tuple[InputCoordinate, float], ...]

    @classmethod
    def single(cls, c: InputCoordinate) -> "LinearInput":
        return cls(c.label, c.kind, ((c, 1.0),))

    def expression(self, mech: Mechanism, x, x0: np.ndarray):
        """CasADi expression of ``Σ w_j value_j`` (see :meth:`InputCoordinate.expression`)."""
        return sum(w * c.expression(mech, x, x0) for c, w in self.terms)

    def absolute(self, mech: Mechanism, x: np.ndarray) -> float | None:
        if len(self.terms) == 1 and self.terms[0][1] == 1.0:
            return self.terms[0][0].absolute(mech, x)
        return None


def segment_inputs(mech: Mechanism, direction: dict[str, float], length_scale: float
                   ) -> tuple[LinearInput, tuple[LinearInput, ...]]:
    """Drive and held combinations for the straight segment ``inputs = λ · direction``.

    ``direction`` maps input labels to their rate per unit ``λ`` (radians or model lengths);
    every other input of the model is held at its value; the held combinations span the
    complement of the direction among the named inputs (lengths divided by ``length_scale``
    so that the complement is scale invariant).
    """
    coords = [parse_input_label(mech, label) for label in direction]
    d = np.array([float(direction[label]) for label in direction])
    if not np.any(d):
        raise SymkinError("the direction in input space is zero")
    kinds = {c.kind for c in coords}
    label = " + ".join(f"{w:g}·{c.label}" for c, w in zip(coords, d)) if len(coords) > 1 else coords[0].label
    norm2 = float(d @ d)
    drive = LinearInput(label, kinds.pop() if len(kinds) == 1 else "segment",
                        tuple((c, float(w) / norm2) for c, w in zip(coords, d)))
    scales = np.array([1.0 if c.kind == "angle" else length_scale for c in coords])
    dhat = d / scales
    dhat = dhat / np.linalg.norm(dhat)
    # complement of dhat: the last rows of an orthonormal basis whose first row is dhat
    q, _ = np.linalg.qr(np.column_stack([dhat, np.eye(len(coords))]))
    held = [LinearInput(f"held {k + 1}", "dimensionless",
                        tuple((c, float(q[j, k + 1] / scales[j])) for j, c in enumerate(coords)))
            for k in range(len(coords) - 1)]
    named = {c.label for c in coords}
    held += [LinearInput.single(c) for c in input_coordinates(mech) if c.label not in named]
    return drive, tuple(held)
