"""Generated C for the evaluators (issue 3, requirement 6) and ``symkin codegen``."""
from __future__ import annotations

import argparse
import json
import os
import shutil
import stat
import subprocess
import warnings
import zlib
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from symkin.commands import codegen as codegen_command
from symkin.model.catalogue import get
from symkin.numeric import codegen
from symkin.analysis.batch import evaluators

HAVE_CC = shutil.which(codegen.find_compiler()) is not None
needs_cc = pytest.mark.skipif(not HAVE_CC, reason="no C compiler on this machine")
FOURBAR = str(Path(__file__).resolve().parents[2] / "papers_examples" / "fourbar_appendix.toml")


def _configurations(ev, n, seed):
    rng = np.random.default_rng(seed)
    return ev.project(ev.q0 + 0.05 * ev.mech.length_scale * rng.standard_normal((n, ev.nf)))


@pytest.fixture
def cache(tmp_path, monkeypatch):
    directory = tmp_path / "cache"
    monkeypatch.setenv("SYMKIN_CACHE", str(directory))
    return directory


def _all_outputs(ev, q):
    out = {}
    for name in ev.functions:
        if name.endswith("_batch"):  # used by map() for whole blocks of configurations
            continue
        res = ev.map(name, q)
        for key, value in res.items():
            out[f"{name}.{key}"] = value
    return out


@needs_cc
@pytest.mark.parametrize("name", ["rrr_3", "rssr", "slider_crank"])
def test_generated_code_gives_identical_numbers(name, cache):
    ev = evaluators(get(name))
    q = _configurations(ev, 1100, zlib.crc32(name.encode()))  # one block of 1024 and a rest
    before = _all_outputs(ev, q)
    single_before = ev("indicators", q[0])
    assert ev.compile() is ev
    assert ev.compiled and ev.library.startswith(str(cache))
    assert all(isinstance(f, ca.Function) and f.class_name() != "SXFunction" for f in ev.functions.values())
    after = _all_outputs(ev, q)
    assert before.keys() == after.keys()
    for key in before:
        np.testing.assert_array_equal(after[key], before[key], err_msg=key)  # bit for bit
    single_after = ev("indicators", q[0])
    for key in single_before:
        np.testing.assert_array_equal(single_after[key], single_before[key])
    # batch decisions do not change either
    assert np.array_equal(ev.batch(q).dof, evaluators(get(name)).batch(q).dof)


@needs_cc
def test_artefacts_are_cached_by_content_hash_and_casadi_version(cache, monkeypatch):
    mech = get("fourbar_appendix")
    ev = evaluators(mech).compile()
    lib = ev.library
    stem = lib.rsplit("/", 1)[1]
    assert mech.content_hash()[:20] in stem
    assert "casadi" + ca.__version__.replace(".", "_") in stem
    for suffix in (".c", ".h", ".json"):
        assert (cache / stem.replace(".so", suffix)).exists()

    def no_compiler(*args, **kwargs):
        raise codegen.CompilerError("compiled again although the artefact is cached")

    monkeypatch.setattr(codegen, "build_library", no_compiler)
    again = evaluators(mech).compile()  # a new process would do the same: load from disk
    assert again.compiled and again.library == lib
    # another configuration is another model: another artefact
    other = mech.with_coordinates({"B": (0.25, 0.9)})
    assert other.content_hash() != mech.content_hash()
    with pytest.warns(codegen.CodegenWarning, match="compiled again"):
        evaluators(other).compile()


@needs_cc
def test_a_damaged_cached_library_is_rebuilt(cache):
    d = get("slider_crank").to_dict()
    d["nodes"]["B"] = [0.8, 0.6]  # a model no other test has loaded in this process
    from symkin import Mechanism

    mech = Mechanism.from_dict(d)
    stem = codegen.artefact_stem(mech, codegen.find_compiler(), codegen.DEFAULT_FLAGS)
    cache.mkdir(parents=True, exist_ok=True)
    so = cache / f"{stem}.so"
    so.write_bytes(b"not a shared library")
    ev = evaluators(mech).compile()
    assert ev.compiled and ev.library == str(so) and so.stat().st_size > 1000
    np.testing.assert_array_equal(ev("G", ev.q0)["G"], evaluators(mech)("G", ev.q0)["G"])


@needs_cc
def test_force_recompiles(cache):
    ev = evaluators(get("fourbar_appendix")).compile()
    so = cache / ev.library.rsplit("/", 1)[1]
    first = so.stat().st_mtime_ns
    evaluators(get("fourbar_appendix")).compile(force=True)
    assert so.stat().st_mtime_ns > first


@pytest.mark.parametrize("setting", ["compiler", "flags"])
def test_without_a_working_compiler_the_in_process_functions_stay(cache, setting):
    ev = evaluators(get("five_bar"))
    q = _configurations(ev, 10, 7)
    before = ev.batch(q)
    kwargs = {"compiler": "/nonexistent/symkin-cc"} if setting == "compiler" else {"flags": ["-no-such-flag"]}
    with pytest.warns(codegen.CodegenWarning, match="in-process"):
        out = ev.compile(**kwargs)
    assert out is ev and not ev.compiled and ev.library is None
    assert ev.functions["indicators"] is ev.symbolic_function("indicators")
    after = ev.batch(q)
    np.testing.assert_array_equal(after.im_indicator, before.im_indicator)
    assert not list(cache.glob("*.so"))


def test_compiler_error_names_the_compiler(tmp_path):
    ev = evaluators(get("fourbar_appendix"))
    c_path, _ = codegen.generate_sources(ev, tmp_path, "m")
    with pytest.raises(codegen.CompilerError, match="nonexistent"):
        codegen.build_library(c_path, tmp_path / "m.so", compiler="/nonexistent/cc")


def test_header_documents_argument_order_and_names(tmp_path):
    ev = evaluators(get("rrr_3"))
    _, h_path = codegen.generate_sources(ev, tmp_path, "rrr")
    text = h_path.read_text()
    for i, label in enumerate(ev.q_labels):
        assert f"q[{i}] = {label}" in text
    for i, label in enumerate(ev.p_labels):
        assert f"p[{i}] = {label}" in text
    for i, owner in enumerate(ev.row_owners):
        assert f"row {i}: {owner}" in text
    assert "indicators(q [12x1]) -> (im [1x1], im_certified [1x1], trace [1x1], dkp_input [1x1]" in text
    assert "G(q [12x1]) -> (G [12x12], G_full [18x18])" in text
    assert "res[3] dkp_input:" in text
    assert "int indicators(const casadi_real** arg, casadi_real** res" in text


@needs_cc
def test_a_c_program_calls_the_generated_function_through_its_header(tmp_path):
    """The header is enough to call the code from C, in the documented argument order."""
    ev = evaluators(get("fourbar_appendix"))
    c_path, h_path = codegen.generate_sources(ev, tmp_path, "fb")
    main = tmp_path / "main.c"
    q = ev.q0
    main.write_text(
        '#include <stdio.h>\n#include "fb.h"\n'
        "int main(void) {\n"
        f"  casadi_real q[4] = {{{', '.join(repr(float(v)) for v in q)}}};\n"
        "  casadi_real r[7]; const casadi_real* arg[indicators_SZ_ARG]; casadi_real* res[indicators_SZ_RES];\n"
        "  casadi_int iw[indicators_SZ_IW + 1]; casadi_real w[indicators_SZ_W + 1]; int i;\n"
        "  arg[0] = q; for (i = 0; i < 7; ++i) res[i] = r + i;\n"
        "  if (indicators(arg, res, iw, w, 0)) return 1;\n"
        '  for (i = 0; i < 7; ++i) printf("%.17g\\n", r[i]);\n  return 0;\n}\n')
    exe = tmp_path / "main"
    subprocess.run([codegen.find_compiler(), "-O2", str(main), str(c_path), "-o", str(exe), "-lm"],
                   check=True, capture_output=True)
    printed = [float(v) for v in subprocess.run([str(exe)], check=True, capture_output=True,
                                                text=True).stdout.split()]
    expected = ev("indicators", q)
    assert printed == [float(expected[name][0, 0]) for name in ev.functions["indicators"].name_out()]


def _run_command(argv):
    parser = argparse.ArgumentParser()
    codegen_command.add_arguments(parser)
    return codegen_command.run(parser.parse_args(argv))


@needs_cc
def test_codegen_command_writes_sources_header_and_a_loadable_library(tmp_path):
    model = tmp_path / "fivebar.json"
    from symkin.model.catalogue import data

    model.write_text(json.dumps(data("five_bar")))
    out_dir = tmp_path / "gen"
    mask = os.umask(0o022)
    try:
        out = _run_command([str(model), "--out", str(out_dir)])
    finally:
        os.umask(mask)
    assert out.code == 0, out.message
    for suffix in (".c", ".h", ".json", ".so"):
        assert (out_dir / f"fivebar_evaluators{suffix}").exists()
    # modes of any generated file under umask 022 (not mkstemp's 0600): sources 0644, the library 0755
    modes = {suffix: stat.S_IMODE((out_dir / f"fivebar_evaluators{suffix}").stat().st_mode)
             for suffix in (".c", ".h", ".json", ".so")}
    assert modes == {".c": 0o644, ".h": 0o644, ".json": 0o644, ".so": 0o755}
    assert "indicators(q[6x1]) -> im[1x1]" in out.text
    ev = evaluators(get("five_bar"))
    q = _configurations(ev, 5, 3)
    so = str(out_dir / "fivebar_evaluators.so")
    for name in ("G", "J", "indicators", "closure_jacobian", "motion"):
        loaded = ca.external(name, so)
        assert loaded.name_in() == ev.functions[name].name_in()
        assert loaded.name_out() == ev.functions[name].name_out()
        for k in range(q.shape[0]):
            args = [q[k]] + ([ev.p0] if loaded.n_in() == 2 else [])
            mine = ev.functions[name].call(args)
            theirs = loaded.call(args)
            for a, b in zip(mine, theirs):
                np.testing.assert_array_equal(np.array(a), np.array(b))
    manifest = json.loads((out_dir / "fivebar_evaluators.json").read_text())
    assert manifest["q"] == list(ev.q_labels)
    assert manifest["content_hash"] == ev.mech.content_hash()


def test_codegen_command_without_compiler_writes_sources_and_fails(tmp_path):
    out = _run_command([FOURBAR, "--out", str(tmp_path),
                        "--compiler", "/nonexistent/cc", "--name", "fb"])
    assert out.code == 1 and "not found" in out.message
    assert (tmp_path / "fb.c").exists() and (tmp_path / "fb.h").exists()
    assert not (tmp_path / "fb.so").exists()


def test_codegen_command_no_compile_and_stem(tmp_path):
    out = _run_command([FOURBAR, "--out", str(tmp_path),
                        "--no-compile", "--name", "4-bar model"])
    assert out.code == 0
    assert (tmp_path / "m_4_bar_model.c").exists()
    assert not list(tmp_path.glob("*.so"))


def test_codegen_command_rejects_a_file_as_out(tmp_path):
    from symkin.errors import SymkinError

    target = tmp_path / "file"
    target.write_text("")
    with pytest.raises(SymkinError, match="not a directory"):
        _run_command([FOURBAR, "--out", str(target)])


def test_command_module_interface():
    assert codegen_command.NAME == "codegen"
    assert codegen_command.HELP
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parser = argparse.ArgumentParser()
        codegen_command.add_arguments(parser)


@needs_cc
@pytest.mark.parametrize("n", [200, 1024 + 300])  # below one block, and a block plus a padded rest
def test_padded_last_block_gives_identical_numbers(n, cache):
    """A last partial block goes through the generated loop padded; the numbers do not change."""
    ev = evaluators(get("rrr_3"))
    q = _configurations(ev, n, 11)
    before = ev.map("indicators", q)
    ev.compile()
    after = ev.map("indicators", q)
    for key in before:
        np.testing.assert_array_equal(after[key], before[key], err_msg=key)
    assert after["im"].shape[0] == n
