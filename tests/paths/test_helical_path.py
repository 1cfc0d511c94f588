"""A path closes only where it comes back to its start itself (the tracer's closed rule).

A screw jack of small pitch (ground–screw R, screw–nut H of pitch p, nut–ground P) comes back
after each turn of its screw to node positions one lead ``2π·p`` from the start: nearer than
the closed rule's radius (two longest steps) but another configuration, so the path goes on,
turn after turn, with the nut at ``−z = p·θ`` (the hand derivation of
``tests/constraints/test_helical.py``: the nut's slide is ``p`` times the screw's rotation).
A four-bar crank, which does come back to its start after one turn, still closes there.
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.curves.stepper import Settings
from symkin.model import catalogue

pytestmark = pytest.mark.usefixtures("in_process_corrector")

JACK = Path(__file__).resolve().parents[1] / "constraints" / "models" / "screw_jack.toml"
PITCH = 0.001
TURNS = 4


@pytest.fixture(scope="module")
def jack():
    data = tomllib.loads(JACK.read_text())
    next(j for j in data["joints"] if j["id"] == "H1")["pitch"] = PITCH
    return symkin.Mechanism.from_dict(data)


def test_small_pitch_jack_turns_several_times(jack):
    # the lead is shorter than the closed rule's radius: without the located check the path
    # would end as closed after one turn (it did)
    assert 2 * math.pi * PITCH / jack.length_scale < 2 * Settings().max_step
    path = symkin.trace(jack, "joint:R1", 0.0, TURNS * 2 * math.pi)
    assert path.stop_reason == "reached"
    assert path.points[-1].input == pytest.approx(TURNS * 2 * math.pi, abs=1e-12)
    k = jack.node_names.index("H1")
    inputs = np.array([pt.input for pt in path.points])
    z = np.array([np.asarray(pt.coordinates).reshape(-1, 3)[k, 2] for pt in path.points])
    assert np.all(np.diff(inputs) > 0)                         # one way, turn after turn
    assert len(path.points) > 4 * TURNS
    assert np.max(np.abs(-z - PITCH * inputs)) < 1e-10
    assert -z[-1] == pytest.approx(PITCH * TURNS * 2 * math.pi, abs=1e-10)


def test_fourbar_crank_path_still_closes_after_one_turn():
    mech = catalogue.get("fourbar_appendix")
    path = symkin.trace(mech, "rotation:crank", 0.0, 720.0, unit="deg")
    assert path.stop_reason == "closed"
    assert path.points[-1].input == pytest.approx(2 * math.pi)
    assert path.points[-2].input < 2 * math.pi
    assert np.array_equal(path.points[-1].coordinates, path.points[0].coordinates)


def test_jack_path_comes_back_by_turning_the_screw_back(jack):
    """Driven back over two turns, the nut retraces its thread to the start (no false closure on the way)."""
    path = symkin.trace(jack, "joint:R1", 0.0, -2 * 2 * math.pi)
    assert path.stop_reason == "reached"
    k = jack.node_names.index("H1")
    for pt in path.points:
        assert -np.asarray(pt.coordinates).reshape(-1, 3)[k, 2] == pytest.approx(PITCH * pt.input, abs=1e-10)
