"""Spatial joint rates between two moving links (issue 16): ``joint:R1``, ``joint:C1.rotation``, ``joint:U1.1|2``.

A spatial relative rotation rate is ``a·(ω₂ − ω₁)`` about the joint's (moving) axis, on the
existing rotation rows of every backend.  Checked against truth computed here without
symkin's rows: the links' rotations fitted to their nodes (Kabsch) along a traced path,
differenced, and angular velocities solved from node velocities by elementary algebra.
"""
from __future__ import annotations

import contextlib
import io
import json
import zlib

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.analysis.batch import evaluators
from symkin.cli import main
from symkin.errors import ModelError
from symkin.model import catalogue
from symkin.numeric import geometric_matrix as gm
from tests.model import joint_forms as jf

symbolic = pytest.importorskip("symkin.symbolic")


def _bennett(outputs=("B", "C", "D")) -> symkin.Mechanism:
    data = jf.bennett(catalogue.get("bennett").coordinates())
    data["outputs"] = [{"joint": j} for j in outputs]
    return symkin.Mechanism.from_dict(data)


def _ups(outputs) -> symkin.Mechanism:
    data = jf.ups_6(symkin.read_model(jf.MODELS / "gough_stewart.toml").coordinates())
    data["outputs"] = list(outputs)
    return symkin.Mechanism.from_dict(data)


def _blocks_c(**extra) -> dict:
    """Two bodies joined by a C along x; the first pivoted to ground by an S (DOF 3 + 2)."""
    return {"name": "two blocks, C", "dim": 3, "mobility": 5,
            "links": {"a": ["A1", "A2", "A3"], "b": ["B1", "B2", "B3"]},
            "nodes": {"A1": [0, 0, 0], "A2": [1, 0, 0], "A3": [0, 1, 0],
                      "B1": [2, 0.5, 0.2], "B2": [3, 0, 0], "B3": [2, 0, 1]},
            "inputs": [{"joint": "J", "motion": "rotation"}],
            "joints": [{"type": "S", "links": ["ground", "a"], "at": [0, 0, 0]},
                       {"id": "J", "type": "C", "links": ["a", "b"], "at": [2, 0, 0], "axis": [1, 0, 0], **extra}]}


def _rotation(p0: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The rotation taking the points ``p0`` to ``p`` (Kabsch): elementary, no symkin rows."""
    a, b = p0 - p0.mean(0), p - p.mean(0)
    u, _, vt = np.linalg.svd(b.T @ a)
    return u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt


def _relative_angle(mech, x0, x, first, second, axis0) -> float:
    """Angle of ``second`` relative to ``first`` about ``axis0`` (the axis at ``x0``, fixed in ``first``)."""
    idx = mech.node_index()

    def turn(link):
        if link == "ground":
            return np.eye(3)
        ns = [idx[n] for n in mech.link_nodes(link)]
        return _rotation(x0[ns], x[ns])

    r = turn(first).T @ turn(second)  # second's rotation seen from first: about axis0
    s = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    return float(np.arctan2(s @ axis0, (np.trace(r) - 1.0) / 2.0))


def _omega(mech, x, v, link) -> np.ndarray:
    """Angular velocity of ``link`` from its node velocities: ``v_k − v_i = ω × r_k`` (least squares)."""
    idx = mech.node_index()
    ns = [idx[n] for n in mech.link_nodes(link)]
    rows, rhs = [], []
    for k in ns[1:]:
        r = x[k] - x[ns[0]]
        rows.append(-np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]]))
        rhs.append(v[k] - v[ns[0]])
    return np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)[0]


def test_bennett_relative_rates_are_derivatives_of_the_relative_angles():
    """Along a traced Bennett path (driven by joint:B, between two moving links), every joint's
    rate ratio equals the centred difference of the independently measured relative angles."""
    m = _bennett()
    assert [p.kind for p in m.outputs] == ["joint", "joint", "rotation"]
    assert m.outputs[0].axis == ("B", "B.axis") and m.outputs[0].labels(3) == ("joint:B",)
    path = symkin.trace(m, "joint:B", 0.0, 0.8, steps=80, branch_analysis=False)
    assert path.stop_reason == "reached"
    x0 = np.array([c for _, c in m.nodes])
    idx = m.node_index()
    axes = {}
    for j in m.joints:
        axes[j.id] = (*j.links, np.array(j.axis))
    xs = [p.coordinates.reshape(-1, 3) for p in path.points]
    angles = {j: np.array([_relative_angle(m, x0, x, *axes[j]) for x in xs]) for j in "ABCD"}
    # the path's input is the position-level joint:B angle: the measured angle itself
    assert np.allclose(angles["B"], [p.input for p in path.points], atol=1e-9)
    checked = 0
    for k in range(1, len(xs) - 1, 7):
        mk = m.with_coordinates(xs[k])
        motion = symkin.analyze(mk).motion
        rows, labels = gm.parameters_matrix(mk, mk.inputs + mk.outputs)
        rates = rows @ motion.V[:, 0]      # V: over all nodal coordinates
        rate = dict(zip(labels, rates))
        fd = {j: (angles[j][k + 1] - angles[j][k - 1]) for j in "ABCD"}
        for j in "ACD":
            assert rate[f"joint:{j}"] / rate["joint:B"] == pytest.approx(fd[j] / fd["B"], rel=2e-3, abs=1e-6), (k, j)
        # and the rate is the difference of the two links' angular velocities about the axis
        v = motion.V[:, 0].reshape(-1, 3)
        a = xs[k][idx["B.axis"]] - xs[k][idx["B"]]
        a /= np.linalg.norm(a)
        truth = a @ (_omega(mk, xs[k], v, "link2") - _omega(mk, xs[k], v, "link1"))
        assert rate["joint:B"] == pytest.approx(truth, rel=1e-9, abs=1e-12)
        checked += 1
    assert checked >= 5


@pytest.mark.slow
def test_ups_u_rates_both_axes_against_measured_angles():
    """6-UPS: both rates of U1 (axis 1 on ground, axis 2 between the cross and the moving
    cylinder) and U2's axis 2 are the derivatives of the measured U angles along every motion
    (centred differences of configurations projected back onto the closure)."""
    m = _ups([{"joint": "U1", "axis": 1}, {"joint": "U1", "axis": 2}, {"joint": "U2", "axis": 2}])
    assert [p.labels(3)[0] for p in m.outputs] == ["joint:U1.1", "joint:U1.2", "joint:U2.2"]
    assert m.outputs[0].kind == "rotation" and m.outputs[1].kind == "joint"
    assert m.outputs[1].target == ("U1.cross", "cyl1") and m.outputs[1].axis == ("U1", "U1.axis2")
    ev = evaluators(m)
    free = gm.free_mask(m)
    x0 = np.array([c for _, c in m.nodes])
    u = {j.id: j for j in m.joints}
    measure = {"joint:U1.1": ("ground", "U1.cross", u["U1"].axis), "joint:U1.2": ("U1.cross", "cyl1", u["U1"].axis2),
               "joint:U2.2": ("U2.cross", "cyl2", u["U2"].axis2)}
    rng = np.random.default_rng(16)
    h = 1e-5 * m.length_scale
    biggest = 0.0
    for q in (ev.q0, ev.project(ev.q0 + 0.03 * m.length_scale * rng.standard_normal(ev.nf), tol=1e-14)):
        mk = ev.mechanism_at(q)
        motion = symkin.analyze(mk).motion
        rows, labels = gm.parameters_matrix(mk, mk.outputs)
        for col in motion.V.T:
            ends = [ev.coordinates(ev.project(q + s * h * col[free], tol=1e-14)) for s in (1.0, -1.0)]
            for row, lab in zip(rows, labels):
                first, second, axis = measure[lab]
                theta = [_relative_angle(m, x0, x.reshape(-1, 3), first, second, np.array(axis)) for x in ends]
                fd = (theta[0] - theta[1]) / (2 * h)
                assert float(row @ col) == pytest.approx(fd, rel=1e-5, abs=1e-6 / m.length_scale), lab
                biggest = max(biggest, abs(fd) * m.length_scale)
    assert biggest > 0.1  # not a vacuous zero


def test_c_rotation_between_moving_bodies_is_the_difference_of_angular_velocities():
    """Every motion of two bodies on a C: joint:J.rotation = a·(ω_b − ω_a), ω solved from node speeds."""
    m = symkin.Mechanism.from_dict(_blocks_c())
    assert m.inputs[0].kind == "joint" and m.inputs[0].axis == ("J.base", "J.line")
    motion = symkin.analyze(m).motion
    assert motion.dof == 5
    x = np.array([c for _, c in m.nodes])
    row = gm.parameter_rows(m, m.inputs[0])[0]
    spin = 0.0
    for col in motion.V.T:
        v = col.reshape(-1, 3)
        truth = np.array([1.0, 0.0, 0.0]) @ (_omega(m, x, v, "b") - _omega(m, x, v, "a"))
        assert float(row @ col) == pytest.approx(truth, abs=1e-12)
        spin = max(spin, abs(truth))
    assert spin > 0.1


def _blocks_u() -> symkin.Mechanism:
    """Two bodies joined by a U (both axes between moving links), the first on an S to ground."""
    data = _blocks_c(axis2=[0, 1, 0])
    data["joints"][1]["type"] = "U"
    data["inputs"] = [{"joint": "J", "axis": 1}, {"joint": "J", "axis": 2}]
    return symkin.Mechanism.from_dict(data)


@pytest.mark.parametrize("make", [lambda: _bennett(), _blocks_u, lambda: symkin.Mechanism.from_dict(_blocks_c())])
def test_numpy_casadi_and_sympy_rows_agree(make):
    """The rows of every backend agree at random configurations on the closure (sympy's on the motions)."""
    mech = make()
    ev = evaluators(mech)
    sm = symbolic.symbolic_model(mech, coordinates="nodes")
    labels = sm.coordinate_labels
    index = [labels.index(s.name) for s in sm.config_symbols]
    sym_in, sym_out = sm.parameter_rows(mech.inputs)[0], sm.parameter_rows(mech.outputs)[0]
    f = sp.lambdify(sm.config_symbols, [sym_in, sym_out], "numpy")
    rng = np.random.default_rng(zlib.crc32(mech.name.encode()))
    q = ev.project(ev.q0 + 0.05 * mech.length_scale * rng.standard_normal((6, ev.nf)), tol=1e-14)
    worst, size = 0.0, 0.0
    for k in range(q.shape[0]):
        xyz = ev.coordinates(q[k]).ravel()
        mk = ev.mechanism_at(q[k])
        cas = ev("parameters", q[k])
        v = symkin.analyze(mk).motion.V
        for s, c, params in zip(f(*xyz[index]), (cas["inputs"], cas["outputs"]), (mk.inputs, mk.outputs)):
            if not params:
                continue
            core = gm.parameters_matrix(mk, params)[0]
            s = np.array(s, dtype=float).reshape(core.shape)
            scale = np.max(np.abs(core))
            worst = max(worst, np.max(np.abs(np.asarray(c) - core)) / scale)   # CasADi: the same rows
            # sympy's spatial rotation rows use two edges of the link: equal on its rigid motions
            worst = max(worst, np.max(np.abs((s - core) @ v)) / np.max(np.abs(core @ v)))
            size = max(size, np.max(np.abs(core @ v)))
    assert size > 0 and worst <= 1e-12


def test_rates_are_scale_invariant_mm_and_m():
    m = _bennett()
    mm = m.moved(scale=1000.0)
    a, b = (gm.parameters_matrix(x, x.outputs)[0] for x in (m, mm))
    assert np.allclose(b * 1000.0, a, rtol=1e-12, atol=1e-12 * np.max(np.abs(a)))


def test_cli_path_drives_a_relative_spatial_rate(tmp_path):
    data = jf.bennett(catalogue.get("bennett").coordinates())
    data["inputs"] = [{"joint": "C"}]
    path = tmp_path / "bennett.json"
    path.write_text(json.dumps(data))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["path", str(path), "--input", "joint:B", "--to", "40", "--no-progress", "--json"])
    assert code == 0, err.getvalue()
    got = json.loads(out.getvalue())
    assert got["input"] == "joint:B" and got["stop_reason"] == "reached"


@pytest.mark.parametrize("entry, expected", [
    ({"joint": "U1", "axis": 3}, "inputs[0]: joint U1 is a U: give axis = 1 or 2"),
    ({"joint": "P1", "motion": "rotation"}, "'motion' and 'axis' go with C and U joints, not with P joint P1"),
    ({"joint": "S1"}, "joint S1 is an S: it has no single rate"),
])
def test_bad_rate_requests_exit_2_naming_the_joint(tmp_path, entry, expected):
    data = jf.ups_6(symkin.read_model(jf.MODELS / "gough_stewart.toml").coordinates())
    data["inputs"] = [entry] + data["inputs"][1:]
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["analyze", str(path)])
    assert code == 2 and expected in err.getvalue() and "Traceback" not in err.getvalue()


def test_c_with_a_motion_it_does_not_have_and_a_rod_on_the_axis_are_named():
    data = _blocks_c()
    data["inputs"] = [{"joint": "J", "motion": "twist"}]
    with pytest.raises(ModelError, match=r"joint J is a C: give motion"):
        symkin.Mechanism.from_dict(data)
    data = _blocks_c()
    data["links"]["b"] = []               # the runner is only its two nodes on the line: a rod on the axis
    data["nodes"] = {k: v for k, v in data["nodes"].items() if not k.startswith("B")}
    data["mobility"] = 4
    with pytest.raises(ModelError, match=r"rotation rate of joint J is not defined: link b is a rod along"):
        symkin.Mechanism.from_dict(data)


def _fourbar(second_ground: bool) -> symkin.Mechanism:
    data = jf.fourbar(catalogue.get("fourbar_appendix").coordinates())
    if second_ground:
        data["joints"][3]["links"] = ["rocker", "ground"]
    return symkin.Mechanism.from_dict(data)


def test_planar_r_with_ground_second_is_minus_the_rocker_rotation():
    """R4 written [rocker, ground]: its rate is ground's rotation (zero) minus the rocker's, in every backend."""
    a, b = _fourbar(False), _fourbar(True)
    assert b.outputs[0].kind == "joint" and b.outputs[0].target == ("rocker", "ground")
    assert b.outputs[0].labels(2) == ("joint:R4",)
    ra, rb = gm.parameters_matrix(a, a.outputs)[0], gm.parameters_matrix(b, b.outputs)[0]
    assert np.abs(ra).max() > 0.1 and np.allclose(rb, -ra, rtol=0, atol=1e-15)
    assert np.allclose(gm.parameter_rows(b, b.outputs[0]), rb, rtol=0, atol=1e-15)   # the planar program and the rows
    ev = evaluators(b)
    assert np.allclose(ev("parameters", ev.q0)["outputs"], rb, rtol=0, atol=1e-15)
    sm = symbolic.symbolic_model(b, coordinates="nodes")
    rows = np.array(sm.evaluate(sm.parameter_rows(b.outputs)[0]), dtype=float)
    v = symkin.analyze(b).motion.V
    assert np.allclose(rows @ v, rb @ v, rtol=0, atol=1e-12)
    # position level: driving R4 by +0.3 rad turns the rocker by −0.3 rad (the same configuration)
    pb = symkin.trace(b, "joint:R4", 0.0, 0.3, steps=10, branch_analysis=False)
    pa = symkin.trace(a, "joint:R4", 0.0, -0.3, steps=10, branch_analysis=False)
    assert pb.stop_reason == pa.stop_reason == "reached"
    assert np.allclose(pb.points[-1].coordinates, pa.points[-1].coordinates, atol=1e-9)
    assert symkin.analyze(a).output_rank == symkin.analyze(b).output_rank == 1


def test_planar_r_with_ground_second_in_the_global_solve():
    a, b = _fourbar(False), _fourbar(True)
    sa, sb = symkin.solve_all(a, {"joint:R4": -0.3}), symkin.solve_all(b, {"joint:R4": 0.3})

    def points(sols):
        return sorted(np.round(np.ravel([s.configuration[n] for n in a.node_names]), 7).tolist() for s in sols.solutions)

    assert len(sa.solutions) == len(sb.solutions) == 2
    assert np.allclose(points(sa), points(sb), atol=1e-6)


def test_planar_r_with_ground_second_in_singularities():
    """The square DKP systems (homotopy) and the traced circuits agree; the output angles are negated."""
    a, b = _fourbar(False), _fourbar(True)
    sa, sb = symkin.singularities(a), symkin.singularities(b)
    check = {c.kind: c for c in sb.checks}["DKP-output"]
    assert check.label == "joint:R4" and check.homotopy == check.traced == check.matched == 4
    assert sorted(-x.output for x in sa.singularities) == pytest.approx(sorted(x.output for x in sb.singularities),
                                                                        abs=1e-6)


@pytest.mark.parametrize("make", [lambda: _bennett(), lambda: _fourbar(True), _blocks_u])
def test_relative_rates_round_trip_through_the_node_form(make):
    m = make()
    again = symkin.Mechanism.from_dict(json.loads(json.dumps(m.to_dict())))
    assert again == m and again.inputs == m.inputs and again.outputs == m.outputs


@pytest.mark.parametrize("make", [lambda: _bennett(), lambda: _fourbar(True), _blocks_u,
                                  lambda: symkin.Mechanism.from_dict(_blocks_c())])
def test_position_coordinate_gradient_is_the_rate_row(make):
    """The position-level joint angle (what a path drives) has the rate row as its gradient on the motions."""
    from symkin.numeric.coordinates import LinearInput, input_coordinates
    from symkin.paths.system import MechanismCurve

    mech = make()
    v = symkin.analyze(mech).motion.V
    free = gm.free_mask(mech)
    checked = 0
    for c in input_coordinates(mech, mech.inputs + tuple(p for p in mech.outputs if p.kind == "joint")):
        curve = MechanismCurve(mech, LinearInput.single(c), generated=False)
        grad = np.array(curve._drive(curve.y0())[1]).ravel() / curve.scale
        row = gm.parameter_rows(mech, c.parameter)[0]
        np.testing.assert_allclose(grad @ v[free], row[free] @ v[free], atol=1e-12, err_msg=c.label)
        checked += c.parameter.kind == "joint"
    assert checked >= 1
