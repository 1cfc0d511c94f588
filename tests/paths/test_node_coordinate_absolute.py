"""The absolute value of a node-coordinate label is that node's coordinate on the label's own axis.

``velocity:O.y`` (a component label) and the components of ``velocity: P`` (a whole-node
output) both name an axis; the absolute value printed by ``modes`` and written by ``path``
must be read on it (a regression: ``velocity:O.y`` was read on x)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from symkin.model.catalogue import get
from symkin.model.model_file import read_model
from symkin.numeric.coordinates import input_coordinates, parse_input_label
from symkin.paths.trace import _node_coordinate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("label, axis", [("velocity:O.x", 0), ("velocity:O.y", 1)])
def test_component_label_reads_its_axis(label, axis):
    mech = read_model(EXAMPLES / "rpr_3.toml")
    x = np.array([xyz for _, xyz in mech.nodes], float)
    c = parse_input_label(mech, label)
    assert _node_coordinate(mech, c, x) == x[mech.node_index()["O"], axis]


def test_whole_node_output_components_read_their_axes():
    mech = get("five_bar")
    x = np.array([xyz for _, xyz in mech.nodes], float)
    cs = [c for c in input_coordinates(mech, mech.outputs) if c.parameter.kind == "velocity"]
    assert [c.label for c in cs] == ["velocity:P.x", "velocity:P.y"]
    p = x[mech.node_index()["P"]]
    assert [_node_coordinate(mech, c, x) for c in cs] == [p[0], p[1]]
    assert p[0] != p[1]


def test_rotation_has_no_node_coordinate():
    mech = read_model(EXAMPLES / "rpr_3.toml")
    x = np.array([xyz for _, xyz in mech.nodes], float)
    assert _node_coordinate(mech, parse_input_label(mech, "rotation:platform"), x) is None
