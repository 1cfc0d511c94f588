"""Working (assembly) modes of a map: the model's configuration and the seed models.

``modes="model"``: the model's configuration is mode 0 (seed ``"model"``) and each seed
(a model file of the same mechanism at another configuration, e.g. the other elbow) is
one more mode; seeds with the same configuration as an earlier mode are merged.
``modes="all"``: every real solution of the position problem at the map's reference point
(the model's axis values and the held values), from the global-solutions solver
(:func:`symkin.solve_all`, the optional extra ``symkin[global]``; without it a clear error
names the extra), each one mode, numbered in the solver's order.
"""
from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np

from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.model.model_file import read_model
from symkin.tolerances import Tolerances
from symkin.workspace.system import MapSystem

__all__ = ["Seed", "model_modes", "MODES"]

#: accepted values of ``modes``
MODES = ("model", "all")

#: fields a seed may change: its configuration and its names
_FREE_FIELDS = {"nodes", "name", "description"}


class Seed(tuple):
    """``(label, q)``: where a mode comes from (``"model"`` or the seed's file / name) and its configuration."""

    @property
    def label(self) -> str:
        return self[0]

    @property
    def q(self) -> np.ndarray:
        return self[1]


def _seed_mechanism(seed) -> tuple[str, Mechanism]:
    if isinstance(seed, Mechanism):
        return seed.name, seed
    path = Path(seed)
    return str(seed), read_model(path)


def _topology_problems(mech: Mechanism, other: Mechanism) -> list[str]:
    out = []
    if other.node_names != mech.node_names:
        out.append(f"nodes {', '.join(other.node_names)} instead of {', '.join(mech.node_names)}")
    for f in fields(Mechanism):
        if f.name in _FREE_FIELDS or f.name == "nodes":
            continue
        if getattr(other, f.name) != getattr(mech, f.name):
            out.append(f"another {f.name}")
    return out


def model_modes(system: MapSystem, seeds=(), modes: str = "model",
                tolerances: Tolerances | float | None = None) -> tuple[list[Seed], list[str]]:
    """The seeds of a map's modes, ``[Seed("model", q0), Seed(seed label, q), ...]``, and notes on merged ones.

    A seed with the configuration of an earlier one (within ``same_configuration``) is merged
    into it (a note says so).
    A seed must be the same mechanism (topology, links, sliders, parameters), close its
    loops with the model's link lengths and lie on the held values; otherwise a
    :class:`SymkinError` names the seed and the problem.
    """
    if modes not in MODES:
        raise SymkinError(f"--modes {modes!r}: use one of {', '.join(MODES)}")
    tol = Tolerances.of(tolerances)
    if modes == "all":
        if seeds:
            raise SymkinError("--modes all takes its modes from the solver: give no --seed with it")
        return _all_modes(system, tol)
    mech = system.mech
    ev = system.evaluators
    ell = mech.length_scale
    out = [Seed(("model", system.q0))]
    merged: list[str] = []
    for seed in seeds:
        label, other = _seed_mechanism(seed)
        problems = _topology_problems(mech, other)
        if problems:
            raise SymkinError(f"seed {label}: not the same mechanism as {mech.name} ({'; '.join(problems)}); a seed "
                              "is the model at another configuration")
        xa, xb = mech.coordinates(), other.coordinates()
        moved = [n for n in mech.fixed if np.linalg.norm(np.subtract(xa[n], xb[n])) > tol.geometry * ell]
        if moved:
            raise SymkinError(f"seed {label}: fixed node(s) {', '.join(moved)} are elsewhere than in {mech.name}")
        q = ev.free_coordinates(other)
        phi = np.abs(ev("closure", q)["phi"]).max() if ev.nf else 0.0
        if phi > tol.geometry * ell:
            raise SymkinError(f"seed {label}: its configuration does not close with the model's link lengths "
                              f"(residual {phi:.3g} model units)")
        if system.holds:
            c = system.evaluate("holds", q[None])[0][0]
            scale = np.array([h.scale(ell) for h in system.holds])
            off = np.abs(c - system.hold_values) / scale
            if np.any(off > tol.geometry):
                k = int(np.argmax(off))
                h = system.holds[k]
                raise SymkinError(f"seed {label}: not on the held values: {h.label} is "
                                  f"{system.to_user(c, 'holds')[k]:.6g}, the map holds "
                                  f"{system.to_user(system.hold_values, 'holds')[k]:.6g}")
        same = next((s for s in out if np.linalg.norm(q - s.q) <= tol.same_configuration * ell), None)
        if same is not None:
            merged.append(f"seed {label} has the configuration of seed {same.label}: merged")
            continue
        out.append(Seed((label, q)))
    return out, merged



def _all_modes(system: MapSystem, tol: Tolerances) -> tuple[list[Seed], list[str]]:
    """Every real solution at the reference point as a mode (``modes="all"``)."""
    import math

    from symkin.solutions import solve_all

    mech, ev = system.mech, system.evaluators
    values = {c.label: 0.0 for c in system.axes}  # at the model's own axis values
    if system.holds:
        here = system.evaluate("holds", system.q0[None])[0][0]
        for h, want, now in zip(system.holds, system.hold_values, here):
            d = float(want - now)
            values[h.label] = math.remainder(d, 2 * math.pi) if h.kind == "angle" else d
    sols = solve_all(mech, values=values, unit="rad", tol=tol)
    if not sols.solutions:
        raise SymkinError(f"--modes all: {mech.name} has no real configuration at the map's reference point "
                          f"({sols.complex} complex solution(s))")
    seeds = [Seed((f"solution {k}", ev.free_coordinates(mech.with_coordinates(s.configuration))))
             for k, s in enumerate(sols.solutions, 1)]
    note = (f"--modes all: {len(seeds)} real solution(s) at the reference point "
            f"({sols.complex} complex, {sols.paths} homotopy paths)")
    return seeds, [note]
