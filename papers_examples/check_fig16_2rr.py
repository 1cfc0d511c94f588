"""Fig. 16: the 2RR variant with a zone A of DKP in the input and a zone B of DKP in the output.

The paper maps the DKP indicators of a variant of the 2RR of Figs. 14-15 over an area: the
DKP-input indicator shows "a singularity exactly in the position of the linkage shown in
Fig. 16(a)" and a zone A where the values are very close to zero; the DKP-output indicator is close
to zero in a zone B.  The model (fig16_2rr.toml; its comment derives it): every moving link of
length l = 5, pivots A1 = (−2, 0), A2 = (2, 0), elbows outward; in the file's configuration the
distal links are aligned (B1, P, B2 on y = 4).

Asserted with the core (``symkin.analyze``), against elementary closed forms computed here from
the coordinates alone:
- the file's configuration: L = F = 2, DKP in the input only, the relation ω1 − ω2 = 0
  (r = 2) from (a1 × d1) ω1 + (a2 × d2) ω2 = 0, and the uncontrolled motion (P moves normal to the
  aligned distal links with the cranks locked);
- zone A: other points of the mode's type-2 locus (P the midpoint of B1B2 with |B1B2| = 2l, built
  from the crank angle): DKP in the input with the closed-form relation; the signed DKP-input test
  function changes sign across the locus at P = (0, 4) and vanishes linearly there;
- zone B: stretched legs, |P − A_i| = 2l: DKP in the output with the relation (P − A_i)·v_P = 0,
  and the DKP-output test function going to zero like the square root of the distance.
Asserted with the map (``symkin.workspace_map``, skipped with a warning until it exists): the
mode assembles exactly where both legs reach; the DKP-input test function changes sign on the
grid across y = 4 on x = 0, and only next to the closed-form type-2 locus (zone A); the
DKP-output function is smallest next to the mode's workspace boundary (zone B); the refined
DKP-input curve lies on the closed-form locus, passes through (0, 4) and ends where the locus
meets the edge of the area; the DKP-output curves lie on the circles |P − A_i| = 10 and meet at
(0, √96).
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

import symkin
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
L_LINK = 5.0
A1, A2 = np.array([-2.0, 0.0]), np.array([2.0, 0.0])
MODE = (-1.0, 1.0)  # signs of (B_i − A_i) × (P − B_i) in the file's working mode
X_AREA, Y_AREA = (-7.0, 7.0), (0.5, 10.5)
N_GRID = 57
MAP_NOTE = "needs symkin.workspace_map (the map engine, issue 8): map claims of Fig. 16 skipped"


def _cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def elbow(a, p, sign: float, l1: float = L_LINK, l2: float = L_LINK) -> np.ndarray | None:
    """Elbow B of the leg A-B-P with |AB| = l1, |BP| = l2 and sign((B − A) × (P − B)) = sign."""
    a, p = np.asarray(a, float), np.asarray(p, float)
    d = p - a
    r = float(np.hypot(*d))
    along = (l1 * l1 - l2 * l2 + r * r) / (2 * r)
    h2 = l1 * l1 - along * along
    if h2 < 0:
        return None
    n = np.array([-d[1], d[0]]) / r
    for b in (a + along * d / r + math.sqrt(h2) * n, a + along * d / r - math.sqrt(h2) * n):
        if _cross(b - a, p - b) * sign > 0:
            return b
    return None


def configuration(p) -> dict[str, np.ndarray]:
    """Nodes of the file's working mode with the end-effector at ``p``."""
    return {"P": np.asarray(p, float), "B1": elbow(A1, p, MODE[0]), "B2": elbow(A2, p, MODE[1])}


def watt_point(theta1: float) -> dict[str, np.ndarray] | None:
    """Type-2 configuration with crank 1 at angle θ1: B2 on its circle with |B1B2| = 2l, P the midpoint.

    Of the two solutions the one in the file's working mode is returned (None when neither is).
    """
    b1 = A1 + L_LINK * np.array([math.cos(theta1), math.sin(theta1)])
    d = A2 - b1
    r = float(np.hypot(*d))
    along = (4 * L_LINK ** 2 - L_LINK ** 2 + r * r) / (2 * r)
    h2 = 4 * L_LINK ** 2 - along * along
    if h2 < 0:
        return None
    n = np.array([-d[1], d[0]]) / r
    for b2 in (b1 + along * d / r + math.sqrt(h2) * n, b1 + along * d / r - math.sqrt(h2) * n):
        p = (b1 + b2) / 2
        if _cross(b1 - A1, p - b1) * MODE[0] > 0 and _cross(b2 - A2, p - b2) * MODE[1] > 0:
            return {"P": p, "B1": b1, "B2": b2}
    return None


def input_relation(cfg) -> float:
    """Coefficient of ω2 in (a1 × d1) ω1 + (a2 × d2) ω2 = 0, pivot ω1 = 1 (distal links aligned)."""
    g1 = _cross(cfg["B1"] - A1, cfg["P"] - cfg["B1"])
    g2 = _cross(cfg["B2"] - A2, cfg["P"] - cfg["B2"])
    return g2 / g1


def check() -> Checklist:
    c = Checklist("fig16_2rr")
    mech = symkin.read_model(HERE / "fig16_2rr.toml")
    xyz = {k: np.array(v) for k, v in mech.coordinates().items()}

    # ---- the construction ------------------------------------------------------------------
    for link in ("crank1", "crank2", "distal1", "distal2"):
        a, b = mech.link_nodes(link)
        c.close(f"{link} has the common length l = 5", math.dist(xyz[a], xyz[b]), L_LINK, tol=1e-15)
    c.equal("base pivots A1 = (−2, 0), A2 = (2, 0)", (tuple(xyz["A1"]), tuple(xyz["A2"])), ((-2.0, 0.0), (2.0, 0.0)))
    c.close("the distal links are aligned: (P − B1) × (P − B2) = 0", _cross(xyz["P"] - xyz["B1"], xyz["P"] - xyz["B2"]),
            0.0, tol=1e-15)
    signs = (_cross(xyz["B1"] - A1, xyz["P"] - xyz["B1"]), _cross(xyz["B2"] - A2, xyz["P"] - xyz["B2"]))
    c.true("working mode: elbow signs −, + (elbows outward)", signs[0] < 0 < signs[1], signs)

    # ---- Fig. 16(a): the file's configuration, a DKP in the input -------------------------------
    res = symkin.analyze(mech)
    c.record("Fig. 16(a): distal links aligned", res)
    c.equal("instantaneous DOF L = F = 2", (res.dof, res.mobility), (2, 2))
    c.equal("classification: DKP in the input only", res.types, ("DKP-input",))
    c.equal("input rank 1 (eq. 12), output rank 2", (res.input_rank, res.output_rank), (1, 2))
    c.equal("one input relation", len(res.input_relations), 1)
    rel = res.input_relations[0] if res.input_relations else None
    coef = rel.as_dict() if rel else {}
    c.equal("... relating both inputs (r = 2)", rel.r if rel else 0, 2)
    c.close("... ω1 − ω2 = 0: coefficient of rotation:crank2 (closed form (a2×d2)/(a1×d1) = −1)",
            coef.get("rotation:crank2", math.nan), input_relation(configuration(xyz["P"])), tol=1e-12)
    c.close("... closed form = −1", input_relation(configuration(xyz["P"])), -1.0, tol=1e-15)
    c.equal("one uncontrolled motion with the cranks locked", len(res.uncontrolled_motions), 1)
    if res.uncontrolled_motions:
        vel = dict(res.uncontrolled_motions[0].velocities)
        c.close("... P moves normal to the aligned distal links (|v_Py| = 1, scaled)", abs(vel["P"][1]), 1.0, tol=1e-12)
        c.close("... with v_Px = 0", vel["P"][0], 0.0, tol=1e-12)
        c.true("... and it moves the outputs", res.uncontrolled_motions[0].moves_outputs)
    c.close("the configuration solves the mode's inverse problem at P = (0, 4) (elbows)",
            max(float(np.abs(configuration(xyz["P"])[b] - xyz[b]).max()) for b in ("B1", "B2")), 0.0, tol=1e-14)

    # ---- zone A: the mode's type-2 locus, and the sign change of the DKP-input function -------
    theta0 = math.atan2(0.8, -0.6)
    for k, dt in enumerate((-0.35, -0.15, 0.1, 0.3)):
        cfg = watt_point(theta0 + dt)
        if cfg is None:
            c.true(f"zone A point {k + 1} (θ1 = θ1(a) {dt:+}) exists in the working mode", False, None)
            continue
        r = symkin.analyze(mech.with_coordinates(cfg))
        co = r.input_relations[0].as_dict() if r.input_relations else {}
        c.equal(f"zone A point {k + 1}, P = ({cfg['P'][0]:.4g}, {cfg['P'][1]:.4g}): DKP in the input only", r.types,
                ("DKP-input",))
        c.close(f"zone A point {k + 1}: relation coefficient of ω2 = (a2×d2)/(a1×d1)",
                co.get("rotation:crank2", math.nan), input_relation(cfg), tol=1e-9)
    below, above = (symkin.analyze(mech.with_coordinates(configuration((0.0, 4.0 + s * 1e-3)))).dkp_input
                    for s in (-1, 1))
    c.true("the DKP-input test function changes sign across the locus at P = (0, 4 ∓ 1e-3)", below * above < 0,
           (below, above))
    tiny = symkin.analyze(mech.with_coordinates(configuration((0.0, 4.0 + 1e-6)))).dkp_input
    c.close("... and vanishes linearly: value at 1e-6 / value at 1e-3 = 1e-3", tiny / above, 1e-3, tol=1e-5)

    # ---- zone B: stretched legs on |P − A_i| = 2l, a DKP in the output -------------------------
    zone_b = {"P = (8, 0), leg 1 stretched": {"P": np.array([8.0, 0.0]), "B1": np.array([3.0, 0.0]),
                                              "B2": np.array([5.0, -4.0])},
              "P = (6, 6), leg 1 stretched": None}
    p66 = A1 + 10.0 * np.array([0.8, 0.6])
    zone_b["P = (6, 6), leg 1 stretched"] = {"P": p66, "B1": A1 + 5.0 * np.array([0.8, 0.6]), "B2": elbow(A2, p66, MODE[1])}
    for name, cfg in zone_b.items():
        r = symkin.analyze(mech.with_coordinates(cfg))
        c.record(f"zone B: {name}", r)
        e = (cfg["P"] - A1) / 10.0
        c.close(f"zone B, {name}: on the circle |P − A1| = 10", math.dist(cfg["P"], A1), 10.0, tol=1e-15)
        c.equal(f"zone B, {name}: DKP in the output only", r.types, ("DKP-output",))
        co = r.output_relations[0].as_dict() if len(r.output_relations) == 1 else {}
        c.close(f"zone B, {name}: relation (P − A1)·v_P = 0, coefficient of velocity:P.x", co.get("velocity:P.x", math.nan), 1.0)
        c.close(f"zone B, {name}: coefficient of velocity:P.y = e_y/e_x", co.get("velocity:P.y", 0.0), e[1] / e[0], tol=1e-9)
    near = [abs(symkin.analyze(mech.with_coordinates(configuration(A1 + (10.0 - dist) * np.array([0.8, 0.6])))).dkp_output)
            for dist in (1e-4, 1e-6)]
    c.close("approaching zone B the DKP-output function goes to zero like √distance: ratio at 1e-4 / 1e-6 = 10",
            near[0] / near[1], 10.0, tol=1e-3)
    c.true("... and is close to zero there (below 1e-2 at 1e-4 length units)", near[0] < 1e-2, near[0])

    _map_claims(c, mech)
    return c


def type2_residual(xs, ys) -> np.ndarray:
    """(P − B1) × (P − B2) / l² on the (ny, nx) grid of the file's mode (NaN where it does not assemble)."""
    out = np.full((len(ys), len(xs)), np.nan)
    for j, y in enumerate(ys):
        for i, x in enumerate(xs):
            b1, b2 = elbow(A1, (x, y), MODE[0]), elbow(A2, (x, y), MODE[1])
            if b1 is not None and b2 is not None:
                out[j, i] = _cross(np.array([x, y]) - b1, np.array([x, y]) - b2) / L_LINK ** 2
    return out


def _neighbour_pairs(shape):
    """Index pairs (a, b) of horizontally and vertically adjacent grid points."""
    ny, nx = shape
    return [((slice(0, ny), slice(0, nx - 1)), (slice(0, ny), slice(1, nx))),
            ((slice(0, ny - 1), slice(0, nx)), (slice(1, ny), slice(0, nx)))]


def _map_claims(c: Checklist, mech) -> None:
    """Zones A and B on the map of ``symkin.workspace_map`` (Fig. 16(b), (c))."""
    if not hasattr(symkin, "workspace_map"):
        warnings.warn(MAP_NOTE, stacklevel=2)
        return
    wmap = symkin.workspace_map(mech, x=f"velocity:P.x={X_AREA[0]}:{X_AREA[1]}",
                                y=f"velocity:P.y={Y_AREA[0]}:{Y_AREA[1]}", n=N_GRID, modes="model", refine=True)
    mode = wmap.modes[0]
    xs, ys = np.asarray(wmap.xs), np.asarray(wmap.ys)
    ok = np.asarray(mode.assembled, dtype=bool)                 # (ny, nx)
    din, dout = np.asarray(mode.dkp_input), np.asarray(mode.dkp_output)
    truth = type2_residual(xs, ys)
    c.equal("map: the mode assembles exactly where both legs reach (|P − A_i| ≤ 10)", bool(np.all(ok == np.isfinite(truth))),
            True)
    # zone A, Fig. 16(b): the sign change of the DKP-input function at the linkage of Fig. 16(a)
    i0 = int(np.argmin(np.abs(xs)))
    col = din[:, i0]
    flips = [j for j in range(len(ys) - 1) if ok[j, i0] and ok[j + 1, i0] and col[j] * col[j + 1] < 0]
    c.true("map, zone A: on x = 0 the DKP-input function changes sign once, between the grid rows around y = 4",
           len(flips) == 1 and ys[flips[0]] <= 4.0 <= ys[flips[0] + 1], [(ys[j], ys[j + 1]) for j in flips])
    wrong = flips_on_grid = 0
    for a, b in _neighbour_pairs(ok.shape):
        flip = ok[a] & ok[b] & (din[a] * din[b] < 0)
        flips_on_grid += int(flip.sum())
        wrong += int(np.sum(flip & ~(truth[a] * truth[b] < 0)))
    c.true("map, zone A: the DKP-input function changes sign on the grid (the zone is crossed)", flips_on_grid > 10,
           flips_on_grid)
    c.equal("map, zone A: every sign change on the grid brackets the closed-form type-2 locus", wrong, 0)
    # zone B, Fig. 16(c): the DKP-output function is smallest next to the mode's workspace boundary
    inner = ok.copy()
    inner[1:-1, 1:-1] &= ok[:-2, 1:-1] & ok[2:, 1:-1] & ok[1:-1, :-2] & ok[1:-1, 2:]
    rim = ok & ~inner
    rim[[0, -1], :] = False
    rim[:, [0, -1]] = False
    lo_rim, lo_inner = float(np.min(np.abs(dout[rim]))), float(np.min(np.abs(dout[inner])))
    c.true("map, zone B: the smallest |DKP-output| is at the grid points next to the boundary |P − A_i| = 10",
           lo_rim < lo_inner, (lo_rim, lo_inner))
    # the refined curves
    curves = wmap.to_dict()["curves"]
    ins = [np.asarray(cv["points"]) for cv in curves if cv["kind"] == "DKP-input"]
    outs = [np.asarray(cv["points"]) for cv in curves if cv["kind"] == "DKP-output"]
    c.true("map: refined DKP-input (zone A) and DKP-output (zone B) curves exist", bool(ins) and bool(outs),
           (len(ins), len(outs)))
    if ins:
        worst = max(float(np.max(np.abs(_type2_on(pts)))) for pts in ins)
        c.close("map: every point of the DKP-input curves is on the closed-form type-2 locus", worst, 0.0, tol=1e-9)
        gap = min(float(np.min(np.abs(pts[:, 1] - 4.0) + np.abs(pts[:, 0]))) for pts in ins)
        on_axis = [pts[np.argmin(np.abs(pts[:, 0]))] for pts in ins]
        c.true("map: a DKP-input curve passes through the linkage of Fig. 16(a), P = (0, 4) (closest point)",
               gap < (Y_AREA[1] - Y_AREA[0]) / (N_GRID - 1), on_axis)
        ends = sorted(float(e[0]) for pts in ins for e in (pts[0], pts[-1]) if abs(e[1] - Y_AREA[0]) < 1e-9)
        edge = _bisect(lambda x: _type2_on([(x, Y_AREA[0])])[0], 0.5, 4.0)
        c.true("map: the DKP-input curve ends on the edge y = 0.5 where the closed-form locus meets it (x = ±"
               f"{edge:.6f}, by bisection on the closed form)",
               len(ends) == 2 and abs(ends[0] + edge) < 1e-9 and abs(ends[1] - edge) < 1e-9, ends)
    if outs:
        top = [pt["at"] for pt in wmap.to_dict()["points"] if pt["kind"] == "DKP-output"]
        c.true("map: the two DKP-output arcs meet at the top of the workspace, (0, √96) (an isolated point)",
               any(abs(a[0]) < 1e-9 and abs(a[1] - math.sqrt(96.0)) < 1e-9 for a in top), top)
        worst = max(float(np.max(np.min(np.abs([np.hypot(*(pts - a).T) - 10.0 for a in (A1, A2)]), axis=0)))
                    for pts in outs)
        c.close("map: every point of the DKP-output curves is on a circle |P − A_i| = 10", worst / L_LINK, 0.0,
                tol=1e-9)


def _bisect(f, lo: float, hi: float) -> float:
    flo = f(lo)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if (f(mid) > 0) == (flo > 0):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _type2_on(points) -> np.ndarray:
    out = []
    for p in np.asarray(points, float):
        cfg = configuration(p)
        out.append(_cross(p - cfg["B1"], p - cfg["B2"]) / L_LINK ** 2)
    return np.array(out)


if __name__ == "__main__":
    raise SystemExit(check().main())
