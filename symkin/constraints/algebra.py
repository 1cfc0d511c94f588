"""The algebras a constraint definition is evaluated under (floats, CasADi SX, sympy).

A constraint module (:mod:`symkin.constraints`) writes its equations and rows once, over
*vectors* that are tuples of scalars and an algebra object ``alg`` that supplies what
differs between backends:

==========================  =====================  ==================  ==========================
operation                   :class:`Floats`        :class:`Casadi`     :class:`Sympy`
==========================  =====================  ==================  ==========================
``sqrt``, ``atan2``, ...    :mod:`math`            ``casadi``          ``sympy``
``const(v, what)``          ``float(v)``           ``float(v)``        a hook (exact, snapped)
``point``, ``direction``    floats                 floats              hooks (snapped, scaled)
``param(label, v)``         ``v``                  a new symbol        ``const(v)``
``pair_length(link, ...)``  ``|d|``                ``|d|``             a hook (a length symbol)
``model_length(...)``       ``(L², L)``            ``L`` a parameter   a hook (exact or scaled ``L²``)
``least_aligned(e, e0)``    at ``e`` (now)         ``if_else`` on e    at ``e0`` (the model)
``per_configuration``       True (now)             False (the model)   False (the model)
==========================  =====================  ==================  ==========================

``const`` is how a number of the model (a slider's point, a direction) enters; ``param``
a number the CasADi closure keeps as a parameter (a bar's length, a slider's offset);
``least_aligned`` the one discrete choice of the definitions (the coordinate axis from
which the normals of a 3D line are built): the numeric core decides it at every
configuration, the CasADi form reproduces that decision with ``if_else``, and the exact
forms decide it once, at the model's configuration (the normals then span the same
plane, so every product ``a aᵀ`` and every zero set agrees).

The vector helpers (:func:`dot`, :func:`cross`, ...) work on tuples under any algebra.
"""
from __future__ import annotations

import math
from typing import Callable

__all__ = ["Floats", "Casadi", "Sympy", "FLOATS", "dot", "cross", "sub", "add", "scaled", "perp", "normal_basis"]


# ---------------------------------------------------------------------- vectors (tuples)
def dot(a, b):
    """``a·b`` of two tuples."""
    out = a[0] * b[0]
    for k in range(1, len(a)):
        out = out + a[k] * b[k]
    return out


def cross(a, b) -> tuple:
    """``a × b`` of two 3-tuples."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def sub(a, b) -> tuple:
    """``a − b``."""
    return tuple(p - q for p, q in zip(a, b))


def add(a, b) -> tuple:
    """``a + b``."""
    return tuple(p + q for p, q in zip(a, b))


def scaled(s, a) -> tuple:
    """``s·a``."""
    return tuple(s * p for p in a)


def perp(a) -> tuple:
    """``a`` turned by +90° (planar)."""
    return (-a[1], a[0])


def normal_basis(u):
    """Orthonormal basis (rows) of the complement of unit vector ``u`` (2D: 1 row, 3D: 2 rows).

    Deterministic: in 3D the first normal is built from the coordinate axis least
    aligned with ``u``.  Quantities built as sums over this basis (projectors) do not
    depend on the choice.  (NumPy arrays; the numeric core's and the CasADi model's
    constant normals.)
    """
    import numpy as np

    if u.size == 2:
        return np.array([[-u[1], u[0]]])
    axis = np.zeros(3)
    axis[int(np.argmin(np.abs(u)))] = 1.0
    n1 = axis - axis.dot(u) * u
    n1 /= np.linalg.norm(n1)
    return np.vstack([n1, np.cross(u, n1)])


def _argmin_abs(v) -> int:
    """Index of the component of least magnitude (first one on ties, as ``np.argmin``)."""
    best, k = abs(v[0]), 0
    for i in range(1, len(v)):
        if abs(v[i]) < best:
            best, k = abs(v[i]), i
    return k


def _one_hot(k: int, n: int, one=1.0, zero=0.0) -> tuple:
    return tuple(one if i == k else zero for i in range(n))


def model_length(alg, p0, q0, label: str) -> tuple:
    """``(L², L)``, ``L = alg.param(label, |q0 − p0|)`` the model's length of a rigid pair (NumPy's norm:
    the CasADi closure's parameter to the last bit)."""
    import numpy as np

    length = alg.param(label, float(np.linalg.norm(np.subtract(q0, p0))))
    return length * length, length


# ---------------------------------------------------------------------- algebras
class Floats:
    """Plain Python floats (the numeric core; faster than NumPy for a constraint's few numbers)."""

    name = "floats"
    exact = False
    #: discrete decisions (a degenerate body's hull and frame) are taken at every configuration
    per_configuration = True
    sqrt = staticmethod(math.sqrt)
    atan2 = staticmethod(math.atan2)
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)

    def const(self, value, what: str = ""):
        return float(value)

    def param(self, label: str, value):
        return float(value)

    def pair_length(self, link, a, b, d):
        return math.sqrt(dot(d, d))

    def model_length(self, link, a, b, p0, q0, label: str):
        """``(L², L)`` of a rigid pair from its nodes' model positions ``p0``, ``q0``: :func:`model_length`."""
        return model_length(self, p0, q0, label)

    def point(self, values, what: str = "") -> tuple:
        return tuple(float(v) for v in values)

    direction = point

    def least_aligned(self, e, e0) -> tuple:
        return _one_hot(_argmin_abs(e), len(e))

    def zero(self):
        return 0.0

    # the vector operations of the numeric core, with NumPy's rounding (its rows, bit for bit)
    def norm(self, v):
        import numpy as np

        return float(np.linalg.norm(np.asarray(v, dtype=float)))

    def inner(self, a, b):
        import numpy as np

        return float(np.dot(np.asarray(a, dtype=float), np.asarray(b, dtype=float)))

    def unit_normals(self, u) -> list[tuple]:
        """The normals of the unit vector ``u``: :func:`normal_basis`."""
        import numpy as np

        return [tuple(map(float, n)) for n in normal_basis(np.asarray(u, dtype=float))]


#: the float algebra (stateless)
FLOATS = Floats()


class Casadi:
    """CasADi ``SX`` scalars; ``param`` makes closure parameters through ``param_hook(label, value)``."""

    name = "casadi"
    exact = False
    per_configuration = False

    def __init__(self, param_hook: Callable | None = None):
        import casadi as ca

        self.ca = ca
        self._param = param_hook
        self.sqrt, self.atan2, self.sin, self.cos = ca.sqrt, ca.atan2, ca.sin, ca.cos

    def const(self, value, what: str = ""):
        return float(value)

    def param(self, label: str, value):
        return self._param(label, float(value)) if self._param is not None else float(value)

    def pair_length(self, link, a, b, d):
        return self.ca.sqrt(dot(d, d))

    def model_length(self, link, a, b, p0, q0, label: str):
        """:func:`model_length`: the length is a closure parameter (``param``)."""
        return model_length(self, p0, q0, label)

    def point(self, values, what: str = "") -> tuple:
        return tuple(float(v) for v in values)

    direction = point

    def norm(self, v):
        if all(isinstance(c, (int, float)) for c in v):
            return FLOATS.norm(v)
        return self.ca.sqrt(dot(v, v))

    def inner(self, a, b):
        if all(isinstance(c, (int, float)) for c in tuple(a) + tuple(b)):
            return FLOATS.inner(a, b)
        return dot(a, b)

    def unit_normals(self, u) -> list[tuple]:
        """:func:`normal_basis` of the unit vector ``u``, the axis picked by ``if_else`` (as the core)."""
        if all(isinstance(c, (int, float)) for c in u):
            return FLOATS.unit_normals(u)
        if len(u) == 2:
            return [(-u[1], u[0])]
        axis = self.least_aligned(u, None)
        d = dot(axis, u)
        n1 = tuple(a - d * c for a, c in zip(axis, u))
        length = self.ca.sqrt(dot(n1, n1))
        n1 = tuple(c / length for c in n1)
        return [n1, cross(u, n1)]

    def least_aligned(self, e, e0) -> tuple:
        """The numeric core's choice (first minimum of ``|e_k|``) as ``if_else`` switches."""
        ca = self.ca
        if all(isinstance(v, (int, float)) for v in e):  # a constant direction: decided now
            return _one_hot(_argmin_abs(e), len(e))
        if len(e) == 2:
            a0, a1 = ca.fabs(e[0]), ca.fabs(e[1])
            return (a0 <= a1, ca.logic_not(a0 <= a1))
        a0, a1, a2 = ca.fabs(e[0]), ca.fabs(e[1]), ca.fabs(e[2])
        pick0 = ca.logic_and(a0 <= a1, a0 <= a2)
        pick1 = ca.logic_and(ca.logic_not(pick0), a1 <= a2)
        pick2 = ca.logic_not(ca.logic_or(pick0, pick1))
        return (pick0, pick1, pick2)

    def zero(self):
        return self.ca.SX(0)


class Sympy:
    """sympy expressions.

    ``const_hook(value, what)`` turns a number of the model into a sympy number (default:
    :func:`sympy.nsimplify`-free exact rational of its shortest decimal); ``length_hook(link,
    a, b, d)`` gives the length of a rigid pair (default ``sqrt(d·d)``; the symbolic rows
    give a design symbol); ``param`` is ``const``.  Discrete choices are taken at the
    model's configuration (``e0``).
    """

    name = "sympy"
    exact = True
    per_configuration = False

    def __init__(self, const_hook: Callable | None = None, length_hook: Callable | None = None,
                 point_hook: Callable | None = None, direction_hook: Callable | None = None,
                 squared_hook: Callable | None = None):
        import sympy as sp

        self.sp = sp
        self._const = const_hook
        self._length = length_hook
        self._squared = squared_hook
        self._point, self._direction = point_hook, direction_hook
        self.sqrt, self.sin, self.cos = sp.sqrt, sp.sin, sp.cos
        self.atan2 = sp.atan2

    def const(self, value, what: str = ""):
        if isinstance(value, self.sp.Basic):
            return value
        if self._const is not None:
            return self._const(value, what)
        return self.sp.Rational(repr(float(value)))

    def param(self, label: str, value):
        return self.const(value, label)

    def pair_length(self, link, a, b, d):
        if self._length is not None:
            return self._length(link, a, b, d)
        return self.sp.sqrt(self.sp.expand(dot(d, d)))

    def model_length(self, link, a, b, p0, q0, label: str):
        """``(L², L)`` of the pair ``a``-``b`` of ``link``: ``squared_hook(link, a, b, p0, q0)`` and its
        square root when given (the polynomial systems' exact or scaled squares), else :func:`model_length`."""
        if self._squared is not None:
            square = self._squared(link, a, b, p0, q0)
            return square, self.sp.sqrt(square)
        return model_length(self, p0, q0, label)

    def point(self, values, what: str = "") -> tuple:
        if self._point is not None:
            return self._point(values, what)
        return tuple(self.const(v, what) for v in values)

    def direction(self, values, what: str = "") -> tuple:
        if self._direction is not None:
            return self._direction(values, what)
        return tuple(self.const(v, what) for v in values)

    def least_aligned(self, e, e0) -> tuple:
        return _one_hot(_argmin_abs([float(v) for v in e0]), len(e0), self.sp.Integer(1), self.sp.Integer(0))

    def norm(self, v):
        return self.sp.sqrt(self.sp.expand(dot(v, v)))

    def inner(self, a, b):
        return dot(a, b)

    def zero(self):
        return self.sp.Integer(0)
