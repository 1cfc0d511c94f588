"""LIM events on paths: a link that stops while the mechanism moves on (§IV-B-3), located and classified.

Independent truth, by elementary geometry (no symkin): in a crank-rocker four-bar A0-A-B-B0 the
rocker B0-B stops where the crank and the coupler side A-B are collinear, i.e. where
``|A0 B| = l_AB ± l_crank``.  There ``B`` is the intersection of the circles ``(A0, |A0 B|)`` and
``(B0, l_rocker)`` on the side of the model's assembly mode, and the crank points along
``A0 → B`` (extended) or ``B → A0`` (folded): the law of cosines in the triangle A0-B-B0 gives
the crank angle.  The two models below put that four-bar inside a Stephenson III six-bar (the
rocker is neither input nor output) in metres and in millimetres, and alone with the coupler's
rotation as output.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from symkin.cli import main
from symkin.kinds import Kind
from symkin.model.model_file import read_model
from symkin.paths.trace import trace
from tests.conftest import ROOT

MODELS = ROOT / "tests" / "paths" / "models"


def rocker_stops(mech) -> list[float]:
    """Crank angles (from the model's crank angle, in [0, 2π)) where crank and A-B are collinear."""
    x = {n: np.array(c, float) for n, c in mech.coordinates().items()}
    a0, a, b, b0 = x["A0"], x["A"], x["B"], x["B0"]
    crank, side, rocker, ground = (float(np.linalg.norm(v)) for v in (a - a0, b - a, b - b0, b0 - a0))
    mode = math.copysign(1.0, float(np.cross(np.append(b0 - a, 0), np.append(b - a, 0))[2]))
    phi0 = math.atan2(*(a - a0)[::-1])
    out = []
    for d, along in ((side + crank, 1.0), (side - crank, -1.0)):
        alpha = math.acos((d * d + ground * ground - rocker * rocker) / (2 * d * ground))  # at A0, law of cosines
        base = math.atan2(*(b0 - a0)[::-1])
        for sign in (1.0, -1.0):
            bb = a0 + d * np.array([math.cos(base + sign * alpha), math.sin(base + sign * alpha)])
            aa = a0 + along * crank * (bb - a0) / d
            if math.copysign(1.0, float(np.cross(np.append(b0 - aa, 0), np.append(bb - aa, 0))[2])) == mode:
                out.append((math.atan2(*(aa - a0)[::-1]) - phi0) % (2 * math.pi))
    return sorted(out)


@pytest.mark.parametrize("model", ["stephenson3_m", "stephenson3_mm", "fourbar_coupler_output"])
def test_rocker_stops_are_lim_events_where_crank_and_coupler_are_collinear(model):
    mech = read_model(MODELS / f"{model}.toml")
    exact = rocker_stops(mech)
    assert len(exact) == 2
    path = trace(mech, stop=2 * math.pi)
    assert path.stop_reason == "reached"
    lims = [e for e in path.events if e.kind == Kind.LIM]
    assert len(lims) == 2
    found = sorted(e.input % (2 * math.pi) for e in lims)
    np.testing.assert_allclose(found, exact, rtol=0, atol=1e-8)
    for e in lims:
        assert e.confirmed and e.analysis.types == (Kind.LIM,)
        assert e.analysis.locked_links == ("rocker",) and e.analysis.dof == 1
        assert e.tests == ("LIM:rocker",)


def test_the_same_lim_events_in_millimetres_and_metres():
    paths = [trace(read_model(MODELS / f"stephenson3_{u}.toml"), stop=2 * math.pi) for u in ("m", "mm")]
    events = [[(str(e.kind), e.tests, e.analysis and e.analysis.types) for e in p.events] for p in paths]
    assert events[0] == events[1]
    np.testing.assert_allclose([e.input for e in paths[0].events], [e.input for e in paths[1].events],
                               rtol=0, atol=1e-10)


def test_an_output_dead_point_is_one_dkp_output_event_carrying_the_lim_of_its_link():
    path = trace(read_model(MODELS / "stephenson3_m.toml"), stop=2 * math.pi)
    dkp = [e for e in path.events if e.kind == Kind.DKP_OUTPUT]
    # the one at 0.9° is met again in the last step, beyond the target 360° (located before the end)
    assert len({round(e.input % (2 * math.pi), 9) for e in dkp}) == 2
    for e in dkp:
        assert e.kinds == (Kind.DKP_OUTPUT, Kind.LIM) and e.tests == ("DKP-output", "LIM:output")
        assert e.analysis.types == (Kind.DKP_OUTPUT, Kind.LIM) and e.analysis.locked_links == ("output",)


def test_path_command_reports_the_lim_events(capsys):
    model = str(MODELS / "stephenson3_mm.toml")
    assert main(["path", model, "--to", "360", "--json", "--no-progress"]) == 0
    data = json.loads(capsys.readouterr().out)
    lims = [e for e in data["events"] if e["kind"] == "LIM"]
    assert len(lims) == 2 and all(e["locked_links"] == ["rocker"] and e["types"] == ["LIM"] for e in lims)
    assert main(["path", model, "--to", "360", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert text.count("LIM at rotation:crank") == 2
    assert text.count("link impossible motion (LIM): rocker cannot move") == 2
