"""Shared fixtures: the catalogue of named mechanisms and the repository paths."""
from __future__ import annotations

from pathlib import Path

import pytest

import symkin
import symkin.reproduce as _reproduce
from symkin.model import catalogue

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "papers_examples"

_RUN_CHECK = _reproduce.run_check
_CHECKS: dict = {}


def shared_run_check(script):
    """:func:`symkin.reproduce.run_check`, run once per test session for each script of ``papers_examples/``.

    ``test_papers_examples`` and the tests of ``symkin reproduce`` (in process) read the same
    check results instead of running every example of the paper three times; a script of any
    other folder runs each time, and a script that raises is not remembered (it raises again).
    """
    path = Path(script).resolve()
    if path.parent != EXAMPLES.resolve():
        return _RUN_CHECK(script)
    if path not in _CHECKS:
        _CHECKS[path] = _RUN_CHECK(script)
    return _CHECKS[path]


@pytest.fixture
def paper_checks_once(monkeypatch):
    """``symkin reproduce`` in this test uses :func:`shared_run_check` (the report is written as always)."""
    monkeypatch.setattr(_reproduce, "run_check", shared_run_check)


@pytest.fixture(params=catalogue.names())
def catalogue_name(request) -> str:
    return request.param


@pytest.fixture
def fourbar() -> symkin.Mechanism:
    return catalogue.get("fourbar_appendix")


@pytest.fixture
def fourbar_data() -> dict:
    return catalogue.data("fourbar_appendix")


#: the planar Gough–Stewart of tests/workspace/models at s1 = 0.05: 4 real and 24 complex assembly modes
GOUGH_STEWART = ROOT / "tests" / "workspace" / "models" / "gough_stewart.toml"
GOUGH_STEWART_VALUES = {**{f"slide:s{i}": 0.0 for i in range(1, 7)}, "slide:s1": 0.05}


@pytest.fixture(scope="session")
def gough_stewart_total_degree():
    """``(mechanism, values, results)``: the planar Gough–Stewart solved by total degree, once per session.

    Bertini's total-degree paths start from a random γ and now and then one fails, so up to three
    solves are made, stopping at the first that counts all 24 complex solutions; ``results`` holds
    them in order.  ``test_solve_all`` checks every one of them, ``test_parameter_homotopy``
    compares the last with PHCpack (the solve, 40 s, was made once in each).
    """
    from symkin.model.model_file import read_model
    from symkin.solutions import solve_all

    m = read_model(GOUGH_STEWART)
    results = []
    for _ in range(3):
        results.append(solve_all(m, dict(GOUGH_STEWART_VALUES), method="total-degree"))
        if results[-1].complex == 24:
            break
    return m, dict(GOUGH_STEWART_VALUES), results


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Compiled artefacts of the test session go to a temporary cache, not the user's.

    Run in parallel (pytest-xdist), the workers share one: the session's temporary folder
    (the parent of each worker's) holds it, and symkin's cache writes are atomic and serialised
    by a lock file (:mod:`symkin.numeric.codegen`), so a model compiled by one worker is loaded by
    the other.
    """
    import os

    old = os.environ.get("SYMKIN_CACHE")
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = tmp_path_factory.getbasetemp().parent / "symkin-cache"
        shared.mkdir(exist_ok=True)
        os.environ["SYMKIN_CACHE"] = str(shared)
    else:
        os.environ["SYMKIN_CACHE"] = str(tmp_path_factory.mktemp("symkin-cache"))
    yield
    if old is None:
        os.environ.pop("SYMKIN_CACHE", None)
    else:
        os.environ["SYMKIN_CACHE"] = old


# ---------------------------------------------------------------- parallel runs (pytest-xdist)
#: fixtures (or function fixtures over a cache of this module) whose one computation several test
#: modules read: their tests run on one worker, in one group named after the fixture
SHARED_ACROSS_MODULES = {"gough_stewart_total_degree": "gough-stewart-total-degree",
                         "paper_checks_once": "paper-checks"}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Group the tests that share an expensive computation, for ``--dist loadgroup`` (README, "Tests").

    pytest-xdist computes a module- or session-scoped fixture once in each worker that runs a
    test using it; so that it is computed once, the tests of a module that uses a module- or
    class-scoped fixture form one group (the module's), and the tests that read a fixture of
    :data:`SHARED_ACROSS_MODULES` form that fixture's group.  A test marked
    ``xdist_group`` already keeps its mark.  (Runs before xdist's own hook, which puts the group
    in the test's id; without xdist, the marks do nothing.)
    """
    for item in items:
        if item.get_closest_marker("xdist_group") is not None:
            continue
        info = getattr(item, "_fixtureinfo", None)
        if info is None:
            continue
        group = None
        for name in info.names_closure:
            if name in SHARED_ACROSS_MODULES:
                group = SHARED_ACROSS_MODULES[name]
                break
            defs = info.name2fixturedefs.get(name) or ()
            if defs and defs[-1].scope in ("module", "class", "package") and group is None:
                group = item.nodeid.split("::", 1)[0]
        if group is not None:
            item.add_marker(pytest.mark.xdist_group(group))
