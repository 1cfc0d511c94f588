"""Angle windows of a map are taken modulo 360° (issue 20 §3).

The five-bar over ``rotation:crank1=360:720`` assembled 0 % where ``0:360`` assembled 72.6 %
and ``-360:0`` 12.6 %: an angle axis was measured on the model's branch only.  Now the branch
is shifted by whole turns to the window, so a window shifted by a turn maps the same.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin.cli import main
from symkin.model.catalogue import get
from symkin.workspace.maps import workspace_map
from symkin.workspace.system import map_system, window_note


@pytest.fixture(scope="module")
def maps():
    mech = get("five_bar")
    return {w: workspace_map(mech, x=f"rotation:crank1={w}", y="rotation:crank2=0:360", n=13, refine=False)
            for w in ("0:360", "360:720", "-360:0")}


def test_a_window_shifted_by_a_turn_maps_the_same(maps):
    base = maps["0:360"].modes[0]
    assert base.assembled.mean() > 0.4
    for w in ("360:720", "-360:0"):
        m = maps[w].modes[0]
        assert np.array_equal(m.assembled, base.assembled), w
        ok = base.assembled
        np.testing.assert_allclose(m.dkp_input[ok], base.dkp_input[ok], atol=1e-9)
        np.testing.assert_allclose(m.dkp_output[ok], base.dkp_output[ok], atol=1e-9)


def test_the_result_says_how_angles_are_measured(maps):
    notes = " ".join(maps["360:720"].notes)
    assert "rotation:crank1: angles are taken modulo a turn" in notes and "(306.87, 666.87]" in notes


def test_branch_follows_the_window_and_holds():
    mech = get("five_bar")
    plain = map_system(mech, "rotation:crank1", "rotation:crank2")
    shifted = map_system(mech, "rotation:crank1", "rotation:crank2", windows=((360, 720), (-400, -300)))
    turns = [(b.offset - a.offset) / (2 * math.pi) for a, b in zip(plain.axes, shifted.axes)]
    assert turns == pytest.approx([1.0, -1.0])
    q, ok, _, _ = shifted.solve(shifted.q0[None], shifted.to_internal([[400.0, -330.0]]))
    q2, ok2, _, _ = plain.solve(plain.q0[None], plain.to_internal([[40.0, 30.0]]))
    assert ok[0] and ok2[0] and np.allclose(q, q2, atol=1e-9)
    inside = window_note(shifted.axes[0], 400.0, 500.0)
    assert inside is None and window_note(shifted.axes[0], 360.0, 720.0) is not None


def test_map_cli_assembles_past_a_turn(capsys):
    code = main(["map", "catalogue:five_bar", "--x=rotation:crank1=360:720", "--y=rotation:crank2=0:360",
                 "--n", "9", "--no-refine", "--no-progress"])
    out = capsys.readouterr().out
    assert code == 0 and "assembled at 0.0%" not in out and "assembled at" in out
    assert "angles are taken modulo a turn" in out
