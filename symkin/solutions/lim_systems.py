"""The LIM systems of :func:`symkin.singularities`: one square system per link that can be locked alone.

A link whose motion relative to the ground has one parameter (planar: a moving link with
exactly one fixed node, a *rocker*) is locked (LIM, paper §V: a link whose free nodes cannot
move while the mechanism does) exactly where its rotation rate is zero along the
configuration curve, i.e. where the rotation, taken as an output, is dependent: the DKP
condition of the coordinate ``rotation:<link>``.  So the square system of
:func:`~symkin.solutions.dkp_system.dkp_system` for that coordinate, ``closure + det[∂R/∂v; rate
row of the link] = 0``, has as real solutions every configuration where the link is locked
(and every IM configuration, where ``∂R/∂v`` loses rank).  The input's own link is left out
(it is locked where the input is stationary: the DKP-input system), and so is the output's when
the output is that link's rotation (the DKP-output system is the same system).

>>> from symkin.model.catalogue import get
>>> [c.label for c in lim_coordinates(get("watt_sixbar"))]
['rotation:rocker']
>>> lim_coordinates(get("fourbar_appendix"))  # its rocker is the output: the DKP-output system
()
"""
from __future__ import annotations

from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate, input_coordinates, parse_input_label

__all__ = ["lim_coordinates", "lim_links"]


def lim_links(mech: Mechanism) -> tuple[str, ...]:
    """The links with a one-parameter motion relative to the ground: planar moving links with exactly one fixed node.

    Parameters
    ----------
    mech : Mechanism

    Returns
    -------
    tuple of str
        In the model's order; empty for a spatial model.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> lim_links(get("watt_sixbar"))
    ('crank', 'rocker', 'output')
    """
    if mech.dim != 2:
        return ()
    fixed = set(mech.fixed)
    return tuple(name for name in mech.moving_links if sum(n in fixed for n in mech.link_nodes(name)) == 1)


def lim_coordinates(mech: Mechanism, output: InputCoordinate | None = None) -> tuple[InputCoordinate, ...]:
    """The rotations ``rotation:<link>`` whose square systems give the LIM configurations (module docstring).

    Parameters
    ----------
    mech : Mechanism
        A planar 1-DOF model; its first input drives.
    output : InputCoordinate, optional
        The model's scalar output (default: its first output when that is one coordinate).

    Returns
    -------
    tuple of InputCoordinate
        One per link of :func:`lim_links` whose rotation is neither the input nor the output.
    """
    inputs = input_coordinates(mech)
    skip = {c.label for c in inputs[:1]}
    if output is None and mech.outputs:
        try:
            outs = input_coordinates(mech, mech.outputs)
        except SymkinError:
            outs = ()
        output = outs[0] if len(outs) == 1 else None
    if output is not None:
        skip.add(output.label)
    out = []
    for link in lim_links(mech):
        c = parse_input_label(mech, f"rotation:{link}")
        if c.label not in skip:
            out.append(c)
    return tuple(out)
