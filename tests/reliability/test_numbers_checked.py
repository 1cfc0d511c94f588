"""Every number a user types is checked: exit 2 with a message, never a traceback (issue 20 §3)."""
from __future__ import annotations

from pathlib import Path

import pytest

from symkin.cli import main
from symkin.model.catalogue import get
from symkin.model.model_file import write_model

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = str(ROOT / "papers_examples" / "fourbar_appendix.toml")
Y = "--y=velocity:P.y=0.2:4.4"


@pytest.fixture(scope="module")
def fivebar(tmp_path_factory):
    return str(write_model(get("five_bar"), tmp_path_factory.mktemp("m") / "fivebar.toml"))


def _refused(argv, capsys, *words):
    try:
        code = main(argv)
    except SystemExit as stop:  # argparse refuses an option's value: usage, message, exit 2
        code = stop.code
    out, err = capsys.readouterr()
    assert code == 2, (argv, code, err[-2000:])
    assert "Traceback" not in err and not out, err
    for w in words:
        assert w in err, (w, err)
    return err


@pytest.mark.parametrize("x, words", [
    ("velocity:P.x=-1e308:1e308", ("width overflows",)),
    ("velocity:P.x=-1e200:1e200", ("far larger than the mechanism",)),
    ("velocity:P.x=-1e6:1e6", ("far larger than the mechanism", "at most")),
    ("velocity:P.x=nan:1", ("finite",)),
    ("velocity:P.x=-inf:1", ("finite",)),
    ("rotation:crank1=0:1e308", ("two turns",)),
])
def test_map_windows(fivebar, capsys, x, words):
    err = _refused(["map", fivebar, f"--x={x}", Y, "--n", "5", "--no-refine"], capsys, *words)
    assert err.startswith(fivebar + ": ")


def test_map_grid_that_does_not_fit_in_memory(fivebar, capsys):
    _refused(["map", fivebar, "--x=velocity:P.x=-3.5:3.5", Y, "--n", "100000"], capsys, "--n 100000", "GiB",
             "memory available")


def test_map_hold_nan(fivebar, capsys):
    _refused(["map", fivebar, "--x=velocity:P.x=-3.5:3.5", Y, "--n", "5", "--hold=rotation:crank1=nan"],
             capsys, "finite")


def test_map_a_reasonable_box_still_runs(fivebar, capsys):
    assert main(["map", fivebar, "--x=velocity:P.x=-100:100", "--y=velocity:P.y=-100:100", "--n", "5",
                 "--no-refine", "--no-progress"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize("opts, words", [
    (["--to", "nan"], ("--to", "finite")),
    (["--from", "nan", "--to", "10"], ("--from", "finite")),
    (["--from", "inf", "--to", "10"], ("--from", "finite")),
    (["--from=1e308", "--to=-1e308"], ("overflows",)),
    (["--to", "90", "--max-arclength", "-1"], ("--max-arclength", "greater than 0")),
    (["--to", "90", "--max-arclength", "0"], ("--max-arclength",)),
    (["--to", "90", "--max-arclength", "nan"], ("--max-arclength",)),
    (["--to", "360", "--steps", "30000"], ("--steps 30000", "20000")),
    (["--to", "360", "--steps", "0"], ("--steps must be a positive integer",)),
])
def test_path_numbers(capsys, opts, words):
    _refused(["path", FOURBAR, "--input", "rotation:crank", *opts], capsys, *words)


@pytest.mark.parametrize("value", ["-1", "nan", "inf"])
def test_conditions_time_limit(capsys, value):
    _refused(["conditions", FOURBAR, "--time-limit", value], capsys, "--time-limit")


def test_conditions_hold_nan(capsys, tmp_path):
    _refused(["conditions", FOURBAR, "--in", "velocity:B.x,velocity:B.y", "--hold", "rotation:crank=nan"], capsys,
             "finite")


@pytest.mark.parametrize("opts, words", [
    (["--out", "/proc/x"], ("--out /proc/x", "cannot")),
    (["--out", "{tmp}", "--flags", "'-O2"], ("--flags", "cannot split")),
    (["--out", "{tmp}", "--name", "a/b"], ("--name", "not a path")),
])
def test_codegen_options(capsys, tmp_path, opts, words):
    opts = [o.replace("{tmp}", str(tmp_path)) for o in opts]
    _refused(["codegen", FOURBAR, "--no-compile", *opts], capsys, *words)


@pytest.mark.parametrize("name, stem", [("_x", "x"), ("x__y", "x_y"), ("élan", "lan"), ("∆", "m"),
                                        ("4-bar", "m_4_bar")])
def test_codegen_names_become_c_identifiers(capsys, tmp_path, name, stem):
    assert main(["codegen", FOURBAR, "--no-compile", "--out", str(tmp_path), "--name", name]) == 0
    capsys.readouterr()
    assert (tmp_path / f"{stem}.c").exists() and (tmp_path / f"{stem}.json").exists()
