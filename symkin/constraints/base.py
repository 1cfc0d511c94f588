"""What a constraint definition is: rows and equations over an algebra.

Every kind of constraint (a bar, a slider on a line, a pair with rows of its own, ...) is
one small class in its own module of :mod:`symkin.constraints`.  It states once

* its **velocity rows** (the paper's dimensionless rows ``a`` over the nodal velocity
  components, eqs. 1-2, A3-A4): :meth:`Constraint.rows` returns :class:`Row` objects,
  ``a = (Σ coef · vec placed at node) / scale``;
* its **position equations**: :meth:`Constraint.equations` returns :class:`Equation`
  objects, the residual ``numerator / denominator`` whose gradient is the row (on the
  closure), with a numerator that is a polynomial of the node coordinates when
  :attr:`Constraint.polynomial` (the form the polynomial systems use).

Both are written over an algebra (:mod:`symkin.constraints.algebra`): node positions
``X[k]`` (tuples of the algebra's scalars, ``k`` the node's position in
``mech.node_names``) and the model's positions ``X0`` (floats: discrete choices are taken
there by the exact algebras).  Each backend assembles the rows its own way: a NumPy row,
a CasADi ``SX`` row, a :class:`symkin.symbolic.rows.SymRow`.
"""
from __future__ import annotations

from typing import NamedTuple

from symkin.constraints.algebra import cross, dot, perp

__all__ = ["Row", "Equation", "Constraint", "normals"]


class Row(NamedTuple):
    """One velocity row: ``(Σ coef·vec at node) / scale``; ``terms`` are ``(node, coef, vec)``."""

    terms: tuple
    scale: object

    def blocks(self) -> dict:
        """Node → the unscaled block ``Σ coef·vec`` (a tuple; nodes in first-appearance order)."""
        out: dict = {}
        for node, coef, vec in self.terms:
            v = tuple(coef * c for c in vec)
            out[node] = tuple(a + b for a, b in zip(out[node], v)) if node in out else v
        return out


class Equation(NamedTuple):
    """One position equation ``numerator / denominator = 0`` (``denominator`` nonzero)."""

    numerator: object
    denominator: object


class Constraint:
    """Base of the constraint kinds (see the module docstring).

    Attributes
    ----------
    kind : str
        The module's name (``"bar"``, ``"slider_line"``, ...).
    owner : str
        What owns the rows, as reports print it (``"slider s1"``, ``"link coupler (B-C)"``).
    element : str
        The element whose geometric matrix the rows make (paper eqs. 1-2).
    polynomial : bool
        Whether the numerators of :meth:`equations` are polynomials of the coordinates.
    why_not_polynomial : str
        What its position equation does, for the message of a polynomial backend that
        refuses it (:func:`symkin.constraints.polynomial_constraints`).
    where : str
        The model key to name when a backend refuses the constraint (a joint, a slider).
    """

    kind = "base"
    polynomial = True
    why_not_polynomial = "states a position equation"
    owner = ""
    element = ""
    where = ""

    def size(self, dim: int) -> int:
        """Number of rows (and of equations)."""
        raise NotImplementedError

    def rows(self, alg, X, X0) -> list[Row]:
        raise NotImplementedError

    def equations(self, alg, X, X0) -> list[Equation]:
        raise NotImplementedError

    def rate_rows(self, alg, X, X0) -> list[Row]:
        """The rows of the constraint's own rate (a slider's slide along its line, model units
        per unit time), the parameter rows of a ``slide`` input or output; a kind without a
        rate raises :class:`~symkin.errors.SymkinError` naming it."""
        from symkin.errors import SymkinError

        raise SymkinError(f"{self.owner}: a {self.kind} constraint has no slide rate (a 'slide' rate needs a line)")

    def slide_equation(self, alg, X) -> "Equation":
        """The slide along the constraint's line as ``numerator / denominator`` (model units): a slider on a
        line states it (the loci's slide coordinates); other kinds raise
        :class:`~symkin.errors.SymkinError` naming the constraint."""
        from symkin.errors import SymkinError

        raise SymkinError(f"{self.owner}: a {self.kind} constraint has no slide (a slide needs a line)")

    def slide_polynomial(self, X, X0, value):
        """The polynomial equation of a prescribed slide (``value`` from the model's): a slider on a
        line states it; other kinds raise :class:`~symkin.errors.SymkinError` naming the constraint."""
        from symkin.errors import SymkinError

        raise SymkinError(f"{self.owner}: a {self.kind} constraint has no slide to prescribe (a slide needs a line)")


def normals(alg, e, e0, length) -> list[tuple[tuple, object]]:
    """The normals of the direction ``e`` (of norm ``length``) as ``(vector, norm)`` pairs.

    Exact algebras (polynomial vectors): planar ``perp(e)`` of norm ``length``; spatial, with
    ``a`` the coordinate axis least aligned with ``e`` (decided at the model's ``e0``) and
    ``w = e × a``, the pair ``(w × e, w)`` of norms ``|w|·length`` and ``|w|``.  Numeric
    algebras: :func:`~symkin.constraints.algebra.normal_basis` of ``u = e/length`` (the same
    vectors normalised, the axis decided at ``e``; norms 1), with the numeric core's rounding.
    Either way ``Σ n nᵀ/|n|² = I − ê êᵀ``.
    """
    if not alg.exact:
        one = alg.const(1)
        return [(n, one) for n in alg.unit_normals(tuple(c / length for c in e))]
    if len(e) == 2:
        return [(perp(e), length)]
    w = cross(e, alg.least_aligned(e, e0))
    nw = alg.sqrt(_expand(alg, dot(w, w)))
    return [(cross(w, e), nw * length), (w, nw)]


def _expand(alg, expr):
    return alg.sp.expand(expr) if alg.exact else expr
