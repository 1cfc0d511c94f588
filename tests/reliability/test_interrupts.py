"""An interrupt never becomes a result (issue 20 §2, issue 18 §1).

SIGINT at random moments of ``symkin reproduce --out`` and ``symkin map --npz --json``:
the exit code is 130 (or 0 when the run had finished), stderr says so in one line, the
outputs that existed before are either untouched or replaced by complete new ones, and
no report records a failed claim.
"""
from __future__ import annotations

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import symkin
from symkin import errors
from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.model.model_file import write_model
from symkin.reproduce import Checklist, _run_guarded, write_report

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "papers_examples"
FAST_CHECKS = ("fourbar_appendix", "fig14_15_2rr", "fig1a_3rrr")
OLD = "an output written before this run\n"
RUNS = 12  # per command: 24 interrupted runs in all


#: the console script's work (import, then ``main()``), saying on stderr when the import is done:
#: before that, Python's own handler answers a Ctrl-C (symkin's code is not running yet)
_PROGRAM = ("import sys\nimport symkin.cli\nsys.stderr.write('symkin-ready\\n')\nsys.stderr.flush()\n"
            "sys.exit(symkin.cli.main())\n")


def _env(cache):
    return dict(os.environ, PYTHONPATH=str(ROOT), SYMKIN_CACHE=str(cache))


def _command(*args) -> list[str]:
    return [sys.executable, "-c", _PROGRAM, *args]


def _interrupt(cmd, env, delay: float) -> subprocess.CompletedProcess:
    """Start ``cmd``, wait until symkin is imported, then ``delay`` seconds, then send SIGINT."""
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    before = []
    for line in proc.stderr:
        if line.strip() == "symkin-ready":
            break
        before.append(line)
    time.sleep(delay)
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=300)
    return subprocess.CompletedProcess(cmd, proc.returncode, out, "".join(before) + err)


def _window(cmd, env) -> tuple[float, float]:
    """Delays after the import at which to interrupt: up to the length of an uninterrupted run."""
    subprocess.run(cmd, env=env, capture_output=True, check=True, timeout=300)  # fills the cache
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import symkin.cli"], env=env, check=True)
    imported = time.perf_counter() - start
    start = time.perf_counter()
    subprocess.run(cmd, env=env, capture_output=True, check=True, timeout=300)
    full = time.perf_counter() - start
    return 0.0, max(full - imported, 0.2)


def _assert_interrupted_cleanly(done: subprocess.CompletedProcess) -> None:
    assert done.returncode in (0, 130), (done.returncode, done.stderr[-3000:])
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
    if done.returncode == 130:
        assert [ln for ln in done.stderr.splitlines() if "interrupt" in ln.lower()] == ["symkin: interrupted"]


@pytest.fixture(scope="module")
def examples(tmp_path_factory):
    folder = tmp_path_factory.mktemp("examples")
    for f in list(EXAMPLES.glob("*.toml")) + [EXAMPLES / "planar_rrr_geometry.py"]:
        shutil.copy(f, folder)
    for name in FAST_CHECKS:
        shutil.copy(EXAMPLES / f"check_{name}.py", folder)
    return folder


@pytest.mark.slow
def test_sigint_during_reproduce_never_writes_a_failed_claim_or_a_partial_report(examples, tmp_path):
    env = _env(tmp_path / "cache")
    rng = random.Random(20)
    finished = 0

    def command(out):
        return _command("reproduce", "--examples", str(examples), "--out", str(out))

    lo, hi = _window(command(tmp_path / "warm"), env)
    shutil.rmtree(tmp_path / "warm")
    for k in range(RUNS):
        out = tmp_path / f"report{k}"
        out.mkdir()
        for name in ("summary.md", "summary.json", "fourbar_appendix__generic.json"):
            (out / name).write_text(OLD)
        done = _interrupt(command(out), env, rng.uniform(lo, hi))
        _assert_interrupted_cleanly(done)
        finished += done.returncode == 0
        md = (out / "summary.md").read_text()
        if done.returncode == 130 and md == OLD:  # interrupted before the report: every file as it was
            assert all((out / n).read_text() == OLD for n in ("summary.json", "fourbar_appendix__generic.json"))
        else:  # a whole new report
            assert md.startswith("# symkin reproduce") and md.endswith("\n")
            assert json.loads((out / "summary.json").read_text())
        for f in out.iterdir():
            text = f.read_text()
            assert "FAIL" not in text and "✘" not in text and '"holds": false' not in text, f
        assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")]  # no staging folder left
    assert finished < RUNS  # the test did interrupt


@pytest.mark.slow
def test_sigint_during_map_leaves_the_outputs_whole(tmp_path):
    env = _env(tmp_path / "cache")
    model = write_model(get("five_bar"), tmp_path / "fivebar.toml")
    rng = random.Random(21)
    interrupted = 0

    def command(npz, js):
        return _command("map", str(model), "--x=velocity:P.x=-3.5:3.5", "--y=velocity:P.y=0.2:4.4", "--n", "41",
                        "--no-progress", "--npz", str(npz), "--json", str(js))

    lo, hi = _window(command(tmp_path / "warm.npz", tmp_path / "warm.json"), env)
    for k in range(RUNS):
        npz, js = tmp_path / f"m{k}.npz", tmp_path / f"m{k}.json"
        npz.write_text(OLD)
        js.write_text(OLD)
        done = _interrupt(command(npz, js), env, rng.uniform(lo, hi))
        _assert_interrupted_cleanly(done)
        interrupted += done.returncode == 130
        for f, check in ((npz, symkin.load_map), (js, lambda p: json.loads(Path(p).read_text())["axes"])):
            if f.read_text(errors="replace") != OLD:
                check(f)  # complete, or it would not load
            elif done.returncode == 0:
                raise AssertionError(f"{f} not written by a finished run")
    assert interrupted
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("."))  == []


def _wrapped_interrupt():
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as ki:  # what CasADi's DM.__array__ does when the interrupt is pending
        raise SystemError("<function DM.__array__> returned a result with an exception set") from ki


def test_an_interrupt_wrapped_by_casadi_is_not_a_failed_claim(tmp_path):
    script = tmp_path / "check_wrapped.py"
    script.write_text("from symkin.errors import SymkinError\n"
                      "def check():\n"
                      "    try:\n"
                      "        raise KeyboardInterrupt\n"
                      "    except KeyboardInterrupt:\n"
                      "        raise SystemError('<function DM.__array__> returned a result with an exception set')\n")
    with pytest.raises(KeyboardInterrupt):
        _run_guarded(script)
    script.write_text("def check():\n    raise ValueError('a real failure')\n")
    failed = _run_guarded(script)
    assert not failed.ok and "ValueError: a real failure" in failed.claims[0].measured


def test_caused_by_interrupt_follows_cause_and_context():
    with pytest.raises(SystemError) as info:
        _wrapped_interrupt()
    assert errors.caused_by_interrupt(info.value)
    assert not errors.caused_by_interrupt(RuntimeError("no"))


def test_a_swallowed_interrupt_still_exits_130(monkeypatch, capsys):
    from symkin import cli

    def run(args):
        errors.note_interrupt()  # what the SIGINT handler records; the command then swallows the exception
        from symkin.commands import Output
        return Output("a result that must not be printed")

    parser = cli.build_parser()
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    parser.set_defaults(_run=run)
    sub = parser._subparsers._group_actions[0].choices["cache"]
    sub.set_defaults(_run=run)
    monkeypatch.setattr(errors, "clear_interrupt", lambda: None)
    try:
        assert cli.main(["cache"]) == 130
    finally:
        errors._INTERRUPT.update(seen=False, deferred=0, pending=False)
    out, err = capsys.readouterr()
    assert "must not be printed" not in out and err.strip() == "symkin: interrupted"


def test_an_error_wrapping_an_interrupt_exits_130(monkeypatch, capsys):
    from symkin import cli

    parser = cli.build_parser()
    parser._subparsers._group_actions[0].choices["cache"].set_defaults(_run=lambda args: _wrapped_interrupt())
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    assert cli.main(["cache"]) == 130
    assert capsys.readouterr().err.strip() == "symkin: interrupted"


def test_write_report_is_all_or_nothing(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.md").write_text(OLD)
    c = Checklist("demo")
    c.equal("one", 1, 1)
    errors.note_interrupt()
    try:
        with pytest.raises(KeyboardInterrupt):
            write_report([c], out)
    finally:
        errors.clear_interrupt()
    assert (out / "summary.md").read_text() == OLD and sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    write_report([c], out)
    assert "demo: all claims hold" in (out / "summary.md").read_text()


@pytest.mark.parametrize("stage", ["made", "cleaned"])
def test_an_interrupt_while_the_staging_folder_is_made_or_removed_leaves_none(tmp_path, monkeypatch, stage):
    """A SIGINT that lands inside ``mkdtemp`` (the folder made, its name not yet returned) or inside
    the clean-up: the staging folder is removed all the same (CI once found a ``.report3.*`` left)."""
    import tempfile

    out = tmp_path / "out"
    c = Checklist("demo")
    c.equal("one", 1, 1)
    real_mkdtemp, real_rmtree = tempfile.mkdtemp, shutil.rmtree

    def mkdtemp(*args, **kwargs):
        path = real_mkdtemp(*args, **kwargs)
        if stage == "made":
            assert not errors.note_interrupt()  # deferred: raised once the name is held
        return path

    def rmtree(path, *args, **kwargs):
        if stage == "cleaned":
            assert not errors.note_interrupt()  # deferred: the clean-up runs to its end
        return real_rmtree(path, *args, **kwargs)

    monkeypatch.setattr(tempfile, "mkdtemp", mkdtemp)
    monkeypatch.setattr(shutil, "rmtree", rmtree)
    try:
        with pytest.raises(KeyboardInterrupt):
            write_report([c], out)
    finally:
        errors.clear_interrupt()
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04" + b"\0" * 100, b"not a map at all"])
def test_load_map_on_a_damaged_or_foreign_file_names_it(tmp_path, content):
    f = tmp_path / "bad.npz"
    f.write_bytes(content)
    with pytest.raises(SymkinError, match="bad.npz"):
        symkin.load_map(f)


def test_load_map_on_a_truncated_map_or_an_npz_of_other_arrays_names_it(tmp_path):
    import numpy as np

    m = symkin.workspace_map(get("five_bar"), x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=5,
                             refine=False)
    good = m.save(tmp_path / "good.npz")
    data = good.read_bytes()
    (tmp_path / "half.npz").write_bytes(data[: len(data) // 2])
    np.savez(tmp_path / "foreign.npz", header=np.array(json.dumps({"axes": 1})))
    np.savez(tmp_path / "other.npz", a=np.zeros(3))
    for name in ("half.npz", "foreign.npz", "other.npz"):
        with pytest.raises(SymkinError, match=name):
            symkin.load_map(tmp_path / name)
    assert symkin.load_map(good).axes == m.axes
