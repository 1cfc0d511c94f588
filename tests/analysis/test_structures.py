"""Structures (F = 0) are singular only when they flex (issue 7 §1)."""
from __future__ import annotations

import json
import math

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


def _prism(theta: float) -> Mechanism:
    """Triangular tensegrity prism as bars: bottom b0-b2 fixed, top turned by ``theta``; the
    verticals v_i join b_i-t_i, the struts s_i join b_i-t_{i+1} (they span theta + 120°)."""
    nodes, links = {}, {}
    for i in range(3):
        a = 2 * math.pi * i / 3
        nodes[f"b{i}"] = [math.cos(a), math.sin(a), 0.0]
        nodes[f"t{i}"] = [math.cos(a + theta), math.sin(a + theta), 1.0]
    for i in range(3):
        j = (i + 1) % 3
        links.update({f"b{i}b{j}": [f"b{i}", f"b{j}"], f"t{i}t{j}": [f"t{i}", f"t{j}"],
                      f"v{i}": [f"b{i}", f"t{i}"], f"s{i}": [f"b{i}", f"t{j}"]})
    return Mechanism.from_dict({"dim": 3, "mobility": 0, "fixed": ["b0", "b1", "b2"],
                                "nodes": nodes, "links": links})


def test_a_tensegrity_prism_at_a_generic_twist_is_rigid_and_not_singular():
    """9 free coordinates, 9 rows touching them: statically determinate at a generic twist."""
    a = analyze(_prism(math.pi / 4))
    assert (a.dof, a.types, a.redundant_constraints) == (0, (), 0)


def test_the_tensegrity_prism_flexes_where_its_struts_span_150_degrees():
    """The prism's known equilibrium (Kenner, Connelly): top turned so that the struts span
    150° (= 90° + 180°/3).  There it has an infinitesimal flex and a self-stress — the prestress
    with every cable (top triangle, verticals) of one sign and every strut of the other."""
    a = analyze(_prism(math.pi / 6))
    assert (a.dof, a.types, a.redundant_constraints) == (1, ("IM",), 1)
    stress = a.self_stresses[0].as_dict()
    cables = [stress[k] for k in ("t0t1", "t1t2", "t2t0", "v0", "v1", "v2")]
    struts = [stress[k] for k in ("s0", "s1", "s2")]
    sign = math.copysign(1.0, cables[0])
    assert all(sign * c > 0 for c in cables) and all(sign * s < 0 for s in struts)
    assert struts == pytest.approx([struts[0]] * 3, rel=1e-9)  # the prism's threefold symmetry
