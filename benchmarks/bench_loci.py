"""Derivation time of the singularity loci as implicit polynomials (issue 9 §3): run on demand.

    python benchmarks/bench_loci.py            # every example
    python benchmarks/bench_loci.py --time-limit 60

For each example and kind, the seconds of :func:`symkin.symbolic.loci.implicit_loci` (the
symbolic condition and the elimination) on a fresh process state (the symbolic model cache
is cleared first), the degrees of the geometric factors and a pass/fail against the one-minute
requirement.  The baseline is the first idea a researcher tries, a lexicographic Gröbner basis of
closure + condition in sympy, on the five-bar's type-2 locus, stopped after ``--baseline`` seconds
in a child process: the ratio printed is a lower bound.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import sympy as sp  # noqa: E402

from symkin.model import catalogue  # noqa: E402
from symkin.model.mechanism import Mechanism  # noqa: E402
from symkin.model.model_file import read_model  # noqa: E402
from symkin.symbolic.loci import implicit_loci  # noqa: E402
from symkin.symbolic.model import _cached_model  # noqa: E402


def _watt_five_bar() -> Mechanism:
    data = catalogue.data("five_bar")
    data["nodes"] = {"A1": [-1.0, 0.0], "A2": [1.0, 0.0], "B1": [-1.0, 2.0], "B2": [1.0, 2.0], "P": [0.0, 2.75]}
    data["name"] = "five-bar with equal distal links (Watt's sextic)"
    return Mechanism.from_dict(data)


EXAMPLES = {
    "five_bar": (lambda: catalogue.get("five_bar"), ("velocity:P.x", "velocity:P.y"), ()),
    "five_bar_watt": (_watt_five_bar, ("velocity:P.x", "velocity:P.y"), ()),
    "rpr_3": (lambda: read_model(ROOT / "tests" / "workspace" / "models" / "rpr_3.toml"),
              ("velocity:O.x", "velocity:O.y"), ("rotation:platform",)),
}


def _groebner_baseline(queue) -> None:
    x, y, b1x, b1y, b2x, b2y = sp.symbols("x y b1x b1y b2x b2y")
    c = sp.Rational(5, 4)
    eqs = [(b1x + 1) ** 2 + b1y ** 2 - 4, (b2x - 1) ** 2 + b2y ** 2 - 4, (x - b1x) ** 2 + (y - b1y) ** 2 - c ** 2,
           (x - b2x) ** 2 + (y - b2y) ** 2 - c ** 2, (b1x - x) * (b2y - y) - (b2x - x) * (b1y - y)]
    t0 = time.perf_counter()
    sp.groebner(eqs, b1x, b1y, b2x, b2y, x, y, order="lex")
    queue.put(time.perf_counter() - t0)


def baseline(limit: float) -> tuple[float, bool]:
    queue = mp.Queue()
    p = mp.Process(target=_groebner_baseline, args=(queue,))
    t0 = time.perf_counter()
    p.start()
    p.join(limit)
    if p.is_alive():
        p.terminate()
        p.join()
        return time.perf_counter() - t0, False
    return queue.get(), True


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("examples", nargs="*", help=f"some of {', '.join(EXAMPLES)} (default: all)")
    ap.add_argument("--time-limit", type=float, default=60.0, help="seconds per locus (default 60)")
    ap.add_argument("--baseline", type=float, default=60.0,
                    help="seconds given to the lex Gröbner baseline (0: skip it)")
    args = ap.parse_args(argv)
    print(f"{'example':<16}{'kind':<12}{'seconds':>9}  degrees of the geometric factors")
    worst = 0.0
    watt = None
    unknown = [n for n in args.examples if n not in EXAMPLES]
    if unknown:
        ap.error(f"unknown example(s) {', '.join(unknown)}; choose from {', '.join(EXAMPLES)}")
    for name in args.examples or list(EXAMPLES):
        make, variables, hold = EXAMPLES[name]
        _cached_model.cache_clear()
        mech = make()
        t0 = time.perf_counter()
        loci = implicit_loci(mech, variables, hold=hold, time_limit=args.time_limit)
        total = time.perf_counter() - t0
        for locus in loci.loci:
            degrees = ", ".join(f"{f.degree}" + (f"^{f.exponent}" if f.exponent != 1 else "") for f in locus.factors)
            print(f"{name:<16}{locus.kind:<12}{locus.seconds:9.3f}  {degrees or 'no curve'}")
            worst = max(worst, locus.seconds)
            if name == "five_bar_watt" and locus.kind == "DKP-input":
                watt = locus.seconds
        for text in loci.skipped:
            print(f"{name:<16}{'':<12}{'—':>9}  {text}")
        print(f"{name:<16}{'(all)':<12}{total:9.3f}")
    print(f"slowest locus: {worst:.3f} s ({'under' if worst < 60 else 'OVER'} a minute)")
    if args.baseline and watt is not None:
        seconds, finished = baseline(args.baseline)
        bound = "" if finished else ">= "
        print(f"baseline lex Gröbner basis (five-bar type 2): {bound}{seconds:.1f} s; "
              f"ratio {bound}{seconds / watt:.0f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
