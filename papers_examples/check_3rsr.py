"""§V, Figs. 10-13: a spatial 3-RSR platform moved from a DKP position to an IM configuration.

The paper analyses a 3-DOF 3-RSR platform (inputs: the three revolute pairs to ground) at
three positions of one motion (its figures are not in our copy; README_3rsr.md explains the
reconstruction):

* (a) Fig. 11 — the lower links are in LIM (DKP with r = 1 in each input), L = 3, and the
  platform has an uncontrolled motion with vertical nodal velocities and a horizontal
  angular velocity;
* (b) Fig. 12 — the platform at its upper position is in LIM: inputs independent, six
  r = 1 relations in the platform twist, platform DOF 0, L = 3;
* (c) Fig. 13 — IM with L = 4; with the inputs locked the platform rotates about a point A
  with 3 DOF; the platform has DOF 4 (three rotations, one translation): a constraint
  singularity.  Read here as: the three inputs have rank 1 (they must be equal), so locking
  them leaves L − 1 = 3 motions, the rotations about A; the fourth platform DOF is the
  vertical translation that the (equal) inputs drive.

One mechanism (fixed link lengths) is used in all three model files and in two generic
configurations; every configuration is built here from the design dimensions and the model
files are checked against that construction.  Asserted for each position: the
classification and its numbers (symkin), closed-form values (relations, velocity ratios),
and an independent twist-algebra computation of the motion space from the joint screws of
the legs, which must span the same space as symkin's V.  The Fig. 10 statement (the IM
indicator falls to zero on the way to (c)) is checked on samples of the same motion.

Run: ``python papers_examples/check_3rsr.py`` (exit code 0 when every claim holds).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import symkin
from symkin.numeric.geometric_matrix import parameters_matrix, rotation_rows
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
FILES = {"a": "fig11_3rsr_a.toml", "b": "fig12_3rsr_b.toml", "c": "fig13_3rsr_c.toml"}
LEGS = (1, 2, 3)

# ---------------------------------------------------------------- the design (README_3rsr.md)
R_BASE = 4.0       # ground revolute axis k: tangential line at radius R_BASE, height 0
LOWER = 5.0        # distance from the sphere centre S_k to the ground axis
R_PLATFORM = 3.0   # platform revolute axis k: tangential line at radius R_PLATFORM
UPPER = 5.0        # distance from S_k to the platform axis (its foot P_k is the axis midpoint)
HALF_AXIS = 1.0    # the two nodes of every revolute axis are ±HALF_AXIS from its midpoint
SQ3_2 = math.sqrt(3.0) / 2.0
AZIMUTH = ((1.0, 0.0), (-0.5, SQ3_2), (-0.5, -SQ3_2))   # legs at 0°, 120°, 240°
TOL = 1e-12        # zero test for velocities of motions scaled to max |v| = 1 (lengths ~ 5)


def frames() -> list[tuple[np.ndarray, np.ndarray]]:
    """Radial unit u_k and tangential unit τ_k = ẑ × u_k of each leg's vertical half-plane."""
    return [(np.array([c, s, 0.0]), np.array([-s, c, 0.0])) for c, s in AZIMUTH]


def configuration(r_s: float, z_s: float) -> dict[str, list[float]]:
    """Symmetric configuration: every S_k at (radial r_s, height z_s) in its leg's half-plane.

    The platform is horizontal with its axes tangential; its height follows from
    ``|S − P| = UPPER`` on the branch with P above S: ``h = z_s + sqrt(UPPER² − (R_PLATFORM − r_s)²)``.
    """
    h = z_s + math.sqrt(UPPER ** 2 - (R_PLATFORM - r_s) ** 2)
    z = np.array([0.0, 0.0, 1.0])
    nodes: dict[str, np.ndarray] = {}
    for k, (u, t) in zip(LEGS, frames()):
        nodes[f"G{k}1"], nodes[f"G{k}2"] = R_BASE * u - HALF_AXIS * t, R_BASE * u + HALF_AXIS * t
    for k, (u, t) in zip(LEGS, frames()):
        nodes[f"S{k}"] = r_s * u + z_s * z
    for k, (u, t) in zip(LEGS, frames()):
        p = R_PLATFORM * u + h * z
        nodes[f"U{k}1"], nodes[f"U{k}2"] = p - HALF_AXIS * t, p + HALF_AXIS * t
    return {n: [float(v) for v in x] for n, x in nodes.items()}


def sphere_centre(position: str) -> tuple[float, float]:
    """(r, z) of S_k in its half-plane at each position, from the design dimensions."""
    if position == "a":        # upper link flat, outward of the platform axis: r = R_p + b
        r = R_PLATFORM + UPPER
        return r, math.sqrt(LOWER ** 2 - (r - R_BASE) ** 2)
    if position == "b":        # G, S, P collinear: |P − G| = LOWER + UPPER (leg fully stretched)
        reach, d = LOWER + UPPER, R_BASE - R_PLATFORM
        h = math.sqrt(reach ** 2 - d ** 2)
        return R_BASE - d * LOWER / reach, h * LOWER / reach
    if position == "c":        # S on the vertical axis of symmetry: the three centres coincide
        return 0.0, math.sqrt(LOWER ** 2 - R_BASE ** 2)
    if position == "generic":  # lower link at cos α = 3/5, between (a) and (b) on the motion
        return R_BASE + 0.6 * LOWER, 0.8 * LOWER
    raise KeyError(position)


def alpha_of(r_s: float, z_s: float) -> float:
    """Angle of the lower link G→S from the outward radial direction."""
    return math.atan2(z_s, r_s - R_BASE)


def s_of_alpha(alpha: float) -> tuple[float, float]:
    return R_BASE + LOWER * math.cos(alpha), LOWER * math.sin(alpha)


def link_distances(mech: symkin.Mechanism) -> np.ndarray:
    """All distances between node pairs inside links, in a fixed order (the link lengths)."""
    x = mech.coordinates()
    return np.array([math.dist(x[ns[i]], x[ns[j]]) for _, ns in mech.links
                     for i in range(len(ns)) for j in range(i + 1, len(ns))])


def at(mech: symkin.Mechanism, coords: dict, name: str) -> symkin.Mechanism:
    """The model of ``mech`` (same topology, inputs, outputs) at other coordinates, validated."""
    data = mech.to_dict()
    data["nodes"], data["name"] = coords, name
    data.pop("description", None)
    return symkin.Mechanism.from_dict(data)


def asymmetric_configuration(mech_generic: symkin.Mechanism) -> tuple[dict, float]:
    """A configuration of the same mechanism without symmetry (Newton on the platform pose).

    The sphere centres are moved to lower-link angles α_k = α₀ + δ_k; the platform pose
    (rotation vector, translation) is solved so that each S_k is in the plane normal to its
    platform axis through the axis midpoint P_k and at distance UPPER from it.  Returns the
    coordinates and the final residual.
    """
    x0 = {n: np.array(v) for n, v in mech_generic.coordinates().items()}
    alpha0 = alpha_of(*sphere_centre("generic"))
    s_nodes = {}
    for k, (u, _), d in zip(LEGS, frames(), (0.10, -0.06, 0.03)):
        r, z = s_of_alpha(alpha0 + d)
        s_nodes[f"S{k}"] = r * u + np.array([0.0, 0.0, z])
    plat = [f"U{k}{i}" for k in LEGS for i in (1, 2)]
    centre = np.mean([x0[n] for n in plat], axis=0)

    def pose(q):
        th = float(np.linalg.norm(q[:3]))
        kx = np.array([[0, -q[2], q[1]], [q[2], 0, -q[0]], [-q[1], q[0], 0]]) / (th if th else 1.0)
        rot = np.eye(3) + math.sin(th) * kx + (1 - math.cos(th)) * kx @ kx
        return {n: rot @ (x0[n] - centre) + centre + q[3:] for n in plat}

    def residual(q):
        u = pose(q)
        out = []
        for k in LEGS:
            e = u[f"U{k}2"] - u[f"U{k}1"]
            mid = (u[f"U{k}1"] + u[f"U{k}2"]) / 2
            s = s_nodes[f"S{k}"] - mid
            out += [s @ e / np.linalg.norm(e), s @ s - UPPER ** 2]
        return np.array(out)

    q = np.zeros(6)
    for _ in range(30):
        f = residual(q)
        if np.abs(f).max() < 1e-14:
            break
        jac = np.column_stack([(residual(q + 1e-7 * e) - residual(q - 1e-7 * e)) / 2e-7 for e in np.eye(6)])
        q = q - np.linalg.solve(jac, f)
    coords = {n: [float(v) for v in x] for n, x in x0.items()}
    coords.update({n: [float(v) for v in x] for n, x in s_nodes.items()})
    coords.update({n: [float(v) for v in x] for n, x in pose(q).items()})
    return coords, float(np.abs(residual(q)).max())


# ---------------------------------------------------------------- independent twist algebra
def _screw(point, direction) -> np.ndarray:
    """Unit rotation twist about the line through ``point`` along ``direction``: (ω, v_O)."""
    e = np.asarray(direction, float) / np.linalg.norm(direction)
    return np.concatenate([e, np.cross(point, e)])


def screw_motion_space(mech: symkin.Mechanism) -> dict:
    """Motion space from the joint screws of the three R-S-R legs (no symkin matrices).

    Unknowns: the platform twist T = (ω, v_O) and, per leg, the ground rate θ̇_k, the three
    spherical rates and the platform-axis rate φ̇_k.  Loop closure of leg k:
    ``T = θ̇_k $_g + Σ ω_i $_(S,i) + φ̇_k $_ℓ`` (6 equations).  Returns L and, for a basis of
    the null space, the platform twists (6, L), the input rates θ̇ (3, L) and the nodal
    velocities of all nodes in symkin's coordinate order (3n, L).
    """
    x = {n: np.array(v) for n, v in mech.coordinates().items()}
    rows = []
    for k in LEGS:
        block = np.zeros((6, 21))
        block[:, :6] = np.eye(6)
        c0 = 6 + 5 * (k - 1)
        block[:, c0] = -_screw(x[f"G{k}1"], x[f"G{k}2"] - x[f"G{k}1"])
        for i, e in enumerate(np.eye(3)):
            block[:, c0 + 1 + i] = -_screw(x[f"S{k}"], e)
        block[:, c0 + 4] = -_screw(x[f"U{k}1"], x[f"U{k}2"] - x[f"U{k}1"])
        rows.append(block)
    a = np.vstack(rows)
    _, s, vt = np.linalg.svd(a)
    r = int(np.count_nonzero(s > 1e-10 * s[0]))
    null = vt[r:].T                                      # (21, L)
    twist = null[:6]
    theta = null[[6 + 5 * (k - 1) for k in LEGS]]
    names = mech.node_names
    vel = np.zeros((3 * len(names), null.shape[1]))
    for i, n in enumerate(names):
        if n.startswith("S"):
            k = int(n[1])
            g1, g2 = x[f"G{k}1"], x[f"G{k}2"]
            e = (g2 - g1) / np.linalg.norm(g2 - g1)
            vel[3 * i: 3 * i + 3] = np.outer(np.cross(e, x[n] - g1), theta[k - 1])
        elif n.startswith("U"):
            vel[3 * i: 3 * i + 3] = twist[3:] + np.cross(twist[:3].T, x[n]).T
    return {"L": null.shape[1], "twist": twist, "theta": theta, "velocities": vel}


def rank(m: np.ndarray, tol: float = 1e-9) -> int:
    return int(np.count_nonzero(np.linalg.svd(m, compute_uv=False) > tol)) if m.size else 0


def span_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance of a unit vector of span(b) from span(a) (0 when span(b) ⊆ span(a))."""
    qa = np.linalg.svd(a, full_matrices=False)[0][:, : rank(a)]
    qb = np.linalg.svd(b, full_matrices=False)[0][:, : rank(b)]
    return float(np.linalg.norm(qb - qa @ (qa.T @ qb), 2)) if qb.size else 0.0


# ---------------------------------------------------------------- helpers on symkin results
def relations(rels) -> list[dict[str, float]]:
    return [r.as_dict() for r in rels]


def relations_match(measured: list[dict], expected: list[dict], tol: float = 1e-9) -> bool:
    if len(measured) != len(expected):
        return False
    for m, e in zip(measured, expected):
        if set(m) != set(e) or any(abs(m[k] - e[k]) > tol * max(1.0, abs(e[k])) for k in e):
            return False
    return True


def velocities(motion) -> dict[str, np.ndarray]:
    return {n: np.array(v) for n, v in motion.velocities}


def platform_nodes() -> list[str]:
    return [f"U{k}{i}" for k in LEGS for i in (1, 2)]


def full_vector(mech, motion) -> np.ndarray:
    """Motion as a vector over all coordinates (fixed nodes zero)."""
    v = velocities(motion)
    return np.concatenate([v.get(n, np.zeros(3)) for n in mech.node_names])


# ---------------------------------------------------------------- the checks
def check_construction(c: Checklist, mechs: dict) -> None:
    ref = link_distances(mechs["a"])
    for key, mech in mechs.items():
        built = configuration(*sphere_centre(key))
        if key in FILES:
            dev = max(float(np.max(np.abs(np.subtract(mech.coordinates()[n], built[n])))) for n in built)
            c.close(f"({key}) {FILES[key]} holds the constructed configuration (max |Δx|)", dev, 0.0, tol=1e-15)
        if key == "a":
            continue
        c.close(f"({key}) same mechanism as (a): link lengths (max |Δ|)",
                float(np.max(np.abs(link_distances(mech) - ref))), 0.0, tol=1e-14)
    alphas = {k: math.degrees(alpha_of(*sphere_centre(k))) for k in ("a", "generic", "b", "c")}
    c.true("one motion: lower-link angle α grows (a) 36.87° → generic 53.13° → (b) 95.74° → (c) 143.13°",
           alphas["a"] < alphas["generic"] < alphas["b"] < alphas["c"],
           {k: round(v, 2) for k, v in alphas.items()})
    hb = configuration(*sphere_centre("b"))["U11"][2]
    heights = [configuration(*s_of_alpha(a))["U11"][2]
               for a in np.linspace(alpha_of(*sphere_centre("a")), alpha_of(*sphere_centre("c")), 61)]
    c.true("(b) is the upper position: platform height √99 is the maximum along the motion",
           hb >= max(heights) - 1e-12 and math.isclose(hb, math.sqrt(99.0), rel_tol=1e-15), hb)


def check_generic(c: Checklist, label: str, mech: symkin.Mechanism) -> None:
    res = symkin.analyze(mech)
    c.record(label, res)
    c.equal(f"{label}: L = 3 = F", res.dof, 3)
    c.equal(f"{label}: not singular", res.types, ())
    c.equal(f"{label}: input rank 3", res.input_rank, 3)
    c.equal(f"{label}: platform DOF 3", res.platform_dof, 3)
    c.true(f"{label}: IM indicator λ_4 clearly non-zero", res.im_indicator > 1e-4, res.im_indicator)
    sc = screw_motion_space(mech)
    c.equal(f"{label}: twist algebra gives L = 3", sc["L"], 3)
    c.equal(f"{label}: twist algebra: input rank 3, platform DOF 3",
            (rank(sc["theta"]), rank(sc["twist"])), (3, 3))
    c.close(f"{label}: twist-algebra motion space = symkin's V (subspace gap)",
            max(span_gap(res.motion.V, sc["velocities"]), span_gap(sc["velocities"], res.motion.V)), 0.0,
            tol=1e-10)


def check_a(c: Checklist, mech: symkin.Mechanism) -> None:
    xyz = mech.coordinates()
    c.close("(a) construction: the upper links lie in the platform plane (max |z_S − z_U|)",
            max(abs(xyz[f"S{k}"][2] - xyz[n][2]) for k in LEGS for n in (f"U{k}1", f"U{k}2")), 0.0, tol=1e-15)
    res = symkin.analyze(mech)
    c.record("Fig. 11, position (a)", res)
    c.equal("(a) no increment in the DOF: L = 3", res.dof, 3)
    c.equal("(a) classification: LIM of the lower links, with DKP r = 1 in the inputs; no IM",
            res.types, ("DKP-input", "LIM"))
    c.equal("(a) the three lower links are in LIM", res.locked_links, ("lower1", "lower2", "lower3"))
    c.equal("(a) the motion space is zero at the spherical joints (S nodes locked)",
            res.locked_nodes, ("S1", "S2", "S3"))
    c.equal("(a) input rank 0", res.input_rank, 0)
    c.true("(a) DKP equations with r = 1: rotation:lowerk = 0 for k = 1, 2, 3",
           relations_match(relations(res.input_relations),
                           [{f"rotation:lower{k}": 1.0} for k in LEGS])
           and [r.r for r in res.input_relations] == [1, 1, 1], relations(res.input_relations))
    s_rows = [3 * mech.node_index()[f"S{k}"] + i for k in LEGS for i in range(3)]
    c.close("(a) rows of V at the S nodes (max |entry|)", float(np.abs(res.motion.V[s_rows]).max()), 0.0,
            tol=1e-14)
    u_rows = [3 * mech.node_index()[n] + i for n in platform_nodes() for i in range(2)]
    c.close("(a) rows of V at the horizontal components of the platform nodes (max |entry|)",
            float(np.abs(res.motion.V[u_rows]).max()), 0.0, tol=1e-14)
    c.equal("(a) platform DOF 3: an uncontrolled platform motion", res.platform_dof, 3)
    c.true("(a) platform: vx = vy = 0 and ωz = 0 (closed form: velocities vertical, ω horizontal)",
           relations_match(relations(res.platform_relations),
                           [{"twist:platform.vx": 1.0}, {"twist:platform.vy": 1.0}, {"twist:platform.wz": 1.0}]),
           relations(res.platform_relations))
    motions = res.uncontrolled_motions
    c.equal("(a) three uncontrolled motions with the inputs locked, all moving the platform",
            [m.moves_platform for m in motions], [True, True, True])
    w_rows = rotation_rows(mech, "platform")
    horiz, wz = [], []
    for m in motions:
        v = velocities(m)
        horiz.append(max(float(np.abs(v[n][:2]).max()) for n in platform_nodes()))
        w = w_rows @ full_vector(mech, m)
        wz.append(abs(float(w[2])))
    c.close("(a) platform nodal velocities are vertical (max horizontal component)", max(horiz, default=math.inf),
            0.0, tol=TOL)
    c.close("(a) platform angular velocity is horizontal (max |ωz|)", max(wz, default=math.inf), 0.0, tol=TOL)
    c.equal("(a) ... and the motions' ω span the horizontal plane (rank 2)",
            rank(np.array([w_rows @ full_vector(mech, m) for m in motions])), 2)
    sc = screw_motion_space(mech)
    c.equal("(a) twist algebra: L = 3", sc["L"], 3)
    c.close("(a) twist algebra: every input rate vanishes on the motion space (max |θ̇|)",
            float(np.abs(sc["theta"]).max()), 0.0, tol=1e-12)
    c.close("(a) twist algebra: platform ωz = 0 and horizontal velocity of every platform node = 0",
            max(float(np.abs(sc["twist"][2]).max()),
                max(float(np.abs(sc["velocities"][3 * mech.node_index()[n]: 3 * mech.node_index()[n] + 2]).max())
                    for n in platform_nodes())), 0.0, tol=1e-12)
    c.close("(a) twist-algebra motion space = symkin's V (subspace gap)",
            max(span_gap(res.motion.V, sc["velocities"]), span_gap(sc["velocities"], res.motion.V)), 0.0,
            tol=1e-10)


def check_b(c: Checklist, mech: symkin.Mechanism) -> None:
    xyz = {n: np.array(v) for n, v in mech.coordinates().items()}
    off, reach, par = [], [], []
    for k in LEGS:
        g = (xyz[f"G{k}1"] + xyz[f"G{k}2"]) / 2
        p = (xyz[f"U{k}1"] + xyz[f"U{k}2"]) / 2
        off.append(float(np.linalg.norm(np.cross(xyz[f"S{k}"] - g, p - g)) / np.linalg.norm(p - g)))
        reach.append(float(np.linalg.norm(p - g)))
        e1, e2 = xyz[f"G{k}2"] - xyz[f"G{k}1"], xyz[f"U{k}2"] - xyz[f"U{k}1"]
        par.append(float(np.linalg.norm(np.cross(e1, e2)) / (np.linalg.norm(e1) * np.linalg.norm(e2))))
    c.close("(b) construction: legs stretched, S on the line G-P (max distance)", max(off), 0.0, tol=1e-14)
    c.close("(b) construction: |P − G| = a + b = 10 in every leg (max)", max(reach), LOWER + UPPER, tol=1e-15)
    c.close("(b) construction: ground axis ∥ platform axis in every leg (max sin of angle)", max(par), 0.0,
            tol=1e-15)
    res = symkin.analyze(mech)
    c.record("Fig. 12, position (b)", res)
    c.equal("(b) no increment in the DOF: L = 3", res.dof, 3)
    c.equal("(b) classification: platform in LIM, DKP r = 1 in the output", res.types, ("DKP-output", "LIM"))
    c.equal("(b) the inputs show no dependency: input rank 3, no relation",
            (res.input_rank, relations(res.input_relations)), (3, []))
    c.equal("(b) platform DOF 0", res.platform_dof, 0)
    c.equal("(b) locked links: the platform only", res.locked_links, ("platform",))
    c.equal("(b) motion space shows no motion in any platform node", res.locked_nodes, tuple(platform_nodes()))
    u_rows = [3 * mech.node_index()[n] + i for n in platform_nodes() for i in range(3)]
    c.close("(b) rows of V at the platform nodes (max |entry|)", float(np.abs(res.motion.V[u_rows]).max()), 0.0,
            tol=1e-14)
    comps = ("vx", "vy", "vz", "wx", "wy", "wz")
    c.true("(b) output: six relations twist:platform.* = 0, each r = 1",
           relations_match(relations(res.output_relations), [{f"twist:platform.{q}": 1.0} for q in comps])
           and [r.r for r in res.output_relations] == [1] * 6, relations(res.output_relations))
    # closed form: with the platform at rest, S_k turns about both parallel axes through the
    # collinear G, S, P: θ̇ (S − G) = φ̇ (S − P), i.e. ω_upper = −(LOWER/UPPER) ω_lower
    dev = 0.0
    for k in LEGS:
        lo, up = rotation_rows(mech, f"lower{k}") @ res.motion.V, rotation_rows(mech, f"upper{k}") @ res.motion.V
        dev = max(dev, float(np.abs(up + (LOWER / UPPER) * lo).max()))
    c.close("(b) each leg folds about its parallel axes: ω_upper = −(a/b)·ω_lower on every motion (max dev)",
            dev, 0.0, tol=1e-12)
    sc = screw_motion_space(mech)
    c.equal("(b) twist algebra: L = 3, input rank 3", (sc["L"], rank(sc["theta"])), (3, 3))
    c.close("(b) twist algebra: the platform twist vanishes on the motion space (max |T|)",
            float(np.abs(sc["twist"]).max()), 0.0, tol=1e-12)
    c.close("(b) twist-algebra motion space = symkin's V (subspace gap)",
            max(span_gap(res.motion.V, sc["velocities"]), span_gap(sc["velocities"], res.motion.V)), 0.0,
            tol=1e-10)


def lift_ratio(xyz: dict) -> float:
    """Closed form θ̇_k / v_z of the vertical translation at (c), from leg 1's half-plane.

    With S = A fixed on the axis of symmetry of the platform's velocity field, the velocity of A
    is vertical, v ẑ; leg 1 requires θ̇ (ŷ × (S − G)) = v ẑ + φ̇ (ŷ × (S − P)) (2 equations in
    the x-z plane), solved by Cramer's rule.  For this design: 4/25.
    """
    s, g = np.array(xyz["S1"]), np.array(xyz["G11"])
    p = (np.array(xyz["U11"]) + np.array(xyz["U12"])) / 2
    y = np.array([0.0, 1.0, 0.0])
    t, w = np.cross(y, s - g), np.cross(y, s - p)
    m = np.array([[t[0], -w[0]], [t[2], -w[2]]])
    theta, _ = np.linalg.solve(m, np.array([0.0, 1.0]))
    return float(theta)


def check_c(c: Checklist, mech: symkin.Mechanism) -> None:
    xyz = mech.coordinates()
    a_pt = np.array(xyz["S1"])
    c.close("(c) the three sphere centres coincide at A = S1 on the vertical axis (max |S_k − A|, |A_xy|)",
            max(max(math.dist(xyz[f"S{k}"], a_pt) for k in LEGS), float(np.abs(a_pt[:2]).max())), 0.0, tol=1e-15)
    res = symkin.analyze(mech)
    c.record("Fig. 13, position (c)", res)
    c.equal("(c) instantaneous DOF L = 4: IM", res.dof, 4)
    c.equal("(c) classification: IM, inputs of rank 1 (DKP), constraint singularity",
            res.types, ("IM", "DKP-input", "constraint"))
    c.true("(c) IM indicator λ_4 = 0 (below the rank threshold squared)",
           res.im_indicator <= res.threshold ** 2, res.im_indicator)
    c.equal("(c) input rank 1", res.input_rank, 1)
    c.true("(c) input relations: rotation:lower1 = rotation:lower2 = rotation:lower3 (closed form)",
           relations_match(relations(res.input_relations),
                           [{"rotation:lower1": 1.0, "rotation:lower3": -1.0},
                            {"rotation:lower2": 1.0, "rotation:lower3": -1.0}]), relations(res.input_relations))
    c.equal("(c) platform DOF 4 > 3 (generic): constraint singularity",
            (res.platform_dof, res.platform_dof_generic), (4, 3))
    # closed form: twists = rotations about A plus a vertical translation, so the velocity of U11
    # is v = ω × (U11 − A) + s ẑ: two relations on the x and y components.
    d = np.array(xyz["U11"]) - a_pt
    expected = [{"twist:platform.vx": 1.0, "twist:platform.wy": -d[2], "twist:platform.wz": d[1]},
                {"twist:platform.vy": 1.0, "twist:platform.wx": d[2], "twist:platform.wz": -d[0]}]
    c.true("(c) platform relations: v_U11 − ω × (U11 − A) is vertical (closed form, 2 relations)",
           relations_match(relations(res.platform_relations), expected), relations(res.platform_relations))

    motions = res.uncontrolled_motions
    c.equal("(c) inputs locked: L − rank = 3 uncontrolled motions, all moving the platform",
            [m.moves_platform for m in motions], [True, True, True])
    w_rows = rotation_rows(mech, "platform")
    resid, s_speed, omegas = [], [], []
    for m in motions:
        v = velocities(m)
        w = w_rows @ full_vector(mech, m)
        omegas.append(w)
        resid.append(max(float(np.linalg.norm(v[n] - np.cross(w, np.array(xyz[n]) - a_pt)))
                         for n in platform_nodes()))
        s_speed.append(max(float(np.linalg.norm(v[f"S{k}"])) for k in LEGS))
    c.close("(c) each locked-input motion is a rotation about A: max |v_P − ω × (P − A)| over platform nodes",
            max(resid, default=math.inf), 0.0, tol=TOL)
    c.close("(c) ... with the sphere centres at rest (max |v_S|)", max(s_speed, default=math.inf), 0.0, tol=TOL)
    c.equal("(c) ... and their ω span 3 dimensions: a 3-DOF rotation about A", rank(np.array(omegas)), 3)

    # the fourth platform DOF: a vertical translation, driven by equal inputs θ̇ = (4/25) v_z
    ms = res.motion
    p_rows, _ = parameters_matrix(mech, list(mech.inputs) + list(mech.outputs))
    pv = p_rows @ ms.V                                   # rows: θ̇1..3, vx, vy, vz, ωx, ωy, ωz
    null_w = np.linalg.svd(pv[6:9])[2][rank(pv[6:9]):].T   # β with platform ω = 0
    c.equal("(c) motions with platform ω = 0: exactly one (the translation)", null_w.shape[1], 1)
    tr = pv @ null_w[:, 0] if null_w.shape[1] else np.full(pv.shape[0], math.nan)
    tr = tr / tr[5] if abs(tr[5]) > 1e-9 else np.full_like(tr, math.nan)
    c.close("(c) translation is vertical (|vx| + |vy| at U11 per unit vz)", abs(tr[3]) + abs(tr[4]), 0.0, tol=1e-12)
    expect = lift_ratio(xyz)
    c.close("(c) closed form θ̇/v_z = 4/25 for the design", expect, 4 / 25, tol=1e-15)
    for k in LEGS:
        c.close(f"(c) translation drives input {k}: θ̇_{k}/v_z = 4/25", float(tr[k - 1]), expect, tol=1e-12)

    sc = screw_motion_space(mech)
    c.equal("(c) twist algebra: L = 4, input rank 1, platform DOF 4",
            (sc["L"], rank(sc["theta"]), rank(sc["twist"])), (4, 1, 4))
    locked = sc["twist"] @ np.linalg.svd(sc["theta"])[2][rank(sc["theta"]):].T
    v_at_a = locked[3:] + np.cross(locked[:3].T, a_pt).T
    c.close("(c) twist algebra: inputs locked → 3 twists with zero velocity at A (max |v_A|)",
            float(np.abs(v_at_a).max()), 0.0, tol=1e-12)
    c.equal("(c) twist algebra: ... whose ω span 3 dimensions", (locked.shape[1], rank(locked[:3])), (3, 3))
    c.close("(c) twist-algebra motion space = symkin's V (subspace gap)",
            max(span_gap(res.motion.V, sc["velocities"]), span_gap(sc["velocities"], res.motion.V)), 0.0,
            tol=1e-10)


def check_path(c: Checklist, mech: symkin.Mechanism) -> None:
    """Fig. 10: the IM indicator λ_4 along the motion (a) → (c)."""
    a0, a1 = alpha_of(*sphere_centre("a")), alpha_of(*sphere_centre("c"))
    alphas = np.linspace(a0, a1, 17)
    lam, dofs = [], []
    for k, al in enumerate(alphas):
        coords = configuration(*s_of_alpha(al)) if k < len(alphas) - 1 else configuration(*sphere_centre("c"))
        res = symkin.analyze(mech.with_coordinates(coords))
        lam.append(res.im_indicator)
        dofs.append(res.dof)
    c.equal("Fig. 10: L = 3 at 16 samples from (a) up to (c), L = 4 at (c)", dofs, [3] * 16 + [4])
    c.true("Fig. 10: λ_4 > 1e-5 before (c)", min(lam[:-1]) > 1e-5, f"min {min(lam[:-1]):.3e}")
    tail = lam[-6:]
    c.true("Fig. 10: λ_4 falls monotonically over the last 5 steps to (c)",
           all(x > y for x, y in zip(tail, tail[1:])), [f"{x:.3e}" for x in tail])
    # σ_4 = sqrt(λ_4) vanishes linearly at the IM configuration: halving the distance in α halves it
    sig = [math.sqrt(symkin.analyze(mech.with_coordinates(configuration(*s_of_alpha(a1 - h)))).im_indicator)
           for h in (1e-3, 5e-4)]
    c.close("Fig. 10: σ_4(α_c − h)/σ_4(α_c − h/2) → 2 (simple zero of σ_4 at (c))", sig[0] / sig[1], 2.0,
            tol=1e-2)


def check() -> Checklist:
    c = Checklist("3rsr (§V, Figs. 10-13)")
    mechs = {k: symkin.read_model(HERE / f) for k, f in FILES.items()}
    mechs["generic"] = at(mechs["a"], configuration(*sphere_centre("generic")),
                          "3-RSR, generic configuration on the motion (a) → (c)")
    check_construction(c, mechs)
    check_generic(c, "generic (symmetric, on the motion)", mechs["generic"])
    coords, resid = asymmetric_configuration(mechs["generic"])
    asym = at(mechs["a"], coords, "3-RSR, generic configuration without symmetry")
    c.close("generic (no symmetry): position equations solved (max residual)", resid, 0.0, tol=1e-12)
    c.close("generic (no symmetry): same link lengths (max |Δ|)",
            float(np.max(np.abs(link_distances(asym) - link_distances(mechs["a"])))), 0.0, tol=1e-12)
    check_generic(c, "generic (no symmetry)", asym)
    check_a(c, mechs["a"])
    check_b(c, mechs["b"])
    check_c(c, mechs["c"])
    check_path(c, mechs["a"])
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
