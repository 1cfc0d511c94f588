"""Structures (F = 0) are singular only when they flex (issue 7 §1)."""
from __future__ import annotations

import json

import pytest

from symkin import Mechanism, analyze, render_text
from symkin.cli import main
from symkin.model import catalogue

MECHANISM_WORDS = ("input", "output", "Gosselin", "Zlatanov", "Locked links", "LIM")


@pytest.mark.parametrize("name", ["pratt_truss", "braced_square"])
def test_a_rigid_truss_is_not_singular(name):
    a = analyze(catalogue.get(name))
    assert (a.dof, a.mobility, a.types, a.singular) == (0, 0, (), False)
    # every link is motionless: listed as data, not a link impossible motion
    assert set(a.locked_links) == set(catalogue.get(name).moving_links)
    text = render_text(a)
    assert "The structure is rigid" in text and "not singular" in text
    assert not any(w in text for w in MECHANISM_WORDS)


def test_a_spatial_tripod_is_a_rigid_structure():
    """Apex D on three bars to a fixed, non-collinear base: rigid (3 rows, 3 coordinates), no LIM."""
    m = Mechanism.from_dict({
        "dim": 3, "mobility": 0, "fixed": ["A", "B", "C"],
        "nodes": {"A": [0.0, 0.0, 0.0], "B": [2.0, 0.0, 0.0], "C": [0.0, 2.0, 0.0], "D": [0.5, 0.5, 1.5]},
        "links": {"AD": ["A", "D"], "BD": ["B", "D"], "CD": ["C", "D"]}})
    a = analyze(m)
    assert (a.dof, a.types, a.redundant_constraints) == (0, (), 0)


def test_statically_determinate_report():
    text = render_text(analyze(catalogue.get("pratt_truss")))
    assert "No self-stress: the structure is statically determinate." in text


def test_a_flexible_structure_is_im_with_its_flexes():
    """B between fixed A and C on their line: the circles |AB| = 1 and |CB| = 1 are tangent, so
    B moves normal to the line to first order (L = 1) — and the bars carry equal tensions."""
    a = analyze(catalogue.get("collinear_truss"))
    assert (a.dof, a.mobility, a.types) == (1, 0, ("IM",))
    assert a.redundant_constraints == 1 and a.self_stresses[0].as_dict() == pytest.approx({"AB": 1.0, "BC": 1.0})
    assert abs(a.motion.V[3, 0]) == pytest.approx(1.0)  # the flex is y_B
    text = render_text(a)
    assert "The structure is flexible: 1 infinitesimal flex (L = 1 > F = 0)" in text
    assert "increased mobility (IM)" in text
    assert "1 redundant constraint: a self-stress in bars AB, BC" in text
    assert not any(w in text for w in MECHANISM_WORDS)


def test_two_flexes_are_counted():
    """Two independent collinear dyads: 2 infinitesimal flexes."""
    m = Mechanism.from_dict({
        "dim": 2, "mobility": 0, "fixed": ["A", "C", "D", "F"],
        "nodes": {"A": [0.0, 0.0], "B": [1.0, 0.0], "C": [2.0, 0.0],
                  "D": [0.0, 1.0], "E": [0.5, 1.5], "F": [1.0, 2.0]},
        "links": {"AB": ["A", "B"], "BC": ["B", "C"], "DE": ["D", "E"], "EF": ["E", "F"]}})
    a = analyze(m)
    assert (a.dof, a.types, a.redundant_constraints) == (2, ("IM",), 2)
    assert "flexible: 2 infinitesimal flexes" in render_text(a)


def test_a_mechanism_locked_in_every_link_is_not_lim_without_motion():
    """LIM needs F ≥ 1 and L > 0: a dyad declared with mobility 1 but locked (L = 0) is not LIM."""
    m = Mechanism.from_dict({"dim": 2, "mobility": 1, "fixed": ["A", "C"],
                             "nodes": {"A": [0, 0], "B": [1, 1], "C": [3, 0]},
                             "links": {"ab": ["A", "B"], "bc": ["B", "C"]}})
    a = analyze(m)
    assert a.dof == 0 and "LIM" not in a.types and a.locked_links == ("ab", "bc")


def test_lim_still_holds_for_a_mechanism():
    a = analyze(catalogue.get("fourbar_dead_centre"))
    assert a.types == ("DKP-output", "LIM") and a.locked_links == ("rocker",)


def test_cli_json_of_a_structure(tmp_path, capsys):
    from symkin.model.model_file import write_model

    path = tmp_path / "truss.toml"
    write_model(catalogue.get("braced_square"), path)
    assert main(["analyze", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["singular"] is False and data["types"] == [] and data["dof"] == 0
    assert data["redundant_constraints"] == 1 and data["warnings"] == []
    assert set(data["self_stresses"][0]) == {"BC", "CD", "DA", "AC", "BD"}
