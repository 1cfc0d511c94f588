"""``[[joints]]``: compilation to nodes, links and sliders; joint-rate labels; bad joints (issue 16)."""
from __future__ import annotations

import contextlib
import copy
import io
import json

import numpy as np
import pytest

import symkin
from symkin.cli import main
from symkin.errors import ModelError
from symkin.model import catalogue
from symkin.model.labels import parse_label
from tests.model import joint_forms as jf


def _rpr():
    return symkin.Mechanism.from_dict(jf.rpr_3(symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates()))


def _gough_nodes():
    return symkin.read_model(jf.MODELS / "gough_stewart.toml").coordinates()


def test_rpr_compiles_to_shared_nodes_and_moving_line_sliders():
    m = _rpr()
    assert dict(m.links)["cyl1"] == ("A1", "P1.line")            # the R's node and the line's point
    assert dict(m.links)["rod1"] == ("P1", "P1.end", "C1")        # two nodes on the line, the R at C1
    assert dict(m.links)["platform"] == ("O", "C1", "C2", "C3")
    assert m.fixed == ("A1", "A2", "A3")
    s = m.slider("P1")
    assert (s.node, s.line, s.link) == ("P1", ("A1", "P1.line"), "cyl1")
    assert m.slider("P1.end").line == ("A1", "P1.line")
    assert [p.labels(2) for p in m.inputs] == [("joint:P1",), ("joint:P2",), ("joint:P3",)]
    assert [p.kind for p in m.inputs] == ["slide"] * 3
    assert [j.id for j in m.joints][:3] == ["A1", "P1", "C1"]


def test_default_ids_type_and_number_and_planar_joint_rate():
    m = symkin.Mechanism.from_dict(jf.fourbar(catalogue.get("fourbar_appendix").coordinates()))
    assert [j.id for j in m.joints] == ["R1", "R2", "R3", "R4"]
    assert m.fixed == ("R1", "R4") and dict(m.links)["coupler"] == ("R2", "R3")
    assert m.inputs[0].kind == "rotation" and m.inputs[0].labels(2) == ("joint:R1",)
    rates = dict(m.joint_rates)
    assert rates["joint:R2"].kind == "joint" and rates["joint:R2"].target == ("crank", "coupler")
    c = parse_label(m, "joint:R2")                    # a joint rate that is not an input
    assert c.label == "joint:R2" and c.kind == "angle"


def test_node_only_models_are_unchanged():
    for name in catalogue.names():
        m = catalogue.get(name)
        assert m.joints == () and m.joint_rates == ()
        assert symkin.Mechanism.from_dict(m.to_dict()) == m


def test_joint_model_round_trips_through_its_node_form():
    m = _rpr()
    again = symkin.Mechanism.from_dict(m.to_dict())
    assert again == m and again.inputs[0].labels(2) == ("joint:P1",)


def test_spatial_kinds_compile_to_axes_cross_and_lines():
    m = symkin.Mechanism.from_dict(jf.rssr(catalogue.get("rssr").coordinates()))
    assert dict(m.links)["crank"] == ("R1", "R1.axis", "S1")
    assert set(m.fixed) == {"R1", "R1.axis", "R2", "R2.axis"}
    assert m.inputs[0].kind == "rotation" and m.inputs[0].axis == (0.0, 0.0, 1.0)
    g = symkin.Mechanism.from_dict(jf.ups_6(_gough_nodes()))
    links = dict(g.links)
    assert links["U1.cross"] == ("U1", "U1.axis", "U1.axis2")
    assert links["cyl1"] == ("U1", "U1.axis2", "P1.line") and links["rod1"] == ("P1", "P1.end", "S1")
    assert {"U1", "U1.axis"} <= set(g.fixed) and "U1.axis2" not in g.fixed
    assert not any(s.id.endswith(".keyed") for s in g.sliders)   # a rod on the line: no key
    rates = dict(g.joint_rates)
    assert set(rates) >= {"joint:P1", "joint:U1.1", "joint:U1.2"}   # U1.2: the cylinder on the cross
    assert rates["joint:U1.2"].kind == "joint" and rates["joint:U1.2"].axis == ("U1", "U1.axis2")


def _two_blocks(jtype: str, **extra) -> dict:
    """Two spatial bodies (not rods) joined by a P or C along x; the first pivoted to ground by an S."""
    return {"name": f"two blocks, {jtype}", "dim": 3, "mobility": 4 if jtype == "P" else 5,
            "links": {"a": ["A1", "A2", "A3"], "b": ["B1", "B2", "B3"]},
            "nodes": {"A1": [0, 0, 0], "A2": [1, 0, 0], "A3": [0, 1, 0],
                      "B1": [2, 0, 0], "B2": [3, 0, 0], "B3": [2, 0, 1]},
            "joints": [{"type": "S", "links": ["ground", "a"], "at": [0, 0, 0]},
                       {"id": "J", "type": jtype, "links": ["a", "b"], "at": [2, 0, 0], "axis": [1, 0, 0], **extra}]}


def test_spatial_p_between_bodies_is_keyed_and_c_is_not():
    p = symkin.Mechanism.from_dict(_two_blocks("P"))
    c = symkin.Mechanism.from_dict(_two_blocks("C"))
    assert "J.keyed" in {s.id for s in p.sliders} and "J.keyed" not in {s.id for s in c.sliders}
    ap, ac = symkin.analyze(p), symkin.analyze(c)
    assert ap.dof == 3 + 1 and ac.dof == 3 + 2          # S: 3, then P: 1 (slide) or C: 2
    assert ap.redundant_constraints == 1 and ac.redundant_constraints == 0


def test_c_and_u_rates_need_their_motion_and_axis():
    data = _two_blocks("C")
    data["joints"][1]["links"] = ["ground", "b"]
    data["joints"][1].pop("at")
    data["joints"][1]["at"] = [2, 0, 0]
    data["inputs"] = [{"joint": "J", "motion": "slide"}, {"joint": "J", "motion": "rotation"}]
    m = symkin.Mechanism.from_dict(data)
    assert [p.labels(3)[0] for p in m.inputs] == ["joint:J.slide", "joint:J.rotation"]
    assert m.inputs[1].kind == "rotation" and m.inputs[1].axis == (1.0, 0.0, 0.0)
    data["inputs"] = [{"joint": "J"}]
    with pytest.raises(ModelError, match=r"joint J is a C: give motion"):
        symkin.Mechanism.from_dict(data)


def _bad(mutate, data=None) -> str:
    data = copy.deepcopy(data or jf.rpr_3(symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates()))
    mutate(data)
    with pytest.raises(ModelError) as info:
        symkin.Mechanism.from_dict(data)
    return str(info.value)


def _set(k, **kv):
    def mutate(data):
        data["joints"][k].update(kv)
    return mutate


@pytest.mark.parametrize("mutate, expected", [
    (_set(1, links=["cyl1", "rod9"]), r"joints\[1\] \(P1\): unknown link 'rod9'"),
    (_set(1, axis=[0.0, 0.0]), r"joints\[1\] \(P1\): zero axis"),
    (_set(1, axis=None), r"joints\[1\] \(P1\): a P joint needs 'axis'"),
    (_set(0, type="C"), r"joints\[0\] \(A1\): type 'C' is not allowed in a planar model"),
    (_set(0, type="S"), r"joints\[0\] \(A1\): type 'S' is not allowed in a planar model"),
    (_set(0, type="Q"), r"joints\[0\] \(A1\): type must be one of R, P"),
    (_set(0, type="H"), r"joints\[0\] \(A1\): type 'H' is not allowed in a planar model"),
    (_set(0, links=["cyl1", "cyl1"]), r"joints\[0\] \(A1\): joins link 'cyl1' to itself"),
    (_set(0, at=[0.0, "x"]), r"joints\[0\] \(A1\): at must be 2 finite numbers"),
    (_set(0, axis=[1.0, 0.0]), r"joints\[0\] \(A1\): 'axis' does not go with a planar R joint"),
    (_set(0, spin=1), r"joints\[0\] \(A1\): unknown key\(s\) 'spin'"),
    (_set(2, id="A1"), r"joints\[2\] \(A1\): duplicate joint id 'A1'"),
    (lambda d: d["inputs"].__setitem__(0, {"joint": "P9"}), r"inputs\[0\]: unknown joint 'P9'"),
    (lambda d: d["links"].__setitem__("platform", ["O", "X"]) or d["nodes"].__setitem__("X", [9.0, 9.0]),
     r"joints \(C1\): the point \[1.5, 1.5\] is not on link platform, the bar O-X"),
])
def test_bad_joints_are_model_errors_naming_the_joint(mutate, expected):
    assert __import__("re").search(expected, _bad(mutate))


def test_u_axes_not_perpendicular_and_every_problem_at_once():
    data = jf.ups_6(_gough_nodes())
    data["joints"][0]["axis2"] = [1.0, 1.0, 0.3]
    data["joints"][3]["links"] = ["ground", "nowhere"]
    text = _bad(lambda d: None, data)
    assert "joints (U1): the axes of U joint U1 are not perpendicular" in text
    assert "joints[3] (U2): unknown link 'nowhere'" in text


def test_spatial_relative_rotation_of_a_rod_on_the_axis_is_a_named_error():
    data = jf.ups_6(_gough_nodes())
    data["joints"][1] = {"id": "P1", "type": "C", "links": ["cyl1", "rod1"], "at": data["joints"][1]["at"],
                         "axis": data["joints"][1]["axis"]}
    data["inputs"][0] = {"joint": "P1", "motion": "rotation"}
    assert "the rotation rate of joint P1 is not defined: link rod1 is a rod along" in _bad(lambda d: None, data)


def test_bad_joint_exits_2_from_the_cli(tmp_path):
    data = jf.rpr_3(symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates())
    data["joints"][1]["axis"] = [0.0, 0.0]
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["analyze", str(path)])
    assert code == 2 and "joints[1] (P1): zero axis" in err.getvalue() and "Traceback" not in err.getvalue()


def test_joint_form_is_scale_invariant():
    m = _rpr()
    data = jf.rpr_3({n: [1000.0 * c for c in xyz] for n, xyz in
                     symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates().items()})
    mm = symkin.Mechanism.from_dict(data)
    a, b = symkin.analyze(m), symkin.analyze(mm)
    assert (a.dof, a.types, a.input_rank, a.output_rank, a.platform_dof) == \
        (b.dof, b.types, b.input_rank, b.output_rank, b.platform_dof)
    assert mm.node_names == m.node_names
    for (n, x), (_, y) in zip(m.nodes, mm.nodes):
        assert [1000.0 * c for c in x] == pytest.approx(y, rel=1e-12, abs=1e-9), n


def test_moved_moves_the_joints_and_their_rate_axes():
    m = symkin.Mechanism.from_dict(jf.rssr(catalogue.get("rssr").coordinates()))
    turn = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    moved = m.moved(rotation=turn, translation=[1.0, 2.0, 3.0], scale=10.0)
    r2 = next(j for j in moved.joints if j.id == "R2")
    assert r2.at == pytest.approx((1.0, 32.0, 13.0)) and r2.axis == pytest.approx((0.0, 1.0, 0.0))
    assert dict(moved.joint_rates)["joint:R2"].axis == pytest.approx((0.0, 1.0, 0.0))


def test_cli_path_accepts_a_joint_label():
    out, err = io.StringIO(), io.StringIO()
    example = jf.ROOT / "papers_examples" / "fourbar_appendix_joints.toml"
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["path", str(example), "--input", "joint:A", "--to", "360", "--no-progress", "--json"])
    assert code == 0, err.getvalue()
    data = json.loads(out.getvalue())
    assert data["input"] == "joint:A" and data["stop_reason"] == "reached" and data["events"]


def test_ground_as_the_second_link_of_a_p_turns_the_slide_around():
    sc = catalogue.get("slider_crank")
    data = jf.slider_crank(sc.coordinates(), (0.0, 0.25), (1.0, 0.0))
    data["joints"][3].update(links=["block", "ground"], axis=[-1.0, 0.0])   # ground slides on the block along -x
    a = symkin.analyze(symkin.Mechanism.from_dict(data))
    b = symkin.analyze(symkin.Mechanism.from_dict(jf.slider_crank(sc.coordinates(), (0.0, 0.25), (1.0, 0.0))))
    va, vb = a.motion.V[:, 0], b.motion.V[:, 0]
    ra = symkin.Mechanism.from_dict(data)
    assert ra.slider("P1").direction == (1.0, 0.0)           # the block's rate along +x, as ground first
    assert (a.dof, a.types, a.input_rank, a.output_rank) == (b.dof, b.types, b.input_rank, b.output_rank)
    assert np.allclose(np.abs(va), np.abs(vb))
