"""Figs. 14-15: the 2RR with equal links has an IM singularity with the end-effector at the origin.

The paper maps the IM indicator (the first non-zero eigenvalue of the geometric matrix, §V) of a
2-DOF 2RR platform "with equal lengths in every link" over an area and finds an IM singularity
"when the end-effector is on the origin".  The model (fig14_2rr.toml; its comment derives it) has
coaxial base pivots A at the origin and links of length l = 5: the loop A-B1-P-B2 is a rhombus of
side l, which collapses onto one line when P reaches the origin.

Asserted with the core (``symkin.analyze``): at the collapsed rhombus, L = 3 > F = 2, IM with a
DKP in the output (v_Py = 0), the uncontrolled motion (P slides along x with the cranks locked),
one self-stress, the singular values against their closed forms; and along the working mode of the
file, the IM indicator against its closed form, derived independently of symkin (below): it is a
function of the elbow angle β alone, with exactly one zero in the area, at the origin, where it
vanishes like (3/4)(ρ/l)².  Asserted with the map (``symkin.workspace_map``, skipped with a
warning until it exists): the mode assembles over the area, the IM indicator on the grid equals the
closed form, its minimum is at the cell containing the origin, ~0 there, and refinement reports
one isolated IM point, at the origin, classified IM with a DKP in the output.

Closed form (independent): in the mode of the file, with P at distance ρ from A, put P = (2t, 0)
l, B1,2 = (t, ±h) l, t = ρ/2l, h = √(1 − t²).  The four unit constraint rows over (v_B1, v_B2, v_P)
have the Gram matrix [[1,0,c,0],[0,1,0,c],[c,0,2,−c],[0,c,−c,2]] with c = h² − t² = cos β (β the
angle A-B1-P at the elbows); on (a,a,b,b) and (a,−a,b,−b) it is [[1,c],[c,2∓c]], so the smallest
non-zero eigenvalue of G = JᵀJ is  λ_3 = (3 − |c| − √(1 − 2|c| + 5c²))/2.
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
# the area of Figs. 14-15 (model units) and the grid: an even number of points, so the origin is the
# centre of a grid cell (at the origin itself the mode's inverse problem is degenerate: with P on the
# common pivot, B1 and B2 may turn together)
BOX = (-6.5, 6.5)
N_GRID = 52
MAP_NOTE = "needs symkin.workspace_map (the map engine, issue 8): map claims of Figs. 14-15 skipped"


def rhombus(rho: float, phi: float, l: float = L_LINK) -> dict[str, np.ndarray]:
    """Nodes of the file's working mode with P at polar (ρ, φ) about A: B1 left, B2 right of A→P."""
    e = np.array([math.cos(phi), math.sin(phi)])
    n = np.array([-e[1], e[0]])
    h = math.sqrt(l * l - rho * rho / 4.0)
    p = rho * e
    return {"P": p, "B1": p / 2 + h * n, "B2": p / 2 - h * n}


def im_closed_form(rho, l: float = L_LINK):
    """λ_3 of the rhombus mode at |P − A| = ρ: (3 − |c| − √(1 − 2|c| + 5c²))/2, c = 1 − ρ²/(2l²)."""
    c = np.abs(1.0 - np.asarray(rho, dtype=float) ** 2 / (2.0 * l * l))
    return (3.0 - c - np.sqrt(1.0 - 2.0 * c + 5.0 * c * c)) / 2.0


def _cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def check() -> Checklist:
    c = Checklist("fig14_15_2rr")
    mech = symkin.read_model(HERE / "fig14_2rr.toml")
    xyz = {k: np.array(v) for k, v in mech.coordinates().items()}

    # ---- the construction ------------------------------------------------------------------
    for link in ("crank1", "crank2", "distal1", "distal2"):
        a, b = mech.link_nodes(link)
        c.close(f"{link} has the common length l = 5", math.dist(xyz[a], xyz[b]), L_LINK, tol=1e-15)
    c.equal("both cranks turn about the one base pivot A at the origin (coaxial)",
            (mech.link_nodes("crank1")[0], mech.link_nodes("crank2")[0], tuple(xyz["A"])), ("A", "A", (0.0, 0.0)))
    sides = [_cross(xyz[b] - xyz["A"], xyz["P"] - xyz[b]) for b in ("B1", "B2")]
    c.true("the file's working mode: elbow signs (B_i − A) × (P − B_i) are −, +", sides[0] < 0 < sides[1], sides)
    seed = symkin.analyze(mech)
    c.record("seed (regular rhombus)", seed)
    c.equal("the seed P = (0, 6) is regular: L = F = 2, no singularity", (seed.dof, seed.types), (2, ()))
    c.close("the seed's IM indicator equals the closed form at ρ = 6", seed.im_indicator,
            float(im_closed_form(6.0)), tol=1e-12)

    # ---- the IM configuration: P at the origin, the rhombus collapsed ------------------------
    im = symkin.analyze(mech.with_coordinates(rhombus(0.0, 0.0)))  # B1 = (0, 5), B2 = (0, −5)
    c.record("end-effector at the origin (IM)", im)
    c.equal("P at the origin: instantaneous DOF L = 3", im.dof, 3)
    c.equal("... above the mobility F = 2", im.mobility, 2)
    c.equal("classification: IM with a DKP in the output", im.types, ("IM", "DKP-output"))
    c.close("IM indicator λ_3 = 0", im.im_indicator, 0.0, tol=1e-14)
    c.equal("the inputs stay independent (rank 2)", im.input_rank, 2)
    c.equal("output rank 1: one output relation", (im.output_rank, len(im.output_relations)), (1, 1))
    rel = im.output_relations[0].as_dict() if im.output_relations else {}
    c.equal("the output relation is v_Py = 0 (P cannot leave the line of the links)", set(rel), {"velocity:P.y"})
    c.close("... with coefficient 1", rel.get("velocity:P.y", math.nan), 1.0)
    c.equal("one uncontrolled motion with the cranks locked", len(im.uncontrolled_motions), 1)
    if im.uncontrolled_motions:
        vel = dict(im.uncontrolled_motions[0].velocities)
        c.close("... P slides along x (|v_Px| = 1 after scaling)", abs(vel["P"][0]), 1.0, tol=1e-12)
        c.close("... with v_Py = 0", vel["P"][1], 0.0, tol=1e-12)
        c.close("... and the elbows at rest", max(np.abs(vel["B1"]).max(), np.abs(vel["B2"]).max()), 0.0, tol=1e-12)
    sv = sorted(im.singular_values)
    expected = [0.0, 0.0, 0.0, math.sqrt(2 - math.sqrt(2)), math.sqrt(2), math.sqrt(2 + math.sqrt(2))]
    for k, (m, e) in enumerate(zip(sv, expected)):
        c.close(f"singular value {k + 1} of the constraint matrix = {e:.6g} (closed form)", m, e, tol=1e-13)
    c.equal("one redundant constraint: the two distal rows coincide", im.redundant_constraints, 1)

    # ---- the IM indicator along the mode: closed form, one zero, at the origin --------------
    worst = 0.0
    for rho in (0.001, 0.01, 0.1, 1.0, 2.5, 5.0, 7.0, 9.0, 9.9):
        for phi in (0.3, math.pi / 2, 2.0, 4.0):
            r = symkin.analyze(mech.with_coordinates(rhombus(rho, phi)))
            ref = float(im_closed_form(rho))
            worst = max(worst, abs(r.im_indicator - ref) / max(ref, 1e-300))
            if r.types:
                c.true(f"regular away from the origin (ρ = {rho}, φ = {phi:.3g})", False, r.types)
    c.close("symkin's IM indicator = closed form (3 − |c| − √(1 − 2|c| + 5c²))/2 (worst relative error)",
            worst, 0.0, tol=1e-9)
    small = symkin.analyze(mech.with_coordinates(rhombus(1e-3, 1.0))).im_indicator
    c.close("near the origin λ_3 ≈ (3/4)(ρ/l)²: λ_3/(ρ/l)² at ρ = 1e-3", small / (1e-3 / L_LINK) ** 2, 0.75, tol=1e-6)
    corner = float(im_closed_form(math.hypot(*BOX)))
    c.true("in the area |x|, |y| ≤ 6.5 the closed form has no other zero (value at the corners)", corner > 0.4, corner)

    _map_claims(c, mech)
    return c


def _map_claims(c: Checklist, mech) -> None:
    """The IM indicator over the area with ``symkin.workspace_map`` (Figs. 14-15)."""
    if not hasattr(symkin, "workspace_map"):
        warnings.warn(MAP_NOTE, stacklevel=2)
        return
    axis = f"{BOX[0]}:{BOX[1]}"
    wmap = symkin.workspace_map(mech, x=f"velocity:P.x={axis}", y=f"velocity:P.y={axis}", n=N_GRID,
                                modes="model", refine=False)
    grid = _grid(wmap, 0)
    xs, ys, im, ok = grid["x"], grid["y"], grid["im_indicator"], grid["assembled"]
    X, Y = np.meshgrid(xs, ys)  # the map's arrays are (ny, nx)
    rho = np.hypot(X, Y)
    c.equal("map: one working mode (the file's)", len(wmap.to_dict()["modes"]), 1)
    c.true("map: the mode assembles at every grid point of the area", bool(ok.all()), f"{int(ok.sum())}/{ok.size}")
    ref = im_closed_form(rho)
    err = float(np.max(np.abs(im[ok] - ref[ok]) / ref[ok])) if ok.any() else math.nan
    c.close("map: IM indicator on the grid = closed form (worst relative error)", err, 0.0, tol=1e-9)
    finite = np.where(ok, im, np.inf)
    lowest = np.isclose(finite, finite.min(), rtol=1e-9, atol=0.0)
    corners = (np.abs(X) < (BOX[1] - BOX[0]) / (N_GRID - 1)) & (np.abs(Y) < (BOX[1] - BOX[0]) / (N_GRID - 1))
    c.equal("map: the minimum of the IM indicator is at the four corners of the cell containing the origin",
            (int(lowest.sum()), bool(np.all(lowest == corners))), (4, True))
    c.true("map: ... and ~0 there: below 1e-2 of the largest value on the grid (the closed form "
           "vanishes at the origin like (3/4)(ρ/l)²)", float(finite.min()) < 1e-2 * float(np.max(im[ok])),
           float(finite.min()))
    # refinement locates the IM point itself (the paper's claim): one isolated IM point, at the origin
    refined = symkin.workspace_map(mech, x=f"velocity:P.x={axis}", y=f"velocity:P.y={axis}", n=N_GRID,
                                   modes="model", refine=True).to_dict()
    ims = [p for p in refined["points"] if p["kind"] == "IM"]
    c.equal("map, refined: one isolated IM point", len(ims), 1)
    if ims:
        c.close("... at the origin (|P|)", math.hypot(*ims[0]["at"]), 0.0, tol=1e-8)
        c.equal("... classified by the core as IM with a DKP in the output (L = 3 > F = 2)",
                tuple(ims[0]["types"]), ("IM", "DKP-output"))


def _grid(wmap, mode: int) -> dict[str, np.ndarray]:
    """Grid axes and the (ny, nx) arrays of one mode of a WorkspaceMap."""
    m = wmap.modes[mode]
    return {"x": np.asarray(wmap.xs), "y": np.asarray(wmap.ys), "im_indicator": np.asarray(m.im_indicator),
            "dkp_input": np.asarray(m.dkp_input), "dkp_output": np.asarray(m.dkp_output),
            "assembled": np.asarray(m.assembled, dtype=bool)}


if __name__ == "__main__":
    raise SystemExit(check().main())
