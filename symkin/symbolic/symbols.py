"""Symbols named after what owns them, and exact numbers from a model's floats.

Names (sympy prints them with subscripts, e.g. ``\\theta_{coupler}`` in LaTeX):

=====================  ===========================================================
``x_B``, ``y_B``, ``z_B``  coordinates of node ``B`` (nodal coordinates)
``theta_coupler``        angle of link ``coupler``: direction of its first node → second node
``l_crank``              length of bar ``crank`` (first node → second node of a link)
``l_platform_C1_C3``     distance between nodes ``C1`` and ``C3`` of body ``platform``
``beta_platform_C1_C3``  angle of ``C1 → C3`` relative to the body's axis (``theta_platform``)
``s_piston``             position of the node of moving-line slider ``piston`` along its line
=====================  ===========================================================

Every configuration symbol is real; lengths are positive (so that a length never
counts as a geometric factor of a condition).
"""
from __future__ import annotations

import math

import sympy as sp

__all__ = ["coordinate_symbol", "angle_symbol", "length_symbol", "offset_symbol", "slide_symbol",
           "exact", "exact_angle", "decimal_rational"]


def decimal_rational(value: float) -> sp.Rational:
    """The float ``value`` as the rational its shortest decimal denotes (``0.1 → 1/10``)."""
    return sp.Rational(repr(float(value)))


def coordinate_symbol(axis: str, node: str) -> sp.Symbol:
    """``x_B``: component ``axis`` (``"x"``, ``"y"``, ``"z"``) of node ``node``."""
    return sp.Symbol(f"{axis}_{node}", real=True)


def angle_symbol(link: str) -> sp.Symbol:
    """``theta_<link>``: angle of the link's first node → second node, from +x."""
    return sp.Symbol(f"theta_{link}", real=True)


def length_symbol(link: str, i: str | None = None, j: str | None = None) -> sp.Symbol:
    """``l_<link>`` (first two nodes) or ``l_<link>_<i>_<j>`` (another pair of a body)."""
    name = f"l_{link}" if i is None else f"l_{link}_{i}_{j}"
    return sp.Symbol(name, positive=True)


def offset_symbol(link: str, i: str, j: str) -> sp.Symbol:
    """``beta_<link>_<i>_<j>``: angle of ``i → j`` minus the body angle ``theta_<link>``."""
    return sp.Symbol(f"beta_{link}_{i}_{j}", real=True)


def slide_symbol(slider: str) -> sp.Symbol:
    """``s_<slider>``: distance of the slider's node from the line's first node, along the line."""
    return sp.Symbol(f"s_{slider}", real=True)


def _close(candidate: sp.Expr, value: float) -> bool:
    try:
        approx = float(candidate)
    except (TypeError, ValueError):
        return False
    return abs(approx - value) <= 4 * math.ulp(max(abs(value), 1e-300))


def exact(value: float) -> sp.Expr:
    """A sympy number for the float ``value``: exact when a short exact form reproduces it.

    ``0.1 → 1/10``, ``0.9219544457292887 → sqrt(85)/10``, ``-3.4641016151377544 → -2*sqrt(3)``;
    a value with no short form stays a (15-digit) ``Float``, which is more honest than a
    rational with thirty digits.

    >>> exact(0.25), exact(2.5), exact(-3.4641016151377544), exact(0.123456789012345)
    (1/4, 5/2, -2*sqrt(3), 0.123456789012345)
    """
    value = float(value)
    if value == int(value) and abs(value) < 2 ** 53:
        return sp.Integer(int(value))
    rational = decimal_rational(value)
    if rational.q <= 10 ** 6:
        return rational
    candidate = sp.nsimplify(value)
    if _close(candidate, value) and sp.count_ops(candidate) <= 8 and len(str(candidate)) <= 16:
        return candidate
    return sp.Float(value, 15)


def exact_angle(value: float) -> sp.Expr:
    """An angle as a sympy number: a simple multiple of π, or ``atan`` of a simple rational
    (``± π``), when that reproduces the float; else :func:`exact`.

    >>> exact_angle(1.0471975511965976), exact_angle(-3.141592653589793), exact_angle(0.9272952180016122)
    (pi/3, -pi, atan(4/3))
    """
    value = float(value)
    if value == 0.0:
        return sp.Integer(0)
    ratio = sp.nsimplify(value / math.pi, tolerance=1e-13, rational=True)
    if ratio.q <= 24 and _close(ratio * sp.pi, value):
        return ratio * sp.pi
    t = sp.nsimplify(math.tan(value), tolerance=1e-12, rational=True)
    if t.q <= 1000 and abs(t.p) <= 10 ** 6:
        for shift in (0, sp.pi, -sp.pi):
            candidate = sp.atan(t) + shift
            if _close(candidate, value):
                return candidate
    return exact(value)
