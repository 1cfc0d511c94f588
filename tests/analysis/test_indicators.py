"""The one definition of the indicators against independent truth (closed forms, plain SVD)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symkin
from symkin.analysis import indicators
from symkin.model.catalogue import get
from symkin.numeric.linalg import independent_rows
from symkin.tolerances import Tolerances


def _perp(u):
    return np.array([-u[1], u[0]])


def _fourbar_closed_form(mech):
    """|DKP| of the four-bar from elementary kinematics (velocities of B and C, coupler rigid).

    ``v_B = ω1 ⊥AB``, ``v_C = ω3 ⊥DC`` and ``(v_C − v_B)·BC = 0`` give ``ω3/ω1``; the unit
    input / output rows restricted to the unit motion vector give ``a/|v|`` and ``|r| c/|v|``.
    """
    x = dict(mech.nodes)
    a_, b_, c_, d_ = (np.array(x[n], float) for n in "ABCD")
    ab, dc, bc = b_ - a_, c_ - d_, c_ - b_
    r = (_perp(ab) @ bc) / (_perp(dc) @ bc)
    a, c = np.linalg.norm(ab), np.linalg.norm(dc)
    norm = math.hypot(a, r * c)
    return a / norm, abs(r) * c / norm


@pytest.mark.parametrize("angle", np.linspace(0.0, 2 * np.pi, 13)[:-1])
def test_fourbar_dkp_values_match_the_closed_form(angle):
    ev = symkin.evaluators(get("fourbar_appendix"))
    mech = ev.mech
    x = dict(mech.nodes)
    # move the crank to ``angle`` (B on its circle) and close the loop for C by Newton
    a_, b_ = np.array(x["A"]), np.array(x["B"])
    rad = np.linalg.norm(b_ - a_)
    q = ev.q0.copy()
    q[:2] = a_ + rad * np.array([math.cos(angle), math.sin(angle)])
    q = ev.project(q)
    moved = ev.mechanism_at(q)
    a = symkin.analyze(moved)
    d_in, d_out = _fourbar_closed_form(moved)
    assert a.dof == 1
    assert abs(a.dkp_input) == pytest.approx(d_in, rel=1e-12)
    assert abs(a.dkp_output) == pytest.approx(d_out, rel=1e-12)


def test_dkp_value_is_the_signed_determinant_of_the_restricted_rows():
    """For k = F: ``det[J_S; P̂]/sqrt(det(J_S J_Sᵀ)) = ±det(P̂ V)`` with V from a plain SVD; |·| ≤ 1."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        js = rng.standard_normal((3, 5))
        p_hat = indicators.unit_rows(rng.standard_normal((2, 5)))[0]
        v = np.linalg.svd(js)[2][3:].T  # orthonormal null space of J_S
        sv = indicators.restricted_singular_values(p_hat, v)
        value = indicators.dkp_value(p_hat, sv, 2, js)
        assert abs(value) == pytest.approx(abs(np.linalg.det(p_hat @ v)), rel=1e-12)
        assert abs(value) == pytest.approx(np.prod(sv), rel=1e-12) and abs(value) <= 1 + 1e-12
        # without J_S (or k != F): the unsigned product of the singular values
        assert indicators.dkp_value(p_hat, sv, 2) == pytest.approx(abs(value), rel=1e-12)


def test_orientation_form_is_the_signed_determinant():
    """``det[J_S; P̂]/vol = sign det[J_S; Vᵀ] · det(P̂ V)`` for random J_S and both orientations of V."""
    rng = np.random.default_rng(11)
    for trial in range(40):
        js = rng.standard_normal((4, 7))
        p_hat = indicators.unit_rows(rng.standard_normal((3, 7)))[0]
        v = np.linalg.svd(js)[2][4:].T
        if trial % 2:
            v[:, 0] *= -1  # the other orientation of the same null space
        m = p_hat @ v
        sv = np.linalg.svd(m, compute_uv=False)
        o = indicators.basis_orientation(js, v)
        assert o in (-1.0, 1.0)
        by_det = indicators.dkp_value(p_hat, sv, 3, js)
        by_orientation = indicators.dkp_value(p_hat, sv, 3, js, restricted_matrix=m, orientation=o)
        assert by_orientation == pytest.approx(by_det, rel=1e-12)
        assert by_orientation == pytest.approx(o * np.linalg.det(m), rel=1e-12)


@pytest.mark.parametrize("name", ["fourbar_appendix", "rrr_3", "slider_crank", "five_bar", "rssr"])
def test_analyze_dkp_values_are_the_determinant_form(name):
    """``analyze`` (orientation form) against ``det[J_S; P̂]/sqrt(det(J_S J_Sᵀ))`` written out here."""
    ev = symkin.evaluators(get(name))
    rng = np.random.default_rng(5)
    q = ev.project(ev.q0 + 0.03 * ev.mech.length_scale * rng.standard_normal((6, ev.nf)))
    for x in q:
        mech = ev.mechanism_at(x)
        a = symkin.analyze(mech)
        jf = a.motion.J
        js = jf[list(indicators.basis_rows(jf, a.mobility, Tolerances()))]
        vol = math.sqrt(np.linalg.det(js @ js.T))
        for params, got in ((mech.inputs, a.dkp_input), (mech.outputs, a.dkp_output)):
            p_hat = a.motion.unit_rows(tuple(params))
            if p_hat.shape[0] != a.mobility:
                continue
            want = np.linalg.det(np.vstack([js, p_hat])) / vol
            assert got == pytest.approx(want, rel=1e-10, abs=1e-14)


def test_stacked_and_single_forms_are_the_same_definition():
    rng = np.random.default_rng(3)
    js = rng.standard_normal((6, 2, 4))
    p_hat = indicators.unit_rows(rng.standard_normal((6, 2, 4)))[0]
    v = np.linalg.svd(js)[2][:, 2:].transpose(0, 2, 1)
    sv = indicators.restricted_singular_values(p_hat, v)
    stacked = indicators.dkp_value(p_hat, sv, 2, js)
    single = [float(indicators.dkp_value(p_hat[k], sv[k], 2, js[k])) for k in range(6)]
    # one formula; a single configuration takes LAPACK's LU directly: equal to rounding
    np.testing.assert_allclose(stacked, single, rtol=1e-13, atol=0)


def test_im_indicator_is_the_eigenvalue_of_g_above_the_generic_zeros():
    mech = get("fourbar_appendix")
    lam = np.sort(np.linalg.eigvalsh(symkin.geometric_matrix(mech, reduced=True)))  # eq. 8
    assert symkin.analyze(mech).im_indicator == pytest.approx(lam[1], rel=1e-9)


def test_decisions_use_the_tolerance():
    tol = Tolerances()
    sv = np.array([[1.0, 0.5 * tol.rank], [1.0, 2 * tol.rank]])
    assert indicators.is_dkp(sv, 2, 2, tol).tolist() == [True, False]
    assert indicators.is_dkp(sv, 0, 2, tol).tolist() == [False, False]
    assert indicators.is_dkp(sv, 2, 2, Tolerances.of(1e-7)).tolist() == [True, True]
    s = np.array([2.0, 1.0, 1.5e-8])
    assert int(indicators.instantaneous_dof(s, indicators.rank_threshold(s, tol))) == 1
    assert int(indicators.instantaneous_dof(s, indicators.rank_threshold(s, Tolerances.of(1e-6)))) == 1
    assert int(indicators.instantaneous_dof(s, indicators.rank_threshold(s, Tolerances.of(1e-9)))) == 0


def test_independent_rows_rank_and_choice_are_scale_invariant():
    a = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0],
                  [0.0, 0.0, 5.0]])
    rows = independent_rows(a, 1e-8)
    assert len(rows) == 3 and np.linalg.matrix_rank(a[list(rows)]) == 3
    assert independent_rows(1e-6 * a, 1e-8) == rows  # relative: scale does not matter
    assert len(independent_rows(a, 1e-8, 2)) == 2
    assert indicators.basis_rows(a[:, :2], 1, Tolerances()) is not None
    # a row below the tolerance (relative to the largest) does not count
    assert independent_rows(np.array([[1.0, 0.0], [0.0, 1e-9]]), 1e-8) == (0,)


def test_analyze_takes_its_tolerance_one_way():
    flat_ish = get("fourbar_appendix")
    a1 = symkin.analyze(flat_ish, tol=1e-6)
    a2 = symkin.analyze(flat_ish, tol=Tolerances(rank=1e-6))
    assert a1.tolerance == a2.tolerance == 1e-6 and a1.to_dict() == a2.to_dict()
    with pytest.raises(TypeError):
        symkin.analyze(flat_ish, tolerances=Tolerances())
    with pytest.raises(TypeError):
        symkin.analyze(flat_ish, tol="1e-6")
    d = symkin.analyze(flat_ish).to_dict()
    assert isinstance(d["dkp_input"], float) and isinstance(d["dkp_output"], float)
    assert symkin.analyze(get("fourbar_flat")).to_dict()["dkp_input"] is None  # IM: not defined


@pytest.mark.parametrize("name", ["fourbar_appendix", "slider_crank", "rrr_3", "five_bar", "rssr"])
def test_dkp_values_are_invariant_under_scaling_and_translation(name):
    mech = get(name)
    a = symkin.analyze(mech)
    for moved in (mech.moved(scale=1000.0), mech.moved(translation=[3.0, -2.0, 1.0][: mech.dim], scale=0.01)):
        b = symkin.analyze(moved)
        for key in ("dkp_input", "dkp_output", "im_indicator"):
            assert getattr(b, key) == pytest.approx(getattr(a, key), rel=1e-10), key
