"""Benchmark of large models (issue 19): trusses of 100 – 10,000 nodes through the sparse path.

Run on demand (not part of the test suite), from a checkout::

    python benchmarks/bench_large.py [--sizes 100 300 1000 3000 10000] [--dense-max 300]
                                     [--pyrigi-max 300] [--json out.json]

The frameworks are written as model files by the generators below, as a user would, and
read back with ``symkin.read_model``:

* **planar truss**: an ``nx × ny`` grid triangulated by one diagonal per cell, pinned by
  fixing the two first nodes of its bottom row (a bar between them: statically
  determinate supports); rigid, with ``(nx − 2)(ny − 2)`` redundant bars;
* **spatial truss**: an ``n × n × n`` grid, each node barred to its 7 neighbours in the
  positive directions (the Freudenthal triangulation of the cubes into tetrahedra), nodes
  moved by up to 10 % of the spacing (seeded), pinned by fixing a triangle of three nodes;
* **rigid body**: one link of 1,000 nodes (the fuzz test's case), pinned at two nodes.

Each case runs in a fresh process (so that its peak resident memory is its own) and
reports: reading the file, ``symkin.analyze`` (the classification: rank, flexes, the number
of self-stresses), the text report (which computes the few stresses it shows), the JSON
report (which computes and lists every stress), the ``symkin analyze`` command line's wall
time, and the peak resident memory (``ru_maxrss``: the process's, the interpreter's ~120 MB
included; the case's, above the process after its imports, up to the text report and
with the JSON report).  Below the size switch (``symkin.analysis.sparse.LARGE_COORDINATES``)
``analyze`` takes the dense path; the rows say which.
Baselines in the same run: the dense path (``classify(model_rows(m))``, the paper's
pairwise form and one full SVD) up to ``--dense-max`` nodes, and PyRigi 1.3
(``Framework.is_inf_rigid(numerical=True)`` and ``Framework.stresses(numerical=True)`` on
the same framework, unpinned: the same counts) up to ``--pyrigi-max`` nodes (planar and
spatial), when it is installed.  The spatial rows say how the dependent rows were chosen
(``LDLT``, ``pivoted``: :class:`symkin.analysis.sparse.SparseStresses`), how many of the listed
stresses are local (:class:`symkin.numeric.sparse_rows.LocalStresses`) and their mean number of bars.  The growth exponents of time and memory over the planar sizes are the slopes
of least-squares lines in log–log.  One thread (``OMP_NUM_THREADS=1``).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


# ---------------------------------------------------------------------- generators (used by the tests too)
def planar_truss(nx: int, ny: int, extra: int = 0, spacing: float = 1.0, angle: float = 0.0,
                 seed: int = 1) -> dict:
    """A triangulated ``nx × ny`` planar grid truss (model dictionary); see the module docstring.

    ``extra`` cells (chosen with ``seed``) also get their second diagonal: each is one more
    redundant bar.  ``spacing`` and ``angle`` (radians) scale and turn the whole truss.
    """
    c, s = math.cos(angle), math.sin(angle)

    def name(i, j):
        return f"N{i}_{j}"

    nodes = {}
    for j in range(ny):
        for i in range(nx):
            x, y = i * spacing, j * spacing
            nodes[name(i, j)] = [c * x - s * y, s * x + c * y]
    links: dict[str, list[str]] = {}
    for j in range(ny):
        for i in range(nx):
            if i + 1 < nx:
                links[f"b{len(links)}"] = [name(i, j), name(i + 1, j)]
            if j + 1 < ny:
                links[f"b{len(links)}"] = [name(i, j), name(i, j + 1)]
            if i + 1 < nx and j + 1 < ny:
                links[f"b{len(links)}"] = [name(i, j), name(i + 1, j + 1)]
    cells = [(i, j) for j in range(ny - 1) for i in range(nx - 1)]
    for i, j in random.Random(seed).sample(cells, extra):
        links[f"b{len(links)}"] = [name(i + 1, j), name(i, j + 1)]
    return {"name": f"planar truss {nx}x{ny}", "dim": 2, "mobility": 0,
            "fixed": [name(0, 0), name(1, 0)], "nodes": nodes, "links": links}


def spatial_truss(nx: int, ny: int, nz: int, spacing: float = 1.0, jitter: float = 0.1, seed: int = 1) -> dict:
    """A spatial grid truss of ``nx × ny × nz`` nodes (model dictionary); see the module docstring."""
    rng = random.Random(seed)

    def name(i, j, k):
        return f"N{i}_{j}_{k}"

    nodes = {}
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                nodes[name(i, j, k)] = [(i + jitter * rng.uniform(-1, 1)) * spacing,
                                        (j + jitter * rng.uniform(-1, 1)) * spacing,
                                        (k + jitter * rng.uniform(-1, 1)) * spacing]
    links: dict[str, list[str]] = {}
    steps = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 0, 1), (0, 1, 1), (1, 1, 1)]
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                for di, dj, dk in steps:
                    if i + di < nx and j + dj < ny and k + dk < nz:
                        links[f"b{len(links)}"] = [name(i, j, k), name(i + di, j + dj, k + dk)]
    return {"name": f"spatial truss {nx}x{ny}x{nz}", "dim": 3, "mobility": 0,
            "fixed": [name(0, 0, 0), name(1, 0, 0), name(0, 1, 0)], "nodes": nodes, "links": links}


def rigid_body(k: int, dim: int = 2) -> dict:
    """One link of ``k`` nodes on a grid (the fuzz test's large link), two of them fixed."""
    nodes = {f"Z{m}": [1.0 + m % 97, 1.0 + m // 97, 0.0][:dim] for m in range(k)}
    return {"name": f"rigid body of {k} nodes", "dim": dim, "mobility": 0, "fixed": ["Z0", "Z1"],
            "nodes": nodes, "links": {"body": list(nodes)}}


def planar_of(n: int, extra: int = 0) -> dict:
    """The planar truss of about ``n`` nodes: ``nx = ⌊√n⌋``, ``ny = n // nx``."""
    nx = int(math.isqrt(n))
    return planar_truss(nx, n // nx, extra)


def spatial_of(n: int) -> dict:
    """The spatial truss of about ``n`` nodes (a cube of ``round(n^(1/3))`` nodes a side)."""
    c = round(n ** (1 / 3))
    return spatial_truss(c, c, c)


# ---------------------------------------------------------------------- one case, in its own process
def _one(kind: str, n: int, what: str, folder: str) -> dict:
    import symkin
    from symkin.analysis.classification import classify
    from symkin.analysis.motion_space import model_rows
    from symkin.report import render_text

    base_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # after the imports
    data = {"planar": planar_of, "spatial": spatial_of, "body": rigid_body}[kind](n)
    path = Path(folder) / f"{kind}_{n}.json"
    path.write_text(json.dumps(data))
    out: dict = {"kind": kind, "n": len(data["nodes"]), "bars": len(data["links"]), "what": what}
    t = time.perf_counter()
    mech = symkin.read_model(str(path))
    out["read"] = time.perf_counter() - t
    if what == "analyze":
        t = time.perf_counter()
        a = symkin.analyze(mech)
        out["analyze"] = time.perf_counter() - t
        t = time.perf_counter()
        render_text(a)
        out["text"] = time.perf_counter() - t
        out["text_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 - base_mb
        t = time.perf_counter()
        json.dumps(a.to_dict())
        out["json"] = time.perf_counter() - t
        out.update(dof=a.dof, stresses=a.redundant_constraints, listed=len(a.self_stresses),
                   choice=getattr(a.self_stresses, "choice", None), local=getattr(a.self_stresses, "local", None),
                   support=sum(r.r for r in a.self_stresses) / max(len(a.self_stresses), 1))
    elif what == "dense":
        t = time.perf_counter()
        a = classify(model_rows(mech))
        out["analyze"] = time.perf_counter() - t
        out.update(dof=a.dof, stresses=a.redundant_constraints)
    elif what == "pyrigi":
        from pyrigi import Framework, Graph

        t = time.perf_counter()
        fw = Framework(Graph([tuple(v) for v in data["links"].values()]), dict(data["nodes"]))
        rigid = fw.is_inf_rigid(numerical=True)
        stresses = fw.stresses(numerical=True)
        out["analyze"] = time.perf_counter() - t
        out.update(dof=0 if rigid else None, stresses=len(stresses))
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    out["case_mb"] = out["peak_mb"] - base_mb
    out["sparse"] = what == "analyze" and __import__("symkin.analysis.sparse").analysis.sparse.is_large(mech)
    return out


def _run(kind: str, n: int, what: str, folder: str) -> dict:
    proc = subprocess.run([sys.executable, __file__, "--one", kind, str(n), what, folder],
                          capture_output=True, text=True)
    if proc.returncode:
        return {"kind": kind, "n": n, "what": what, "error": proc.stderr.strip().splitlines()[-1:]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _cli(kind: str, n: int, folder: str) -> float:
    path = Path(folder) / f"{kind}_{n}.json"
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "symkin", "analyze", str(path)], capture_output=True, text=True)
    if proc.returncode:
        return math.nan
    return time.perf_counter() - t


def _slope(xs, ys) -> float:
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def _have_pyrigi() -> bool:
    try:
        import pyrigi  # noqa: F401
    except ImportError:
        return False
    return True


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 1000, 3000, 10000])
    p.add_argument("--spatial", type=int, nargs="*", default=[1000, 3375])
    p.add_argument("--dense-max", type=int, default=300, help="largest planar size run on the dense path")
    p.add_argument("--pyrigi-max", type=int, default=300, help="largest size (planar or spatial) run with PyRigi")
    p.add_argument("--no-body", action="store_true", help="skip the 1,000-node rigid body")
    p.add_argument("--json", help="write the rows to this file")
    p.add_argument("--one", nargs=4, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.one:
        kind, n, what, folder = args.one
        print(json.dumps(_one(kind, int(n), what, folder)))
        return 0
    print(f"load average {os.getloadavg()[0]:.2f}; PyRigi {'installed' if _have_pyrigi() else 'not installed'}")
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        cases = [("planar", n) for n in args.sizes] + [("spatial", n) for n in args.spatial] + \
            ([("body", 1000)] if not args.no_body else [])
        for kind, n in cases:
            row = _run(kind, n, "analyze", folder)
            if "error" not in row:
                row["cli"] = _cli(kind, n, folder)
            new = [row]
            if kind == "planar" and n <= args.dense_max:
                new.append(_run(kind, n, "dense", folder))
            if kind in ("planar", "spatial") and n <= args.pyrigi_max and _have_pyrigi():
                new.append(_run(kind, n, "pyrigi", folder))
            _print(new)
            rows += new
    print(f"load average {os.getloadavg()[0]:.2f}")
    _summary(rows)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=2))
    return 0


def _fmt(v, unit="s") -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.3g} {unit}"


def _print(rows) -> None:
    for r in rows:
        if "error" in r:
            print(f"{r['kind']:8} {r['n']:>6} {r['what']:7} error: {r['error']}")
            continue
        what = r["what"] + (" (sparse)" if r.get("sparse") else " (dense)" if r["what"] == "analyze" else "")
        print(f"{r['kind']:8} {r['n']:>6} nodes {what:18} read {_fmt(r['read'])}, analyze {_fmt(r['analyze'])}, "
              f"text {_fmt(r.get('text'))}, json {_fmt(r.get('json'))}, CLI {_fmt(r.get('cli'))}, "
              f"peak {_fmt(r['peak_mb'], 'MB')} (+{_fmt(r['case_mb'], 'MB')} for the case, "
              f"+{_fmt(r.get('text_mb'), 'MB')} up to the text report); "
              f"DOF {r['dof']}, {r['stresses']} self-stresses"
              + (f" ({r['listed']} listed)" if r.get("listed", r["stresses"]) != r["stresses"] else "")
              + (f", rows chosen by {r['choice']}" if r.get("choice") else "")
              + (f", {r['local']} local, {r['support']:.1f} bars a stress on average"
                 if r.get("listed") and r.get("local") is not None else ""),
              flush=True)


def _summary(rows) -> None:
    sparse = [r for r in rows if r["kind"] == "planar" and r["what"] == "analyze" and "error" not in r]
    if len(sparse) >= 2:
        ns = [r["n"] for r in sparse]
        print(f"planar growth exponents over {ns[0]}–{ns[-1]} nodes: analyze {_slope(ns, [r['analyze'] for r in sparse]):.2f}, "
              f"analyze + text {_slope(ns, [r['analyze'] + r['text'] for r in sparse]):.2f}, "
              f"analyze + JSON {_slope(ns, [r['analyze'] + r['json'] for r in sparse]):.2f}, "
              f"peak memory {_slope(ns, [r['peak_mb'] for r in sparse]):.2f}, "
              f"memory of the case (peak minus the process after its imports) "
              f"{_slope(ns, [max(r['case_mb'], 1.0) for r in sparse]):.2f} "
              f"(up to the text report {_slope(ns, [max(r['text_mb'], 1.0) for r in sparse]):.2f})")
    for what in ("dense", "pyrigi"):
        for r in (r for r in rows if r["what"] == what and "error" not in r):
            s = next((x for x in rows if x["kind"] == r["kind"] and x["what"] == "analyze" and x["n"] == r["n"]
                      and "error" not in x), None)
            if s:
                print(f"{r['kind']} {r['n']} nodes: {what} / analyze = {r['analyze'] / s['analyze']:.1f}× "
                      f"(counts {what}: DOF {r['dof']}, {r['stresses']} stresses; analyze: DOF {s['dof']}, "
                      f"{s['stresses']})")


if __name__ == "__main__":
    sys.exit(main())
