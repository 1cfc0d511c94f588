"""Self-stresses and redundant constraints (issue 7 §2), against statics worked by hand,
Grübler–Kutzbach counts, PyRigi's stress count, and similarity invariance."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symkin import Mechanism, analyze, read_model
from symkin.analysis.statics import constraint_labels, frame_dependent, self_stresses
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import constraint_rows
from tests.conftest import EXAMPLES
from tests.analysis.test_invariance import MODELS, load, rotation_matrix


def _stress(mech) -> dict:
    (rel,) = analyze(mech).self_stresses
    return rel.as_dict()


def test_braced_square_has_one_self_stress_sides_in_tension_diagonals_in_compression():
    """Unit square, both diagonals, A and B pinned.  Equilibrium at corner C (bars CB along
    −y, CD along −x, CA along −(1, 1)/√2): t_BC (0, −1) + t_CD (−1, 0) − t_AC (1, 1)/√2 = 0, so
    t_BC = t_CD = −t_AC/√2; the same at D: the sides carry s, the diagonals −√2 s.  Bar A-B
    joins two fixed nodes (its force goes to the ground): it is not in the stress."""
    a = analyze(catalogue.get("braced_square"))
    assert a.redundant_constraints == 1 and a.dof == 0 and a.types == ()
    stress = a.self_stresses[0].as_dict()
    assert set(stress) == {"BC", "CD", "DA", "AC", "BD"}
    assert stress == pytest.approx({"BC": 1.0, "CD": 1.0, "DA": 1.0, "AC": -math.sqrt(2), "BD": -math.sqrt(2)},
                                   rel=1e-12)
    assert a.to_dict()["self_stresses"] == [stress] and a.to_dict()["redundant_constraints"] == 1


def test_statically_determinate_truss_has_no_self_stress():
    """Pratt truss: 13 bars + 3 reactions = 2 × 8 joints, and rigid: no stress."""
    a = analyze(catalogue.get("pratt_truss"))
    assert (a.redundant_constraints, a.self_stresses, a.dof) == (0, (), 0)


def test_bennett_linkage_has_three_redundant_constraints():
    """Our model: bodies link1 (A, A2, B, B2), link2 (B, B2, C, C2), link3 (C, C2, D, D2), with A, A2,
    D, D2 fixed.  Rows touching a free coordinate: link1 5 (A-A2 joins fixed nodes), link2 6,
    link3 5 = 16; free coordinates 12 (B, B2, C, C2); L = 1, so rank 11 and 16 − 11 = 5
    stresses.  Two of them are the axis distances B-B2 and C-C2, kept by both bodies sharing
    the axis (the node model of a revolute pair), and are excluded: 3 remain.  Independently:
    Grübler–Kutzbach 6·(4 − 1) − 5·4 = −2, the Bennett linkage moves with F = 1: 1 − (−2) = 3."""
    mech = catalogue.get("bennett")
    a = analyze(mech)
    assert a.dof == 1 and a.types == () and a.redundant_constraints == 3
    st_ = self_stresses(mech)
    assert st_.artefacts == 2 and len(st_.self_stresses) == 3
    # each stress is orthogonal to the artefacts: both copies of a shared axis pair carry the same force
    for rel in st_.self_stresses:
        c = rel.as_dict()
        for pair in ("B-B2", "C-C2"):
            first, second = [c.get(f"{link}[{pair}]", 0.0) for link in
                             (("link1", "link2") if pair == "B-B2" else ("link2", "link3"))]
            assert first == pytest.approx(second, rel=1e-9, abs=1e-12)


def test_a_generic_4r_loop_is_a_structure_with_two_redundant_constraints():
    """Turn the axis at C off the Bennett condition: the loop locks (L = 0), and with F = 0
    Grübler's −2 means 2 redundant constraints (16 rows − rank 12 − 2 axis copies = 2)."""
    d = catalogue.data("bennett")
    d["nodes"]["C2"][1] += 0.125
    d["mobility"] = 0
    a = analyze(Mechanism.from_dict(d))
    assert (a.dof, a.types, a.redundant_constraints) == (0, (), 2)


def test_double_parallelogram_crank_forces_balance_the_coupler():
    """Three parallel cranks (direction c) at B, C, F of the coupler; with n ⟂ c the moment
    arms are n·B = 0, n·C = −2, n·F = −1.5 (n = (−1, 0.5)), so t1 + t2 + t3 = 0 and
    −2 t2 − 1.5 t3 = 0: t = (1, 3, −4).  Grübler 3·4 − 2·6 = 0 < F = 1: one redundancy."""
    a = analyze(catalogue.get("double_parallelogram"))
    assert (a.dof, a.types, a.redundant_constraints) == (1, (), 1)
    s = a.self_stresses[0].as_dict()
    assert [s["crank"], s["middle"], s["rocker"]] == pytest.approx([1.0, 3.0, -4.0], rel=1e-12)


def test_the_stresses_inside_a_rigid_body_are_not_redundant_constraints():
    """A collinear coupler B-C-F (pair rows + one rigidity row: 4 rows of rank 3) carries one
    stress of its own; it is excluded, the redundant third crank stays (forces 1, −2, 1: arms 0, 2, 4)."""
    d = catalogue.data("double_parallelogram")
    d["nodes"].update({"E": [4.0, 0.0], "F": [4.5, 1.0]})
    mech = Mechanism.from_dict(d)
    st_ = self_stresses(mech)
    assert (st_.redundant_constraints, st_.artefacts) == (1, 1)
    s = st_.self_stresses[0].as_dict()
    assert [s["crank"], s["middle"], s["rocker"]] == pytest.approx([1.0, -2.0, 1.0], rel=1e-12)
    # a planar body of 4 nodes: 6 pair rows of rank 5, no redundancy of the four-bar
    d = catalogue.data("fourbar_appendix")
    d["nodes"].update({"E": [1.0, 1.5], "G": [1.5, 0.5]})
    d["links"]["coupler"] = ["B", "C", "E", "G"]
    st_ = self_stresses(Mechanism.from_dict(d))
    assert (st_.redundant_constraints, st_.artefacts) == (0, 1)


def test_a_four_bar_with_a_redundant_parallel_bar():
    """A second bar on C-B (a parallel bar): a bar's row does not depend on the order of its
    nodes, so the stress is one bar in tension and the other in equal compression."""
    d = catalogue.data("fourbar_appendix")
    d["links"]["tie"] = ["C", "B"]
    a = analyze(Mechanism.from_dict(d))
    assert (a.dof, a.types, a.redundant_constraints) == (1, (), 1)
    assert a.self_stresses[0].as_dict() == pytest.approx({"coupler": 1.0, "tie": -1.0}, rel=1e-12)


def test_two_sliders_on_one_guide_are_redundant():
    """Slider C on the line y = 0.25 twice: the two guides share one reaction."""
    d = catalogue.data("slider_crank")
    d["sliders"].append({"id": "guide2", "node": "C", "point": [1.0, 0.25], "direction": [-2.0, 0.0]})
    a = analyze(Mechanism.from_dict(d))
    assert (a.dof, a.redundant_constraints) == (1, 1)
    (rel,) = a.self_stresses
    assert set(rel.as_dict()) == {"slider:piston", "slider:guide2"}
    assert abs(rel.as_dict()["slider:guide2"]) == pytest.approx(1.0, rel=1e-12)


def test_rows_between_fixed_nodes_are_not_redundant():
    """A ground bar A-D and a ground body do not touch a free coordinate."""
    d = catalogue.data("fourbar_appendix")
    d["links"]["ground"] = ["A", "D"]
    a = analyze(Mechanism.from_dict(d))
    assert a.redundant_constraints == 0 and a.self_stresses == ()


def test_constraint_labels_name_bars_body_pairs_rigidity_rows_and_sliders():
    d = catalogue.data("double_parallelogram")
    d["nodes"].update({"E": [4.0, 0.0], "F": [4.5, 1.0]})
    mech = Mechanism.from_dict(d)
    labels = constraint_labels(mech, constraint_rows(mech).owners)
    assert labels == ("crank", "middle", "rocker", "coupler[B-C]", "coupler[B-F]", "coupler[C-F]",
                      "coupler:rigidity[1]")
    spatial = Mechanism.from_dict({
        "dim": 3, "fixed": ["A"], "nodes": {"A": [0.0, 0.0, 0.0], "B": [1.0, 0.0, 0.0]},
        "links": {"ab": ["A", "B"]},
        "sliders": [{"id": "s", "node": "B", "point": [1.0, 0.0, 0.0], "direction": [0.0, 1.0, 0.0]}]})
    assert constraint_labels(spatial, constraint_rows(spatial).owners) == ("ab", "slider:s[1]", "slider:s[2]")


FRAMEWORKS = {
    "braced square": ({"A": (0, 0), "B": (1, 0), "C": (1, 1), "D": (0, 1)},
                      ["AB", "BC", "CD", "DA", "AC", "BD"]),
    "square with one diagonal": ({"A": (0, 0), "B": (1, 0), "C": (1, 1), "D": (0, 1)},
                                 ["AB", "BC", "CD", "DA", "AC"]),
    "K4 in a triangle": ({"A": (0, 0), "B": (4, 0), "C": (0, 4), "D": (1, 1)},
                         ["AB", "BC", "CA", "AD", "BD", "CD"]),
    "two triangles on a collinear hinge": ({"A": (0, 0), "B": (2, 0), "C": (4, 0), "D": (1, 1), "E": (3, -1)},
                                           ["AB", "BC", "AD", "BD", "BE", "CE", "AC"]),
    "K5": ({"A": (0, 0), "B": (3, 0), "C": (4, 2), "D": (1, 3), "E": (-1, 2)},
           ["AB", "AC", "AD", "AE", "BC", "BD", "BE", "CD", "CE", "DE"]),
}


@pytest.mark.parametrize("name", FRAMEWORKS)
def test_stress_count_agrees_with_pyrigi(name):
    """PyRigi counts the stresses of a free framework; symkin the same framework with no fixed node."""
    pyrigi = pytest.importorskip("pyrigi")
    nodes, bars = FRAMEWORKS[name]
    framework = pyrigi.Framework(pyrigi.Graph([(b[0], b[1]) for b in bars]),
                                 {n: list(x) for n, x in nodes.items()})
    expected = len(framework.stresses(numerical=True))
    mech = Mechanism.from_dict({"dim": 2, "mobility": 0, "nodes": {n: list(map(float, x)) for n, x in nodes.items()},
                                "links": {b: [b[0], b[1]] for b in bars}})
    assert self_stresses(mech).redundant_constraints == expected


def _same(a, b):
    """Same count; same coefficients on the rows whose weight does not depend on the frame."""
    assert a.redundant_constraints == b.redundant_constraints == len(a.self_stresses)
    for ra, rb in zip(a.self_stresses, b.self_stresses):
        fa = {k: v for k, v in ra.as_dict().items() if not frame_dependent(k)}
        fb = {k: v for k, v in rb.as_dict().items() if not frame_dependent(k)}
        assert set(fa) == set(fb)
        assert fa == pytest.approx(fb, rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("source, name", MODELS)
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(angles=st.tuples(*[st.floats(-math.pi, math.pi)] * 3),
       shift=st.tuples(*[st.floats(-100, 100)] * 3),
       log_scale=st.floats(-3, 3))
def test_self_stresses_are_similarity_invariant(source, name, angles, shift, log_scale):
    """Rows are unit vectors: a similarity leaves the count and the (dimensionless) forces unchanged."""
    mech = load(source, name)
    moved = mech.moved(rotation_matrix(mech.dim, angles), shift[: mech.dim], 10.0 ** log_scale)
    _same(analyze(mech), analyze(moved))


def test_stresses_are_in_the_left_null_space():
    """ωᵀ J_free = 0 for every reported stress (rows looked up by label)."""
    for name in ("braced_square", "bennett", "double_parallelogram", "collinear_truss"):
        mech = catalogue.get(name)
        rows = constraint_rows(mech)
        labels = constraint_labels(mech, rows.owners)
        from symkin.numeric.geometric_matrix import free_mask
        jf = rows.matrix[:, free_mask(mech)]
        for rel in analyze(mech).self_stresses:
            w = np.array([rel.as_dict().get(x, 0.0) for x in labels])
            assert np.max(np.abs(w @ jf)) <= 1e-12 * np.max(np.abs(w))


def test_paper_examples_have_the_stresses_their_geometry_gives():
    """Fig. 7 (3-RRP in IM) and Fig. 13 (3-RSR in IM) gain one stress with their extra motion
    (square systems: rows = free coordinates − F); the regular ones have none."""
    counts = {p.name: analyze(read_model(p)).redundant_constraints for p in sorted(EXAMPLES.glob("*.toml"))}
    assert counts["fig7_3rrp.toml"] == 1 and counts["fig13_3rsr_c.toml"] == 1
    assert counts["fourbar_appendix.toml"] == 0 and counts["fig1a_3rrr.toml"] == 0
