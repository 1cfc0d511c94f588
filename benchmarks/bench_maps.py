"""Benchmark of singularity maps (issue 8, part 4b), run on demand — not a test.

    python benchmarks/bench_maps.py [--n 501] [--n-rrr 201] [--baseline 2000] [--n-dask 1001]
                                    [--n-memory 2001] [--refine-n 161 ...] [--only-refine]
                                    [--skip-dask] [--skip-memory]

It measures, in one run:

1. grid points per second of ``symkin.workspace_map(..., refine=False)`` (one mode, one
   process) for the catalogue five-bar (``--n`` × ``--n``, P over [−3.5, 3.5] × [0.2, 4.4]) and
   the 3-RRR at constant orientation (C1 over ±1.5 around its model position, the platform
   rotation held), against the loop a user writes, timed in the same run on a subsample of
   ``--baseline`` grid points (a serpentine sweep of a block of the same grid around the model
   configuration, so every point starts from its neighbour's solution):
   ``scipy.optimize.root(method="hybr", jac=True, xtol=1e-12)`` on a NumPy closure (bar lengths
   of every node pair of a link, the two axis coordinates, the held platform direction; the
   :class:`UserClosure` rows of ``bench_paths.py``), then the lambdified reduced G of
   ``bench_analyze.py`` with ``numpy.linalg.eigh`` (λ_{F+1}) and the two DKP determinants
   (``det`` of the closure Jacobian with the axes fixed — DKP-output — and with the inputs
   fixed — DKP-input).  Ratio = symkin points/s ÷ baseline points/s (target ≥ 50 on the five-bar).
2. refinement cost: :func:`symkin.workspace.loci.refine` on the five-bar and 3-RRR grids of
   (1) at 201 × 201: located points, residual-and-Jacobian evaluations per located point and
   per traced curve point (``RefineStats``).
2b. refinement against the grid (``--refine-n``, default 161): ``workspace_map(..., refine=True)``
   of the catalogue five-bar and of the 3-RPR at constant orientation (``tests/workspace/models/rpr_3.toml``,
   the platform rotation held; O over the boxes of :data:`RPR_BOXES`); the time inside
   :func:`symkin.workspace.loci.refine` ("refine s") against the rest of the call ("grid s"), in the
   same call; ratio = refine s ÷ grid s (target ≤ 2, and the 3-RPR 161 × 161 map under 30 s).  The
   LIM columns give the LIM screen's share (:mod:`symkin.workspace.lim_points`): the grid's LIM
   indicator (inside "grid s") and the LIM step of refinement (inside "refine s"), and the LIM points.
3. Dask: the five-bar at ``--n-dask``² (≥ 10⁶) points, tiles of ``parallel.TILE``, in one
   process (one continuation, ``tile=0``; the default: the same tiles, batched together) and on
   a ``LocalCluster`` of 2 worker processes (cluster start-up timed apart); the grid arrays of
   the default run and the Dask run are compared.
4. peak memory of a ``--n-memory``² five-bar map (``resource.getrusage`` max RSS of a fresh
   child process, and ``tracemalloc``'s peak of Python allocations in it).

One thread per process (OMP/OpenBLAS); ``uptime`` is printed (2 shared cores here).
"""
from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.optimize import root  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import symkin  # noqa: E402
from bench_analyze import baseline_function  # noqa: E402
from bench_paths import UserClosure  # noqa: E402
from symkin.model.catalogue import get  # noqa: E402
from symkin import read_model  # noqa: E402
from symkin.workspace import loci, parallel  # noqa: E402
from symkin.workspace.grid import continue_mode  # noqa: E402
from symkin.workspace.loci import GridData, refine  # noqa: E402
from symkin.workspace.maps import GRID_ARRAYS, workspace_map  # noqa: E402
from symkin.workspace.system import map_system  # noqa: E402

FIVE = dict(x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4")


def rrr_case():
    mech = get("rrr_3")
    c1 = dict(mech.nodes)["C1"]
    return mech, dict(x=f"velocity:C1.x={c1[0] - 1.5}:{c1[0] + 1.5}", y=f"velocity:C1.y={c1[1] - 1.5}:{c1[1] + 1.5}",
                      hold=("rotation:platform",))


# ---------------------------------------------------------------------- the user's loop
class UserMap(UserClosure):
    """The user's square map system: bar rows, then ``node.x − X``, ``node.y − Y``, the held platform direction."""

    def __init__(self, mech, node: str, platform: str | None = None):
        super().__init__(mech)
        idx = mech.node_index()
        self.k = idx[node]
        self.npairs = len(self.i)
        self.platform = None
        if platform is not None:
            nodes = mech.link_nodes(platform)
            a, b = idx[nodes[0]], idx[nodes[1]]
            d = self.x0[b] - self.x0[a]
            self.platform = (a, b, math.atan2(d[1], d[0]))

    def map_residual(self, q, xy):
        r, jac_in = self.residual_and_jacobian(q, self.angles(q))
        x = self.x0.ravel().copy()
        x[self.free] = q
        x = x.reshape(self.n, 2)
        rows = [x[self.k, 0] - xy[0], x[self.k, 1] - xy[1]]
        jrows = np.zeros((2, self.n * 2))
        jrows[0, 2 * self.k], jrows[1, 2 * self.k + 1] = 1.0, 1.0
        if self.platform is not None:
            a, b, phi = self.platform
            s, c = math.sin(phi), math.cos(phi)
            d = x[b] - x[a]
            rows.append(d[0] * s - d[1] * c)
            jp = np.zeros(self.n * 2)
            jp[2 * b: 2 * b + 2] += (s, -c)
            jp[2 * a: 2 * a + 2] -= (s, -c)
            jrows = np.vstack([jrows, jp])
        res = np.concatenate([r[:self.npairs], rows])
        jac = np.vstack([jac_in[:self.npairs], jrows[:, self.free]])
        return res, jac

    def angles(self, q):
        """The inputs' current angles from their model directions (for the input rows)."""
        x = self.x0.ravel().copy()
        x[self.free] = q
        x = x.reshape(self.n, 2)
        out = []
        for _, a, b, phi0 in self.inputs:
            d = x[b] - x[a]
            out.append(math.atan2(d[1], d[0]) - phi0)
        return np.array(out)


def serpentine(system, xs, ys, count):
    """About ``count`` grid indices of a square block around the model configuration, in a serpentine order."""
    a0 = system.axis_values(system.q0[None])[0]
    i0, j0 = int(np.argmin(abs(xs - a0[0]))), int(np.argmin(abs(ys - a0[1])))
    side = int(math.ceil(math.sqrt(count)))
    i_lo = int(np.clip(i0 - side // 2, 0, len(xs) - side))
    j_lo = int(np.clip(j0 - side // 2, 0, len(ys) - side))
    out = []
    for r, j in enumerate(range(j_lo, j_lo + side)):
        cols = range(i_lo, i_lo + side)
        out += [(j, i) for i in (cols if r % 2 == 0 else reversed(cols))]
    return out[:count]


def rows_sweep(system, xs, ys, count):
    """About ``count`` grid indices of whole grid rows through the model configuration, serpentine (assembled or not)."""
    a0 = system.axis_values(system.q0[None])[0]
    j0 = int(np.argmin(abs(ys - a0[1])))
    nrows = max(1, int(math.ceil(count / len(xs))))
    j_lo = int(np.clip(j0 - nrows // 2, 0, len(ys) - nrows))
    out = []
    for r, j in enumerate(range(j_lo, j_lo + nrows)):
        cols = range(len(xs))
        out += [(j, i) for i in (cols if r % 2 == 0 else reversed(cols))]
    return out[:count]


def run_baseline(mech, node, platform, xs, ys, points, q0, mobility):
    user = UserMap(mech, node, platform)
    f_g = baseline_function(mech)
    q = q0.copy()
    fails = 0
    lam, d_out, d_in = [], [], []
    t0 = time.perf_counter()
    for j, i in points:
        sol = root(user.map_residual, q, args=(np.array([xs[i], ys[j]]),), jac=True, method="hybr",
                   options={"xtol": 1e-12})
        if not sol.success:
            fails += 1
            continue
        q = sol.x
        w = np.linalg.eigh(f_g(*q))[0]
        lam.append(w[mobility])
        _, jac_out = user.map_residual(q, np.array([xs[i], ys[j]]))
        _, jac_in = user.residual_and_jacobian(q, user.angles(q))
        d_out.append(np.linalg.det(jac_out))
        d_in.append(np.linalg.det(jac_in))
    dt = time.perf_counter() - t0
    return len(points) / dt, fails


def grid_rate(mech, kw, n):
    workspace_map(mech, n=5, refine=False, **kw)  # compile / load the artefacts once
    t0 = time.perf_counter()
    m = workspace_map(mech, n=n, refine=False, **kw)
    dt = time.perf_counter() - t0
    return n * n / dt, dt, m


def section_rates(args):
    print("\n1. grid points per second (one mode, no refinement, one process)")
    rows = []
    for name, (mech, kw), n, node, platform in (
            ("five-bar", (get("five_bar"), FIVE), args.n, "P", None),
            ("3-RRR const. orientation", rrr_case(), args.n_rrr, "C1", "platform")):
        rate, dt, m = grid_rate(mech, kw, n)
        s = map_system(mech, kw["x"].split("=")[0], kw["y"].split("=")[0], hold=kw.get("hold", ()))
        frac = m.modes[0].fraction
        pts = serpentine(s, m.xs, m.ys, args.baseline)
        base, fails = run_baseline(mech, node, platform, m.xs, m.ys, pts, s.q0, mech.mobility_value)
        pts_r = rows_sweep(s, m.xs, m.ys, args.baseline)
        base_r, fails_r = run_baseline(mech, node, platform, m.xs, m.ys, pts_r, s.q0, mech.mobility_value)
        rows.append((name, n, rate, dt, base, fails, frac))
        print(f"   {name}: {n}x{n} in {dt:.2f} s = {rate:,.0f} grid points/s, {rate * frac:,.0f} assembled "
              f"points/s (assembled {100 * frac:.1f} %)")
        print(f"      user loop, whole grid rows through the model ({len(pts_r)} points, {fails_r} not assembled): "
              f"{base_r:,.0f} grid points/s -> ratio {rate / base_r:.1f}x per grid point")
        print(f"      user loop, block around the model ({len(pts)} points, {fails} not assembled): "
              f"{base:,.0f} points/s -> ratio {rate * frac / base:.1f}x per assembled point")
    return rows


def section_refine():
    print("\n2. refinement cost (loci.refine on a 201 x 201 grid)")
    for name, (mech, kw) in (("five-bar", (get("five_bar"), FIVE)), ("3-RRR const. orientation", rrr_case())):
        (lx, xr), (ly, yr) = kw["x"].split("="), kw["y"].split("=")
        s = map_system(mech, lx, ly, hold=kw.get("hold", ()))
        xs = np.linspace(*map(float, xr.split(":")), 201)
        ys = np.linspace(*map(float, yr.split(":")), 201)
        xi = s.to_internal(np.column_stack([xs, np.zeros_like(xs)]))[:, 0]
        yi = s.to_internal(np.column_stack([np.zeros_like(ys), ys]))[:, 1]
        g = continue_mode(s, xi, yi, s.q0)
        grid = GridData(xs, ys, g.assembled, g.dkp_input, g.dkp_output, g.im_indicator, configuration=g.config)
        t0 = time.perf_counter()
        curves, points, st = refine(s, grid)
        dt = time.perf_counter() - t0
        print(f"   {name}: {len(curves)} curves ({', '.join(sorted({c.kind for c in curves}))}), {len(points)} points, "
              f"{st.located} located ({st.crossings} sign brackets, {st.folds} fold brackets, {st.dips} dips "
              f"subdivided with {st.subdivided} quadtree points, {st.double_zeros} double zeros, {st.duplicates} "
              f"duplicates): {st.evaluations_per_located_point:.1f} evaluations per located point; tracing "
              f"{st.trace_evaluations} evaluations for {st.traced_points} curve points "
              f"({st.trace_evaluations / max(st.traced_points, 1):.1f} per point); {dt:.2f} s")


#: 3-RPR boxes of O (the platform rotation held): the map tests' box (tests/workspace/test_map_truth.py); ±1.5
#: around the model position, whose corner (1, 0.5) puts C1 on A1 (leg 1 of zero length: a closed type-1
#: locus there whose meetings with the conic seed many curves); a wide box over the base with IM-indicator minima
RPR_BOXES = {"tests' box": ((1.5, 4.5), (0.75, 3.25)), "±1.5": ((1.0, 4.0), (0.5, 3.5)),
             "wide": ((-1.0, 6.0), (-1.0, 5.0))}


def rpr_case(box="tests' box"):
    mech = read_model(HERE.parent / "tests" / "workspace" / "models" / "rpr_3.toml")
    (x0, x1), (y0, y1) = RPR_BOXES[box]
    return mech, dict(x=f"velocity:O.x={x0}:{x1}", y=f"velocity:O.y={y0}:{y1}", hold=("rotation:platform",))


def _timer(owner, name, spent: list, k: int):
    """Wrap ``owner.name`` so that its time adds to ``spent[k]``; returns the original."""
    inner = getattr(owner, name)

    def timed(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            spent[k] += time.perf_counter() - t0

    setattr(owner, name, timed)
    return inner


def timed_map(mech, kw, n, lim_times: list | None = None):
    """``workspace_map(refine=True)`` with the time spent in ``loci.refine`` apart: (grid s, refine s, map).

    ``lim_times`` (a list) receives the LIM screen's share: the grid's LIM indicator
    (``LimIndicator.smallest``, inside "grid s") and the LIM step of refinement (inside "refine s").
    """
    spent = [0.0, 0.0, 0.0]
    workspace_map(mech, n=5, refine=False, **kw)  # compile / load the artefacts once
    patched = [(loci, "refine", _timer(loci, "refine", spent, 0))]
    if hasattr(loci, "_lim_points"):
        from symkin.workspace.lim_points import LimIndicator

        patched += [(LimIndicator, "smallest", _timer(LimIndicator, "smallest", spent, 1)),
                    (loci, "_lim_points", _timer(loci, "_lim_points", spent, 2))]
    try:
        t0 = time.perf_counter()
        m = workspace_map(mech, n=n, refine=True, **kw)
        total = time.perf_counter() - t0
    finally:
        for owner, name, inner in patched:
            setattr(owner, name, inner)
    if lim_times is not None:
        lim_times[:] = spent[1:]
    return total - spent[0], spent[0], m


def section_refine_ratio(sizes, boxes=tuple(RPR_BOXES)):
    print("\n2b. refinement against the grid (workspace_map(refine=True), one process)")
    print("   | mechanism | n | grid s | refine s | ratio | curves | points | LIM: grid s | refine s | points |")
    print("   |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    cases = [("five-bar", (get("five_bar"), FIVE))] + [(f"3-RPR const. orientation, {b}", rpr_case(b)) for b in boxes]
    for name, (mech, kw) in cases:
        for n in sizes:
            lim = [math.nan, math.nan]
            grid_s, refine_s, m = timed_map(mech, kw, n, lim)
            n_lim = sum(p.kind == "LIM" for p in m.points)
            print(f"   | {name} | {n} | {grid_s:.2f} | {refine_s:.2f} | {refine_s / grid_s:.2f} | "
                  f"{len(m.curves)} | {len(m.points)} | {lim[0]:.2f} | {lim[1]:.2f} | {n_lim} |", flush=True)


def section_dask(n):
    print(f"\n3. Dask: five-bar {n}x{n} = {n * n:,} points, tiles of {parallel.TILE}, no refinement")
    mech = get("five_bar")
    workspace_map(mech, n=5, refine=False, **FIVE)
    t0 = time.perf_counter()
    workspace_map(mech, n=n, refine=False, tile=0, **FIVE)
    t_one = time.perf_counter() - t0
    t0 = time.perf_counter()
    ser = workspace_map(mech, n=n, refine=False, tile=parallel.TILE, **FIVE)
    t_ser = time.perf_counter() - t0
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    t_start = time.perf_counter() - t0
    try:
        workspace_map(mech, n=9, refine=False, tile=4, client=client, **FIVE)  # workers build their evaluators
        t0 = time.perf_counter()
        dsk = workspace_map(mech, n=n, refine=False, tile=parallel.TILE, client=client, **FIVE)
        t_dask = time.perf_counter() - t0
    finally:
        client.close()
        cluster.close()
    same = all(np.array_equal(getattr(ser.modes[0], k), getattr(dsk.modes[0], k), equal_nan=True) for k in GRID_ARRAYS)
    print(f"   one process, one continuation (tile=0): {t_one:.1f} s ({n * n / t_one:,.0f} points/s)")
    print(f"   one process, tiles (the default):       {t_ser:.1f} s ({n * n / t_ser:,.0f} points/s)")
    print(f"   Dask, 2 local workers, tiles:  {t_dask:.1f} s ({n * n / t_dask:,.0f} points/s), "
          f"{t_ser / t_dask:.2f}x the serial tiles (cluster start {t_start:.1f} s, not included); "
          f"grid arrays identical to the serial tiles: {same}")


MEMORY_CHILD = """
import resource, sys, time, tracemalloc
from symkin.model.catalogue import get
from symkin.workspace.maps import workspace_map
n = int(sys.argv[1])
mech = get("five_bar")
workspace_map(mech, n=5, refine=False, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4")
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
tracemalloc.start()
t0 = time.perf_counter()
m = workspace_map(mech, n=n, refine=False, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4")
dt = time.perf_counter() - t0
peak = tracemalloc.get_traced_memory()[1]
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, base, peak, dt, m.modes[0].fraction)
"""


def section_memory(n):
    print(f"\n4. peak memory of a {n}x{n} five-bar map (one mode, no refinement, fresh process)")
    out = subprocess.run([sys.executable, "-c", MEMORY_CHILD, str(n)], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=str(HERE.parent)), check=True).stdout.split()
    rss, base, peak, dt = int(out[0]), int(out[1]), int(out[2]), float(out[3])
    print(f"   max RSS {rss / 1024:.0f} MB (after start-up and compile {base / 1024:.0f} MB); tracemalloc peak "
          f"{peak / 2**20:.0f} MB; {dt:.1f} s under tracemalloc")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=501)
    p.add_argument("--n-rrr", type=int, default=201)
    p.add_argument("--baseline", type=int, default=2000)
    p.add_argument("--n-dask", type=int, default=1001)
    p.add_argument("--n-memory", type=int, default=2001)
    p.add_argument("--refine-n", type=int, nargs="+", default=[161])
    p.add_argument("--rpr-boxes", nargs="+", default=list(RPR_BOXES), choices=list(RPR_BOXES))
    p.add_argument("--only-refine", action="store_true", help="section 2b only")
    p.add_argument("--skip-dask", action="store_true")
    p.add_argument("--skip-memory", action="store_true")
    args = p.parse_args(argv)
    print(f"symkin {getattr(symkin, '__version__', '?')}, python {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs; uptime: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}")
    if args.only_refine:
        section_refine_ratio(args.refine_n, args.rpr_boxes)
        return 0
    section_rates(args)
    section_refine()
    section_refine_ratio(args.refine_n, args.rpr_boxes)
    if not args.skip_dask:
        try:
            import distributed  # noqa: F401
        except ImportError:
            print("\n3. Dask: skipped (needs the dask extra: pip install -e '.[dask]')")
        else:
            section_dask(args.n_dask)
    if not args.skip_memory:
        section_memory(args.n_memory)
    print(f"\nuptime at the end: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
