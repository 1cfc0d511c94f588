"""Every singular configuration of a 1-DOF mechanism against elementary geometry (issue 9 §2).

The expected configurations are built here from the law of cosines (circle intersections),
independently of symkin: a four-bar's input is stationary where coupler and rocker are
collinear (B, C, D on a line), its output where crank and coupler are (A, B, C on a line),
and a change-point four-bar is IM where all four joints are on the ground line.  The
number of circuits follows Grashof's rule.
"""
from __future__ import annotations

import itertools
import json
import math
import sys

import numpy as np
import pytest

from symkin import Mechanism, SymkinError
from symkin.cli import main
from symkin.model import catalogue
from symkin.model.model_file import write_model
from tests.conftest import EXAMPLES

pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global] "
                                      "(pip install -e '.[global]')")

from symkin.solutions.circuits import singularities  # noqa: E402

TOL = 1e-9


def circle_points(p, r1, q, r2):
    """The intersections of the circles (p, r1) and (q, r2), none when they miss (law of cosines)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = float(np.linalg.norm(q - p))
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h2 = r1 * r1 - a * a
    if h2 < -1e-12:
        return []
    h = math.sqrt(max(h2, 0.0))
    e = (q - p) / d
    n = np.array([-e[1], e[0]])
    return [p + a * e + h * n, p + a * e - h * n] if h > 0 else [p + a * e]


def fourbar(g, a, b, c, phi_deg=60.0, name="four-bar"):
    """Ground A=(0,0)-D=(g,0), crank AB = a at phi, coupler BC = b, rocker DC = c."""
    phi = math.radians(phi_deg)
    B = np.array([a * math.cos(phi), a * math.sin(phi)])
    C = circle_points(B, b, (g, 0.0), c)[0]
    return Mechanism.from_dict({
        "name": name, "dim": 2, "fixed": ["A", "D"], "mobility": 1,
        "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "B": B.tolist(), "C": C.tolist(), "D": [g, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})


def collinear_configurations(g, a, b, c):
    """(kind, B, C) of every four-bar configuration with B, C, D or A, B, C collinear (law of cosines)."""
    A, D = np.zeros(2), np.array([g, 0.0])
    out = []
    for r in {b + c, abs(b - c)}:  # coupler and rocker collinear: |BD| = r
        for B in circle_points(A, a, D, r):
            u = (D - B) / np.linalg.norm(D - B)
            C = B + b * u if (r == b + c or b > c) else B - b * u
            out.append(("DKP-input", B, C))
    for r in {a + b, abs(a - b)}:  # crank and coupler collinear: |AC| = r
        for C in circle_points(A, r, D, c):
            u = C / np.linalg.norm(C)
            B = a * u if (r == a + b or a > b) else -a * u
            out.append(("DKP-output", B, C))
    return out


def flat_configurations(g, a, b, c):
    """Every configuration with the four joints on the ground line (IM of a change-point four-bar)."""
    out = []
    for sb, sc in itertools.product((1, -1), repeat=2):
        B, C = np.array([sb * a, 0.0]), np.array([g + sc * c, 0.0])
        if abs(np.linalg.norm(C - B) - b) <= 1e-12:
            out.append(("IM", B, C))
    return out


def wrap(v):
    return math.remainder(v, 2 * math.pi)


def assert_singular_set(result, expected, mech, input_of):
    """Each expected (kind, free coordinates) reported once with that type and its DOF, and nothing else."""
    scale = mech.length_scale
    got = [(s, np.concatenate([s.configuration[n] for n in mech.free_nodes])) for s in result.singularities]
    assert len(got) == len(expected), ([s.types for s, _ in got], [k for k, _ in expected])
    for kind, q in expected:
        dist = [float(np.max(np.abs(g - q))) for _, g in got]
        k = int(np.argmin(dist))
        s = got[k][0]
        assert dist[k] <= TOL * scale, (kind, q, dist[k])
        assert kind in s.types
        assert s.dof == (2 if kind == "IM" else 1)
        assert abs(wrap(s.input - input_of(q))) <= TOL
    assert result.agree


def crank_input(mech):
    """Crank angle measured from the model's configuration, at free coordinates (B, C)."""
    b0 = np.array(mech.coordinates()["B"])
    return lambda q: math.atan2(q[1], q[0]) - math.atan2(b0[1], b0[0])


GRASHOF = {  # name: (g, a, b, c), circuits by Grashof's rule (s + l < p + q: 2; > : 1)
    "crank_rocker": ((4.0, 1.0, 3.0, 3.5), 2),   # shortest link the crank
    "double_crank": ((1.0, 3.0, 3.5, 4.0), 2),   # shortest link the ground (drag link)
    "double_rocker": ((4.0, 3.0, 1.0, 3.5), 2),  # shortest link the coupler
    "triple_rocker": ((4.0, 2.0, 3.0, 2.5), 1),  # non-Grashof: s + l = 6 > p + q = 5.5
}


@pytest.fixture(scope="module")
def results():
    cache = {}

    def get(name):
        if name not in cache:
            (g, a, b, c), _ = GRASHOF[name]
            m = fourbar(g, a, b, c, name=name)
            cache[name] = (m, singularities(m))
        return cache[name]
    return get


def test_grashof_rule_matches_the_lengths():
    for (g, a, b, c), n in GRASHOF.values():
        s, l, p, q = sorted((g, a, b, c))[0], max(g, a, b, c), *sorted((g, a, b, c))[1:3]
        assert (s + l < p + q) == (n == 2)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(GRASHOF))
def test_fourbar_circuits_and_singularities_law_of_cosines(results, name):
    (g, a, b, c), circuits = GRASHOF[name]
    m, r = results(name)
    assert len(r.circuits) == circuits
    assert all(c_.closed for c_ in r.circuits)
    expected = [(k, np.concatenate([B, C])) for k, B, C in collinear_configurations(g, a, b, c)]
    assert_singular_set(r, expected, m, crank_input(m))
    # the cross-check saw the same configurations: both counts reported
    by_kind = {ch.kind: ch for ch in r.checks}
    assert by_kind["DKP-input"].homotopy == by_kind["DKP-input"].traced == \
        sum(k == "DKP-input" for k, _ in expected)
    assert by_kind["DKP-output"].homotopy == by_kind["DKP-output"].traced == \
        sum(k == "DKP-output" for k, _ in expected)


@pytest.mark.slow
def test_fourbar_crank_of_a_crank_rocker_turns_fully_on_both_circuits(results):
    m, r = results("crank_rocker")
    assert [c.full_turn for c in r.circuits] == [True, True]
    # the two circuits are the two assembly modes: at the seed input, one solve_all solution on each
    assert r.seeds == 2
    # the ground line A-D is the x axis: the mirror image of a circuit is the other circuit
    def mirrored(s):
        return np.concatenate([[q[0], -q[1]] for q in (s.configuration["B"], s.configuration["C"])])
    one = [s for s in r.singularities if s.circuit == 1]
    two = [np.concatenate([s.configuration["B"], s.configuration["C"]]) for s in r.singularities if s.circuit == 2]
    assert len(one) == len(two) == 2
    for s in one:
        assert min(float(np.max(np.abs(mirrored(s) - q))) for q in two) <= TOL


@pytest.mark.slow
def test_double_rocker_input_oscillates_between_its_dkp_input_limits(results):
    m, r = results("double_rocker")
    for c in r.circuits:
        assert not c.full_turn
        limits = sorted(s.input for s in r.singularities if s.circuit == c.index and "DKP-input" in s.types)
        lo, hi = (float(f(b.inputs)) for f in (np.min, np.max) for b in c.branches[:1])
        assert len(limits) == 2
        # the traced input never goes beyond its two turning points (to the located accuracy)
        assert limits[0] - 1e-9 <= lo and hi <= limits[1] + 1e-9


@pytest.mark.slow
def test_change_point_fourbar_one_circuit_through_the_flat_im_configuration():
    g, a, b, c = 4.0, 1.0, 3.0, 2.0  # s + l = 1 + 4 = p + q = 3 + 2: Grashof's boundary
    m = fourbar(g, a, b, c, name="change point")
    r = singularities(m)
    flat = flat_configurations(g, a, b, c)
    assert len(flat) == 1
    flat_q = [np.concatenate([B, C]) for _, B, C in flat]

    def is_flat(B, C):
        return any(float(np.max(np.abs(np.concatenate([B, C]) - q))) <= 1e-12 for q in flat_q)
    expected = [(k, np.concatenate([B, C])) for k, B, C in collinear_configurations(g, a, b, c) if not is_flat(B, C)]
    expected += [("IM", q) for q in flat_q]
    assert_singular_set(r, expected, m, crank_input(m))
    # the two assembly modes meet at the IM configuration: one circuit (a connected component),
    # its branch turns the crank twice (once in each mode) and crosses itself there
    assert len(r.circuits) == 1
    (branch,) = r.circuits[0].branches
    assert branch.closed and float(np.ptp(branch.inputs)) >= 4 * math.pi - 1e-6
    im = [s for s in r.singularities if "IM" in s.types]
    assert len(im) == 1 and im[0].dof == 2 and abs(wrap(im[0].input - crank_input(m)(flat_q[0]))) <= TOL


# ---------------------------------------------------------------- Watt six-bar
def _rigid(p0, q0, r0, p, q):
    """Where r0 goes when the rigid body (p0, q0, r0) is moved so that p0 → p, q0 → q (planar)."""
    a0 = math.atan2(*(np.subtract(q0, p0)[::-1]))
    a = math.atan2(*(np.subtract(q, p)[::-1]))
    c, s = math.cos(a - a0), math.sin(a - a0)
    d = np.subtract(r0, p0)
    return np.asarray(p) + np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])


def watt_expected():
    """Every DKP configuration of the catalogue's Watt II six-bar by elementary geometry.

    Loop 1 A-B-C-D, rigid rocker D-C-E, loop 2 D-E-G-F.  The crank is stationary where B, C, D
    are collinear (loop 1's limit) or E, G, F are (loop 2 stops the rocker); the output F-G
    where A, B, C are (the rocker stops) or D, E, G are (loop 2's limit).
    """
    x = {n: np.array(v) for n, v in catalogue.get("watt_sixbar").coordinates().items()}
    L = {k: float(np.linalg.norm(x[k[0]] - x[k[1]])) for k in ("AB", "BC", "DC", "DE", "EG", "FG")}
    A, D, F = x["A"], x["D"], x["F"]
    out = []

    def on_line(p, q, length, towards=True):
        u = (q - p) / np.linalg.norm(q - p)
        return p + (length if towards else -length) * u

    def finish_from_c(kind, B, C):
        E = _rigid(x["D"], x["C"], x["E"], D, C)
        for G in circle_points(E, L["EG"], F, L["FG"]):
            out.append((kind, np.concatenate([B, C, E, G])))

    def finish_from_e(kind, E, G):
        C = _rigid(x["D"], x["E"], x["C"], D, E)
        for B in circle_points(A, L["AB"], C, L["BC"]):
            out.append((kind, np.concatenate([B, C, E, G])))

    b, c = L["BC"], L["DC"]
    for r in {b + c, abs(b - c)}:                       # B, C, D collinear
        for B in circle_points(A, L["AB"], D, r):
            finish_from_c("DKP-input", B, on_line(B, D, b, r == b + c or b > c))
    e, g = L["EG"], L["FG"]
    for r in {e + g, abs(e - g)}:                       # E, G, F collinear
        for E in circle_points(D, L["DE"], F, r):
            finish_from_e("DKP-input", E, on_line(E, F, e, r == e + g or e > g))
    a = L["AB"]
    for r in {a + b, abs(a - b)}:                       # A, B, C collinear
        for C in circle_points(A, r, D, c):
            finish_from_c("DKP-output", on_line(A, C, a, r == a + b or a > b), C)
    d = L["DE"]
    for r in {d + e, abs(d - e)}:                       # D, E, G collinear
        for G in circle_points(D, r, F, g):
            E = on_line(D, G, d, r == d + e or d > e)
            finish_from_e("DKP-output", E, G)
    return out


@pytest.mark.slow
def test_watt_sixbar_every_dkp_configuration_by_elementary_geometry():
    m = catalogue.get("watt_sixbar")
    r = singularities(m)
    expected = watt_expected()
    assert {k for k, _ in expected} == {"DKP-input", "DKP-output"}
    assert_singular_set(r, expected, m, crank_input(m))
    assert len(r.circuits) >= 1 and all(c.closed for c in r.circuits)
    by_kind = {ch.kind: ch for ch in r.checks}
    assert by_kind["DKP-input"].homotopy == sum(k == "DKP-input" for k, _ in expected)
    assert by_kind["DKP-output"].homotopy == sum(k == "DKP-output" for k, _ in expected)
    # the rocker D-C-E stops where A, B, C are collinear (DKP-output) and where E, G, F are (DKP-input):
    # its LIM system finds those 2 + 2 again, merged with them (no new configuration)
    lim = by_kind["LIM"]
    assert lim.name == "LIM:rocker" and lim.homotopy == lim.matched == 4 and lim.agree is True
    assert sum("rocker" in s.locked_links and "LIM" in s.types for s in r.singularities) == 4


# ---------------------------------------------------------------- errors and the command line
def test_not_one_dof_is_a_clear_error():
    with pytest.raises(SymkinError, match="1-DOF mechanism.*F = 2"):
        singularities(catalogue.get("five_bar"))


def test_not_one_dof_exit_code_2(tmp_path, capsys):
    from symkin.model.model_file import write_model

    path = tmp_path / "five.toml"
    write_model(catalogue.get("five_bar"), path)
    assert main(["singularities", str(path)]) == 2
    err = capsys.readouterr().err
    assert "1-DOF" in err and "Traceback" not in err and str(path) in err


def test_without_the_solver_the_error_names_the_extra(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "bertini", None)  # import bertini raises ImportError
    with pytest.raises(SymkinError, match=r"symkin\[global\]"):
        singularities(catalogue.get("fourbar_appendix"))
    assert main(["singularities", str(EXAMPLES / "fourbar_appendix.toml")]) == 2
    err = capsys.readouterr().err
    assert "global" in err and "Traceback" not in err


@pytest.mark.slow
def test_cli_json_contract_and_plot(tmp_path, capsys):
    png = tmp_path / "circuits.png"
    assert main(["singularities", str(EXAMPLES / "fourbar_appendix.toml"), "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["circuits"] == 2
    assert len(out["singularities"]) == 4
    for s in out["singularities"]:
        assert set(s) >= {"configuration", "types", "circuit", "input"}
        assert s["types"][0] == "DKP-output" and s["circuit"] in (1, 2)
        assert -180.0 < s["input"] <= 180.0  # degrees by default
    assert out["agree"] is True
    assert [c["homotopy"] for c in out["cross_check"]] == [0, 4]
    assert png.stat().st_size > 10_000


@pytest.mark.slow
def test_millimetres_and_metres_give_the_same_answer():
    m = catalogue.get("fourbar_appendix")
    mm = Mechanism.from_dict({**m.to_dict(), "nodes": {n: [1000.0 * v for v in c] for n, c in m.nodes}})
    a, b = singularities(m), singularities(mm)
    assert len(a.circuits) == len(b.circuits) == 2
    assert [s.types for s in a.singularities] == [s.types for s in b.singularities]
    assert np.allclose([s.input for s in a.singularities], [s.input for s in b.singularities], atol=1e-9)


@pytest.mark.slow
def test_a_disagreement_is_a_field_and_a_warning(monkeypatch):
    import symkin.solutions.circuits as circuits

    real = circuits._real_roots

    def one_more(system, tol):  # a root that no traced circuit passes through
        found, paths = real(system, tol)
        fake = {n: list(x) for n, x in system.closure.mechanism.coordinates().items()}
        return found + [fake], paths

    monkeypatch.setattr(circuits, "_real_roots", one_more)
    with pytest.warns(circuits.SingularitiesWarning, match="only by the homotopy"):
        r = singularities(catalogue.get("fourbar_appendix"))
    assert r.agree is False and r.to_dict()["agree"] is False
    for ch in r.checks:
        assert ch.homotopy == ch.traced + 1 and len(ch.unmatched_homotopy) == 1 and not ch.unmatched_traced
    assert any("only by the homotopy" in w for w in r.warnings)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["double_rocker", "triple_rocker"])
def test_without_the_square_systems_the_rounds_find_every_circuit(name, capsys, tmp_path, monkeypatch):
    """max_paths = 0 and no msolve: no square system is solved; seeds in rounds between the traced critical values.

    The double rocker's second circuit (its mirror image) lies in a crank range that holds
    no seed at the model's input: only the second round reaches it.  The answer is the law
    of cosines' all the same; the cross-checks say they were skipped, ``agree`` is None.
    """
    from symkin.solutions.circuits import SingularitiesWarning

    import symkin.solutions.exact as exact

    monkeypatch.setattr(exact, "msolve_executable", lambda: None)
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path / "cache"))
    (g, a, b, c), circuits = GRASHOF[name]
    m = fourbar(g, a, b, c, name=name)
    with pytest.warns(SingularitiesWarning, match="NOT cross-checked"):
        r = singularities(m, max_paths=0)
    # the rounds' repeated solve_all calls are parameter homotopies from start solutions made once
    assert len(list((tmp_path / "cache" / "parameter-homotopy").glob("*.npz"))) == 1
    assert len(r.circuits) == circuits and all(c_.closed for c_ in r.circuits)
    expected = [(k, np.concatenate([B, C])) for k, B, C in collinear_configurations(g, a, b, c)]
    got = [np.concatenate([s.configuration[n] for n in m.free_nodes]) for s in r.singularities]
    assert len(got) == len(expected)
    for kind, q in expected:
        k = int(np.argmin([float(np.max(np.abs(g_ - q))) for g_ in got]))
        assert float(np.max(np.abs(got[k] - q))) <= TOL * m.length_scale and kind in r.singularities[k].types
    assert r.agree is None and all(ch.agree is None and ch.skipped.startswith(f"{ch.paths} paths > max_paths = 0")
                                   and "msolve is not installed" in ch.skipped for ch in r.checks)
    assert len(r.samples) >= (2 if name == "double_rocker" else 1)
    assert main(["singularities", "--max-paths", "0", "--json", str(write_model(m, tmp_path / "m.json"))]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["agree"] is None and out["circuits"] == circuits
    assert all(ch["skipped"] for ch in out["cross_check"])


@pytest.mark.slow
def test_samples_replace_the_default_seeds(capsys, tmp_path):
    """--samples: solve_all only there (with the square systems: and the critical points); bad values exit 2."""
    m = catalogue.get("fourbar_appendix")
    seen: list[str] = []
    r = singularities(m, unit="deg", samples=[10.0, 200.0], progress=seen.append)
    assert [round(v, 9) for v in r.to_dict()["samples"]] == [10.0, -160.0]
    assert seen[:2] == ["square DKP-input system", "square DKP-output system"]
    assert "solve_all at rotation:crank = 10°" in seen and "solve_all at rotation:crank = -160°" in seen
    assert sum(w.startswith("trace ") for w in seen) == sum(len(c.branches) for c in r.circuits)
    assert len(r.circuits) == 2 and r.agree is True
    path = str(write_model(m, tmp_path / "m.json"))
    with pytest.raises(SystemExit) as exit_:
        main(["singularities", path, "--samples", "10,x"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--samples" in err and "not a comma-separated list of numbers" in err and "Traceback" not in err


@pytest.mark.slow
def test_beyond_max_paths_msolve_solves_the_square_systems_exactly():
    """max_paths = 0 with msolve: the exact systems give the Watt six-bar's DKP configurations, and they agree."""
    from symkin.solutions.exact import msolve_executable

    if msolve_executable() is None:
        pytest.skip("msolve is the optional extra symkin[exact] (pip install -e '.[exact]')")
    m = catalogue.get("watt_sixbar")
    r = singularities(m, max_paths=0)
    expected = watt_expected()
    assert_singular_set(r, expected, m, crank_input(m))
    assert [ch.name for ch in r.checks] == ["DKP-input", "DKP-output", "LIM:rocker"]  # the rocker D-C-E's LIM system
    assert [ch.solver for ch in r.checks] == ["msolve", "msolve", "msolve"] and r.agree is True
    by_kind = {ch.kind: ch for ch in r.checks}
    for kind in ("DKP-input", "DKP-output"):
        ch = by_kind[kind]
        assert ch.homotopy == ch.matched == ch.traced == sum(k == kind for k, _ in expected) and not ch.skipped
