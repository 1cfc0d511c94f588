"""Paths of mechanisms: located singular configurations against closed-form results."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin import Mechanism, SymkinError
from symkin.kinds import Kind
from symkin.model import catalogue
from symkin.paths.trace import follow_branch, trace


def fourbar(a_pos, b_pos, c_pos, d_pos, name="four-bar"):
    return Mechanism.from_dict({"name": name, "dim": 2, "fixed": ["A", "D"],
                                "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
                                "nodes": {"A": a_pos, "B": b_pos, "C": c_pos, "D": d_pos},
                                "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})


def angle_diff(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))


def test_crank_rocker_dead_centres_match_the_law_of_cosines():
    m = catalogue.get("fourbar_appendix")
    x = m.coordinates()
    a, b, c = (math.dist(x[p], x[q]) for p, q in (("A", "B"), ("B", "C"), ("D", "C")))
    d = math.dist(x["A"], x["D"])
    expected = []
    for r, turn in ((a + b, 0.0), (b - a, math.pi)):  # crank and coupler extended / folded
        expected.append(math.acos((r * r + d * d - c * c) / (2 * r * d)) + turn)
    path = trace(m, stop=360, unit="deg")
    events = path.singular_events()
    assert path.stop_reason == "reached" and len(events) == 2
    assert all(e.kind == "DKP-output" and e.analysis.types == ("DKP-output", "LIM") for e in events)
    found = sorted(e.absolute % (2 * math.pi) for e in events)
    for f, e in zip(found, sorted(v % (2 * math.pi) for v in expected)):
        assert angle_diff(f, e) < 1e-9
    assert all(e.analysis.locked_links == ("rocker",) and e.analysis.dof == 1 for e in events)
    # a full revolution with both dead centres located costs far fewer than 5000 residual evaluations
    assert path.residual_evaluations < 5000


def test_offset_slider_crank_dead_centres():
    m = catalogue.get("slider_crank")
    x = m.coordinates()
    a, b, e = math.dist(x["A"], x["B"]), math.dist(x["B"], x["C"]), 0.25
    ext = math.atan2(e, math.sqrt((a + b) ** 2 - e * e))
    fold = math.atan2(e, math.sqrt((b - a) ** 2 - e * e)) + math.pi
    path = trace(m, stop=2 * math.pi)
    events = path.singular_events()
    assert [ev.kind for ev in events] == ["DKP-output", "DKP-output"]
    found = sorted(ev.absolute % (2 * math.pi) for ev in events)
    assert angle_diff(found[0], ext) < 1e-9 and angle_diff(found[1], fold) < 1e-9
    for ev in events:
        assert ev.analysis.output_relations[0].as_dict() == {"slide:piston": 1.0}


def test_double_rocker_turns_back_and_closes_the_loop():
    """Crank 2, coupler 1, rocker 2.5, ground 3: the crank cannot turn fully (non-Grashof).
    The input turns back where coupler and rocker align: |BD| = b + c (DKP-input)."""
    a, b, c, d = 2.0, 1.0, 2.5, 3.0
    th = 1.2
    bpos = [a * math.cos(th), a * math.sin(th)]
    bd = math.dist(bpos, (d, 0.0))
    along = (b * b - c * c + bd * bd) / (2 * bd)
    h = math.sqrt(b * b - along * along)
    ex, ey = (d - bpos[0]) / bd, -bpos[1] / bd
    cpos = [bpos[0] + along * ex - h * ey, bpos[1] + along * ey + h * ex]
    m = fourbar([0.0, 0.0], bpos, cpos, [d, 0.0])
    path = trace(m, stop=360, unit="deg")
    # the loop closes without the crank reaching 360°: it turns back where |BD| = b + c
    assert path.stop_reason == "unreachable" and "cannot reach 360°" in path.message
    turning = [e for e in path.singular_events() if e.kind == "DKP-input"]
    assert len(turning) >= 2
    for bd_star in (b + c,):
        crank = math.acos((a * a + d * d - bd_star ** 2) / (2 * a * d))
        assert min(angle_diff(e.absolute, crank) for e in turning) < 1e-9 or \
            min(angle_diff(e.absolute, -crank) for e in turning) < 1e-9
    for e in turning:
        assert e.analysis.types[0] == "DKP-input" and e.analysis.input_relations[0].as_dict() == {"rotation:crank": 1.0}


def test_parallelogram_bifurcation_and_both_branches():
    m = fourbar([0.0, 0.0], [0.0, 1.0], [2.0, 1.0], [2.0, 0.0], "parallelogram")
    path = trace(m, stop=360, unit="deg")
    ims = [e for e in path.singular_events() if e.kind == "IM"]
    assert [round(math.degrees(e.input), 9) for e in ims] == [90.0, 270.0]
    for e in ims:
        assert e.analysis.dof == 2 and "IM" in e.analysis.types
        assert e.bifurcation.status == "simple" and len(e.bifurcation.directions) == 2
        assert abs(e.coordinates[1][1]) < 1e-12 and abs(e.coordinates[2][1]) < 1e-12  # flattened
    turns = []
    for branch in (0, 1):
        sub = follow_branch(path, ims[0], branch, max_arclength=1.0)
        coupler = [math.atan2(*(p.coordinates[2] - p.coordinates[1])[::-1]) for p in sub.points[1:]]
        turns.append(max(abs(math.remainder(cp - coupler[0], math.pi)) for cp in coupler))
    # one branch translates the coupler (parallelogram), the other turns it (anti-parallelogram)
    assert min(turns) < 1e-9 and max(turns) > 0.1


def test_five_bar_segment_with_one_input_held():
    path = trace(catalogue.get("five_bar"), input="rotation:crank1", stop=40, unit="deg")
    assert path.stop_reason == "reached"
    held = [math.atan2(*(p.coordinates[3] - p.coordinates[1])[::-1]) for p in path.points]
    assert max(abs(h - held[0]) for h in held) < 1e-10  # crank2 stays where it was


def test_bad_input_and_unreachable_start():
    m = catalogue.get("fourbar_appendix")
    with pytest.raises(SymkinError, match="unknown input 'rotation:nope'"):
        trace(m, input="rotation:nope", stop=1.0)
    # a double rocker (crank 2, ground 3): the crank cannot reach 170°
    m2 = fourbar([0.0, 0.0], [2.0 * math.cos(1.2), 2.0 * math.sin(1.2)], [2.9, 1.9], [3.0, 0.0])
    with pytest.raises(SymkinError):
        trace(m2, start=170, stop=180, unit="deg")


# ---------------------------------------------------------------------- events: once each, on the closure
def link_length_error(mech, x) -> float:
    """Largest change of a distance inside a link (bars and bodies), in units of the length scale."""
    x0 = mech.coordinates()
    idx = mech.node_index()
    worst = 0.0
    for _, nodes in mech.links:
        for i, p in enumerate(nodes):
            for q in nodes[i + 1:]:
                worst = max(worst, abs(math.dist(x[idx[p]], x[idx[q]]) - math.dist(x0[p], x0[q])))
    return worst / mech.length_scale


def peaucellier_flat_poses():
    """The flattened poses, by elementary geometry: O, C, A = B, P on one line with |OC| = |OA| − |AC|,
    and C on the crank circle through O (isosceles triangle O-Q-C: angle QOC = acos(|OC| / (2|QC|)))."""
    m = catalogue.get("peaucellier")
    x = m.coordinates()
    arm, side, crank = math.dist(x["O"], x["A"]), math.dist(x["A"], x["C"]), math.dist(x["Q"], x["C"])
    oc = arm - side
    oq = math.atan2(x["Q"][1], x["Q"][0])
    poses = []
    for sgn in (1, -1):
        phi = oq + sgn * math.acos(oc / (2 * crank))
        c = (oc * math.cos(phi), oc * math.sin(phi))
        poses.append({"line": phi, "C": c, "crank": math.atan2(c[1] - x["Q"][1], c[0] - x["Q"][0])})
    return m, arm, side, poses


def _without_lim(path):
    """The singular events other than LIM; the LIM events (the arms O-A, O-B stop and turn back) are confirmed."""
    lim = [e for e in path.singular_events() if e.kind == Kind.LIM]
    assert all(e.confirmed and len(e.analysis.locked_links) == 1 for e in lim)
    return [e for e in path.singular_events() if e.kind != Kind.LIM]


def test_peaucellier_flattened_pose_reported_once_on_the_closure_with_its_classification():
    m, arm, side, poses = peaucellier_flat_poses()
    path = trace(m, stop=360, unit="deg")
    events = _without_lim(path)
    # the crank is a rocker between the two flattened poses: each is reported once
    assert len(events) == 2
    assert path.stop_reason == "unreachable"
    assert min(angle_diff(path.turning_absolute, p["crank"]) for p in poses) < 1e-12
    idx = m.node_index()
    for e in events:
        x = e.coordinates
        assert link_length_error(m, x) <= 1e-12
        assert float(np.linalg.norm(path.curve.residual(e.y))) <= 1e-12
        pose = min(poses, key=lambda p: angle_diff(p["crank"], e.absolute))
        assert angle_diff(e.absolute, pose["crank"]) < 1e-12
        assert math.dist(x[idx["A"]], x[idx["B"]]) <= 1e-12 * m.length_scale
        assert math.dist(x[idx["C"]], pose["C"]) <= 1e-12 * m.length_scale
        u = np.array([math.cos(pose["line"]), math.sin(pose["line"])])
        np.testing.assert_allclose(x[idx["P"]], (arm + side) * u, atol=1e-12 * m.length_scale)
        # O-A-C folded: C is locked (|OC| is at its minimum and C is on the crank circle), so the crank is;
        # A, B and P may each move perpendicular to the line: L = 3 for F = 1
        a = e.analysis
        assert (e.kind, a.types, a.dof, a.mobility, a.locked_links) == ("IM", ("IM", "DKP-input", "LIM"), 3, 1,
                                                                         ("crank",))
        assert [r.as_dict() for r in a.input_relations] == [{"rotation:crank": 1.0}]
        # the crank is locked, so all three motions are uncontrolled; each moves A, B or P across the line
        assert len(a.uncontrolled_motions) == 3
        moved = set()
        for motion in a.uncontrolled_motions:
            v = dict(motion.velocities)
            assert float(np.linalg.norm(v["C"])) <= 1e-9
            for node in "ABP":
                assert abs(float(np.dot(v[node], u))) <= 1e-9 * float(np.linalg.norm(v[node])) + 1e-15
            moved |= {node for node in "ABP" if float(np.linalg.norm(v[node])) > 1e-9}
        assert moved == {"A", "B", "P"}
        # located by the turning point of the crank and by the IM test: one event carrying both
        # (and by the LIM test of the crank, which stops there)
        assert set(e.tests) == {"DKP-input", "IM", "LIM:crank"} and e.kinds == ("IM", "DKP-input", "LIM")
    assert sorted(round(math.degrees(e.absolute), 9) for e in events) == \
        sorted(round(math.degrees(p["crank"]) % 360, 9) for p in poses)  # absolute angles in [0°, 360°)


@pytest.mark.parametrize("name, kwargs", [
    ("fourbar_appendix", dict(stop=360, unit="deg")),
    ("slider_crank", dict(stop=2 * math.pi)),
    ("rrr_3", dict(stop=360, unit="deg")),
    ("rssr", dict(stop=360, unit="deg")),
    ("five_bar", dict(input="rotation:crank1", stop=40, unit="deg")),
    ("parallelogram", dict(stop=360, unit="deg")),
    ("double rocker", dict(stop=360, unit="deg")),
    ("peaucellier", dict(stop=360, unit="deg")),
])
def test_every_located_event_is_on_the_closure(name, kwargs):
    if name == "parallelogram":
        m = fourbar([0.0, 0.0], [0.0, 1.0], [2.0, 1.0], [2.0, 0.0], name)
    elif name == "double rocker":
        m = fourbar([0.0, 0.0], [2.0 * math.cos(1.2), 2.0 * math.sin(1.2)], [2.9, 1.9], [3.0, 0.0])
    else:
        m = catalogue.get(name)
    path = trace(m, **kwargs)
    assert path.events
    ys = [e.y for e in path.singular_events()]
    for e in path.events:
        assert float(np.linalg.norm(path.curve.residual(e.y))) <= 1e-12, (e.kind, e.input)
        assert link_length_error(m, e.coordinates) <= 1e-12
    # no configuration is reported twice
    for i, a in enumerate(ys):
        for b in ys[i + 1:]:
            assert float(np.linalg.norm(a - b)) > 1e-6


def rocker_limits(m):
    """Absolute angles of the rocker D→C where crank and coupler align (|AC| = coupler ± crank), for
    C above the ground line A-D: the law of cosines in triangle A-C-D gives the angle at D."""
    x = m.coordinates()
    a, b, c = (math.dist(x[p], x[q]) for p, q in (("A", "B"), ("B", "C"), ("D", "C")))
    d = math.dist(x["A"], x["D"])
    return {"extended": math.pi - math.acos((c * c + d * d - (a + b) ** 2) / (2 * c * d)),
            "folded": math.pi - math.acos((c * c + d * d - (b - a) ** 2) / (2 * c * d))}


def test_rocker_driven_past_its_limit_is_unreachable_and_says_where_it_turns_back():
    m = catalogue.get("fourbar_appendix")
    x = m.coordinates()
    start = math.atan2(x["C"][1] - x["D"][1], x["C"][0] - x["D"][0])
    limits = rocker_limits(m)
    # turning the rocker counter-clockwise from the model's 85.6° folds the crank onto the coupler
    assert limits["extended"] < start < limits["folded"]
    path = trace(m, input="rotation:rocker", stop=180, unit="deg")
    assert path.stop_reason == "unreachable"
    assert abs(path.turning_absolute - limits["folded"]) < 1e-9
    assert abs(path.turning_input - (limits["folded"] - start)) < 1e-9
    assert "the input cannot reach 180°" in path.message and "closed on its start" not in path.message[:40]
    assert f"turns back at {math.degrees(path.turning_input):.10g}°" in path.message
    assert f"(absolute {math.degrees(path.turning_absolute):.10g}°)" in path.message
    data = path.to_dict("deg")
    assert data["stop_reason"] == "unreachable"
    assert data["turning"]["absolute"] == pytest.approx(math.degrees(limits["folded"]), abs=1e-7)
    # the other way it turns back at the extended dead centre
    back = trace(m, input="rotation:rocker", stop=-180, unit="deg")
    assert back.stop_reason == "unreachable" and abs(back.turning_absolute - limits["extended"]) < 1e-9
    # a crank that turns fully is not "unreachable": its loop closes after a full turn
    assert trace(m, stop=720, unit="deg").stop_reason == "closed"


@pytest.mark.parametrize("factor", [1024.0, 1.0 / 1024.0])
def test_peaucellier_events_do_not_depend_on_the_unit_of_length(factor):
    _, _, _, poses = peaucellier_flat_poses()
    data = catalogue.data("peaucellier")
    data["nodes"] = {n: [factor * v for v in c] for n, c in data["nodes"].items()}
    m = Mechanism.from_dict(data)
    path = trace(m, stop=360, unit="deg")
    events = _without_lim(path)
    assert path.stop_reason == "unreachable" and len(events) == 2
    for e in events:
        assert (e.analysis.types, e.analysis.dof) == (("IM", "DKP-input", "LIM"), 3)
        assert min(angle_diff(e.absolute, p["crank"]) for p in poses) < 1e-12
        assert link_length_error(m, e.coordinates) <= 1e-12


def test_trace_results_honour_the_unit_asked_for():
    """``trace(..., unit="deg")``: ``values``/``to_dict`` in degrees; relative in (−180°, 180°], absolute in [0°, 360°)."""
    m = catalogue.get("fourbar_appendix")
    deg = trace(m, stop=360, unit="deg")
    rad = trace(m, stop=2 * math.pi)
    assert deg.unit == "deg" and rad.unit == "rad"
    for a, b in zip(deg.singular_events(), rad.singular_events()):
        vd, vr = deg.values(a), rad.values(b)
        for key in ("input", "relative", "absolute"):
            assert vd[key] == pytest.approx(math.degrees(vr[key]), abs=1e-7)
        assert -180 < vd["relative"] <= 180 and 0 <= vd["absolute"] < 360
        assert math.isclose(math.remainder(vd["input"] - vd["relative"], 360), 0, abs_tol=1e-9)
    events = deg.to_dict()["events"]  # the JSON in the unit of the trace by default
    assert [e["input"] for e in events] == pytest.approx([deg.values(e)["input"] for e in deg.events])
    assert rad.to_dict("deg")["events"][0]["relative"] == pytest.approx(events[0]["relative"], abs=1e-7)
    out = deg.outputs(deg.singular_events()[-1])
    assert out["rotation:rocker"]["relative"] == pytest.approx(-24.24725354, abs=1e-7)
    assert out["rotation:rocker"]["absolute"] == pytest.approx(61.3540411, abs=1e-6)


def test_coordinate_values_relative_and_absolute():
    """A node coordinate's absolute value is the coordinate (as a map's axes); a length is not wrapped."""
    from symkin.paths.trace import CoordinateValues

    m = catalogue.get("five_bar")
    x = np.array([c for _, c in m.nodes], float)
    x[m.node_index()["P"], 0] += 0.5  # values are expressions of the coordinates: no closure needed
    v = CoordinateValues(m, ["velocity:P.x", "velocity:P.y", "rotation:crank1"])(x, unit="deg")
    assert v["velocity:P.x"] == {"relative": 0.5, "absolute": 0.5}
    assert v["velocity:P.y"] == {"relative": 0.0, "absolute": 2.0}
    assert v["rotation:crank1"]["relative"] == 0.0
    assert v["rotation:crank1"]["absolute"] == pytest.approx(180 - math.degrees(math.atan2(0.8, 0.6)), abs=1e-12)
