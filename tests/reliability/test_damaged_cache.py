"""A damaged artefact in the cache is rebuilt, never loaded (issue 20 §1).

A truncated or zero-filled shared library can be mapped by the dynamic loader and then
crash the process with SIGBUS or SIGSEGV: every run here is a subprocess whose return
code is checked.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from symkin.numeric import codegen

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "papers_examples" / "fourbar_appendix.toml"
needs_cc = pytest.mark.skipif(shutil.which(codegen.find_compiler()) is None, reason="no C compiler")

_EVALUATE = """
import json, warnings
import symkin
from symkin.model.catalogue import get
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    ev = symkin.evaluators(get("fourbar_appendix")).compile()
    g = ev("G", ev.q0)["G"].tolist()
print(json.dumps({"compiled": ev.compiled, "G": g, "warnings": [str(w.message) for w in caught]}))
"""
_PATH = [sys.executable, "-m", "symkin", "path", str(FOURBAR), "--input", "rotation:crank",
         "--from", "0", "--to", "120", "--unit", "deg"]


def _run(cmd, cache):
    env = dict(os.environ, SYMKIN_CACHE=str(cache), PYTHONPATH=str(ROOT))
    return subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)


def _evaluate(cache):
    proc = _run([sys.executable, "-c", _EVALUATE], cache)
    assert proc.returncode == 0, f"exit {proc.returncode}: {proc.stderr[-2000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _halve(so: Path, other: Path) -> None:
    os.truncate(so, so.stat().st_size // 2)


def _to_1000_bytes(so: Path, other: Path) -> None:
    os.truncate(so, 1000)


def _zero_8k_in_the_middle(so: Path, other: Path) -> None:
    with open(so, "r+b") as fh:
        fh.seek(max(0, so.stat().st_size // 2 - 4096))
        fh.write(b"\0" * 8192)


def _replace_by_another_library(so: Path, other: Path) -> None:
    shutil.copyfile(other, so)


DAMAGES = [_halve, _to_1000_bytes, _zero_8k_in_the_middle, _replace_by_another_library]


@pytest.mark.slow
@needs_cc
def test_every_damaged_library_is_rebuilt_with_a_warning_and_the_results_stay(tmp_path):
    cache = tmp_path / "cache"
    good = _evaluate(cache)
    assert good["compiled"] and not good["warnings"]
    path_good = _run(_PATH, cache)
    assert path_good.returncode == 0, path_good.stderr
    evaluators_so, = cache.glob("symkin_*.so")
    corrector_so, = (cache / "paths").glob("corrector_*.so")
    assert Path(str(evaluators_so) + ".sha256").exists() and Path(str(corrector_so) + ".sha256").exists()
    for damage in DAMAGES:
        damage(evaluators_so, corrector_so)
        again = _evaluate(cache)
        assert again["compiled"] and again["G"] == good["G"], damage.__name__
        assert len(again["warnings"]) == 1 and "damaged" in again["warnings"][0], (damage.__name__, again)
        assert codegen.verify_artefact(evaluators_so) is None
        damage(corrector_so, evaluators_so)
        path = _run(_PATH, cache)
        assert path.returncode == 0, (damage.__name__, path.returncode, path.stderr[-2000:])
        assert path.stdout == path_good.stdout, damage.__name__
        warning_lines = [ln for ln in path.stderr.splitlines() if "damaged" in ln]
        assert len(warning_lines) == 1 and len(path.stderr.strip().splitlines()) == 1, path.stderr
        assert codegen.verify_artefact(corrector_so) is None


def test_verify_artefact_sees_size_content_and_a_missing_record(tmp_path):
    so = tmp_path / "a.so"
    so.write_bytes(b"x" * 5000)
    assert codegen.verify_artefact(so) == "no recorded hash"
    codegen.record_artefact(so)
    assert codegen.verify_artefact(so) is None
    with open(so, "r+b") as fh:
        fh.seek(2000)
        fh.write(b"\0" * 100)
    assert "content" in codegen.verify_artefact(so)
    os.truncate(so, 1000)
    assert "size 1000" in codegen.verify_artefact(so)
    Path(str(so) + ".sha256").write_text("{not json")
    assert "unreadable" in codegen.verify_artefact(so)


def test_a_library_without_its_recorded_hash_is_rebuilt_not_loaded(tmp_path):
    calls = []

    def write_sources(tmp: Path) -> Path:
        calls.append(tmp)
        (tmp / "lib.c").write_text("double f(double x) { return x; }\n")
        return tmp / "lib.c"

    (tmp_path / "lib.so").write_bytes(b"\x7fELF" + b"\0" * 3000)  # would be mapped, then crash
    rebuilt = []
    original = codegen.build_library

    def fake_build(c_path, so_path, *a, **k):
        rebuilt.append(so_path)
        Path(so_path).write_bytes(b"a rebuilt library")
        return Path(so_path)

    codegen.build_library = fake_build
    try:
        with pytest.warns(codegen.CodegenWarning, match="damaged"):
            with pytest.raises(RuntimeError):  # our fake library does not load: the point is it was rebuilt
                codegen.cached_library(tmp_path, "lib", write_sources, ["f"])
    finally:
        codegen.build_library = original
    assert rebuilt and calls
    assert (tmp_path / "lib.so").read_bytes() == b"a rebuilt library"


def test_stale_build_folders_are_removed_and_fresh_ones_kept(tmp_path):
    old, fresh = tmp_path / ".build-old", tmp_path / ".build-fresh"
    old.mkdir()
    (old / "x.c").write_text("int x;")
    fresh.mkdir()
    hours_ago = time.time() - 2 * 3600
    os.utime(old, (hours_ago, hours_ago))
    assert codegen.clean_stale_builds(tmp_path) == [old]
    assert not old.exists() and fresh.exists()


def test_cache_command_prints_where_and_clears(tmp_path, monkeypatch, capsys):
    from symkin.cli import main

    cache = tmp_path / "c"
    (cache / "paths").mkdir(parents=True)
    (cache / "a.so").write_bytes(b"1" * 2048)
    (cache / "paths" / "b.so").write_bytes(b"2" * 1024)
    monkeypatch.setenv("SYMKIN_CACHE", str(cache))
    assert main(["cache"]) == 0
    out = capsys.readouterr().out
    assert str(cache) in out and "2 file(s)" in out and "3.0 KiB" in out
    assert main(["cache", "--clear"]) == 0
    assert "removed 2 file(s)" in capsys.readouterr().out
    assert cache.is_dir() and not any(cache.iterdir())
