"""Every example of the paper: its check script's claims all hold."""
from __future__ import annotations

import pytest

from symkin.reproduce import discover, run_check
from tests.conftest import EXAMPLES

SCRIPTS = discover(EXAMPLES)


def test_there_are_examples():
    assert SCRIPTS, "papers_examples/ has no check_*.py scripts"


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_paper_claims_hold(script):
    result = run_check(script)
    assert result.claims, f"{script.name} makes no claims"
    assert result.ok, result.summary()
