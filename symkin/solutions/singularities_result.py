"""The result types of :func:`symkin.singularities`: circuits, branches, singular configurations, cross-checks.

Frozen dataclasses, produced by :func:`symkin.solutions.circuits.singularities` and only read by
the plots (:mod:`symkin.plots.circuits`), the reports and the command ``symkin singularities``;
``to_dict`` gives the JSON of ``symkin singularities --json``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symkin.analysis.classification import Analysis
from symkin.model.mechanism import Mechanism
from symkin.paths.trace import Path

__all__ = ["Branch", "Circuit", "CrossCheck", "SingularConfiguration", "Singularities", "SingularitiesWarning"]


class SingularitiesWarning(UserWarning):
    """The traced circuits and the square DKP systems do not give the same singular configurations."""


@dataclass(frozen=True)
class SingularConfiguration:
    """One singular configuration on the circuits.

    Attributes
    ----------
    configuration : dict
        Node → coordinates (model units).
    types : tuple of str
        :func:`symkin.analyze`'s types at the configuration (``IM``, ``DKP-input``, ``DKP-output``, ``LIM``...).
    dof : int
        Instantaneous DOF ``L`` (``analyze``).
    circuit : int
        The circuit (connected component, numbered from 1) it lies on.
    branches : tuple of int
        The traced branches (numbered from 1 over all circuits) that pass through it (two
        at a branch point where two traced branches cross; one branch that crosses itself
        there, as at the change point of a four-bar, is located once).
    input, output : float
        The input and output coordinates, measured from the model's configuration
        (angles in ``unit``, in (−180°, 180°] / (−π, π]; lengths in model units); output None without one.
    kinds : tuple of str
        What located it: the trace's test functions (``DKP-input``, ``DKP-output``, ``IM``, ``LIM``)
        and ``LIM`` for a real solution of a link's LIM system (:mod:`symkin.solutions.lim_systems`).
    arclength : float
        Its arclength along the first branch that located it (for a plot without an output).
    locked_links : tuple of str
        The links locked there (``analyze``'s ``locked_links``: not empty at a LIM configuration).
    """

    configuration: dict
    types: tuple
    dof: int
    circuit: int
    branches: tuple
    input: float
    output: float | None
    kinds: tuple
    arclength: float = field(default=0.0, compare=False)
    analysis: Analysis | None = field(default=None, compare=False, repr=False)
    locked_links: tuple = ()

    def to_dict(self) -> dict:
        return {"configuration": {n: list(x) for n, x in self.configuration.items()}, "types": list(self.types),
                "circuit": self.circuit, "input": self.input, "output": self.output, "dof": self.dof,
                "branches": list(self.branches), "kinds": list(self.kinds), "locked_links": list(self.locked_links)}


@dataclass(frozen=True)
class Branch:
    """One traced loop: its seed, its points in input–output space and how its trace ended.

    ``inputs`` / ``outputs`` are unwrapped along the trace (radians or model units, measured from
    the model's configuration); ``full_turn`` says that the input takes every value (a crank);
    ``closed`` that the trace closed on itself, or came back to a branch point it had passed in
    the same direction (``stop_reason`` ``"returned"``: from there on it would retrace itself).
    """

    index: int
    seed: dict
    inputs: np.ndarray = field(repr=False)
    outputs: np.ndarray | None = field(repr=False)
    closed: bool
    full_turn: bool
    stop_reason: str
    path: Path | None = field(default=None, repr=False, compare=False)

    def to_dict(self, conv: float) -> dict:
        return {"branch": self.index, "closed": self.closed, "full_turn": self.full_turn,
                "stop_reason": self.stop_reason, "points": int(len(self.inputs)),
                "input_range": [float(np.min(self.inputs)) * conv, float(np.max(self.inputs)) * conv],
                "seed": {n: list(x) for n, x in self.seed.items()}}


@dataclass(frozen=True)
class Circuit:
    """A connected component of the configuration curve: its traced branches (usually one).

    Branches that share a configuration (a branch point, IM) are one circuit.
    """

    index: int
    branches: tuple[Branch, ...]

    @property
    def closed(self) -> bool:
        return all(b.closed for b in self.branches)

    @property
    def full_turn(self) -> bool:
        return any(b.full_turn for b in self.branches)

    def to_dict(self, conv: float) -> dict:
        return {"circuit": self.index, "closed": self.closed, "full_turn": self.full_turn,
                "branches": [b.to_dict(conv) for b in self.branches]}


@dataclass(frozen=True)
class CrossCheck:
    """The square system ``closure + D = 0`` of one parameter against the traced configurations.

    ``kind`` is ``DKP-input``, ``DKP-output`` or ``LIM`` (the system of ``link``'s rotation,
    :mod:`symkin.solutions.lim_systems`; :attr:`name` ``"LIM:<link>"``).
    ``homotopy`` counts its distinct real solutions, ``traced`` the traced configurations whose
    kinds it detects (``kind`` or IM; for LIM, the traced LIM events where ``link`` is locked);
    ``unmatched_homotopy`` / ``unmatched_traced`` the
    configurations found by one side only.  ``paths`` is the number of homotopy paths (tracked,
    or that would have been tracked when the system was solved exactly or not at all).
    ``solver`` is ``"bertini"`` (the homotopy) or ``"msolve"`` (beyond ``max_paths``: the exact
    system of :mod:`symkin.solutions.exact`, Gröbner basis and certified real roots);
    ``skipped`` says why neither solved it.
    """

    kind: str
    label: str
    homotopy: int
    traced: int
    matched: int
    paths: int
    degree: int
    unmatched_homotopy: tuple = ()
    unmatched_traced: tuple = ()
    seconds: float = 0.0
    skipped: str = ""
    solver: str = "bertini"
    link: str = ""

    @property
    def name(self) -> str:
        """``kind``, or ``"LIM:<link>"`` for a link's LIM system."""
        return f"{self.kind}:{self.link}" if self.link else str(self.kind)

    @property
    def agree(self) -> bool | None:
        """Both sides found the same configurations; None when the square system was not solved (``skipped``)."""
        if self.skipped:
            return None
        return not self.unmatched_homotopy and not self.unmatched_traced

    def to_dict(self) -> dict:
        return {"kind": self.kind, "name": self.name, "link": self.link or None,
                "label": self.label, "homotopy": self.homotopy, "traced": self.traced,
                "matched": self.matched, "agree": self.agree, "paths": self.paths, "degree": self.degree,
                "skipped": self.skipped, "solver": self.solver,
                "unmatched_homotopy": [{n: list(x) for n, x in c.items()} for c in self.unmatched_homotopy],
                "unmatched_traced": [{n: list(x) for n, x in c.items()} for c in self.unmatched_traced],
                "seconds": self.seconds}


@dataclass(frozen=True)
class Singularities:
    """Result of :func:`symkin.singularities`: the circuits and every singular configuration on them."""

    mechanism: Mechanism = field(repr=False)
    input: str
    output: str | None
    unit: str
    kind: str
    circuits: tuple[Circuit, ...]
    singularities: tuple[SingularConfiguration, ...]
    checks: tuple[CrossCheck, ...]
    samples: tuple[float, ...]
    seeds: int
    warnings: tuple[str, ...]
    seconds: float

    @property
    def agree(self) -> bool | None:
        """The traced circuits and every square system (DKP, LIM) give the same configurations.

        False when one check disagrees; None when none disagrees but a square system was not
        solved (:attr:`CrossCheck.skipped`): the traced answer is then not cross-checked.
        """
        values = [c.agree for c in self.checks]
        if False in values:
            return False
        return None if None in values else True

    def to_dict(self) -> dict:
        """``{"circuits": n, "singularities": [...], ...}``: the ``--json`` of ``symkin singularities``.

        Each singularity's ``input`` / ``output`` are relative to the model, in (−180°, 180°];
        ``input_absolute`` / ``output_absolute`` the absolute angles in [0°, 360°) (a node's
        coordinate for ``velocity:N.x``; None for a slide or a spatial rotation), in ``unit``:
        the one angle convention, :func:`symkin.paths.trace.relative_angle`.
        """
        from symkin.paths.trace import CoordinateValues

        conv = self._conv()
        labels = [self.input] + ([] if self.output is None else [self.output])
        values = CoordinateValues(self.mechanism, labels)
        singular = []
        for s in self.singularities:  # the absolute values too, as every command gives them
            at = values(s.configuration, self.unit)
            singular.append({**s.to_dict(), "input_absolute": at[self.input]["absolute"],
                             **({} if self.output is None else {"output_absolute": at[self.output]["absolute"]})})
        return {"mechanism": self.mechanism.name, "circuits": len(self.circuits),
                "singularities": singular,
                "input_label": self.input, "output_label": self.output, "unit": self.unit,
                "agree": self.agree, "cross_check": [c.to_dict() for c in self.checks],
                "circuit_list": [c.to_dict(conv) for c in self.circuits],
                "samples": [v * conv for v in self.samples], "seeds": self.seeds,
                "warnings": list(self.warnings), "seconds": self.seconds}

    def _conv(self) -> float:
        return 180.0 / math.pi if (self.unit == "deg" and self.kind == "angle") else 1.0
