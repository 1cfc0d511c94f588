"""Model dictionaries are checked completely; every problem is reported at once, by location."""
from __future__ import annotations

import copy
import math

import pytest

from symkin import Mechanism, ModelError
from symkin.model import catalogue


def problems_of(data) -> list[str]:
    with pytest.raises(ModelError) as info:
        Mechanism.from_dict(data)
    return [str(p) for p in info.value.problems]


def test_valid_model_round_trips(fourbar_data):
    m = Mechanism.from_dict(fourbar_data)
    assert Mechanism.from_dict(m.to_dict()) == m
    assert m.free_nodes == ("B", "C") and m.ground_links == () and m.mobility_value == 1


def test_every_problem_is_reported_at_once(fourbar_data):
    d = copy.deepcopy(fourbar_data)
    d["colour"] = "red"
    d["nodes"]["B"] = [0.2, 0.9, 1.0]
    d["nodes"]["C"] = [float("nan"), 1.3]
    d["links"]["crank"] = ["A", "Z"]
    d["inputs"] = [{"rotation": "crank2"}]
    probs = problems_of(d)
    text = "\n".join(probs)
    assert "unknown key(s) 'colour'" in text
    assert "nodes.B: coordinates must have 2 components" in text
    assert "nodes.C: coordinates must be finite" in text
    assert "links.crank: unknown node 'Z'" in text
    assert "inputs[0]: unknown link 'crank2'" in text
    assert len(probs) >= 5


@pytest.mark.parametrize("mutate, expected", [
    (lambda d: d.update(dim=4), "dim: must be 2 (planar) or 3 (spatial)"),
    (lambda d: d.update(dim=True), "dim: must be 2 (planar) or 3 (spatial)"),
    (lambda d: d.pop("dim"), "dim: missing"),
    (lambda d: d.pop("nodes"), "nodes: missing"),
    (lambda d: d["links"].update(stub=["A"]), "links.stub: a link needs at least 2 nodes"),
    (lambda d: d["links"].update(loop=["B", "C", "B"]), "links.loop: node(s) B repeated"),
    (lambda d: d["nodes"].update(C=[0.2, 0.9]), "links.coupler: zero-length bar"),
    (lambda d: d["nodes"].update(E=[5.0, 5.0]), "nodes.E: node belongs to no link"),
    (lambda d: d.update(fixed=["A", "A", "D"]), "fixed: node 'A' listed twice"),
    (lambda d: d.update(fixed=["A", "Q"]), "fixed: unknown node 'Q'"),
    (lambda d: d.update(inputs=[{"rotation": "crank", "slide": "x"}]), "needs exactly one of"),
    (lambda d: d.update(inputs=[{"spin": "crank"}]), "unknown key(s) 'spin'"),
    (lambda d: d.update(inputs=[{"velocity": "A"}]), "node A is fixed"),
    (lambda d: d.update(inputs=[{"velocity": "B", "component": "z"}]), "component must be one of x, y"),
    (lambda d: d.update(inputs=[{"slide": "piston"}]), "unknown slider 'piston'"),
    (lambda d: d.update(inputs=[{"joint": ["crank", "rocker"]}]), "share no node"),
    (lambda d: d.update(inputs=[{"rotation": "crank", "axis": [0, 0, 1]}]), "a planar rotation has no axis"),
    (lambda d: d.update(mobility=-1), "mobility: must be a non-negative integer"),
    (lambda d: d.update(platform="hull"), "platform: unknown link 'hull'"),
    (lambda d: d.update(platform="coupler", platform_dof=7), "platform_dof: must be an integer from 0 to 3"),
    (lambda d: d.update(sliders=[{"node": "C", "point": [0, 0], "direction": [0, 0]}]), "zero direction"),
    (lambda d: d.update(sliders=[{"node": "C", "point": [0, 0], "direction": [1, 0]}]),
     "node C is 1.3 away from its line"),
    (lambda d: d.update(sliders=[{"node": "A", "point": [0, 0], "direction": [1, 0]}]), "node A is fixed"),
    (lambda d: d.update(sliders=[{"node": "C", "line": ["A", "B"], "link": "coupler"}]),
     "node(s) A of the line are not nodes of link coupler"),
    (lambda d: d.update(sliders=[{"node": "C", "point": [0, 0, 0], "normal": [0, 0, 1]}]),
     "'normal' (a fixed plane) is for spatial models"),
])
def test_single_problem_is_named(fourbar_data, mutate, expected):
    d = copy.deepcopy(fourbar_data)
    mutate(d)
    text = "\n".join(problems_of(d))
    assert expected in text


def test_spatial_rotation_needs_axis():
    d = catalogue.data("rssr")
    d["inputs"] = [{"rotation": "crank"}]
    assert any("a spatial rotation needs an axis" in p for p in problems_of(d))


def test_slider_reference_by_node_or_id():
    d = catalogue.data("slider_crank")
    d["outputs"] = [{"slide": "C"}]  # the node has one slider: naming the node works
    m = Mechanism.from_dict(d)
    assert m.slider("C").id == "piston"
    assert m.outputs[0].labels(2) == ("slide:piston",)


def test_length_scale_is_homogeneous(fourbar):
    scaled = fourbar.with_coordinates({n: tuple(1000 * v for v in xyz) for n, xyz in fourbar.nodes})
    assert math.isclose(scaled.length_scale, 1000 * fourbar.length_scale, rel_tol=1e-12)


def test_rotation_of_a_rod_about_its_own_axis_is_rejected():
    d = catalogue.data("rssr")
    d["outputs"] = [{"rotation": "coupler", "axis": ["B", "C"]}]
    assert any("spin of a rod about its own axis" in p for p in problems_of(d))
    d["outputs"] = [{"rotation": "coupler", "axis": [0.0, 0.0, 1.0]}]  # across the rod: fine
    assert Mechanism.from_dict(d).outputs[0].axis == (0.0, 0.0, 1.0)
