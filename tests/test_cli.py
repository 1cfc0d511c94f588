"""The command line: reports, JSON contract, and user errors as `file: message` with exit code 2."""
from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import pytest

from symkin.cli import main
from tests.conftest import EXAMPLES, ROOT

JSON_KEYS = {"dof", "mobility", "singular", "types", "input_rank", "output_rank", "platform_dof",
             "locked_links", "input_relations", "output_relations", "uncontrolled_motions",
             "im_indicator", "singular_values", "tolerance"}


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_analyze_text_report(capsys):
    code, out, err = run(capsys, "analyze", str(EXAMPLES / "fourbar_appendix.toml"))
    assert code == 0 and err == ""
    assert "The configuration is not singular." in out
    assert "L = 1, equal to the full-cycle mobility F = 1" in out


def test_analyze_json_contract(capsys, tmp_path):
    from symkin import write_model
    from symkin.model import catalogue

    path = write_model(catalogue.get("fourbar_dead_centre"), tmp_path / "dc.json")
    code, out, _ = run(capsys, "analyze", str(path), "--json", "--tol", "1e-7")
    data = json.loads(out)
    assert code == 0 and JSON_KEYS <= set(data)
    assert data["types"] == ["DKP-output", "LIM"] and data["singular"] is True
    assert data["output_relations"] == [{"rotation:rocker": 1.0}] and data["tolerance"] == 1e-7
    assert data["platform_dof"] is None and data["locked_links"] == ["rocker"]


@pytest.mark.parametrize("content, suffix, expected", [
    ('name = "x"\ndim = 2\nnodes = {A = [0, 0]\n', ".toml", "malformed TOML"),
    ('{"dim": 5, "nodes": {"A": [0, 0]}, "links": {"l": ["A", "B"]}}', ".json", "dim: must be 2"),
    ('{"dim": 2, "nodes": {"A": [0, 0]}, "links": {"l": ["A", "B"]}}', ".json", "links.l: unknown node 'B'"),
])
def test_user_errors_exit_2_with_file_and_message(capsys, tmp_path, content, suffix, expected):
    p = tmp_path / f"bad{suffix}"
    p.write_text(content)
    code, out, err = run(capsys, "analyze", str(p))
    assert code == 2 and out == ""
    assert err.startswith(f"{p}: ") and expected in err and "Traceback" not in err


def test_missing_file_and_bad_option(capsys, tmp_path):
    code, _, err = run(capsys, "analyze", str(tmp_path / "none.toml"))
    assert code == 2 and "no such file" in err
    with pytest.raises(SystemExit) as info:
        main(["analyze", str(EXAMPLES / "fourbar_appendix.toml"), "--tol", "2"])
    assert info.value.code == 2
    assert "must be between 0 and 1" in capsys.readouterr().err


def test_console_script_runs_as_module():
    proc = subprocess.run([sys.executable, "-m", "symkin", "analyze", str(EXAMPLES / "fourbar_appendix.toml"),
                           "--json"], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0 and json.loads(proc.stdout)["dof"] == 1


@pytest.mark.slow
def test_reproduce_writes_a_report_folder(capsys, tmp_path, paper_checks_once):
    code, out, err = run(capsys, "reproduce", "--out", str(tmp_path / "rep"))
    assert code == 0, out + err
    assert "examples reproduced" in out and (tmp_path / "rep" / "summary.md").exists()
    summary = json.loads((tmp_path / "rep" / "summary.json").read_text())
    assert summary and all(item["ok"] for item in summary)


def test_reproduce_without_examples_is_a_user_error(capsys, tmp_path):
    code, _, err = run(capsys, "reproduce", "--examples", str(tmp_path))
    assert code == 2 and "no papers_examples folder" in err


def test_path_text_json_and_csv(capsys, tmp_path):
    model = str(EXAMPLES / "fourbar_appendix.toml")
    code, out, err = run(capsys, "path", model, "--to", "360", "--no-progress")
    assert code == 0 and "DKP-output at rotation:crank = 137.56215" in out
    code, out, _ = run(capsys, "path", model, "--input", "rotation:crank", "--from", "0", "--to", "360",
                       "--unit", "deg", "--json")
    data = json.loads(out)
    assert code == 0 and {"points", "events"} <= set(data)
    events = [e for e in data["events"] if e["kind"] != "end"]
    assert [e["types"] for e in events] == [["DKP-output", "LIM"], ["DKP-output", "LIM"]]
    for e in events:
        assert {"input", "absolute", "kind", "types", "locked_links", "dof", "configuration"} <= set(e)
        assert e["locked_links"] == ["rocker"] and e["dof"] == 1
    assert data["points"][0]["input"] == 0.0 and data["points"][-1]["input"] == pytest.approx(360.0)
    target = tmp_path / "p.csv"
    code, _, err = run(capsys, "path", model, "--to", "90", "--steps", "30", "--csv", str(target))
    rows = target.read_text().splitlines()
    assert code == 0 and rows[0].startswith("input,absolute,s,") and len(rows) >= 31


@pytest.mark.parametrize("args, expected", [
    (["--to", "10", "--input", "rotation:nope"], "unknown input 'rotation:nope'"),
    (["--to", "0"], "--from and --to are equal"),
    (["--to", "10", "--steps", "0"], "--steps must be a positive integer"),
])
def test_path_user_errors(capsys, args, expected):
    model = str(EXAMPLES / "fourbar_appendix.toml")
    code, out, err = run(capsys, "path", model, *args)
    assert code == 2 and err.startswith(f"{model}: ") and expected in err and "Traceback" not in err


def test_path_plot_writes_a_png(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    target = tmp_path / "fig.png"
    code, out, err = run(capsys, "path", str(EXAMPLES / "fourbar_appendix.toml"), "--to", "360",
                         "--plot", str(target), "--json")
    assert code == 0 and json.loads(out)["stop_reason"] == "reached"
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "figure written" in err


def test_path_driven_past_a_rocker_limit_says_it_cannot_reach_the_value(capsys):
    from symkin.model import catalogue
    from tests.paths.test_trace import rocker_limits

    model = str(EXAMPLES / "fourbar_appendix.toml")
    folded = math.degrees(rocker_limits(catalogue.get("fourbar_appendix"))["folded"])
    code, out, err = run(capsys, "path", model, "--input", "rotation:rocker", "--to", "180", "--no-progress")
    assert code == 0 and "the input cannot reach 180°: it turns back at" in out
    assert f"(absolute {folded:.7f}°)" in out and "(a full loop)" not in out
    code, out, _ = run(capsys, "path", model, "--input", "rotation:rocker", "--to", "180", "--json")
    data = json.loads(out)
    assert data["stop_reason"] == "unreachable" and data["turning"]["absolute"] == pytest.approx(folded, abs=1e-7)


def test_path_bad_input_lists_every_accepted_label(capsys):
    model = str(EXAMPLES / "fourbar_appendix.toml")
    code, out, err = run(capsys, "path", model, "--to", "10", "--input", "rotation:rocker2")
    assert code == 2 and out == "" and "Traceback" not in err
    assert err.startswith(f"{model}: unknown input 'rotation:rocker2'; a path can be driven by ")
    for part in ("the model's inputs (rotation:crank)", "its outputs (rotation:rocker)",
                 "rotation:<link> for a moving link (crank, coupler, rocker)",
                 "velocity:<node>.<x|y> for a free node (B, C)"):
        assert part in err
    # what the message lists is accepted
    for label in ("rotation:rocker", "rotation:coupler", "velocity:C.y"):
        assert run(capsys, "path", model, "--to", "1", "--input", label, "--no-progress")[0] == 0


def test_path_errors_keep_their_class_and_data(capsys, monkeypatch):
    import symkin.paths.trace
    from symkin.cli import build_parser
    from symkin.errors import ModelError, NotConvergedError, Problem

    model = str(EXAMPLES / "fourbar_appendix.toml")
    args = build_parser().parse_args(["path", model, "--to", "10", "--no-progress"])
    problems = (Problem("links.crank", "has no moving node"), Problem("nodes.B", "is not in a link"))

    def bad_model(*a, **k):
        raise ModelError(problems)
    monkeypatch.setattr(symkin.paths.trace, "trace", bad_model)
    with pytest.raises(ModelError) as info:
        args._run(args)
    assert info.value.problems == problems and info.value.source == model
    code, _, err = run(capsys, "path", model, "--to", "10")
    assert code == 2 and err.splitlines() == [f"{model}: links.crank: has no moving node",
                                              f"{model}: nodes.B: is not in a link"]

    def not_converged(*a, **k):
        raise NotConvergedError("Newton reached a residual of 0.25", residual=0.25, y=[1.0, 2.0])
    monkeypatch.setattr(symkin.paths.trace, "trace", not_converged)
    with pytest.raises(NotConvergedError) as info:
        args._run(args)
    assert info.value.data == {"residual": 0.25, "y": [1.0, 2.0]}
    assert str(info.value) == f"{model}: Newton reached a residual of 0.25"
    code, _, err = run(capsys, "path", model, "--to", "10")
    assert code == 2 and err.strip() == f"{model}: Newton reached a residual of 0.25" and "Traceback" not in err


def test_catalogue_names_are_models(capsys):
    """``catalogue:NAME`` is taken wherever a model file is; an unknown name is exit 2, listing the names."""
    code, out, err = run(capsys, "analyze", "catalogue:fourbar_dead_centre", "--json")
    assert code == 0 and json.loads(out)["types"] == ["DKP-output", "LIM"]
    code, out, err = run(capsys, "analyze", "catalogue:fivebar")
    assert code == 2 and out == ""
    assert err.startswith("catalogue:fivebar: no mechanism 'fivebar' in the catalogue; known: ") and "five_bar" in err


def test_shipped_examples_are_the_catalogue_and_test_models():
    """``examples/`` holds the README's models: the catalogue five-bar and the tests' map models."""
    from symkin import read_model
    from symkin.model import catalogue

    assert read_model(ROOT / "examples" / "fivebar.toml").to_dict() == catalogue.get("five_bar").to_dict()
    for name in ("gough_stewart.toml", "rpr_3.toml"):
        assert (ROOT / "examples" / name).read_text() == (ROOT / "tests" / "workspace" / "models" / name).read_text()


def test_path_and_singularities_print_the_same_numbers_for_the_same_configuration(capsys):
    """One angle convention: relative to the model in (−180°, 180°], absolute in [0°, 360°), in every command."""
    pytest.importorskip("bertini")
    model = str(EXAMPLES / "fourbar_appendix.toml")
    crank = "rotation:crank = -53.91904574 deg (absolute 23.55214655 deg)"
    rocker = "rotation:rocker = -24.24725354 deg (absolute 61.3540411 deg)"
    code, path_text, _ = run(capsys, "path", model, "--to", "360", "--no-progress")
    assert code == 0 and f"at {crank}, 306.0809543 deg along the path" in path_text
    assert f"outputs: {rocker}" in path_text
    code, sing_text, _ = run(capsys, "singularities", model, "--no-progress")
    assert code == 0 and f"at {crank}, {rocker}" in sing_text
    # the JSON of both: the same numbers under the keys each had, and the absolute ones added
    code, out, _ = run(capsys, "path", model, "--to", "360", "--json", "--no-progress")
    event = json.loads(out)["events"][1]
    code, out, _ = run(capsys, "singularities", model, "--json", "--no-progress")
    (same,) = [s for s in json.loads(out)["singularities"] if abs(s["input"] - event["relative"]) < 1e-6]
    assert event["input"] == pytest.approx(306.0809543, abs=1e-6)
    assert same["input_absolute"] == pytest.approx(event["absolute"], abs=1e-9)
    assert same["output"] == pytest.approx(event["outputs"]["rotation:rocker"]["relative"], abs=1e-9)
    assert same["output_absolute"] == pytest.approx(event["outputs"]["rotation:rocker"]["absolute"], abs=1e-9)
    for s in json.loads(out)["singularities"]:
        assert -180 < s["input"] <= 180 and 0 <= s["input_absolute"] < 360 and 0 <= s["output_absolute"] < 360


def test_path_csv_and_modes_give_the_outputs(capsys, tmp_path):
    """``path --csv`` and ``modes`` give the outputs' values (relative and absolute), not only node coordinates."""
    model = str(EXAMPLES / "fourbar_appendix.toml")
    code, _, _ = run(capsys, "path", model, "--to", "360", "--csv", str(tmp_path / "p.csv"), "--no-progress")
    rows = list(csv.DictReader((tmp_path / "p.csv").open()))
    assert code == 0 and {"relative", "rotation:rocker", "rotation:rocker absolute"} <= set(rows[0])
    assert float(rows[0]["rotation:rocker"]) == 0.0
    assert float(rows[0]["rotation:rocker absolute"]) == pytest.approx(85.60129464500446, abs=1e-9)
    assert all(-180 < float(r["relative"]) <= 180 and 0 <= float(r["absolute"]) < 360 for r in rows)
    pytest.importorskip("bertini")
    code, out, _ = run(capsys, "modes", model, "--at", "rotation:crank=30")
    assert code == 0 and "at rotation:crank = 30 deg (absolute 107.4711923 deg)" in out
    assert "outputs: rotation:rocker = 20.92279412 deg (absolute 106.5240888 deg)" in out
    code, out, _ = run(capsys, "modes", model, "--at", "rotation:crank=30", "--json")
    sols = json.loads(out)["solutions"]
    assert sorted(round(s["outputs"]["rotation:rocker"]["relative"], 6) for s in sols) == [20.922794, 125.636035]


def test_map_says_what_rejected_points_and_branch_changes_mean(capsys, monkeypatch):
    """``symkin map`` explains its rejected points and branch changes: whether to trust the map, what to do."""
    import dataclasses

    import numpy as np

    import symkin
    from symkin.workspace import maps

    real = symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3.5:3.5",
                                y="velocity:P.y=0.2:4.4", n=11, refine=False)
    rejected = np.zeros_like(real.modes[0].rejected)
    rejected[3, 3] = True
    mode = dataclasses.replace(real.modes[0], rejected=rejected, branch_changes=(((1, 1), (1, 2)),))
    monkeypatch.setattr(maps, "workspace_map", lambda *a, **k: dataclasses.replace(real, modes=(mode,)))
    code, out, _ = run(capsys, "map", "catalogue:five_bar", "--x", "velocity:P.x=-3.5:3.5",
                       "--y", "velocity:P.y=0.2:4.4", "--n", "11", "--no-refine")
    assert code == 0
    assert "1 rejected point(s): " in out and "never a wrong value" in out and "give a larger --n" in out
    assert "1 branch change(s): " in out and "can be trusted" in out and "its own --seed" in out


@pytest.mark.parametrize("option", ["--version", "--help"])
def test_version_and_help_import_neither_scipy_nor_casadi(option):
    """``symkin --version`` / ``--help`` are fast: the command modules and ``import symkin`` load no heavy library."""
    code = ("import sys, symkin.cli\n"
            f"try:\n    symkin.cli.main([{option!r}])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in ('scipy', 'casadi', 'sympy', 'matplotlib') if m in sys.modules))")
    run_ = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert run_.returncode == 0, run_.stderr
    assert run_.stdout.strip().splitlines()[-1] == "[]"


def test_lazy_public_names_are_the_real_ones():
    import symkin
    from symkin.analysis.classification import analyze
    from symkin.analysis.batch import evaluators

    assert symkin.analyze is analyze and symkin.evaluators is evaluators
    assert set(symkin.__all__) <= set(dir(symkin))
    assert symkin.report.render_text is symkin.render_text
    with pytest.raises(AttributeError):
        symkin.no_such_name
