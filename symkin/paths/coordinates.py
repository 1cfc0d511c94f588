"""Finite input coordinates: the position-level quantities whose rates are kinematic parameters.

A path is driven by *input values* measured from the model's configuration (0 = as in the
file): the angle a link has turned (planar; spatial about a fixed axis), a slider's
displacement along its line, a node's coordinate, or a planar joint angle.  Each
coordinate's gradient with respect to the free nodal coordinates is the parameter row of
:func:`symkin.numeric.geometric_matrix.parameter_rows` on the constraint manifold, which a
test checks.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from symkin.errors import SymkinError
from symkin.model.mechanism import AXES, Mechanism, Parameter
from symkin.numeric.geometric_matrix import free_mask

__all__ = ["InputCoordinate", "input_coordinates", "parse_input_label"]


@dataclass(frozen=True)
class InputCoordinate:
    """One scalar input coordinate ``value(x)`` (all coordinates ``x``, shape (n, dim)) and its gradient.

    ``kind`` is ``"angle"`` (radians) or ``"length"`` (model units); ``label`` as in reports.
    """

    label: str
    kind: str
    parameter: Parameter
    component: int = 0

    def value(self, mech: Mechanism, x: np.ndarray, x0: np.ndarray) -> float:
        """Value at ``x`` measured from the configuration ``x0`` (angles wrapped to (−π, π])."""
        return _value(self, mech, x, x0)

    def absolute(self, mech: Mechanism, x: np.ndarray) -> float | None:
        """Absolute value (planar rotation: direction of first node → reference node from +x)."""
        if self.parameter.kind == "rotation" and mech.dim == 2:
            i, j = _pair(mech, self.parameter.target[0])
            d = x[j] - x[i]
            return math.atan2(d[1], d[0])
        return None

    def gradient(self, mech: Mechanism, x: np.ndarray) -> np.ndarray:
        """Gradient with respect to the free coordinates (flattened in node order)."""
        g = _gradient(self, mech, x)
        return g.ravel()[free_mask(mech)]


def _pair(mech: Mechanism, link: str) -> tuple[int, int]:
    """The link's first node and the node farthest from it (as for the rotation rows)."""
    idx = mech.node_index()
    ns = mech.link_nodes(link)
    xyz = np.array([c for _, c in mech.nodes])
    first = idx[ns[0]]
    far = max((idx[n] for n in ns), key=lambda k: float(np.linalg.norm(xyz[k] - xyz[first])))
    return first, far


def _planar_angle(x, i, j) -> float:
    d = x[j] - x[i]
    return math.atan2(d[1], d[0])


def _wrap(a: float) -> float:
    return math.atan2(math.sin(a), math.cos(a))


def _axis_angle_setup(mech: Mechanism, p: Parameter):
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


def _value(c: InputCoordinate, mech, x, x0) -> float:
    p = c.parameter
    if p.kind == "rotation" and mech.dim == 2:
        i, j = _pair(mech, p.target[0])
        return _wrap(_planar_angle(x, i, j) - _planar_angle(x0, i, j))
    if p.kind == "joint":
        (i1, j1), (i2, j2) = _pair(mech, p.target[0]), _pair(mech, p.target[1])
        turn = (_planar_angle(x, i2, j2) - _planar_angle(x0, i2, j2)) - (_planar_angle(x, i1, j1) - _planar_angle(x0, i1, j1))
        return _wrap(turn)
    if p.kind == "rotation":
        a, origin, k = _axis_angle_setup(mech, p)
        r, r0 = x[k] - origin, x0[k] - origin
        r, r0 = r - (r @ a) * a, r0 - (r0 @ a) * a
        return math.atan2(float(np.cross(r0, r) @ a), float(r0 @ r))
    if p.kind == "velocity":
        i = mech.node_index()[p.target[0]]
        axis = AXES.index(p.component) if p.component else c.component
        return float(x[i, axis] - x0[i, axis])
    if p.kind == "slide":
        s = mech.slider(p.target[0])
        idx = mech.node_index()
        k = idx[s.node]
        if s.kind == "moving_line":
            a_, c_ = idx[s.line[0]], idx[s.line[1]]

            def along(xx):
                u = xx[c_] - xx[a_]
                return float((xx[k] - xx[a_]) @ (u / np.linalg.norm(u)))
            return along(x) - along(x0)
        d = np.array(s.direction, float)
        return float((x[k] - x0[k]) @ (d / np.linalg.norm(d)))
    raise SymkinError(f"{c.label}: a {p.kind} cannot drive a path; use rotation, slide, velocity "
                      "components or joint inputs")


def _gradient(c: InputCoordinate, mech, x) -> np.ndarray:
    """Gradient over all coordinates, shape (n, dim)."""
    p = c.parameter
    g = np.zeros_like(x)
    if p.kind in ("rotation", "joint") and mech.dim == 2:
        links = [(p.target[0], 1.0)] if p.kind == "rotation" else [(p.target[1], 1.0), (p.target[0], -1.0)]
        for link, sign in links:
            i, j = _pair(mech, link)
            d = x[j] - x[i]
            perp = np.array([-d[1], d[0]]) / float(d @ d)
            g[j] += sign * perp
            g[i] -= sign * perp
        return g
    if p.kind == "rotation":
        a, origin, k = _axis_angle_setup(mech, p)
        r = x[k] - origin
        r = r - (r @ a) * a
        g[k] = np.cross(a, r) / float(r @ r)
        return g
    if p.kind == "velocity":
        i = mech.node_index()[p.target[0]]
        g[i, AXES.index(p.component) if p.component else c.component] = 1.0
        return g
    if p.kind == "slide":
        s = mech.slider(p.target[0])
        idx = mech.node_index()
        k = idx[s.node]
        if s.kind == "moving_line":
            a_, c_ = idx[s.line[0]], idx[s.line[1]]
            e = x[c_] - x[a_]
            le = float(np.linalg.norm(e))
            u = e / le
            w = x[k] - x[a_]
            du = (w - (w @ u) * u) / le  # derivative of (w·u) with respect to x_C
            g[k] += u
            g[a_] -= u + du
            g[c_] += du
            return g
        d = np.array(s.direction, float)
        g[k] = d / np.linalg.norm(d)
        return g
    raise SymkinError(f"{c.label}: a {p.kind} cannot drive a path")


def input_coordinates(mech: Mechanism, params=None) -> tuple[InputCoordinate, ...]:
    """Scalar input coordinates of ``params`` (default: the model's inputs)."""
    out = []
    for p in (mech.inputs if params is None else params):
        labels = p.labels(mech.dim)
        if p.kind == "twist" or (p.kind == "velocity" and p.component is None):
            if p.kind == "twist":
                raise SymkinError(f"{labels[0]}: a twist cannot drive a path; use velocity components and a rotation")
            out += [InputCoordinate(lab, "length", p, k) for k, lab in enumerate(labels)]
            continue
        kind = "angle" if p.kind in ("rotation", "joint") else "length"
        out.append(InputCoordinate(labels[0], kind, p))
    return tuple(out)


def parse_input_label(mech: Mechanism, label: str) -> InputCoordinate:
    """The input coordinate named ``label`` (``rotation:crank``, ``slide:piston``, ``velocity:P.x`` ...).

    Matches the model's input labels first, then any rotation/slide/velocity it can build.
    """
    for c in input_coordinates(mech):
        if c.label == label:
            return c
    kind, _, rest = label.partition(":")
    target, _, comp = rest.partition(".")
    if kind == "rotation" and target in mech.link_names and mech.dim == 2:
        return input_coordinates(mech, [Parameter("rotation", (target,))])[0]
    if kind == "slide":
        try:
            return input_coordinates(mech, [Parameter("slide", (mech.slider(target).id,))])[0]
        except KeyError:
            pass
    if kind == "velocity" and target in mech.node_names and comp in AXES[: mech.dim]:
        return input_coordinates(mech, [Parameter("velocity", (target,), component=comp)])[0]
    known = ", ".join(c.label for c in input_coordinates(mech)) or "none"
    raise SymkinError(f"unknown input {label!r} (the model's inputs: {known})")
