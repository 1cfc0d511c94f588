"""Symbolic stage of symkin: geometric matrices with symbols and singularity conditions.

:func:`symbolic_model` builds the paper's geometric matrix (eqs. 1-4, A1-A6) with symbols
named after their owners, in nodal or (planar) link-angle coordinates; its
``im_condition()`` and ``dkp_condition()`` derive the singularity conditions (§III, §VI)
as :class:`Condition` objects, factored, with readable geometric factors;
:func:`implicit_loci` eliminates every other coordinate and gives each singularity locus as a
factored polynomial in two workspace coordinates (:mod:`symkin.symbolic.loci`).

>>> import symkin
>>> from symkin.symbolic import symbolic_model
>>> sm = symbolic_model(symkin.catalogue.get("fourbar_appendix"), coordinates="angles")
>>> sm.dkp_condition("output").readable
sin(theta_coupler - theta_crank)
"""
from symkin.symbolic.conditions import Condition, Factor, dkp_condition, im_condition
from symkin.symbolic.model import LAMBDA, SymbolicModel, symbolic_model
from symkin.symbolic.loci import Loci, Locus, LocusFactor, implicit_loci

__all__ = ["Condition", "Factor", "LAMBDA", "Loci", "Locus", "LocusFactor", "SymbolicModel", "dkp_condition",
           "im_condition", "implicit_loci", "symbolic_model"]
