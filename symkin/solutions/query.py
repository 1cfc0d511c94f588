"""What a later query of the parameter homotopy keeps from an earlier one (issue 17: ``symkin modes`` in ≤ 2 s).

A query's position equations fall in two groups (:class:`symkin.solutions.system.ValueEquations`):
the bodies' and the sliders', which do not depend on the prescribed values, and the values' and
the prismatic legs'.  The first query of a model with given labels makes them all (sympy: 0.3 s
on the general 6-6 Gough–Stewart, more on a loaded machine) and keeps in the artefact cache
(:func:`symkin.numeric.codegen.cache_directory`):

* ``query-checks/<key>.py``: the value-free original equations and their Jacobian as generated
  NumPy source (the checks of :func:`symkin.solutions.solve_all.sort_endpoints`; :func:`checks_file`);
* ``query-plans/<key>.npz``: the value-free rows of the family's coefficient matrix
  (:meth:`~symkin.solutions.parameter_homotopy.ParameterFamily.coefficient_matrix` of the equations
  with the legs reduced), how many value-free original equations there are, and the owners, legs and
  kept unknowns the rest must have (:class:`QueryPlan`).

A later query makes only the value equations (a few small expressions) and reads the rest back:
the same numbers as made afresh, bit for bit, since the same code made them from the same model
(``tests/solutions/test_query_path.py`` compares the answers).  A query whose value equations do not
have the planned owners, legs or monomials (e.g. a slide that puts a leg's joint on its pivot, so
the leg is not reduced) makes everything afresh.  The keys hash the model's content, the tolerances,
the labels (plans), the sympy and NumPy versions and the source text of the modules that make the
equations (:data:`SOURCES`), so a changed model or a changed builder is a new key.
"""
from __future__ import annotations

import hashlib
import importlib.util
import marshal
import os
import sys
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from symkin.model.mechanism import Mechanism
from symkin.tolerances import Tolerances

__all__ = ["QueryPlan", "SOURCES", "checks_file", "load_checks", "load_plan", "plan_file", "save_plan"]

#: bump when the cached files change form
FORMAT = "1"
#: the modules (relative to the package) whose source decides the equations and their generated code
SOURCES = ("solutions/system.py", "solutions/solve_all.py", "solutions/parameter_homotopy.py", "solutions/query.py",
           "numeric/coordinates.py", "model/mechanism.py", "constraints/*.py")


@lru_cache(maxsize=1)
def _fingerprint() -> str:
    root = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for pattern in SOURCES:
        for path in sorted(root.glob(pattern)):
            digest.update(path.relative_to(root).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


def _key(mech: Mechanism, tol: Tolerances, *parts: str) -> str:
    import sympy

    text = "|".join([FORMAT, sympy.__version__, np.__version__, _fingerprint(), mech.content_hash(),
                     repr(Tolerances.of(tol)), *parts])
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def checks_file(mech: Mechanism, tol: Tolerances, cache_dir=None) -> Path:
    """The generated source of ``mech``'s value-free original equations and their Jacobian (any labels)."""
    from symkin.numeric.codegen import cache_directory

    return cache_directory(cache_dir) / "query-checks" / f"{_key(mech, tol)}.py"


def plan_file(mech: Mechanism, labels, tol: Tolerances, cache_dir=None) -> Path:
    """The :class:`QueryPlan` of ``mech`` with ``labels`` prescribed."""
    from symkin.numeric.codegen import cache_directory

    return cache_directory(cache_dir) / "query-plans" / f"{_key(mech, tol, 'labels', *labels)}.npz"


def load_checks(path: Path):
    """``(equations, jacobian)`` of a :func:`checks_file` (NumPy functions of the unknowns' vector), or None.

    The compiled source is kept beside it (``<key>.<cache tag>.code``: the interpreter's magic number,
    the source's hash and the marshalled code object), so a later query does not compile it again
    (45 ms for the 6-6 Gough–Stewart's 24 kB).
    """
    try:
        source = path.read_bytes()
        header = importlib.util.MAGIC_NUMBER + hashlib.sha256(source).digest()[:16]
        kept = path.with_name(f"{path.stem}.{sys.implementation.cache_tag}.code")
        code = None
        try:
            data = kept.read_bytes()
            if data[:len(header)] == header:
                code = marshal.loads(data[len(header):])
        except (OSError, ValueError, EOFError, TypeError):
            code = None
        if code is None:
            code = compile(source.decode(), str(path), "exec")
            try:
                tmp = kept.with_name(f".{kept.name}.{os.getpid()}")
                tmp.write_bytes(header + marshal.dumps(code))
                os.replace(tmp, kept)
            except OSError:
                pass  # compiled again next time
        space: dict = dict(np.__dict__)
        exec(code, space)  # our own artefact
        return space["equations"], space["jacobian"]
    except Exception:  # missing or damaged: made again
        return None


@dataclass(frozen=True, eq=False)
class QueryPlan:
    """What a later query of ``mech`` with given labels reads back (module docstring).

    Attributes
    ----------
    fixed_rows : ndarray
        (k, K) coefficients of the family's first ``k`` equations (bodies and sliders), on its monomials.
    reduced_owners : tuple of str
        Owners of the family's other equations (values, then legs).
    legs : tuple of str
        The reduced legs (:attr:`ValueEquations.legs`).
    kept : tuple of int
        The family's unknowns among the position system's.
    base : int
        Number of value-free original equations (those of :func:`checks_file`).
    original_owners : tuple of str
        Owners of the original value equations.
    """

    fixed_rows: np.ndarray
    reduced_owners: tuple
    legs: tuple
    kept: tuple
    base: int
    original_owners: tuple

    def coefficients(self, family, values) -> np.ndarray | None:
        """The query's coefficient matrix (as :meth:`ParameterFamily.coefficient_matrix` of all its equations)
        from the kept rows and its :class:`ValueEquations` ``values``; None when they do not fit the plan."""
        if (tuple(o for o, _ in values.reduced) != self.reduced_owners or tuple(values.legs) != self.legs
                or tuple(values.kept) != self.kept or tuple(o for o, _ in values.original) != self.original_owners
                or self.fixed_rows.shape[0] + len(values.reduced) != family.base.shape[0]
                or self.fixed_rows.shape[1] != family.base.shape[1]):
            return None
        rows = family.coefficient_rows(values.reduced, [values.unknowns[k] for k in values.kept])
        if rows is None:
            return None
        return np.vstack([self.fixed_rows, rows])


def load_plan(path: Path) -> QueryPlan | None:
    """The plan of :func:`plan_file`, or None (missing or damaged)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            return QueryPlan(np.array(data["fixed_rows"], float), tuple(str(s) for s in data["reduced_owners"]),
                             tuple(str(s) for s in data["legs"]), tuple(int(k) for k in data["kept"]),
                             int(data["base"]), tuple(str(s) for s in data["original_owners"]))
    except (OSError, KeyError, ValueError):
        return None


def save_plan(path: Path, plan: QueryPlan) -> None:
    """Write ``plan`` (atomically; a cache that cannot be written is skipped: the next query makes it again)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp.npz")
        np.savez(tmp, fixed_rows=plan.fixed_rows, reduced_owners=np.array(plan.reduced_owners, dtype=str),
                 legs=np.array(plan.legs, dtype=str), kept=np.array(plan.kept, dtype=int), base=plan.base,
                 original_owners=np.array(plan.original_owners, dtype=str))
        tmp.replace(path)
    except OSError:
        pass
