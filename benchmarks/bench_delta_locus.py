"""The Delta's type-2 locus at constant height (issue 17 §5): the arms' elimination and the factoring,
the new way against the old in the same run.  Run on demand:

    python benchmarks/bench_delta_locus.py                 # both models, old way stopped after 150 s
    python benchmarks/bench_delta_locus.py --limit 60 120

Models: ``examples/delta.json`` (short decimals) and the 120° Delta of ``tests/workspace/truth.py``
(16-digit cos/sin of 120°, 240°; ``120``).  For each, in seconds of wall time:

* ``det``: the condition ``det(P V)`` over the translation (:func:`~symkin.symbolic.pose_loci.pose_condition`);
* ``values``: :func:`~symkin.symbolic.pose_loci.eliminate_arms` by values (the default);
* ``resultants``: the same by the symbolic resultants (the old way), in a child process stopped
  after ``--limit`` seconds (then printed as ``> limit``, and the ratio is a lower bound);
* ``certify``: :func:`~symkin.symbolic.pose_loci.factor_list` (irreducibility certified), against
  ``sympy.factor_list`` (the old way, in a child process with the same limit).

The two polynomials are compared when both finish (proportional: ``same curve``).
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "workspace"))

import sympy as sp

from symkin.kinds import Kind
from symkin.model.labels import parse_label
from symkin.model.mechanism import Mechanism
from symkin.model.model_file import read_model
from symkin.symbolic.loci import _LOCUS_LABELS
from symkin.symbolic.model import symbolic_model
from symkin.symbolic.pose_loci import (
    eliminate_arms,
    factor_list,
    pose_condition,
    translation_slice,
)
from symkin.tolerances import Tolerances


def _model(name: str) -> Mechanism:
    if name == "120":
        from truth import Delta
        return Mechanism.from_dict(Delta().model((0.1, -0.05, -2.2)))
    return read_model(ROOT / "examples" / "delta.json")


MODELS = ("delta.json", "120")


def _slice(name: str):
    mech = _model(name)
    coords = [parse_label(mech, v, "coordinate", _LOCUS_LABELS) for v in ("velocity:P.x", "velocity:P.y")]
    held = parse_label(mech, "velocity:P.z", "coordinate", _LOCUS_LABELS)
    ps = translation_slice(mech, coords, [(held, None)], Tolerances().geometry)
    det, _ = pose_condition(symbolic_model(mech, coordinates="nodes"), ps, Kind.DKP_INPUT)
    return ps, det


def _child(name: str, what: str, queue) -> None:
    ps, det = _slice(name)
    t0 = time.perf_counter()
    if what == "resultants":
        poly, _ = eliminate_arms(det, ps, method="resultants")
        queue.put((time.perf_counter() - t0, sp.srepr(poly)))
    else:
        poly, _ = eliminate_arms(det, ps)
        t0 = time.perf_counter()
        _, fl = sp.factor_list(sp.Poly(poly, *ps.variables, domain="QQ"))
        queue.put((time.perf_counter() - t0, [f.total_degree() for f, _ in fl]))


def _limited(name: str, what: str, limit: float):
    """``(seconds, result)`` of :func:`_child`, or None when it did not finish within ``limit`` s (plus
    10 s for the child's set-up: the model and ``det``)."""
    import queue as queues
    queue = mp.Queue()
    p = mp.Process(target=_child, args=(name, what, queue))
    p.start()
    try:
        out = queue.get(timeout=limit + 10.0)
    except queues.Empty:
        out = None
    if p.is_alive():
        p.terminate()
    p.join()
    return None if out is None or out[0] > limit else out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*", default=list(MODELS), help=f"some of {', '.join(MODELS)}")
    ap.add_argument("--limit", type=float, default=150.0, help="seconds for each old-way run (default 150)")
    args = ap.parse_args(argv)
    print(f"{'model':<11} {'det':>6} {'values':>8} {'resultants':>11} {'ratio':>7} {'certify':>8} "
          f"{'sympy factor':>13} {'ratio':>7}  result")
    for name in args.models:
        t0 = time.perf_counter()
        ps, det = _slice(name)
        t_det = time.perf_counter() - t0
        t0 = time.perf_counter()
        poly, _ = eliminate_arms(det, ps)
        t_val = time.perf_counter() - t0
        p = sp.Poly(poly, *ps.variables, domain="QQ")
        t0 = time.perf_counter()
        _, fl = factor_list(p)
        t_cert = time.perf_counter() - t0
        old = _limited(name, "resultants", args.limit)
        fac = _limited(name, "factor", args.limit)
        same = ""
        if old is not None:
            q = sp.Poly(eval(old[1], dict(vars(sp))), *ps.variables)
            same = "same curve" if (p * q.LC() - q * p.LC()).is_zero else "DIFFERENT"
        t_old = f"{old[0]:.1f}" if old else f"> {args.limit:g}"
        r_old = f"{old[0] / t_val:.0f}x" if old else f"> {args.limit / t_val:.0f}x"
        t_fac = f"{fac[0]:.1f}" if fac else f"> {args.limit:g}"
        r_fac = f"{fac[0] / t_cert:.0f}x" if fac else f"> {args.limit / t_cert:.0f}x"
        degrees = "+".join(str(f.total_degree()) for f, _ in fl)
        print(f"{name:<11} {t_det:>6.2f} {t_val:>8.2f} {t_old:>11} {r_old:>7} {t_cert:>8.2f} {t_fac:>13} {r_fac:>7}  "
              f"degree {degrees}, {max(len(str(abs(c))) for c in p.clear_denoms()[1].coeffs())}-digit "
              f"coefficients {same}")
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
