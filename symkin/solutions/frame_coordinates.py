"""Coordinates of :func:`symkin.singularities` measured in the model's frame, at any configuration.

An input or output coordinate's value relative to the model's configuration (a CasADi
function of all nodal coordinates), angles wrapped to (−π, π], and the conversions between a
configuration given as a dict (node → coordinates), all nodal coordinates and the free ones.
"""
from __future__ import annotations

import math

import numpy as np

from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate, input_coordinates

__all__ = ["CoordinateValue", "as_dict", "flat_coordinates", "format_value", "free_coordinates", "output_coordinate",
           "wrap"]


class CoordinateValue:
    """A coordinate (input or output) measured from the *model's* configuration, at any configuration.

    Parameters
    ----------
    mech : Mechanism
        The model; its configuration is the origin of the coordinate.
    c : InputCoordinate
        The coordinate (``kind`` ``"angle"``, radians, or ``"length"``, model units).

    Calling it with all nodal coordinates (flat, in the order of ``mech.node_names``) gives the
    value (an angle in (−π, π] relative to the model's).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> m = get("fourbar_appendix")
    >>> value = CoordinateValue(m, input_coordinates(m)[0])
    >>> value(flat_coordinates(m, m.coordinates())), value.kind
    (0.0, 'angle')
    """

    def __init__(self, mech: Mechanism, c: InputCoordinate):
        import casadi as ca

        x = ca.SX.sym("x", len(mech.nodes) * mech.dim)
        x0 = np.array([p for _, p in mech.nodes], float)
        self.c, self.kind = c, c.kind
        self.f = ca.Function("value", [x], [c.expression(mech, x, x0)])

    def __call__(self, x: np.ndarray) -> float:
        return float(self.f(np.asarray(x, float).ravel()))


def wrap(v: float, kind: str) -> float:
    """An angle (``kind`` ``"angle"``) wrapped to (−π, π]; any other value unchanged.

    Parameters
    ----------
    v : float
        The value (radians for an angle).
    kind : {"angle", "length"}
        The coordinate's kind.

    Returns
    -------
    float

    Examples
    --------
    >>> round(wrap(4.0, "angle"), 6), wrap(4.0, "length")
    (-2.283185, 4.0)
    """
    return math.remainder(v, 2 * math.pi) if kind == "angle" else v


def free_coordinates(mech: Mechanism, configuration) -> np.ndarray:
    """Free nodal coordinates (flat, node by node in ``mech.free_nodes`` order) of a configuration.

    Parameters
    ----------
    mech : Mechanism
    configuration : dict or array_like
        Node → coordinates, or all nodal coordinates as an (n, dim) or flat array.

    Returns
    -------
    numpy.ndarray
    """
    if isinstance(configuration, dict):
        return np.concatenate([np.asarray(configuration[n], float) for n in mech.free_nodes])
    idx = mech.node_index()
    x = np.asarray(configuration, float).reshape(len(mech.nodes), mech.dim)
    return np.concatenate([x[idx[n]] for n in mech.free_nodes])


def flat_coordinates(mech: Mechanism, conf: dict) -> np.ndarray:
    """All nodal coordinates (flat, in ``mech.node_names`` order) of a configuration ``conf`` (node → coordinates).

    Parameters
    ----------
    mech : Mechanism
    conf : dict

    Returns
    -------
    numpy.ndarray
    """
    return np.concatenate([np.asarray(conf[n], float) for n in mech.node_names])


def as_dict(mech: Mechanism, x: np.ndarray) -> dict:
    """A configuration as a dict node → list of coordinates, from all nodal coordinates ``x`` (flat or (n, dim)).

    Parameters
    ----------
    mech : Mechanism
    x : array_like

    Returns
    -------
    dict
    """
    x = np.asarray(x, float).reshape(len(mech.nodes), mech.dim)
    return {n: [float(v) for v in x[k]] for k, n in enumerate(mech.node_names)}


def output_coordinate(mech: Mechanism) -> InputCoordinate | None:
    """The model's output as one scalar coordinate, or None (no output, a twist, several scalars).

    Parameters
    ----------
    mech : Mechanism

    Returns
    -------
    InputCoordinate or None

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> output_coordinate(get("fourbar_appendix")).label
    'rotation:rocker'
    """
    if not mech.outputs:
        return None
    try:
        coords = input_coordinates(mech, mech.outputs)
    except SymkinError:
        return None
    return coords[0] if len(coords) == 1 else None


def format_value(value: float, kind: str, unit: str) -> str:
    """A coordinate's value as a report writes it: an angle (radians) in ``unit``, a length in model units.

    Parameters
    ----------
    value : float
    kind : {"angle", "length"}
    unit : {"rad", "deg"}

    Returns
    -------
    str

    Examples
    --------
    >>> format_value(math.pi / 2, "angle", "deg"), format_value(2.5, "length", "deg")
    ('90°', '2.5')
    """
    if kind != "angle":
        return f"{value:.10g}"
    return f"{math.degrees(value):.10g}°" if unit == "deg" else f"{value:.10g} rad"
