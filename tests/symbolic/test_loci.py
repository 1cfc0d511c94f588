"""Singularity loci as implicit polynomials (issue 9 §3) against elementary geometry.

Expected polynomials are derived here independently: the five-bar's type-1 circles
``|P − A_i| = l1 ± l2``; its type-2 locus with equal distal links, Watt's sextic (P the midpoint
of B1B2, Wikipedia's closed form, itself checked on constructed midpoints) and the
coincident-elbow circles; the 3-RPR's conic at constant orientation (the line-matrix
determinant of tests/workspace/truth.py); and the curves ``symkin.workspace_map`` traces.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.errors import SymkinError
from symkin.model import catalogue
from symkin.symbolic.loci import closure_polynomials, implicit_loci
from tests.workspace import truth as T

RPR = Path(__file__).resolve().parents[1] / "workspace" / "models" / "rpr_3.toml"
x, y = sp.symbols("x_P y_P", real=True)
xo, yo = sp.symbols("x_O y_O", real=True)


def primitive(expr, gens) -> sp.Poly:
    """``expr`` as a primitive integer polynomial with a positive leading coefficient."""
    p = sp.Poly(sp.expand(expr), *gens, domain="QQ").clear_denoms()[1]
    p = p.primitive()[1]
    return -p if p.LC() < 0 else p


def same_up_to_constant(a, b, gens) -> bool:
    return primitive(a, gens) == primitive(b, gens)


def factor_set(locus, gens) -> set:
    return {primitive(f.polynomial, gens) for f in locus.factors}


def five_bar(a1, a2, b1, b2, p, scale=1) -> symkin.Mechanism:
    data = catalogue.data("five_bar")
    data["nodes"] = {k: [float(v) * scale for v in xyz] for k, xyz in
                     {"A1": a1, "A2": a2, "B1": b1, "B2": b2, "P": p}.items()}
    return symkin.Mechanism.from_dict(data)


# ----------------------------------------------------------------------------------- closure
@pytest.mark.parametrize("mech", [catalogue.get("five_bar"), symkin.read_model(RPR)], ids=["five_bar", "rpr_3"])
def test_closure_polynomials_vanish_on_the_numeric_closure(mech):
    """At configurations the numeric core projects onto its closure, every polynomial vanishes."""
    ev = symkin.evaluators(mech)
    rng = np.random.default_rng(1)
    x0 = np.array([c for _, c in mech.nodes], float)
    free = [k for k, n in enumerate(mech.node_names) if n in set(mech.free_nodes)]
    polys = closure_polynomials(mech)
    assert len(polys) >= len(free) * mech.dim - mech.mobility_value
    for _ in range(3):
        q = ev.project(np.asarray(ev.q0, float).ravel() + 0.05 * rng.standard_normal(len(free) * mech.dim))
        xyz = x0.copy()
        xyz[free] = np.asarray(q).reshape(-1, mech.dim)
        values = {sp.Symbol(f"{'xyz'[a]}_{n}", real=True): xyz[k, a] for k, n in enumerate(mech.node_names)
                  for a in range(mech.dim)}
        for e, owner in polys:
            assert abs(float(e.xreplace(values))) < 1e-9 * mech.length_scale ** 2, owner


# ----------------------------------------------------------------------------------- five-bar type 1
def test_five_bar_type1_circles_at_the_pivots():
    """DKP-output (type 1, a leg stretched or folded): |P − A_i| = l1 ± l2, exactly four circles."""
    mech = catalogue.get("five_bar")
    loci = implicit_loci(mech, kinds=("DKP-output",))
    (la, lb) = (1, 2)  # |B1 − A1| = 1, |P − B1| = 2 in the catalogue's model
    expected = {primitive((x - ax) ** 2 + y ** 2 - r ** 2, (x, y)) for ax in (-1, 1) for r in (la + lb, lb - la)}
    locus = loci["DKP-output"]
    assert factor_set(locus, (x, y)) == expected
    assert [f.degree for f in locus.factors] == [2, 2, 2, 2] and all(f.exponent == 1 for f in locus.factors)
    assert sum("radius 3 = l_crank1 + l_distal1" in f.meaning and "pivot A1" in f.meaning for f in locus.factors) == 1
    assert sum("radius 1 = |l_crank2 - l_distal2|" in f.meaning for f in locus.factors) == 1
    assert not locus.trivial


# ----------------------------------------------------------------------------------- five-bar type 2
A, B, C = 1, 2, sp.Rational(5, 4)  # pivots (∓A, 0), cranks B, distal links C (equal)


def watt_sextic(a, b, c):
    """Watt's curve: the midpoint of a bar of length 2c whose ends run on circles of radius b
    about (∓a, 0): (x²+y²)(x²+y²−d²)² + 4a²y²(x²+y²−b²), d² = a² + b² − c²."""
    r2, d2 = x ** 2 + y ** 2, a ** 2 + b ** 2 - c ** 2
    return r2 * (r2 - d2) ** 2 + 4 * a ** 2 * y ** 2 * (r2 - b ** 2)


def test_watt_sextic_closed_form_holds_on_constructed_midpoints():
    """The closed form itself, on midpoints built from the two circles and the bar."""
    a, b, c = float(A), float(B), float(C)
    f = sp.lambdify((x, y), watt_sextic(A, B, C))
    hits = 0
    for alpha in np.linspace(0.1, 6.2, 40):
        b1 = np.array([-a + b * math.cos(alpha), b * math.sin(alpha)])
        # B2 on the circle about (a, 0), radius b, at distance 2c from B1
        d = np.linalg.norm(b1 - [a, 0.0])
        along = (d * d + b * b - 4 * c * c) / (2 * d)
        h2 = b * b - along * along
        if d == 0 or h2 < 0:
            continue
        u = ([a, 0.0] - b1) / d
        for s in (1, -1):
            b2 = np.array([a, 0.0]) - along * u + s * math.sqrt(h2) * np.array([-u[1], u[0]])
            m = (b1 + b2) / 2
            assert abs(f(*m)) < 1e-9 * (1 + np.dot(m, m)) ** 3
            hits += 1
    assert hits > 20


def test_five_bar_type2_is_watts_sextic_and_the_coincident_elbow_circles():
    """DKP-input (type 2, distal links aligned) with equal distal links: P the midpoint of B1B2
    (Watt's sextic) or B1 = B2 (P on a circle of radius C about an intersection of the crank
    circles, (0, ±√(B² − A²)): the two circles multiply to a quartic over the rationals)."""
    mech = five_bar((-1, 0), (1, 0), (-1, 2), (1, 2), (0, 2.75))  # cranks 2, distal links 5/4
    loci = implicit_loci(mech, kinds=("DKP-input",))
    h2 = B ** 2 - A ** 2
    elbow_circles = sp.expand((x ** 2 + (y - sp.sqrt(h2)) ** 2 - C ** 2) * (x ** 2 + (y + sp.sqrt(h2)) ** 2 - C ** 2))
    expected = {primitive(watt_sextic(A, B, C), (x, y)), primitive(elbow_circles, (x, y))}
    locus = loci["DKP-input"]
    assert factor_set(locus, (x, y)) == expected
    assert sorted(f.degree for f in locus.factors) == [4, 6]
    sextic = [f for f in locus.factors if f.degree == 6][0]
    assert "tricircular sextic" in sextic.meaning
    assert same_up_to_constant(locus.polynomial, watt_sextic(A, B, C) * elbow_circles, (x, y))


def test_five_bar_without_curve_of_increased_mobility():
    loci = implicit_loci(catalogue.get("five_bar"))
    assert [l.kind for l in loci.loci] == ["DKP-input", "DKP-output", "IM"]
    assert loci["IM"].factors == () and "share no factor" in loci["IM"].note


def test_scale_invariance_millimetres_and_metres():
    """The model in millimetres: the same factors with x → x/1000."""
    args = ((-1, 0), (1, 0), (-1, 2), (1, 2), (0, 2.75))
    m, mm = five_bar(*args), five_bar(*args, scale=1000)
    for kind in ("DKP-input", "DKP-output"):
        a = factor_set(implicit_loci(m, kinds=(kind,))[kind], (x, y))
        b = {primitive(f.polynomial.xreplace({x: 1000 * x, y: 1000 * y}), (x, y))
             for f in implicit_loci(mm, kinds=(kind,))[kind].factors}
        assert a == b, kind


def two_r_arm(scale=1.0) -> symkin.Mechanism:
    return symkin.Mechanism.from_dict({
        "name": "2R arm", "dim": 2, "fixed": ["A"],
        "inputs": [{"rotation": "upper"}, {"rotation": "fore"}], "outputs": [{"velocity": "P"}],
        "nodes": {"A": [0.0, 0.0], "B": [3.0 * scale, 4.0 * scale], "P": [3.0 * scale, 6.0 * scale]},
        "links": {"upper": ["A", "B"], "fore": ["B", "P"]}})


def test_joint_space_locus_in_tangent_half_angles():
    """A 2R arm (links 5 and 2) in (t_upper, t_fore) = tan(θ/2): the end point cannot move along
    the arm where sin(θ_fore − θ_upper) = 0, whose numerator in the half-angle tangents is
    (t_fore − t_upper)(1 + t_upper t_fore); in (x_P, y_P) the circles of radius 5 ± 2 about A."""
    mech = two_r_arm()
    loci = implicit_loci(mech, ("rotation:upper", "rotation:fore"), kinds=("DKP-output",))
    tu, tf = loci.variables
    assert (tu.name, tf.name) == ("t_upper", "t_fore")
    cos = lambda t: (1 - t ** 2) / (1 + t ** 2)  # noqa: E731
    sin = lambda t: 2 * t / (1 + t ** 2)  # noqa: E731
    expected = sp.numer(sp.together(sin(tf) * cos(tu) - cos(tf) * sin(tu)))  # sin(θf − θu)
    assert same_up_to_constant(loci["DKP-output"].polynomial, expected, (tu, tf))
    assert {f.degree for f in loci["DKP-output"].factors} == {1, 2}
    assert any("opposite directions" in f.meaning for f in loci["DKP-output"].factors)
    ws = implicit_loci(mech, ("velocity:P.x", "velocity:P.y"), kinds=("DKP-output",))["DKP-output"]
    assert factor_set(ws, (x, y)) == {primitive(x ** 2 + y ** 2 - r ** 2, (x, y)) for r in (3, 7)}


# ----------------------------------------------------------------------------------- 3-RPR conic
def test_rpr_constant_orientation_conic_of_sefrioui_gosselin():
    """At constant orientation the type-2 locus is a conic: its cubic terms cancel (degree 2)."""
    mech = symkin.read_model(RPR)
    loci = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=("rotation:platform",),
                         kinds=("DKP-input",))
    locus = loci["DKP-input"]
    conics = [f for f in locus.factors if f.degree == 2 and "conic" in f.meaning]
    assert len(conics) == 1 and max(f.degree for f in locus.factors) == 2
    coef = T.rpr_conic(np.array([[0.0, 0.0], [6.0, 0.0], [2.0, 5.0]]),
                       np.array([[-1.0, -0.5], [1.25, -0.25], [0.0, 1.0]]), 0.0)
    p = sp.Poly(conics[0].polynomial, xo, yo)
    mine = np.array([float(p.coeff_monomial(m)) for m in (xo ** 2, xo * yo, yo ** 2, xo, yo, 1)])
    np.testing.assert_allclose(mine / mine[0], coef / coef[0], rtol=1e-12, atol=1e-12)
    # the other factors: a leg of zero length, C_k on A_k (one real point each: O = A_k − c_k)
    points = {tuple(sp.solve([sp.diff(f.polynomial, xo), sp.diff(f.polynomial, yo)], [xo, yo]).values())
              for f in locus.factors if "the point" in f.meaning}
    assert points == {(1, sp.Rational(1, 2)), (sp.Rational(19, 4), sp.Rational(1, 4)), (2, 4)}


# ----------------------------------------------------------------------------------- agreement with the maps
def _relative(f, pts, gens) -> np.ndarray:
    """|f(p)| over the sum of the absolute values of its terms at p (scale-free)."""
    p = sp.Poly(f, *gens)
    terms = [(float(c), m) for m, c in p.terms()]
    val = sum(c * pts[:, 0] ** m[0] * pts[:, 1] ** m[1] for c, m in terms)
    mag = sum(abs(c) * np.abs(pts[:, 0]) ** m[0] * np.abs(pts[:, 1]) ** m[1] for c, m in terms)
    return np.abs(val) / np.maximum(mag, 1e-300)


def _check_map(wmap, loci, gens) -> int:
    checked = 0
    for curve in wmap.curves:
        pts = np.asarray(curve.points, float)
        factors = loci[curve.kind].factors
        assert factors, curve.kind
        rel = np.min([_relative(f.polynomial, pts, gens) for f in factors], axis=0)
        assert rel.max() < 1e-9, (curve.kind, rel.max())
        checked += len(pts)
    return checked


@pytest.mark.slow
def test_five_bar_map_curves_lie_on_the_loci():
    mech = five_bar((-1, 0), (1, 0), (-1, 2), (1, 2), (0, 2.75))
    loci = implicit_loci(mech, kinds=("DKP-input", "DKP-output"))
    wmap = symkin.workspace_map(mech, x="velocity:P.x=-3.2:3.2", y="velocity:P.y=0.1:3.6", n=(33, 19), refine=True)
    kinds = {c.kind for c in wmap.curves}
    assert {"DKP-input", "DKP-output"} <= kinds
    assert _check_map(wmap, loci, (x, y)) > 100


@pytest.mark.slow
def test_rpr_map_curves_lie_on_the_conic():
    mech = symkin.read_model(RPR)
    loci = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=("rotation:platform",),
                         kinds=("DKP-input", "DKP-output"))
    wmap = symkin.workspace_map(mech, x="velocity:O.x=1.5:4.5", y="velocity:O.y=0.75:3.25", n=(31, 26),
                                hold=("rotation:platform",), refine=True)
    assert any(c.kind == "DKP-input" for c in wmap.curves)
    assert _check_map(wmap, loci, (xo, yo)) > 20


# ----------------------------------------------------------------------------------- errors, limits, CLI
def test_bad_labels_and_holds_are_named():
    mech = symkin.read_model(RPR)
    with pytest.raises(SymkinError, match="velocity:Q.x"):
        implicit_loci(mech, ("velocity:Q.x", "velocity:O.y"), hold=("rotation:platform",))
    with pytest.raises(SymkinError, match="1 held coordinate"):
        implicit_loci(mech, ("velocity:O.x", "velocity:O.y"))
    with pytest.raises(SymkinError, match="named twice"):
        implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=("velocity:O.x",))
    with pytest.raises(SymkinError, match="do not fix the mechanism"):
        implicit_loci(mech, ("velocity:O.x", "velocity:C1.x"), hold=("rotation:platform",))


def test_time_limit_names_the_locus_instead_of_hanging():
    mech = symkin.read_model(RPR)
    loci = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=("rotation:platform",),
                         kinds=("DKP-input",), time_limit=0.05)
    assert loci.loci == () and len(loci.skipped) == 1
    assert loci.skipped[0].startswith("DKP-input") and "time limit of 0.05 s" in loci.skipped[0]


@pytest.fixture
def five_bar_file(tmp_path) -> Path:
    path = tmp_path / "five_bar.toml"
    symkin.write_model(catalogue.get("five_bar"), path)
    return path


def test_cli_json(capsys, five_bar_file):
    from symkin.cli import main

    code = main(["conditions", str(five_bar_file), "--in", "velocity:P.x,velocity:P.y", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    assert data["variables"] == ["x_P", "y_P"]
    assert [l["kind"] for l in data["loci"]] == ["DKP-input", "DKP-output", "IM"]
    out = {l["kind"]: l for l in data["loci"]}
    assert {f["degree"] for f in out["DKP-output"]["factors"]} == {2}
    for f in out["DKP-input"]["factors"] + out["DKP-output"]["factors"]:
        e = sp.sympify(f["polynomial"])
        assert {str(s) for s in e.free_symbols} <= {"x_P", "y_P"}
        assert sp.Poly(e, *sorted(e.free_symbols, key=str)).total_degree() == f["degree"] and f["meaning"]


def test_cli_bad_label_exit_2(capsys, five_bar_file):
    from symkin.cli import main

    code = main(["conditions", str(five_bar_file), "--in", "velocity:Q.x,velocity:P.y"])
    err = capsys.readouterr().err
    assert code == 2 and "velocity:Q.x" in err and "Traceback" not in err
    assert "unknown coordinate 'velocity:Q.x'; a locus can be written in the model's inputs" in err
    assert "velocity:<node>.<x|y> for a free node (" in err and "path" not in err


def test_cli_one_dof_says_there_is_no_curve(capsys, tmp_path):
    """F = 1 (the four-bar, the spatial RSSR): no singularity curve in two coordinates; the message says why."""
    from symkin.cli import main

    for name, labels in (("fourbar_appendix", "rotation:crank,rotation:rocker"),
                         ("rssr", "rotation:crank[O1-O1b],rotation:rocker[O2-O2b]")):
        path = symkin.write_model(catalogue.get(name), tmp_path / f"{name}.toml")
        code = main(["conditions", str(path), "--in", labels])
        err = capsys.readouterr().err
        assert code == 2 and "F = 1" in err and "symkin singularities" in err and "Traceback" not in err
        assert "-1 held" not in err


def test_rpr_im_locus_has_no_curve_the_loci_share_only_points():
    """3-RPR at constant orientation: IM ⊂ DKP-input ∩ DKP-output, which share only the three points
    where a leg has zero length (O = A_k − c_k): the IM locus has no curve, decided without the minors."""
    from symkin.symbolic.loci import _one_real_point

    mech = symkin.read_model(RPR)
    loci = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=("rotation:platform",))
    inp, out, im = loci["DKP-input"], loci["DKP-output"], loci["IM"]
    shared = {sp.srepr(f.polynomial) for f in inp.factors} & {sp.srepr(f.polynomial) for f in out.factors}
    points = [f.polynomial for f in out.factors]
    assert len(shared) == 3 and all(_one_real_point(p, (xo, yo)) for p in points)
    # each shared factor is (O − (A_k − c_k))² up to a constant: one real point, at a zero-length leg
    zeros = {tuple(sp.solve([sp.diff(p, xo), sp.diff(p, yo)], [xo, yo]).values()) for p in points}
    assert zeros == {(1, sp.Rational(1, 2)), (sp.Rational(19, 4), sp.Rational(1, 4)), (2, 4)}
    conic = [f.polynomial for f in inp.factors if f.degree == 2 and "conic" in f.meaning]
    assert len(conic) == 1 and not _one_real_point(conic[0], (xo, yo))
    assert im.factors == () and "one real point" in im.note and not loci.skipped
    assert not _one_real_point(xo ** 2 + yo ** 2 - 1, (xo, yo)) and _one_real_point(3 * (xo - 1) ** 2 + 3 * yo ** 2, (xo, yo))


# ----------------------------------------------------------------------------------- float data (issue 17 §4)
def _floated(mech: symkin.Mechanism) -> symkin.Mechanism:
    """The same five-bar with its moving nodes recomputed in floats from angles, as a user writes them
    (every length equal to the exact one only up to rounding)."""
    nodes = dict(mech.nodes)

    def polar(origin, target):
        dx, dy = target[0] - origin[0], target[1] - origin[1]
        r, a = math.hypot(dx, dy), math.atan2(dy, dx)
        return r, a

    out = {k: list(v) for k, v in nodes.items()}
    for pivot, elbow in (("A1", "B1"), ("A2", "B2")):
        r, a = polar(nodes[pivot], nodes[elbow])
        out[elbow] = [nodes[pivot][0] + r * math.cos(a), nodes[pivot][1] + r * math.sin(a)]
    r, a = polar(nodes["B1"], nodes["P"])
    out["P"] = [out["B1"][0] + r * math.cos(a), out["B1"][1] + r * math.sin(a)]
    data = mech.to_dict()
    data["nodes"] = out
    return symkin.Mechanism.from_dict(data)


def test_float_five_bar_gives_the_exact_models_factors():
    """Pivots (±1, 0), cranks 2, distal links 5/2 (B2 = (−13/17, 16/17), a rational point): the model
    rebuilt in floats (and the issue's own float five-bar) gives the same factors and meanings as the
    exact one, and says which numbers it snapped."""
    exact = five_bar((-1, 0), (1, 0), (-1, 2), (-13 / 17, 16 / 17), (1.5, 2))
    floated = _floated(exact)
    b1 = (-1.9686951572356552, 1.7497513230022688)
    issue = five_bar((-1, 0), (1, 0), b1, (-b1[0], b1[1]), (0.0, b1[1] + math.sqrt(2.5 ** 2 - b1[0] ** 2)))
    want = implicit_loci(exact)
    assert want.snap.snapped == []
    for mech in (floated, issue):
        got = implicit_loci(mech)
        for kind in ("DKP-input", "DKP-output"):
            assert factor_set(got[kind], (x, y)) == factor_set(want[kind], (x, y)), kind
            if mech is floated:
                assert [f.meaning for f in got[kind].factors] == [f.meaning for f in want[kind].factors]
        out = got["DKP-output"]
        assert sorted(f.degree for f in out.factors) == [2, 2, 2, 2]
        assert sum("radius 9/2 = l_crank1 + l_distal1" in f.meaning for f in out.factors) == 1
        assert sorted(f.degree for f in got["DKP-input"].factors) == [4, 6]
        assert any("sextic" in f.meaning for f in got["DKP-input"].factors)
    issue_loci = implicit_loci(issue)
    assert [s.exact for s in issue_loci.snap.snapped] == [sp.Rational(25, 4)] * 2
    assert "snapped to the simplest rationals within 1e-06 x the length scale" in str(issue_loci)
    data = issue_loci.as_dict()["snapping"]
    assert data["relative_tolerance"] == 1e-6 and {s["snapped"] for s in data["snapped"]} == {"25/4"}
    assert all(s["what"].startswith("squared length of distal") for s in data["snapped"])


def test_snapping_a_shared_length_once_and_within_the_tolerance():
    from symkin.symbolic.snapping import simplest_rational, snap_model

    assert simplest_rational(2.0000000000000004, 1e-6) == 2 and simplest_rational(1 / 3, 1e-9) == sp.Rational(1, 3)
    assert simplest_rational(2750.0, 0.002) == 2750  # an integer stays itself in any unit
    r = simplest_rational(0.1234567, 1e-12)  # the smallest denominator within the tolerance
    assert abs(float(r) - 0.1234567) <= 1e-12 and r.q < 10 ** 7
    # two links whose lengths differ by less than the tolerance get one rational
    mech = five_bar((-1, 0), (1, 0), (-1, 2.0000001), (1, 2.0000002), (0, 2.75))
    s = snap_model(mech)
    assert s.squared_length("crank1", "A1", "B1") == s.squared_length("crank2", "A2", "B2") == 4
    assert abs(float(s.squared_length("crank1", "A1", "B1")) - 2.0000001 ** 2) <= 2 * 2.0000001 * s.tolerance


def test_a_sextic_with_one_real_point_is_named_as_such():
    """Cranks 1 about (∓1, 0), distal links 3: B1, P, B2 never line up (|B1 B2| ≤ 4 < 6), so the
    DKP-input sextic (Watt's curve of a bar of length 6, P its midpoint) has only its isolated real
    point at the origin, and is named like a circle of radius 0; the model is written in floats
    (P = (0, 1 + √8))."""
    from symkin.symbolic.real_points import isolated_real_points

    mech = five_bar((-1, 0), (1, 0), (-1, 1), (1, 1), (0, 1 + math.sqrt(8)))
    locus = implicit_loci(mech, kinds=("DKP-input",))["DKP-input"]
    sextic = [f for f in locus.factors if f.degree == 6]
    assert len(sextic) == 1 and same_up_to_constant(sextic[0].polynomial, watt_sextic(1, 1, 3), (x, y))
    assert sextic[0].meaning.startswith("the point (0, 0) (a tricircular sextic") and "one real point" in sextic[0].meaning
    assert isolated_real_points(watt_sextic(A, B, C), (x, y)) is None  # the five-bar's real Watt curve
    assert isolated_real_points(x ** 4 + y ** 4 + 1, (x, y)) == []


# ----------------------------------------------------------------------------------- spatial (issue 17 §5)
GOUGH = Path(__file__).resolve().parents[1] / "workspace" / "models" / "gough_stewart.toml"


def plucker_type2(mech: symkin.Mechanism, gens) -> sp.Poly:
    """The Gough–Stewart's type-2 condition at the model's orientation and height, written
    independently: the 6 × 6 matrix of the legs' Plücker lines (direction C_k − A_k, moment
    A_k × C_k) with C_k = O + (C_k0 − O_0) (the platform translated), O = (x, y, z_0)."""
    nodes = {n: [sp.Rational(repr(float(v))) for v in xyz] for n, xyz in mech.nodes}
    o0 = nodes["O"]
    ox, oy = gens
    rows = []
    for k in range(1, 7):
        a = sp.Matrix(nodes[f"A{k}"])
        c = sp.Matrix([ox + nodes[f"C{k}"][0] - o0[0], oy + nodes[f"C{k}"][1] - o0[1], nodes[f"C{k}"][2]])
        rows.append(list(c - a) + list(a.cross(c)))
    return sp.Poly(sp.expand(sp.Matrix(rows).det(method="berkowitz")), *gens)


def test_gough_stewart_plucker_locus_is_a_conic_for_planar_base_and_platform():
    """The model's base joints are coplanar (z = 0) and so are its platform joints: at constant
    orientation and height the Plücker determinant has no cubic terms (a conic in (x_O, y_O), the
    issue's coplanar case, not the general 6-6's cubic)."""
    det = plucker_type2(symkin.read_model(GOUGH), (xo, yo))
    top = max(abs(float(c)) for c in det.coeffs())
    assert det.total_degree() <= 3
    assert all(abs(float(c)) <= 1e-12 * top for m, c in det.terms() if sum(m) == 3)
    assert max(abs(float(c)) for m, c in det.terms() if sum(m) == 2) > 1e-3 * top


def test_gough_stewart_type2_locus_against_the_plucker_determinant():
    mech = symkin.read_model(GOUGH)
    holds = ("velocity:O.z", "rotation:platform[x]", "rotation:platform[y]", "rotation:platform[z]")
    locus = implicit_loci(mech, ("velocity:O.x", "velocity:O.y"), hold=holds, kinds=("DKP-input",),
                          time_limit=600)["DKP-input"]
    det = plucker_type2(mech, (xo, yo))
    grid = np.array([(gx, gy) for gx in np.linspace(-0.75, 1.25, 9) for gy in np.linspace(-1, 1, 9)])
    g = sp.lambdify((xo, yo), det.as_expr())
    kept = [p for p in grid if abs(g(*p)) > 1e-9]

    def proportional(factor) -> bool:
        f = sp.lambdify((xo, yo), factor.polynomial)
        ratio = np.array([f(*p) / g(*p) for p in kept])
        return bool(np.allclose(ratio, ratio[0], rtol=1e-8))

    assert sum(proportional(f) for f in locus.factors) == 1  # one factor is the Plücker determinant
