"""Symbolic conditions of a model with a helical pair H (issue 16): the screw jack.

The screw jack (``tests/constraints/models/screw_jack.toml``): a screw turning about the
fixed z axis (R to ground) drives a nut (H of pitch p) that a guide keeps from turning (P to
ground).  It has one degree of freedom everywhere and ``v = p·ω`` exactly (the nut's slide
rate ``joint:P1`` per screw rate ``joint:R1``), so it has no singular configuration: every
condition is nonzero all along its motion.

The motion, by hand: the screw turned by θ carries its arm node ``H1.guide`` from
``(−1, 0, 0)`` to ``(−cos θ, −sin θ, 0)``; the nut's axis nodes ``H1``, ``H1.end`` and its arm
``H1.arm`` go down by ``pθ`` (``z_H1 = −pθ``; tests/constraints/test_helical.py).

The values, by hand.  The velocity equation the conditions use has 12 constraint rows
over the 12 free coordinates (the P's sliders repeat the H's on the same fixed axis: 4
repeated constant rows dropped), unit rows, with one dependency: the nut's bar ``H1``-``H1.arm``
is the sum of the rows holding ``y_H1`` (slider) and ``y_H1.arm`` (the key) — so of the 13
maximal minors of ``[J; input row]`` exactly the three that leave out one of those rows
survive, all of the same size.  Each splits into the screw's block (its two bars and the
input row ``ω = −ẏ_guide``, determinant ``1/√2`` at θ = 0, the screw's bar to ``R1.axis`` at
45°) times the nut's block (the six unit slider rows, the nut's bars ``H1``-``H1.end`` and
``H1.end``-``H1.arm`` and the helical row ``ż_H1 − p·θ̇_rel``, whose z-columns give
``1/√2``): DKP-input ``= 3·(1/2)² = 3/4`` at every configuration of the motion (rotation
about the axis and the nut's slide change no block).  DKP-output: the output row replaces
the input row; on the motion a minor with an output row is ``v/ω = p`` times the same minor
with the input row (both are the motion's component along the row times one cofactor), so
DKP-output ``= p²·3/4`` exactly — the screw relation read off the conditions.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.symbolic.conditions import DerivationTimeout
from symkin.symbolic.model import SymbolicModel, symbolic_model
from symkin.symbolic.polynomials import free_rows, independent_constant_rows, scale_factors
from symkin.symbolic.rows import known_nodes

MODELS = Path(__file__).parents[1] / "constraints" / "models"
JACK = MODELS / "screw_jack.toml"


def _jack(pitch: float = 0.004) -> symkin.Mechanism:
    data = tomllib.loads(JACK.read_text())
    next(j for j in data["joints"] if j["id"] == "H1")["pitch"] = pitch
    return symkin.Mechanism.from_dict(data)


def _on_motion(theta: float, pitch: float) -> dict:
    """The jack's configuration at screw angle θ (module docstring), as symbol name → value."""
    z = -pitch * theta
    nodes = {"H1": (0.0, 0.0, z), "H1.end": (0.0, 0.0, 1.0 + z), "H1.arm": (0.0, 1.0, z),
             "H1.guide": (-math.cos(theta), -math.sin(theta), 0.0)}
    return {f"{a}_{n}": xyz[k] for n, xyz in nodes.items() for k, a in enumerate("xyz")}


THETAS = (0.0, 0.4, math.pi / 2, 2.5, math.pi, 5.0, 9.0)  # past a full turn too


def test_fixed_nodes_enter_as_numbers_only_with_a_helical_pair():
    jack = _jack()
    assert known_nodes(jack) == {"R1", "R1.axis"}
    sm = SymbolicModel(jack, "nodes")
    names = {s.name for s in sm.config_symbols}
    assert not any(n.endswith(("_R1", "_R1.axis")) for n in names)
    assert {"x_H1", "z_H1.guide"} <= names
    # node-only models keep a symbol for every node, fixed ones included
    for name in ("rssr", "slider_crank", "bennett"):
        mech = symkin.catalogue.get(name)
        assert known_nodes(mech) == frozenset()
        sm = SymbolicModel(mech, "nodes")
        assert len(sm.config_symbols) == mech.dim * len(mech.nodes)


def test_repeated_constant_rows_and_scale_factors():
    """The P's sliders hold the nut's axis nodes on the H's (fixed) axis again: their 4 rows go;
    the helical row's scale gives |E × r|² and |E × g|² (E = (0, 0, 1) here)."""
    jack = _jack()
    sm = symbolic_model(jack, "nodes")
    rows, _ = free_rows(sm, list(sm.rows))
    kept = independent_constant_rows(sm, rows)
    assert sorted(r.owner for r in rows if r not in kept) == ["slider P1", "slider P1", "slider P1.end",
                                                              "slider P1.end"]
    x = {s.name: s for s in sm.config_symbols}
    r2 = (x["x_H1.arm"] - x["x_H1"]) ** 2 + (x["y_H1.arm"] - x["y_H1"]) ** 2
    g2 = x["x_H1.guide"] ** 2 + x["y_H1.guide"] ** 2
    found = [(f.expand(), owner) for f, owner in scale_factors(sm)]
    assert (r2.expand(), "helical H1") in found and (g2.expand(), "helical H1") in found
    # a model without repeated constant rows keeps them all
    crank = symbolic_model(symkin.catalogue.get("slider_crank"), "nodes")
    rows, _ = free_rows(crank, list(crank.rows))
    assert independent_constant_rows(crank, rows) == rows


@pytest.mark.parametrize("pitch", [0.004, -0.03])
def test_screw_jack_conditions_never_vanish_on_its_motion(pitch):
    """DKP-input = 3/4, DKP-output = p²·3/4 and IM > 0 (the reduced equation's e₁₁) at every
    configuration of the motion: no singular configuration, and v = p·ω read off the ratio."""
    jack = _jack(pitch)
    sm = SymbolicModel(jack, "nodes")
    im = sm.im_condition(time_limit=300)
    dkp_in = sm.dkp_condition("input", time_limit=300)
    dkp_out = sm.dkp_condition("output", time_limit=300)
    assert (dkp_in.labels, dkp_out.labels) == (("joint:R1",), ("joint:P1",))
    assert "repeated constant rows dropped (4)" in im.note
    # the equation the IM condition sums over: the numeric core's unit rows minus the repeated ones
    drop = [k for k, owner in enumerate(constraint_rows(jack).owners) if owner in ("slider P1", "slider P1.end")]
    assert len(drop) == 4
    free = list(sm.free)
    for theta in THETAS:
        values = _on_motion(theta, pitch)
        assert dkp_in.evaluate(values) == pytest.approx(0.75, rel=1e-12)
        assert dkp_out.evaluate(values) == pytest.approx(pitch ** 2 * 0.75, rel=1e-12)
        # IM: e_11(Jᵀ J) of the numeric core's rows at that configuration (the product of the 11
        # nonzero eigenvalues: L = F = 1 there)
        coords = {n: (values[f"x_{n}"], values[f"y_{n}"], values[f"z_{n}"]) for n in ("H1", "H1.end", "H1.arm",
                                                                                      "H1.guide")}
        moved = jack.with_coordinates(coords)
        j = np.delete(constraint_rows(moved).matrix, drop, axis=0)[:, free]
        eig = np.sort(np.linalg.eigvalsh(j.T @ j))
        assert eig[0] < 1e-12 * eig[-1] and eig[1] > 1e-3
        e11 = float(np.prod(eig[1:]))
        assert im.evaluate(values) == pytest.approx(e11, rel=1e-9)
        assert e11 > 0.7


def test_cli_conditions_of_the_screw_jack():
    """``symkin conditions`` on the README's screw jack derives all three conditions (exit 0)."""
    run = subprocess.run([sys.executable, "-m", "symkin", "conditions", "--json", str(JACK)],
                         capture_output=True, text=True, timeout=600, env=dict(os.environ))
    assert run.returncode == 0, run.stderr
    data = json.loads(run.stdout)
    assert data["skipped"] == []
    values = {c["kind"]: c["value_at_model"] for c in data["conditions"]}
    assert values["DKP-input"] == pytest.approx(0.75, rel=1e-12)
    assert values["DKP-output"] == pytest.approx(0.004 ** 2 * 0.75, rel=1e-12)
    assert values["IM"] > 0.7
    assert not any(s.startswith(("x_R1", "y_R1", "z_R1")) for s in data["symbols"])


def test_moving_guide_stops_at_the_time_limit():
    """The RHSS loop (H on a moving crank): its helical row is of degree 11 in the guide's
    symbols; the derivation is out of reach, and the time limit stops it (it used to run on
    in an expansion that never checked the limit)."""
    sm = SymbolicModel(symkin.read_model(MODELS / "rhss.toml"), "nodes")
    with pytest.raises(DerivationTimeout, match="time limit"):
        sm.dkp_condition("output", time_limit=0.5)

