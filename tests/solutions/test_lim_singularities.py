"""LIM configurations in ``symkin singularities``: a Stephenson III six-bar against elementary geometry.

The model (``models/stephenson3_mm.toml``, and the same in metres): a crank-rocker four-bar
A0-A-B-B0 (crank 12, ternary coupler side A-B 35, rocker B0-B 30, ground 40) whose coupler
carries C; the dyad C-D-D0 (40, 35) to a third pivot never folds, so the crank turns fully on
all four circuits (two assembly modes of the four-bar times two of the dyad).  The rocker
stops, and is locked while everything else moves (LIM, paper §V), where crank and coupler
side A-B are collinear: ``|A0 B| = l_crank ± l_AB``.  No IM or DKP test changes sign there;
the LIM system of the rocker (closure + det[J; rate row of the rocker] = 0) finds them.

The expected configurations are built here by elementary geometry (no symkin): B on the
circle about B0 of radius l_rocker and on the circle about A0 of radius l_crank ± l_AB, A on
the segment A0-B (``+``) or its extension beyond A0 (``−``), the crank angle atan2(A − A0).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from symkin.cli import main
from symkin.model.model_file import read_model

pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global] "
                                      "(pip install -e '.[global]')")

from symkin.solutions.circuits import singularities  # noqa: E402
from tests.solutions.test_solve_all import circle_points  # noqa: E402

MODELS = Path(__file__).parent / "models"
ANGLE = 1e-8   # rad: crank angles, geometry against symkin
PLACE = 1e-9   # length scales: node positions, geometry against symkin


def locked_rocker_configurations(mech):
    """(crank angle from the model's, A, B) of every four-bar configuration with crank and A-B collinear."""
    x = {n: np.array(v, float) for n, v in mech.coordinates().items()}
    a0, b0 = x["A0"], x["B0"]
    crank, ab, rocker = (float(np.linalg.norm(x[p] - x[q])) for p, q in (("A", "A0"), ("A", "B"), ("B", "B0")))
    theta0 = math.atan2(*(x["A"] - a0)[::-1])
    out = []
    for sign in (1.0, -1.0):   # A0, A, B in this order (|A0 B| = crank + AB), or A between... beyond A0
        for b in circle_points(a0, ab + sign * crank, b0, rocker):
            u = (b - a0) / np.linalg.norm(b - a0)
            a = a0 + sign * crank * u
            assert abs(np.linalg.norm(b - a) - ab) <= 1e-12 * ab
            out.append((math.remainder(math.atan2(*(a - a0)[::-1]) - theta0, 2 * math.pi), a, b))
    return out


@pytest.fixture(scope="module")
def results():
    return {unit: singularities(read_model(MODELS / f"stephenson3_{unit}.toml")) for unit in ("mm", "m")}


def lim_of(result, link="rocker"):
    return [s for s in result.singularities if link in s.locked_links]


@pytest.mark.slow
@pytest.mark.parametrize("unit", ["mm", "m"])
def test_every_locked_rocker_configuration_by_elementary_geometry(results, unit):
    r = results[unit]
    mech = r.mechanism
    expected = locked_rocker_configurations(mech)
    assert len(expected) == 4
    got = lim_of(r)
    # each four-bar configuration twice: the dyad's two assembly modes (two circuits each)
    assert len(got) == 2 * len(expected) == 8
    for s in got:
        assert s.types == ("LIM",) and s.locked_links == ("rocker",) and s.dof == 1
        assert "LIM" in s.kinds
    scale = mech.length_scale
    for theta, a, b in expected:
        near = [s for s in got if abs(math.remainder(s.input - theta, 2 * math.pi)) <= ANGLE]
        assert len(near) == 2, (theta, sorted(s.input for s in got))
        for s in near:
            assert np.linalg.norm(np.array(s.configuration["A"]) - a) <= PLACE * scale
            assert np.linalg.norm(np.array(s.configuration["B"]) - b) <= PLACE * scale
        assert {s.circuit for s in near} == {near[0].circuit, near[1].circuit} and near[0].circuit != near[1].circuit
    # nothing else is LIM with the rocker locked; every other configuration is DKP-output (the output D0-D stops)
    assert all("DKP-output" in s.types and s.locked_links == ("output",) for s in r.singularities if s not in got)
    assert len(r.circuits) == 4 and all(c.full_turn and c.closed for c in r.circuits)


@pytest.mark.slow
@pytest.mark.parametrize("unit", ["mm", "m"])
def test_the_lim_system_cross_check(results, unit):
    r = results[unit]
    by_name = {ch.name: ch for ch in r.checks}
    assert set(by_name) == {"DKP-input", "DKP-output", "LIM:rocker"}   # the output's own is the DKP-output system
    lim = by_name["LIM:rocker"]
    assert lim.kind == "LIM" and lim.link == "rocker" and lim.label == "rotation:rocker"
    assert lim.homotopy == lim.matched == 8 and lim.agree is True and lim.solver == "bertini"
    assert lim.traced == 8   # the LIM events that symkin.trace locates where the rocker is locked
    assert by_name["DKP-input"].homotopy == 0   # the crank turns fully
    assert r.agree is True and not r.warnings


@pytest.mark.slow
def test_millimetres_and_metres_give_the_same_answer(results):
    """The same configurations (crank angle, types, locked links) and the same circuits (their crank
    angles), whichever circuit the search numbers first."""
    def key(r):  # the crank angle, then (the dyad's two modes at one angle) where D is, in length scales
        return lambda s: (round(s.input, 6), tuple(np.round(np.array(s.configuration["D"]) / r.mechanism.length_scale, 6)))

    a, b = (sorted(r.singularities, key=key(r)) for r in (results["mm"], results["m"]))
    assert [(s.types, s.locked_links, s.dof) for s in a] == [(s.types, s.locked_links, s.dof) for s in b]
    assert np.allclose([s.input for s in a], [s.input for s in b], atol=1e-9)
    # the same partition into circuits: two configurations share a circuit in mm exactly when they do in m
    assert [[s.circuit == t.circuit for t in a] for s in a] == [[s.circuit == t.circuit for t in b] for s in b]


def test_cli_without_msolve_lists_the_lim_configurations(capsys, monkeypatch, tmp_path):
    """Without the extra ``exact`` (msolve) the LIM system's paths are Bertini's, within max_paths.

    On the four-bar whose rocker is neither input nor output (its output is the coupler's
    rotation; ``tests/paths/models/fourbar_coupler_output.toml``): the rocker stops where crank
    and coupler are collinear, four configurations, one on each side of each circuit's dead
    positions.  (The six-bar's own systems take minutes through Bertini alone: the fixture
    ``results`` checks the six-bar with msolve.)
    """
    import symkin.solutions.exact as exact

    model = Path(__file__).parents[1] / "paths" / "models" / "fourbar_coupler_output.toml"
    monkeypatch.setattr(exact, "msolve_executable", lambda: None)
    png = tmp_path / "c.png"
    assert main(["singularities", str(model), "--json", "--unit", "rad", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    lim = [s for s in out["singularities"] if "rocker" in s["locked_links"]]
    assert len(lim) == 4 and all(s["types"] == ["LIM"] and s["kinds"] == ["LIM"] and s["dof"] == 1 for s in lim)
    expected = locked_rocker_configurations(read_model(model))
    assert len(expected) == 4
    for theta, _, _ in expected:
        assert sum(abs(math.remainder(s["input"] - theta, 2 * math.pi)) <= ANGLE for s in lim) == 1
    (check,) = [c for c in out["cross_check"] if c["name"] == "LIM:rocker"]
    assert check["kind"] == "LIM" and check["solver"] == "bertini" and check["agree"] is True
    assert png.stat().st_size > 10_000
    assert main(["singularities", str(model)]) == 0
    text = capsys.readouterr().out
    assert text.count("LIM (L = 1, locked links: rocker)") == 4
    assert "cross-check LIM:rocker: 4 real solution(s)" in text


def test_lim_links_are_the_rockers_other_than_input_and_output():
    from symkin.solutions.lim_systems import lim_coordinates, lim_links

    mech = read_model(MODELS / "stephenson3_mm.toml")
    assert lim_links(mech) == ("crank", "rocker", "output")
    assert [c.label for c in lim_coordinates(mech)] == ["rotation:rocker"]


@pytest.mark.slow
def test_the_circuit_plot_marks_the_lim_configurations(results):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    from symkin.plots.circuits import LIM_STYLE, plot_circuits

    r = results["mm"]
    ax = plot_circuits(r)
    lim = [line for line in ax.lines if line.get_gid() == "singularity:LIM"]
    assert len(lim) == 8 and all(line.get_marker() == LIM_STYLE["marker"] for line in lim)
    # the plot's axes are absolute angles (the crank's direction), whole turns taken off
    from symkin.paths.trace import CoordinateValues

    mech = r.mechanism
    offset = CoordinateValues(mech, [r.input])(np.array([c for _, c in mech.nodes], float), "rad")[r.input]["absolute"]
    turn = 2 * np.pi
    got = sorted(float(np.remainder(line.get_xdata()[0], turn)) for line in lim)
    assert np.allclose(got, sorted(float(np.remainder(s.input + offset, turn)) for s in lim_of(r)), atol=1e-12)
    assert "LIM (rocker locked)" in [t.get_text() for t in ax.get_legend().get_texts()]
