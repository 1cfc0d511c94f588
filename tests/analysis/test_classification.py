"""Classification of single configurations against closed-form kinematics and elementary geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin import Mechanism, analyze, motion_space
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import parameter_rows


def rates(mech, params, column=0):
    ms = motion_space(mech)
    return [float((parameter_rows(mech, p) @ ms.V[:, column])[0]) for p in params]


def test_fourbar_velocity_ratio_matches_loop_equation(fourbar):
    """ω_rocker/ω_crank = a sin(θ1−θ2) / (c sin(θ3−θ2)) from the derivative of the loop equation."""
    x = fourbar.coordinates()
    th = {k: math.atan2(x[q][1] - x[p][1], x[q][0] - x[p][0]) for k, (p, q) in
          {"1": ("A", "B"), "2": ("B", "C"), "3": ("D", "C")}.items()}
    a, c = math.dist(x["A"], x["B"]), math.dist(x["D"], x["C"])
    w1, w3 = rates(fourbar, [fourbar.inputs[0], fourbar.outputs[0]])
    assert w3 / w1 == pytest.approx(a * math.sin(th["1"] - th["2"]) / (c * math.sin(th["3"] - th["2"])), rel=1e-12)
    result = analyze(fourbar)
    assert (result.dof, result.types, result.input_rank, result.output_rank) == (1, (), 1, 1)
    assert result.gosselin_angeles is None and result.zlatanov == ()


def test_slider_crank_piston_speed_matches_closed_form():
    m = catalogue.get("slider_crank")
    x = m.coordinates()
    a, b, e = math.dist(x["A"], x["B"]), math.dist(x["B"], x["C"]), 0.25
    th = math.atan2(x["B"][1], x["B"][0])
    # x_C = a cosθ + sqrt(b² − (a sinθ − e)²)  →  dx_C/dθ
    s = a * math.sin(th) - e
    dxc = -a * math.sin(th) - s * a * math.cos(th) / math.sqrt(b * b - s * s)
    w, v = rates(m, [m.inputs[0], m.outputs[0]])
    assert v / w == pytest.approx(dxc, rel=1e-12)


def test_dead_centre_is_dkp_output_with_locked_rocker():
    r = analyze(catalogue.get("fourbar_dead_centre"))
    assert r.dof == 1 and r.types == ("DKP-output", "LIM")
    assert (r.input_rank, r.output_rank) == (1, 0)
    assert [x.as_dict() for x in r.output_relations] == [{"rotation:rocker": 1.0}]
    assert r.output_relations[0].r == 1 and r.locked_links == ("rocker",) and r.locked_nodes == ("C",)
    assert r.gosselin_angeles == "type 1" and "IO" in r.zlatanov


def test_coupler_rocker_alignment_is_dkp_input():
    """Coupler and rocker aligned: the crank cannot be driven (ω_crank = 0), the coupler turns about C."""
    d = catalogue.data("fourbar_dead_centre")
    # coupler B→C along +x and D on the same line beyond C: rocker aligned with the coupler
    d["nodes"] = {"A": [0.0, 0.0], "B": [0.0, 3.0], "C": [4.0, 3.0], "D": [7.0, 3.0]}
    r = analyze(Mechanism.from_dict(d))
    assert r.dof == 1 and "DKP-input" in r.types
    assert [x.as_dict() for x in r.input_relations] == [{"rotation:crank": 1.0}]
    assert r.locked_links == ("crank",)
    (motion,) = r.uncontrolled_motions
    vel = dict(motion.velocities)
    np.testing.assert_allclose(vel["B"], [0.0, 0.0], atol=1e-14)
    assert abs(vel["C"][0]) < 1e-14 and abs(vel["C"][1]) == pytest.approx(1.0)
    assert motion.moves_outputs is True and r.gosselin_angeles == "type 2"


def test_flattened_fourbar_is_im_with_the_perpendicular_motion():
    r = analyze(catalogue.get("fourbar_flat"))
    assert r.dof == 2 and r.mobility == 1 and r.types == ("IM",)
    assert r.im_indicator == pytest.approx(0.0, abs=1e-28)
    (motion,) = r.uncontrolled_motions
    vel = dict(motion.velocities)
    np.testing.assert_allclose(vel["B"], [0, 0], atol=1e-15)
    np.testing.assert_allclose(np.abs(vel["C"]), [0, 1], atol=1e-15)
    assert "IIM" in r.zlatanov and r.gosselin_angeles == "type 3"


def rrr_concurrent(point, thetas, crank_angles, radius=1.0, l1=1.7):
    """3-RRR whose distal lines meet at ``point``: platform joints C_i on a circle about the
    point (distal direction = toward the point), elbows B_i at distance radius along
    the line beyond C_i, base pivots A_i at distance l1 from B_i at the given crank angles."""
    p = np.array(point, float)
    nodes, links = {}, {}
    for k, (t, ca) in enumerate(zip(thetas, crank_angles), 1):
        u = np.array([math.cos(t), math.sin(t)])
        c = p + 0.8 * u
        b = c + radius * u
        a = b - l1 * np.array([math.cos(ca), math.sin(ca)])
        nodes.update({f"A{k}": list(a), f"B{k}": list(b), f"C{k}": list(c)})
        links.update({f"crank{k}": [f"A{k}", f"B{k}"], f"distal{k}": [f"B{k}", f"C{k}"]})
    links["platform"] = ["C1", "C2", "C3"]
    return {"dim": 2, "fixed": ["A1", "A2", "A3"], "nodes": nodes, "links": links,
            "inputs": [{"rotation": f"crank{k}"} for k in (1, 2, 3)],
            "outputs": [{"twist": "platform"}], "platform": "platform", "platform_dof": 3}


def test_3rrr_concurrent_distal_lines_give_the_dkp_relation_of_eq_13():
    """γ_i = w_i (a_i × d_i) with w the equilibrium weights of the concurrent distal lines."""
    data = rrr_concurrent((0.3, -0.2), (0.1, 2.3, 4.0), (1.0, 2.9, -0.4))
    m = Mechanism.from_dict(data)
    r = analyze(m)
    assert r.dof == 3 and r.types == ("DKP-input",) and r.input_rank == 2
    x = {k: np.array(v) for k, v in m.coordinates().items()}
    d = [x[f"C{k}"] - x[f"B{k}"] for k in (1, 2, 3)]
    a = [x[f"B{k}"] - x[f"A{k}"] for k in (1, 2, 3)]
    # w: Σ w_i d_i = 0 (the moment condition holds since the lines are concurrent)
    w = np.linalg.svd(np.array(d).T)[2][-1]
    gamma = np.array([w[i] * (a[i][0] * d[i][1] - a[i][1] * d[i][0]) for i in range(3)])
    gamma /= gamma[0]
    (rel,) = r.input_relations
    got = rel.as_dict()
    assert rel.r == 3
    np.testing.assert_allclose([got["rotation:crank1"], got["rotation:crank2"], got["rotation:crank3"]],
                               gamma, rtol=1e-9)
    (motion,) = r.uncontrolled_motions
    assert motion.moves_platform is True and motion.moves_outputs is True
    # the platform's uncontrolled motion is a rotation about the concurrency point
    vel = dict(motion.velocities)
    p = np.array([0.3, -0.2])
    for k in (1, 2, 3):
        rel_pos = x[f"C{k}"] - p
        assert abs(np.dot(vel[f"C{k}"], rel_pos)) < 1e-12


def test_3rrr_generic_is_regular():
    r = analyze(catalogue.get("rrr_3"))
    assert (r.dof, r.types, r.input_rank, r.output_rank, r.platform_dof) == (3, (), 3, 3, 3)


def test_five_bar_type_1_leg_stretched():
    """Leg 1 stretched (crank and distal aligned): P cannot move along that leg (DKP-output, r = 2)."""
    d = catalogue.data("five_bar")
    u = np.array([0.6, 0.8])
    d["nodes"]["B1"] = list(np.array([-1.0, 0.0]) + 1.0 * u)
    d["nodes"]["P"] = list(np.array([-1.0, 0.0]) + 2.5 * u)
    # place B2 on the intersection of circles: |B2 - A2| = 1.3, |B2 - P| = 1.6
    a2, p = np.array([1.0, 0.0]), np.array(d["nodes"]["P"])
    dist = np.linalg.norm(p - a2)
    along = (1.3 ** 2 - 1.6 ** 2 + dist ** 2) / (2 * dist)
    h = math.sqrt(1.3 ** 2 - along ** 2)
    e = (p - a2) / dist
    d["nodes"]["B2"] = list(a2 + along * e + h * np.array([e[1], -e[0]]))
    r = analyze(Mechanism.from_dict(d))
    assert r.dof == 2 and r.types == ("DKP-output",) and r.output_rank == 1
    (rel,) = r.output_relations
    assert rel.as_dict() == pytest.approx({"velocity:P.x": 1.0, "velocity:P.y": 0.8 / 0.6}, rel=1e-12)
    assert r.gosselin_angeles == "type 1"


def test_five_bar_type_2_distal_links_aligned():
    """Both distal links on one line: P can move along the normal with the cranks locked."""
    d = catalogue.data("five_bar")
    d["nodes"].update({"B1": [-0.5, 1.5], "P": [0.0, 1.5], "B2": [0.75, 1.5]})
    r = analyze(Mechanism.from_dict(d))
    assert r.dof == 2 and r.types == ("DKP-input",) and r.input_rank == 1
    (motion,) = r.uncontrolled_motions
    vel = dict(motion.velocities)
    np.testing.assert_allclose(vel["P"], [0.0, 1.0], atol=1e-14)
    assert motion.moves_outputs is True and r.gosselin_angeles == "type 2"


def test_relations_carry_physical_units():
    """A bar A→B = (0, 2) turning about A: v_Bx = −2ω, v_By = 0.  Coefficients of a relation
    mixing velocities and ω have units of length: ×1000 from metres to millimetres."""
    data = {"dim": 2, "fixed": ["A"], "mobility": 1, "nodes": {"A": [0.0, 0.0], "B": [0.0, 2.0]},
            "links": {"bar": ["A", "B"]}, "outputs": [{"velocity": "B"}, {"rotation": "bar"}]}
    m = Mechanism.from_dict(data)
    r = analyze(m)
    assert r.types == () and r.output_rank == 1
    assert [x.as_dict() for x in r.output_relations] == [
        pytest.approx({"velocity:B.x": 1.0, "rotation:bar": 2.0}, rel=1e-12),
        pytest.approx({"velocity:B.y": 1.0})]
    mm = analyze(m.with_coordinates({"B": (0.0, 2000.0)}))
    assert mm.output_relations[0].as_dict() == pytest.approx({"velocity:B.x": 1.0, "rotation:bar": 2000.0},
                                                              rel=1e-12)


def test_a_dyad_between_two_pivots_is_a_structure_not_lim():
    """A dyad between two ground pivots is a structure (F = 0): flexible (IM) with its joints
    aligned; rigid, motionless links listed as data but NOT LIM, otherwise (issue 7 §1)."""
    m = Mechanism.from_dict({"dim": 2, "fixed": ["A", "C"], "nodes": {"A": [0, 0], "B": [1, 0], "C": [3, 0]},
                             "links": {"ab": ["A", "B"], "bc": ["B", "C"]}})
    r = analyze(m)
    # B can still move perpendicular to the line: no LIM, but IM (generic DOF 0)
    assert r.dof == 1 and r.types == ("IM",)
    m2 = m.with_coordinates({"B": (1.0, 1.0)})
    r2 = analyze(m2)
    assert r2.dof == 0 and r2.types == () and r2.locked_links == ("ab", "bc") and not r2.singular


def test_tolerance_override_changes_a_near_miss():
    """Coordinates typed to 4 digits: 1e-8 calls it regular (with a small margin), --tol 1e-3 singular."""
    d = catalogue.data("fourbar_flat")
    d["nodes"]["C"] = [3.0, 1e-5]
    m = Mechanism.from_dict(d)
    loose, strict = analyze(m, tol=1e-3), analyze(m)
    assert strict.types == () and strict.dof == 1
    assert loose.types == ("IM",) and loose.dof == 2
    assert strict.singular_values[1] < 1e-5 and strict.margin < 1e4


@pytest.mark.parametrize("name", ["fourbar_flat", "rrr_3", "bennett"])
def test_analysis_built_by_analyze_equals_the_dataclass_constructor(name):
    """``analyze`` fills the frozen dataclass without its ``__init__``: every field, the same object."""
    import dataclasses

    from symkin.analysis.classification import Analysis

    a = analyze(catalogue.get(name))
    names = {f.name for f in dataclasses.fields(Analysis)}
    assert set(a.__dict__) == names
    assert a == Analysis(**{n: getattr(a, n) for n in names})
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.dof = 7
