"""The events of ``symkin.trace`` over a full turn of every catalogue mechanism and papers example
stay those of ``data/event_baseline.json`` (written by ``data/make_event_baseline.py`` on the code
before the paths stage moved onto :mod:`symkin.curves`): same kinds and types, inputs to 1e-10.

The curves use the generated corrector in-process (``generated="vm"``: the same numbers as the
compiled C, see ``tests/numeric/test_artefact_cache.py``) so that the test session, whose
artefact cache is empty, compiles nothing.

LIM events (a link that stops while the input moves) were added after the baseline: events of
kind LIM are new and are left out of the comparison, and a baseline event may now also carry
the LIM test among its ``kinds``.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import symkin.paths.trace
from symkin.kinds import Kind

from .data.make_event_baseline import cases, events_of

BASELINE = json.loads((Path(__file__).parent / "data" / "event_baseline.json").read_text())
CASES = {source: mech for _, source, mech in cases()}


@pytest.fixture(autouse=True)
def _in_process_corrector(monkeypatch):
    make_curve = symkin.paths.trace.make_curve

    def in_process(*args, **kwargs):
        curve = make_curve(*args, **kwargs)
        curve.generated = "vm"
        return curve

    monkeypatch.setattr(symkin.paths.trace, "make_curve", in_process)


def _comparable(events: list[dict]) -> list[dict]:
    return [{**e, "kinds": [k for k in e["kinds"] if k != Kind.LIM]} for e in events if e["kind"] != Kind.LIM]


@pytest.mark.parametrize("source", sorted(BASELINE))
def test_events_match_the_baseline(source):
    expected = BASELINE[source]
    got = events_of(CASES[source])
    assert got["drive"] == expected["drive"]
    assert got.get("error") == expected.get("error")
    assert got.get("stop_reason") == expected.get("stop_reason")
    before, after = _comparable(expected.get("events", [])), _comparable(got.get("events", []))
    assert [(e["kind"], e["kinds"], e["types"], e["locked_links"]) for e in after] == \
        [(e["kind"], e["kinds"], e["types"], e["locked_links"]) for e in before]
    for a, b in zip(after, before):
        assert a["input"] == pytest.approx(b["input"], abs=1e-10)
