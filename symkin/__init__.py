"""symkin: singular configurations of mechanisms by the geometric-matrix method.

Altuzarra, Pinto, Avilés, Hernández, "A practical procedure to analyze singular
configurations in closed kinematic chains", IEEE T-RO 20(6), 2004.

>>> import symkin
>>> result = symkin.analyze(symkin.catalogue.get("fourbar_flat"))
>>> result.dof, result.types
(2, ('IM',))
"""
from symkin.startup import exit_on_early_interrupt

exit_on_early_interrupt()  # first: in the symkin program, a Ctrl-C while the imports below run exits 130

import importlib

from symkin import catalogue
from symkin.errors import ModelError, ModelFileError, NotConvergedError, SymkinError
from symkin.model.mechanism import Mechanism, Parameter, Slider
from symkin.model.model_file import read_model, write_model

# discovery of the pair kinds: symkin.constraints imports every module of its package, each
# registering its kind in symkin.model.pairs, before any model is parsed (NumPy-free)
importlib.import_module("symkin.constraints")

#: names imported on first use (scipy and CasADi load with them, not with ``import symkin``,
#: so that ``symkin --version`` and ``symkin --help`` are fast): name → defining module
_LAZY = {
    "Analysis": "symkin.analysis.classification", "Motion": "symkin.analysis.classification",
    "Relation": "symkin.analysis.classification", "analyze": "symkin.analysis.classification",
    "MotionSpace": "symkin.analysis.motion_space", "motion_space": "symkin.analysis.motion_space",
    "Evaluators": "symkin.analysis.batch", "evaluators": "symkin.analysis.batch",
    "geometric_matrix": "symkin.numeric.geometric_matrix", "render_text": "symkin.report",
}


def __getattr__(name: str):
    """The public names of :data:`_LAZY` (and the module ``report``), imported on first use."""
    if name == "report":
        return importlib.import_module("symkin.report")
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'symkin' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))


def symbolic_model(mechanism, *args, **kwargs):
    """Symbolic geometric matrices and conditions: see :func:`symkin.symbolic.symbolic_model`.

    sympy is imported on first use, not with ``import symkin``.
    """
    from symkin.symbolic import symbolic_model as _symbolic_model

    return _symbolic_model(mechanism, *args, **kwargs)


def implicit_loci(mechanism, *args, **kwargs):
    """Singularity loci as implicit polynomials in two coordinates: see
    :func:`symkin.symbolic.loci.implicit_loci` (sympy is imported on first use)."""
    from symkin.symbolic.loci import implicit_loci as _implicit_loci

    return _implicit_loci(mechanism, *args, **kwargs)


def trace(mechanism, *args, **kwargs):
    """Trace a path and locate its singular configurations: see :func:`symkin.paths.trace.trace`."""
    from symkin.paths.trace import trace as _trace

    return _trace(mechanism, *args, **kwargs)


def workspace_map(mechanism, *args, **kwargs):
    """A workspace or joint-space singularity map: see :func:`symkin.workspace.maps.workspace_map`."""
    from symkin.workspace.maps import workspace_map as _workspace_map

    return _workspace_map(mechanism, *args, **kwargs)


def load_map(path):
    """Read a map saved by ``WorkspaceMap.save``: see :func:`symkin.workspace.maps.load_map`."""
    from symkin.workspace.maps import load_map as _load_map

    return _load_map(path)


def solve_all(mechanism, *args, **kwargs):
    """Every real solution of the position problem: see :func:`symkin.solutions.solve_all.solve_all`.

    Needs the optional extra ``symkin[global]`` (Bertini 2, GPL-3); without it a
    :class:`SymkinError` names the extra.
    """
    from symkin.solutions import solve_all as _solve_all

    return _solve_all(mechanism, *args, **kwargs)


def singularities(mechanism, *args, **kwargs):
    """Every circuit and singular configuration of a 1-DOF mechanism: see :func:`symkin.solutions.circuits.singularities`.

    Needs the optional extra ``symkin[global]`` (Bertini 2, GPL-3); without it a
    :class:`SymkinError` names the extra.
    """
    from symkin.solutions.circuits import singularities as _singularities

    return _singularities(mechanism, *args, **kwargs)


from symkin.tolerances import Tolerances

__version__ = "0.1.0"

__all__ = ["Analysis", "Evaluators", "Mechanism", "ModelError", "ModelFileError", "Motion", "MotionSpace",
           "NotConvergedError", "Parameter", "Relation", "Slider", "SymkinError", "Tolerances",
           "analyze", "trace", "solve_all", "singularities", "catalogue", "evaluators", "symbolic_model",
           "implicit_loci", "geometric_matrix", "motion_space", "read_model", "render_text", "report",
           "write_model", "workspace_map", "load_map",
           "__version__"]
