"""All solutions of the position problem by homotopy continuation (stage 4, beside :mod:`symkin.paths`).

:mod:`~symkin.solutions.system` builds the polynomial system from the model data,
:mod:`~symkin.solutions.homotopy` tracks it with Bertini 2 (the optional extra
``symkin[global]``, imported only when used), :mod:`~symkin.solutions.solve_all` refines,
verifies and labels the real solutions (``symkin.solve_all``);
:mod:`~symkin.solutions.dkp_system` builds the square systems "closure + DKP test function = 0" and
:mod:`~symkin.solutions.circuits` finds every circuit and singular configuration of a 1-DOF
mechanism (``symkin.singularities``).
"""
from symkin.solutions.solve_all import Solution, Solutions, solve_all
from symkin.solutions.system import PolynomialSystem, closure_system, position_system


def __getattr__(name):
    """``Singularities`` and ``singularities`` on first use: ``symkin modes`` does not import the
    circuit search (0.3 s of imports, scipy.optimize among them)."""
    if name in ("Singularities", "singularities"):
        from symkin.solutions import circuits

        return getattr(circuits, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = ["PolynomialSystem", "Singularities", "Solution", "Solutions", "closure_system", "position_system",
           "singularities", "solve_all"]
