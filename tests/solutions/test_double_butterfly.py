"""The double butterfly of ``papers_examples/`` in ``symkin singularities`` (issue 9 §2, its last truth case).

Independent truth (no symkin continuation, no homotopy):

* an enumeration of the real assembly modes at a crank angle θ by elementary geometry and a
  scipy root search: V1 = P2 + |P2V1| (cos θ, sin θ); the coupler turns about V1 by β, which
  places C and V2; Q2 is where the wing's circle about O meets link3's circle about V2 (two
  choices), the wing's rotation then places Q1; U2 is where the circles about C and Q1 meet (two
  choices), the upper triangle then places U1; a mode is a root in β of ``|U1 − P1|² − l1²``.
  (Not U1 first: U1 is the midpoint of P1–C at S, where those two circles are tangent.)
  The crank's turning points (DKP-input) are where two modes merge: the folds of the mode count,
  solved as ``g = ∂g/∂β = 0`` (∂g/∂β by the complex step, so the fold is located to rounding);
* the contact points T1, T2 with the LIM branch by the construction of README_paths.md (crank
  along P2→P1 and P1→P2, C = Q2 = P2).

* the square system "closure + DKP-input determinant = 0" solved exactly by msolve (the extra
  ``symkin[exact]``; 768 homotopy paths are beyond ``max_paths``): its 18 real solutions are the
  traced configurations, and the enumeration's.

Without msolve the run seeds solve_all on a grid of 6 crank angles 60° apart (``--samples``; the
oval circuit's crank range is 64° wide) instead of the default rounds between traced critical
values (25 solve_all calls, minutes), and the cross-check is reported skipped.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

from symkin.cli import main
from symkin.model.model_file import read_model
from symkin.solutions.exact import msolve_executable
from tests.conftest import EXAMPLES

pytest.importorskip("bertini", reason="the homotopy solver is the optional extra symkin[global] "
                                      "(pip install -e '.[global]')")

MODEL = EXAMPLES / "double_butterfly.toml"


# ---------------------------------------------------------------- the independent enumeration
class Butterfly:
    """The model's geometry (node coordinates of its configuration S) and its modes at a crank angle."""

    def __init__(self, mech):
        x = {n: np.array(c, float) for n, c in mech.coordinates().items()}
        self.x = x
        self.l_crank = np.linalg.norm(x["V1"] - x["P2"])
        self.l3 = np.linalg.norm(x["V2"] - x["Q2"])
        self.l1 = np.linalg.norm(x["U1"] - x["P1"])
        self.l2 = np.linalg.norm(x["U2"] - x["Q1"])
        self.r_wing = np.linalg.norm(x["Q2"] - x["O"])
        self.r_cu2 = np.linalg.norm(x["U2"] - x["C"])
        self.theta_s = math.atan2(*(x["V1"] - x["P2"])[::-1])

    @staticmethod
    def _rot(c, s, v):
        return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    @staticmethod
    def _meet(p, r1, q, r2, sign):
        """A meeting point of the circles (p, r1), (q, r2) (complex-analytic; NaN where they miss)."""
        d = q - p
        dd = d[0] * d[0] + d[1] * d[1]
        a = (r1 * r1 - r2 * r2 + dd) / (2 * dd)
        h2 = r1 * r1 / dd - a * a
        h = np.sqrt(h2) if np.iscomplexobj(h2) else np.sqrt(np.where(h2 >= 0, h2, np.nan))
        h = np.squeeze(h) if np.ndim(h) > 1 else h
        return p + a * d + sign * h * np.array([-d[1], d[0]])

    def g(self, theta, beta, s1, s2):
        """|U1 − P1|² − l1² at crank angle θ, coupler angle β (turn from S about V1), choices s1, s2."""
        with np.errstate(invalid="ignore", divide="ignore"):  # NaN where two circles miss: by design
            return self.nodes(theta, beta, s1, s2)["residual"]

    def nodes(self, theta, beta, s1, s2):
        """The free nodes placed from (θ, β, s1, s2), and the residual of link1 (see the module docstring)."""
        shape = (2,) + (1,) * np.ndim(beta)
        x = {n: v.reshape(shape) for n, v in self.x.items()}
        v1 = x["P2"] + self.l_crank * np.array([np.cos(theta), np.sin(theta)]).reshape(shape)
        cb, sb = np.cos(beta), np.sin(beta)
        c = v1 + self._rot(cb, sb, x["C"] - x["V1"])
        v2 = v1 + self._rot(cb, sb, x["V2"] - x["V1"])
        q2 = self._meet(x["O"], self.r_wing, v2, self.l3, s1)
        q20 = x["Q2"] - x["O"]
        cw = (q2[0] * q20[0] + q2[1] * q20[1]) / self.r_wing ** 2
        sw = (q20[0] * q2[1] - q20[1] * q2[0]) / self.r_wing ** 2
        q1 = x["O"] + self._rot(cw, sw, x["Q1"] - x["O"])
        u2 = self._meet(c, self.r_cu2, q1, self.l2, s2)
        e, e0 = u2 - c, x["U2"] - x["C"]
        cu = (e[0] * e0[0] + e[1] * e0[1]) / self.r_cu2 ** 2
        su = (e0[0] * e[1] - e0[1] * e[0]) / self.r_cu2 ** 2
        u1 = c + self._rot(cu, su, x["U1"] - x["C"])
        d = u1 - x["P1"]
        return {"V1": v1, "C": c, "V2": v2, "Q2": q2, "Q1": q1, "U2": u2, "U1": u1,
                "residual": d[0] * d[0] + d[1] * d[1] - self.l1 ** 2}

    @staticmethod
    def _grid(grid=7200):
        # a closed grid (the last cell wraps round) offset from β = 0 so that S is not a grid point
        return np.linspace(-math.pi, math.pi, grid + 1) + math.sqrt(0.5) * 2 * math.pi / grid

    def _brackets(self, theta, s1, s2):
        beta = self._grid()
        g = self.g(theta, beta, s1, s2)
        return beta, np.nonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] < 0))[0]

    def count(self, theta):
        """The number of real modes at crank angle θ (sign changes of g on the β grid)."""
        return sum(len(self._brackets(theta, s1, s2)[1]) for s1 in (1, -1) for s2 in (1, -1))

    def modes(self, theta):
        """Every real mode (β, s1, s2) at crank angle θ: sign changes of g on a β grid, refined by brentq."""
        out = []
        for s1 in (1, -1):
            for s2 in (1, -1):
                beta, cells = self._brackets(theta, s1, s2)
                for k in cells:
                    b = brentq(lambda b: self.g(theta, b, s1, s2), beta[k], beta[k + 1], xtol=1e-15)
                    out.append((math.remainder(b, 2 * math.pi), s1, s2))
        return out

    def fold(self, theta, beta, s1, s2):
        """The crank's turning point near (θ, β): g = 0 and ∂g/∂β = 0 (complex step), by fsolve."""
        def eqs(z):
            t, b = z
            db = self.g(t, b + 1e-30j, s1, s2).imag / 1e-30
            return [self.g(t, b, s1, s2), db]
        z, info, _, _ = fsolve(eqs, [theta, beta], xtol=1e-14, full_output=True)
        # accepted on its residuals (g is a squared length, 10² here), whatever fsolve's progress flag says
        return (float(z[0]), float(z[1])) if max(abs(v) for v in eqs(z)) < 1e-9 else None

    def turning_points(self, step_deg=0.25):
        """Crank angles (radians, absolute) of every turning point: changes of the mode count, then fold()."""
        thetas = np.radians(np.arange(-180.0, 180.0 + step_deg, step_deg))
        step = math.radians(step_deg)
        counts = [self.count(t) for t in thetas]
        found = []
        for k in range(len(thetas) - 1):
            if counts[k] == counts[k + 1]:
                continue
            # Newton on the fold system from every mode on both sides and from the midpoints of
            # neighbouring modes of one branch (the merging pair may straddle a change of branch)
            # (the bracket is subdivided 10 times: near a fold the pair is close to it in θ)
            lo, hi = thetas[k] - step, thetas[k + 1] + step
            needed, before = abs(counts[k + 1] - counts[k]) // 2, len(found)  # a fold changes the count by 2
            for t in np.linspace(thetas[k], thetas[k + 1], 11):
                if len(found) - before >= needed:
                    break
                here = self.modes(t)
                starts = list(here)
                for branch in {(s1, s2) for _, s1, s2 in here}:
                    betas = sorted(b for b, *sb in here if tuple(sb) == branch)
                    starts += [(0.5 * (b1 + b2), *branch) for b1, b2 in zip(betas, betas[1:])]
                for b0, s1, s2 in starts:
                    z = self.fold(t, b0, s1, s2)
                    if z is not None and lo <= z[0] <= hi and \
                            all(abs(math.remainder(z[0] - f, 2 * math.pi)) > 1e-9 for f in found):
                        found.append(z[0])
        return sorted(math.remainder(f, 2 * math.pi) for f in found)


def wrap_deg(v):
    return math.remainder(v, 360.0)


# ---------------------------------------------------------------- one CLI run
GRID = ",".join(str(v) for v in range(0, 360, 60))   # finer than the narrowest circuit's crank range (64°)


EXACT = msolve_executable() is not None


@pytest.fixture(scope="module")
def cli_json():
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["singularities", str(MODEL), "--json"] + ([] if EXACT else ["--samples", GRID]))
    assert code == 0
    return json.loads(buf.getvalue())


@pytest.fixture(scope="module")
def butterfly():
    return Butterfly(read_model(MODEL))


@pytest.fixture(scope="module")
def turning(butterfly):
    return butterfly.turning_points()


@pytest.mark.slow
def test_enumeration_is_sound_at_the_model_configuration(butterfly):
    """The root search finds S itself (β = 0) among the modes at S's crank angle, and g vanishes there."""
    modes = butterfly.modes(butterfly.theta_s)
    assert min(abs(b) for b, _, _ in modes) <= 1e-12
    assert len(modes) == 10  # = solve_all's real count at the model's input (README: 10 real, 6 complex)


@pytest.mark.slow
def test_every_dkp_input_configuration_against_the_independent_enumeration(cli_json, butterfly, turning):
    """Every crank turning point of the enumeration is reported once, DKP-input with L = 1, to 1e-9 degrees."""
    got = [s for s in cli_json["singularities"] if "DKP-input" in s["types"]]
    expected = sorted(wrap_deg(math.degrees(t - butterfly.theta_s)) for t in turning)
    assert len(expected) == 16
    assert len(got) == len(expected), ([round(s["input"], 6) for s in got], [round(e, 6) for e in expected])
    for e in expected:
        s = min(got, key=lambda s: abs(wrap_deg(s["input"] - e)))
        assert abs(wrap_deg(s["input"] - e)) <= 1e-9, (s["input"], e)
        assert s["dof"] == 1 and s["types"] == ["DKP-input", "LIM"]
    # at each one the crank's own angle (atan2 of the reported configuration) is the reported input
    for s in got:
        v1, p2 = np.array(s["configuration"]["V1"]), np.array(s["configuration"]["P2"])
        assert abs(wrap_deg(math.degrees(math.atan2(*(v1 - p2)[::-1]) - butterfly.theta_s) - s["input"])) <= 1e-9


@pytest.mark.slow
def test_the_two_tangent_contacts_with_the_lim_branch_exactly(cli_json, butterfly):
    """T1 and T2 (README_paths.md): IM, L = 2, C = Q2 = P2, each reported once and located to rounding."""
    x = butterfly.x
    along = math.atan2(*(x["P1"] - x["P2"])[::-1])
    t_inputs = sorted(wrap_deg(math.degrees(a - butterfly.theta_s)) for a in (along, along + math.pi))
    assert [round(t, 4) for t in t_inputs] == [-163.7398, 16.2602]
    im = sorted((s for s in cli_json["singularities"] if "IM" in s["types"]), key=lambda s: s["input"])
    assert len(im) == 2
    scale = max(np.ptp(np.array(list(x.values())), axis=0))
    for s, t in zip(im, t_inputs):
        assert s["types"] == ["IM"] and s["dof"] == 2
        # located by deflation (symkin.curves.locate), not by the trace's minimum of σ₂ (~1e-3°)
        assert abs(wrap_deg(s["input"] - t)) <= 1e-9
        for n in ("C", "Q2"):
            assert np.linalg.norm(np.array(s["configuration"][n]) - x["P2"]) <= 1e-12 * scale
        for n in ("Q1", "Q2"):  # the wing lies on the ground triangle
            assert np.linalg.norm(np.array(s["configuration"][n]) - x[n]) <= 1e-12 * scale
        # four half-branches leave each contact: the two traced loops and the LIM branch pass through it
        assert len(s["branches"]) >= 2
    # nothing else but the traced LIM events (a link that stops while the rest moves, L = 1): every
    # singular configuration is a turning point, a contact or a LIM
    lim = [s for s in cli_json["singularities"] if s["types"] == ["LIM"]]
    assert all(s["dof"] == 1 and s["locked_links"] and "LIM" in s["kinds"] for s in lim)
    assert len(cli_json["singularities"]) == len(im) + len(lim) + sum("DKP-input" in s["types"]
                                                                      for s in cli_json["singularities"])


@pytest.mark.slow
def test_circuits_and_the_cross_check_report(cli_json, turning, butterfly):
    """Two circuits: the one through T1 and T2 (with the LIM branch), and an oval apart from it.

    The oval's four turning points are the enumeration's 64.38°, 107.63°, 122.98°, 128.11°: its crank
    range lies beyond the model's input (0), so only a seed at another input value finds it.
    """
    assert cli_json["circuits"] == 2
    for s in cli_json["singularities"]:
        assert set(s) >= {"configuration", "types", "circuit", "input"}
        assert s["circuit"] in (1, 2)
    im_circuits = {s["circuit"] for s in cli_json["singularities"] if "IM" in s["types"]}
    assert len(im_circuits) == 1
    oval = [s for s in cli_json["singularities"] if s["circuit"] not in im_circuits]
    turning_oval = [s for s in oval if "DKP-input" in s["types"]]
    assert len(turning_oval) == 4 and all(s["types"] == ["DKP-input", "LIM"] for s in turning_oval)
    assert all(s["types"] == ["LIM"] and s["locked_links"] for s in oval if s not in turning_oval)
    enumerated = [wrap_deg(math.degrees(t - butterfly.theta_s)) for t in turning]
    for s in turning_oval:
        assert min(abs(wrap_deg(s["input"] - e)) for e in enumerated) <= 1e-9
    assert 0.0 < min(s["input"] for s in oval)  # the oval's crank range excludes the model's input 0
    check, *lim = cli_json["cross_check"]
    assert check["kind"] == "DKP-input" and check["paths"] == 768 and check["traced"] == 18
    # the wing and link1 are locked along the whole LIM branch: their LIM systems are not zero-dimensional
    # (msolve says so) or beyond max_paths: not solved, so the traced LIM events are not cross-checked
    assert [c["name"] for c in lim] == ["LIM:wing", "LIM:link1"] and all(c["skipped"] for c in lim)
    assert all(c["agree"] is None for c in lim) and cli_json["agree"] is None
    if EXACT:  # solved exactly: the same 18 configurations, each matched
        assert check["solver"] == "msolve" and not check["skipped"]
        assert check["homotopy"] == check["matched"] == 18 and check["agree"] is True
        assert all("not zero-dimensional" in c["skipped"] for c in lim)
        assert len(cli_json["samples"]) == 1, cli_json["samples"]
        assert all("did not close" in w or "LIM) are NOT cross-checked" in w for w in cli_json["warnings"]), \
            cli_json["warnings"]
    else:
        assert check["skipped"] and check["agree"] is None and cli_json["agree"] is None
        assert any("NOT cross-checked" in w for w in cli_json["warnings"])
        assert all("NOT cross-checked" in w or "did not close" in w for w in cli_json["warnings"])
        assert [round(v, 9) for v in cli_json["samples"]] == [wrap_deg(v) for v in range(0, 360, 60)]
    # a branch closes, or ends where it comes back to a tangent contact it had passed (the LIM branch,
    # round and round); one that passes a contact unseen (no IM event between two points) may go on
    # to its turn limit instead: it is reported, and the half-branches of the contacts are traced anyway
    branches = [b for c in cli_json["circuit_list"] for b in c["branches"]]
    assert any(b["stop_reason"] == "returned" for b in branches)
    for b in branches:
        assert b["closed"] or any(f"branch {b['branch']} " in w and "did not close" in w for w in cli_json["warnings"])


@pytest.mark.slow
def test_without_msolve_the_default_rounds_give_the_same_answer(monkeypatch, tmp_path, butterfly, turning):
    """No msolve, default seeds: rounds of solve_all (parameter homotopies from one set of start solutions)."""
    import warnings

    import symkin.solutions.exact as exact
    from symkin.solutions.circuits import singularities

    monkeypatch.setattr(exact, "msolve_executable", lambda: None)
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = singularities(read_model(MODEL), unit="deg")
    got = [s for s in r.to_dict()["singularities"] if "DKP-input" in s["types"]]
    expected = sorted(wrap_deg(math.degrees(t - butterfly.theta_s)) for t in turning)
    assert len(r.circuits) == 2 and len(got) == len(expected) == 16
    for e in expected:
        assert min(abs(wrap_deg(s["input"] - e)) for s in got) <= 1e-9
    assert sum("IM" in s.types for s in r.singularities) == 2  # the tangent contacts T1, T2
    assert r.agree is None and len(r.samples) > 6
    assert len(list((tmp_path / "parameter-homotopy").glob("*.npz"))) == 1
