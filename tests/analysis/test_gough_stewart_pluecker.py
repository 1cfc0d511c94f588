"""A 6-UPS written with U, P and S joints: its type-2 locus at constant orientation is the Plücker locus (issue 16).

The platform translates in (x, y) at a fixed height and a fixed, general orientation.  At every
pose the joint form's nodes are placed here by elementary inverse kinematics (each U turns the
cylinder onto the leg, the rod slides along it, the platform translates), and symkin's
indicator of the type-2 (direct-kinematics) singularity — DKP with the six slides locked — is
read from :func:`symkin.analyze`.  Truth, written independently: the 6×6 determinant of the
legs' Plücker lines, rows ``(d_k, c_k × d_k)`` (unit leg direction, platform joint × it).  The
geometry is irregular (no hexagonal symmetry) and the check runs in metres and millimetres.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import symkin
from symkin.kinds import Kind
from symkin.numeric import geometric_matrix as gm
from tests.model import joint_forms as jf

pytestmark = pytest.mark.slow


def _rot(axis, angle: float) -> np.ndarray:
    """Rodrigues: the rotation by ``angle`` about the unit ``axis``."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def _geometry():
    """Base joints A_k and platform joints c_k (platform frame): irregular hexagons, not coplanar."""
    rng = np.random.default_rng(7)
    ang_a = np.radians([-23, 17, 95, 148, 212, 266])
    ang_c = np.radians([-55, 41, 73, 166, 197, 285])
    a = np.array([[2.0 * (1 + 0.08 * rng.standard_normal()) * np.cos(t),
                   2.0 * (1 + 0.08 * rng.standard_normal()) * np.sin(t), 0.1 * rng.standard_normal()] for t in ang_a])
    c = np.array([[1.0 * (1 + 0.08 * rng.standard_normal()) * np.cos(t),
                   1.0 * (1 + 0.08 * rng.standard_normal()) * np.sin(t), 0.05 * rng.standard_normal()] for t in ang_c])
    return a, c


A, C_LOCAL = _geometry()
ROT = _rot([0, 0, 1], np.radians(65)) @ _rot([1, 0, 0], np.radians(25)) @ _rot([0, 1, 0], np.radians(7))
Z = 1.6
START = np.array([0.0, -0.8])        # the model's (x, y): a regular pose
LINES = (-0.8, 0.0, 0.8)             # x of the lines along y crossed by the locus
Y_RANGE = (-1.2, 1.2)


def pluecker_det(xy, scale: float = 1.0) -> float:
    """det of the six legs' Plücker lines (unit direction, platform joint × direction), lengths / scale."""
    o = np.array([xy[0], xy[1], Z * scale]) / scale
    c = o + C_LOCAL @ ROT.T
    d = c - A
    d /= np.linalg.norm(d, axis=1)[:, None]
    return float(np.linalg.det(np.hstack([d, np.cross(c, d)])))


def _model(scale: float) -> symkin.Mechanism:
    o = np.array([*START, Z]) * scale
    nodes = {f"A{k + 1}": list(scale * A[k]) for k in range(6)}
    nodes |= {f"C{k + 1}": list(o + scale * ROT @ C_LOCAL[k]) for k in range(6)}
    nodes["O"] = list(o)
    data = jf.ups_6(nodes)
    data["name"] = "irregular 6-UPS by its joints"
    return symkin.Mechanism.from_dict(data)


def _pose(m: symkin.Mechanism, xy, scale: float) -> symkin.Mechanism:
    """``m`` with its platform translated to (x, y, z): the joints' nodes by inverse kinematics."""
    x0 = {n: np.array(p) for n, p in m.nodes}
    shift = np.array([xy[0], xy[1], Z * scale]) - x0["O"]
    joints = {j.id: j for j in m.joints}
    links = dict(m.links)
    new = dict(x0)
    for k in range(1, 7):
        u = joints[f"U{k}"]
        a, e1, e2 = np.array(u.at), np.array(u.axis), np.array(u.axis2)
        d0 = np.cross(e1, e2)                        # the leg's direction at the model (normal to both axes)
        c0 = x0[f"S{k}"]
        assert np.allclose(d0, (c0 - a) / np.linalg.norm(c0 - a))
        c = c0 + shift
        d = (c - a) / np.linalg.norm(c - a)
        alpha = np.arctan2(-d @ e2, d @ d0)          # the cross about axis 1, then the cylinder about axis 2
        beta = np.arcsin(np.clip(d @ e1, -1.0, 1.0))
        turn = _rot(e1, alpha) @ _rot(e2, beta)
        assert np.allclose(turn @ d0, d)
        slide = np.linalg.norm(c - a) - np.linalg.norm(c0 - a)
        for n in links[f"U{k}.cross"] + links[f"cyl{k}"]:
            if n not in m.fixed:
                new[n] = a + turn @ (x0[n] - a)
        for n in links[f"rod{k}"]:
            new[n] = a + turn @ (x0[n] - a) + slide * d
    for n in links["platform"]:
        new[n] = x0[n] + shift
    for k in range(1, 7):
        assert np.allclose(new[f"S{k}"], x0[f"S{k}"] + shift)
    return m.with_coordinates({n: list(v) for n, v in new.items()})


def _indicator(m, scale, x, y) -> float:
    """symkin's type-2 indicator, free of the motion basis: ``det(P V) / det(T V)``.

    ``V`` is the motion space of :func:`symkin.analyze`, ``P`` the six slides' rows (the
    inputs), ``T`` the platform's twist rows (the output): the determinant of the slides'
    rates as functions of the platform's twist, zero where the locked slides leave the
    platform a motion (DKP-input, type 2).
    """
    mk = _pose(m, (x, y), scale)
    v = symkin.analyze(mk).motion.V
    p = gm.parameters_matrix(mk, mk.inputs)[0]
    t = gm.parameters_matrix(mk, mk.outputs)[0]
    return float(np.linalg.det(p @ v) / np.linalg.det(t @ v))


@pytest.mark.parametrize("scale", [1.0, 1000.0], ids=["m", "mm"])
def test_type2_locus_is_the_pluecker_determinants_zero_set(scale):
    m = _model(scale)
    start = symkin.analyze(m)
    assert start.dof == 6 and start.types == ()
    assert abs(pluecker_det(START * scale, scale)) > 0.02
    ys = np.linspace(*Y_RANGE, 7) * scale
    located = 0
    for x in LINES if scale == 1.0 else LINES[1:2]:
        x = x * scale
        sym = np.array([_indicator(m, scale, x, y) for y in ys])
        det = np.array([pluecker_det((x, y), scale) for y in ys])
        # the same function: the twist's moment rows carry 1/length, so a factor scale³
        assert sym / scale ** 3 == pytest.approx(det, rel=1e-9, abs=1e-12)
        assert (det > 0).any() and (det < 0).any()                 # the line crosses the locus
        big = np.max(np.abs(det))
        for k in np.nonzero(sym[:-1] * sym[1:] < 0)[0]:
            y_sym = brentq(lambda y, x=x: _indicator(m, scale, x, y), ys[k], ys[k + 1], xtol=1e-10 * scale)
            y_true = brentq(lambda y, x=x: pluecker_det((x, y), scale), ys[k], ys[k + 1], xtol=1e-12 * scale)
            assert abs(pluecker_det((x, y_sym), scale)) < 1e-8 * big, (x, y_sym)
            assert y_sym == pytest.approx(y_true, abs=1e-8 * scale)
            at = symkin.analyze(_pose(m, (x, y_sym), scale))
            assert Kind.DKP_INPUT in at.types and at.dof == 6     # the locked slides leave the platform a motion
            assert at.input_rank == 5
            located += 1
        # and between the roots, symkin says regular
        for y in ys[[0, -1]]:
            assert Kind.DKP_INPUT not in symkin.analyze(_pose(m, (x, y), scale)).types
    assert located >= (3 if scale == 1.0 else 1)
