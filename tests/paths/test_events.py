"""Event refinement: the point of higher rank loss on a family of singular configurations."""
from __future__ import annotations

import math

import numpy as np

from symkin.model import catalogue
from symkin.curves.locate import locate_singular_point
from symkin.paths.system import make_curve


def circle_intersection(c0, r0, c1, r1, side):
    d = math.dist(c0, c1)
    along = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(r0 * r0 - along * along)
    e = (np.asarray(c1) - c0) / d
    return np.asarray(c0) + along * e + side * h * np.array([-e[1], e[0]])


def test_the_locator_finds_the_flattened_peaucellier_pose_from_a_nearby_a_equals_b_pose():
    m = catalogue.get("peaucellier")
    curve = make_curve(m)
    x = m.coordinates()
    arm, side, crank = math.dist(x["O"], x["A"]), math.dist(x["A"], x["C"]), math.dist(x["Q"], x["C"])
    # on the A = B family (every pose IM, L = 2) with the crank 0.2° from the flattened pose: O-A-C not folded
    oc = arm - side
    phi = math.atan2(x["Q"][1], x["Q"][0]) + math.acos(oc / (2 * crank))
    exact_c = np.array([oc * math.cos(phi), oc * math.sin(phi)])
    turn = math.atan2(*(exact_c - x["Q"])[::-1]) - math.radians(0.2)
    c = np.asarray(x["Q"]) + crank * np.array([math.cos(turn), math.sin(turn)])
    a = circle_intersection((0.0, 0.0), arm, c, side, -1.0)
    p = a + (a - c) @ np.array([[math.cos(0.1), math.sin(0.1)], [-math.sin(0.1), math.cos(0.1)]])  # P off the line
    pose = {"O": x["O"], "Q": x["Q"], "C": c, "A": a, "B": a, "P": p}
    y = curve.y_of(np.array([pose[n] for n in m.node_names], float).ravel()[curve.free])
    assert np.linalg.norm(curve.residual(y)) < 1e-12
    s = np.linalg.svd(curve.jacobian(y), compute_uv=False)
    assert s[-1] < 1e-12 < 1e-3 < s[-2]  # one rank loss here
    point = locate_singular_point(curve, y, 2, max_deflations=0)
    found, converged = point.y, point.converged
    assert converged and np.linalg.norm(curve.residual(found)) < 1e-12
    s = np.linalg.svd(curve.jacobian(found), compute_uv=False)
    assert s[-2] < 1e-12  # two rank losses: the flattened pose
    xf = curve.x_of(found)
    idx = m.node_index()
    u = np.array([math.cos(phi), math.sin(phi)])
    np.testing.assert_allclose(xf[idx["C"]], exact_c, atol=1e-12)
    np.testing.assert_allclose(xf[idx["A"]], arm * u, atol=1e-12)
    np.testing.assert_allclose(xf[idx["B"]], arm * u, atol=1e-12)
    np.testing.assert_allclose(xf[idx["P"]], (arm + side) * u, atol=1e-12)
