"""A node on a fixed plane (spatial; the README's slider with ``point`` + ``normal``).

Row: ``n·ẋ_P = 0``, ``n`` the plane's unit normal.  Equation: ``(n·x_P − n·p) / |n|``
(linear; ``n·p`` the offset, a parameter of the CasADi closure).
"""
from __future__ import annotations

from symkin.constraints.algebra import dot
from symkin.constraints.base import Constraint, Equation, Row

__all__ = ["SliderPlane"]


class SliderPlane(Constraint):
    """Slider ``slider`` (a :class:`~symkin.model.mechanism.Slider`) of node position ``p``."""

    kind = "slider_plane"

    def __init__(self, slider, p: int):
        self.slider, self.p = slider, p
        self.owner = self.element = f"slider {slider.id}"
        self.where = f"sliders ({slider.id})"

    def size(self, dim: int) -> int:
        return 1

    def _vector(self, alg, which: str, values):
        what = f"{which} of slider {self.slider.id}"
        return alg.point(values, what) if which == "point" else alg.direction(values, what)

    def _normal(self, alg):
        """``(n, |n|)``: the normal as given (exact algebras) or normalised (numeric ones)."""
        n = self._vector(alg, "normal", self.slider.normal)
        length = alg.norm(n)
        return (n, length) if alg.exact else (tuple(c / length for c in n), alg.const(1))

    def rows(self, alg, X, X0) -> list[Row]:
        n, nn = self._normal(alg)
        return [Row(((self.p, alg.const(1), n),), nn)]

    def equations(self, alg, X, X0) -> list[Equation]:
        n, nn = self._normal(alg)
        point = self._vector(alg, "point", self.slider.point)
        off = alg.param(f"offset slider {self.slider.id}", alg.inner(n, point))
        return [Equation(dot(n, X[self.p]) - off, nn)]

    def nodes(self) -> tuple:
        """The node positions the constraint involves."""
        return (self.p,)
