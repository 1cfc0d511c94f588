"""Benchmark of path continuation (issue 4), run on demand — not a test.

    python benchmarks/bench_paths.py [--repeat R] [--steps N]

For the appendix four-bar, the 3-RRR (``rrr_3``), the spatial RSSR (``rssr``) and the
3-RSR of Fig. 12 (``papers_examples/fig12_3rsr_b.toml``) it measures, in one run:

1. ``symkin.paths.trace.trace`` over an input range: wall time, accepted points per second,
   residual evaluations in total and for each located event (``Path.residual_evaluations``,
   ``PathEvent.evaluations``);
2. the continuation alone (``continue_curve`` on the trace's curve problem, no indicators or
   events): accepted steps per second and Newton (corrector) iterations per step;
3. one corrector iteration in isolation: ``newton`` from a predictor ``y + h·t`` with the
   pseudo-arclength hyperplane, total time divided by the iterations it took;
4. the baseline a user would write: a NumPy closure residual (bar lengths of every node pair
   in a link, plus each input angle fixed) with its analytic Jacobian, solved by
   ``scipy.optimize.root(method="hybr", jac=True, xtol=1e-12)`` in a loop at fixed input
   steps, warm-started from the previous solution; and the same without a Jacobian
   (finite differences, what ``root(fun, x0)`` does by default).  One hybr iteration
   evaluates the residual and Jacobian once (``nfev``), so µs per ``nfev`` is its cost
   per Newton step.  The baseline's last configuration is checked against the trace's;
5. the classification of the located events: ``analyze(mech.with_coordinates(x))`` (the model
   rebuilt at the event, as before) against ``classify_event`` (from the curve's evaluator
   rows where they cover the model), µs per event.

Ratios are baseline / symkin.  For the four-bar it also checks the issue's target: both dead
centres located within 1e-10 rad of the law of cosines in fewer than 5,000 residual
evaluations for the full revolution.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path as FilePath

import numpy as np
from scipy.optimize import root

import symkin
from symkin.curves.stepper import Settings, SteppingError, continue_curve, correct as newton, tangent
from symkin.paths.trace import classify_event, curve_rows_cover, trace

ROOT = FilePath(__file__).resolve().parents[1]


# ---------------------------------------------------------------------- the user's baseline
class UserClosure:
    """Closure equations as a user writes them in NumPy, with the F inputs fixed.

    Rows: ``|x_i − x_j|² − L_ij²`` for every node pair of every link that has a free node,
    then one row per input: the driven / held link direction at its prescribed angle
    (planar: ``d × u(φ) = 0``; about a fixed axis ``a``: ``(r × w(θ))·a = 0``).
    Unknowns: the free nodal coordinates (model units).
    """

    def __init__(self, mech: symkin.Mechanism):
        if mech.sliders:
            raise NotImplementedError("the baseline handles bars, bodies and rotation inputs only")
        self.mech = mech
        self.x0 = np.array([c for _, c in mech.nodes], float)
        n, dim = self.x0.shape
        self.n, self.dim = n, dim
        fixed = set(mech.fixed)
        self.free = np.repeat([name not in fixed for name in mech.node_names], dim)
        idx = mech.node_index()
        pairs = []
        for _, nodes in mech.links:
            for a in range(len(nodes)):
                for b in range(a + 1, len(nodes)):
                    if nodes[a] in fixed and nodes[b] in fixed:
                        continue
                    pairs.append((idx[nodes[a]], idx[nodes[b]]))
        self.i = np.array([p[0] for p in pairs])
        self.j = np.array([p[1] for p in pairs])
        self.l2 = np.sum((self.x0[self.i] - self.x0[self.j]) ** 2, axis=1)
        self.inputs = [self._input(p) for p in mech.inputs]
        self.m = len(pairs) + len(self.inputs)
        if self.m != int(self.free.sum()):
            raise NotImplementedError(f"{mech.name}: {self.m} equations for {int(self.free.sum())} unknowns "
                                      "(not a square system)")

    def _input(self, p):
        x0, idx, fixed = self.x0, self.mech.node_index(), set(self.mech.fixed)
        nodes = self.mech.link_nodes(p.target[0])
        first = idx[nodes[0]]
        if self.dim == 2:
            far = max((idx[n] for n in nodes), key=lambda k: np.linalg.norm(x0[k] - x0[first]))
            d = x0[far] - x0[first]
            return ("planar", first, far, math.atan2(d[1], d[0]))
        if not isinstance(p.axis[0], str):
            raise NotImplementedError("axis given by a vector")
        origin, a = x0[idx[p.axis[0]]], x0[idx[p.axis[1]]] - x0[idx[p.axis[0]]]
        a = a / np.linalg.norm(a)
        moving = [idx[n] for n in nodes if n not in fixed]

        def radial(k):
            r = x0[k] - origin
            return r - (r @ a) * a
        k = max(moving, key=lambda k: np.linalg.norm(radial(k)))
        r0 = radial(k)
        return ("axis", k, origin, a, r0, np.cross(a, r0), float(np.linalg.norm(r0)))

    def residual_and_jacobian(self, q: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = self.x0.ravel().copy()
        x[self.free] = q
        x = x.reshape(self.n, self.dim)
        d = x[self.i] - x[self.j]
        r = np.empty(self.m)
        jac = np.zeros((self.m, self.n * self.dim))
        npairs = len(self.i)
        r[:npairs] = np.sum(d * d, axis=1) - self.l2
        rows = np.arange(npairs)
        for c in range(self.dim):
            jac[rows, self.dim * self.i + c] = 2 * d[:, c]
            jac[rows, self.dim * self.j + c] = -2 * d[:, c]
        for row, (spec, theta) in enumerate(zip(self.inputs, angles), start=npairs):
            if spec[0] == "planar":
                _, a_, b_, phi0 = spec
                s, c = math.sin(phi0 + theta), math.cos(phi0 + theta)
                dd = x[b_] - x[a_]
                r[row] = dd[0] * s - dd[1] * c
                jac[row, 2 * b_: 2 * b_ + 2] += (s, -c)
                jac[row, 2 * a_: 2 * a_ + 2] -= (s, -c)
            else:
                _, k, origin, a, r0, ar0, norm0 = spec
                w = r0 * math.cos(theta) + ar0 * math.sin(theta)
                g = np.cross(w, a) / norm0
                r[row] = float((x[k] - origin) @ g)
                jac[row, 3 * k: 3 * k + 3] = g
        return r, jac[:, self.free]

    def q0(self) -> np.ndarray:
        return self.x0.ravel()[self.free].copy()


@dataclass
class Baseline:
    solves: int
    seconds: float
    nfev: int
    njev: int
    seconds_fd: float
    nfev_fd: int
    final: np.ndarray
    failures: int


def run_baseline(mech, angles_deg: np.ndarray) -> Baseline:
    """Fixed input steps of the first input (the others held), ``scipy.optimize.root`` each."""
    user = UserClosure(mech)
    nin = len(user.inputs)

    def thetas(a):
        out = np.zeros(nin)
        out[0] = math.radians(a)
        return out

    results = {}
    for mode in ("jac", "fd"):
        q = user.q0()
        nfev = njev = failures = 0
        t0 = time.perf_counter()
        for a in angles_deg:
            th = thetas(a)
            if mode == "jac":
                sol = root(user.residual_and_jacobian, q, args=(th,), jac=True, method="hybr",
                           options={"xtol": 1e-12})
                njev += int(getattr(sol, "njev", 0))
            else:
                sol = root(lambda qq, tt=th: user.residual_and_jacobian(qq, tt)[0], q, method="hybr",
                           options={"xtol": 1e-12})
            nfev += int(sol.nfev)
            failures += int(not sol.success)
            q = sol.x
        results[mode] = (time.perf_counter() - t0, nfev, njev, failures, q)
    (tj, nf, nj, fj, qj), (tf, nff, _, _, _) = results["jac"], results["fd"]
    x = user.x0.ravel().copy()
    x[user.free] = qj
    return Baseline(len(angles_deg), tj, nf, nj, tf, nff, x.reshape(user.x0.shape), fj)


# ---------------------------------------------------------------------- symkin measurements
class CountingProblem:
    """Counts residual(+Jacobian) evaluations of a curve problem (used only for counting, not timing)."""

    def __init__(self, problem):
        self.p, self.evals = problem, 0

    def residual(self, y):
        self.evals += 1
        return self.p.residual(y)

    def jacobian(self, y):
        return self.p.jacobian(y)

    def residual_and_jacobian(self, y):
        self.evals += 1
        return self.p.residual_and_jacobian(y)


def run_continuation(curve, steps: int) -> tuple[float, int, list, str]:
    """``steps`` accepted steps of ``continue_curve`` from the model's configuration."""
    y0 = curve.y0()
    t0 = tangent(curve, y0)
    pts, reason = [], "steps"
    start = time.perf_counter()
    try:
        for cp in continue_curve(curve, y0, t0, Settings()):
            pts.append(cp)
            if len(pts) > steps:
                break
    except SteppingError as exc:
        reason = f"stopped: {exc}"
    return time.perf_counter() - start, len(pts) - 1, pts, reason


def generated_microbenchmark(curve, points, h: float = 0.05) -> tuple[float, int] | None:
    """Time the generated (compiled) corrector from predictors ``y + h t``: (seconds, Newton iterations).

    This is the corrector ``trace`` uses for square systems; None when it has none."""
    fast = curve.fast_corrector
    if fast is None:
        return None
    jobs = [(cp.y + h * cp.t, cp.t) for cp in points]
    before = fast.steps
    start = time.perf_counter()
    for pred, t in jobs:
        try:
            fast.correct(pred, t, 1e-12, 10)
        except symkin.NotConvergedError:
            continue
    return time.perf_counter() - start, fast.steps - before


def corrector_microbenchmark(curve, points, h: float = 0.05) -> tuple[float, int, float, float]:
    """Time ``newton`` from predictors ``y + h t`` at the given points: (seconds, iterations, µs per
    residual+Jacobian call, µs per least-squares solve of the augmented system)."""
    jobs = []
    for cp in points:
        pred = cp.y + h * cp.t

        def hyperplane(y, p=pred, tt=cp.t):
            return np.array([tt @ (y - p)]), tt[None, :]
        jobs.append((pred, hyperplane))
    iters = 0
    start = time.perf_counter()
    for pred, hp in jobs:
        try:
            _, k, _ = newton(curve, pred, extra=hp, tol=1e-12, max_iterations=10)
        except symkin.NotConvergedError:
            continue
        iters += k
    seconds = time.perf_counter() - start
    y = points[len(points) // 2].y
    reps = 2000
    t = time.perf_counter()
    for _ in range(reps):
        r, j = curve.residual_and_jacobian(y)
    call = (time.perf_counter() - t) / reps * 1e6
    a = np.vstack([j, points[0].t[None, :]])
    b = np.concatenate([r, [0.0]])
    t = time.perf_counter()
    for _ in range(reps):
        np.linalg.lstsq(a, b, rcond=None)
    solve = (time.perf_counter() - t) / reps * 1e6
    return seconds, iters, call, solve


def dead_centres(mech) -> list[float]:
    """Absolute crank angles where crank and coupler align (law of cosines), radians."""
    x = {n: np.array(c) for n, c in mech.nodes}
    crank, coupler = np.linalg.norm(x["B"] - x["A"]), np.linalg.norm(x["C"] - x["B"])
    rocker, g = np.linalg.norm(x["C"] - x["D"]), np.linalg.norm(x["D"] - x["A"])
    base = math.atan2(*(x["D"] - x["A"])[::-1])
    out = []
    for ac, turn in ((coupler + crank, 0.0), (coupler - crank, math.pi)):
        phi = math.acos((ac * ac + g * g - rocker * rocker) / (2 * ac * g))
        out += [math.remainder(base + s * phi + turn, 2 * math.pi) for s in (1, -1)]
    return out


# ---------------------------------------------------------------------- driver
CASES = [
    # label, model, trace stop [deg], baseline input range [deg] (monotone, before any turning point)
    ("four-bar (appendix)", "fourbar_appendix", 360.0, np.arange(1.0, 361.0, 1.0)),
    ("3-RRR (rrr_3)", "rrr_3", 360.0, np.arange(0.25, 18.01, 0.25)),
    ("RSSR (spatial)", "rssr", 360.0, np.arange(1.0, 86.0, 1.0)),
    ("3-RSR (Fig. 12, b)", ROOT / "papers_examples" / "fig12_3rsr_b.toml", 60.0, None),
]


def classification_times(path, located, repeat) -> tuple[float, float]:
    """Seconds per located event: ``analyze`` of the rebuilt model (old) and ``classify_event`` (new).

    The two are timed in turn, ``repeat`` rounds (after one call of each), each keeping its
    best round: the machine's load falls on both alike.
    """
    mech, curve = path.mechanism, path.curve
    reps = 20

    def old():
        for _ in range(reps):
            for e in located:
                symkin.analyze(mech.with_coordinates(e.coordinates))

    def new():
        for _ in range(reps):
            for e in located:
                classify_event(curve, e.y)

    classify_event(curve, located[0].y)  # builds the curve's row Function once
    t_old = t_new = math.inf
    for _ in range(repeat):
        t_old = min(t_old, best_of(old, 1)[0])
        t_new = min(t_new, best_of(new, 1)[0])
    n = reps * len(located)
    return t_old / n, t_new / n


def best_of(fn, repeat):
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (best is kept)")
    ap.add_argument("--steps", type=int, default=300, help="accepted steps for the continuation-only timing")
    args = ap.parse_args(argv)
    print(f"symkin {symkin.__version__}, numpy {np.__version__}, python {sys.version.split()[0]}")
    print("times: best of", args.repeat, "runs; µs = microseconds\n")
    summary = []
    for label, model, stop, base_range in CASES:
        mech = symkin.read_model(model) if isinstance(model, FilePath) else symkin.catalogue.get(model)
        print(f"== {label}: {mech.name}")
        t_trace, path = best_of(lambda: trace(mech, stop=stop, unit="deg"), args.repeat)
        npts = len(path.points) - 1
        sing = path.singular_events()
        print(f"  trace 0 -> {stop:g} deg: {t_trace * 1e3:.1f} ms, {npts} steps ({npts / t_trace:,.0f} steps/s), "
              f"stop: {path.stop_reason}, residual evaluations: {path.residual_evaluations}")
        for e in path.events:
            print(f"    event {e.kind:10s} input {math.degrees(e.input):+12.6f} deg  "
                  f"{e.evaluations:4d} residual evaluations to locate")
        if sing:
            own = [e.evaluations for e in sing]
            print(f"  per located singular event: {np.mean(own):.1f} residual evaluations to locate it "
                  f"(whole trace / events: {path.residual_evaluations / len(sing):.0f})")
        located = [e for e in path.events if e.analysis is not None]
        if located:
            t_old, t_new = classification_times(path, located, args.repeat)
            how = "curve rows" if curve_rows_cover(path.curve) else "falls back to analyze"
            print(f"  classification per event ({how}): analyze(mech.with_coordinates(x)) {t_old * 1e6:.0f} µs, "
                  f"classify_event {t_new * 1e6:.0f} µs ({t_old / t_new:.2f}x)")

        curve = path.curve
        runs = [run_continuation(curve, args.steps) for _ in range(args.repeat)]
        t_cont = min(r[0] for r in runs)
        _, nsteps, pts, reason = runs[0]
        inputs = [curve.input_value(p.y) for p in pts]
        inputs = np.unwrap(inputs) if path.kind == "angle" else np.array(inputs)
        dinput = float(np.mean(np.abs(np.diff(inputs))))
        dinput = math.degrees(dinput) if path.kind == "angle" else dinput
        counter = CountingProblem(curve)
        y0 = curve.y0()
        for k, _ in enumerate(continue_curve(counter, y0, tangent(curve, y0), Settings())):
            if k >= nsteps:
                break
        corr_iters = sum(p.corrector_iterations for p in pts[1:])
        print(f"  continuation only: {nsteps} steps in {t_cont * 1e3:.1f} ms = {nsteps / t_cont:,.0f} steps/s, "
              f"{t_cont / nsteps * 1e6:.0f} µs/step, mean |input change| {dinput:.2f} "
              f"{'deg' if path.kind == 'angle' else 'model units'}/step; {counter.evals / nsteps:.2f} "
              f"residual+Jacobian evaluations/step ({corr_iters / nsteps:.2f} corrector iterations/accepted "
              f"step) [{reason}]")
        micro = [corrector_microbenchmark(curve, pts[1:]) for _ in range(args.repeat)]
        sec, iters, call, solve = min(micro, key=lambda m: m[0] / max(m[1], 1))
        us_lsq = sec / iters * 1e6
        print(f"  least-squares corrector (NumPy; the fallback for over-constrained systems): {us_lsq:.1f} µs per "
              f"Newton iteration ({iters} iterations); of which residual+Jacobian call {call:.1f} µs, "
              f"least-squares solve {solve:.1f} µs")
        gen = [generated_microbenchmark(curve, pts[1:]) for _ in range(args.repeat)]
        if gen[0] is not None:
            gsec, giters = min(gen, key=lambda m: m[0] / max(m[1], 1))
            us_corr = gsec / giters * 1e6
            kind = "compiled C" if curve.fast_corrector.compiled else "in-process CasADi"
            print(f"  generated corrector ({kind}, buffer interface; what trace uses): {us_corr:.2f} µs per "
                  f"Newton iteration including the Python loop ({giters} iterations)")
        else:
            us_corr = us_lsq

        row = dict(label=label, trace_ms=t_trace * 1e3, steps_s=nsteps / t_cont, us_corr=us_corr,
                   evals=path.residual_evaluations, events=len(sing))
        if base_range is not None:
            _, base = best_of(lambda: run_baseline(mech, base_range), 1)
            ref = trace(mech, stop=float(base_range[-1]), unit="deg")
            diff = float(np.abs(base.final - ref.points[-1].coordinates).max()) / mech.length_scale
            us_nfev = base.seconds / base.nfev * 1e6
            print(f"  baseline scipy root (hybr, analytic Jacobian, xtol 1e-12): {base.solves} solves at fixed "
                  f"input steps ({base_range[0]:g}..{base_range[-1]:g} deg) in {base.seconds * 1e3:.1f} ms = "
                  f"{base.seconds / base.solves * 1e6:.0f} µs/solve, {base.nfev / base.solves:.1f} nfev/solve, "
                  f"{base.njev / base.solves:.1f} njev/solve -> {us_nfev:.1f} µs per Newton step; "
                  f"failures {base.failures}")
            iters_per_solve = base.nfev / base.solves  # hybr iterations per solve (one f+J evaluation each)
            us_fd_step = base.seconds_fd / base.solves / iters_per_solve * 1e6
            print(f"  baseline without Jacobian (finite differences, root's default): "
                  f"{base.seconds_fd / base.solves * 1e6:.0f} µs/solve, {base.nfev_fd / base.solves:.1f} nfev/solve "
                  f"-> {us_fd_step:.1f} µs per Newton step (solve time / the {iters_per_solve:.1f} iterations per "
                  f"solve of the analytic-Jacobian run)")
            print(f"  baseline vs trace at {base_range[-1]:g} deg: max |Δx| / length scale = {diff:.1e}")
            print(f"  ratio per Newton step (baseline / symkin corrector): {us_nfev / us_corr:.2f}x with the analytic "
                  f"Jacobian, {us_fd_step / us_corr:.2f}x with finite differences")
            print(f"  per configuration: baseline {base.seconds / base.solves * 1e6:.0f} µs/solve at input steps of "
                  f"{base_range[1] - base_range[0]:g} deg; symkin continuation {t_cont / nsteps * 1e6:.0f} µs per "
                  f"accepted step of {dinput:.2f} deg on average")
            row.update(us_base=us_nfev, ratio=us_nfev / us_corr, us_fd=us_fd_step, ratio_fd=us_fd_step / us_corr)
        else:
            print("  baseline: n/a (the six coplanar platform nodes make the all-pairs closure rank deficient "
                  "out of plane: not a square well-posed system for hybr)")
        if model == "fourbar_appendix":
            closed = dead_centres(mech)
            errs = [min(abs(math.remainder(e.absolute - c, 2 * math.pi)) for c in closed)
                    for e in sing if e.kind == "DKP-output"]
            ok = len(errs) == 2 and max(errs) <= 1e-10 and path.residual_evaluations < 5000
            print(f"  target: full revolution, both dead centres to 1e-10 rad, < 5,000 residual evaluations: "
                  f"errors {', '.join(f'{e:.1e}' for e in errs)} rad, {path.residual_evaluations} evaluations "
                  f"-> {'MET' if ok else 'NOT MET'}")
        if model == "rrr_3":
            print(f"  target: corrector step <= 5 µs and >= 15x the baseline: {us_corr:.1f} µs, "
                  f"{row.get('ratio', float('nan')):.2f}x (analytic) / {row.get('ratio_fd', float('nan')):.2f}x (FD) "
                  f"-> {'MET' if us_corr <= 5 and row.get('ratio_fd', 0) >= 15 else 'NOT MET'}")
        summary.append(row)
        print()

    print("columns: trace time; continuation-only steps/s; µs per corrector (Newton) iteration; baseline µs per")
    print("Newton step with analytic Jacobian (jac) and finite differences (fd); ratios baseline/symkin; residual")
    print("evaluations of the whole trace; located singular events")
    print(f"{'mechanism':22s} {'trace ms':>8s} {'steps/s':>8s} {'µs/corr':>8s} {'jac µs':>7s} {'fd µs':>7s} "
          f"{'jac x':>6s} {'fd x':>6s} {'evals':>6s} {'events':>6s}")
    nan = float("nan")
    for r in summary:
        print(f"{r['label']:22s} {r['trace_ms']:8.1f} {r['steps_s']:8,.0f} {r['us_corr']:8.1f} "
              f"{r.get('us_base', nan):7.1f} {r.get('us_fd', nan):7.1f} {r.get('ratio', nan):6.2f} "
              f"{r.get('ratio_fd', nan):6.2f} {r['evals']:6d} {r['events']:6d}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
