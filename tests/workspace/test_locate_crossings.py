"""Sign-change crossings located in batches (:func:`symkin.workspace.locate.locate_crossings`) agree with the
one-at-a-time locator (:func:`symkin.workspace.locate.locate_crossing`): the 3-RPR of ``models/rpr_3.toml`` at
constant orientation, its type-2 (DKP-input) conic crossing the grid rows."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from symkin.kinds import Kind
import symkin
from symkin.workspace.grid import continue_mode
from symkin.workspace.locate import locate_crossing, locate_crossings
from symkin.workspace.locus_problems import LocusProblems, LocusSystem
from symkin.workspace.system import map_system


@pytest.fixture(scope="module")
def brackets():
    mech = symkin.read_model(Path(__file__).resolve().parent / "models" / "rpr_3.toml")
    s = map_system(mech, "velocity:O.x", "velocity:O.y", hold=["rotation:platform"])
    xs, ys = np.linspace(1.5, 4.5, 21), np.linspace(0.75, 3.25, 21)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    pb = LocusProblems(LocusSystem.of(s))
    scale = np.array(s.axis_scale, float)
    v, asm, q = np.asarray(g.dkp_input, float), np.asarray(g.assembled, bool), np.asarray(g.q, float)
    rows = []
    for j in range(len(ys)):
        for i in range(len(xs) - 1):
            if asm[j, i] and asm[j, i + 1] and v[j, i] * v[j, i + 1] < 0:
                rows.append((np.array([xs[i], ys[j]]) / scale, q[j, i] / pb.scale,
                             np.array([xs[i + 1], ys[j]]) / scale, q[j, i + 1] / pb.scale))
    assert len(rows) >= 5
    return pb, rows


def test_batched_crossings_are_the_single_ones(brackets):
    pb, rows = brackets
    batch = locate_crossings(pb, Kind.DKP_INPUT, *(np.array([r[k] for r in rows]) for k in range(4)))
    assert len(batch) == len(rows) and all(b is not None for b in batch)
    for r, (y, s) in zip(rows, batch):
        y1, s1 = locate_crossing(pb, Kind.DKP_INPUT, *r)
        assert abs(s - s1) <= 1e-9 and np.abs(y - y1).max() <= 1e-9
        assert 0.0 <= s <= 1.0 and abs(pb.tests(y)[Kind.DKP_INPUT]) <= 1e-10


def test_no_bracket_no_crossing(brackets):
    assert locate_crossings(brackets[0], Kind.DKP_INPUT, np.zeros((0, 2)), np.zeros((0, brackets[1][0][1].size)), np.zeros((0, 2)),
                            np.zeros((0, brackets[1][0][1].size))) == []
