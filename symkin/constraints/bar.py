"""A bar: a pair of nodes of a link at a fixed distance (paper eqs. A3 planar, A4 spatial).

Row: ``+u`` at node i, ``−u`` at node j, ``u = (x_j − x_i)/|x_j − x_i|``; its product
``a aᵀ`` is the paper's element matrix entry by entry.  Equation: ``(L² − |x_j − x_i|²) /
(2L)``, ``L`` the bar's length (a parameter of the CasADi closure; the polynomial systems give
``L²`` exactly or scaled, :meth:`~symkin.constraints.algebra.Sympy.model_length`): its gradient is the row
times ``|x_j − x_i|/L``, so exactly the row on the closure; the numerator is the
polynomial distance equation.

The numeric core keeps a vectorised evaluation of this definition for all bars at once
(:func:`symkin.numeric.geometric_matrix.constraint_rows`); ``tests/constraints`` keeps
the two equal.
"""
from __future__ import annotations

from symkin.constraints.algebra import dot, sub
from symkin.constraints.base import Constraint, Equation, Row

__all__ = ["Bar"]


class Bar(Constraint):
    """The pair ``(a, b)`` of link ``link`` (node names) at node positions ``(i, j)``."""

    kind = "bar"

    def __init__(self, link: str, a: str, b: str, i: int, j: int):
        self.link, self.a, self.b, self.i, self.j = link, a, b, i, j
        self.owner = f"link {link} ({a}-{b})"
        self.element = link
        self.where = f"links.{link}"

    def size(self, dim: int) -> int:
        return 1

    def rows(self, alg, X, X0) -> list[Row]:
        d = sub(X[self.j], X[self.i])
        one = alg.const(1)
        return [Row(((self.i, one, d), (self.j, -one, d)), alg.pair_length(self.link, self.a, self.b, d))]

    def _square(self, alg, X, X0) -> tuple:
        """``(|d|², L², L)``: the pair's squared distance and the model's ``(L², L)`` (the closure's
        parameter squared, or the polynomial systems' exact or scaled square)."""
        d = sub(X[self.j], X[self.i])
        square, length = alg.model_length(self.link, self.a, self.b, X0[self.i], X0[self.j],
                                          f"length {self.owner[5:]}")
        return dot(d, d), square, length

    def equations(self, alg, X, X0) -> list[Equation]:
        dd, square, length = self._square(alg, X, X0)
        return [Equation(square - dd, 2 * length)]

    def polynomial(self, alg, X, X0):
        """The distance equation ``|d|² − L²`` (the numerator of :meth:`equations` negated, as the
        polynomial systems write it; stated apart so that each keeps its rounding and sign of zero)."""
        dd, square, _ = self._square(alg, X, X0)
        return dd - square
