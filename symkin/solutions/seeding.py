"""Where :func:`symkin.singularities` seeds its traces without the square DKP-input system: sample rounds.

Input values midway between consecutive critical values, and in every gap wider than
:data:`MAX_SAMPLE_GAP` (module docstring of :mod:`symkin.solutions.circuits`, "Without the square
system"); :func:`sample_near_zero` is the one seed with the square system.
"""
from __future__ import annotations

import math

from symkin.solutions.frame_coordinates import wrap

__all__ = ["MAX_SAMPLE_GAP", "MAX_SEED_ROUNDS", "cluster", "midpoints", "sample_gap", "sample_near_zero", "uncovered"]

#: at most this many rounds of seeds placed between the traced critical values (no square DKP-input system)
MAX_SEED_ROUNDS = 8
#: without the square DKP-input system, no two consecutive samples of an angle input are farther apart than this
MAX_SAMPLE_GAP = math.radians(30.0)


def sample_gap(critical: list[float], kind: str) -> float:
    """Widest gap between samples without the square system: :data:`MAX_SAMPLE_GAP` for angles, 1/12 of the critical range for lengths.

    Parameters
    ----------
    critical : list of float
        Critical input values (sorted; radians for an angle, wrapped to (−π, π]).
    kind : {"angle", "length"}
        The input's kind.

    Returns
    -------
    float
        ``inf`` for a length input with fewer than two critical values.

    Examples
    --------
    >>> round(sample_gap([], "angle"), 6), sample_gap([0.0, 6.0], "length"), sample_gap([1.0], "length")
    (0.523599, 0.5, inf)
    """
    if kind == "angle":
        return MAX_SAMPLE_GAP
    return (max(critical) - min(critical)) / 12.0 if len(critical) >= 2 else math.inf


def sample_near_zero(critical: list[float], kind: str) -> float:
    """The middle of the interval between consecutive critical values that holds the model's input 0.

    Parameters
    ----------
    critical, kind
        As for :func:`sample_gap`.

    Returns
    -------
    float
        0 without critical values.

    Examples
    --------
    >>> sample_near_zero([], "angle"), sample_near_zero([-1.0, 3.0], "length")
    (0.0, 1.0)
    >>> round(sample_near_zero([1.0, 2.0], "angle"), 6)  # the interval (2, 1 + 2π) wraps round through 0
    -1.641593
    """
    if not critical:
        return 0.0
    if kind != "angle":
        inside = [0.5 * (a + b) for a, b in zip(critical, critical[1:]) if a < 0.0 < b]
        return inside[0] if inside else 0.0
    bounds = list(zip(critical, critical[1:])) + [(critical[-1], critical[0] + 2 * math.pi)]
    for a, b in bounds:
        if a < a + (0.0 - a) % (2 * math.pi) < b:
            return wrap(0.5 * (a + b), kind)
    return wrap(critical[0] + math.pi, kind)


def midpoints(critical: list[float], kind: str) -> list[float]:
    """Input values midway between consecutive critical values (the model's value 0 when there is none).

    ``critical`` and ``kind`` as for :func:`sample_gap`; for an angle the last interval wraps
    round (through ±π).

    >>> midpoints([-1.0, 1.0], "angle"), midpoints([], "length")
    ([0.0, 3.141592653589793], [0.0])
    """
    if not critical:
        return [0.0]
    if len(critical) == 1:
        return [wrap(critical[0] + math.pi, kind)] if kind == "angle" else [0.0]
    mids = [0.5 * (a + b) for a, b in zip(critical, critical[1:])]
    if kind == "angle":
        mids.append(wrap(0.5 * (critical[-1] + critical[0] + 2 * math.pi), kind))
    return mids


def cluster(values: list[float], radius: float) -> list[float]:
    """Sorted values with runs of neighbours closer than ``radius`` replaced by their mean.

    Parameters
    ----------
    values : list of float
    radius : float
        Neighbours at most this far apart are one value.

    Returns
    -------
    list of float

    Examples
    --------
    >>> cluster([0.0, 1.0, 1.0625, 3.0], 0.1)
    [0.0, 1.03125, 3.0]
    """
    groups: list[list[float]] = []
    for v in sorted(values):
        if groups and v - groups[-1][-1] <= radius:
            groups[-1].append(v)
        else:
            groups.append([v])
    return [sum(g) / len(g) for g in groups]


def uncovered(critical: list[float], samples: list[float], kind: str, gap: float = math.inf) -> list[float]:
    """Input values still to sample: the middle of every interval between consecutive critical values
    that holds no sample yet, and of every gap between consecutive critical values and samples
    wider than ``gap``.

    Angles are taken mod 2π (the last interval wraps round); the first sample is 0 (the model's
    input).  A length input's circuits are bounded, each has its least and greatest value among
    the critical ones: only the intervals between them count.

    Parameters
    ----------
    critical : list of float
        Traced critical input values, sorted (wrapped for an angle).
    samples : list of float
        The input values sampled so far.
    kind : {"angle", "length"}
    gap : float
        Widest gap left between consecutive samples and critical values (:func:`sample_gap`).

    Returns
    -------
    list of float
        The next input values to sample (wrapped), none when every interval is covered.

    Examples
    --------
    >>> uncovered([], [], "angle"), uncovered([], [0.0], "angle"), uncovered([], [0.0], "angle", gap=4.0)
    ([0.0], [], [3.141592653589793])
    >>> [round(v, 6) for v in uncovered([-1.0, 1.0], [0.0], "angle")]
    [3.141593]
    >>> [round(v, 6) for v in uncovered([-1.0, 1.0], [0.0, 3.0], "angle", gap=2.0)]
    [-2.141593]
    """
    if not samples:
        return [0.0]
    if kind != "angle":
        bounds = list(zip(critical, critical[1:]))
    elif critical:
        bounds = list(zip(critical, critical[1:])) + [(critical[-1], critical[0] + 2 * math.pi)]
    else:
        first = sorted(samples)[0]
        bounds = [(first, first + 2 * math.pi)]  # one interval, from a sample round to itself
    out = []
    for a, b in bounds:
        inside = sorted(a + (s_ - a) % (2 * math.pi) if kind == "angle" else s_ for s_ in samples)
        inside = [v for v in inside if a < v < b]
        if critical and not inside:
            out.append(0.5 * (a + b))
            continue
        points = [a] + inside + [b]
        out += [0.5 * (p + q) for p, q in zip(points, points[1:]) if q - p > gap]
    return [wrap(v, kind) for v in out]
