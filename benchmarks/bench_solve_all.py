"""Benchmark of ``symkin.solve_all`` (issue 9 §1) and ``symkin singularities`` (§2), run on demand — not a test.

    PYTHONPATH=$PWD /work/venv/bin/python benchmarks/bench_solve_all.py [--repeat R] [--only solve_all|parameter|query|singularities] [--baseline DIR]

For each example of the truth tests (``tests/solutions/test_solve_all.py``) it prints the
wall time of ``solve_all`` (best of R, the evaluators already built once), the time of the
homotopy alone, the system given to the solver (unknowns after elimination, equations before
squaring up), the paths tracked and the real / complex / at-infinity counts.  Needs the extra
``symkin[global]``.

``--only parameter`` times the parameter homotopy (issue 17 §1) against the total-degree solve,
query by query, in the same run.  ``--only query`` times the whole later query of the command
line, ``symkin modes gough_stewart_66.toml --at slide:s1=… --no-progress`` in a fresh process
(imports, the model's equations, the checks, the tracking of the cached start solutions,
labelling and printing; the target is at most 2 s), against the imports alone and the
``solve_all`` call alone in the same run; ``--baseline DIR`` also times the code in ``DIR``
(e.g. ``git worktree add /tmp/base <commit>``), alternating, and checks the same output.

The second table times ``symkin.singularities`` (the command's work, without printing) on the
appendix four-bar (a Grashof crank-rocker) and the catalogue's Watt II six-bar: total seconds,
the seconds of the square DKP systems' homotopies, their paths, the circuits, the singular
configurations and whether the cross-check agrees.  Bertini starts each homotopy with random
constants, so the times vary from run to run: the best and the worst of R are printed.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from symkin.model import catalogue  # noqa: E402
from symkin.solutions import solve_all  # noqa: E402
from tests.solutions.test_solve_all import rpr_model  # noqa: E402


def examples():
    yield "four-bar (fourbar_appendix), crank +30°", catalogue.get("fourbar_appendix"), {"rotation:crank": 30}, "deg"
    yield "five-bar (five_bar), P moved (0.1, -0.2)", catalogue.get("five_bar"), \
        {"velocity:P.x": 0.1, "velocity:P.y": -0.2}, "rad"
    yield "3-RRR (rrr_3), pose", catalogue.get("rrr_3"), \
        {"velocity:C1.x": 0.05, "velocity:C1.y": -0.05, "rotation:platform": 5}, "deg"
    m, values = rpr_model()
    yield "3-RPR forward (Gosselin-Sefrioui-Richard)", m, values, "rad"
    yield "RSSR (rssr), crank +20°", catalogue.get("rssr"), {"rotation:crank[O1-O1b]": 20}, "deg"
    yield "Peaucellier (peaucellier), crank +10°", catalogue.get("peaucellier"), {"rotation:crank": 10}, "deg"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", choices=("solve_all", "parameter", "query", "singularities"), default=None)
    ap.add_argument("--baseline", metavar="DIR", default=None,
                    help="--only query: also time the command of the code in DIR (e.g. a git worktree of an "
                         "earlier commit), alternating, and check it prints the same")
    ap.add_argument("--butterfly", action="store_true",
                    help="also run singularities on the double butterfly (minutes: its rounds of seeds)")
    args = ap.parse_args()
    if args.only in (None, "parameter"):
        bench_parameter(args.repeat)
    if args.only in (None, "query"):
        bench_query_path(args.repeat, args.baseline)
    if args.only in (None, "solve_all"):
        bench_solve_all(args.repeat)
    if args.only in (None, "singularities"):
        bench_singularities(args.repeat, args.butterfly)


def bench_singularities(repeat: int, butterfly: bool = False) -> None:
    """``singularities`` on the four-bar and the Watt six-bar, against stop 12's seeding in the same run.

    The baseline seeds solve_all midway between every pair of consecutive critical input values
    (``samples=`` those midpoints), as stop 12 did (it also traces from the critical points, which
    stop 12 did not: its extra cost is a few covered-point checks); the default seeds one input
    value and the square systems' critical points.  Same answer (circuits, singular
    configurations) asserted.
    """
    import math

    from symkin.solutions.circuits import singularities
    from symkin.solutions.seeding import midpoints

    print(f"\n{'singularities':32s} {'best s':>7s} {'base s':>7s} {'ratio':>6s} {'solve_all':>9s} {'hom s':>6s} "
          f"{'paths':>6s} {'circ':>5s} {'sing':>5s} {'agree':>6s}")
    for name in ("fourbar_appendix", "watt_sixbar"):
        m = catalogue.get(name)
        times, base, r = [], [], None
        for _ in range(repeat):
            t = time.perf_counter()
            r = singularities(m)
            times.append(time.perf_counter() - t)
        critical = sorted({round(math.remainder(s.input, 2 * math.pi), 12) for s in r.singularities
                           if "DKP-input" in s.types or "IM" in s.types})
        mids = midpoints(critical, "angle")
        for _ in range(repeat):
            t = time.perf_counter()
            rb = singularities(m, samples=mids)
            base.append(time.perf_counter() - t)
        assert len(rb.circuits) == len(r.circuits) and [s.types for s in rb.singularities] == \
            [s.types for s in r.singularities]
        hom = sum(c.seconds for c in r.checks)
        paths = sum(c.paths for c in r.checks)
        print(f"{name:32s} {min(times):7.2f} {min(base):7.2f} {min(base) / min(times):6.2f} "
              f"{len(r.samples):4d}/{len(mids):<4d} {hom:6.2f} {paths:6d} {len(r.circuits):5d} "
              f"{len(r.singularities):5d} {str(r.agree):>6s}")
    if butterfly:
        import warnings

        from symkin.model.model_file import read_model

        m = read_model(Path(__file__).resolve().parents[1] / "papers_examples" / "double_butterfly.toml")
        for label, options in (("double butterfly, default rounds", {}),
                               ("double butterfly, --samples 60° grid", {"samples": [0, 60, 120, 180, 240, 300]})):
            t = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = singularities(m, unit="deg", **options)
            dt = time.perf_counter() - t
            kinds = [s.types for s in r.singularities]
            print(f"{label:32s} {dt:7.1f} s, {len(r.samples)} solve_all, {len(r.circuits)} circuits, "
                  f"{sum('DKP-input' in k for k in kinds)} DKP-input, {sum('IM' in k for k in kinds)} IM, "
                  f"agree {r.agree} ({r.checks[0].skipped})")


def bench_parameter(repeat: int) -> None:
    """Per-query time of the parameter homotopy against the total-degree solve, in the same run (issue 17 §1).

    The first call builds the start solutions (monodromy, plus the total-degree check when it has
    at most 1,024 paths; cached in ``$SYMKIN_CACHE``, here a fresh temporary directory); the
    queries then move the values.  The general 6-6 Gough–Stewart's total-degree solve (4,096
    paths after elimination) is not run: its path count and the time estimated from its first
    paths (:func:`symkin.solutions.homotopy.estimate_seconds`) are printed instead.
    """
    import os
    import tempfile

    from symkin.model.model_file import read_model
    from symkin.solutions.homotopy import estimate_seconds, square_up, total_degree
    from symkin.solutions.system import position_system

    os.environ["SYMKIN_CACHE"] = tempfile.mkdtemp(prefix="symkin-bench-")
    m3, v3 = rpr_model()
    gs = read_model(ROOT / "examples" / "gough_stewart_66.toml")
    cases = [("3-RPR forward (6)", m3, v3, "rad", 0.3),
             ("3-RRR inverse (8)", catalogue.get("rrr_3"),
              {"velocity:C1.x": 0.05, "velocity:C1.y": -0.05, "rotation:platform": 5}, "deg", 0.01),
             ("five-bar (4)", catalogue.get("five_bar"), {"velocity:P.x": 0.1, "velocity:P.y": -0.2}, "rad", 0.02),
             ("four-bar (2)", catalogue.get("fourbar_appendix"), {"rotation:crank": 30}, "deg", 5.0),
             ("general 6-6 Gough-Stewart (40)", gs, {f"slide:s{k}": 0.0 for k in range(1, 7)}, "rad", 0.02)]
    print(f"{'parameter homotopy':32s} {'first s':>8s} {'param s':>8s} {'total s':>8s} {'ratio':>6s} "
          f"{'paths p/t':>10s} {'real':>5s} {'cplx':>5s}")
    for name, m, values, unit, delta in cases:
        t = time.perf_counter()
        solve_all(m, values, unit=unit, method="parameter")
        first = time.perf_counter() - t
        par, tot, rp, rt = [], [], None, None
        big = m is gs
        for k in range(repeat):
            q = {key: v + (k + 1) * delta * (1 if i % 2 else -1) for i, (key, v) in enumerate(values.items())}
            t = time.perf_counter()
            rp = solve_all(m, q, unit=unit, method="parameter")
            par.append(time.perf_counter() - t)
            if big:
                continue
            t = time.perf_counter()
            rt = solve_all(m, q, unit=unit, method="total-degree")
            tot.append(time.perf_counter() - t)
            assert (len(rp.solutions), rp.complex) == (len(rt.solutions), rt.complex), name
        if big:
            system = position_system(m, q, unit)
            eqs = square_up(system.reduced, len(system.solve_for))
            paths = total_degree(eqs, list(system.solve_for))
            per_path, measured = estimate_seconds(eqs, list(system.solve_for))
            print(f"{name:32s} {first:8.2f} {min(par):8.3f} {'~' + format(per_path * paths, '.0f'):>8s} "
                  f"{per_path * paths / min(par):6.0f} {rp.paths:4d}/{paths:<5d} {len(rp.solutions):5d} {rp.complex:5d}"
                  f"   (total degree not run: estimated from {measured} paths)")
            continue
        print(f"{name:32s} {first:8.2f} {min(par):8.3f} {min(tot):8.3f} {min(tot) / min(par):6.2f} "
              f"{rp.paths:4d}/{rt.paths:<5d} {len(rp.solutions):5d} {rp.complex:5d}")


def bench_query_path(repeat: int, baseline: str | None = None) -> None:
    """The whole later query of ``symkin modes`` on the general 6-6 Gough–Stewart (issue 17: ≤ 2 s).

    A first ``solve_all`` fills a fresh ``$SYMKIN_CACHE`` with the start solutions; then each of
    ``repeat`` rounds runs the command line in a new process, timed whole (wall and the child's CPU
    time), beside the same query through ``solve_all`` in this process and the command's imports alone
    (a new process that imports ``symkin.cli`` and the solver and exits): the part that no cache
    can remove.  Every round's command is a later query: a warm-up query first writes what later
    queries read back (:mod:`symkin.solutions.query`) and the interpreter's bytecode (kept in a
    temporary ``PYTHONPYCACHEPREFIX``, as an installed package has it; ``PYTHONDONTWRITEBYTECODE``
    is dropped for the children).

    ``baseline`` (``--baseline DIR``, e.g. a ``git worktree`` of an earlier commit) also runs the
    command with ``PYTHONPATH=DIR`` (its own artefact cache, the same start solutions copied in),
    alternating with this tree in every round, and asserts the same standard output apart from the
    timings it prints.
    """
    import os
    import re
    import resource
    import shutil
    import subprocess
    import tempfile

    from symkin.model.model_file import read_model

    work = Path(tempfile.mkdtemp(prefix="symkin-bench-query-"))
    trees = {"this tree": ROOT}
    if baseline:
        trees["baseline"] = Path(baseline).resolve()
    envs = {}
    for name, tree in trees.items():
        env = dict(os.environ, SYMKIN_CACHE=str(work / f"cache-{len(envs)}"), PYTHONPATH=str(tree),
                   PYTHONPYCACHEPREFIX=str(work / f"pycache-{len(envs)}"))
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        envs[name] = env
    os.environ["SYMKIN_CACHE"] = envs["this tree"]["SYMKIN_CACHE"]
    path = ROOT / "examples" / "gough_stewart_66.toml"
    gs = read_model(path)
    t = time.perf_counter()
    solve_all(gs, {f"slide:s{k}": 0.0 for k in range(1, 7)}, method="parameter")
    first = time.perf_counter() - t
    for env in list(envs.values())[1:]:
        shutil.copytree(Path(envs["this tree"]["SYMKIN_CACHE"]) / "parameter-homotopy",
                        Path(env["SYMKIN_CACHE"]) / "parameter-homotopy")
    mask = re.compile(r"tracked in [0-9.]+ s \([0-9.]+ s in all\)")

    def command(env, tree, legs):
        args = [a for k, v in enumerate(legs, 1) for a in ("--at", f"slide:s{k}={v}")]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        out = subprocess.run([sys.executable, "-m", "symkin", "modes", str(path), *args, "--no-progress"], env=env,
                             cwd=tree, capture_output=True, text=True)
        wall = time.perf_counter() - t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        assert out.returncode == 0, out.stderr
        return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, mask.sub("", out.stdout)

    for name, env in envs.items():  # the warm-up query: bytecode and what later queries read back
        command(env, trees[name], [0.01] * 6)
    imports, inproc = [], []
    cli = {name: [] for name in envs}
    for r in range(repeat):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import symkin.cli, symkin.commands.modes, symkin.solutions.solve_all"],
                       env=envs["this tree"], check=True)
        imports.append(time.perf_counter() - t)
        legs = [0.02 * (r + 1) * (1 if k % 2 else -1) for k in range(1, 7)]
        outputs = {}
        for name, env in envs.items():
            wall, cpu, outputs[name] = command(env, trees[name], legs)
            cli[name].append((wall, cpu))
        assert len(set(outputs.values())) == 1, "the baseline prints another answer"
        t = time.perf_counter()
        res = solve_all(gs, {f"slide:s{k}": v for k, v in enumerate(legs, 1)}, method="parameter")
        inproc.append(time.perf_counter() - t)
        assert res.method == "parameter" and res.paths == 40
    print(f"{'later query, general 6-6 (40 paths)':40s} {'first s':>8s} {'imports s':>10s} {'solve_all s':>12s} "
          f"{'CLI whole s':>12s} {'CLI CPU s':>10s} {'target':>7s}")
    for k, (name, times) in enumerate(cli.items()):
        walls, cpus = [w for w, _ in times], [c for _, c in times]
        lead = (f"{first:8.2f} {min(imports):10.2f} {min(inproc):12.2f}" if not k else f"{'':8s} {'':10s} {'':12s}")
        print(f"{name:40s} {lead} {min(walls):12.2f} {min(cpus):10.2f} {'2.00':>7s}"
              f"   (best of {repeat}; worst CLI {max(walls):.2f} s)")
    if baseline:
        print(f"{'':40s} same output in every round; load average {os.getloadavg()[0]:.1f}")


def bench_solve_all(repeat: int) -> None:
    print(f"{'example':45s} {'s':>7s} {'track s':>8s} {'unk':>4s} {'eq':>3s} {'paths':>6s} "
          f"{'real':>5s} {'cplx':>5s} {'inf':>4s}")
    for name, m, values, unit in examples():
        first = time.perf_counter()
        r = solve_all(m, values, unit=unit)
        first = time.perf_counter() - first
        best, track = min(_timed(m, values, unit) for _ in range(repeat))
        print(f"{name:45s} {best:7.3f} {track:8.3f} {r.unknowns:4d} {r.equations:3d} {r.paths:6d} "
              f"{len(r.solutions):5d} {r.complex:5d} {r.at_infinity:4d}   (first call {first:.2f} s)")


def _timed(m, values, unit) -> tuple[float, float]:
    t = time.perf_counter()
    r = solve_all(m, values, unit=unit)
    return time.perf_counter() - t, r.track_seconds


if __name__ == "__main__":
    main()
