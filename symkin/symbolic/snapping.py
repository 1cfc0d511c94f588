"""Exact model data from floats: the simplest rationals within the geometry tolerance (issue 17 §4).

A model written with floats (``B1 = (-1.9686951572356552, 1.7497513230022688)`` on a crank of
length 2 "up to rounding") taken at face value (``sp.Rational(repr(v))``) gives squared lengths
with thirty digits, so that the eliminated loci do not factor.  Before an elimination the numbers
it uses are *snapped*: each is replaced by the simplest rational (smallest denominator, then
the nearest) within an absolute tolerance

    ``Tolerances.geometry × length_scale``   (``1e-6 ×`` the mean link length by default),

the tolerance the model-file checks use for "same point" and "on the line".  What is snapped is
what the elimination uses, never the free nodes' coordinates (which the snapped lengths need not
admit as rationals):

* the coordinates of the fixed nodes (pivots);
* the squared distances between the node pairs of each link (squared lengths, which the closure
  uses and which are rational for a model with rational coordinates, unlike the lengths), within
  ``2 l ×`` the tolerance; equal ones snap once, to one rational (a length shared by two links
  stays shared);
* the affine coordinates of a body's further nodes in its frame (dimensionless, within the
  tolerance divided by the frame's length).

A number that is already the simplest within the tolerance (``2.5``) is kept and not reported;
every other one is listed in :attr:`ModelSnap.snapped`, which ``symkin conditions --in`` prints.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import sympy as sp

from symkin.model.mechanism import Mechanism
from symkin.symbolic.symbols import decimal_rational
from symkin.tolerances import Tolerances

__all__ = ["simplest_rational", "Snap", "ModelSnap", "snap_model"]


def simplest_rational(value: float, tol: float) -> sp.Rational:
    """The simplest rational ``p/q`` with ``|p/q − value| ≤ tol``: the smallest denominator ``q``,
    and of those the nearest to ``value`` (so that an integer stays itself whatever the unit).

    The smallest denominator by continued fractions of the interval's ends (the Stern–Brocot
    descent); ``tol = 0`` gives the float's exact value.

    >>> simplest_rational(2.0000000000000004, 1e-6), simplest_rational(0.333333, 1e-6)
    (2, 1/3)
    >>> simplest_rational(-1.25, 1e-9), simplest_rational(3.14159, 2e-3), simplest_rational(1562500.0, 5.0)
    (-5/4, 22/7, 1562500)
    """
    value, tol = float(value), abs(float(tol))
    if not math.isfinite(value):
        raise ValueError(f"cannot snap {value!r}")
    if value < 0:
        return -simplest_rational(-value, tol)
    lo, hi = Fraction(value) - Fraction(tol), Fraction(value) + Fraction(tol)
    if lo <= 0:
        return sp.Integer(0)
    q = _simplest_between(lo, hi).denominator
    return sp.Rational(round(Fraction(value) * q), q)  # the nearest of that denominator: 1562500, not 1562496


def _simplest_between(lo: Fraction, hi: Fraction) -> Fraction:
    """The simplest fraction in the closed interval ``[lo, hi]``, ``0 < lo ≤ hi``."""
    fl = math.floor(lo)
    if fl == lo:
        return Fraction(fl)
    if fl + 1 <= hi:
        return Fraction(fl + 1)
    # lo and hi share the integer part: recurse on the reciprocals of the fractional parts
    inner = _simplest_between(1 / (hi - fl), 1 / (lo - fl))
    return fl + 1 / inner


@dataclass(frozen=True)
class Snap:
    """One snapped number: ``what`` (e.g. ``"length of crank1 (A1-B1)"``), the float, the rational."""

    what: str
    value: float
    exact: sp.Rational

    def as_dict(self) -> dict:
        return {"what": self.what, "value": self.value, "snapped": sp.sstr(self.exact)}

    def __str__(self) -> str:
        return f"{self.what} {self.value!r} -> {sp.sstr(self.exact)}"


@dataclass
class ModelSnap:
    """The exact numbers of a model for an elimination, and which of them were snapped.

    Attributes
    ----------
    tolerance : float
        The absolute tolerance (model units): ``relative × length_scale``.
    relative : float
        ``Tolerances.geometry``.
    pivots : dict
        Fixed node → its exact coordinates.
    snapped : list of Snap
        The numbers that changed (those whose face value is not the simplest within the tolerance).
    """

    mech: Mechanism
    tolerance: float
    relative: float
    pivots: dict = field(default_factory=dict)
    snapped: list = field(default_factory=list)
    _lengths: dict = field(default_factory=dict)
    _seen: list = field(default_factory=list)

    def number(self, value: float, what: str, scale: float = 1.0) -> sp.Rational:
        """``value`` snapped within ``tolerance / scale``, reported in :attr:`snapped` when it changed."""
        tol = self.tolerance / scale
        out = simplest_rational(value, tol)
        if out != decimal_rational(value) and all(s.what != what for s in self.snapped):
            self.snapped.append(Snap(what, float(value), out))
        return out

    def squared_length(self, link: str, i: str, j: str) -> sp.Rational:
        """The exact squared distance of nodes ``i``, ``j`` of ``link``, as the closure uses it.

        Snapped within ``2 l × tolerance`` (a length within the tolerance); squared lengths equal
        up to that snap once, to one rational (a length shared by two links stays shared).
        """
        key = (link,) + tuple(sorted((i, j)))
        if key in self._lengths:
            return self._lengths[key]
        nodes = dict(self.mech.nodes)
        value = math.dist(nodes[i], nodes[j])
        square, tol = value * value, 2.0 * value * self.tolerance
        what = f"squared length of {link} ({i}-{j})"
        for previous, exact in self._seen:  # a length equal to one already snapped snaps to it
            if abs(previous - square) <= tol and abs(float(exact) - square) <= tol:
                out = exact
                if out != decimal_rational(square):
                    self.snapped.append(Snap(what, square, out))
                break
        else:
            out = self.number(square, what, self.tolerance / tol)
            self._seen.append((square, out))
        self._lengths[key] = out
        return out

    def length(self, link: str, i: str, j: str) -> sp.Expr:
        """``sqrt`` of :meth:`squared_length` (a rational when the snapped square is one)."""
        return sp.sqrt(self.squared_length(link, i, j))

    @property
    def changed(self) -> bool:
        return bool(self.snapped)

    def note(self) -> str:
        """One sentence for the report (empty when nothing was snapped)."""
        if not self.snapped:
            return ""
        return (f"{len(self.snapped)} number(s) of the model snapped to the simplest rationals within "
                f"{self.relative:g} x the length scale ({self.tolerance:.3g}): "
                + "; ".join(str(s) for s in self.snapped))

    def as_dict(self) -> dict:
        return {"relative_tolerance": self.relative, "tolerance": self.tolerance,
                "snapped": [s.as_dict() for s in self.snapped]}


def snap_model(mech: Mechanism, tolerances: Tolerances | float | None = None) -> ModelSnap:
    """The model's pivots snapped (lengths and affine coordinates are snapped on demand,
    :meth:`ModelSnap.length`, :meth:`ModelSnap.number`).

    >>> from symkin.model.catalogue import get
    >>> s = snap_model(get("five_bar"))
    >>> s.pivots["A1"], s.length("crank1", "A1", "B1"), s.snapped
    ((-1, 0), 1, [])
    >>> s.squared_length("distal1", "B1", "P"), s.length("distal1", "B1", "P")
    (4, 2)
    """
    tol = Tolerances.of(tolerances)
    snap = ModelSnap(mech, tol.geometry * mech.length_scale, tol.geometry)
    nodes = dict(mech.nodes)
    for n in mech.fixed:
        snap.pivots[n] = tuple(snap.number(v, f"coordinate {'xyz'[a]} of pivot {n}")
                               for a, v in enumerate(nodes[n]))
    return snap
