"""Shared fixtures: the catalogue of named mechanisms and the repository paths."""
from __future__ import annotations

from pathlib import Path

import pytest

import symkin
from symkin.model import catalogue

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "papers_examples"


@pytest.fixture(params=catalogue.names())
def catalogue_name(request) -> str:
    return request.param


@pytest.fixture
def fourbar() -> symkin.Mechanism:
    return catalogue.get("fourbar_appendix")


@pytest.fixture
def fourbar_data() -> dict:
    return catalogue.data("fourbar_appendix")


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Compiled artefacts of the test session go to a temporary cache, not the user's."""
    import os

    old = os.environ.get("SYMKIN_CACHE")
    os.environ["SYMKIN_CACHE"] = str(tmp_path_factory.mktemp("symkin-cache"))
    yield
    if old is None:
        os.environ.pop("SYMKIN_CACHE", None)
    else:
        os.environ["SYMKIN_CACHE"] = old
