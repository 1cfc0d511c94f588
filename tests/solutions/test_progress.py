"""Progress and estimates of the global solves (issue 17 §3): fake clocks and callbacks, no timed test."""
from __future__ import annotations

import io

import pytest

from symkin.errors import SymkinError
from symkin.solutions.homotopy import estimate_seconds
from symkin.solutions.progress import Progress, as_progress, format_seconds


class FakeClock:
    def __init__(self, step: float = 0.0):
        self.now, self.step = 0.0, step

    def __call__(self) -> float:
        value = self.now
        self.now += self.step
        return value


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_summary_line_every_30_seconds_of_the_clock():
    clock, out = FakeClock(), io.StringIO()
    p = Progress("modes", bar=False, stream=out, clock=clock, timer=False)
    p.stage("parameter homotopy", total=40, unit="path")
    p.advance(10)
    clock.now = 29.0
    assert not p.tick() and out.getvalue() == ""
    clock.now = 31.0
    assert p.tick()
    assert out.getvalue() == "symkin modes: parameter homotopy 10/40 paths, 31 s elapsed\n"
    p.advance(30)
    clock.now = 45.0
    assert not p.tick()  # 14 s after the last line
    clock.now = 125.0
    assert p.tick() and out.getvalue().splitlines()[-1] == \
        "symkin modes: parameter homotopy 40/40 paths, 2 min 05 s elapsed"
    p.stage("monodromy", unit="loop")
    p.advance(3)
    p.describe("monodromy loop 3: 12 solutions")
    clock.now = 200.0
    assert p.tick() and out.getvalue().splitlines()[-1] == \
        "symkin modes: monodromy loop 3: 12 solutions (3 loops), 3 min 20 s elapsed"
    p.note("an estimate")  # printed at once
    assert out.getvalue().splitlines()[-1] == "symkin modes: an estimate"
    p.close()


def test_the_timer_thread_prints_without_any_call(monkeypatch):
    import threading

    out = io.StringIO()
    p = Progress("singularities", bar=False, stream=out, every=0.0)
    p.stage("a long homotopy", total=64, unit="path")
    done = threading.Event()
    for _ in range(200):  # the thread wakes every 0.05 s at every = 0; wait for it, not for a time
        if "a long homotopy 0/64 paths" in out.getvalue():
            done.set()
            break
        done.wait(0.05)
    p.close()
    assert done.is_set()


def test_a_bar_over_the_paths_on_a_terminal():
    term = Terminal()
    p = Progress("modes", stream=term, clock=FakeClock())
    assert p.tqdm is not None
    p.stage("parameter homotopy", total=40, unit="path")
    p.advance(40)
    p.bar.refresh()
    assert "40/40" in term.getvalue() and "parameter homotopy" in term.getvalue()
    p.close()


def test_a_callable_is_told_the_stages():
    seen = []
    p = as_progress(seen.append)
    p.stage("parameter homotopy", total=6, unit="path")
    p.advance(6)
    p.describe("monodromy loop 2: 6 solutions")
    p.note("estimate")
    assert seen == ["parameter homotopy: 6 paths", "monodromy loop 2: 6 solutions", "estimate"]
    with pytest.raises(TypeError):
        as_progress(3)


def test_format_seconds():
    assert [format_seconds(s) for s in (2.25, 42, 185, 7800)] == ["2.2 s", "42 s", "3 min 05 s", "2 h 10 min"]


def test_the_estimate_is_the_measured_time_per_path_of_the_first_paths():
    import sympy as sp

    x, y = sp.symbols("x y")
    eqs = [x**2 + y**2 - 4, x * y - 1]
    clock = FakeClock(step=6.0)  # the first reading 0, the second 6: 6 s for the measured paths
    per_path, measured = estimate_seconds(eqs, [x, y], paths=3, clock=clock)
    assert measured == 3 and per_path == pytest.approx(2.0)


def test_solve_all_refuses_a_large_homotopy_with_its_estimate():
    pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global]")
    from tests.solutions.test_solve_all import rpr_model
    from symkin.solutions import solve_all

    m, values = rpr_model()
    seen = []
    with pytest.raises(SymkinError, match=r"would track \d+ paths, more than max_paths = 2: about .* "
                                          r"\(estimated from its first 4 paths, .* s each\)"):
        solve_all(m, values, max_paths=2, method="total-degree", progress=seen.append)
    assert seen and seen[0].startswith("estimating the time of")


def test_solve_all_tells_the_paths_and_the_monodromy_loops(tmp_path, monkeypatch):
    pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global]")
    from tests.solutions.test_solve_all import rpr_model
    from symkin.solutions import solve_all

    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    m, values = rpr_model()
    out = io.StringIO()
    p = Progress("modes", bar=False, stream=out, clock=FakeClock(), timer=False)
    solve_all(m, values, method="parameter", progress=p)  # the first solve ends with its total-degree check
    assert p.description == "total-degree check of the first solve"
    result = solve_all(m, values, method="parameter", progress=p)  # from the cached start solutions
    assert p.description == "parameter homotopy" and (p.done, p.total) == (6, 6) == (result.paths, result.paths)
    seen = []
    solve_all(m, values, method="total-degree", progress=seen.append)
    assert seen == [f"total-degree homotopy: {solve_all(m, values, method='total-degree').paths} paths"]
    seen.clear()
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path / "again"))
    solve_all(m, values, method="parameter", progress=seen.append)
    assert any(s.startswith("monodromy loop") for s in seen) and "parameter homotopy: 6 paths" in seen
