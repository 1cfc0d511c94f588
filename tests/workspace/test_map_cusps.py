"""Cusps of the singular curves in a map (issue 8: "isolated singular points ... a cusp").

Truth, independent of symkin's analysis: the 3-RPR of ``models/rpr_3.toml`` (base pivots A_k,
platform joints C_k = O + R(φ) c_k) has leg lengths ρ_k = |C_k − A_k| and the 3 × 3 Jacobian
J = ∂ρ/∂(x, y, φ), row k = [u_k, (R'(φ) c_k) · u_k] with u_k the unit leg vector, written here
from the geometry.  Its singular poses (det J = 0) at fixed ρ3 form a 1-D set; in (ρ1, ρ2) the
set has a cusp where d(ρ1, ρ2)/dt = 0 along it.  There d(ρ1, ρ2, ρ3)/dt = J t = 0, so the
tangent is the null vector n of J: the cusps are the solutions of det J = 0, ∇det J · n = 0.
With ρ3 fixed the pose is C3 = A3 + ρ3 (cos α, sin α) and φ (a torus), on which both
functions are sampled; cells where both change sign seed Newton (scipy), derivatives by
complex step (exact to rounding).  Only numpy and scipy are used for the truth.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import fsolve

import symkin
from symkin.model import catalogue

MODELS = Path(__file__).resolve().parent / "models"
A = np.array([[0.0, 0.0], [6.0, 0.0], [2.0, 5.0]])
C_LOCAL = np.array([[-1.0, -0.5], [1.25, -0.25], [0.0, 1.0]])
RHO3 = float(np.hypot(0.5, 2.0))  # |A3 C3| in the model: the held slide:s3
BOX = ((1.5, 5.5), (2.0, 5.0))


# ----------------------------------------------------------------------------- independent truth
def _joints(p):
    """C_k and dC_k/dφ of poses ``p = (x, y, φ)`` (arrays ``(..., 3)``, real or complex)."""
    x, y, f = p[..., 0], p[..., 1], p[..., 2]
    c, s = np.cos(f)[..., None], np.sin(f)[..., None]
    cx, cy = C_LOCAL[:, 0], C_LOCAL[:, 1]
    C = np.stack([x[..., None] + c * cx - s * cy, y[..., None] + s * cx + c * cy], axis=-1)
    dC = np.stack([-s * cx - c * cy, c * cx - s * cy], axis=-1)
    return C, dC


def leg_lengths(p):
    d = _joints(p)[0] - A
    return np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2)


def jacobian(p):
    C, dC = _joints(p)
    u = (C - A) / leg_lengths(p)[..., None]
    return np.concatenate([u, (dC * u).sum(-1)[..., None]], axis=-1)


def _grad_det(p, h=1e-20):
    p = np.asarray(p, float)
    return np.stack([np.linalg.det(jacobian(p + 1j * h * e)).imag / h for e in np.eye(3)], axis=-1)


def cusp_functions(p):
    """``(det J, ∇det J · n)``, n = J₁ × J₂ (a null vector of J where det J = 0)."""
    J = jacobian(p)
    n = np.cross(J[..., 0, :], J[..., 1, :])
    return np.linalg.det(J), (_grad_det(p) * n).sum(-1)


def pose(alpha, phi, rho3=RHO3):
    alpha, phi = np.asarray(alpha, float), np.asarray(phi, float)
    c3 = A[2] + rho3 * np.stack([np.cos(alpha), np.sin(alpha)], axis=-1)
    o = c3 - np.stack([np.cos(phi) * C_LOCAL[2, 0] - np.sin(phi) * C_LOCAL[2, 1],
                       np.sin(phi) * C_LOCAL[2, 0] + np.cos(phi) * C_LOCAL[2, 1]], axis=-1)
    return np.concatenate([o, phi[..., None]], axis=-1)


def independent_cusps(n=240):
    """Poses of the cusps at ρ3 = RHO3 (all of them, on the (α, φ) torus)."""
    g = np.linspace(-np.pi, np.pi, n, endpoint=False)
    al, ph = np.meshgrid(g, g, indexing="ij")
    D, H = cusp_functions(pose(al, ph))
    found = []
    for i, j in np.argwhere(np.ones((n, n), bool)):
        cell = ([i, (i + 1) % n, i, (i + 1) % n], [j, j, (j + 1) % n, (j + 1) % n])
        if np.ptp(np.sign(D[cell])) == 2 and np.ptp(np.sign(H[cell])) == 2:
            v = fsolve(lambda v: np.array(cusp_functions(pose(v[0], v[1]))), [g[i], g[j]], xtol=1e-13)
            p = pose(v[0], v[1])
            d, h = cusp_functions(p)
            if abs(d) < 1e-12 and abs(h) < 1e-10 and not any(np.linalg.norm(p - q) < 1e-6 for q in found):
                found.append(p)
    return found


def _mechanism_at(mech, p):
    """The model at pose ``p`` (D_k the midpoint of A_k C_k, as in the model file)."""
    C, _ = _joints(np.asarray(p, float))
    coords = {"A1": A[0], "A2": A[1], "A3": A[2], "O": p[:2]}
    for k in range(3):
        coords[f"C{k + 1}"], coords[f"D{k + 1}"] = C[k], 0.5 * (A[k] + C[k])
    return mech.with_coordinates([[float(v) for v in coords[name]] for name in mech.node_names])


# ----------------------------------------------------------------------------- tests
@pytest.fixture(scope="module")
def truth():
    cusps = independent_cusps()
    assert len(cusps) >= 2  # a cuspidal manipulator (the torus holds several; the check of the truth itself)
    for p in cusps:  # the truth's own consistency: a singular pose on the held leg length
        assert abs(np.linalg.det(jacobian(p))) < 1e-12 and abs(leg_lengths(p)[2] - RHO3) < 1e-12
    return cusps


@pytest.mark.slow
@pytest.mark.parametrize("scale", [1.0, 1000.0], ids=["m", "mm"])
def test_rpr_joint_space_cusps_match_the_geometry(truth, scale):
    model = symkin.read_model(MODELS / "rpr_3.toml")
    (x0, x1), (y0, y1) = BOX
    m = symkin.workspace_map(model.moved(scale=scale), x=f"slide:s1={x0 * scale}:{x1 * scale}",
                             y=f"slide:s2={y0 * scale}:{y1 * scale}", n=31, hold=["slide:s3"])
    cusps = [(np.array(p.at) / scale, p.types) for p in m.points if p.kind == "cusp"]  # in the file's units
    inside = [(p, leg_lengths(p)[:2]) for p in truth
              if x0 <= leg_lengths(p)[0] <= x1 and y0 <= leg_lengths(p)[1] <= y1]
    assert inside, "the box holds no independent cusp: the test would prove nothing"
    for at, types in cusps:  # every reported cusp is one of the geometry's, to 1e-8 relative
        err = min(np.linalg.norm(at - r) / np.linalg.norm(r) for _, r in inside)
        assert err < 1e-8, (at, err)
        assert types == ("DKP-input",)
    for p, r in inside:  # every cusp of the geometry in the box is reported
        assert any(np.linalg.norm(at - r) / np.linalg.norm(r) < 1e-8 for at, _ in cusps), r
        # the core at the independent pose: type 2 (DKP-input, leg lines concurrent), not IM, DOF 3
        a = symkin.analyze(_mechanism_at(model, p))
        assert a.dof == 3 and "DKP-input" in a.types and "IM" not in a.types, (a.dof, a.types)
    # a cusp does not split the traced curve: a traced DKP-input curve passes it (within two cells, the
    # tracer's largest step) and ends farther away
    cell = (x1 - x0) / 30
    for at, _ in cusps:
        assert any(cv.kind == "DKP-input" and
                   np.min(np.linalg.norm(np.asarray(cv.points) / scale - at, axis=1)) < 2 * cell and
                   min(np.linalg.norm(np.asarray(cv.points)[[0, -1]] / scale - at, axis=1)) > 2 * cell
                   for cv in m.curves)
    assert m.to_dict()["counts"]["0"].get("cusp", 0) == len(cusps)


def test_five_bar_workspace_map_has_no_cusp():
    m = symkin.workspace_map(catalogue.get("five_bar"), x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=15)
    assert m.curves  # curves were traced (so a cusp could have been found on them)
    assert [p for p in m.points if p.kind == "cusp"] == []
