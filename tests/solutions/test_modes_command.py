"""``symkin modes``: JSON contract, user errors (exit 2), and a clear error without the optional solver."""
from __future__ import annotations

import json
import math
import re
import sys

import numpy as np
import pytest

from symkin import SymkinError
from symkin.cli import main
from symkin.model import catalogue
from tests.conftest import EXAMPLES

FOURBAR = str(EXAMPLES / "fourbar_appendix.toml")


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_without_the_solver_the_error_names_the_extra(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "bertini", None)  # import bertini raises ImportError
    import symkin

    with pytest.raises(SymkinError, match=r'pip install -e "\.\[global\]"'):
        symkin.solve_all(catalogue.get("fourbar_appendix"), {"rotation:crank": 30}, unit="deg",
                         method="total-degree")
    code, out, err = run(capsys, "modes", FOURBAR, "--at", "rotation:crank=30", "--method", "total-degree")
    assert code == 2 and out == "" and "symkin[global]" in err and "Traceback" not in err
    # every other command still works
    assert run(capsys, "analyze", FOURBAR)[0] == 0


@pytest.mark.parametrize("args, expected", [
    (["--at", "rotation:crnk=30"], "unknown input 'rotation:crnk'"),
    ([], "F = 1 but 0 value(s) given"),
    (["--at", "rotation:crank=30", "--at", "rotation:rocker=5"], "too many values"),
    (["--at", "rotation:crank"], "expected LABEL=VALUE"),
    (["--at", "rotation:crank=abc"], "'abc' is not a number"),
    (["--at", "rotation:crank=1", "--at", "rotation:crank=2"], "given twice"),
])
def test_user_errors_exit_2_with_file_and_message(capsys, args, expected):
    # the values are checked before the solver is needed: these run without the extra too
    code, out, err = run(capsys, "modes", FOURBAR, *args)
    assert code == 2 and out == ""
    assert expected in err and "Traceback" not in err
    if "LABEL=VALUE" not in expected and "not a number" not in expected and "twice" not in expected:
        assert err.startswith(FOURBAR)


def test_json_contract_and_text(capsys):
    pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global]")
    code, out, err = run(capsys, "modes", FOURBAR, "--at", "rotation:crank=30", "--json", "--method", "total-degree")
    assert code == 0
    data = json.loads(out)
    assert set(data) >= {"solutions", "complex", "paths"}
    assert data["paths"] == 2 and data["complex"] == 0 and len(data["solutions"]) == 2
    m = catalogue.get("fourbar_appendix")
    x = m.coordinates()
    th = math.atan2(x["B"][1], x["B"][0]) + math.radians(30)
    l1 = math.dist(x["A"], x["B"])
    # Newton stops at a closure residual of 1e-12 (length scales): coordinates agree to about that, times
    # the conditioning; Bertini's random start changes their last bits between runs (1.4e-12 seen)
    close = 1e-11 * m.length_scale
    for s in data["solutions"]:
        assert set(s) >= {"configuration", "signs", "residual"}
        assert s["residual"] <= 1e-10
        assert s["configuration"]["B"] == pytest.approx([l1 * math.cos(th), l1 * math.sin(th)], abs=close)
        assert math.dist(s["configuration"]["B"], s["configuration"]["C"]) == pytest.approx(
            math.dist(x["B"], x["C"]), abs=close)
        assert set(s["signs"]) == {"dkp_input", "dkp_output"}
    # radians give the same configurations
    code, out_rad, _ = run(capsys, "modes", FOURBAR, "--at", f"rotation:crank={math.radians(30)!r}",
                           "--unit", "rad", "--json")
    got = sorted(np.concatenate([s["configuration"]["C"] for s in json.loads(out_rad)["solutions"]]))
    assert got == pytest.approx(sorted(np.concatenate([s["configuration"]["C"] for s in data["solutions"]])),
                                abs=close)
    code, text, _ = run(capsys, "modes", FOURBAR, "--at", "rotation:crank=30", "--analyze",
                         "--method", "total-degree")
    assert code == 0 and "2 real solution(s)" in text and "2 paths (total-degree) tracked" in text and "analysis: L = 1" in text


def test_no_progress_prints_summary_lines_on_stderr(capsys, monkeypatch, tmp_path):
    pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global]")
    import importlib

    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    monkeypatch.setattr(importlib.import_module("symkin.solutions.progress"), "SUMMARY_EVERY", 0.0)
    code, out, err = run(capsys, "modes", FOURBAR, "--at", "rotation:crank=30", "--no-progress", "--method", "parameter")
    assert code == 0 and "2 real solution(s)" in out
    # the timer thread prints the current stage (every 0.05 s here): the monodromy loops take longer than that
    assert re.search(r"symkin modes: (monodromy|parameter homotopy|total-degree).*, [0-9.]+ s elapsed", err)
