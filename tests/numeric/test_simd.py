"""The vector batch loop (symkin.numeric.simd) gives CasADi's scalar results bit for bit."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from symkin.analysis.batch import evaluators
from symkin.model.catalogue import get
from symkin.numeric import codegen, simd

needs_cc = pytest.mark.skipif(shutil.which(codegen.find_compiler()) is None, reason="no C compiler")

#: values where the operations' corner cases live: signed zeros, infinities, NaN, subnormals
SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.5, -3.75, 1e-310, -1e-310, 1e308, -1e308, np.inf, -np.inf, np.nan, 0.1]


def _cpu_flags() -> set[str]:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return set()
    for line in text.splitlines():
        if line.startswith("flags"):
            return set(line.split(":", 1)[1].split())
    return set()


def _every_op() -> ca.Function:
    """An SX Function that uses every operation of ``simd.SUPPORTED`` on two inputs."""
    x = ca.SX.sym("x")
    y = ca.SX.sym("y")
    outs = [x + y, x - y, x * y, x / y, -x, x * x, 2 * x, 1 / x, ca.sqrt(x), ca.fabs(x),
            ca.fmax(x, y), ca.fmin(x, y), x < y, x <= y, x == y, x != y,
            ca.logic_not(x), ca.logic_and(x, y), ca.logic_or(x, y),
            ca.if_else(x < y, x * 3, y, False), ca.sign(x), ca.SX(-0.0) + 0 * x, ca.SX(np.inf) * 0 + x,
            y ** 2]
    f = ca.Function("every_op", [ca.vertcat(x, y)], [ca.vertcat(*outs)], {"cse": True})
    ops = {f.instruction_id(k) for k in range(f.n_instructions())}
    assert ops <= simd.SUPPORTED and len(ops) >= 18  # the test exercises (nearly) the whole table
    return f


def _build(f: ca.Function, n: int, tmp: Path, flags, vector: bool) -> ca.Function:
    fm = f.map(f"{f.name()}_batch", "serial", n, [], [])
    tag = f"{f.name()}_{'v' if vector else 's'}_{abs(hash(tuple(flags))) % 10**8}"
    cg = ca.CodeGenerator(f"{tag}.c")
    cg.add(fm)
    cg.generate(str(tmp) + os.sep)
    c_path = tmp / f"{tag}.c"
    if vector:
        text = simd.patch_batch(c_path.read_text(), fm.name(), f, n)
        assert f"return sk_{f.name()}(arg, res, {n});" in text
        c_path.write_text(text)
    so = codegen.build_library(c_path, tmp / f"{tag}.so", flags=flags)
    return ca.external(fm.name(), str(so))


def _bits(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    return np.where(np.isnan(a), np.int64(-1), a.view(np.int64))  # NaN payloads aside, every bit


def _widths() -> list[tuple[str, tuple]]:
    out = [("sse2 (2 lanes)", codegen.DEFAULT_FLAGS),
           ("no vector code (-DSYMKIN_NO_VECTOR: CasADi's bodies)", codegen.DEFAULT_FLAGS + ("-DSYMKIN_NO_VECTOR",))]
    flags = _cpu_flags()
    if "avx2" in flags:
        out.append(("avx2 (4 lanes)", codegen.DEFAULT_FLAGS + ("-mavx2",)))
    if "avx512f" in flags:
        out.append(("avx512 (8 lanes)", codegen.DEFAULT_FLAGS + ("-mavx512f",)))
    return out


@needs_cc
@pytest.mark.parametrize("n", [1, 7, 64])  # fewer than, not a multiple of, and a multiple of the lanes
def test_every_operation_bit_for_bit_on_special_values(n, tmp_path):
    f = _every_op()
    pairs = np.array([(a, b) for a in SPECIAL for b in SPECIAL])
    scalar = {}
    for label, flags in _widths():
        s = _build(f, n, tmp_path, flags, vector=False)
        v = _build(f, n, tmp_path, flags, vector=True)
        for start in range(0, len(pairs), n):
            chunk = pairs[start:start + n]
            if len(chunk) < n:
                chunk = np.vstack([chunk, np.tile(chunk[-1], (n - len(chunk), 1))])
            qs = ca.DM(chunk.T)
            ref = _bits(s(qs))
            scalar.setdefault(start, ref)
            np.testing.assert_array_equal(_bits(v(qs)), ref, err_msg=f"{label}, pairs {start}..")
            np.testing.assert_array_equal(ref, scalar[start], err_msg=f"{label}: scalar code differs by flags")


@needs_cc
@pytest.mark.slow
@pytest.mark.parametrize("name", ["rrr_3", "double_parallelogram"])
def test_indicator_kernel_lanes_equal_scalar_at_every_width(name, tmp_path):
    """The r0 = 0 kernel (3-RRR) and the redundant-row one (a parallelogram with a redundant link); degenerate inputs (zeros, NaN, tiny) too."""
    ev = evaluators(get(name))
    f = ev.symbolic_function("indicators")
    rng = np.random.default_rng(3)
    q = ev.project(ev.q0 + 0.05 * ev.mech.length_scale * rng.standard_normal((60, ev.nf)))
    q = np.vstack([q, np.zeros((2, ev.nf)), np.full((2, ev.nf), np.nan), q[:1] * 1e-200])  # 0/0, NaN
    qs = ca.DM(q.T)
    n = q.shape[0]
    ref = None
    for label, flags in _widths():
        s = _build(f, n, tmp_path, flags, vector=False)
        v = _build(f, n, tmp_path, flags, vector=True)
        a = _bits(np.vstack([np.array(x) for x in s(qs)]))
        b = _bits(np.vstack([np.array(x) for x in v(qs)]))
        np.testing.assert_array_equal(b, a, err_msg=label)
        ref = a if ref is None else ref
        np.testing.assert_array_equal(a, ref, err_msg=f"{label}: scalar code differs by flags")


def test_unsupported_operation_keeps_casadi_loop():
    x = ca.SX.sym("x")
    f = ca.Function("s", [x], [ca.sin(x)])
    assert simd.lanes_source(f, "s_batch") is None
    text = "int unrelated(void);\n"
    assert simd.patch_batch(text, "s_batch", f, 8) == text
    mx = ca.MX.sym("x")
    assert simd.lanes_source(ca.Function("m", [mx], [2 * mx]), "m_batch") is None


def test_patch_needs_the_exported_function():
    x = ca.SX.sym("x")
    with pytest.raises(ValueError, match="no exported function 'f_batch'"):
        simd.patch_batch("int other(void);\n", "f_batch", ca.Function("f", [x], [2 * x]), 4)


@needs_cc
def test_compiled_evaluators_use_the_vector_loop(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    ev = evaluators(get("rrr_3")).compile()
    assert ev.compiled
    text = Path(ev.library).with_suffix(".c").read_text()
    # one vector kernel serves the single call and the batch loop
    assert "return sk_indicators(arg, res, 1);" in text
    assert f"return sk_indicators(arg, res, {ev.functions['indicators_batch'].size_in(0)[1]});" in text
    assert text.count("static int sk_indicators(") == 1


def test_native_flags_key_holds_the_processor():
    assert codegen._target_fingerprint(codegen.DEFAULT_FLAGS) == ""
    native = codegen._target_fingerprint(codegen.NATIVE_FLAGS)
    assert len(native) == 16
    mech = get("rrr_3")
    assert codegen.artefact_stem(mech, "cc", codegen.DEFAULT_FLAGS) != codegen.artefact_stem(mech, "cc", codegen.NATIVE_FLAGS)
