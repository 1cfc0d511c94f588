"""The helical pair H: one constraint module (:mod:`symkin.constraints.helical`) and its joint compilation.

Checked against hand derivations, not against earlier output:

* the screw jack (ground–screw R, screw–nut H of pitch p, nut–ground P): DOF 1 and the nut's
  slide rate ``v = p·ω`` exactly, in m and mm, rotated, for a left-handed screw too;
* H with pitch 0 is an R: the same DOF and ranks as the jack with an R in place of its H, and
  in a loop the same motion (node velocities per input rate) as with an R;
* a single-loop spatial RHSS mechanism of generic geometry has DOF 1 (closed form below), one
  less than the same loop with a C, and its motion keeps ``slide = p · rotation`` at the pair;
* the polynomial backends refuse it with the joint's name; bad ``pitch`` keys are model errors.
"""
from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.errors import ModelError
from symkin.numeric.geometric_matrix import parameters_matrix

MODELS = Path(__file__).parent / "models"


def _data(name: str) -> dict:
    return tomllib.loads((MODELS / f"{name}.toml").read_text())


def _joint(data: dict, jid: str) -> dict:
    return next(j for j in data["joints"] if j["id"] == jid)


def _ratio(mech) -> np.ndarray:
    """Output rates per input rate along the motion space (DOF 1): ``(rows_out V) / (rows_in V)``."""
    ms = symkin.motion_space(mech)
    assert ms.dof == 1
    rin, _ = parameters_matrix(mech, mech.inputs)
    rout, _ = parameters_matrix(mech, mech.outputs)
    return (rout @ ms.V).ravel() / float((rin @ ms.V).ravel()[0])


def _rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    return q * np.sign(np.linalg.det(q))


@pytest.mark.parametrize("pitch", [0.004, -0.03, 0.25])
def test_screw_jack_slide_is_pitch_times_rotation(pitch):
    """Screw (R to ground, axis z) drives the nut (P to ground, axis z) through H of pitch p.

    The nut does not turn, so its rotation relative to the screw is ``−ω``; the H makes the
    nut's slide along +z relative to the screw ``p·(−ω)``; the P's rate (its slider runs
    along −z, ground being the P's second link) is then ``v = p·ω``.  DOF 1.
    """
    data = _data("screw_jack")
    _joint(data, "H1")["pitch"] = pitch
    mech = symkin.Mechanism.from_dict(data)
    a = symkin.analyze(mech)
    assert (a.dof, a.input_rank, a.output_rank, a.types) == (1, 1, 1, ())
    assert _ratio(mech) == pytest.approx([pitch], rel=1e-12)
    # m vs mm (the pitch is a length: it scales), rotated and moved
    assert _ratio(mech.moved(scale=1000.0)) == pytest.approx([1000.0 * pitch], rel=1e-12)
    assert _ratio(mech.moved(rotation=_rotation(5), translation=[0.3, -2.0, 7.0])) == \
        pytest.approx([pitch], rel=1e-12)


def test_screw_jack_from_the_model_file():
    mech = symkin.read_model(MODELS / "screw_jack.toml")
    assert [h.id for h in mech.helicals] == ["H1"]
    assert {"H1.arm", "H1.guide"} <= set(mech.node_names)
    assert _ratio(mech) == pytest.approx([0.004], rel=1e-12)
    # round trip through the model dictionary
    again = symkin.Mechanism.from_dict(mech.to_dict())
    assert again.helicals == mech.helicals
    assert _ratio(again) == pytest.approx([0.004], rel=1e-12)


def test_ground_guide_rate_is_the_joint_rate():
    """H with ground as its guide: ``{joint = "H1"}`` is the rotation about the axis and the
    screw's slide along it is ``pitch`` times that (here a left-handed screw, p = −0.05)."""
    mech = symkin.read_model(MODELS / "ground_screw.toml")
    assert mech.inputs[0].label == "joint:H1"
    assert _ratio(mech) == pytest.approx([-0.05], rel=1e-12)


def _with_r(data: dict, jid: str) -> dict:
    """The model with joint ``jid`` (an H) turned into an R on the same axis."""
    out = copy.deepcopy(data)
    j = _joint(out, jid)
    j["type"] = "R"
    del j["pitch"]
    return out


def test_pitch_zero_is_a_revolute_pair():
    """Pitch 0 (and 1e-12 of the length scale) is an R.

    Screw jack: the nut can neither slide relative to the screw nor turn (P), so it is locked
    while the screw turns: DOF 1, output rank 0 (an R between screw and nut would share the
    screw's fixed axis nodes, so the jack has no node-form R twin).  RHSS loop: the same DOF,
    ranks and velocity of S1 per crank rate as the RRSS loop with an R on the H's axis.
    """
    for pitch in (0.0, 1e-12):
        d = _data("screw_jack")
        _joint(d, "H1")["pitch"] = pitch
        a = symkin.analyze(symkin.Mechanism.from_dict(d))
        assert (a.dof, a.input_rank, a.output_rank) == (1, 1, 0)
    data = _data("rhss")
    r = symkin.Mechanism.from_dict(_with_r(data, "H1"))
    as_r = symkin.analyze(r)
    for pitch in (0.0, 1e-12):
        d = copy.deepcopy(data)
        _joint(d, "H1")["pitch"] = pitch
        h0 = symkin.Mechanism.from_dict(d)
        a = symkin.analyze(h0)
        assert (a.dof, a.input_rank, a.output_rank) == (as_r.dof, as_r.input_rank, as_r.output_rank) == (1, 1, 1)
        assert _ratio(h0) == pytest.approx(_ratio(r), rel=1e-9, abs=1e-12)
    assert not np.allclose(_ratio(symkin.read_model(MODELS / "rhss.toml")), _ratio(r))  # the pitch matters


def _twist(mech, v: np.ndarray, link: str):
    """Angular velocity of ``link`` and the velocity field's value at the origin, fitted to its
    nodes' velocities ``v`` (n, 3) by least squares — independent of the constraint rows."""
    idx = [mech.node_names.index(n) for n in mech.link_nodes(link)]
    x = np.array([c for _, c in mech.nodes], float)[idx]
    rows, rhs = [], []
    for k, p in enumerate(x):  # v_k = v_o + ω × p_k = v_o − [p_k]× ω
        skew = np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])
        rows.append(np.hstack([np.eye(3), -skew]))
        rhs.append(v[idx[k]])
    sol, *_ = np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)
    return sol[3:], sol[:3]


def test_single_loop_rhss_closed_form():
    """A single loop ground –R– crank –H– nut –S– rod –S– ground, generic geometry.

    Closed form (Kutzbach–Grübler for one loop of n = 4 links and j = 4 joints):
    ``M = 6(n − 1 − j) + Σ f_i − idle = −6 + (1 + 1 + 3 + 3) − 1 = 1``, the idle freedom
    being the rod's spin about its S–S line (no coordinate of the nodal method: the rod is a
    bar).  With a C (f = 2) in place of the H: ``M = −6 + 9 − 1 = 2``; the H is the C plus
    one equation (s = p·θ), so it takes exactly one freedom away.  Along the motion, the
    nut's twist relative to the crank is a screw about the pair's axis of pitch p: the slide
    of the point on the axis is p times the relative rotation (both fitted from node
    velocities, not read from the rows).
    """
    mech = symkin.read_model(MODELS / "rhss.toml")
    a = symkin.analyze(mech)
    assert (a.dof, a.redundant_constraints) == (1, 0)
    data = _data("rhss")
    as_c = copy.deepcopy(data)
    _joint(as_c, "H1")["type"] = "C"
    del _joint(as_c, "H1")["pitch"]
    assert symkin.analyze(symkin.Mechanism.from_dict(as_c)).dof == 2
    # the screw relation along the motion, at the model and in mm, rotated
    for m in (mech, mech.moved(scale=1000.0, rotation=_rotation(9))):
        h = m.helicals[0]
        v = symkin.motion_space(m).V[:, 0].reshape(-1, 3)
        w_crank, o_crank = _twist(m, v, "crank")
        w_nut, o_nut = _twist(m, v, "nut")
        coords = m.coordinates()
        at = np.array(coords[h.node])
        e = np.array(coords[h.line[1]]) - np.array(coords[h.line[0]])
        e /= np.linalg.norm(e)
        omega = float((w_nut - w_crank) @ e)
        slide = float(((o_nut + np.cross(w_nut, at)) - (o_crank + np.cross(w_crank, at))) @ e)
        assert abs(omega) * m.length_scale > 1e-3 * np.abs(v).max()  # the pair does turn
        assert slide == pytest.approx(h.pitch * omega, rel=1e-9)


def test_path_turns_the_screw():
    """The CasADi closure of H (the arms' angle by atan2, wrapped): a path of the screw jack over
    most of a half turn keeps the nut at ``−z = p·θ`` at finite displacements, point by point."""
    mech = symkin.read_model(MODELS / "screw_jack.toml")
    path = symkin.trace(mech, stop=2.9)
    assert path.points[-1].input == pytest.approx(2.9)
    k = mech.node_names.index("H1")
    for pt in path.points:
        z = np.asarray(pt.coordinates).reshape(-1, 3)[k, 2]
        assert -z == pytest.approx(0.004 * pt.input, abs=1e-10)


def test_polynomial_backends_refuse_with_the_joint():
    mech = symkin.read_model(MODELS / "screw_jack.toml")
    from symkin.solutions.system import closure_system
    from symkin.symbolic.loci import closure_polynomials

    for f in (closure_system, closure_polynomials):
        with pytest.raises(ModelError, match=r"joints \(H1\).*not polynomial"):
            f(mech)


@pytest.mark.parametrize("change,message", [
    ({"pitch": None}, "needs 'pitch'"),
    ({"pitch": "fast"}, "pitch must be a finite number"),
    ({"pitch": float("inf")}, "pitch must be a finite number"),
])
def test_bad_pitch_is_a_model_error(change, message):
    data = _data("screw_jack")
    j = _joint(data, "H1")
    for k, v in change.items():
        if v is None:
            del j[k]
        else:
            j[k] = v
    with pytest.raises(ModelError, match=rf"joints\[1\] \(H1\).*{message}"):
        symkin.Mechanism.from_dict(data)


def test_pitch_on_another_joint_and_h_in_the_plane_are_model_errors():
    data = _data("screw_jack")
    _joint(data, "R1")["pitch"] = 0.1
    with pytest.raises(ModelError, match=r"R1.*'pitch' goes with a helical joint H"):
        symkin.Mechanism.from_dict(data)
    planar = {"name": "h", "dim": 2, "links": {"a": []},
              "joints": [{"id": "H1", "type": "H", "links": ["ground", "a"], "at": [0, 0], "pitch": 0.1}]}
    with pytest.raises(ModelError, match=r"H1.*not allowed in a planar model"):
        symkin.Mechanism.from_dict(planar)


@pytest.mark.parametrize("command", [["singularities"], ["modes", "--at", "joint:R1=10"]])
def test_cli_refuses_the_global_solve_naming_the_joint(command):
    """``modes`` and ``singularities`` need polynomial equations: exit 2, the joint named, no traceback."""
    import os
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-m", "symkin", *command, str(MODELS / "screw_jack.toml")],
                         capture_output=True, text=True, timeout=300, env=dict(os.environ))
    assert run.returncode == 2
    assert "joints (H1)" in run.stderr and "not polynomial" in run.stderr
    assert "Traceback" not in run.stderr
