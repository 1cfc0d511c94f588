"""A node P on the moving line through nodes A, C of a link (the README's ``line`` + ``link``).

Rows: ``n·(ẋ_P − (1−t) ẋ_A − t ẋ_C) = 0`` for each normal ``n`` of ``e = x_C − x_A``,
``t = (x_P − x_A)·e / |e|²`` the position of P on A→C (a rigid velocity field is affine
along the line).  Written over the pair's length ``l`` (a design symbol in the symbolic
rows) with polynomial blocks: ``(l² ẋ_P − (l² − τ) ẋ_A − τ ẋ_C)·n / (l²|n|)``, ``τ =
(x_P − x_A)·e``.  Equations: ``n·(x_P − x_A) / |n|`` (the cross product ``e × (x_P − x_A)``
in the plane; degree 2 and 3 in space).  Slide coordinate: ``(x_P − x_A)·e/|e|``; its rate row (:meth:`SliderMovingLine.rate_rows`, the
slide of P relative to the line's rigid velocity field): ``ê·(ẋ_P − (1−t) ẋ_A − t ẋ_C)``
(exact algebras: ``e·(l² ẋ_P − (l² − τ) ẋ_A − τ ẋ_C) / l³``).
"""
from __future__ import annotations

from symkin.constraints.algebra import dot, sub
from symkin.constraints.base import Constraint, Equation, Row, normals

__all__ = ["SliderMovingLine"]


class SliderMovingLine(Constraint):
    """Slider ``slider`` (a :class:`~symkin.model.mechanism.Slider`); node positions ``p``, ``a``, ``c``."""

    kind = "slider_moving_line"

    def __init__(self, slider, p: int, a: int, c: int):
        self.slider, self.p, self.a, self.c = slider, p, a, c
        self.owner = self.element = f"slider {slider.id}"
        self.where = f"sliders ({slider.id})"

    def size(self, dim: int) -> int:
        return dim - 1

    def rows(self, alg, X, X0) -> list[Row]:
        s = self.slider
        e = sub(X[self.c], X[self.a])
        r = sub(X[self.p], X[self.a])
        e0 = sub(X0[self.c], X0[self.a])
        if alg.exact:  # polynomial blocks over the pair's length (a design symbol in the symbolic rows)
            length = alg.pair_length(s.link, s.line[0], s.line[1], e)
            l2 = length * length
            tau = dot(r, e)
            return [Row(((self.p, l2, n), (self.a, -(l2 - tau), n), (self.c, -tau, n)), l2 * nn)
                    for n, nn in normals(alg, e, e0, length)]
        # numeric: the same row as unit normals and t = (x_P − x_A)·u/|e| (the core's rounding)
        length = alg.norm(e)
        t = alg.inner(r, tuple(c / length for c in e)) / length
        one = alg.const(1)
        return [Row(((self.p, one, n), (self.a, -(one - t), n), (self.c, -t, n)), nn)
                for n, nn in normals(alg, e, e0, length)]

    def equations(self, alg, X, X0) -> list[Equation]:
        e = sub(X[self.c], X[self.a])
        r = sub(X[self.p], X[self.a])
        return [Equation(dot(n, r), nn) for n, nn in normals(alg, e, sub(X0[self.c], X0[self.a]), alg.norm(e))]

    def slide(self, alg, X):
        """The slide of P along the line from A (model units)."""
        e = sub(X[self.c], X[self.a])
        return dot(sub(X[self.p], X[self.a]), e) / alg.norm(e)

    def slide_equation(self, alg, X) -> Equation:
        """The slide as ``(x_P − x_A)·e`` over the pair's length (``alg.pair_length``: a rigid
        length where the algebra knows it, the loci's snapped one)."""
        s = self.slider
        e = sub(X[self.c], X[self.a])
        return Equation(dot(sub(X[self.p], X[self.a]), e), alg.pair_length(s.link, s.line[0], s.line[1], e))

    def rate_rows(self, alg, X, X0) -> list[Row]:
        """The slide rate of P along the line, relative to the line's rigid motion (module docstring)."""
        e = sub(X[self.c], X[self.a])
        r = sub(X[self.p], X[self.a])
        if alg.exact:
            s = self.slider
            length = alg.pair_length(s.link, s.line[0], s.line[1], e)
            l2 = length * length
            tau = dot(r, e)
            return [Row(((self.p, l2, e), (self.a, -(l2 - tau), e), (self.c, -tau, e)), l2 * length)]
        length = alg.norm(e)
        u = tuple(c / length for c in e)
        t = alg.inner(r, u) / length
        one = alg.const(1)
        return [Row(((self.p, one, u), (self.a, -(one - t), u), (self.c, -t, u)), one)]

    def nodes(self) -> tuple:
        """The node positions the constraint involves."""
        return (self.p, self.a, self.c)

    def slide_polynomial(self, X, X0, value):
        """The polynomial systems' prescribed slide: ``(x_P − x_A)·e − (s₀ + value)·|e₀|`` (bilinear;
        the slide from A is ``s₀ + value``, ``s₀`` the model's, the pair's length ``|e₀|`` fixed; ``X0``
        the model's positions, ``value`` in the units of ``X``)."""
        import numpy as np

        e0 = np.asarray(X0[self.c]) - np.asarray(X0[self.a])
        rho = float((np.asarray(X0[self.p]) - np.asarray(X0[self.a])) @ e0 / np.linalg.norm(e0)) + value
        return dot(sub(X[self.p], X[self.a]), sub(X[self.c], X[self.a])) - rho * float(np.linalg.norm(e0))
