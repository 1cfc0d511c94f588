"""Events are classified from the curve's own rows where those give ``analyze``'s answer.

:func:`symkin.paths.trace.classify_event` classifies a located event from the rows of the
curve's evaluators (:func:`~symkin.paths.trace.curve_rows`) when
:func:`~symkin.paths.trace.curve_rows_cover` says they are the core's, and falls back to
``analyze(mech.with_coordinates(x))`` otherwise.  Over the cases of
``test_event_baseline.py`` (a full turn, or a unit length, of every catalogue mechanism and
papers example with an input), every located event's analysis, and the classification from
the curve's rows, equal ``analyze`` at the event's configuration.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin.analysis.classification import analyze, classify
from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import input_coordinates
from symkin.paths.trace import classify_event, curve_rows, curve_rows_cover, trace

from .data.make_event_baseline import MAX_ARCLENGTH, cases

CASES = {source: mech for _, source, mech in cases()}
#: sources the curve rows cover (planar, no sliders, no degenerate bodies); the others fall back
FALLBACK = {"catalogue:slider_crank", "catalogue:rssr", "catalogue:bennett", "papers_examples/fig12_3rsr_b.toml"}
#: a spatial model whose trace takes more than a minute
SLOW = {"papers_examples/fig12_3rsr_b.toml"}
#: redundant mechanisms whose turn has no singular configuration: no event located (the baseline's
#: candidates there were sign changes of a row subset fixed at the start, test_event_baseline.py)
NO_EVENTS = {"catalogue:bennett", "catalogue:double_parallelogram"}
#: relations and self-stresses compared to this (absolute, on canonical coefficients)
RELATION_TOL = 1e-10


pytestmark = pytest.mark.usefixtures("in_process_corrector")


def _path(mech: Mechanism):
    drive = input_coordinates(mech)[0]
    stop = 2 * math.pi if drive.kind == "angle" else mech.length_scale
    return trace(mech, start=0.0, stop=stop, max_arclength=MAX_ARCLENGTH)


def _same_relations(got, expected) -> bool:
    if len(got) != len(expected):
        return False
    for g, e in zip(got, expected):
        gd, ed = g.as_dict(), e.as_dict()
        if list(gd) != list(ed) or any(abs(gd[k] - ed[k]) > RELATION_TOL for k in gd):
            return False
    return True


def _assert_same(got, expected) -> None:
    fields = ("dof", "mobility", "types", "input_labels", "output_labels", "input_rank", "output_rank",
              "locked_links", "locked_nodes", "platform_dof", "redundant_constraints", "warnings",
              "gosselin_angeles", "zlatanov")
    assert {f: getattr(got, f) for f in fields} == {f: getattr(expected, f) for f in fields}
    for rel in ("input_relations", "output_relations", "platform_relations", "self_stresses"):
        assert _same_relations(getattr(got, rel), getattr(expected, rel)), rel
    np.testing.assert_allclose(got.motion.xyz, expected.motion.xyz, rtol=0, atol=0)


@pytest.mark.parametrize("source", [pytest.param(s, marks=pytest.mark.slow) if s in SLOW else s
                                    for s in sorted(CASES)])
def test_event_classification_equals_analyze(source):
    mech = CASES[source]
    try:
        path = _path(mech)
    except SymkinError:
        pytest.skip("the start is a branch point: no path (test_event_baseline.py)")
    assert curve_rows_cover(path.curve) == (source not in FALLBACK)
    located = [e for e in path.events if e.analysis is not None]
    assert bool(located) == (source not in NO_EVENTS)
    for e in located:
        expected = analyze(mech.with_coordinates(e.coordinates), tol=None)
        _assert_same(e.analysis, expected)
        if source not in FALLBACK:
            _assert_same(classify(curve_rows(path.curve, e.y)), expected)


def test_covered_events_do_not_rebuild_the_model(monkeypatch):
    mech = get("watt_sixbar")
    path = _path(mech)
    located = [e for e in path.events if e.analysis is not None]
    assert curve_rows_cover(path.curve) and located

    def refuse(self, coords):
        raise AssertionError("an event rebuilt the model")

    monkeypatch.setattr(Mechanism, "with_coordinates", refuse)
    for e in located:
        got = classify_event(path.curve, e.y)
        assert got.types == e.analysis.types and got.dof == e.analysis.dof


def test_uncovered_events_fall_back_to_analyze(monkeypatch):
    mech = get("slider_crank")
    path = _path(mech)
    event = next(e for e in path.events if e.analysis is not None)
    assert not curve_rows_cover(path.curve)
    calls = []
    with_coordinates = Mechanism.with_coordinates

    def counting(self, coords):
        calls.append(1)
        return with_coordinates(self, coords)

    monkeypatch.setattr(Mechanism, "with_coordinates", counting)
    got = classify_event(path.curve, event.y)
    assert calls and got.types == event.analysis.types
