"""Benchmark of ``symkin.solve_all`` (issue 9 §1), run on demand — not a test.

    PYTHONPATH=$PWD /work/venv/bin/python benchmarks/bench_solve_all.py [--repeat R]

For each example of the truth tests (``tests/solutions/test_solve_all.py``) it prints the
wall time of ``solve_all`` (best of R, the evaluators already built once), the time of the
homotopy alone, the system given to the solver (unknowns after elimination, equations before
squaring up), the paths tracked and the real / complex / at-infinity counts.  Needs the extra
``symkin[global]``.
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
    args = ap.parse_args()
    print(f"{'example':45s} {'s':>7s} {'track s':>8s} {'unk':>4s} {'eq':>3s} {'paths':>6s} "
          f"{'real':>5s} {'cplx':>5s} {'inf':>4s}")
    for name, m, values, unit in examples():
        first = time.perf_counter()
        r = solve_all(m, values, unit=unit)
        first = time.perf_counter() - first
        best, track = min(_timed(m, values, unit) for _ in range(args.repeat))
        print(f"{name:45s} {best:7.3f} {track:8.3f} {r.unknowns:4d} {r.equations:3d} {r.paths:6d} "
              f"{len(r.solutions):5d} {r.complex:5d} {r.at_infinity:4d}   (first call {first:.2f} s)")


def _timed(m, values, unit) -> tuple[float, float]:
    t = time.perf_counter()
    r = solve_all(m, values, unit=unit)
    return time.perf_counter() - t, r.track_seconds


if __name__ == "__main__":
    main()
