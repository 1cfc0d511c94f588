"""Every output path is checked before the work; a write that fails after it loses nothing (issue 18 §1).

``--plot x.jpgg`` or ``--csv``/``--json``/``--npz`` into a missing folder ended with exit 3 and
a traceback after the whole computation.  Now: exit 2 with ``--option PATH: why`` before any
work (the computation is replaced by one that fails the test), and a write that still fails
after the work goes to the current folder under a printed name, exit 1.
"""
from __future__ import annotations

import shutil

import pytest

from symkin.cli import main
from symkin.commands.outputs import check_figure_file, save_output

PATH = ["path", "catalogue:fourbar_appendix", "--input", "rotation:crank", "--to", "360", "--no-progress"]
MAP = ["map", "catalogue:five_bar", "--x=velocity:P.x=-3.5:3.5", "--y=velocity:P.y=0.2:4.4", "--n", "5",
       "--no-refine", "--no-progress"]
SING = ["singularities", "catalogue:fourbar_appendix", "--no-progress"]


def _no_work(*args, **kwargs):
    raise AssertionError("the computation ran before its outputs were checked")


@pytest.fixture
def no_work(monkeypatch):
    import symkin.paths.trace
    import symkin.solutions.circuits
    import symkin.workspace.maps

    monkeypatch.setattr(symkin.paths.trace, "trace", _no_work)
    monkeypatch.setattr(symkin.workspace.maps, "workspace_map", _no_work)
    monkeypatch.setattr(symkin.solutions.circuits, "singularities", _no_work)


@pytest.mark.parametrize("command, option, name, words", [
    (PATH, "--plot", "x.jpgg", ("unknown figure format '.jpgg'", ".png")),
    (MAP, "--plot", "x.jpgg", ("unknown figure format",)),
    (SING, "--plot", "x.jpgg", ("unknown figure format",)),
    (PATH, "--csv", "missing/x.csv", ("does not exist",)),
    (MAP, "--json", "missing/x.json", ("does not exist",)),
    (MAP, "--npz", "missing/x.npz", ("does not exist",)),
    (PATH, "--csv", ".", ("is a folder",)),
    (PATH, "--plot", "missing/x.png", ("does not exist",)),
])
def test_bad_output_refused_before_the_work(no_work, tmp_path, monkeypatch, capsys, command, option, name, words):
    monkeypatch.chdir(tmp_path)
    assert main([*command, option, name]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{option} {name}: ") and "Traceback" not in err
    for w in words:
        assert w in err
    assert [p.name for p in tmp_path.iterdir()] == []


def test_out_folders_refused_before_the_work(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert main(["reproduce", "--out", str(tmp_path / "file" / "sub")]) == 2
    assert capsys.readouterr().err.startswith(f"--out {tmp_path / 'file' / 'sub'}: ")
    assert main(["codegen", "catalogue:fourbar_appendix", "--no-compile", "--out", str(tmp_path / "file")]) == 2
    assert "--out" in capsys.readouterr().err


def test_without_matplotlib_the_extra_is_named(monkeypatch, capsys):
    import sys

    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(Exception, match="plots extra"):
        check_figure_file("x.png")


def test_a_write_failing_after_the_work_goes_to_the_current_folder(tmp_path, monkeypatch, capsys):
    """The folder of --csv and --plot goes away while the path is traced: exit 1, both files kept."""
    import symkin.paths.trace

    out = tmp_path / "out"
    out.mkdir()
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    real = symkin.paths.trace.trace

    def trace_then_remove(*args, **kwargs):
        result = real(*args, **kwargs)
        shutil.rmtree(out)
        return result

    monkeypatch.setattr(symkin.paths.trace, "trace", trace_then_remove)
    code = main([*PATH, "--csv", str(out / "p.csv"), "--plot", str(out / "p.png")])
    err = capsys.readouterr().err
    assert code == 1, err
    assert "Traceback" not in err
    assert f"--csv {out / 'p.csv'}: could not be written" in err and "symkin-p.csv" in err
    assert (here / "symkin-p.csv").read_text().startswith("input,")
    assert (here / "symkin-p.png").read_bytes()[:4] == b"\x89PNG"


def test_save_output_keeps_an_existing_fallback(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "symkin-r.json").write_text("old")
    saved = save_output(tmp_path / "gone" / "r.json", lambda tmp: tmp.write_text("new"), "--json")
    assert saved.path.name == "symkin-1-r.json" and saved.path.read_text() == "new"
    assert (tmp_path / "symkin-r.json").read_text() == "old" and "--json" in saved.problem
