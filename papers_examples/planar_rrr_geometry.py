"""Elementary planar geometry shared by the 3-RRR checks (Figs. 1a, 1b, 2).

Independent of symkin's classifier: these functions recompute, from the coordinates alone,
what the checks compare symkin's results with (the DKP relation coefficients of eq. 5 from
the equilibrium of the distal-link force lines, and the centre of an uncontrolled rotation).
"""
from __future__ import annotations

import numpy as np

LEGS = (1, 2, 3)


def cross(u, v) -> float:
    """z component of the planar cross product."""
    return float(u[0] * v[1] - u[1] * v[0])


def perp(v) -> np.ndarray:
    return np.array([-v[1], v[0]], dtype=float)


def hand_gamma(xyz: dict) -> tuple[np.ndarray, float]:
    """Coefficients γ_i = w_i (a_i × d_i) of eq. (5), independently of symkin.

    ``w`` spans the null space of the 3×3 matrix whose column i is the force line of
    distal link i acting on the platform, ``(d_x, d_y, C_i × d_i)``; γ is scaled so that
    its first non-zero entry is 1.  Also returns the smallest singular value of that
    matrix (zero when such a self-equilibrated set of forces exists).
    """
    cols, arms = [], []
    for k in LEGS:
        a_, b_, c_ = (np.array(xyz[f"{n}{k}"], dtype=float) for n in "ABC")
        d = c_ - b_
        cols.append([d[0], d[1], cross(c_, d)])
        arms.append(cross(b_ - a_, d))
    _, s, vt = np.linalg.svd(np.array(cols).T)
    gamma = vt[-1] * np.array(arms)
    pivot = next(g for g in gamma if abs(g) > 1e-12 * np.abs(gamma).max())
    return gamma / pivot, float(s[-1] / s[0])


def rotation_about(motion, xyz: dict, centre, movers) -> tuple[float, float, float]:
    """Fit ``v = Ω (X − centre)⊥`` to the velocities of ``movers``.

    Returns Ω, the relative residual of the fit, and the largest speed of the other free
    nodes (zero when only ``movers`` move).
    """
    vel = {n: np.array(v) for n, v in motion.velocities}
    basis = np.concatenate([perp(np.subtract(xyz[n], centre)) for n in movers])
    v = np.concatenate([vel[n] for n in movers])
    omega = float(basis @ v / (basis @ basis))
    resid = float(np.linalg.norm(v - omega * basis) / np.linalg.norm(v))
    others = max((float(np.linalg.norm(w)) for n, w in vel.items() if n not in movers), default=0.0)
    return omega, resid, others
