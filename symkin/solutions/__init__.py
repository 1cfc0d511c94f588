"""All solutions of the position problem by homotopy continuation (stage 4, beside :mod:`symkin.paths`).

:mod:`~symkin.solutions.system` builds the polynomial system from the model data,
:mod:`~symkin.solutions.homotopy` tracks it with Bertini 2 (the optional extra
``symkin[global]``, imported only when used), :mod:`~symkin.solutions.solve_all` refines,
verifies and labels the real solutions (``symkin.solve_all``).
"""
from symkin.solutions.solve_all import Solution, Solutions, solve_all
from symkin.solutions.system import PolynomialSystem, position_system

__all__ = ["PolynomialSystem", "Solution", "Solutions", "position_system", "solve_all"]
