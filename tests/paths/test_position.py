"""The position problem against closed-form four-bar and slider-crank positions."""
from __future__ import annotations

import math

import pytest

from symkin import Mechanism, NotConvergedError
from symkin.model import catalogue
from symkin.paths.position import solve_position


def circle_intersection(p, r1, q, r2, sign):
    d = math.dist(p, q)
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h = math.sqrt(r1 * r1 - a * a)
    ex, ey = (q[0] - p[0]) / d, (q[1] - p[1]) / d
    return (p[0] + a * ex - sign * h * ey, p[1] + a * ey + sign * h * ex)


@pytest.mark.parametrize("continuation", [True, False])
def test_fourbar_position_matches_circle_intersection(continuation):
    m = catalogue.get("fourbar_appendix")
    x = m.coordinates()
    a, b, c = (math.dist(x[p], x[q]) for p, q in (("A", "B"), ("B", "C"), ("D", "C")))
    th = math.atan2(x["B"][1], x["B"][0]) + math.radians(25.0)
    new = solve_position(m, {"rotation:crank": 25.0}, unit="deg", continuation=continuation)
    bpos = (a * math.cos(th), a * math.sin(th))
    assert new.coordinates()["B"] == pytest.approx(bpos, abs=1e-12)
    # same assembly mode as the model: the intersection on the model's side of the line B-D
    cpos = min((circle_intersection(bpos, b, x["D"], c, s) for s in (1, -1)), key=lambda p: math.dist(p, x["C"]))
    assert new.coordinates()["C"] == pytest.approx(cpos, abs=1e-12)


def test_slider_crank_position():
    m = catalogue.get("slider_crank")
    new = solve_position(m, {"rotation:crank": -0.5})
    x = m.coordinates()
    a, b = math.dist(x["A"], x["B"]), math.dist(x["B"], x["C"])
    th = math.atan2(x["B"][1], x["B"][0]) - 0.5
    xc = a * math.cos(th) + math.sqrt(b * b - (a * math.sin(th) - 0.25) ** 2)
    assert new.coordinates()["C"] == pytest.approx((xc, 0.25), abs=1e-12)


def test_unreachable_inputs_cannot_be_assembled():
    m = Mechanism.from_dict({"dim": 2, "fixed": ["A", "D"], "inputs": [{"rotation": "crank"}],
                             "nodes": {"A": [0, 0], "B": [2 * math.cos(1.2), 2 * math.sin(1.2)],
                                       "C": [2.9, 1.9], "D": [3, 0]},
                             "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})
    with pytest.raises(NotConvergedError, match="cannot be assembled") as info:
        solve_position(m, {"rotation:crank": 150.0}, unit="deg", continuation=False)
    assert info.value.data["residual"] > 0.01
    with pytest.raises(NotConvergedError, match="cannot reach"):
        solve_position(m, {"rotation:crank": 150.0}, unit="deg")
