"""Benchmark: a workspace map of a mechanism written by its joints against its node form (issue 16), on demand.

    PYTHONPATH=$PWD /work/venv/bin/python benchmarks/bench_joint_form_map.py [--n 11] [--repeat 1] [--profile]

The Gough–Stewart constant-orientation slice of ``tests/workspace/test_map_joint_forms.py``
(``tests/workspace/models/gough_stewart.toml``; O over [−0.75, 1.25] × [−1, 1], the orientation
held; the joint form is ``tests/model/joint_forms.ups_6``: per leg a U, a P and an S joint), an
``--n`` × ``--n`` grid with refinement, one BLAS thread (as the other benchmarks; ``--blas-threads``
leaves OpenBLAS its default, one thread per core: on this shared 2-core machine under load a
91 × 93 SVD then takes 60 ms instead of 1 ms, and the joint form's refinement takes hundreds of
them), node form and joint form alternating in the same run, each
in a fresh artefact cache (``$SYMKIN_CACHE`` a new temporary directory per run: every kernel is
built, as a first map of a model is).  Printed per form: the model's size (nodes, free coordinates,
constraint rows), the map's wall time (best of ``--repeat``), and where it goes, from one profiled
run (``--profile``; cProfile's overhead is on Python code only): building the evaluators (the
CasADi model and its Functions, :func:`symkin.numeric.evaluators.evaluators`), building the batch
indicator kernel (on first use), the map's own problem (:func:`symkin.workspace.system.map_system`),
the grid continuation (:func:`symkin.workspace.parallel.tiled_mode`), refinement
(:func:`symkin.workspace.maps._refine`, its own kernels included) and, across all of them, CasADi
``Function`` construction (``Function(...)``, ``.map``, ``.buffer``) and the derivatives; and the
ratio joint / node.  The maps are checked to be the same (curve counts by kind, assembled grid).
"""
from __future__ import annotations

import argparse
import cProfile
import os

if "--blas-threads" not in " ".join(os.sys.argv):  # one BLAS thread, as the other benchmarks (see --blas-threads)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import pstats
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import symkin  # noqa: E402
from tests.model import joint_forms as jf  # noqa: E402
from tests.workspace import test_map_truth as MT  # noqa: E402

#: (label, function file suffix, function name) of the parts reported from the profile
PARTS = (("evaluators", "numeric/evaluators.py", "evaluators"),
         ("batch kernel", "numeric/evaluators.py", "build_kernel"),
         ("map_system", "workspace/system.py", "map_system"),
         ("grid", "workspace/parallel.py", "tiled_mode"),
         ("refine", "workspace/maps.py", "_refine"),
         ("Function()", "casadi/casadi.py", "__init__"),
         ("jacobian", "casadi/casadi.py", "jacobian"),
         ("Function.map", "casadi/casadi.py", "map"),
         ("codegen", "numeric/codegen.py", "compile_evaluators"))


def forms():
    node = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    joint = symkin.Mechanism.from_dict(jf.ups_6(node.coordinates()))
    return (("node form", node), ("joint form (6-UPS)", joint))


def run(mech, n: int, profile: bool):
    os.environ["SYMKIN_CACHE"] = tempfile.mkdtemp(prefix="symkin-bench-joint-map-")
    from symkin.analysis import batch

    from symkin.workspace import parallel

    batch._SHARED.clear()  # a first map of the model: nothing built in this process either
    parallel._SYSTEMS.clear()
    kw = dict(x="velocity:O.x=-0.75:1.25", y="velocity:O.y=-1.0:1.0", n=(n, n), hold=MT.GS_HOLD_ORIENTATION,
              refine=True)
    prof = cProfile.Profile() if profile else None
    t = time.perf_counter()
    if prof is not None:
        prof.enable()
    wmap = symkin.workspace_map(mech, **kw)
    if prof is not None:
        prof.disable()
    return wmap, time.perf_counter() - t, prof


def parts(prof) -> dict:
    stats = pstats.Stats(prof).stats
    out = {}
    for label, suffix, name in PARTS:
        out[label] = sum(v[3] for (file, _, func), v in stats.items()
                         if func == name and file.replace(os.sep, "/").endswith(suffix))
    return out


def size(mech) -> str:
    from symkin.analysis.batch import evaluators_for

    rows = evaluators_for(mech).model.J.shape[0]
    return f"{len(mech.nodes)} nodes, {len(mech.free_nodes) * mech.dim} free coords, {rows} rows"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=11)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--profile", action="store_true", help="one more run of each form under cProfile")
    ap.add_argument("--blas-threads", action="store_true",
                    help="leave OpenBLAS its default threads (one per core) instead of one")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}; grid {args.n} x {args.n}, refine=True; "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'default')}")
    best, maps, profiles = {}, {}, {}
    cases = forms()
    for _ in range(args.repeat):
        for name, mech in cases:
            wmap, dt, _ = run(mech, args.n, False)
            best[name] = min(best.get(name, np.inf), dt)
            maps[name] = wmap
    if args.profile:
        for name, mech in cases:
            profiles[name] = parts(run(mech, args.n, True)[2])
    (na, a), (nb, b) = ((name, maps[name]) for name, _ in cases)
    kinds = [sorted(str(c.kind) for c in m.curves) for m in (a, b)]
    same = kinds[0] == kinds[1] and np.array_equal(np.asarray(a.modes[0].assembled), np.asarray(b.modes[0].assembled))
    for name, mech in cases:
        print(f"{name:22s} {best[name]:8.1f} s   ({size(mech)})")
        if name in profiles:
            print("    profiled: " + ", ".join(f"{k} {v:.1f} s" for k, v in profiles[name].items()))
    print(f"ratio joint / node: {best[nb] / best[na]:.2f}; same map: {same} "
          f"(curves {kinds[0]} / {kinds[1]}); load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
