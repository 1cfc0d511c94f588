"""Warnings for legal models a user probably got wrong (issue 7 §3)."""
from __future__ import annotations

import json

import pytest

from symkin import Mechanism, analyze, read_model, render_text
from symkin.cli import main
from symkin.model import catalogue, diagnostics
from tests.conftest import EXAMPLES


def _with(name: str, **changes) -> Mechanism:
    d = catalogue.data(name)
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(d.get(key), dict):
            d[key].update(value)
        else:
            d[key] = value
    return Mechanism.from_dict(d)


def test_a_floating_part_is_named():
    m = _with("fourbar_appendix", nodes={"P": [5.0, 5.0], "Q": [6.0, 5.0]}, links={"loose": ["P", "Q"]})
    a = analyze(m)
    (w,) = a.warnings
    assert "Nodes P, Q (links loose) are connected to nothing fixed" in w
    assert a.dof == 1 + 3  # still analysed: the bar's rigid motions are counted in L


def test_a_part_held_by_a_fixed_slider_or_a_moving_line_does_not_float():
    assert analyze(catalogue.get("slider_crank")).warnings == ()
    # a node on the moving line of a grounded link belongs to that link's part
    d = catalogue.data("fourbar_appendix")
    d["nodes"]["P"] = [1.15, 1.1]
    d["links"]["arm"] = ["P", "C"]
    d["sliders"] = [{"id": "s", "node": "P", "line": ["B", "C"], "link": "coupler"}]
    assert diagnostics.topology_warnings(Mechanism.from_dict(d)) == ()
    chain = Mechanism.from_dict({"dim": 2, "fixed": ["A"], "nodes": {"A": [0, 0], "B": [1, 0], "C": [3, 0]},
                                    "links": {"ab": ["A", "B"], "bc": ["B", "C"]}})
    assert diagnostics.topology_warnings(chain) == ()  # held by its fixed end


def test_no_fixed_node_at_all():
    d = catalogue.data("braced_square")
    d["fixed"] = []
    (w,) = analyze(Mechanism.from_dict(d)).warnings
    assert w.startswith("The model has no fixed node")
    assert "declare 'fixed'" in w


def test_the_same_bar_listed_twice():
    m = _with("fourbar_appendix", links={"tie": ["C", "B"]})
    (w,) = analyze(m).warnings
    assert w == ("Links coupler and tie join the same nodes (B, C): the same bar is listed twice "
                 "(it carries a self-stress).")


def test_the_same_body_listed_twice():
    d = catalogue.data("rrr_3")
    d["links"]["plate"] = ["C3", "C1", "C2"]
    (w,) = diagnostics.topology_warnings(Mechanism.from_dict(d))
    assert "Links platform and plate join the same nodes (C1, C2, C3): the same body is listed twice" in w


def test_mobility_taken_from_the_inputs():
    """A five-bar with one input listed and no 'mobility': F = 1 is taken, L = 2 is found."""
    d = catalogue.data("five_bar")
    d["inputs"] = d["inputs"][:1]
    a = analyze(Mechanism.from_dict(d))
    assert a.types[0] == "IM" and (a.mobility, a.dof) == (1, 2)
    (w,) = a.warnings
    assert "No 'mobility' is declared, so F = 1 was taken from the 1 scalar input(s) (rotation:crank1)" in w
    assert "L = 2" in w and "declare mobility = 2" in w
    d["mobility"] = 2
    assert analyze(Mechanism.from_dict(d)).warnings == ()


def test_warnings_end_the_text_report():
    m = _with("fourbar_appendix", links={"tie": ["C", "B"]})
    text = render_text(analyze(m)).rstrip("\n").splitlines()
    assert text[-1].startswith("Warning: Links coupler and tie")


@pytest.mark.parametrize("name", catalogue.names())
def test_catalogue_mechanisms_are_clean(name):
    assert analyze(catalogue.get(name)).warnings == ()


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_paper_examples_are_clean(path):
    assert analyze(read_model(path)).warnings == ()


def test_cli_json_lists_warnings(tmp_path, capsys):
    assert main(["analyze", str(EXAMPLES / "fourbar_appendix.toml"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["warnings"] == [] and data["redundant_constraints"] == 0 and data["self_stresses"] == []
    d = catalogue.data("five_bar")
    d["inputs"] = d["inputs"][:1]
    path = tmp_path / "five_bar.json"
    path.write_text(json.dumps(d))
    assert main(["analyze", str(path), "--json"]) == 0
    (w,) = json.loads(capsys.readouterr().out)["warnings"]
    assert "declare mobility = 2" in w
    assert main(["analyze", str(path)]) == 0
    assert capsys.readouterr().out.rstrip().splitlines()[-1] == f"Warning: {w}"


def test_topology_warnings_are_cached_along_a_path():
    """They depend on the topology only: a moved copy of the mechanism reuses the answer."""
    m = _with("fourbar_appendix", links={"tie": ["C", "B"]})
    first = diagnostics.topology_warnings(m)
    before = diagnostics._topology_warnings.cache_info().hits
    moved = m.with_coordinates({"B": (0.3, 0.9)})
    assert diagnostics.topology_warnings(moved) is first
    assert diagnostics._topology_warnings.cache_info().hits == before + 1
