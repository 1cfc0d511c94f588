"""A trace says why it stopped: the stepper's budget of steps is its own reason (issue 20 §3).

``path --steps 30000`` used to stop at the hidden ``Settings.max_steps`` with the false reason
"arclength limit 60 reached"; the budget now ends the trace with ``"max_steps"``.
"""
from __future__ import annotations

import functools
import json

import pytest

from symkin.cli import main
from symkin.curves.stepper import Settings
from symkin.model.catalogue import get
from symkin.paths.trace import trace


def test_step_budget_is_its_own_reason():
    p = trace(get("fourbar_appendix"), stop=360, unit="deg", settings=Settings(max_steps=7))
    assert p.stop_reason == "max_steps"
    assert "7 accepted steps" in p.message and "max_steps" in p.message
    assert "arclength" not in p.message
    assert len(p.points) == 8  # the start and seven steps


@pytest.mark.parametrize("kwargs, reason", [
    ({}, "reached"),
    ({"max_arclength": 0.5}, "max_arclength"),
])
def test_other_reasons_unchanged(kwargs, reason):
    p = trace(get("fourbar_appendix"), stop=360, unit="deg", **kwargs)
    assert p.stop_reason == reason


@pytest.fixture
def small_budget(monkeypatch):
    """The command's continuation settings with a budget of 20 steps (``--steps`` up to 10)."""
    import symkin.curves.stepper as stepper

    monkeypatch.setattr(stepper, "Settings", functools.partial(Settings, max_steps=20))


def test_path_cli_says_the_budget_ran_out(small_budget, capsys):
    args = ["path", "catalogue:fourbar_appendix", "--input", "rotation:crank", "--to", "360", "--no-progress"]
    assert main([*args, "--steps", "10"]) == 0
    out = capsys.readouterr().out
    assert "step budget ran out: 20 accepted steps" in out and "--steps" in out
    assert "arclength limit" not in out
    assert main([*args, "--steps", "10", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["stop_reason"] == "max_steps" and "20" in data["message"]
    assert main([*args, "--steps", "11"]) == 2  # over the cap: refused before tracing
    capsys.readouterr()


def test_path_cli_few_steps_reach(capsys):
    assert main(["path", "catalogue:fourbar_appendix", "--input", "rotation:crank", "--to", "360", "--steps", "1",
                 "--no-progress", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["stop_reason"] == "reached"
