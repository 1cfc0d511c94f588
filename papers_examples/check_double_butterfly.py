"""§IV-A and §IV-B-3, Figs. 3, 4, 5, 8: the double butterfly linkage moved into IM, its branches.

The paper (its figures are not in our copy; README_paths.md explains the construction):

* Fig. 3 — a 1-DOF linkage "is moved from (a) a nonsingular position to (b) an IM
  configuration"; the first nonzero eigenvalue of G (the IM indicator, eq. 8) goes to zero.
* Fig. 4 — at that IM point "the two vectors of the motion space" give "the two different
  motions"; "the instantaneous center of rotation of the coupler in both possible motions is in
  the same point A. This causes the branches to be tangent in the double point."
* Fig. 5 — "the path of the revolute pair already mentioned ... showing the existence of two other
  points of bifurcation, and therefore, IM configurations" (three black dots).
* Fig. 8 — at a bifurcation point "two possibilities of motion are found. One of them goes on with
  the motion along the path drawn, but the other one is the motion of part of the linkage while the
  rest is locked ... a DKP configuration with r = 1 happens in the kinematic parameters that define
  the motion of the locked links" (a LIM branch).

``double_butterfly.toml`` is built so that a path from its nonsingular configuration S reaches a
configuration T1 where the path touches a finite LIM branch TANGENTIALLY (the coupler, the crank
and link3 turn as one body about the point A where C, Q2 and P2 coincide, everything else at
rest).  Asserted: the construction (exact binary lengths, kites, the tangency conditions); Fig. 3
(the IM indicator falling to zero along the traced path, the IM event at the input computed by
elementary geometry); Fig. 4 at T1 (L = 2, the two motion-space vectors, the coupler turning about
A in every motion, the path's tangent equal to the LIM branch's, the branch analysis "degenerate"
and follow_branch refusing to guess); Fig. 8 (a point of the LIM branch: L = 1, exactly the wing,
the upper triangle, link1 and link2 locked, r = 1 relations for their rotations).  A companion
geometry with ONE node moved (V2 reflected in the line C-P2) has TRANSVERSAL crossings with the
same LIM branch: there follow_branch switches onto the LIM branch (Fig. 8), the closed path has
four bifurcation points at elementary inputs (Fig. 5), and at two of them the branches cross
transversally in configuration space ('simple') while the coupler still turns about A in both
motions, so that the paths of its points have tangent branches: the other possible reading of the
Fig. 4 sentence (README_paths.md discusses both).

Run: ``python papers_examples/check_double_butterfly.py`` (exit code 0 when every claim holds).
"""
from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import numpy as np

import symkin
from symkin.errors import SymkinError
from symkin.paths.branching import branch_directions
from symkin.paths.trace import follow_branch, trace
from symkin.curves.locate import locate_singular_point
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
MODEL = HERE / "double_butterfly.toml"
LOCKED_ON_LIM = ("wing", "upper", "link1", "link2")   # locked on the LIM branch (symkin's link order)
TURNING = ("coupler", "crank", "link3")               # turn as one body about A on the LIM branch
DEG = math.pi / 180.0


# ---------------------------------------------------------------- exact (rational) geometry
def exact(mech: symkin.Mechanism) -> dict[str, np.ndarray]:
    """Coordinates as exact fractions (every coordinate of the models is a binary fraction)."""
    return {n: np.array([Fraction(v) for v in c], dtype=object) for n, c in mech.coordinates().items()}


def exact_length(p: np.ndarray, q: np.ndarray) -> Fraction | None:
    """|p − q| as a fraction when it is rational, else None."""
    d2 = Fraction(sum((a - b) ** 2 for a, b in zip(p, q)))
    rn, rd = math.isqrt(d2.numerator), math.isqrt(d2.denominator)
    return Fraction(rn, rd) if rn * rn == d2.numerator and rd * rd == d2.denominator else None


def link_lengths(mech: symkin.Mechanism, x: dict) -> dict[tuple[str, str], Fraction | None]:
    return {(a, b): exact_length(x[a], x[b]) for _, ns in mech.links
            for i, a in enumerate(ns) for b in ns[i + 1:]}


def rotate(v: np.ndarray, c: Fraction, s: Fraction) -> np.ndarray:
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]], dtype=object)


def rotation_taking(u: np.ndarray, w: np.ndarray) -> tuple[Fraction, Fraction]:
    """(cos, sin) of the rotation taking direction u to direction w (|u| = |w|, exact)."""
    n2 = u[0] * u[0] + u[1] * u[1]
    return (u[0] * w[0] + u[1] * w[1]) / n2, (u[0] * w[1] - u[1] * w[0]) / n2


def on_lim_branch(x_s: dict, crank_dir: tuple[Fraction, Fraction]) -> dict[str, np.ndarray]:
    """A configuration of the LIM branch, built from S by elementary geometry (exact).

    The wing stays on the ground triangle (Q = P); the upper kite (upper, link1, link2) turns about
    P1 = Q1 until C reaches P2 (|C − P1| = |P2 − P1|); the coupler, the crank and link3 then form
    one rigid body about P2 = Q2 = C, placed so that the crank points along ``crank_dir``.
    """
    p1, p2, c0 = x_s["P1"], x_s["P2"], x_s["C"]
    cu, su = rotation_taking(c0 - p1, p2 - p1)
    x = dict(x_s)
    x["C"] = p2.copy()
    for n in ("U1", "U2"):
        x[n] = p1 + rotate(x_s[n] - p1, cu, su)
    r = exact_length(x_s["V1"], c0)
    cc, sc = rotation_taking(x_s["V1"] - c0, np.array([r * crank_dir[0], r * crank_dir[1]], dtype=object))
    for n in ("V1", "V2"):
        x[n] = p2 + rotate(x_s[n] - c0, cc, sc)
    return x


def as_float(x: dict) -> dict[str, list[float]]:
    return {n: [float(v) for v in c] for n, c in x.items()}


def reflect_in_line(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    t = ((p - a) @ d) / (d @ d)
    foot = a + t * d
    return 2 * foot - p


# ---------------------------------------------------------------- independent numerics (no symkin)
def rigidity(mech: symkin.Mechanism, x: np.ndarray, extra_rows=()) -> np.ndarray:
    """Singular values (descending) of the bar rows (unit vectors) over the free coordinates."""
    idx = mech.node_index()
    free = [n for n in mech.node_names if n not in mech.fixed]
    col = {n: 2 * k for k, n in enumerate(free)}
    rows = []
    for _, ns in mech.links:
        for i, a in enumerate(ns):
            for b in ns[i + 1:]:
                u = (x[idx[b]] - x[idx[a]]) / np.linalg.norm(x[idx[b]] - x[idx[a]])
                r = np.zeros(2 * len(free))
                if a in col:
                    r[col[a]: col[a] + 2] -= u
                if b in col:
                    r[col[b]: col[b] + 2] += u
                rows.append(r)
    for node_a, node_b in extra_rows:   # rotation rate of the bar a→b (b free, a fixed)
        d = x[idx[node_b]] - x[idx[node_a]]
        r = np.zeros(2 * len(free))
        r[col[node_b]: col[node_b] + 2] = np.array([-d[1], d[0]]) / (d @ d)
        rows.append(r / np.linalg.norm(r))
    s = np.linalg.svd(np.array(rows), compute_uv=False)
    return np.concatenate([s, np.zeros(max(0, 2 * len(free) - s.size))])


def nullity(s: np.ndarray, tol: float = 1e-9) -> int:
    return int(np.count_nonzero(s <= tol * s[0]))


def crank_angle(mech: symkin.Mechanism, x: np.ndarray) -> float:
    idx = mech.node_index()
    d = x[idx["V1"]] - x[idx["P2"]]
    return math.atan2(d[1], d[0])


def wrap(a: float) -> float:
    return math.remainder(a, 2 * math.pi)


def angle_between(u: np.ndarray, v: np.ndarray) -> float:
    """Angle between the lines of u and v (radians, in [0, π/2])."""
    return math.acos(min(1.0, abs(float(u @ v)) / (np.linalg.norm(u) * np.linalg.norm(v))))


def instant_centre(xa, xb, va, vb) -> np.ndarray | None:
    """Instantaneous centre of a planar rigid body from two of its nodes and their velocities."""
    d = xb - xa
    omega = float(np.array([-d[1], d[0]]) @ (vb - va) / (d @ d))
    if abs(omega) < 1e-14:
        return None
    return xa + np.array([-va[1], va[0]]) / omega


def full_vector(mech: symkin.Mechanism, curve, t_free: np.ndarray) -> np.ndarray:
    v = np.zeros(2 * len(mech.node_names))
    v[curve.free] = t_free
    return v


def node_rows(mech: symkin.Mechanism, name: str) -> slice:
    k = mech.node_index()[name]
    return slice(2 * k, 2 * k + 2)


# ---------------------------------------------------------------- the checks
def check_construction(c: Checklist, mech: symkin.Mechanism, x: dict) -> None:
    lengths = link_lengths(mech, x)
    c.true("every link length is rational (exact in binary: the singularities are exact)",
           all(v is not None and v.denominator & (v.denominator - 1) == 0 for v in lengths.values()),
           {f"{a}-{b}": str(v) for (a, b), v in lengths.items()})

    def L(a: str, b: str) -> Fraction | None:
        return exact_length(x[a], x[b])

    c.equal("wing congruent to the ground triangle (|OQ1|, |OQ2|, |Q1Q2| = |OP1|, |OP2|, |P1P2|)",
            (L("O", "Q1"), L("O", "Q2"), L("Q1", "Q2")), (L("O", "P1"), L("O", "P2"), L("P1", "P2")))
    c.equal("kites: link1 = |CU1|, link2 = |CU2|, crank = |CV1|, link3 = |CV2|",
            (L("P1", "U1"), L("Q1", "U2"), L("P2", "V1"), L("Q2", "V2")),
            (L("C", "U1"), L("C", "U2"), L("C", "V1"), L("C", "V2")))
    c.equal("C is as far from P1 as P2 is (the upper kite can swing C onto P2)", L("P1", "C"), L("P1", "P2"))
    c.equal("U1 is the midpoint of P1-C", tuple(x["U1"]), tuple((x["P1"] + x["C"]) / 2))

    def cv(a: str, b: str, o: str) -> Fraction:
        """cos of the angle a-o-b (exact)."""
        return (x[a] - x[o]) @ (x[b] - x[o]) / (L(a, o) * L(b, o))

    c.equal("coupler angle at C = ground angle at P2 (cos, exact)", cv("V1", "V2", "C"), cv("P1", "O", "P2"))


def check_fig3_fig4(c: Checklist, mech: symkin.Mechanism, x_s: dict) -> None:
    idx = mech.node_index()
    names = mech.node_names
    res_s = symkin.analyze(mech)
    c.record("S: nonsingular start (Fig. 3a)", res_s)
    c.equal("Fig. 3(a) S is nonsingular: L = F = 1, no singularity", (res_s.dof, res_s.types), (1, ()))

    # T1 by elementary geometry: the LIM branch with the crank along P2 -> P1
    x_t1 = on_lim_branch(x_s, (Fraction(0), Fraction(-1)))
    c.equal("T1 is a configuration of the same mechanism (exact link lengths)", link_lengths(mech, x_t1),
            link_lengths(mech, x_s))
    c.true("T1: V2 lies on the line P2-O (the second tangency condition, exact cross product)",
           (x_t1["V2"] - x_t1["P2"])[0] * x_t1["P2"][1] - (x_t1["V2"] - x_t1["P2"])[1] * x_t1["P2"][0] == 0)
    x_t1f = np.array([as_float(x_t1)[n] for n in names])
    theta_s = crank_angle(mech, np.array([as_float(x_s)[n] for n in names]))
    in_t1 = wrap(-math.pi / 2 - theta_s)
    c.close("T1 input (crank along P2→P1, elementary): 16.2602°", in_t1 / DEG, 16.26020470831196, tol=1e-12)

    # Fig. 3: the traced path from S reaches T1; the IM indicator falls to zero
    path = trace(mech, stop=2000.0, unit="deg", max_arclength=18.3)
    ims = [e for e in path.events if e.kind == "IM"]
    c.true("Fig. 3(b): the path from S reaches an IM event", bool(ims), len(ims))
    if not ims:
        return
    errs = [abs(wrap(e.input - in_t1)) / DEG for e in ims]
    c.true("... every IM event is T1 (|input − 16.2602°| ≤ 1e-2°)", max(errs) <= 1e-2, errs)
    c.true("... the best located to ≤ 1e-5° (a tangent contact limits the accuracy; see README_paths.md)",
           min(errs) <= 1e-5, min(errs))
    c.true("... and within 1e-2 length units of T1 (max |Δx|; lengths here are 9 to 30)",
           max(float(np.abs(e.coordinates - x_t1f).max()) for e in ims) <= 1e-2,
           [float(np.abs(e.coordinates - x_t1f).max()) for e in ims])
    c.equal("... classified IM with L = 2 at every IM event", {(e.analysis.dof, e.analysis.types) for e in ims},
            {(2, ("IM",))})
    c.equal("... branch analysis: 'degenerate' (tangent branches), not a guess",
            {e.bifurcation.status for e in ims}, {"degenerate"})
    # beyond the trace's σ₂ minimum: the branch point located again by deflated Newton (symkin.curves.locate)
    located = [locate_singular_point(path.curve, e.y) for e in ims]
    c.true("... each IM event located again by deflated Newton is T1 to rounding (≤ 1e-12 length units; "
           "the singular system deflated twice)",
           all(b.converged and b.deflations == 2 for b in located)
           and max(float(np.abs(path.curve.x_of(b.y) - x_t1f).max()) for b in located) <= 1e-12,
           [(b.deflations, float(np.abs(path.curve.x_of(b.y) - x_t1f).max())) for b in located])
    first = min(ims, key=lambda e: e.s)
    before = [p for p in path.points if p.s < first.s]
    ind = [p.indicators["im_indicator"] for p in before[-5:]]
    c.true("Fig. 3(c): the IM indicator λ₂ falls monotonically over the last 5 points before T1",
           all(b < a for a, b in zip(ind, ind[1:])), ind)
    c.true("... by more than three orders of magnitude", ind[-1] < 1e-3 * ind[0], ind[-1] / ind[0])
    c.true("... and is λ₂ ≤ 1e-18 at the IM events", max(e.analysis.im_indicator for e in ims) <= 1e-18,
           [e.analysis.im_indicator for e in ims])

    back = trace(mech, stop=-2000.0, unit="deg", max_arclength=19.3)
    back_ims = [e for e in back.events if e.kind == "IM"]
    c.true("the other way round from S the path also arrives at T1 first (best |Δinput| ≤ 1e-3°): the path "
           "through S is one loop that touches the LIM branch at T1 only",
           bool(back_ims) and min(abs(wrap(e.input - in_t1)) for e in back_ims) / DEG <= 1e-3,
           [abs(wrap(e.input - in_t1)) / DEG for e in back_ims])

    # DKP-input events on the way (turning points of the crank), checked independently
    dkp = [e for e in path.events if e.kind == "DKP-input" and e.s < first.s and "DKP-input" in e.analysis.types]
    c.equal("turning points of the crank before T1 confirmed by the classifier", len(dkp), 4)
    ok = []
    for e in dkp:
        s_rows = rigidity(mech, e.coordinates, extra_rows=[("P2", "V1")])
        rel = [r.as_dict() for r in e.analysis.input_relations]
        ok.append((e.analysis.dof, [sorted(r) for r in rel], all(abs(v - 1.0) <= 1e-9 for r in rel for v in r.values()),
                   e.analysis.locked_links, float(s_rows[-1] / s_rows[0]) < 1e-9,
                   abs(wrap(crank_angle(mech, e.coordinates) - theta_s - e.input)) < 1e-12))
    c.equal("... each: L = 1, rotation:crank = 0 (r = 1), crank in LIM; independently: [J; crank row] singular, "
            "input = crank angle from atan2", ok,
            [(1, [["rotation:crank"]], True, ("crank",), True, True)] * len(dkp))

    # Fig. 4 at the exact T1
    mt = mech.with_coordinates(as_float(x_t1))
    res = symkin.analyze(mt)
    c.record("T1: tangent contact with the LIM branch (Figs. 3b, 4, 8)", res)
    c.equal("Fig. 4: T1 is IM with L = 2 (F = 1)", (res.dof, res.types), (2, ("IM",)))
    c.close("... deciding singular value σ₂ (relative)", float(res.singular_values[1]), 0.0, tol=1e-15)
    c.equal("... independently (bar rows by hand): nullity 2", nullity(rigidity(mech, x_t1f)), 2)
    c.equal("... C, Q2 and P2 coincide at T1 (the paper's point A)", (tuple(x_t1["C"]), tuple(x_t1["Q2"])),
            (tuple(x_t1["P2"]),) * 2)
    V = res.motion.V
    m1 = np.zeros(2 * len(names))
    for n in ("V1", "V2"):
        r = x_t1f[idx[n]] - x_t1f[idx["P2"]]
        m1[node_rows(mech, n)] = [-r[1], r[0]]
    m1 /= np.linalg.norm(m1)
    c.close("motion-space vector 1: the coupler, crank and link3 turning about A, the rest at rest (residual)",
            float(np.linalg.norm(m1 - V @ (V.T @ m1))), 0.0, tol=1e-14)
    c.equal("one uncontrolled motion with the crank locked (eq. 11: L − F = 1)", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        vel = {n: np.array(v) for n, v in res.uncontrolled_motions[0].velocities}
        moving = sorted(n for n, v in vel.items() if np.linalg.norm(v) > 1e-12)
        c.equal("motion-space vector 2 (crank locked): only the wing, upper, link1, link2 move (C at rest)",
                moving, ["Q1", "Q2", "U1", "U2"])
    c.equal("C is at rest in every motion (locked node)", res.locked_nodes, ("C",))
    cpl = np.vstack([V[node_rows(mech, n)] for n in ("C", "V1", "V2")])
    sv = np.linalg.svd(cpl, compute_uv=False)
    c.close("the coupler's velocities over the motion space have rank 1 (σ₂/σ₁)", float(sv[1] / sv[0]), 0.0,
            tol=1e-14)
    ic = instant_centre(x_t1f[idx["C"]], x_t1f[idx["V1"]], m1[node_rows(mech, "C")], m1[node_rows(mech, "V1")])
    c.close("... so its instantaneous centre is the same point in every motion: A = P2 (distance)",
            float(np.linalg.norm(ic - x_t1f[idx["P2"]])) if ic is not None else math.inf, 0.0, tol=1e-12)

    curve = path.curve
    y_t1 = curve.y_of(x_t1f.ravel()[curve.free])
    c.close("T1 closes the curve's equations (residual)", float(np.abs(curve.residual(y_t1)).max()), 0.0,
            tol=1e-14)
    bif = branch_directions(curve, y_t1)
    c.equal("second-order branch analysis at T1: degenerate, nullity 2", (bif.status, bif.nullity),
            ("degenerate", 2))
    c.close("... zero discriminant of the quadratic branch equation (tangent branches)",
            abs(bif.discriminant) if bif.discriminant is not None else math.inf, 0.0, tol=1e-9)
    best = min(ims, key=lambda e: abs(wrap(e.input - in_t1)))
    ang = angle_between(full_vector(mech, curve, best.t), m1)
    c.true("the path's tangent at T1 is the LIM branch's (angle ≤ 1e-4 rad): the branches are tangent",
           ang <= 1e-4, ang)
    chords = [np.ravel(b.coordinates - a.coordinates) for a, b in zip(before[-6:-1], before[-5:])]
    angs = [angle_between(ch, m1) for ch in chords]
    c.true("... approaching T1 the path turns into that direction (chord angles to it decrease)",
           all(b < a for a, b in zip(angs, angs[1:])), [round(a / DEG, 2) for a in angs])
    tv = full_vector(mech, curve, best.t)
    ic_path = instant_centre(best.coordinates[idx["C"]], best.coordinates[idx["V1"]], tv[node_rows(mech, "C")],
                             tv[node_rows(mech, "V1")])
    c.true("on the path at T1 the coupler also turns about A (distance of its centre from P2 ≤ 1e-3)",
           ic_path is not None and float(np.linalg.norm(ic_path - x_t1f[idx["P2"]])) <= 1e-3,
           None if ic_path is None else float(np.linalg.norm(ic_path - x_t1f[idx["P2"]])))
    v2 = tv[node_rows(mech, "V2")]
    c.true("the path of the upper pair V2 is tangent there to its circle about A on the LIM branch",
           angle_between(v2, x_t1f[idx["V2"]] - x_t1f[idx["P2"]]) >= math.pi / 2 - 1e-4,
           angle_between(v2, x_t1f[idx["V2"]] - x_t1f[idx["P2"]]))
    try:
        follow_branch(path, best, 0)
        refused = ""
    except SymkinError as exc:
        refused = str(exc)
    c.true("follow_branch refuses to switch at T1 and says why (degenerate)", "degenerate" in refused, refused)

    # the second contact of the LIM branch, half a turn of the coupler later
    x_t2 = on_lim_branch(x_s, (Fraction(0), Fraction(1)))
    res2 = symkin.analyze(mech.with_coordinates(as_float(x_t2)))
    c.record("T2: the other contact of the LIM branch", res2)
    x_t2f = np.array([as_float(x_t2)[n] for n in names])
    bif2 = branch_directions(curve, curve.y_of(x_t2f.ravel()[curve.free]))
    c.equal("T2 (crank along P1→P2, input −163.7398°): IM, L = 2, degenerate", (res2.dof, res2.types, bif2.status),
            (2, ("IM",), "degenerate"))


def check_fig8_lim(c: Checklist, mech: symkin.Mechanism, x_s: dict) -> None:
    x_f = on_lim_branch(x_s, (Fraction(1), Fraction(0)))
    c.equal("a point of the LIM branch (crank along +x) is a configuration of the mechanism (exact lengths)",
            link_lengths(mech, x_f), link_lengths(mech, x_s))
    mf = mech.with_coordinates(as_float(x_f))
    res = symkin.analyze(mf)
    c.record("a point of the LIM branch (Fig. 8b)", res)
    c.equal("Fig. 8(b): L = 1, the part-locked motion is a LIM", (res.dof, res.types), (1, ("LIM",)))
    c.equal("... locked links: wing, upper, link1, link2", res.locked_links, LOCKED_ON_LIM)
    c.equal("... locked nodes", res.locked_nodes, ("Q1", "Q2", "C", "U1", "U2"))
    data = mf.to_dict()
    data["outputs"] = [{"rotation": n} for n in LOCKED_ON_LIM]
    res_out = symkin.analyze(symkin.Mechanism.from_dict(data))
    c.equal("... DKP with r = 1 in the parameters of the locked links: rotation:L = 0 for each",
            [(r.as_dict(), r.r) for r in res_out.output_relations],
            [({f"rotation:{n}": 1.0}, 1) for n in LOCKED_ON_LIM])
    c.equal("... independently (bar rows by hand): nullity 1",
            nullity(rigidity(mech, np.array([as_float(x_f)[n] for n in mech.node_names]))), 1)


def check_transversal(c: Checklist, mech: symkin.Mechanism, x_s: dict) -> None:
    """The companion geometry: V2 reflected in the line C-P2 (crossings instead of contacts)."""
    idx = mech.node_index()
    names = mech.node_names
    v2 = reflect_in_line(x_s["V2"], x_s["C"], x_s["P2"])
    x_a = dict(x_s)
    x_a["V2"] = v2
    c.equal("companion: V2 reflected in the line C-P2 is a binary fraction point", tuple(v2),
            (Fraction(-267, 8), Fraction(11, 2)))
    la, ls = link_lengths(mech, x_a), link_lengths(mech, x_s)
    c.equal("... every link length unchanged except the coupler's side V1-V2",
            sorted(k for k in la if la[k] != ls[k]), [("V1", "V2")])
    ma = mech.with_coordinates(as_float(x_a))
    res_s = symkin.analyze(ma)
    c.equal("... its S is nonsingular", (res_s.dof, res_s.types), (1, ()))

    theta_s = crank_angle(ma, np.array([as_float(x_a)[n] for n in names]))
    # elementary crossing inputs: V1 on the line P2-P1, or V2 on the line P2-O (both directions)
    cv, cc = x_a["V1"] - x_a["C"], x_a["V2"] - x_a["C"]
    gamma = math.atan2(float(cv[0] * cc[1] - cv[1] * cc[0]), float(cv @ cc))   # angle V1 -> V2 at C
    p2 = [float(v) for v in x_a["P2"]]
    dirs_v1 = [-math.pi / 2, math.pi / 2]
    dirs_v2 = [math.atan2(p2[1], p2[0]) - gamma, math.atan2(-p2[1], -p2[0]) - gamma]
    expected = sorted(wrap(d - theta_s) % (2 * math.pi) for d in dirs_v1 + dirs_v2)

    path = trace(ma, stop=2000.0, unit="deg", max_arclength=3.5)
    ims = [e for e in path.events if e.kind == "IM"]
    c.equal("companion, Fig. 3: the path from S reaches one IM event first", len(ims), 1)
    if not ims:
        return
    ev = ims[0]
    c.close("... at the elementary input 16.2602° (V1 on the line P2-P1), in degrees", ev.input / DEG,
            wrap(-math.pi / 2 - theta_s) / DEG, tol=1e-9)
    c.record("companion: transversal crossing with the LIM branch (Fig. 8a)", ev.analysis)
    c.equal("... L = 2, IM; branch analysis 'simple' with two directions",
            (ev.analysis.dof, ev.analysis.types, ev.bifurcation.status, len(ev.bifurcation.directions)),
            (2, ("IM",), "simple", 2))

    def wing(p) -> float:
        return math.atan2(p.coordinates[idx["Q1"]][1], p.coordinates[idx["Q1"]][0])

    kinds = []
    for b in (0, 1):
        sub = follow_branch(path, ev, b, sign=1.0, max_arclength=1.0)
        turn = max(abs(wrap(wing(p) - wing(sub.points[0]))) for p in sub.points)
        a = symkin.analyze(ma.with_coordinates(sub.points[len(sub.points) // 2].coordinates))
        kinds.append(("LIM branch" if turn < 1e-12 else "path", a.dof, a.types, a.locked_links))
    c.equal("Fig. 8: follow_branch gives one branch that goes on with the path (nonsingular) and one that "
            "moves the coupler, crank and link3 with the rest locked (LIM)",
            sorted(kinds), sorted([("path", 1, (), ()), ("LIM branch", 1, ("LIM",), LOCKED_ON_LIM)]))
    lim = next(b for b in (0, 1) if kinds[b][0] == "LIM branch")
    found = []
    for sign in (1.0, -1.0):
        sub = follow_branch(path, ev, lim, sign=sign, max_arclength=1.0)
        found += [e.input for e in sub.events if e.kind == "IM"]
    c.close("... along the LIM branch the next crossing is at an elementary input (V2 on the line P2-O): "
            "error in degrees", min((min(abs(wrap(f - e)) for e in expected) for f in found), default=math.inf) / DEG,
            0.0, tol=1e-9)

    # Fig. 5: the whole path of the companion, its bifurcation points
    loop = trace(ma, stop=2000.0, unit="deg", max_arclength=100.0)
    bps = [e for e in loop.events if e.kind == "IM"]
    c.equal("Fig. 5: the companion's path is a closed loop", loop.stop_reason, "closed")
    got = sorted(e.input % (2 * math.pi) for e in bps)
    c.equal("... with four bifurcation points (IM, 'simple')", [(e.analysis.dof, e.bifurcation.status) for e in bps],
            [(2, "simple")] * 4)
    c.equal("... at the four elementary inputs (mod 360°, rounded to 1e-6°)", [round(g / DEG, 6) for g in got],
            [round(e / DEG, 6) for e in expected])
    c.close("... max error of the four located inputs (degrees)",
            max(abs(wrap(g - e)) for g, e in zip(got, expected)) / DEG if len(got) == 4 else math.inf, 0.0, tol=1e-9)
    # the other reading of Fig. 4: transversal branches whose coupler points have tangent paths
    at48 = [e for e in bps if abs(wrap(e.input - expected[1])) / DEG <= 1e-6]
    if at48:
        e = at48[0]
        V = e.analysis.motion.V
        sv = np.linalg.svd(np.vstack([V[node_rows(ma, n)] for n in ("C", "V1", "V2")]), compute_uv=False)
        full = [full_vector(ma, loop.curve, d) for d in e.bifurcation.directions]
        v2 = [f[node_rows(ma, "V2")] for f in full]
        c.equal("companion at 48.7806° (V2 on the line P2-O): branches cross transversally ('simple'), C at rest",
                (e.bifurcation.status, e.analysis.locked_nodes), ("simple", ("C",)))
        c.close("... yet the coupler's velocities over the motion space have rank 1 (σ₂/σ₁): its centre is A in "
                "both motions", float(sv[1] / sv[0]), 0.0, tol=1e-12)
        c.true("... the two branch directions differ (angle > 10°) ...", angle_between(*full) > 10 * DEG,
               angle_between(*full) / DEG)
        c.close("... but V2 moves along the same line on both: its path has two TANGENT branches there (angle, rad)",
                angle_between(*v2), 0.0, tol=1e-9)
    else:
        c.true("companion: a bifurcation point at 48.7806°", False, [e.input / DEG for e in bps])
    c.close("... each on the LIM branch: C, Q2 and P2 coincide there (max distance)",
            max((max(float(np.linalg.norm(e.coordinates[idx["C"]] - e.coordinates[idx[n]])) for n in ("Q2", "P2"))
                 for e in bps), default=math.inf), 0.0, tol=1e-9)


def check() -> Checklist:
    c = Checklist("double_butterfly")
    mech = symkin.read_model(MODEL)
    x_s = exact(mech)
    check_construction(c, mech, x_s)
    check_fig3_fig4(c, mech, x_s)
    check_fig8_lim(c, mech, x_s)
    check_transversal(c, mech, x_s)
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
