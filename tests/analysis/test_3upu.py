"""Tsai's 3-UPU translational manipulator in joint form: its constraint singularity (issue 16).

Each leg: a U at the base (first axis ``s1`` fixed in the base, tangent to the base circle;
second axis ``s2`` normal to ``s1`` and to the leg), a P along the leg, a U at the platform
whose first axis (in the rod) is parallel to ``s2`` and whose last axis (in the platform) is
parallel to ``s1`` — Tsai's arrangement: the two intermediate axes parallel, the first parallel
to the last.  Such a leg transmits to the platform one constraint couple, normal to both U
axes: along ``s1 × s2``, i.e. the leg direction's component normal to ``s1``.  Three
independent couples leave the platform its three translations; where they become linearly
dependent the platform gains a rotation (Zlatanov, Bonev & Gosselin, ICRA 2002; Wolf &
Shoham).

Derived here by elementary geometry: base joints ``a r_k``, platform joints ``p + b r_k``
(platform parallel to the base, ``r_k`` the unit radial directions at 0°, 120°, 240°), so the
couple of leg ``k`` is ``c_k = α_k r_k + p_z ẑ`` with ``α_k = p·r_k + b − a``, and
``det[c_1 c_2 c_3] = p_z sin 120° (α_1α_2 + α_2α_3 + α_3α_1) = p_z sin 120° (3(b − a)² − ¾|p_xy|²)``:
the constraint singularities at constant (parallel) orientation are the vertical cylinder
``|p_xy| = 2|a − b|``.  The test computes the couples from the joints' own axes too.
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from symkin.kinds import Kind
from symkin.numeric import geometric_matrix as gm

A_RADIUS, B_RADIUS, HEIGHT = 1.0, 0.6, 0.7
RADIAL = [np.array([np.cos(t), np.sin(t), 0.0]) for t in np.radians([0.0, 120.0, 240.0])]
Z = np.array([0.0, 0.0, 1.0])


def _unit(v):
    return np.asarray(v, float) / np.linalg.norm(v)


def upu_3(p, scale: float = 1.0) -> dict:
    """The 3-UPU by its joints with the platform centre at ``p`` (platform parallel to the base)."""
    p = np.asarray(p, float)
    joints = []
    for k, r in enumerate(RADIAL, start=1):
        a, b = A_RADIUS * r, p + B_RADIUS * r
        d = _unit(b - a)
        s1 = np.cross(Z, r)                          # tangent to the base circle, in the base plane
        s2 = _unit(np.cross(d, s1))                  # normal to s1 and to the leg
        joints += [{"id": f"UA{k}", "type": "U", "links": ["ground", f"cyl{k}"], "at": list(scale * a),
                    "axis": list(s1), "axis2": list(s2)},
                   {"id": f"P{k}", "type": "P", "links": [f"cyl{k}", f"rod{k}"], "at": list(scale * a), "axis": list(d)},
                   {"id": f"UB{k}", "type": "U", "links": [f"rod{k}", "platform"], "at": list(scale * b),
                    "axis": list(s2), "axis2": list(s1)}]
    links = {name: [] for k in (1, 2, 3) for name in (f"cyl{k}", f"rod{k}")}
    links["platform"] = []
    return {"name": "3-UPU (Tsai) by its joints", "dim": 3, "mobility": 3, "platform": "platform",
            "platform_dof": 3, "inputs": [{"joint": f"P{k}"} for k in (1, 2, 3)],
            "outputs": [{"twist": "platform"}], "links": links, "joints": joints}


def couples(m: symkin.Mechanism) -> np.ndarray:
    """The legs' constraint couples ``s1 × s2`` from the base U joints' own axes (rows)."""
    return np.array([np.cross(j.axis, j.axis2) for j in m.joints if j.id.startswith("UA")])


def closed_form_det(p) -> float:
    """``det[c_1 c_2 c_3]`` of the module docstring (couples ``α_k r_k + p_z ẑ``)."""
    alpha = [float(np.dot(p, r)) + B_RADIUS - A_RADIUS for r in RADIAL]
    return p[2] * np.sin(np.radians(120.0)) * (alpha[0] * alpha[1] + alpha[1] * alpha[2] + alpha[2] * alpha[0])


def _singular_point(phi_deg: float = 35.0) -> np.ndarray:
    rho = 2.0 * abs(A_RADIUS - B_RADIUS)
    phi = np.radians(phi_deg)
    return np.array([rho * np.cos(phi), rho * np.sin(phi), HEIGHT])


def _platform_motions(m: symkin.Mechanism, analysis) -> tuple[np.ndarray, np.ndarray]:
    """Platform twists (v of its first node, ω) of every motion, and of the motions with the slides locked."""
    v = analysis.motion.V
    p_in = gm.parameters_matrix(m, m.inputs)[0] @ v
    twist = gm.parameters_matrix(m, m.outputs)[0] @ v
    _, s, vt = np.linalg.svd(p_in)
    locked = vt[int(np.sum(s > 1e-9 * s[0])):].T                  # motions leaving the three slides still
    return twist, twist @ locked


def test_the_closed_form_is_the_determinant_of_the_joints_couples():
    for p in (_singular_point(), _singular_point(200.0), np.array([0.1, -0.2, 0.5])):
        m = symkin.Mechanism.from_dict(upu_3(p))
        c = couples(m)
        unit = np.array([_unit(v) for v in c])
        # the couple is the leg direction's part normal to s1: (α_k r_k + p_z ẑ) up to a positive factor
        for k, r in enumerate(RADIAL):
            expect = _unit((np.dot(p, r) + B_RADIUS - A_RADIUS) * r + p[2] * Z)
            assert unit[k] == pytest.approx(expect, abs=1e-12)
        norms = [np.linalg.norm((np.dot(p, r) + B_RADIUS - A_RADIUS) * r + p[2] * Z) for r in RADIAL]
        assert np.linalg.det(unit.T) * np.prod(norms) == pytest.approx(closed_form_det(p), abs=1e-12)
    assert abs(closed_form_det(_singular_point())) < 1e-15
    assert abs(closed_form_det(np.array([0.1, -0.2, 0.5]))) > 0.1


@pytest.mark.parametrize("scale", [1.0, 1000.0], ids=["m", "mm"])
def test_regular_configuration_translates_only(scale):
    m = symkin.Mechanism.from_dict(upu_3(np.array([0.1, -0.2, HEIGHT]), scale))
    a = symkin.analyze(m)
    assert a.dof == 3 and a.platform_dof == 3 and Kind.CONSTRAINT not in a.types and a.types == ()
    twist, locked = _platform_motions(m, a)
    assert np.max(np.abs(twist[3:])) < 1e-12 * np.max(np.abs(twist[:3])) * scale   # ω = 0: translations only
    assert np.linalg.matrix_rank(twist[:3], tol=1e-9 * np.max(np.abs(twist))) == 3
    assert locked.shape[1] == 0                                                     # slides locked: rigid


@pytest.mark.parametrize("scale", [1.0, 1000.0], ids=["m", "mm"])
def test_constraint_singularity_gains_a_rotation(scale):
    p = _singular_point()
    m = symkin.Mechanism.from_dict(upu_3(p, scale))
    c = couples(m)
    a = symkin.analyze(m)
    assert Kind.CONSTRAINT in a.types
    assert a.dof == 4 and a.platform_dof == 4 and a.platform_dof_generic == 3
    assert Kind.IM in a.types                                   # one motion more than the mobility
    twist, locked = _platform_motions(m, a)
    # the slides locked, the platform still turns: about the normal of the dependent couples
    assert locked.shape[1] == 1 and len(a.uncontrolled_motions) == 1
    assert set(a.types) == {Kind.IM, Kind.CONSTRAINT}          # the gained motion is the rotation
    omega = locked[3:, 0]
    normal = np.linalg.svd(c)[2][-1]                            # the direction normal to all three couples
    assert np.linalg.norm(omega) > 0.1 / scale
    assert abs(np.dot(_unit(omega), normal)) == pytest.approx(1.0, abs=1e-9)
    # a rotation gained, not a translation: every motion's ω lies along that normal
    assert np.linalg.matrix_rank(twist[3:], tol=1e-9 * np.max(np.abs(twist[3:]))) == 1
    # nearby, off the cylinder, the platform is back to its three translations
    off = symkin.analyze(symkin.Mechanism.from_dict(upu_3(p * np.array([1.1, 1.1, 1.0]), scale)))
    assert off.dof == 3 and Kind.CONSTRAINT not in off.types
