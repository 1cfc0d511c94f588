"""A mechanism written by its joints analyses as its node form (issue 16, "checks that assert").

Same DOF, types, ranks, platform DOF and relations (the coefficients, up to the joint-rate
labels) at the model configuration and at a singular one; the same path events over a
segment; the 6-UPS Gough–Stewart by U, P and S joints as the SPS node form; the 3-PRR at a
regular pose and at its type-2 and type-1 configurations (built by elementary geometry) and
along a path.  Spatial: test_joint_forms_spatial.py; spatial path events:
tests/paths/test_joint_form_paths.py; maps: tests/workspace/test_map_joint_forms.py.
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from tests.model import joint_forms as jf
from tests.paths.conftest import in_process_corrector  # noqa: F401  (a fixture: paths without compiling)

#: the path tests: the generated corrector in-process, as in tests/paths (compiling it for each joint
#: form would cost minutes on a busy machine; the numbers are the compiled ones)
paths = pytest.mark.usefixtures("in_process_corrector")


def _summary(a):
    rel = [tuple(c for _, c in r.coefficients) for r in a.input_relations + a.output_relations + a.platform_relations]
    return (a.dof, a.mobility, a.types, a.input_rank, a.output_rank, a.platform_dof, a.gosselin_angeles,
            a.zlatanov), rel


def _same(node: symkin.Mechanism, joint: symkin.Mechanism, extra_lim: str | None = None):
    """Equal summaries; ``extra_lim``: a link of the joint form that the node form has not (LIM)."""
    an, aj = symkin.analyze(node), symkin.analyze(joint)
    if extra_lim is None:
        assert aj.redundant_constraints == an.redundant_constraints
    (a, ra), (b, rb) = _summary(an), _summary(aj)
    if extra_lim is not None:
        assert aj.locked_links == (extra_lim,) and "LIM" in b[2] and "LIM" not in a[2]
        b = b[:2] + (tuple(t for t in b[2] if t != "LIM"),) + b[3:]
        a, b = a[:6], b[:6]
    assert a == b
    assert len(ra) == len(rb)
    for x, y in zip(ra, rb):
        assert np.allclose(x, y, rtol=1e-7, atol=1e-9)


def _rpr_node():
    return symkin.read_model(jf.MODELS / "rpr_3.toml")


def _pairs():
    fb = [catalogue.get(n) for n in ("fourbar_appendix", "fourbar_dead_centre", "fourbar_flat")]
    sc = catalogue.get("slider_crank")
    gough = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    return [(m.name, m, jf.fourbar(m.coordinates())) for m in fb] + [
        (sc.name, sc, jf.slider_crank(sc.coordinates(), (0.0, 0.25), (1.0, 0.0))),
        ("rssr", catalogue.get("rssr"), jf.rssr(catalogue.get("rssr").coordinates())),
        ("five-bar", catalogue.get("five_bar"), jf.five_bar(catalogue.get("five_bar").coordinates())),
        ("3-RRR", catalogue.get("rrr_3"), jf.rrr_3(catalogue.get("rrr_3").coordinates())),
        ("Bennett", catalogue.get("bennett"), jf.bennett(catalogue.get("bennett").coordinates())),
        ("3-RPR", _rpr_node(), jf.rpr_3(_rpr_node().coordinates())),
        ("6-UPS", gough, jf.ups_6(gough.coordinates())),
    ]


@pytest.mark.parametrize("name, node, joint", _pairs(), ids=[p[0] for p in _pairs()])
def test_joint_form_analyses_as_node_form(name, node, joint):
    _same(node, symkin.Mechanism.from_dict(joint))


def test_slider_crank_at_its_dead_centre():
    # crank A-B along A->C: the slider stops (DKP-output), in both forms; the joint form has the
    # block as a link, and a link that cannot move is LIM (as the four-bar's rocker at its dead centre)
    c = np.array([3.5, 0.25])
    b = 0.8 * c / np.linalg.norm(c)
    node = catalogue.get("slider_crank").with_coordinates({"B": tuple(b), "C": tuple(c)})
    assert "DKP-output" in symkin.analyze(node).types
    _same(node, symkin.Mechanism.from_dict(jf.slider_crank(node.coordinates(), (0.0, 0.25), (1.0, 0.0))),
          extra_lim="block")


@paths
def test_rssr_path_events_and_a_singular_configuration():
    node = catalogue.get("rssr")
    joint = symkin.Mechanism.from_dict(jf.rssr(node.coordinates()))
    pn = symkin.trace(node, None, 0.0, 360.0, unit="deg")
    pj = symkin.trace(joint, "joint:R1", 0.0, 360.0, unit="deg")
    en, ej = pn.singular_events(), pj.singular_events()
    assert [e.kind for e in en] == [e.kind for e in ej] and en
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)
    at = node.with_coordinates(en[0].coordinates.reshape(-1, 3))
    assert symkin.analyze(at).types
    _same(at, symkin.Mechanism.from_dict(jf.rssr(at.coordinates())))


@paths
def test_rpr_at_a_singular_configuration_and_along_a_path():
    node = _rpr_node()
    joint = symkin.Mechanism.from_dict(jf.rpr_3(node.coordinates()))
    pn = symkin.trace(node, "slide:s1", 0.0, 3.0)
    pj = symkin.trace(joint, "joint:P1", 0.0, 3.0)
    en, ej = pn.singular_events(), pj.singular_events()
    assert [e.kind for e in en] == [e.kind for e in ej] and len(en) == 2
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)
    assert pn.stop_reason == pj.stop_reason
    # the node form's configuration at its first event, written by its joints
    e = en[0]
    at = node.with_coordinates(e.coordinates.reshape(-1, 2))
    assert "DKP-input" in symkin.analyze(at).types
    _same(at, symkin.Mechanism.from_dict(jf.rpr_3(at.coordinates())))


@paths
def test_fourbar_path_events():
    node = catalogue.get("fourbar_appendix")
    joint = symkin.Mechanism.from_dict(jf.fourbar(node.coordinates()))
    pn = symkin.trace(node, "rotation:crank", 0.0, 360.0, unit="deg")
    pj = symkin.trace(joint, "joint:R1", 0.0, 360.0, unit="deg")
    en, ej = pn.singular_events(), pj.singular_events()
    assert [e.kind for e in en] == [e.kind for e in ej] and en
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)


def test_gough_joint_form_mm_and_m():
    gough = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    mm = {n: [1000.0 * c for c in x] for n, x in gough.coordinates().items()}
    _same(gough.moved(scale=1000.0), symkin.Mechanism.from_dict(jf.ups_6(mm)))


@pytest.mark.parametrize("name", ["fig11_3rsr_a", "fig12_3rsr_b", "fig13_3rsr_c"])
def test_paper_3rsr_positions_by_their_joints(name):
    node = symkin.read_model(jf.ROOT / "papers_examples" / f"{name}.toml")
    joint = symkin.Mechanism.from_dict(jf.rsr_3(node.coordinates()))
    an, aj = symkin.analyze(node), symkin.analyze(joint)
    assert (an.dof, an.types, an.input_rank, an.output_rank, an.platform_dof, an.locked_links) == \
        (aj.dof, aj.types, aj.input_rank, aj.output_rank, aj.platform_dof, aj.locked_links)
    assert an.types                                   # each position is singular (the paper's point)
    for x, y in zip(an.input_relations + an.output_relations, aj.input_relations + aj.output_relations):
        assert np.allclose([c for _, c in x.coefficients], [c for _, c in y.coefficients], rtol=1e-7, atol=1e-9)


def test_gough_joint_form_turned_and_moved():
    gough = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    data = jf.ups_6(gough.coordinates())
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    shift = np.array([0.3, -1.2, 4.0])
    place = lambda p: list(rot @ np.asarray(p, float) + shift)
    turn = lambda v: list(rot @ np.asarray(v, float))
    for j in data["joints"]:
        j["at"] = place(j["at"])
        for key in ("axis", "axis2"):
            if key in j:
                j[key] = turn(j[key])
    data["nodes"] = {n: place(p) for n, p in data["nodes"].items()}
    _same(gough.moved(rotation=rot, translation=shift), symkin.Mechanism.from_dict(data))


# ----------------------------------------------------------------------------------- 3-PRR
#: a regular pose of the 3-PRR (platform reference point O, turn φ) and its working mode
PRR_POSE = ((0.3, -0.2), 0.2)


def _prr(nodes: dict) -> tuple[symkin.Mechanism, symkin.Mechanism]:
    return symkin.Mechanism.from_dict(jf.prr_3_node(nodes)), symkin.Mechanism.from_dict(jf.prr_3(nodes))


def _line(p, q) -> np.ndarray:
    """Homogeneous coefficients of the planar line through ``p`` and ``q``."""
    return np.cross(np.r_[p, 1.0], np.r_[q, 1.0])


def _concurrency(nodes: dict) -> float:
    """det of the three distal lines B_k C_k (homogeneous, each normalised): 0 where they meet in a point."""
    rows = [_line(nodes[f"B{k}"], nodes[f"C{k}"]) for k in (1, 2, 3)]
    return float(np.linalg.det([r / np.linalg.norm(r[:2]) for r in rows]))


def _perpendicularity(nodes: dict) -> float:
    """min over the legs of |cos| between distal link and guide: 0 where a distal link is normal to its guide."""
    out = []
    for k, (_, d) in enumerate(jf.prr_guides(), 1):
        bar = np.subtract(nodes[f"C{k}"], nodes[f"B{k}"])
        out.append(abs(bar @ d) / np.linalg.norm(bar))
    return min(out)


def _on_guide(k: int, p, q) -> list[float]:
    """The point where the line through ``p`` and ``q`` meets guide ``k``."""
    v, d = (np.asarray(x, float) for x in jf.prr_guides()[k - 1])
    x = np.cross(_line(p, q), np.cross(np.r_[v, 1.0], np.r_[v + d, 1.0]))
    return list(x[:2] / x[2])


def test_prr_regular_pose_dof_by_grubler_and_joint_form():
    """8 links (ground, 3 blocks, 3 distal links, platform), 9 one-DOF pairs: 3 (8 − 1 − 9) + 9 = 3."""
    nodes = jf.prr_3_nodes(*PRR_POSE)
    node, joint = _prr(nodes)
    a = symkin.analyze(node)
    assert (a.dof, a.types, a.input_rank, a.output_rank, a.platform_dof) == (3, (), 3, 3, 3)
    assert abs(_concurrency(nodes)) > 1e-2 and _perpendicularity(nodes) > 1e-2
    _same(node, joint)


def test_prr_concurrent_distal_lines_are_type_2_in_both_forms():
    """The platform of the model's pose; each slider moved to where the line C_k Q meets its guide, Q a
    point inside: the three distal lines meet at Q (elementary geometry), a DKP-input configuration."""
    nodes = jf.prr_3_nodes(*PRR_POSE)
    q = np.array([0.2, 0.1])
    for k in (1, 2, 3):
        nodes[f"B{k}"] = _on_guide(k, q, nodes[f"C{k}"])
    assert abs(_concurrency(nodes)) < 1e-12 and _perpendicularity(nodes) > 1e-2
    node, joint = _prr(nodes)
    a = symkin.analyze(node)
    assert a.types == ("DKP-input",) and (a.dof, a.input_rank, a.output_rank) == (3, 2, 3)
    _same(node, joint)


def test_prr_distal_link_normal_to_its_guide_is_type_1_in_both_forms():
    """Slider 1 moved to the foot of C_1 on its guide: distal link 1 normal to guide 1, a DKP-output
    configuration (the slide moves with the platform held)."""
    nodes = jf.prr_3_nodes(*PRR_POSE)
    v, d = (np.asarray(x, float) for x in jf.prr_guides()[0])
    nodes["B1"] = list(v + ((np.asarray(nodes["C1"]) - v) @ d) * d)
    assert _perpendicularity(nodes) < 1e-12 and abs(_concurrency(nodes)) > 1e-2
    node, joint = _prr(nodes)
    a = symkin.analyze(node)
    assert a.types == ("DKP-output",) and (a.dof, a.input_rank, a.output_rank) == (3, 3, 2)
    _same(node, joint, extra_lim=None)


@paths
def test_prr_path_events_in_both_forms():
    """Slide 1 driven, slides 2 and 3 held: the loop closes with the same events; each DKP-input event
    has concurrent distal lines, each DKP-output event a distal link normal to its guide."""
    node, joint = _prr(jf.prr_3_nodes(*PRR_POSE))
    pn, pj = symkin.trace(node, "slide:s1", -3.0, 3.0), symkin.trace(joint, "joint:P1", -3.0, 3.0)
    en, ej = pn.singular_events(), pj.singular_events()
    assert [e.kind for e in en] == [e.kind for e in ej]
    assert {"DKP-input", "DKP-output"} <= {str(e.kind) for e in en}
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)
    assert pn.stop_reason == pj.stop_reason == "unreachable"   # a closed loop: slide 1 turns back
    for path in (pn, pj):   # no event twice: the loop's end does not meet its first events again
        ys = [e.coordinates for e in path.singular_events()]
        assert all(np.linalg.norm(a - b) > 1e-3 for i, a in enumerate(ys) for b in ys[:i])
    names = pn.node_names
    for e in en:
        nodes = dict(zip(names, e.coordinates.reshape(-1, 2)))
        if e.kind == "DKP-input":
            assert abs(_concurrency(nodes)) < 1e-7
        else:
            assert _perpendicularity(nodes) < 1e-7


@paths
@pytest.mark.parametrize("name, drive", [("slider_crank", "joint:R1"), ("five_bar", "joint:A1"),
                                         ("rrr_3", "joint:A1")])
def test_path_events_of_planar_joint_forms(name, drive):
    node = catalogue.get(name)
    nodes = node.coordinates()
    build = {"slider_crank": lambda: jf.slider_crank(nodes, (0.0, 0.25), (1.0, 0.0)),
             "five_bar": lambda: jf.five_bar(nodes), "rrr_3": lambda: jf.rrr_3(nodes)}[name]
    joint = symkin.Mechanism.from_dict(build())
    pn = symkin.trace(node, None, 0.0, 360.0, unit="deg")
    pj = symkin.trace(joint, drive, 0.0, 360.0, unit="deg")
    en, ej = pn.singular_events(), pj.singular_events()
    assert en and [e.kind for e in en] == [e.kind for e in ej]
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)
    assert pn.stop_reason == pj.stop_reason


def test_readme_spatial_joint_example_is_the_screw_jack():
    """The README's spatial ``[[joints]]`` example is the screw jack file (less its description) and
    analyses as it says: L = 1, the nut's slide 0.004 × the screw's rotation (v = p·ω)."""
    import re
    import tomllib

    blocks = [b for b in re.findall(r"```toml\n(.*?)```", (jf.ROOT / "README.md").read_text(), re.S)
              if 'name = "screw jack"' in b]
    assert len(blocks) == 1
    data = tomllib.loads(blocks[0])
    jack = tomllib.loads((jf.ROOT / "tests" / "constraints" / "models" / "screw_jack.toml").read_text())
    jack.pop("description")
    assert data == jack
    a = symkin.analyze(symkin.Mechanism.from_dict(data))
    assert a.dof == 1
    from symkin.numeric.geometric_matrix import parameters_matrix
    m = symkin.Mechanism.from_dict(data)
    rin, _ = parameters_matrix(m, m.inputs)
    rout, _ = parameters_matrix(m, m.outputs)
    v = symkin.motion_space(m).V
    assert float((rout @ v).ravel()[0] / (rin @ v).ravel()[0]) == pytest.approx(0.004, rel=1e-12)
