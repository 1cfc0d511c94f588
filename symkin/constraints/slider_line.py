"""A node on a fixed line (the README's slider with ``point`` + ``direction``).

Rows: ``n·ẋ_P = 0`` for each normal ``n`` of the line (one in the plane, two in space:
:func:`symkin.constraints.base.normals`).  Equations: ``(n·x_P − n·p) / |n|`` (linear;
``n·p`` is the slider's offset, a parameter of the CasADi closure).  Slide coordinate:
``(x_P − p)·d/|d|``; its rate row (:meth:`SliderLine.rate_rows`): ``d·ẋ_P/|d|``.
"""
from __future__ import annotations

from symkin.constraints.algebra import dot, sub
from symkin.constraints.base import Constraint, Equation, Row, normals

__all__ = ["SliderLine"]


class SliderLine(Constraint):
    """Slider ``slider`` (a :class:`~symkin.model.mechanism.Slider`) of node position ``p``."""

    kind = "slider_line"

    def __init__(self, slider, p: int):
        self.slider, self.p = slider, p
        self.owner = self.element = f"slider {slider.id}"
        self.where = f"sliders ({slider.id})"

    def size(self, dim: int) -> int:
        return dim - 1

    def _vector(self, alg, which: str, values):
        what = f"{which} of slider {self.slider.id}"
        return alg.point(values, what) if which == "point" else alg.direction(values, what)

    def _normals(self, alg):
        d = self._vector(alg, "direction", self.slider.direction)
        return normals(alg, d, self.slider.direction, alg.norm(d))

    def rows(self, alg, X, X0) -> list[Row]:
        one = alg.const(1)
        return [Row(((self.p, one, n),), nn) for n, nn in self._normals(alg)]

    def equations(self, alg, X, X0) -> list[Equation]:
        point = self._vector(alg, "point", self.slider.point)
        ns = self._normals(alg)
        out = []
        for k, (n, nn) in enumerate(ns):
            off = alg.param(f"offset slider {self.slider.id}" + (f" [{k}]" if len(ns) > 1 else ""),
                            alg.inner(n, point))
            out.append(Equation(dot(n, X[self.p]) - off, nn))
        return out

    def slide(self, alg, X):
        """The slide of the node along the line, from the slider's point (model units)."""
        eq = self.slide_equation(alg, X)
        return eq.numerator / eq.denominator

    def slide_equation(self, alg, X) -> Equation:
        """The slide as ``(x_P − p)·d`` over ``|d|``."""
        d = self._vector(alg, "direction", self.slider.direction)
        point = self._vector(alg, "point", self.slider.point)
        return Equation(dot(sub(X[self.p], point), d), alg.norm(d))

    def rate_rows(self, alg, X, X0) -> list[Row]:
        """The slide rate ``d·ẋ_P / |d|``: the unit direction at P (exact algebras: ``d`` over ``|d|``)."""
        d = self._vector(alg, "direction", self.slider.direction)
        if alg.exact:
            return [Row(((self.p, alg.const(1), d),), alg.norm(d))]
        length = alg.norm(d)
        return [Row(((self.p, alg.const(1), tuple(c / length for c in d)),), alg.const(1))]

    def nodes(self) -> tuple:
        """The node positions the constraint involves."""
        return (self.p,)

    def slide_polynomial(self, X, X0, value):
        """The polynomial systems' prescribed slide: ``d̂·(x_P − x⁰_P) − value`` (linear; ``X0`` the
        model's positions, ``value`` in the units of ``X``)."""
        import numpy as np

        d = np.array(self.slider.direction, float)
        d = d / np.linalg.norm(d)
        return dot([float(v) for v in d], sub(X[self.p], tuple(X0[self.p]))) - value
