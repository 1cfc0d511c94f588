"""Benchmark of the evaluators (issue 3, issue 7 §6): configurations per second, ratios to a baseline.

Run on demand from a checkout where symkin is installed (not part of the test suite)::

    python benchmarks/bench_evaluators.py [--batch 100000] [--loop 5000] [--models rrr_3 rssr]
                                          [--kernel fused|laguerre-sturm] [--json out.json]

For the 3-RRR and a spatial example (the RSSR) it measures, in one run and on valid
configurations (perturbed and projected onto the closure manifold):

(a) the baseline a researcher writes by hand: ``sympy.lambdify`` of the reduced G and
    ``numpy.linalg.eigh`` in a Python loop, one configuration at a time;
(b) symkin's numeric core per configuration: ``symkin.analyze`` (full classification) and
    ``symkin.motion_space`` (motion space only);
(c) CasADi in-process (SX virtual machine): the ``indicators`` Function called plainly and
    through CasADi's buffer interface;
(d) the generated C, loaded with ``casadi.external``: buffer calls (indicator values only)
    and ``ev.indicators_at`` (values and the core's IM / DKP decisions);
(e) ``ev.batch`` over ``--batch`` configurations (``Function.map`` + decisions), compiled and
    in-process, and the orthonormal motion-space bases ``ev.map("motion", ...)``; compiled
    three ways, alternating: the vector loop of :mod:`symkin.numeric.simd` with the default
    (portable) flags, CasADi's scalar loop (the code before it), and the vector loop with
    ``codegen.NATIVE_FLAGS`` (``-march=native``: 4 or 8 configurations per instruction);
(f) the indicator kernel alone, generated C, for both IM eigenvalue kernels and for the
    vector loop (default and native flags): CasADi instructions and CPU µs per
    configuration (best of several passes over 4096 configurations, alternating), and the
    share of configurations each one certifies.

and the time to generate, compile and load the C of each model (a fresh cache, wall
time).  Every figure is measured in this run; ratios are to (a).  Rates are per second of
the process's CPU time (``time.process_time``), so that other jobs on a shared machine,
which take the CPU from the Python baseline and from the generated code at different
moments, do not decide the ratios; they still slow both through shared caches.  The
load average is printed before and after.  One process, one thread: NumPy's
small-matrix LAPACK calls do not use threads.

``--kernel`` picks the IM eigenvalue kernel of (a)-(e): ``fused`` (the current one,
:func:`symkin.numeric.sx_linalg.smallest_eigenvalue`) or ``laguerre-sturm`` (the previous
one, :func:`symkin.numeric.sx_linalg.eigenvalue_above` with separate Sturm counts).
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import sys
import tempfile
import time

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import casadi as ca  # noqa: E402
import sympy as sp  # noqa: E402

import symkin  # noqa: E402
from symkin.analysis.batch import fast_caller  # noqa: E402
from symkin.analysis.batch import evaluators  # noqa: E402
from symkin.numeric import codegen, simd, sx_linalg  # noqa: E402
from symkin.numeric import evaluators as evaluators_module  # noqa: E402

#: the IM eigenvalue kernels of ``--kernel``: (A = J_e J_eᵀ, r0) → (value, certificate)
KERNELS = {
    "fused": evaluators_module._im_kernel,
    "laguerre-sturm": lambda gram, r0: sx_linalg.eigenvalue_above(*sx_linalg.householder_tridiagonal(gram), r0),
}


# ---------------------------------------------------------------------- the baseline (a)
def lambdified_g(mech):
    """The reduced G of a bar/body model written with sympy and lambdified, as a user would."""
    if mech.sliders:
        raise ValueError("the hand-written baseline covers bars and bodies only")
    free = [n for n in mech.node_names if n not in set(mech.fixed)]
    coords = mech.coordinates()
    syms = {n: sp.symbols(" ".join(f"{a}_{n}" for a in "xyz"[: mech.dim])) for n in free}
    pos = {n: (sp.Matrix(syms[n]) if n in syms else sp.Matrix(coords[n])) for n in mech.node_names}
    order = [s for n in free for s in syms[n]]
    g = sp.zeros(len(order), len(order))
    for _, ns in mech.links:
        for a in range(len(ns)):
            for b in range(a + 1, len(ns)):
                d = pos[ns[b]] - pos[ns[a]]
                u = d / sp.sqrt(sum(c ** 2 for c in d))
                row = sp.zeros(1, len(order))
                for sign, n in ((1, ns[a]), (-1, ns[b])):
                    if n in syms:
                        for c, s in enumerate(syms[n]):
                            row[0, order.index(s)] += sign * u[c]
                g += row.T * row
    return sp.lambdify(order, g, "numpy")


def baseline(mech, q, f_g, n_loop):
    f = mech.mobility_value
    out = np.empty(n_loop)
    start = time.process_time()
    for k in range(n_loop):
        w, v = np.linalg.eigh(f_g(*q[k]))
        out[k] = w[f]  # IM indicator; v[:, :f] the motion space
    return n_loop / (time.process_time() - start), out


# ---------------------------------------------------------------------- helpers
def rate(fn, n):
    gc.collect()
    gc.freeze()  # the sympy objects of the baseline should not slow the collector in later timings
    start = time.process_time()
    fn()
    return n / (time.process_time() - start)


def configurations(ev, n, seed=0):
    rng = np.random.default_rng(seed)
    q = ev.q0 + 0.05 * ev.mech.length_scale * rng.standard_normal((n, ev.nf))
    return ev.project(q)


# ---------------------------------------------------------------------- (f) the kernel alone
def kernel_function(ev, kernel: str) -> ca.Function:
    """The ``indicators`` Function of ``ev`` with the IM outputs of ``kernel`` (same rows, same DKP)."""
    cm = ev.model
    free = np.flatnonzero(cm.free).tolist()
    je = cm.J[:, free][list(ev.effective_rows), :]
    r0 = len(ev.effective_rows) - (ev.nf - ev.mobility)
    outs = ev.symbolic_function("indicators").call([cm.q])
    lam, ok = KERNELS[kernel](ca.mtimes(je, je.T), r0)
    return ca.Function(f"indicators_{kernel.replace('-', '_')}", [cm.q], [lam, ok] + outs[2:],
                       ["q"], list(evaluators_module.INDICATOR_NAMES), {"cse": True})


def compiled_map(f: ca.Function, n: int, directory: str, vector: bool = False,
                 flags=codegen.DEFAULT_FLAGS, tag: str = "") -> ca.Function:
    """``f`` mapped over ``n`` configurations, generated as C and loaded.

    ``vector``: the loop replaced by :mod:`symkin.numeric.simd`'s (as ``ev.compile()`` does).
    """
    fm = f.map(f"{f.name()}_map", "serial", n, [], [])
    stem = f"{f.name()}{tag}"
    cg = ca.CodeGenerator(f"{stem}.c")
    cg.add(fm)
    cg.generate(directory + os.sep)
    c_path = os.path.join(directory, f"{stem}.c")
    if vector:
        with open(c_path) as fh:
            text = simd.patch_batch(fh.read(), fm.name(), f, n)
        with open(c_path, "w") as fh:
            fh.write(text)
    so = codegen.build_library(c_path, os.path.join(directory, f"{stem}.so"), flags=flags)
    return ca.external(fm.name(), str(so))


def scalar_loop(ev, cache: str) -> None:
    """Compile ``ev`` with CasADi's own scalar batch loop (the code before the vector loop)."""
    saved = simd.patch
    codegen.simd.patch = lambda text, *args: text
    try:
        ev.compile(cache_dir=cache, force=True)
    finally:
        codegen.simd.patch = saved


def native(ev, cache: str) -> None:
    """Compile ``ev`` for this processor (``codegen.NATIVE_FLAGS``: wider vectors)."""
    ev.compile(cache_dir=cache, flags=codegen.NATIVE_FLAGS)


def _batch_arrays(res) -> list:
    return [res.im_indicator, res.dkp_input, res.dkp_output, res.dof, res.path]


def kernel_figures(ev, q: np.ndarray, passes: int = 15) -> dict:
    """Instructions, CPU µs per configuration and certified share of both kernels (generated C)."""
    n = 4096
    qs = ca.DM(np.ascontiguousarray(q[:n]).T)
    fns, out = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for kernel in KERNELS:
            f = kernel_function(ev, kernel)
            fns[kernel] = compiled_map(f, n, tmp)
            cert = np.array(fns[kernel](qs)[1]).ravel()
            out[kernel] = {"instructions": f.n_instructions(), "us": np.inf,
                           "certified": float(np.mean(cert == 1.0))}
        f = kernel_function(ev, "fused")
        for label, flags in (("fused, vector loop", codegen.DEFAULT_FLAGS),
                             ("fused, vector, native", codegen.NATIVE_FLAGS)):
            fns[label] = compiled_map(f, n, tmp, vector=True, flags=flags, tag=f"_v{len(fns)}")
            out[label] = dict(out["fused"], us=np.inf)
        for _ in range(passes):  # alternate, keep the best pass of each
            for kernel, fm in fns.items():
                start = time.process_time()
                fm(qs)
                out[kernel]["us"] = min(out[kernel]["us"], (time.process_time() - start) / n * 1e6)
    return out


def bench(name: str, n_batch: int, n_loop: int) -> dict:
    mech = symkin.catalogue.get(name)
    results: dict = {"model": name, "nf": None, "rates": {}, "notes": {}, "kernels": {}}
    t0 = time.perf_counter()
    ev = evaluators(mech)
    results["notes"]["build evaluators [s]"] = time.perf_counter() - t0
    results["nf"] = ev.nf
    q = configurations(ev, max(n_batch, n_loop))
    ql = q[:n_loop]
    r = results["rates"]

    results["kernels"] = kernel_figures(ev, q)
    f_g = lambdified_g(mech)
    r["(a) sympy.lambdify + numpy eigh, Python loop"], im_base = baseline(mech, ql, f_g, n_loop)

    n_core = max(200, n_loop // 10)
    r["(b) symkin.analyze per configuration"] = rate(
        lambda: [symkin.analyze(ev.mechanism_at(x)) for x in ql[:n_core]], n_core)
    r["(b) symkin.motion_space per configuration"] = rate(
        lambda: [symkin.motion_space(ev.mechanism_at(x)) for x in ql[:n_core]], n_core)

    f_sx = ev.functions["indicators"]
    r["(c) CasADi in-process, plain call"] = rate(lambda: [f_sx(x) for x in ql], n_loop)
    call = fast_caller(ev)
    r["(c) CasADi in-process, buffer call"] = rate(lambda: [call(x) for x in ql], n_loop)
    n_ip = min(n_batch, 20000)
    ev.batch(q[:10])
    r[f"(e) batch in-process ({n_ip} configurations)"] = rate(lambda: ev.batch(q[:n_ip]), n_ip)
    ref = ev.map("indicators", q[:1000])

    with tempfile.TemporaryDirectory() as cache:
        t0 = time.perf_counter()
        ev.compile(cache_dir=cache)
        results["notes"]["generate + compile + load C [s]"] = time.perf_counter() - t0
        if not ev.compiled:
            results["notes"]["compiled"] = False
            return results
        new = ev.map("indicators", q[:1000])
        results["notes"]["generated == in-process (bit for bit)"] = all(
            np.array_equal(ref[k], new[k]) for k in ref)
        call = fast_caller(ev)
        r["(d) generated C, buffer call (values)"] = rate(lambda: [call(x) for x in ql], n_loop)
        r["(d) generated C, indicators_at (values + decisions)"] = rate(
            lambda: [ev.indicators_at(x) for x in ql], n_loop)
        ev.batch(q[:10])
        variants = {"(e) batch, generated C, vector loop": ev}
        for label, build in (("(e) batch, generated C, CasADi's scalar loop (before)", scalar_loop),
                             ("(e) batch, generated C, vector loop, -march=native", native)):
            other = evaluators(mech)
            with tempfile.TemporaryDirectory() as extra:
                build(other, extra)
            if other.compiled:
                variants[label] = other
        best = {label: 0.0 for label in variants}
        for _ in range(3):  # alternate, keep the best round of each
            for label, e in variants.items():
                best[label] = max(best[label], rate(lambda: e.batch(q[:n_batch]), n_batch))
        for label, v in best.items():
            r[label.replace("(e) batch", f"(e) batch ({n_batch} configurations)")] = v
        before = variants.get("(e) batch, generated C, CasADi's scalar loop (before)")
        if before is not None:  # the single call: the vector kernel at one configuration, and CasADi's
            calls = {"vector kernel": fast_caller(ev), "CasADi's scalar kernel (before)": fast_caller(before)}
            single = {k: 0.0 for k in calls}
            for _ in range(3):
                for k, c in calls.items():
                    single[k] = max(single[k], rate(lambda: [c(x) for x in ql], n_loop))
            for k, v in single.items():
                r[f"(d) generated C, buffer call (values), {k}"] = v
        results["notes"]["vector loop == scalar loop (bit for bit)"] = all(
            np.array_equal(a, b, equal_nan=True)
            for e in variants.values()
            for a, b in zip(_batch_arrays(ev.batch(q[:5000])), _batch_arrays(e.batch(q[:5000]))))
        r[f"(e) motion-space bases V, generated C ({n_batch} configurations)"] = rate(
            lambda: ev.map("motion", q[:n_batch]), n_batch)
        res = ev.batch(q[:n_batch])
        results["notes"]["exact-path fraction in the batch"] = float(res.exact.mean())
        im = ev.batch(ql).im_indicator
        results["notes"]["max rel. difference of im vs baseline eigh"] = float(
            np.max(np.abs(im - im_base) / np.abs(im_base)))
    return results


def report(results: dict) -> str:
    lines = [f"== {results['model']} (nf = {results['nf']})"]
    rates = results["rates"]
    base = next(v for k, v in rates.items() if k.startswith("(a)"))
    width = max(len(k) for k in rates)
    lines.append(f"{'method'.ljust(width)}  {'configs/s':>12}  {'ratio to (a)':>12}")
    for k, v in rates.items():
        lines.append(f"{k.ljust(width)}  {v:12,.0f}  {v / base:12.1f}")
    for k, v in results["notes"].items():
        lines.append(f"  {k}: {v:.3g}" if isinstance(v, float) else f"  {k}: {v}")
    kernels = results.get("kernels") or {}
    if kernels:
        lines.append("(f) indicator kernel, generated C (CPU time, best pass over 4096 configurations):")
        ref = kernels["laguerre-sturm"]["us"]
        for k, v in kernels.items():
            lines.append(f"  IM kernel {k:22s} {v['instructions']:6d} instructions  {v['us']:6.3f} us/configuration"
                         f"  ({ref / v['us']:.2f}x the laguerre-sturm kernel)  certified {v['certified']:.4f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--batch", type=int, default=100_000, help="configurations in the batched runs")
    p.add_argument("--loop", type=int, default=5_000, help="configurations in the per-call loops")
    p.add_argument("--models", nargs="+", default=["rrr_3", "rssr"])
    p.add_argument("--kernel", choices=list(KERNELS), default="fused",
                   help="IM eigenvalue kernel of the evaluators timed in (a)-(e)")
    p.add_argument("--json", default=None, help="also write the figures to this file")
    args = p.parse_args(argv)
    if args.kernel != "fused":  # the evaluators are built with the previous kernel
        evaluators_module._im_kernel = KERNELS[args.kernel]
    print(f"symkin {symkin.__version__}, casadi {ca.__version__}, numpy {np.__version__}, "
          f"sympy {sp.__version__}, Python {platform.python_version()}, {platform.processor() or platform.machine()}")
    print(f"IM kernel of (a)-(e): {args.kernel}; load average at start: "
          + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    everything = []
    for name in args.models:
        res = bench(name, args.batch, args.loop)
        everything.append(res)
        print(report(res))
        sys.stdout.flush()
    print("load average at end: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(everything, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
