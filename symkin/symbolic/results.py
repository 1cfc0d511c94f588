"""Result types of the singularity conditions (paper §III-IV, §VI).

:class:`Condition` is one derived condition (IM, DKP-input or DKP-output): a nonzero
constant times trivial and geometric :class:`Factor` objects, each with a readable form,
and for sums of squares the distinct maximal minors.  They are built by
:mod:`symkin.symbolic.minors` and :mod:`symkin.symbolic.gram` and returned by
:func:`~symkin.symbolic.conditions.im_condition` and
:func:`~symkin.symbolic.conditions.dkp_condition`.
"""
from __future__ import annotations
from symkin.kinds import Kind
from symkin.kinds import latex as latex_name

from dataclasses import dataclass, field

import sympy as sp

__all__ = ["Factor", "Condition"]


def _json_exponent(e):
    """A factor's exponent as JSON: an int (sympy's ``-1`` is ``NegativeOne``, not an int), else a string."""
    try:
        return int(e) if sp.sympify(e).is_integer else sp.sstr(e)
    except (TypeError, ValueError, sp.SympifyError):
        return sp.sstr(e)


@dataclass(frozen=True)
class Factor:
    """One factor of a condition.

    Attributes
    ----------
    expr : sympy.Expr
        The factor as derived (design parameters substituted unless kept symbolic).
    exponent : int
        Its multiplicity; negative for the scales of the rows (denominators).
    readable : sympy.Expr
        An equal expression that is easier to read, e.g. ``sin(theta_coupler - theta_rocker)``.
    trivial : bool
        True for factors that cannot vanish: nonzero constants, lengths, ``cos² + sin²``,
        squared lengths, row scales.
    meaning : str
        What the factor says, when recognised, e.g. ``"coupler ∥ rocker"``.
    """

    expr: sp.Expr
    exponent: int
    readable: sp.Expr
    trivial: bool
    meaning: str = ""

    def __str__(self) -> str:
        power = "" if self.exponent == 1 else f"**({sp.sstr(self.exponent)})"
        tail = f"   [{self.meaning}]" if self.meaning else ""
        return f"({sp.sstr(self.readable)}){power}{tail}"


@dataclass(frozen=True, eq=False)
class Condition:
    """A singularity condition: the configurations where ``expression`` vanishes.

    Attributes
    ----------
    kind : str
        ``"IM"``, ``"DKP-input"`` or ``"DKP-output"``.
    labels : tuple of str
        Kinematic parameters involved (DKP), e.g. ``("rotation:crank",)``.
    method : str
        ``"determinant"`` (square velocity equation) or ``"sum of squared maximal minors"``.
    constant : sympy.Expr
        Nonzero numeric factor (0 when the condition holds everywhere).
    factors : tuple of Factor
        Trivial and geometric factors; ``expression = constant · Π expr**exponent``.
    minors : tuple of sympy.Expr
        For sums of squares: the distinct nonzero maximal minors, factored (readable forms).
        The condition holds exactly where all of them vanish.
    coordinates : str
        ``"nodes"`` or ``"angles"``.
    seconds : float
        Time the derivation took.
    note : str
        What the zero set contains, in words.
    rows : tuple of str
        Owners of the rows of the velocity equation it was derived from, in order
        (constraint rows as :attr:`SymbolicModel.row_owners`, then parameter labels).
    """

    kind: str
    labels: tuple[str, ...]
    method: str
    constant: sp.Expr
    factors: tuple[Factor, ...]
    minors: tuple[sp.Expr, ...]
    coordinates: str
    seconds: float
    note: str
    model: object = field(repr=False, default=None)
    rows: tuple[str, ...] = ()

    # ---------------------------------------------------------------- views
    @property
    def expression(self) -> sp.Expr:
        """The raw scalar as derived: ``constant · Π factor**exponent``."""
        return self.constant * sp.Mul(*[f.expr ** f.exponent for f in self.factors])

    @property
    def trivial_factors(self) -> tuple[Factor, ...]:
        return tuple(f for f in self.factors if f.trivial)

    @property
    def geometric_factors(self) -> tuple[Factor, ...]:
        return tuple(f for f in self.factors if not f.trivial)

    @property
    def identically_zero(self) -> bool:
        """True when the condition holds at every configuration."""
        return self.constant == 0

    @property
    def never(self) -> bool:
        """True when no configuration satisfies it (no geometric factor)."""
        return self.constant != 0 and not self.geometric_factors

    @property
    def readable(self) -> sp.Expr:
        """Product of the readable geometric factors: the condition is ``readable = 0``."""
        if self.identically_zero:
            return sp.Integer(0)
        return sp.Mul(*[f.readable ** f.exponent for f in self.geometric_factors])

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(sorted(self.expression.free_symbols, key=lambda s: s.name))

    def evaluate(self, values: dict | None = None) -> float:
        """Value of ``expression`` at ``values`` (default: the model's configuration).

        ``values`` maps symbols or their names to numbers (see
        :meth:`SymbolicModel.values_at <symkin.symbolic.model.SymbolicModel.values_at>`).
        """
        return self.model.evaluate(self.expression, values)

    def evaluate_readable(self, values: dict | None = None) -> float:
        """Value of ``readable`` (the geometric factors only) at ``values``."""
        return self.model.evaluate(self.readable, values)

    def evaluate_factors(self, values: dict | None = None) -> list[float]:
        """Values of the geometric factors' readable forms at ``values``."""
        return [self.model.evaluate(f.readable, values) for f in self.geometric_factors]

    def lambdify(self, readable: bool = True):
        """A NumPy function of the model's symbols (in ``model.symbols`` order plus any design
        symbols), vectorised over arrays: handy for plotting a condition over a grid.

        Returns ``(function, symbols)``.
        """
        expr = self.readable if readable else self.expression
        expr = expr.replace(lambda e: isinstance(e, sp.Determinant), lambda e: e.doit())
        expr = self.model.substitute_design(expr)
        syms = list(self.model.symbols)
        return sp.lambdify(syms, expr, modules="numpy"), tuple(syms)

    # ---------------------------------------------------------------- rendering
    def _heading(self) -> str:
        what = {Kind.IM: "IM (L > F)", Kind.DKP_INPUT: Kind.DKP_INPUT, Kind.DKP_OUTPUT: Kind.DKP_OUTPUT}[self.kind]
        if self.labels:
            what += f" [{', '.join(self.labels)}]"
        return what

    def __str__(self) -> str:
        lines = [f"{self._heading()} — {self.method}, derived in {self.seconds:.3g} s"]
        geo = self.geometric_factors
        if self.identically_zero:
            lines.append("  holds at every configuration (the expression is identically 0)")
        elif self.never:
            lines.append("  holds at no configuration (no geometric factor)")
        else:
            if len(geo) > 1:
                lines.append("  holds where any of these factors vanishes:")
            for f in geo:
                power = f"  (power {f.exponent})" if f.exponent != 1 else ""
                tail = f"   [{f.meaning}]" if f.meaning else ""
                lines.append(f"  {sp.sstr(f.readable)} = 0{power}{tail}")
        triv = self.trivial_factors
        if self.constant not in (0, 1) or triv:
            parts = [sp.sstr(self.constant)] if self.constant not in (0, 1) else []
            parts += [f"({sp.sstr(f.readable)})**({sp.sstr(f.exponent)})" if f.exponent != 1
                      else f"({sp.sstr(f.readable)})" for f in triv]
            lines.append(f"  trivial factors (never zero): {' * '.join(parts)}")
        if self.minors:
            lines.append(f"  equivalently: all {len(self.minors)} distinct maximal minors vanish")
        if self.note:
            lines.append(f"  note: {self.note}")
        return "\n".join(lines)

    def latex(self) -> str:
        """LaTeX of the condition: ``readable = 0`` and the trivial factors separated."""
        head = latex_name(self.kind)
        if self.identically_zero:
            return head + r":\; 0 = 0"
        if self.never:
            return head + r":\; \text{never}"
        body = r" \cdot ".join(
            (rf"\left({sp.latex(f.readable)}\right)^{{{f.exponent}}}" if f.exponent != 1
             else (sp.latex(f.readable) if len(self.geometric_factors) == 1
                   else rf"\left({sp.latex(f.readable)}\right)"))
            for f in self.geometric_factors)
        out = head + r":\; " + body + " = 0"
        triv = sp.Mul(*[f.readable ** f.exponent for f in self.trivial_factors]) * self.constant
        if triv != 1:
            out += r"\quad\left(\text{trivial factor } " + sp.latex(triv) + r"\right)"
        return out

    def as_dict(self) -> dict:
        """JSON-ready summary: expressions as strings; a factor's ``exponent`` an int, or a string such
        as ``"-1/2"`` when fractional (the square-root scale of a row in node coordinates)."""
        return {"kind": self.kind, "labels": list(self.labels), "method": self.method,
                "coordinates": self.coordinates, "seconds": self.seconds,
                "identically_zero": self.identically_zero, "never": self.never,
                "readable": sp.sstr(self.readable), "expression": sp.sstr(self.expression),
                "geometric_factors": [{"readable": sp.sstr(f.readable), "exponent": _json_exponent(f.exponent),
                                       "meaning": f.meaning} for f in self.geometric_factors],
                "trivial_factors": [{"readable": sp.sstr(f.readable), "exponent": _json_exponent(f.exponent),
                                     "meaning": f.meaning} for f in self.trivial_factors],
                "constant": sp.sstr(self.constant), "minors": [sp.sstr(m) for m in self.minors],
                "note": self.note}
