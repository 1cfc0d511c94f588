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

    def rows(self, alg, X, X0) -> list[Row]:
        n = self._vector(alg, "normal", self.slider.normal)
        return [Row(((self.p, alg.const(1), n),), alg.sqrt(dot(n, n)))]

    def equations(self, alg, X, X0) -> list[Equation]:
        n = self._vector(alg, "normal", self.slider.normal)
        point = self._vector(alg, "point", self.slider.point)
        off = alg.param(f"offset slider {self.slider.id}", dot(n, point))
        return [Equation(dot(n, X[self.p]) - off, alg.sqrt(dot(n, n)))]
