"""Fixtures of the paths tests."""
from __future__ import annotations

import pytest

import symkin.paths.trace


@pytest.fixture
def in_process_corrector(monkeypatch):
    """Curves use the generated corrector in-process (``generated="vm"``): nothing is compiled.

    The same numbers as the compiled C (``tests/numeric/test_artefact_cache.py``); the test
    session's artefact cache is empty.
    """
    make_curve = symkin.paths.trace.make_curve

    def in_process(*args, **kwargs):
        curve = make_curve(*args, **kwargs)
        curve.generated = "vm"
        return curve

    monkeypatch.setattr(symkin.paths.trace, "make_curve", in_process)
