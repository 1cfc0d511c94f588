"""§V, Fig. 10: the 3-RSR platform traced along one motion through positions (a), (b), (c).

The paper: "A spatial 3-RSR platform has been analyzed along the motion from a DKP position to
the IM configuration ... with three inputs in the revolute pairs to ground.  The plot of the first
nonzero eigenvalue (Fig. 10) indicates how the 3-DOF platform is moving toward a singularity of
the IM type.  For every simulated successive position, the procedure for singularity detection has
been used" — positions (a) Fig. 11, (b) Fig. 12, (c) Fig. 13.

The mechanism and the three positions are those of ``check_3rsr.py`` (README_3rsr.md): one
motion with the three lower-link angles equal, α = 36.87° (a), 53.13° (generic), 95.74° (b),
143.13° (c).  A positive input turns a lower link about +τ_k and lowers α, so the path
``inputs = λ·(1, 1, 1)`` from the generic configuration meets (a) at λ = +16.2602°, (b) at
−42.6091° and (c) at −90°.  Asserted, with symkin's path tracer (README_paths.md has the
findings in full):

* (b) is located as a DKP-output event at its exact input and configuration, classified as the
  single-configuration file (L = 3, DKP-output + LIM of the platform, platform DOF 0);
* the path reaches (c): at λ = −90° its configuration is the file's and is classified as the file
  (L = 4, IM + DKP-input + constraint, input rank 1, platform DOF 4); the IM indicator (Fig. 10)
  falls monotonically to zero on the way;
* (c) lies on a finite 3-DOF self-motion: the platform and the upper links turning rigidly about
  A with the lower links locked (the paper's "3-DOF rotation of the platform about point A" is a
  finite motion), where L = 3 with DKP-input and LIM of the lower links; the path's own Jacobian
  has nullity 4 at (c).  Each IM event the tracer locates at −90° is (c) itself or a point of
  that self-motion (today: points turned by 0.001° and 0.01° about A, classified L = 3);
* (a) is located as a DKP-input event at its exact input, its configuration within 2e-7 of the
  file's; it is a degenerate turning point of the path (nullity 3) where the path passes from
  the platform-above-S to the platform-below-S assembly of the symmetric motion; at a rank
  tolerance matching that accuracy it is classified as the file (input rank 0, LIM).

Run: ``python papers_examples/check_3rsr_path.py`` (exit code 0 when every claim holds).
"""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np

import symkin
from symkin.paths.branching import branch_directions
from symkin.paths.trace import trace
from symkin.reproduce import Checklist

HERE = Path(__file__).resolve().parent
LEGS = (1, 2, 3)
DRIVE = {f"rotation:lower{k}": 1.0 for k in LEGS}
A = np.array([0.0, 0.0, 3.0])   # where the sphere centres meet at (c)
DEG = math.pi / 180.0


def _rsr():
    """The construction helpers of check_3rsr.py (one geometry for both checks)."""
    spec = importlib.util.spec_from_file_location("symkin_example_check_3rsr_helpers", HERE / "check_3rsr.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def xyz(mech: symkin.Mechanism) -> np.ndarray:
    c = mech.coordinates()
    return np.array([c[n] for n in mech.node_names], dtype=float)


def lower_alpha(mech: symkin.Mechanism, x: np.ndarray, k: int, rsr) -> float:
    """α of leg k: angle of G→S from the outward radial direction, in the leg's vertical half-plane."""
    idx = mech.node_index()
    u, _ = rsr.frames()[k - 1]
    g = (x[idx[f"G{k}1"]] + x[idx[f"G{k}2"]]) / 2
    d = x[idx[f"S{k}"]] - g
    return math.atan2(d[2], float(d @ u))


def rigid_fit(p0: np.ndarray, p1: np.ndarray) -> tuple[float, float]:
    """Rotation about the origin best taking rows p0 to rows p1: (angle in degrees, max residual)."""
    u, _, vt = np.linalg.svd(p1.T @ p0)
    r = u @ vt
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(r) - 1.0) / 2.0))))
    return angle, float(np.abs(p1 - p0 @ r.T).max())


def rotation(axis, angle: float) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def summary(res) -> tuple:
    return res.dof, res.types, res.input_rank, res.platform_dof, res.locked_links


def check() -> Checklist:
    c = Checklist("3rsr_path")
    rsr = _rsr()
    files = {k: symkin.read_model(HERE / f) for k, f in rsr.FILES.items()}
    gen = rsr.at(files["a"], rsr.configuration(*rsr.sphere_centre("generic")), "3-RSR, generic configuration")
    alpha = {k: rsr.alpha_of(*rsr.sphere_centre(k)) for k in ("a", "generic", "b", "c")}
    lam = {k: alpha["generic"] - alpha[k] for k in ("a", "b", "c")}
    idx = gen.node_index()
    s_rows = [idx[f"S{k}"] for k in LEGS]
    moving_about_a = [idx[n] for n in ("U11", "U12", "U21", "U22", "U31", "U32")]

    # ---- generic -> (c): positions (b) and (c), Fig. 10 ---------------------------------------
    path = trace(gen, input=DRIVE, stop=lam["c"] / DEG, unit="deg")
    c.equal("generic → (c): the path reaches λ = −90°", path.stop_reason, "reached")
    end = path.events[-1]
    c.close("sign convention: at the end every lower link is at α(c) = 143.13° (max error, rad)",
            max(abs(lower_alpha(gen, end.coordinates, k, rsr) - alpha["c"]) for k in LEGS), 0.0, tol=1e-9)
    res_b = symkin.analyze(files["b"])
    outs = [e for e in path.events if e.kind == "DKP-output"]
    c.equal("one DKP-output event on the way: position (b)", len(outs), 1)
    if outs:
        eb = outs[0]
        c.close("(b) located at its input λ = −42.6091° (degrees)", eb.input / DEG, lam["b"] / DEG, tol=1e-9)
        c.close("(b) located at the file's configuration (max |Δx|)",
                float(np.abs(eb.coordinates - xyz(files["b"])).max()), 0.0, tol=1e-8)
        c.record("path event at (b)", eb.analysis)
        c.equal("(b) classified as fig12_3rsr_b: L, types, input rank, platform DOF, locked links",
                summary(eb.analysis), summary(res_b))
        c.equal("(b) six r = 1 output relations (no output whatever the inputs)",
                sorted(next(iter(r.as_dict())) for r in eb.analysis.output_relations if r.r == 1),
                sorted(next(iter(r.as_dict())) for r in res_b.output_relations))
    xc = xyz(files["c"])
    c.close("(c) the path at λ = −90° is the file's configuration (max |Δx|)",
            float(np.abs(end.coordinates - xc).max()), 0.0, tol=1e-7)
    res_end = symkin.analyze(gen.with_coordinates(end.coordinates))
    res_c = symkin.analyze(files["c"])
    c.record("path at λ = −90° (position c)", res_end)
    c.equal("(c) classified as fig13_3rsr_c: L = 4, IM + DKP-input + constraint, input rank 1, platform DOF 4",
            summary(res_end), summary(res_c))

    ind = [p.indicators["im_indicator"] for p in path.points]
    lam_pts = [p.input for p in path.points]
    peak = max(k for k in range(1, len(ind) - 1) if ind[k] > ind[k - 1] and ind[k] > ind[k + 1])
    c.true("Fig. 10: the IM indicator's last local maximum is between (b) and (c)",
           lam["c"] < lam_pts[peak] < lam["b"], lam_pts[peak] / DEG)
    tail = ind[peak:]
    c.true("... from there it falls monotonically as the platform approaches (c)",
           all(b < a for a, b in zip(tail, tail[1:])), [f"{v:.3g}" for v in tail])
    c.close("... to zero at (c) (λ₄ at the end of the path)", ind[-1], 0.0, tol=1e-20)
    check_pts = [0, len(ind) // 2, peak]
    c.close("the path's indicator is the classifier's λ₄ at the same configurations (max relative difference)",
            max(abs(ind[k] - symkin.analyze(gen.with_coordinates(path.points[k].coordinates)).im_indicator) / ind[k]
                for k in check_pts), 0.0, tol=1e-9)

    # ---- what the IM events at -90° are: a finite self-motion about A through (c) --------------
    ims = [e for e in path.events if e.kind == "IM"]
    c.true("IM events located at λ = −90° (before the end)", len(ims) >= 1 and
           max(abs(e.input - lam["c"]) for e in ims) / DEG <= 1e-9, [e.input / DEG for e in ims])
    verdicts = []
    for e in ims:
        angle, fit = rigid_fit(xc[moving_about_a] - A, e.coordinates[moving_about_a] - A)
        at_a = float(np.abs(e.coordinates[s_rows] - A).max())
        is_c = float(np.abs(e.coordinates - xc).max()) <= 1e-7 and summary(e.analysis) == summary(res_c)
        on_self_motion = (at_a <= 1e-9 and fit <= 1e-9 and e.analysis.dof == 3 and e.analysis.input_rank == 0
                          and e.analysis.locked_links == ("lower1", "lower2", "lower3"))
        verdicts.append(("(c)" if is_c else "self-motion" if on_self_motion else "neither", round(angle, 6)))
    c.true("each IM event at −90° is (c) itself or a point of the self-motion about A through (c) (sphere "
           "centres at A, platform turned rigidly about A, L = 3, lower links locked) — (label, turn in degrees)",
           bool(verdicts) and all(v[0] != "neither" for v in verdicts), verdicts)
    curve = path.curve
    y_c = curve.y_of(xc.ravel()[curve.free])
    sv = np.linalg.svd(curve.jacobian(y_c), compute_uv=False)
    c.equal("the path's Jacobian (closure + held inputs) has nullity 4 at (c)",
            int(curve.jacobian(y_c).shape[1] - np.count_nonzero(sv > 1e-9 * sv[0])), 4)
    bif = branch_directions(curve, y_c)
    c.equal("... so the branch analysis at (c) says 'degenerate' with nullity 4", (bif.status, bif.nullity),
            ("degenerate", 4))
    lengths = rsr.link_distances(files["c"])
    for axis, angle in (((1.0, 0.0, 0.0), 25.0), ((2.0, -1.0, 2.0), 70.0)):
        r = rotation(axis, angle * DEG)
        x = xc.copy()
        x[moving_about_a] = (xc[moving_about_a] - A) @ r.T + A
        moved = gen.with_coordinates(x)
        c.close(f"self-motion: (c) with platform and upper links turned {angle:g}° about A, axis {axis}: "
                "same link lengths (max |Δ|)", float(np.abs(rsr.link_distances(moved) - lengths).max()), 0.0,
                tol=1e-13)
        res = symkin.analyze(moved)
        c.equal("... same inputs (lower links untouched); L = 3, lower links locked, platform DOF 3, no IM",
                (res.dof, res.types, res.input_rank, res.platform_dof, res.locked_links),
                (3, ("DKP-input", "LIM"), 0, 3, ("lower1", "lower2", "lower3")))

    # ---- generic -> (a): the DKP position ------------------------------------------------------
    res_a = symkin.analyze(files["a"])
    path_a = trace(gen, input=DRIVE, stop=20.0, unit="deg", max_arclength=2.5)
    dkp = [e for e in path_a.events if e.kind == "DKP-input"]
    c.equal("generic → (a): one DKP-input event", len(dkp), 1)
    if dkp:
        ea = dkp[0]
        xa = xyz(files["a"])
        c.close("(a) located at its input λ = +16.2602° (degrees)", ea.input / DEG, lam["a"] / DEG, tol=1e-9)
        dist = float(np.abs(ea.coordinates - xa).max())
        c.close("(a) located within 1e-6 of the file's configuration (max |Δx|)", dist, 0.0, tol=1e-6)
        m_in, _, _ = ea.analysis.motion.restrict(gen.inputs)
        c.close("... where all three input rows over the motion space are nearly zero (largest singular value)",
                float(np.linalg.svd(m_in, compute_uv=False)[0]), 0.0, tol=1e-6)
        res_loose = symkin.analyze(gen.with_coordinates(ea.coordinates), tol=1e-6)
        c.record("path event at (a), rank tolerance 1e-6", res_loose)
        c.equal("(a) classified as fig11_3rsr_a at a rank tolerance matching that accuracy (1e-6)",
                summary(res_loose), summary(res_a))
        y_a = curve.y_of(xa.ravel()[curve.free])
        sva = np.linalg.svd(curve.jacobian(y_a), compute_uv=False)
        c.equal("(a) is a degenerate turning point: the path's Jacobian has nullity 3 there",
                int(curve.jacobian(y_a).shape[1] - np.count_nonzero(sva > 1e-9 * sva[0])), 3)
        last = path_a.points[-1]
        c.true("after (a) the input decreases again (a turning point of the motion)", last.input < ea.input,
               last.input / DEG)
        z_s = max(last.coordinates[k][2] for k in s_rows)
        z_u = max(last.coordinates[k][2] for k in moving_about_a)
        c.true("... and the platform is now below the sphere centres: the other assembly of the symmetric motion",
               z_u < z_s, (z_u, z_s))
    return c


if __name__ == "__main__":
    raise SystemExit(check().main())
