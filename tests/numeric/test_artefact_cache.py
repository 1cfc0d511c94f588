"""The one artefact cache (issue 7 §4): keys, atomic writes, concurrent builders."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from symkin.model.catalogue import get
from symkin.numeric import codegen

ROOT = Path(__file__).resolve().parents[2]
needs_cc = pytest.mark.skipif(shutil.which(codegen.find_compiler()) is None, reason="no C compiler")

_WORKER = r"""
import json, sys
import numpy as np
import symkin
from symkin.model.catalogue import get
from symkin.paths.system import make_curve
ev = symkin.evaluators(get("rrr_3"))
ev.compile()
corrector = make_curve(get("rrr_3")).fast_corrector
rng = np.random.default_rng(1)
q = ev.project(ev.q0 + 0.02 * ev.mech.length_scale * rng.standard_normal((50, ev.nf)))
ind = ev.map("indicators", q)
y = make_curve(get("rrr_3")).y0()
y_next, res, step, t_next = corrector.step(y, np.eye(y.size)[0], y)
print(json.dumps({"compiled": ev.compiled, "corrector_compiled": corrector.compiled, "library": ev.library,
                  "im": ind["im"].ravel().tolist(), "dkp": ind["dkp_input"].ravel().tolist(),
                  "corrector": y_next.tolist()}))
"""


@needs_cc
@pytest.mark.slow
def test_two_processes_compiling_into_one_empty_cache_both_succeed(tmp_path):
    cache = tmp_path / "empty-cache"
    env = dict(os.environ, SYMKIN_CACHE=str(cache), PYTHONPATH=str(ROOT))
    procs = [subprocess.Popen([sys.executable, "-W", "error::UserWarning", "-c", _WORKER], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = []
    for p in procs:
        out, err = p.communicate(timeout=600)
        assert p.returncode == 0, err
        outs.append(json.loads(out.strip().splitlines()[-1]))
    a, b = outs
    assert a["compiled"] and b["compiled"] and a["corrector_compiled"] and b["corrector_compiled"]
    assert a["library"] == b["library"]
    assert a["im"] == b["im"] and a["dkp"] == b["dkp"] and a["corrector"] == b["corrector"]
    # one library per artefact, no temporary left behind, the manifest is whole JSON
    libs = sorted(p.name for p in cache.rglob("*.so"))
    assert len(libs) == 2 and any(n.startswith("corrector_") for n in libs)
    assert not [p for p in cache.rglob(".*") if p.name not in (".", "..")]
    manifests = list(cache.glob("*.json"))
    assert len(manifests) == 1 and json.loads(manifests[0].read_text())["mechanism"]


def test_artefact_key_changes_with_compiler_flags_sources_and_content(tmp_path):
    src = tmp_path / "gen.py"
    src.write_text("a = 1\n")
    base = codegen.artefact_key(["model", "drive"], "cc", ("-O3",), sources=(src,))
    assert base == codegen.artefact_key(["model", "drive"], "cc", ("-O3",), sources=(src,))
    assert base != codegen.artefact_key(["model", "drive"], "gcc", ("-O3",), sources=(src,))
    assert base != codegen.artefact_key(["model", "drive"], "cc", ("-O2",), sources=(src,))
    assert base != codegen.artefact_key(["other", "drive"], "cc", ("-O3",), sources=(src,))
    src.write_text("a = 2\n")
    assert base != codegen.artefact_key(["model", "drive"], "cc", ("-O3",), sources=(src,))


def test_corrector_key_has_the_source_fingerprint_compiler_and_flags():
    from symkin.paths import generated
    from symkin.paths.system import make_curve

    curve = make_curve(get("fourbar_appendix"))
    k = generated._key(curve, "cc", codegen.DEFAULT_FLAGS)
    assert k != generated._key(curve, "clang", codegen.DEFAULT_FLAGS)
    assert k != generated._key(curve, "cc", ("-O0",))


def test_write_atomic_replaces_whole_files(tmp_path):
    target = tmp_path / "m.json"
    codegen.write_atomic(target, "old")
    codegen.write_atomic(target, "new")
    assert target.read_text() == "new" and [p.name for p in tmp_path.iterdir()] == ["m.json"]


def test_a_failing_build_leaves_no_library_and_raises_a_compiler_error(tmp_path):
    def write_sources(tmp):
        c = tmp / "broken.c"
        c.write_text("this is not C\n")
        return c

    with pytest.raises(codegen.CompilerError):
        codegen.cached_library(tmp_path, "broken", write_sources, ["f"])
    assert not list(tmp_path.glob("*.so")) and not [p for p in tmp_path.iterdir() if p.is_dir()]
