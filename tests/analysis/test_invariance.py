"""Rigid motions and uniform scaling (mm vs m, 1e-3 to 1e3) leave DOF, ranks and classification unchanged.

Checked with hypothesis on every catalogue mechanism and every model file of the paper's examples.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symkin import analyze, read_model
from symkin.model import catalogue
from tests.conftest import EXAMPLES

MODELS = [("catalogue", n) for n in catalogue.names()] + \
         [("file", p.name) for p in sorted(EXAMPLES.glob("*.toml")) + sorted(EXAMPLES.glob("*.json"))]


def load(source: str, name: str):
    return catalogue.get(name) if source == "catalogue" else read_model(EXAMPLES / name)


def rotation_matrix(dim: int, angles) -> np.ndarray:
    if dim == 2:
        c, s = math.cos(angles[0]), math.sin(angles[0])
        return np.array([[c, -s], [s, c]])
    a, b, g = angles
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rx = np.array([[1, 0, 0], [0, math.cos(g), -math.sin(g)], [0, math.sin(g), math.cos(g)]])
    return rz @ ry @ rx


def signature(result, frame_free: bool = False):
    """What must not change.  The r of a relation among Cartesian components (velocity:P.x,
    twist:L.vx) depends on the frame, so under rotations only the number of relations is compared."""
    def rel(rs):
        return tuple(r.r for r in rs) if frame_free else len(rs)
    return (result.dof, result.types, result.input_rank, result.output_rank, result.platform_dof,
            result.locked_links, rel(result.input_relations), rel(result.output_relations),
            len(result.uncontrolled_motions))


@pytest.mark.parametrize("source, name", MODELS)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(angles=st.tuples(*[st.floats(-math.pi, math.pi)] * 3),
       shift=st.tuples(*[st.floats(-100, 100)] * 3),
       log_scale=st.floats(-3, 3))
def test_similarity_leaves_the_analysis_unchanged(source, name, angles, shift, log_scale):
    mech = load(source, name)
    base = signature(analyze(mech))
    scale = 10.0 ** log_scale
    moved = mech.moved(rotation_matrix(mech.dim, angles), shift[: mech.dim], scale)
    assert signature(analyze(moved)) == base


@pytest.mark.parametrize("source, name", MODELS)
def test_millimetres_and_metres_agree(source, name):
    mech = load(source, name)
    a, b = analyze(mech), analyze(mech.moved(scale=1000.0))
    assert signature(a, frame_free=True) == signature(b, frame_free=True)
    assert a.im_indicator == pytest.approx(b.im_indicator, rel=1e-9, abs=1e-12)
