"""All solutions of the position problem against closed forms and elementary geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin import Mechanism, SymkinError
from symkin.model import catalogue
from symkin.solutions import position_system, solve_all

pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global] "
                                      "(pip install -e '.[global]')")


def circle_points(p, r1, q, r2):
    """Both intersections of the circles (p, r1) and (q, r2) (law of cosines)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = float(np.linalg.norm(q - p))
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h = math.sqrt(r1 * r1 - a * a)
    e = (q - p) / d
    n = np.array([-e[1], e[0]])
    return [p + a * e + h * n, p + a * e - h * n]


def assert_same_configurations(result, expected, nodes, scale=1.0):
    """Every expected configuration found once, and nothing else (to 1e-9 of the length scale)."""
    assert len(result.solutions) == len(expected)
    found = [np.concatenate([s.configuration[n] for n in nodes]) for s in result.solutions]
    for e in expected:
        dist = [float(np.max(np.abs(f - e))) for f in found]
        assert min(dist) <= 1e-9 * scale, (e, found)
    for s in result.solutions:
        assert s.residual <= 1e-10 and s.closure <= 1e-10


def cross(u, v):
    return float(u[0] * v[1] - u[1] * v[0])


def rotate(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


# ---------------------------------------------------------------- four-bar: 2 assembly modes
def test_fourbar_two_assembly_modes_law_of_cosines():
    m = catalogue.get("fourbar_appendix")
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    l1, l2, l3 = (float(np.linalg.norm(x[p] - x[q])) for p, q in (("A", "B"), ("B", "C"), ("D", "C")))
    th = math.atan2(x["B"][1], x["B"][0]) + math.radians(30.0)
    b = l1 * np.array([math.cos(th), math.sin(th)])
    expected = [np.concatenate([b, c]) for c in circle_points(b, l2, x["D"], l3)]
    result = solve_all(m, {"rotation:crank": 30}, unit="deg", method="total-degree")
    assert_same_configurations(result, expected, ["B", "C"])
    assert result.complex == 0 and result.near_real == 0
    assert result.paths == 2  # the crank angle fixes B linearly; one quadratic is left
    # the two modes are told apart by the DKP signs, as by the side of the line B-D that C is on
    side = [np.sign(cross(np.subtract(s.configuration["D"], s.configuration["B"]),
                          np.subtract(s.configuration["C"], s.configuration["B"]))) for s in result.solutions]
    assert side[0] != side[1]
    assert result.solutions[0].signs != result.solutions[1].signs
    d = result.to_dict()
    assert set(d) >= {"solutions", "complex", "paths"}
    assert set(d["solutions"][0]) >= {"configuration", "signs", "residual"}


def test_fourbar_that_does_not_assemble_has_two_complex_solutions():
    # non-Grashof four-bar: ground 2, crank 1.2, coupler 1, rocker 1; at 90° |BD| = 2.33 > 2
    b = 1.2 * np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
    c = circle_points(b, 1.0, (2.0, 0.0), 1.0)[0]
    m = Mechanism.from_dict({"name": "non-Grashof four-bar", "dim": 2, "fixed": ["A", "D"],
                             "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
                             "nodes": {"A": [0, 0], "B": list(b), "C": list(c), "D": [2, 0]},
                             "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})
    result = solve_all(m, {"rotation:crank": 60}, unit="deg", method="total-degree")
    assert len(result.solutions) == 0 and result.complex == 2 and result.paths == 2
    ok = solve_all(m, {"rotation:crank": 10}, unit="deg")
    b2 = 1.2 * np.array([math.cos(math.radians(40)), math.sin(math.radians(40))])
    assert_same_configurations(ok, [np.concatenate([b2, p]) for p in circle_points(b2, 1.0, (2, 0), 1.0)], ["B", "C"])


def test_opposite_half_line_is_filtered_not_returned():
    # a spatial crank-less check is not needed: the planar angle's half-line is part of the system.
    m = catalogue.get("slider_crank")
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    th = math.atan2(x["B"][1], x["B"][0]) + math.radians(20)
    b = 1.0 * np.array([math.cos(th), math.sin(th)])
    rod = float(np.linalg.norm(x["C"] - x["B"]))
    dy = 0.25 - b[1]
    cx = [b[0] + s * math.sqrt(rod * rod - dy * dy) for s in (1, -1)]
    result = solve_all(m, {"rotation:crank": 20}, unit="deg")
    assert_same_configurations(result, [np.concatenate([b, [c, 0.25]]) for c in cx], ["B", "C"])
    for s in result.solutions:  # the crank points along the prescribed half-line, not opposite
        assert np.dot(s.configuration["B"], [math.cos(th), math.sin(th)]) > 0


# ---------------------------------------------------------------- five-bar: 4 working modes
def five_bar_truth(m, p):
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    legs = []
    for k in (1, 2):
        lc = float(np.linalg.norm(x[f"B{k}"] - x[f"A{k}"]))
        ld = float(np.linalg.norm(x["P"] - x[f"B{k}"]))
        legs.append(circle_points(x[f"A{k}"], lc, p, ld))
    return [np.concatenate([b1, b2, p]) for b1 in legs[0] for b2 in legs[1]]


def test_five_bar_four_working_modes_at_a_point():
    m = catalogue.get("five_bar")
    p = np.array(m.coordinates()["P"]) + [0.1, -0.2]
    result = solve_all(m, {"velocity:P.x": 0.1, "velocity:P.y": -0.2})
    assert_same_configurations(result, five_bar_truth(m, p), ["B1", "B2", "P"])
    assert result.complex == 0 and result.paths == 4


def test_five_bar_same_count_in_millimetres_and_moved():
    m = catalogue.get("five_bar")
    rot = [[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]]
    mm = m.moved(rotation=rot, translation=[120.0, -40.0], scale=1000.0)
    dx = rotate([0.1, -0.2], 0.7) * 1000.0
    p = np.array(mm.coordinates()["P"]) + dx
    result = solve_all(mm, {"velocity:P.x": dx[0], "velocity:P.y": dx[1]})
    assert_same_configurations(result, five_bar_truth(mm, p), ["B1", "B2", "P"], scale=1000.0)
    assert result.paths == 4 and result.complex == 0
    metres = solve_all(m, {"velocity:P.x": 0.1, "velocity:P.y": -0.2})
    assert sorted(tuple(s.signs.items()) for s in result.solutions) == \
        sorted(tuple(s.signs.items()) for s in metres.solutions)


# ---------------------------------------------------------------- 3-RRR: 8 working modes
@pytest.mark.parametrize("scale", [1.0, 1000.0])
def test_3rrr_eight_working_modes_at_a_pose(scale):
    m = catalogue.get("rrr_3").moved(scale=scale)
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    shift, turn = np.array([0.05, -0.05]) * scale, math.radians(5.0)
    c1 = x["C1"] + shift
    cs = [c1] + [c1 + rotate(x[f"C{k}"] - x["C1"], turn) for k in (2, 3)]
    legs = []
    for k in (1, 2, 3):
        lc = float(np.linalg.norm(x[f"B{k}"] - x[f"A{k}"]))
        ld = float(np.linalg.norm(x[f"C{k}"] - x[f"B{k}"]))
        legs.append(circle_points(x[f"A{k}"], lc, cs[k - 1], ld))
    expected = [np.concatenate([b1, b2, b3, *cs]) for b1 in legs[0] for b2 in legs[1] for b3 in legs[2]]
    result = solve_all(m, {"velocity:C1.x": shift[0], "velocity:C1.y": shift[1], "rotation:platform": 5},
                       unit="deg", method="total-degree")
    assert_same_configurations(result, expected, ["B1", "B2", "B3", "C1", "C2", "C3"], scale=scale)
    assert result.paths == 8 and result.complex == 0
    assert len({tuple(s.signs.items()) for s in result.solutions}) >= 2


# ---------------------------------------------------------------- 3-RPR: 6 assembly modes
# Gosselin, Sefrioui & Richard (1994) design, as quoted in Merlet, "Parallel Robots" (2006), §4.2:
# A1 = (0, 0), A2 = (15.91, 0), A3 = (0, 10); platform sides B1B2 = 17.04, B1B3 = 20.84 at 0.882 rad;
# legs 14.98, 15.38, 12: six real assembly modes.
BASE = [(0.0, 0.0), (15.91, 0.0), (0.0, 10.0)]
L2, L3, THETA = 17.04, 20.84, 0.882
RHO = (14.98, 15.38, 12.0)


def rpr_model():
    """3-RPR: each leg a bar A_i-D_i with the platform node C_i sliding on the moving line A_i D_i."""
    c1 = np.array([3.0, 4.0])
    cs = [c1, c1 + L2 * np.array([math.cos(0.2), math.sin(0.2)]),
          c1 + L3 * np.array([math.cos(0.2 + THETA), math.sin(0.2 + THETA)])]
    nodes, links, sliders = {}, {}, []
    for i in range(3):
        a = np.array(BASE[i])
        nodes[f"A{i + 1}"], nodes[f"C{i + 1}"] = list(a), list(cs[i])
        nodes[f"D{i + 1}"] = list(a + (cs[i] - a) / np.linalg.norm(cs[i] - a))
        links[f"leg{i + 1}"] = [f"A{i + 1}", f"D{i + 1}"]
        sliders.append({"id": f"s{i + 1}", "node": f"C{i + 1}", "line": [f"A{i + 1}", f"D{i + 1}"],
                        "link": f"leg{i + 1}"})
    links["platform"] = ["C1", "C2", "C3"]
    m = Mechanism.from_dict({"name": "3-RPR (Gosselin, Sefrioui, Richard)", "dim": 2, "fixed": ["A1", "A2", "A3"],
                             "inputs": [{"slide": f"s{i}"} for i in (1, 2, 3)], "outputs": [{"twist": "platform"}],
                             "platform": "platform", "platform_dof": 3, "nodes": nodes, "links": links,
                             "sliders": sliders})
    values = {f"slide:s{i + 1}": RHO[i] - float(np.linalg.norm(cs[i] - np.array(BASE[i]))) for i in range(3)}
    return m, values


def rpr_truth():
    """Assembly modes by a sweep: C1 on its circle, C2 by circle intersection, C3 from the platform; roots of |A3C3|² − ρ3²."""
    from scipy.optimize import brentq

    a1, a2, a3 = (np.array(p) for p in BASE)

    def pose(t, sign):
        c1 = a1 + RHO[0] * np.array([math.cos(t), math.sin(t)])
        d = float(np.linalg.norm(a2 - c1))
        a = (L2 ** 2 - RHO[1] ** 2 + d * d) / (2 * d)
        if L2 ** 2 - a * a < 0:
            return None
        e = (a2 - c1) / d
        c2 = c1 + a * e + sign * math.sqrt(L2 ** 2 - a * a) * np.array([-e[1], e[0]])
        c3 = c1 + rotate(c2 - c1, THETA) * (L3 / L2)
        return c1, c2, c3

    def f(t, sign):
        p = pose(t, sign)
        return math.nan if p is None else float(np.sum((p[2] - a3) ** 2) - RHO[2] ** 2)

    roots = []
    ts = np.linspace(0, 2 * math.pi, 20001)
    for sign in (1, -1):
        v = [f(t, sign) for t in ts]
        for k in range(len(ts) - 1):
            if math.isfinite(v[k]) and math.isfinite(v[k + 1]) and v[k] * v[k + 1] < 0:
                t = brentq(f, ts[k], ts[k + 1], args=(sign,), xtol=1e-15)
                roots.append(np.concatenate(pose(t, sign)))
    return roots


def test_3rpr_forward_problem_six_real_assembly_modes():
    m, values = rpr_model()
    truth = rpr_truth()
    assert len(truth) == 6  # the literature's count, by an independent sweep
    result = solve_all(m, values, method="total-degree")
    assert_same_configurations(result, truth, ["C1", "C2", "C3"])
    assert result.complex == 0  # the forward problem has 6 solutions over C: all real here
    assert result.paths == 16
    for s in result.solutions:  # leg lengths and the D nodes recovered on their legs
        for i in range(3):
            c, a, d = (np.array(s.configuration[f"{n}{i + 1}"]) for n in "CAD")
            assert np.linalg.norm(c - a) == pytest.approx(RHO[i], abs=1e-9)
            assert np.linalg.norm(d - a) == pytest.approx(1.0, abs=1e-12)
            assert cross(d - a, c - a) == pytest.approx(0.0, abs=1e-9)
    mm = solve_all(m.moved(scale=1000.0), {k: 1000.0 * v for k, v in values.items()})
    assert len(mm.solutions) == 6 and mm.complex == 0


# ---------------------------------------------------------------- overconstrained, analysis, errors
def test_overconstrained_double_parallelogram_checked_against_original_equations():
    m = catalogue.get("double_parallelogram")
    sys_ = position_system(m, {"rotation:crank": 40}, unit="deg")
    assert len(sys_.equations) > len(sys_.unknowns)  # one redundant constraint
    result = solve_all(m, {"rotation:crank": 40}, unit="deg")
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    th = math.atan2(x["B"][1], x["B"][0]) + math.radians(40)
    crank = float(np.linalg.norm(x["B"])) * np.array([math.cos(th), math.sin(th)])
    expected = [np.concatenate([x["A"] + crank, x["D"] + crank, x["E"] + crank])]
    # the third crank excludes the anti-parallelogram modes: the translating coupler is the only one
    assert_same_configurations(result, expected, ["B", "C", "F"])


def test_analyze_each_solution_agrees_with_the_labels():
    m = catalogue.get("five_bar")
    result = solve_all(m, {"velocity:P.x": 0.1, "velocity:P.y": -0.2}, analyze=True)
    for s in result.solutions:
        assert s.analysis is not None and s.analysis.dof == 1 + 1 and s.analysis.types == s.types
        for key in ("dkp_input", "dkp_output"):
            value = getattr(s.analysis, key)
            assert s.signs[key] == (None if value is None else int(np.sign(value)))


@pytest.mark.parametrize("values, message", [
    ({"rotation:crnk": 30}, "unknown input"),
    ({}, "not isolated"),
    ({"rotation:crank": 30, "rotation:rocker": 10}, "too many values"),
])
def test_bad_values_raise_naming_the_problem(values, message):
    with pytest.raises(SymkinError, match=message):
        solve_all(catalogue.get("fourbar_appendix"), values, unit="deg")


# ---------------------------------------------------------------- spatial rotation and joint angles
def test_rssr_two_assembly_modes_on_the_rocker_circle():
    m = catalogue.get("rssr")
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    t = math.radians(20)
    b = np.array([math.cos(t), math.sin(t), 0.0])  # B = (1, 0, 0) turned about the z axis
    coupler = float(np.linalg.norm(x["C"] - x["B"]))
    r = float(np.linalg.norm(x["C"] - x["O2"]))
    # C turns about the x axis through O2 = (3, 0, 1): in the plane x = 3, the circle (y, z) about (0, 1)
    # meets the sphere about B, i.e. the circle about (b_y, 0) of radius sqrt(coupler² − (3 − b_x)²)
    yz = circle_points((0.0, 1.0), r, (b[1], 0.0), math.sqrt(coupler ** 2 - (3.0 - b[0]) ** 2))
    expected = [np.concatenate([b, [3.0, y, z]]) for y, z in yz]
    result = solve_all(m, {"rotation:crank[O1-O1b]": 20}, unit="deg", method="total-degree")
    assert_same_configurations(result, expected, ["B", "C"])
    assert result.paths == 2 and result.complex == 0


def test_joint_angle_prescribed_on_a_five_bar():
    d = catalogue.data("five_bar")
    d["inputs"] = [{"rotation": "crank1"}, {"joint": ["crank1", "distal1"]}]
    m = Mechanism.from_dict(d)
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    b1 = x["A1"] + rotate(x["B1"] - x["A1"], math.radians(10))
    p = b1 + rotate(x["P"] - x["B1"], math.radians(15))  # the distal turns 10° + 5°
    lc, ld = float(np.linalg.norm(x["B2"] - x["A2"])), float(np.linalg.norm(x["P"] - x["B2"]))
    expected = [np.concatenate([b1, b2, p]) for b2 in circle_points(x["A2"], lc, p, ld)]
    result = solve_all(m, {"rotation:crank1": 10, "joint:crank1-distal1": 5}, unit="deg", method="total-degree")
    assert_same_configurations(result, expected, ["B1", "B2", "P"])
    assert result.paths == 2


def test_dead_centre_is_one_double_solution_labelled_dkp():
    # crank 1 and coupler 3 aligned: B = (0.6, 0.8), C = 4 B; with the rocker's angle prescribed the
    # two positions of B (circle about A meets circle about C) coincide: one solution, two paths
    m = catalogue.get("fourbar_dead_centre")
    result = solve_all(m, {"rotation:rocker": 0}, method="total-degree")
    assert len(result.solutions) == 1 and result.paths == 2 and result.complex == 0
    s = result.solutions[0]
    assert s.multiplicity == 2
    assert np.concatenate([s.configuration["B"], s.configuration["C"]]) == pytest.approx([0.6, 0.8, 2.4, 3.2],
                                                                                        abs=1e-9)
    assert s.types == ("DKP-output",) and s.signs["dkp_output"] == 0
    # with the crank's angle prescribed there are two distinct modes, one of them the dead centre
    both = solve_all(m, {"rotation:crank": 0})
    assert [x.multiplicity for x in both.solutions] == [1, 1]
    assert sorted(x.types for x in both.solutions) == [(), ("DKP-output",)]


def test_overconstrained_structure_squared_up_gives_the_square_and_its_mirror():
    # unit square with both diagonals on A = (0, 0), B = (1, 0): 5 bars, 4 unknowns
    m = catalogue.get("braced_square")
    result = solve_all(m, {})
    assert result.equations > result.unknowns  # squared up by random combinations
    expected = [np.array([1.0, 1.0, 0.0, 1.0]), np.array([1.0, -1.0, 0.0, -1.0])]
    assert_same_configurations(result, expected, ["C", "D"])
    assert result.complex == 0
    # the squared-up system has 4 real solutions (resultant: y_C ∈ {−1.318, −0.889, 0.439, 0.010} in
    # units of the length scale); the 2 that fail the original equations are rejected, not merged
    assert result.rejected == 2 and [s.multiplicity for s in result.solutions] == [1, 1]


def test_too_many_paths_is_refused_with_the_count():
    with pytest.raises(SymkinError, match="would track 8192 paths"):
        solve_all(catalogue.get("pratt_truss"), {})


def test_spatial_moving_line_slider_redundant_cross_product_component():
    # C slides on the line of the bar A-D (spherical at A), on the plane z = 1, and hangs on the rod E-C;
    # with x_C prescribed: C = (1.2, ±sqrt(3 − 0.64 − 1), 1) and D = ±C/|C| on the line: 4 solutions.
    # The line gives three bilinear components (C − A) × (D − A) = 0 of rank 2: the redundant one must go.
    c = np.array([1.0, 1.0, 1.0])
    m = Mechanism.from_dict({"name": "spatial leg", "dim": 3, "fixed": ["A", "E"], "mobility": 1,
                             "inputs": [{"velocity": "C", "component": "x"}],
                             "nodes": {"A": [0, 0, 0], "E": [2, 0, 0], "C": list(c), "D": list(c / np.linalg.norm(c))},
                             "links": {"leg": ["A", "D"], "rod": ["E", "C"]},
                             "sliders": [{"id": "s", "node": "C", "line": ["A", "D"], "link": "leg"},
                                         {"id": "p", "node": "C", "point": [0, 0, 1], "normal": [0, 0, 1]}]})
    y = math.sqrt(3.0 - 0.64 - 1.0)
    expected = []
    for sy in (1, -1):
        cc = np.array([1.2, sy * y, 1.0])
        expected += [np.concatenate([cc, sd * cc / np.linalg.norm(cc)]) for sd in (1, -1)]
    result = solve_all(m, {"velocity:C.x": 0.2})
    assert_same_configurations(result, expected, ["C", "D"])
    # the line is two equations (the cross product's components along the line's normals at the model);
    # where the cross product turns along the line itself they hold off the line: such endpoints are
    # rejected by the check on the original equations, never counted. How many endpoints Bertini's
    # total-degree solve leaves there varies from run to run (0 to 4 seen in six runs of 24 paths), so
    # the count itself is not asserted: what holds is that none of them is counted as a solution
    assert result.complex == 0, f"{result.complex} complex solutions counted ({result.rejected} rejected)"


def test_a_failed_bertini_solve_is_retried_then_reported(monkeypatch):
    """Bertini 2 now and then aborts a whole solve on one path: a new (random) homotopy is tried, up to RETRIES."""
    import bertini

    from symkin.solutions import homotopy

    real = bertini.nag_algorithm.ZeroDimPowerSeriesDoublePrecisionTotalDegree
    calls = {"n": 0}

    class Flaky:
        def __init__(self, system):
            self.alg = real(system)

        def solve(self):
            calls["n"] += 1
            if calls["n"] <= calls.get("fail", 1):
                raise RuntimeError("trying to evaluate system, but number of input variables (0) doesn't match")
            self.alg.solve()

        def solutions(self):
            return self.alg.solutions()

    monkeypatch.setattr(bertini.nag_algorithm, "ZeroDimPowerSeriesDoublePrecisionTotalDegree", Flaky)
    import sympy as sp

    x, y = sp.symbols("x y")
    ends = homotopy.track([x**2 - 1, y - 2], [x, y], endgame="power_series")
    assert calls["n"] == 2 and sorted(round((v[1] / v[0]).real, 9) for v in ends) == [-1.0, 1.0]
    calls.update(n=0, fail=homotopy.RETRIES)
    with pytest.raises(SymkinError, match="failed 3 times"):
        homotopy.track([x**2 - 1, y - 2], [x, y], endgame="power_series")


# ---------------------------------------------------------------- every endpoint verified (issue 17 §2)
def _spurious_complex_endpoint(system, eqs):
    """A complex root of the squared-up equations ``eqs`` that fails the original equations (Newton from random starts)."""
    import sympy as sp

    from symkin.curves.corrector import gauss_newton, real_form

    v = list(system.solve_for)
    f = sp.lambdify([v], eqs, "numpy")
    j = sp.lambdify([v], sp.Matrix(eqs).jacobian(v), "numpy")
    orig = sp.lambdify([list(system.unknowns)], [e for _, e in system.equations], "numpy")
    fun = real_form(lambda x: (np.array(f(x), complex), np.array(j(x), complex).reshape(len(eqs), len(v))))
    rng = np.random.default_rng(3)
    for _ in range(200):
        z0 = rng.standard_normal(2 * len(v))
        c = gauss_newton(fun, z0, tol=1e-13, max_iterations=50)
        w = c.z[:len(v)] + 1j * c.z[len(v):]
        if c.converged and np.max(np.abs(w.imag)) > 1e-3 and \
                np.max(np.abs(np.array(orig(system.recover(w)), complex))) > 1e-3:
            return w
    raise AssertionError("no spurious complex root found")


def test_complex_endpoint_of_the_squared_up_system_only_is_not_counted(monkeypatch):
    import sympy as sp

    import importlib

    sa = importlib.import_module("symkin.solutions.solve_all")

    m = catalogue.get("braced_square")
    system = position_system(m, {})
    # squared up by complex random combinations: its extra roots are complex
    a = np.random.default_rng(1).standard_normal((len(system.solve_for), len(system.reduced), 2))
    eqs = [sp.expand(sum(complex(*a[i, k]) * e for k, e in enumerate(system.reduced)))
           for i in range(len(system.solve_for))]
    w = _spurious_complex_endpoint(system, eqs)
    plain = solve_all(m, {}, method="total-degree")
    real_track = sa.track
    monkeypatch.setattr(sa, "track", lambda e, u, **k: np.vstack([real_track(e, u, **k),
                                                                  np.concatenate([[1.0], w])[None, :]]))
    result = solve_all(m, {}, method="total-degree")
    assert result.complex == plain.complex  # the spurious complex endpoint is not a solution
    assert result.rejected == plain.rejected + 1 and result.to_dict()["rejected"] == result.rejected
    assert len(result.solutions) == len(plain.solutions) == 2


@pytest.mark.slow
def test_planar_gough_stewart_counts_only_verified_complex_solutions(gough_stewart_total_degree):
    """4 real + 24 complex, as PHCpack's polyhedral blackbox on a 9-unknown formulation (issue 17)."""
    # Bertini's total-degree paths start from a random γ and now and then one fails: every count is of
    # verified solutions (never above the truth), so up to three solves are taken and the largest kept
    # (the solves: tests/conftest.py, gough_stewart_total_degree, shared with test_parameter_homotopy)
    m, values, results = gough_stewart_total_degree
    assert values == {**{f"slide:s{i}": 0.0 for i in range(1, 7)}, "slide:s1": 0.05}
    counts = []
    for result in results:
        assert len(result.solutions) == 4 and result.complex <= 24
        counts.append(result.complex)
    # 28 were counted before verification: endpoints of the reduced system that fail the original
    # equations (4 to 8 of them, as the random start goes) are now rejected, not counted
    assert max(counts) == 24, counts
