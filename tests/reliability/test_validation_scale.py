"""Validation and parameter bookkeeping stay O(n log n); duplicates are reported once (issue 20 §4).

No timing thresholds: each case is timed at 1,000 and at 100,000 entries (or 20,000 for
the heavy ones) and the ratio must stay far below what quadratic work gives (10,000× for
100× more entries); an alarm stops a run that is quadratic instead of waiting for it.
"""
from __future__ import annotations

import signal
import time

import pytest

from symkin.errors import ModelError
from symkin.model.labels import accepted_labels
from symkin.model.mechanism import Mechanism, length_scale
from tests.reliability import model_cases as cases


class _TooSlow(Exception):
    pass


def _load(d) -> str:
    """Validate and do the bookkeeping a command does first; 'ok' or the error message."""
    try:
        m = Mechanism.from_dict(d)
        m.content_hash()
        accepted_labels(m)
        m.free_nodes, m.moving_links
        return "ok"
    except ModelError as exc:
        return str(exc)


def _seconds(build, n: int, budget: float) -> tuple[float, str]:
    d = build(n)

    def stop(*_):
        raise _TooSlow(f"{build.__name__}({n}) still running after {budget:.0f} s")

    old = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, budget)
    try:
        best = float("inf")
        for _ in range(3 if n <= 1000 else 1):
            start = time.perf_counter()
            result = _load(d)
            best = min(best, time.perf_counter() - start)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    return best, result


def _assert_near_linear(build, big: int) -> tuple[str, str]:
    small_t, small = _seconds(build, 1000, 60)
    factor = big / 1000
    # linear: factor; n log n: ~1.7 factor; quadratic: factor**2.  Allow 15 factor (+ 2 s of noise)
    limit = 15 * factor * max(small_t, 1e-3) + 2.0
    big_t, large = _seconds(build, big, limit)
    assert big_t < limit, (build.__name__, small_t, big_t)
    return small, large


@pytest.mark.parametrize("build", [cases.fixed_repeated, cases.identical_sliders, cases.dup_inputs,
                                   cases.dup_outputs])
def test_duplicates_are_reported_once_with_their_count_in_near_linear_time(build):
    small, large = _assert_near_linear(build, 100_000)
    assert len(large.splitlines()) <= 3, large[:500]
    assert "1000" in small or "500 times" in small, small
    assert "100000" in large or "50000 times" in large, large


@pytest.mark.slow
@pytest.mark.parametrize("build", [cases.big_link, cases.all_fixed, cases.inputs, cases.outputs,
                                   cases.many_velocity_outputs])
def test_large_models_validate_in_near_linear_time(build):
    _assert_near_linear(build, 20_000)


def test_messages_of_duplicates():
    assert "node 'A' listed 50000 times" in _load(cases.fixed_repeated(100_000))
    d = cases.fixed_repeated(2)
    d["fixed"] = ["A", "D", "A"]
    assert "node 'A' listed twice" in _load(d)
    d = cases.big_link(3)
    d["links"]["body"] = ["C", "N0", "N1", "N0", "N0", "N1"]
    assert "node(s) N0 (3 times), N1 repeated" in _load(d)
    assert "every node is fixed (30 nodes): nothing can move" in _load(cases.all_fixed(30))
    msg = _load(cases.dup_inputs(4))
    assert msg == "inputs[0]: listed 4 times (also inputs[1], [2], [3])"
    assert "duplicate slider id 'piston': 3 sliders have it" in _load(cases.identical_sliders(3))


def test_coincident_nodes_of_a_big_body_are_found_once():
    d = cases.big_link(2000)
    d["nodes"]["N7"] = list(d["nodes"]["N3"])
    d["nodes"]["N1500"] = list(d["nodes"]["N3"])
    msg = _load(d)
    assert "coincident nodes in a rigid body: nodes N3, N7, N1500 are at the same point" in msg, msg
    d = cases.fixed_repeated(2)
    d["nodes"]["B"] = list(d["nodes"]["A"])
    assert "zero-length bar: nodes A and B are at the same point" in _load(d)


def test_length_scale_of_a_huge_body_is_deterministic_and_close_to_the_exact_mean():
    import math

    k = 1100  # 604,450 pairs: above the exact limit
    coords = {f"N{i}": (math.cos(i), math.sin(3 * i)) for i in range(k)}
    names = list(coords)
    exact = sum(math.dist(coords[a], coords[b]) for i, a in enumerate(names) for b in names[i + 1:])
    exact /= k * (k - 1) / 2
    first = length_scale(coords, [names])
    assert first == length_scale(coords, [names])
    assert abs(first - exact) < 5e-3 * exact
