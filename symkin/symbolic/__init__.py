"""Symbolic stage of symkin: geometric matrices with symbols and singularity conditions.

:func:`symbolic_model` builds the paper's geometric matrix (eqs. 1-4, A1-A6) with symbols
named after their owners, in nodal or (planar) link-angle coordinates; its
``im_condition()`` and ``dkp_condition()`` derive the singularity conditions (§III, §VI)
as :class:`Condition` objects, factored, with readable geometric factors.

>>> import symkin
>>> from symkin.symbolic import symbolic_model
>>> sm = symbolic_model(symkin.catalogue.get("fourbar_appendix"), coordinates="angles")
>>> sm.dkp_condition("output").readable
sin(theta_coupler - theta_crank)
"""
from symkin.symbolic.conditions import Condition, Factor, dkp_condition, im_condition
from symkin.symbolic.model import LAMBDA, SymbolicModel, symbolic_model

__all__ = ["Condition", "Factor", "LAMBDA", "SymbolicModel", "dkp_condition", "im_condition",
           "symbolic_model"]
