"""Every example of the paper: its check script's claims all hold."""
from __future__ import annotations

import pytest

from symkin.reproduce import discover
from tests.conftest import EXAMPLES, shared_run_check

SCRIPTS = discover(EXAMPLES)
# in a parallel run, on the worker of the reproduce tests that read the same check results (conftest.py)
pytestmark = pytest.mark.xdist_group("paper-checks")


def test_there_are_examples():
    assert SCRIPTS, "papers_examples/ has no check_*.py scripts"


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_paper_claims_hold(script):
    result = shared_run_check(script)  # run once per session: the reproduce tests read the same results
    assert result.claims, f"{script.name} makes no claims"
    assert result.ok, result.summary()
