"""Benchmark: the time to build the CasADi evaluators of a joint-form model, as a ratio to its node form.

Run on demand from a checkout (not part of the test suite)::

    python benchmarks/bench_evaluator_build.py [--repeat 1] [--compile] [--json out.json]

It builds, in one process, ``symkin.numeric.evaluators.evaluators`` (every Function, the
indicator kernel included) of the Gough–Stewart platform of
``tests/workspace/models/gough_stewart.toml`` in its node form and in its joint form
(``tests.model.joint_forms.ups_6``: per leg a U, a P and an S joint, 43 nodes instead of 19),
and prints the CPU time (``time.process_time``: other jobs on a shared machine do not count)
of each, the ratio joint / node, the free coordinates, the constraint rows that touch them and
the instructions of the ``indicators`` Function.  ``--compile`` also times the generation,
compilation and loading of the C (wall time, a fresh cache each).

The joint form's kernel works on a 109 × 109 Gram matrix (the node form's on 43 × 43): its
tridiagonal reduction is cubic in that size, 1.9 million CasADi instructions.  Before this
benchmark existed the build took 49 s CPU (ratio 14 to the node form, same machine, same run):
the Householder reduction built its graph one scalar operation at a time through CasADi's
Python bindings (23 s), and CasADi's common-subexpression pass on the 1.9 million instructions
took 16-20 s for 1.3 % fewer instructions.  Now the reduction and the Givens QR build the same
graphs with whole-matrix operations (the same operations in the same order: the same values bit
for bit) and CSE is skipped above ``evaluators.CSE_LIMIT`` instructions: 8.75 s (ratio 4.6).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import symkin  # noqa: E402
from symkin.numeric.evaluators import evaluators  # noqa: E402
from tests.model import joint_forms  # noqa: E402


def _models():
    node = symkin.read_model(joint_forms.MODELS / "gough_stewart.toml")
    joint = symkin.Mechanism.from_dict(joint_forms.ups_6(node.coordinates()))
    return {"node form": node, "joint form (6-UPS)": joint}


def _build(mech, repeat: int) -> tuple[float, object]:
    best, ev = float("inf"), None
    for _ in range(repeat):
        t = time.process_time()
        ev = evaluators(mech)
        best = min(best, time.process_time() - t)
    return best, ev


def _compile(ev) -> float:
    with tempfile.TemporaryDirectory(prefix="symkin-bench-build-") as tmp:
        t = time.perf_counter()
        ev.compile(cache_dir=tmp, force=True)
        return time.perf_counter() - t


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1, help="builds per model (the best is kept)")
    ap.add_argument("--compile", action="store_true", help="also time generating, compiling and loading the C")
    ap.add_argument("--json", help="write the figures to this file")
    args = ap.parse_args(argv)
    print(f"load average at start: {os.getloadavg()}")
    out = {}
    for name, mech in _models().items():
        seconds, ev = _build(mech, args.repeat)
        row = {"seconds": seconds, "nodes": len(mech.nodes), "free": ev.nf, "rows": len(ev.effective_rows),
               "instructions": ev.functions["indicators"].n_instructions() if ev.fast else 0}
        if args.compile:
            row["compile_seconds"] = _compile(ev)
        out[name] = row
        print(f"{name:22s} build {seconds:7.2f} s CPU   nodes {row['nodes']:3d}  free {row['free']:3d}  "
              f"rows {row['rows']:3d}  indicator instructions {row['instructions']:,}"
              + (f"   compile {row['compile_seconds']:.1f} s wall" if args.compile else ""))
    node, joint = out["node form"]["seconds"], out["joint form (6-UPS)"]["seconds"]
    out["ratio"] = joint / node
    print(f"ratio joint / node form: {out['ratio']:.1f}")
    print(f"load average at end: {os.getloadavg()}")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2))
    return out


if __name__ == "__main__":
    main()
