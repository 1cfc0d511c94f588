"""``symkin map``: text, --json, --npz, and user errors as a message with exit code 2."""
from __future__ import annotations

import json

import pytest

import symkin
from symkin.cli import main
from symkin.model.catalogue import get
from symkin.model.model_file import write_model

X, Y = "--x=velocity:P.x=-3.5:3.5", "--y=velocity:P.y=0.2:4.4"


def run(capsys, *args):
    code = main(["map", *map(str, args)])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    return write_model(get("five_bar"), tmp_path_factory.mktemp("m") / "fivebar.toml")


def test_text_report(capsys, model):
    code, out, err = run(capsys, model, X, Y, "--n", 21, "--no-refine")
    assert code == 0, err
    assert "mode 0 (seed model): assembled at 15.6% of the grid" in out  # closed form: 0.1565
    assert "Traceback" not in err


def test_json_to_stdout_and_npz(capsys, model, tmp_path):
    npz = tmp_path / "m.npz"
    code, out, err = run(capsys, model, X, Y, "--n", 21, "--no-refine", "--json", "-", "--npz", npz)
    assert code == 0
    d = json.loads(out)  # nothing but the JSON object on stdout (no progress bar)
    assert d["axes"][0] == {"label": "velocity:P.x", "lo": -3.5, "hi": 3.5, "n": 21}
    assert d["modes"][0]["seed"] == "model"
    assert str(npz) in err
    assert symkin.load_map(npz).to_dict() == d


def test_json_to_file(capsys, model, tmp_path):
    target = tmp_path / "m.json"
    code, out, err = run(capsys, model, X, Y, "--n", 5, "--no-refine", "--json", target)
    assert code == 0 and json.loads(target.read_text())["axes"][1]["n"] == 5


def test_nothing_assembles_is_a_result(capsys, model):
    code, out, err = run(capsys, model, "--x=velocity:P.x=10:12", "--y=velocity:P.y=10:12", "--n", 3,
                         "--no-refine")
    assert code == 0 and "Nothing assembles in this box" in out


@pytest.mark.parametrize("args, message", [
    (("--x=velocity:Q.x=0:1", Y), "unknown input 'velocity:Q.x'"),
    (("--x=velocity:P.x=1:0", Y), "LO must be less than HI"),
    ((X, Y, "--n", 1), "at least 2"),
    ((X, Y, "--hold", "rotation:crank1"), "over-determined"),
    ((X, Y, "--workers", 0), "number of workers must be at least 1"),
    ((X, "--y=velocity:P.x=0:1"), "named twice"),
])
def test_bad_input_exits_2(capsys, model, args, message):
    code, out, err = run(capsys, model, *args, "--no-refine")
    assert code == 2 and message in err and "Traceback" not in err


def test_modes_all_with_a_seed_exits_2(capsys, model):
    code, _, err = run(capsys, model, X, Y, "--n", 3, "--no-refine", "--modes", "all", "--seed", model)
    assert code == 2 and "no --seed" in err and "Traceback" not in err


def test_seed_errors_exit_2(capsys, model, tmp_path):
    other = write_model(get("fourbar_appendix"), tmp_path / "four.toml")
    code, _, err = run(capsys, model, X, Y, "--n", 3, "--no-refine", "--seed", other)
    assert code == 2 and "not the same mechanism" in err and str(other) in err
    rrr = write_model(get("rrr_3"), tmp_path / "rrr.toml")
    code, _, err = run(capsys, rrr, "--x=velocity:C1.x=-1:1", "--y=velocity:C1.y=-1:1", "--n", 3, "--no-refine",
                       "--hold", "rotation:platform=10", "--seed", rrr)
    assert code == 2 and "not on the held values" in err
    code, _, err = run(capsys, rrr, "--x=velocity:C1.x=-1:1", "--y=velocity:C1.y=-1:1", "--n", 3, "--no-refine")
    assert code == 2 and "--hold" in err and "1 held coordinate" in err


def test_plot_is_a_clear_error_or_a_file(capsys, model, tmp_path):
    import importlib.util

    target = tmp_path / "m.png"
    code, _, err = run(capsys, model, X, Y, "--n", 5, "--no-refine", "--plot", target)
    if importlib.util.find_spec("symkin.plots.maps") is None:
        assert code == 2 and ("not available yet" in err or "plots extra" in err)
    else:
        assert code == 0 and target.exists()
