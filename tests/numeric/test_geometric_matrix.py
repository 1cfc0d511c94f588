"""The geometric matrix against the paper's printed formulas (A3, A4, A5, A6) and rigidity facts."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin import Mechanism, geometric_matrix, motion_space
from symkin.numeric.geometric_matrix import constraint_rows, parameter_rows


def a3(theta: float) -> np.ndarray:
    """Eq. (A3) exactly as printed: cos/sin of the bar's angle."""
    c, s = math.cos(theta), math.sin(theta)
    g = np.array([[c * c, c * s], [c * s, s * s]])
    return np.block([[g, -g], [-g, g]])


def angle(p, q) -> float:
    return math.atan2(q[1] - p[1], q[0] - p[0])


def test_a3_each_bar_of_the_appendix_fourbar(fourbar):
    xyz = fourbar.coordinates()
    rows = constraint_rows(fourbar)
    idx = fourbar.node_index()
    for (name, (i, j)), row in zip(fourbar.links, rows.matrix):
        cols = [2 * idx[i], 2 * idx[i] + 1, 2 * idx[j], 2 * idx[j] + 1]
        ge = np.outer(row, row)[np.ix_(cols, cols)]
        np.testing.assert_allclose(ge, a3(angle(xyz[i], xyz[j])), atol=1e-15, err_msg=name)


def paper_order(fourbar) -> list[int]:
    """Column permutation to the paper's node numbering: 1 = B, 2 = C, 3 = D, 4 = A."""
    idx = fourbar.node_index()
    return [2 * idx[n] + k for n in ("B", "C", "D", "A") for k in (0, 1)]


def a5(theta, phi, psi):
    """Eq. (A5) with the rocker (bar 2-3) at angle ψ; as printed it reads φ there (see papers_examples)."""
    def blk(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[c * c, c * s], [c * s, s * s]])
    t, f, p = blk(theta), blk(phi), blk(psi)
    z = np.zeros((2, 2))
    return np.block([[t + f, -t, z, -f], [-t, t + p, -p, z], [z, -p, p, z], [-f, z, z, f]])


def test_a5_assembled_matrix_in_paper_numbering(fourbar):
    xyz = fourbar.coordinates()
    theta, phi, psi = angle(xyz["B"], xyz["C"]), angle(xyz["A"], xyz["B"]), angle(xyz["D"], xyz["C"])
    order = paper_order(fourbar)
    g = geometric_matrix(fourbar)[np.ix_(order, order)]
    np.testing.assert_allclose(g, a5(theta, phi, psi), atol=1e-15)
    # as printed (φ on bar 2-3) it only holds when the rocker is parallel to the crank
    assert np.abs(g - a5(theta, phi, phi)).max() > 0.1


def test_a6_boundary_form(fourbar):
    xyz = fourbar.coordinates()
    theta, phi, psi = angle(xyz["B"], xyz["C"]), angle(xyz["A"], xyz["B"]), angle(xyz["D"], xyz["C"])
    order = paper_order(fourbar)
    g = geometric_matrix(fourbar, boundary=True)[np.ix_(order, order)]
    expected = a5(theta, phi, psi)
    expected[4:, :] = 0.0
    expected[:, 4:] = 0.0
    expected[4:, 4:] = np.eye(4)
    np.testing.assert_allclose(g, expected, atol=1e-15)


def test_a4_spatial_rod_and_length_independence():
    p1, p2 = np.array([0.3, -1.2, 0.7]), np.array([2.0, 0.5, -0.4])
    m = Mechanism.from_dict({"dim": 3, "nodes": {"P": list(p1), "Q": list(p2)}, "links": {"rod": ["P", "Q"]}})
    d = p2 - p1
    g = np.outer(d, d) / (d @ d)
    expected = np.block([[g, -g], [-g, g]])  # eq. (A4)
    np.testing.assert_allclose(geometric_matrix(m), expected, atol=1e-15)
    longer = m.with_coordinates({"Q": tuple(p1 + 7.5 * d)})
    np.testing.assert_allclose(geometric_matrix(longer), expected, atol=1e-14)


def free_dof(data) -> int:
    return motion_space(Mechanism.from_dict(data)).dof


@pytest.mark.parametrize("nodes, dim, expected", [
    ({"A": [0, 0], "B": [1, 0], "C": [0, 1]}, 2, 3),                   # triangle
    ({"A": [0, 0], "B": [1, 0], "C": [0, 1], "D": [1, 1]}, 2, 3),       # quaternary plate
    ({"A": [0, 0], "B": [1, 0], "C": [3, 0]}, 2, 3),                   # collinear ternary lever
    ({"A": [0, 0, 0], "B": [1, 0, 0], "C": [0, 1, 0]}, 3, 6),           # triangle in space
    ({"A": [0, 0, 0], "B": [1, 0, 0], "C": [0, 1, 0], "D": [1, 1, 0]}, 3, 6),   # coplanar plate
    ({"A": [0, 0, 0], "B": [1, 0, 0], "C": [0, 1, 0], "D": [0, 0, 1]}, 3, 6),   # tetrahedron
    ({"A": [0, 0, 0], "B": [1, 1, 1], "C": [3, 3, 3]}, 3, 5),           # collinear rod: spin invisible
])
def test_free_rigid_body_has_rigid_body_dof(nodes, dim, expected):
    """A free rigid body of any shape moves as a rigid body: 3 DOF planar, 6 spatial (5 for a rod)."""
    assert free_dof({"dim": dim, "nodes": nodes, "links": {"body": list(nodes)}}) == expected


def test_collinear_lever_moves_rigidly():
    """A ternary lever with collinear pins, pivoted at A: 1 DOF, middle pin at the lever ratio."""
    m = Mechanism.from_dict({"dim": 2, "fixed": ["A"], "nodes": {"A": [0, 0], "M": [1, 0], "B": [3, 0]},
                             "links": {"lever": ["A", "M", "B"]}})
    ms = motion_space(m)
    assert ms.dof == 1
    v = ms.V[:, 0]
    np.testing.assert_allclose(v[2:4] * 3, v[4:6], atol=1e-14)  # v_M = v_B / 3
    assert abs(v[2]) < 1e-14 and abs(v[4]) < 1e-14              # perpendicular to the lever


def test_spatial_body_rotation_rows_recover_omega():
    """Rows of a spatial body's angular velocity give ω exactly for any rigid velocity field."""
    rng = np.random.default_rng(3)
    nodes = {f"N{k}": list(rng.normal(size=3)) for k in range(4)}
    m = Mechanism.from_dict({"dim": 3, "nodes": nodes, "links": {"body": list(nodes)},
                             "inputs": [{"rotation": "body", "axis": [0.0, 0.0, 1.0]}]})
    omega, vel = rng.normal(size=3), rng.normal(size=3)
    x = np.array([nodes[n] for n in nodes])
    xdot = (vel + np.cross(omega, x)).ravel()
    from symkin.numeric.geometric_matrix import rotation_rows
    np.testing.assert_allclose(rotation_rows(m, "body") @ xdot, omega, atol=1e-12)
    np.testing.assert_allclose(parameter_rows(m, m.inputs[0]) @ xdot, [omega[2]], atol=1e-12)


def test_rod_rotation_is_the_normal_angular_velocity():
    m = Mechanism.from_dict({"dim": 3, "nodes": {"P": [0, 0, 0], "Q": [2, 0, 0]}, "links": {"rod": ["P", "Q"]}})
    from symkin.numeric.geometric_matrix import rotation_rows
    omega = np.array([0.3, -1.1, 0.4])  # the spin 0.3 about the rod's axis moves no node
    x = np.array([[0, 0, 0], [2, 0, 0]], float)
    xdot = np.cross(omega, x).ravel()
    np.testing.assert_allclose(rotation_rows(m, "rod") @ xdot, [0.0, -1.1, 0.4], atol=1e-14)


@pytest.mark.parametrize("k", [3, 4, 6])
def test_spatial_rotation_rows_both_ways_recover_omega(k, monkeypatch):
    """The normal-equation rows of a well-conditioned link give ω of any rigid velocity field and equal
    the pseudo-inverse rows (the fast path switched off) to 1e-12; nearly collinear links keep the latter."""
    from symkin.numeric import geometric_matrix as gm

    rng = np.random.default_rng(k)
    for trial in range(60):
        base = rng.normal(size=3)
        if trial % 3 == 0:  # nearly collinear: the SVD path must decide
            pts = base + np.outer(rng.uniform(-1, 1, k), rng.normal(size=3)) + 1e-6 * rng.normal(size=(k, 3))
        else:
            pts = base + rng.normal(size=(k, 3)) * 10.0 ** rng.uniform(-3, 3)
        nodes = {f"N{j}": list(p) for j, p in enumerate(pts)}
        m = Mechanism.from_dict({"dim": 3, "nodes": nodes, "links": {"body": list(nodes)}})
        omega, vel = rng.normal(size=3), rng.normal(size=3)
        xdot = (vel + np.cross(omega, pts)).ravel()
        fast_rows = gm.rotation_rows(m, "body")
        with monkeypatch.context() as mp:
            mp.setattr(gm, "_WELL_CONDITIONED", np.inf)  # always the pseudo-inverse
            svd_rows = gm.rotation_rows(m, "body")
        scale = np.abs(svd_rows).max()
        np.testing.assert_allclose(fast_rows, svd_rows, rtol=0, atol=1e-12 * scale)
        r = (pts[1:] - pts[0]).tolist()
        if trial % 3 == 0:
            assert gm._spatial_rotation_blocks(r) is None  # (and the rows are those of before)
        else:
            assert gm._spatial_rotation_blocks(r) is not None
            np.testing.assert_allclose(fast_rows @ xdot, omega, rtol=1e-9, atol=1e-9 * np.abs(omega).max())
