"""A traced "curve" whose image in the axes is one point is one singular point of the map.

The 3-RPR of ``models/rpr_3.toml`` at constant orientation, O over [1, 4] × [0.5, 3.5]: at the
corner O = (1, 0.5) the platform's C1 lies on the base pivot A1 (leg 1 of zero length), so cylinder 1
turns freely about A1 — a one-parameter family of type-1 configurations over that one map point.
It is reported as ONE point, classified by the core, and seeds nothing (before: a closed type-1
"curve" there with 109 meetings, 65 seeded pieces and 93 cusps).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin

MODELS = Path(__file__).resolve().parent / "models"
CORNER = np.array([1.0, 0.5])


@pytest.fixture(scope="module")
def corner_map():
    mech = symkin.read_model(MODELS / "rpr_3.toml")
    return symkin.workspace_map(mech, x="velocity:O.x=1.0:4.0", y="velocity:O.y=0.5:3.5", n=161,
                                hold=("rotation:platform",), refine=True)


def test_the_zero_length_leg_is_one_point(corner_map):
    at_corner = [p for p in corner_map.points if np.linalg.norm(np.array(p.at) - CORNER) < 1e-9]
    assert len(at_corner) == 1
    assert set(at_corner[0].types) == {"DKP-input", "DKP-output"}  # the core's classification
    assert len(corner_map.points) == 1


def test_no_curve_is_seeded_at_the_point(corner_map):
    assert [c.kind for c in corner_map.curves] == ["DKP-input"]  # the conic; no piece seeded at the corner
    for c in corner_map.curves:
        pts = np.asarray(c.points, float)
        assert np.sum(np.linalg.norm(pts - CORNER, axis=1) < 1e-9) <= 1
