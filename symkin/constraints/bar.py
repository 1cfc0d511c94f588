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

    def equations(self, alg, X, X0) -> list[Equation]:
        d = sub(X[self.j], X[self.i])
        # (L², L) of the model: the closure's parameter squared, or the polynomial systems' exact square
        square, length = alg.model_length(self.link, self.a, self.b, X0[self.i], X0[self.j],
                                          f"length {self.owner[5:]}")
        # L² − |d|² written −(|d|² − L²): the same floats (IEEE rounding is symmetric), and the polynomial
        # systems' |d|² − L² is its negation exactly (sympy's −(−x) is x: their expressions as before)
        return [Equation(-(dot(d, d) - square), 2 * length)]
