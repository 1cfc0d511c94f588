"""Independent truth for the singularity maps: closed forms in plain NumPy, no symkin analysis inside.

Each function gives a quantity whose zero set is a singular locus of a mechanism at a slice of its
workspace, or samples points on such a locus, from elementary geometry alone (circle intersections,
line coordinates, Plücker lines).  The map engine (``symkin.workspace_map``) and the refined curves
(``symkin.workspace.loci``) are checked against them in ``test_map_truth.py``; each function is
checked on its own, with points built to be on or off its locus, in ``test_truth.py``.

Mechanisms (geometries read from the catalogue's plain model data or given explicitly):

- five-bar (2RR; catalogue ``five_bar``): type-1 circles ``|P − A_i| = l1 ± l2``; type-2 where
  B1, P, B2 are collinear, per working mode (elbow signs); the aligned case with equal distal links
  (P the midpoint of B1B2 with |B1B2| = 2 l2: a Watt's curve) and the folded case (coincident
  elbows, B1 = B2: circles of radius l2 about the intersections of the crank circles);
  reachability.
- 3-RPR at constant orientation: the type-2 locus (three leg lines concurrent) is a conic
  (Sefrioui & Gosselin, Mech. Mach. Theory 30(4), 1995); its six coefficients.
- 3-RRR at constant orientation (catalogue ``rrr_3``): type-2 where the three distal lines are
  concurrent (3×3 determinant of line coordinates), per working mode; type-1 circles.
- Gough–Stewart platform at constant orientation and height: type-2 where the 6×6 matrix of the
  legs' Plücker lines is singular.

Conventions: points are arrays of shape (..., 2) (planar) and broadcast; an elbow sign is
``sign((B − A) × (P − B))`` (the z component of the planar cross product); residuals are
dimensionless (lengths divided by the mechanism's link lengths) and NaN where a leg does not
reach.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import product

import numpy as np

# ----------------------------------------------------------------------------------- planar basics


def cross2(u, v) -> np.ndarray:
    """z component of the planar cross product, broadcast over leading axes."""
    u, v = np.asarray(u, float), np.asarray(v, float)
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def rot2(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def elbow(a, p, l1: float, l2: float, sign) -> np.ndarray:
    """Elbow B of a dyad A-B-P (|AB| = l1, |BP| = l2) with ``sign((B − A) × (P − B)) = sign``.

    Vectorised over ``p`` (..., 2) (and ``a``, ``sign``); NaN where |P − A| is outside
    [|l1 − l2|, l1 + l2].  On the boundary (stretched or folded dyad) both signs give the same B.
    """
    a, p = np.asarray(a, float), np.asarray(p, float)
    d = p - a
    r = np.hypot(d[..., 0], d[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        along = (l1 * l1 - l2 * l2 + r * r) / (2 * r)
        h2 = l1 * l1 - along * along
        # a point on the stretched / folded circle up to rounding (1e-12 relative) is on it
        h2 = np.where((h2 < 0) & (h2 > -1e-12 * l1 * l1), 0.0, h2)
        h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        u = d / r[..., None]
    n = np.stack([-u[..., 1], u[..., 0]], axis=-1)
    # B = A + along u + t h n (n the left normal of u) gives (B − A) × (P − B) = −t h r: t = −sign
    s = np.sign(np.asarray(sign, float))
    return a + along[..., None] * u - (s * h)[..., None] * n


# ----------------------------------------------------------------------------------- five-bar


@dataclass(frozen=True)
class FiveBar:
    """A five-bar (2RR): fixed pivots A_i, crank lengths l1[i] (A_i B_i), distal lengths l2[i] (B_i P)."""

    a: np.ndarray          # (2, 2)
    l1: tuple[float, float]
    l2: tuple[float, float]

    @classmethod
    def from_data(cls, data: dict) -> "FiveBar":
        """From a model dictionary with nodes A1, A2, B1, B2, P (e.g. ``catalogue.data("five_bar")``)."""
        n = {k: np.asarray(v, float) for k, v in data["nodes"].items()}
        return cls(np.array([n["A1"], n["A2"]]),
                   tuple(float(np.linalg.norm(n[f"B{i}"] - n[f"A{i}"])) for i in (1, 2)),
                   tuple(float(np.linalg.norm(n["P"] - n[f"B{i}"])) for i in (1, 2)))

    def scaled(self, s: float) -> "FiveBar":
        return FiveBar(self.a * s, tuple(v * s for v in self.l1), tuple(v * s for v in self.l2))

    @property
    def scale(self) -> float:
        return float(np.mean(self.l1 + self.l2))


MODES_5BAR = ((1, 1), (1, -1), (-1, 1), (-1, -1))


def five_bar_mode(fb: FiveBar, nodes: dict) -> tuple[int, int]:
    """Elbow signs of a configuration given by its nodes B1, B2, P (the working mode)."""
    p = np.asarray(nodes["P"], float)
    return tuple(int(np.sign(cross2(np.asarray(nodes[f"B{i + 1}"], float) - fb.a[i],
                                    p - np.asarray(nodes[f"B{i + 1}"], float)))) for i in range(2))


def five_bar_elbows(fb: FiveBar, p, mode) -> tuple[np.ndarray, np.ndarray]:
    """B1, B2 of working mode ``mode`` = (s1, s2) with the end-effector at ``p`` (NaN: unreachable)."""
    return tuple(elbow(fb.a[i], p, fb.l1[i], fb.l2[i], mode[i]) for i in range(2))


def five_bar_type1(fb: FiveBar, p) -> np.ndarray:
    """Type-1 residuals, shape (..., 2, 2): ``(|P − A_i| − (l1 ± l2)) / (l1 + l2)``, [leg, (+, −)].

    Zero on the circles where leg i is stretched (+) or folded (−): DKP in the output
    (Gosselin–Angeles type 1).  With l1 = l2 the folded "circle" is the point A_i.
    """
    p = np.asarray(p, float)
    out = []
    for i in range(2):
        r = np.linalg.norm(p - fb.a[i], axis=-1)
        tot = fb.l1[i] + fb.l2[i]
        out.append(np.stack([(r - tot) / tot, (r - abs(fb.l1[i] - fb.l2[i])) / tot], axis=-1))
    return np.stack(out, axis=-2)


def five_bar_reachable(fb: FiveBar, p) -> np.ndarray:
    """Both legs reach P: |l1 − l2| ≤ |P − A_i| ≤ l1 + l2 (every working mode assembles there)."""
    p = np.asarray(p, float)
    ok = np.ones(p.shape[:-1], bool)
    for i in range(2):
        r = np.linalg.norm(p - fb.a[i], axis=-1)
        ok &= (r >= abs(fb.l1[i] - fb.l2[i])) & (r <= fb.l1[i] + fb.l2[i])
    return ok


def five_bar_type2(fb: FiveBar, p, mode) -> np.ndarray:
    """Type-2 residual of working mode ``mode``: ``(P − B1) × (P − B2) / (l2₁ l2₂)``.

    The sine of the angle between the distal links: zero where B1, P, B2 are collinear (DKP in
    the input, Gosselin–Angeles type 2), signed, NaN where the mode does not assemble.
    """
    p = np.asarray(p, float)
    b1, b2 = five_bar_elbows(fb, p, mode)
    return cross2(p - b1, p - b2) / (fb.l2[0] * fb.l2[1])


def _circle_circle(c1, r1, c2, r2):
    """The two intersections of circles (c1, r1), (c2, r2), vectorised over c1; NaN when none."""
    c1, c2 = np.asarray(c1, float), np.asarray(c2, float)
    d = c2 - c1
    r = np.linalg.norm(d, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        along = (r1 * r1 - r2 * r2 + r * r) / (2 * r)
        h2 = r1 * r1 - along * along
        h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        u = d / r[..., None]
    n = np.stack([-u[..., 1], u[..., 0]], axis=-1)
    m = c1 + along[..., None] * u
    return m + h[..., None] * n, m - h[..., None] * n


def five_bar_type2_samples(fb: FiveBar, n: int = 721, aligned: bool = True):
    """Points on the type-2 locus, with the working mode each belongs to.

    Crank 1 at n angles θ; B2 on its crank circle at |B1B2| = l2₁ + l2₂ (``aligned``: P between
    B1 and B2 on the segment, P = B1 + l2₁ (B2 − B1)/|B2 − B1|) or |l2₁ − l2₂| (folded: the distal
    links on each other).  With equal distal links the aligned points are midpoints of B1B2 (a
    Watt's curve) and the folded case is the coincident-elbow circles (see
    :func:`five_bar_coincident_elbow_circles`), not sampled here.  Returns ``(P, modes)``:
    arrays (m, 2) and (m, 2) of elbow signs; points where a leg is stretched or folded (sign 0)
    are dropped.
    """
    theta = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    b1 = fb.a[0] + fb.l1[0] * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    dist = fb.l2[0] + fb.l2[1] if aligned else abs(fb.l2[0] - fb.l2[1])
    if dist == 0.0:
        raise ValueError("equal distal links fold onto each other only with coincident elbows: "
                         "use five_bar_coincident_elbow_circles")
    pts, modes = [], []
    for b2 in _circle_circle(b1, dist, fb.a[1], fb.l1[1]):
        u = (b2 - b1) / dist
        # aligned: P between the elbows; folded: P beyond both on their line, |P − B_i| = l2_i
        p = b1 + fb.l2[0] * u if aligned or fb.l2[0] > fb.l2[1] else b1 - fb.l2[0] * u
        s = np.stack([np.sign(cross2(b1 - fb.a[0], p - b1)), np.sign(cross2(b2 - fb.a[1], p - b2))], axis=-1)
        keep = np.all(np.isfinite(p), axis=-1) & np.all(s != 0, axis=-1)
        pts.append(p[keep])
        modes.append(s[keep].astype(int))
    return np.concatenate(pts), np.concatenate(modes)


def five_bar_coincident_elbow_circles(fb: FiveBar) -> list[tuple[np.ndarray, float]]:
    """With equal distal links: the circles (centre, radius l2) of P when the elbows coincide.

    B1 = B2 = B is an intersection of the two crank circles; the two distal links then lie on
    each other and P turns about B: a type-2 configuration for every P on the circle.
    """
    if not np.isclose(fb.l2[0], fb.l2[1], rtol=1e-15, atol=0.0):
        return []
    b, b_ = _circle_circle(fb.a[0], fb.l1[0], fb.a[1], fb.l1[1])
    return [(c, fb.l2[0]) for c in (b, b_) if np.all(np.isfinite(c))]


def watt_curve_residual(fb: FiveBar, p) -> np.ndarray:
    """Implicit Watt's curve of the midpoint of B1B2 (|B1B2| = 2 l2, equal distal links), any mode.

    ``min`` over the four elbow choices of ``(|B1B2| − 2 l2)/(2 l2)`` with B_i on circle(A_i, l1)
    and on circle(P, l2): zero exactly where some mode is aligned with P the midpoint.
    """
    p = np.asarray(p, float)
    vals = []
    for mode in MODES_5BAR:
        b1, b2 = five_bar_elbows(fb, p, mode)
        vals.append((np.linalg.norm(b2 - b1, axis=-1) - 2 * fb.l2[0]) / (2 * fb.l2[0]))
    return np.nanmin(np.abs(np.stack(vals)), axis=0)


# ----------------------------------------------------------------------------------- 3-RPR


def rpr_line_matrix(a, c_local, phi: float, p) -> np.ndarray:
    """Rows (d_x, d_y, A × d) of the leg lines A_i → C_i, C_i = p + R(φ) c_i; shape (..., 3, 3)."""
    a = np.asarray(a, float)
    c = np.asarray(p, float)[..., None, :] + np.asarray(c_local, float) @ rot2(phi).T
    d = c - a
    return np.concatenate([d, cross2(a, d)[..., None]], axis=-1)


def rpr_type2_det(a, c_local, phi: float, p) -> np.ndarray:
    """det of :func:`rpr_line_matrix`: zero where the three leg lines are concurrent (or parallel)."""
    return np.linalg.det(rpr_line_matrix(a, c_local, phi, p))


def rpr_conic(a, c_local, phi: float) -> np.ndarray:
    """Coefficients (c_xx, c_xy, c_yy, c_x, c_y, c_0) of the 3-RPR type-2 conic at orientation φ.

    Row i of the line matrix is affine in p = (x, y): r_i = r_i⁰ + x e_i + y f_i with
    r_i⁰ = (b_x, b_y, A_i × C_i⁰) (b = C_i⁰ − A_i, C_i⁰ = R(φ) c_i), e_i = (1, 0, −A_iy),
    f_i = (0, 1, A_ix).  The determinant is multilinear in the rows, so each monomial's coefficient
    is a sum of determinants of rows picked from {r⁰, e, f}; the cubic terms cancel because e and f
    have the same first two entries in every row (Sefrioui & Gosselin 1995: the locus is a conic).
    Returns the coefficients of det(p) = c_xx x² + c_xy xy + c_yy y² + c_x x + c_y y + c_0.
    The conic also passes through the three points p = A_i − C_i⁰ where leg i has zero length
    (a zero row), which are not configurations; and it splits into two lines when a side of the
    platform is parallel to the corresponding side of the base (e.g. legs 1 and 2 on one line).
    """
    a = np.asarray(a, float)
    c0 = np.asarray(c_local, float) @ rot2(phi).T
    b = c0 - a
    rows = {"0": np.column_stack([b, cross2(a, c0)]),
            "x": np.column_stack([np.ones(3), np.zeros(3), -a[:, 1]]),
            "y": np.column_stack([np.zeros(3), np.ones(3), a[:, 0]])}
    coef = {}
    for pick in product("0xy", repeat=3):
        mono = "".join(sorted(k for k in pick if k != "0"))
        coef[mono] = coef.get(mono, 0.0) + np.linalg.det(np.array([rows[k][i] for i, k in enumerate(pick)]))
    for cubic in ("xxx", "xxy", "xyy", "yyy"):
        if abs(coef.get(cubic, 0.0)) > 1e-9 * max(abs(v) for v in coef.values()):
            raise AssertionError(f"cubic term {cubic} does not cancel: {coef[cubic]}")
    return np.array([coef.get(k, 0.0) for k in ("xx", "xy", "yy", "x", "y", "")])


def conic_value(coef, p) -> np.ndarray:
    p = np.asarray(p, float)
    x, y = p[..., 0], p[..., 1]
    cxx, cxy, cyy, cx, cy, c0 = coef
    return cxx * x * x + cxy * x * y + cyy * y * y + cx * x + cy * y + c0


def conic_points(coef, xs) -> np.ndarray:
    """Real points of the conic on the vertical lines x ∈ xs (both roots in y), shape (m, 2)."""
    cxx, cxy, cyy, cx, cy, c0 = coef
    out = []
    for x in np.asarray(xs, float):
        qa, qb, qc = cyy, cxy * x + cy, cxx * x * x + cx * x + c0
        if abs(qa) < 1e-14 * max(abs(qb), abs(qc), 1.0):
            if qb != 0:
                out.append((x, -qc / qb))
            continue
        disc = qb * qb - 4 * qa * qc
        if disc >= 0:
            s = np.sqrt(disc)
            out += [(x, (-qb + s) / (2 * qa)), (x, (-qb - s) / (2 * qa))]
    return np.array(out).reshape(-1, 2)


def lines_concurrency(points_a, points_c) -> float:
    """Distance of the third line from the intersection of the other two, over the mean leg length.

    Lines through points_a[i] and points_c[i]; the two least parallel lines are intersected.  An
    independent test of concurrency (0 when the three lines meet in one point; inf when all are
    parallel).
    """
    a, c = np.asarray(points_a, float), np.asarray(points_c, float)
    d = c - a
    u = d / np.linalg.norm(d, axis=-1)[:, None]
    i, j, k = max(((0, 1, 2), (0, 2, 1), (1, 2, 0)), key=lambda t: abs(cross2(u[t[0]], u[t[1]])))
    den = cross2(d[i], d[j])
    if den == 0:
        return np.inf
    t = cross2(a[j] - a[i], d[j]) / den
    q = a[i] + t * d[i]
    dist = abs(cross2(u[k], q - a[k]))
    return float(dist / np.mean(np.linalg.norm(d, axis=-1)))


# ----------------------------------------------------------------------------------- 3-RRR


@dataclass(frozen=True)
class RRR3:
    """A 3-RRR: base pivots a (3, 2), platform joints c_local (3, 2) about the platform reference
    point at orientation 0, crank lengths l1 (3,), distal lengths l2 (3,)."""

    a: np.ndarray
    c_local: np.ndarray
    l1: np.ndarray
    l2: np.ndarray

    @classmethod
    def from_data(cls, data: dict, reference=(0.0, 0.0), phi: float = 0.0) -> "RRR3":
        """From a model dictionary with nodes A_k, B_k, C_k (e.g. ``catalogue.data("rrr_3")``).

        ``reference`` and ``phi``: the platform reference point and orientation of the model's
        configuration, so that ``c_local`` is the platform at orientation 0.
        """
        n = {k: np.asarray(v, float) for k, v in data["nodes"].items()}
        a = np.array([n[f"A{k}"] for k in (1, 2, 3)])
        c = np.array([n[f"C{k}"] for k in (1, 2, 3)])
        b = np.array([n[f"B{k}"] for k in (1, 2, 3)])
        c_local = (c - np.asarray(reference, float)) @ rot2(-phi).T
        return cls(a, c_local, np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1))

    def platform(self, p, phi: float) -> np.ndarray:
        """Platform joints C_i (..., 3, 2) at reference point p and orientation φ."""
        return np.asarray(p, float)[..., None, :] + self.c_local @ rot2(phi).T


MODES_3RRR = tuple(product((1, -1), repeat=3))


def rrr_mode(r: RRR3, nodes: dict) -> tuple[int, int, int]:
    """Elbow signs sign((B_k − A_k) × (C_k − B_k)) of a configuration (the working mode)."""
    return tuple(int(np.sign(cross2(np.asarray(nodes[f"B{k + 1}"]) - r.a[k],
                                    np.asarray(nodes[f"C{k + 1}"]) - np.asarray(nodes[f"B{k + 1}"]))))
                 for k in range(3))


def rrr_elbows(r: RRR3, p, phi: float, mode) -> np.ndarray:
    """Elbows B_k (..., 3, 2) of working mode ``mode`` (NaN where leg k does not reach)."""
    c = r.platform(p, phi)
    return np.stack([elbow(r.a[k], c[..., k, :], r.l1[k], r.l2[k], mode[k]) for k in range(3)], axis=-2)


def rrr_type2(r: RRR3, p, phi: float, mode) -> np.ndarray:
    """det of the unit line coordinates (d_x, d_y, C × d)/|d| of the distal lines, over the
    platform's circumradius for the moment column: zero where they are concurrent (type 2)."""
    c = r.platform(p, phi)
    b = rrr_elbows(r, p, phi, mode)
    d = (c - b) / r.l2[:, None]
    rho = float(np.mean(np.linalg.norm(r.c_local, axis=1)))
    m = np.concatenate([d, (cross2(c, d) / rho)[..., None]], axis=-1)
    with np.errstate(invalid="ignore"):
        return np.linalg.det(m)


def rrr_type1(r: RRR3, p, phi: float) -> np.ndarray:
    """Type-1 residuals (..., 3, 2): (|C_k − A_k| − (l1 ± l2))/(l1 + l2), leg k stretched (+) / folded (−)."""
    c = r.platform(p, phi)
    dist = np.linalg.norm(c - r.a, axis=-1)
    tot = r.l1 + r.l2
    return np.stack([(dist - tot) / tot, (dist - np.abs(r.l1 - r.l2)) / tot], axis=-1)


def rrr_reachable(r: RRR3, p, phi: float) -> np.ndarray:
    """Every leg reaches its platform joint (then all eight working modes assemble)."""
    res = rrr_type1(r, p, phi)
    return np.all((res[..., 0] <= 0) & (res[..., 1] >= 0), axis=-1)


# ----------------------------------------------------------------------------------- Gough–Stewart


def rot3(rx: float, ry: float, rz: float) -> np.ndarray:
    """R = Rz(rz) Ry(ry) Rx(rx)."""
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    rxm = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    rym = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rzm = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rzm @ rym @ rxm


def gough_platform(c_local, rotation, position) -> np.ndarray:
    """Platform joints C_i = position + R c_i; position (..., 3), result (..., 6, 3)."""
    return np.asarray(position, float)[..., None, :] + np.asarray(c_local, float) @ np.asarray(rotation).T


def gough_plucker(a, c) -> np.ndarray:
    """Unit Plücker lines of the legs A_i → C_i: rows (u, A × u / s), s the mean base radius."""
    a, c = np.asarray(a, float), np.asarray(c, float)
    u = (c - a) / np.linalg.norm(c - a, axis=-1)[..., None]
    s = float(np.mean(np.linalg.norm(a, axis=-1)))
    return np.concatenate([u, np.cross(a, u) / s], axis=-1)


def gough_type2_det(a, c_local, rotation, z: float, xy) -> np.ndarray:
    """det of the 6×6 leg Plücker matrix at platform position (x, y, z), orientation ``rotation``.

    Zero where the six leg lines are linearly dependent (a wrench-singular pose: type 2).
    """
    xy = np.asarray(xy, float)
    pos = np.concatenate([xy, np.full(xy.shape[:-1] + (1,), float(z))], axis=-1)
    return np.linalg.det(gough_plucker(a, gough_platform(c_local, rotation, pos)))


def gough_leg_lengths(a, c_local, pose) -> np.ndarray:
    """Leg lengths at pose (x, y, z, rx, ry, rz): an independent inverse kinematics."""
    pose = np.asarray(pose, float)
    c = gough_platform(c_local, rot3(*pose[3:]), pose[:3])
    return np.linalg.norm(c - np.asarray(a, float), axis=-1)


def gough_jacobian_sigma(a, c_local, pose, h: float = 1e-6) -> float:
    """Smallest over largest singular value of d(leg lengths)/d(pose) by central differences.

    Independent of :func:`gough_plucker`: zero (to the differencing error) at type-2 poses.
    """
    cols = []
    for k in range(6):
        e = np.zeros(6)
        e[k] = h
        cols.append((gough_leg_lengths(a, c_local, pose + e) - gough_leg_lengths(a, c_local, pose - e)) / (2 * h))
    s = np.linalg.svd(np.column_stack(cols), compute_uv=False)
    return float(s[-1] / s[0])


def hexagon(radius: float, half_angle: float, offset: float = 0.0, z: float = 0.0) -> np.ndarray:
    """Six joints of a semi-regular hexagon: pairs at 120° k ± half_angle (+ offset), at height z."""
    ang = np.array([2 * np.pi * k / 3 + s * half_angle + offset for k in range(3) for s in (-1, 1)])
    return np.column_stack([radius * np.cos(ang), radius * np.sin(ang), np.full(6, z)])


def bisect_root(f, lo: float, hi: float, tol: float = 1e-14) -> float:
    """A root of scalar ``f`` in [lo, hi] with f(lo) f(hi) < 0, by bisection (no derivatives)."""
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if fm == 0 or hi - lo < tol * max(1.0, abs(mid)):
            return mid
        if np.sign(fm) == np.sign(flo):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ----------------------------------------------------------------------------------- Delta (3-R(SS)²)


@dataclass(frozen=True)
class Delta:
    """A Delta robot: three legs at angles φ_i = 0°, 120°, 240° about the vertical z.

    Leg i: an arm turning about the horizontal axis through A_i = R u_i along t_i (u_i = (cos φ_i,
    sin φ_i, 0), t_i = (−sin φ_i, cos φ_i, 0)), elbow B_i = A_i + la (cos θ_i u_i − sin θ_i e_z); a
    parallelogram of two bars of length lb from B_i ∓ (w/2) t_i to C_i ∓ (w/2) t_i, C_i = P + r u_i on
    the platform, which therefore only translates (P its reference point).
    """

    radius: float = 1.0     # R: base
    arm: float = 1.0        # la
    bar: float = 2.0        # lb
    platform: float = 0.3   # r
    width: float = 0.4      # w: parallelogram width

    def frames(self):
        phi = np.radians([0.0, 120.0, 240.0])
        u = np.stack([np.cos(phi), np.sin(phi), np.zeros(3)], -1)
        t = np.stack([-np.sin(phi), np.cos(phi), np.zeros(3)], -1)
        return u, t

    def angles(self, p, knee: int = 1) -> np.ndarray:
        """Arm angles θ_i (3,) with the platform at ``p`` (closed form), NaN where a leg does not reach.

        ``|P + r u_i − B_i(θ)| = lb`` is ``q_u cos θ − q_z sin θ = K`` with ``Q = P − (R − r) u_i`` and
        ``K = (|Q|² + la² − lb²) / (2 la)``, i.e. ``ρ cos(θ + α) = K``, ``α = atan2(q_z, q_u)``; ``knee``
        (±1, or one per leg) picks the root.
        """
        u, _ = self.frames()
        p = np.asarray(p, float)
        out = []
        for i in range(3):
            q = p - (self.radius - self.platform) * u[i]
            qu, qz = q @ u[i], q[2]
            k = (q @ q + self.arm ** 2 - self.bar ** 2) / (2 * self.arm)
            c = k / np.hypot(qu, qz)
            sign = knee[i] if np.ndim(knee) else knee
            out.append(np.nan if abs(c) > 1 else -np.arctan2(qz, qu) + sign * np.arccos(c))
        return np.array(out)

    def reach_margin(self, p) -> float:
        """``min_i (1 − |K_i/ρ_i|)`` (see :meth:`angles`): positive where every leg reaches ``p``."""
        u, _ = self.frames()
        p = np.asarray(p, float)
        out = []
        for i in range(3):
            q = p - (self.radius - self.platform) * u[i]
            k = (q @ q + self.arm ** 2 - self.bar ** 2) / (2 * self.arm)
            out.append(1.0 - abs(k / np.hypot(q @ u[i], q[2])))
        return float(min(out))

    def elbows(self, theta) -> np.ndarray:
        u, _ = self.frames()
        ez = np.array([0.0, 0.0, 1.0])
        return np.array([self.radius * u[i] + self.arm * (np.cos(theta[i]) * u[i] - np.sin(theta[i]) * ez)
                         for i in range(3)])

    def bar_directions(self, p, knee: int = 1) -> np.ndarray:
        """Unit vectors (3, 3) along the legs' bars, B_i → C_i."""
        u, _ = self.frames()
        b = self.elbows(self.angles(p, knee))
        d = np.asarray(p, float) + self.platform * u - b
        return d / np.linalg.norm(d, axis=1)[:, None]

    def type2_det(self, p, knee: int = 1) -> float:
        """det of the forward Jacobian of the leg constraints ``|C_i − B_i|² = lb²`` in P with the arms
        locked (rows: the bar directions): zero where the three bars are parallel to one plane (type 2)."""
        return float(np.linalg.det(self.bar_directions(p, knee)))

    def rotation_det(self, p, knee: int = 1) -> float:
        """det of the three moments ``t_i × d_i`` that the parallelograms exert on the platform: zero where
        the locked platform can turn (a constraint singularity, not a type-2 translation)."""
        _, t = self.frames()
        return float(np.linalg.det(np.cross(t, self.bar_directions(p, knee))))

    def nodes(self, p, knee: int = 1) -> dict:
        """Node positions of the model at platform position ``p`` (see :meth:`model`)."""
        u, t = self.frames()
        p = np.asarray(p, float)
        b = self.elbows(self.angles(p, knee))
        h = 0.5 * self.width
        out = {"P": p}
        for i in range(3):
            k = i + 1
            out[f"A{k}"] = self.radius * u[i]
            out[f"A{k}b"] = self.radius * u[i] + t[i]
            out[f"B{k}a"], out[f"B{k}b"] = b[i] - h * t[i], b[i] + h * t[i]
            c = p + self.platform * u[i]
            out[f"C{k}a"], out[f"C{k}b"] = c - h * t[i], c + h * t[i]
        return out

    def model(self, p, knee: int = 1, scale: float = 1.0) -> dict:
        """A symkin model dictionary: arms [A_i, A_i b, B_i a, B_i b] turning about A_i A_i b (the inputs),
        bars [B_i a, C_i a], [B_i b, C_i b], platform [C.., P]; the output is the velocity of P."""
        nodes = self.nodes(p, knee)
        links = {}
        for k in (1, 2, 3):
            links[f"arm{k}"] = [f"A{k}", f"A{k}b", f"B{k}a", f"B{k}b"]
            links[f"bar{k}a"] = [f"B{k}a", f"C{k}a"]
            links[f"bar{k}b"] = [f"B{k}b", f"C{k}b"]
        links["platform"] = [f"C{k}{s}" for k in (1, 2, 3) for s in "ab"] + ["P"]
        return {"name": "Delta 3-R(SS)2", "dim": 3, "fixed": [f"A{k}{s}" for k in (1, 2, 3) for s in ("", "b")],
                "mobility": 3,
                "inputs": [{"rotation": f"arm{k}", "axis": [f"A{k}", f"A{k}b"]} for k in (1, 2, 3)],
                "outputs": [{"velocity": "P"}],
                "nodes": {n: [float(v) * scale for v in x] for n, x in nodes.items()}, "links": links}
