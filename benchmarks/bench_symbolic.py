"""Timings of the symbolic side (issue 3, requirement 4): run on demand, prints a table.

    python benchmarks/bench_symbolic.py            # all catalogue mechanisms
    python benchmarks/bench_symbolic.py rrr_3      # some of them
    python benchmarks/bench_symbolic.py rrr_3 --baseline 60

For each mechanism and coordinate set it measures, on a fresh model (no cache):
building the symbolic G, the characteristic polynomial of the reduced G (small models),
and the three conditions (IM, DKP-input, DKP-output).  ``--baseline T`` also runs the
naive derivation a researcher would type — ``sympy.Matrix.det()`` of the augmented
velocity equation [J; P_in] — in a child process stopped after T seconds, and prints the
ratio.  The requirement is that each 3-RRR condition derives in under a minute.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkin.model import catalogue  # noqa: E402
from symkin.symbolic.model import SymbolicModel  # noqa: E402

#: characteristic polynomials are only timed where they take seconds, not minutes
CHARPOLY = {("rrr_3", "nodes"), ("rssr", "nodes")}


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def _naive_det(name: str, queue) -> None:
    """The naive route: build [J; P_in] over the free coordinates and call det()."""
    mech = catalogue.get(name)
    sm = SymbolicModel(mech, "angles", False)
    rows, _ = sm.parameter_rows(mech.inputs)
    j = sm.J.extract(list(range(sm.J.rows)), list(sm.free))
    keep = [k for k in range(j.rows) if any(e != 0 for e in j.row(k))]
    m = j.extract(keep, list(range(j.cols))).col_join(rows.extract(list(range(rows.rows)), list(sm.free)))
    t0 = time.perf_counter()
    d = sp.factor(m.det(method="berkowitz"))
    queue.put((time.perf_counter() - t0, sp.count_ops(d)))


def naive_baseline(name: str, limit: float) -> float | None:
    """Seconds of the naive derivation, or None when it did not finish within ``limit``."""
    queue: mp.Queue = mp.Queue()
    proc = mp.Process(target=_naive_det, args=(name, queue))
    proc.start()
    proc.join(limit)
    if proc.is_alive():
        proc.terminate()
        proc.join()
        return None
    return queue.get()[0] if not queue.empty() else None


def bench(name: str) -> list[str]:
    mech = catalogue.get(name)
    lines = []
    for mode in (("angles", "nodes") if mech.dim == 2 else ("nodes",)):
        sm, t_model = timed(lambda: SymbolicModel(mech, mode, False))
        _, t_g = timed(lambda: sm.G)
        t_cp = None
        if (name, mode) not in CHARPOLY:
            _, t_cp = timed(sm.characteristic_polynomial)
        im, t_im = timed(sm.im_condition)
        dkp_in, t_in = timed(lambda: sm.dkp_condition("input")) if mech.inputs else (None, None)
        dkp_out, t_out = timed(lambda: sm.dkp_condition("output")) if mech.outputs else (None, None)

        def fmt(t):
            return "   —   " if t is None else f"{t:7.3f}"

        lines.append(f"{name:20s} {mode:6s} {fmt(t_model + t_g)} {fmt(t_cp)} {fmt(t_im)} {fmt(t_in)} {fmt(t_out)}"
                     f"   factors: in {len(dkp_in.geometric_factors) if dkp_in else '-'},"
                     f" out {len(dkp_out.geometric_factors) if dkp_out else '-'}, IM minors {len(im.minors)}")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="catalogue mechanisms (default: all)")
    parser.add_argument("--baseline", type=float, default=0.0, metavar="T",
                        help="also time the naive sympy det() of [J; P_in] (angles), stopped after T s")
    args = parser.parse_args(argv)
    names = args.names or list(catalogue.names())
    print(f"sympy {sp.__version__}; seconds per derivation (fresh model, one core)")
    print(f"{'mechanism':20s} {'coords':6s} {'G':>7s} {'charpoly':>7s} {'IM':>7s} {'DKP-in':>7s} {'DKP-out':>7s}")
    for name in names:
        for line in bench(name):
            print(line)
    if args.baseline > 0:
        print()
        for name in names:
            if catalogue.get(name).dim != 2:
                continue
            sm = SymbolicModel(catalogue.get(name), "angles", False)
            _, t_ours = timed(lambda: sm.dkp_condition("input"))
            t_naive = naive_baseline(name, args.baseline)
            naive = f"> {args.baseline:g} s (stopped)" if t_naive is None else f"{t_naive:.3f} s"
            ratio = f"≥ {args.baseline / t_ours:.0f}×" if t_naive is None else f"{t_naive / t_ours:.1f}×"
            print(f"{name:20s} DKP-input angles: symkin {t_ours:.3f} s, naive det()+factor {naive}: {ratio}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
