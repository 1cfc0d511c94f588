"""Benchmark of the per-configuration API (issue 7 §6): ``symkin.analyze`` and ``symkin.motion_space``.

Run on demand (not part of the test suite), from a checkout::

    python benchmarks/bench_analyze.py [--n 2000] [--models rrr_3 ...] [--repeat 3]

At ``--n`` valid configurations of each catalogue model (its free coordinates perturbed by
5 % of the length scale and projected onto the closure manifold with
``symkin.evaluators(mech).project``), it times, in one run:

(a) the baseline a user writes by hand: ``sympy.lambdify`` of the reduced symbolic G
    (``symkin.symbolic_model(mech, coordinates="nodes").reduced_G``, fixed nodes replaced by
    their values, lambdified over the free coordinates), then ``numpy.linalg.eigh`` in a Python loop (λ_{F+1} and the
    motion space, nothing else);
(b) ``symkin.analyze(m)`` per configuration (full classification: DOF, IM, DKP in/out,
    LIM, constraint, relations, uncontrolled motions, Gosselin–Angeles, Zlatanov);
(c) ``symkin.motion_space(m)`` per configuration;

(b) and (c) both on prebuilt mechanisms and in the user's loop that also builds each one
with ``mech.with_coordinates(xyz)``; ``with_coordinates`` alone is timed too.  The methods
are timed in turn for ``--repeat`` rounds and the best round of each is kept, so that the
load of a shared machine affects them alike; ratios are to (a) of the same run, by the wall
clock and by the process's CPU time (steadier when other jobs share the cores).  The last
column is the steadiest on a shared machine: every method and the baseline run on the same
chunk of 100 configurations one right after the other, 40 times, and the median of the
chunks' CPU-time ratios is printed (:func:`paired_ratios`).  One process, one thread.
"""
from __future__ import annotations

import argparse
import gc
import os
import platform
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

import symkin  # noqa: E402


def baseline_function(mech):
    """``sympy.lambdify`` of the reduced symbolic G over the free coordinates, in node order."""
    sm = symkin.symbolic_model(mech, coordinates="nodes")
    assert len(sm.config_symbols) == sm.ncoord  # x_A, y_A, ... in the core's coordinate order
    free = [sm.config_symbols[k] for k in sm.free]
    ground = {s: v for s, v in sm.values.items() if s not in set(free)}
    return sp.lambdify(free, sm.reduced_G.xreplace(ground), "numpy")


def baseline(f_g, q, mobility):
    """λ_{F+1} and the motion space from ``eigh`` per configuration, as a user writes it."""
    out = np.empty(len(q))
    for k, x in enumerate(q):
        w, v = np.linalg.eigh(f_g(*x))
        out[k] = w[mobility]  # IM indicator; v[:, :mobility] spans the motion space
    return out


def best_rates(methods: dict, n: int, repeat: int) -> dict:
    """Configurations per second of each ``fn()`` over ``n`` configurations, best of ``repeat``.

    Returns ``{name: (wall, cpu)}``: rates by the wall clock and by the process's CPU time
    (on a shared machine the CPU time is less disturbed by other jobs).  The methods are
    timed in turn, round after round, so that a change of load affects them alike; the
    best round of each is kept.
    """
    best = {name: [0.0, 0.0] for name in methods}
    for _ in range(repeat):
        for name, fn in methods.items():
            gc.collect()
            wall, cpu = time.perf_counter(), time.process_time()
            fn()
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            best[name] = [max(best[name][0], n / wall), max(best[name][1], n / max(cpu, 1e-9))]
    return {name: tuple(v) for name, v in best.items()}


def paired_ratios(methods: dict, items: list, chunk: int = 100, rounds: int = 40) -> dict:
    """Median over ``rounds`` of each method's rate over the first method's rate, chunk by chunk.

    ``methods`` maps a name to ``fn(chunk_of_items)``; in every round each method runs once
    on the same chunk of ``chunk`` items, one right after the other, so a change of load on a
    shared machine hits the numerator and the denominator of a round's ratio alike; the
    median of the rounds' ratios (CPU time) discards the rounds a burst of load disturbed.
    """
    names = list(methods)
    ratios = {name: [] for name in names}
    for r in range(rounds):
        start = (r * chunk) % max(1, len(items) - chunk + 1)
        part = items[start:start + chunk]
        cpu = {}
        for name in names:
            t = time.process_time()
            methods[name](part)
            cpu[name] = time.process_time() - t
        for name in names:
            ratios[name].append(cpu[names[0]] / max(cpu[name], 1e-12))
    return {name: float(np.median(v)) for name, v in ratios.items()}


def configurations(mech, n: int, seed: int = 0):
    """``n`` valid configurations: free coordinates and the (n_nodes, dim) coordinate arrays."""
    ev = symkin.evaluators(mech)
    rng = np.random.default_rng(seed)
    q = ev.project(ev.q0 + 0.05 * mech.length_scale * rng.standard_normal((n, ev.nf)))
    return q, [ev.coordinates(x) for x in q]


def bench(name: str, n: int, repeat: int) -> dict:
    mech = symkin.catalogue.get(name)
    q, xyz = configurations(mech, n)
    mechs = [mech.with_coordinates(x) for x in xyz]
    f_g = baseline_function(mech)
    f = mech.mobility_value
    base = baseline(f_g, q[:20], f)  # warm-up
    gc.freeze()  # the sympy objects of the baseline should not slow the collector later
    rates = best_rates({
        "(a) sympy.lambdify(G) + numpy eigh, Python loop": lambda: baseline(f_g, q, f),
        "(b) symkin.analyze(m)": lambda: [symkin.analyze(m) for m in mechs],
        "(b) symkin.analyze(mech.with_coordinates(xyz))":
            lambda: [symkin.analyze(mech.with_coordinates(x)) for x in xyz],
        "(c) symkin.motion_space(m)": lambda: [symkin.motion_space(m) for m in mechs],
        "(c) symkin.motion_space(mech.with_coordinates(xyz))":
            lambda: [symkin.motion_space(mech.with_coordinates(x)) for x in xyz],
        "    mech.with_coordinates(xyz) alone": lambda: [mech.with_coordinates(x) for x in xyz],
    }, n, repeat)
    pairs = list(zip(q, xyz, mechs))
    paired = paired_ratios({
        "(a) sympy.lambdify(G) + numpy eigh, Python loop":
            lambda part: baseline(f_g, np.array([x for x, _, _ in part]), f),
        "(b) symkin.analyze(m)": lambda part: [symkin.analyze(m) for _, _, m in part],
        "(b) symkin.analyze(mech.with_coordinates(xyz))":
            lambda part: [symkin.analyze(mech.with_coordinates(x)) for _, x, _ in part],
        "(c) symkin.motion_space(m)": lambda part: [symkin.motion_space(m) for _, _, m in part],
        "(c) symkin.motion_space(mech.with_coordinates(xyz))":
            lambda part: [symkin.motion_space(mech.with_coordinates(x)) for _, x, _ in part],
        "    mech.with_coordinates(xyz) alone": lambda part: [mech.with_coordinates(x) for _, x, _ in part],
    }, pairs)
    gc.unfreeze()
    base = baseline(f_g, q, f)
    analyses = [symkin.analyze(m) for m in mechs]
    im = np.array([a.im_indicator for a in analyses])
    notes = {
        "max rel. difference of analyze's λ_{F+1} vs the baseline's eigh": float(
            np.max(np.abs(im - base) / np.abs(base))),
        "singular configurations among them": sum(a.singular for a in analyses),
    }
    return {"model": name, "n": n, "rates": rates, "paired": paired, "notes": notes}


def report(results: dict) -> str:
    rates = results["rates"]
    base_wall, base_cpu = next(iter(rates.values()))
    width = max(len(k) for k in rates)
    paired = results["paired"]
    lines = [f"== {results['model']} ({results['n']} configurations)",
             f"{'method'.ljust(width)}  {'configs/s':>10}  {'ratio to (a)':>12}  {'ratio, CPU time':>15}"
             f"  {'paired median':>13}"]
    lines += [f"{k.ljust(width)}  {w:10,.0f}  {w / base_wall:12.2f}  {c / base_cpu:15.2f}  {paired[k]:13.2f}"
              for k, (w, c) in rates.items()]
    lines += [f"  {k}: {v:.3g}" if isinstance(v, float) else f"  {k}: {v}"
              for k, v in results["notes"].items()]
    return "\n".join(lines)


def load() -> str:
    try:
        return ", ".join(f"{v:.2f}" for v in os.getloadavg())
    except OSError:
        return "unknown"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n", type=int, default=2000, help="configurations per model")
    p.add_argument("--models", nargs="+", default=["rrr_3"])
    p.add_argument("--repeat", type=int, default=5, help="rounds (every method once per round); the best is reported")
    args = p.parse_args(argv)
    print(f"symkin {symkin.__version__}, numpy {np.__version__}, sympy {sp.__version__}, "
          f"Python {platform.python_version()}, {platform.processor() or platform.machine()}")
    print(f"load average before: {load()}")
    for name in args.models:
        print(report(bench(name, args.n, args.repeat)))
        sys.stdout.flush()
    print(f"load average after: {load()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
