"""One analysis core: analyze, batch evaluation and trace agree along paths (issue 7 §4).

For three catalogue mechanisms a path is traced; at every path point the indicators that
trace recorded, ``ev.batch`` (generated kernel and exact SVD path) at the same
configuration and ``analyze(ev.mechanism_at(q))`` give the same IM indicator and signed
DKP values (1e-10 relative) and the same IM / DKP decisions (exactly).  At the located
events the decisions agree too, and the event's kind is among them.
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from symkin.model.catalogue import get
from symkin.paths.trace import trace

DECIDED = ("IM", "DKP-input", "DKP-output")
RTOL = 1e-10

PATHS = {
    "fourbar_appendix": dict(stop=360, unit="deg"),  # two dead centres of the rocker (DKP-output)
    "rrr_3": dict(stop=40, unit="deg"),               # crank 1 of the 3-RRR: DKP-input and -output
    "slider_crank": dict(stop=360, unit="deg"),       # the piston's two dead centres
}


def _core_types(a) -> tuple[str, ...]:
    return tuple(t for t in a.types if t in DECIDED)


def _close(value, reference) -> bool:
    return abs(value - reference) <= RTOL * abs(reference)


@pytest.fixture(scope="module", params=sorted(PATHS))
def traced(request):
    name = request.param
    path = trace(get(name), **PATHS[name])
    ev = path.curve.evaluators
    q = np.array([p.coordinates.ravel()[ev.free] for p in path.points])
    return name, path, ev, q


def test_trace_batch_and_analyze_agree_at_every_path_point(traced):
    name, path, ev, q = traced
    kernel, exact = ev.batch(q), ev.batch(q, exact=True)
    assert np.count_nonzero(kernel.path == 0) > len(path.points) // 2  # the generated kernel is compared
    keys = (("im_indicator", "im_indicator", "im_indicator"), ("DKP-input", "dkp_input", "dkp_input"),
            ("DKP-output", "dkp_output", "dkp_output"))
    compared = 0
    for k, point in enumerate(path.points):
        a = symkin.analyze(ev.mechanism_at(q[k]))
        assert kernel.types(k) == exact.types(k) == _core_types(a), (name, k)
        assert a.dof == kernel.dof[k] == exact.dof[k] == a.mobility
        for recorded, field, attr in keys:
            reference = getattr(a, attr)
            assert reference is not None and np.isfinite(reference)
            assert _close(point.indicators[recorded], reference), (name, k, recorded)
            assert _close(getattr(kernel, field)[k], reference), (name, k, field, "kernel")
            assert _close(getattr(exact, field)[k], reference), (name, k, field, "exact")
            compared += 1
    assert compared == 3 * len(path.points)


def test_decisions_agree_at_the_located_events(traced):
    name, path, ev, _ = traced
    events = path.singular_events()
    assert events and all(e.kind in ("DKP-input", "DKP-output") for e in events)
    q = np.array([e.coordinates.ravel()[ev.free] for e in events])
    res = ev.batch(q)
    for k, e in enumerate(events):
        a = symkin.analyze(ev.mechanism_at(q[k]))
        assert res.types(k) == _core_types(a) == _core_types(e.analysis), (name, k)
        assert e.kind in a.types and e.confirmed
        # the located root: the signed value of the one definition vanishes there
        value = a.dkp_input if e.kind == "DKP-input" else a.dkp_output
        assert abs(value) < 1e-9 and abs(e.value - value) < 1e-10


def test_signs_change_at_the_events_and_nowhere_else(traced):
    """The recorded signed DKP values change sign exactly where trace located an event of that kind."""
    name, path, _, _ = traced
    for kind in ("DKP-input", "DKP-output"):
        v = np.array([p.indicators[kind] for p in path.points[:-1]])
        changes = int(np.count_nonzero(np.sign(v[1:]) != np.sign(v[:-1])))
        assert changes == sum(e.kind == kind for e in path.singular_events()), (name, kind)
