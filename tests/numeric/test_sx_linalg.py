"""The SX linear-algebra kernels against NumPy: random, ill-conditioned, clustered, exact zeros.

Every kernel is wrapped in a ``casadi.Function`` of symbolic matrix entries (as the
indicator kernel is) and evaluated numerically; the reference is ``numpy.linalg``.
"""
from __future__ import annotations

from functools import lru_cache

import casadi as ca
import numpy as np
import pytest

from symkin.numeric import sx_linalg as L

EPS = np.finfo(float).eps


def _rng(seed: int) -> np.random.Generator:
    return np.random.default_rng(seed)


def _symmetric_with(eigenvalues, rng) -> np.ndarray:
    n = len(eigenvalues)
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    a = q @ np.diag(eigenvalues) @ q.T
    return (a + a.T) / 2


@lru_cache(maxsize=None)
def _tridiagonal_function(n: int):
    a = ca.SX.sym("a", n, n)
    diag, off = L.householder_tridiagonal(a)
    return ca.Function("tri", [a], [ca.vertcat(*diag), ca.vertcat(*off) if off else ca.SX(0, 1)])


def _tridiagonal(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    d, e = _tridiagonal_function(a.shape[0])(a)
    return np.array(d).ravel(), np.array(e).ravel()


def _tri_matrix(d, e) -> np.ndarray:
    return np.diag(d) + np.diag(e, 1) + np.diag(e, -1)


@lru_cache(maxsize=None)
def _eigen_function(n: int, kernel: str, r0: int = 0):
    """(diag, off) → (value, certificate) of :func:`smallest_eigenvalue` or :func:`eigenvalue_above`."""
    d = ca.SX.sym("d", n)
    e = ca.SX.sym("e", max(n - 1, 0))
    diag, off = [d[i] for i in range(n)], [e[i] for i in range(n - 1)]
    out = L.smallest_eigenvalue(diag, off) if kernel == "smallest" else L.eigenvalue_above(diag, off, r0)
    return ca.Function(kernel, [d, e], list(out))


def _eigen(a: np.ndarray, kernel: str = "smallest", r0: int = 0) -> tuple[float, float]:
    d, e = _tridiagonal(a)
    value, ok = _eigen_function(a.shape[0], kernel, r0)(d, e)
    return float(value), float(ok)


# ---------------------------------------------------------------------- Givens QR
def _qr(a: np.ndarray, m: int, zeros=()):
    """givens_qr of ``a`` with the entries ``zeros`` structurally zero; returns R-part, Q."""
    n, c = a.shape
    s = ca.SX.sym("a", n, c)
    cols = [[ca.SX(0) if (i, j) in zeros else s[i, j] for j in range(c)] for i in range(n)]
    out, rotations = L.givens_qr(cols, m)
    q = [[ca.SX(1.0 if i == j else 0.0) for j in range(n)] for i in range(n)]
    for k, i, cc, ss in rotations:  # accumulate Qᵀ = G_N ... G_1
        for j in range(n):
            qk, qi = q[k][j], q[i][j]
            q[k][j] = cc * qk + ss * qi
            q[i][j] = cc * qi - ss * qk
    f = ca.Function("qr", [s], [ca.vertcat(*[ca.horzcat(*row) for row in out]),
                               ca.vertcat(*[ca.horzcat(*row) for row in q])])
    r, qt = (np.array(v) for v in f(a))
    return r, qt.T, len(rotations)


@pytest.mark.parametrize("shape", [(4, 3, 3), (12, 9, 15), (6, 5, 5), (3, 1, 2)])
def test_givens_qr_is_an_orthogonal_triangularisation(shape):
    n, m, c = shape
    rng = _rng(n * 100 + c)
    a = rng.standard_normal((n, c))
    zeros = {(i, j) for i in range(n) for j in range(c) if rng.random() < 0.4}
    for i, j in zeros:
        a[i, j] = 0.0
    r, q, _ = _qr(a, m, zeros)
    np.testing.assert_allclose(q.T @ q, np.eye(n), atol=1e-14)
    assert np.linalg.det(q) == pytest.approx(1.0, abs=1e-13)  # rotations only
    np.testing.assert_allclose(q @ r, a, atol=1e-14 * np.abs(a).max() * n)
    assert np.all(np.tril(r[:, :m], -1) == 0.0)  # exact zeros below the diagonal
    ref = np.linalg.qr(a[:, :m], mode="r")
    np.testing.assert_allclose(np.abs(np.diag(r[:m, :m])), np.abs(np.diag(ref)), rtol=1e-12, atol=1e-14)
    if np.any(a[1:, 0] != 0):  # rotations in column 0 leave its norm on the diagonal
        assert r[0, 0] == pytest.approx(np.linalg.norm(a[:, 0]), rel=1e-15)


def test_givens_qr_skips_structural_zeros_and_handles_a_zero_column():
    a = np.array([[1.0, 0.0, 2.0], [0.0, 0.0, 1.0], [3.0, 0.0, 0.0]])
    zeros = {(1, 0), (0, 1), (1, 1), (2, 1)}  # the middle column is structurally zero
    r, q, count = _qr(a, 3, zeros)
    assert count == 1  # (0, 2) in column 0; none for the zero (1, 0) nor the zero column 1
    np.testing.assert_allclose(q @ r, a, atol=1e-15)
    np.testing.assert_allclose(np.abs(np.diag(r)), np.abs(np.diag(np.linalg.qr(a, mode="r"))), atol=1e-15)


def test_givens_qr_of_numerically_zero_entries_is_the_identity_rotation():
    s = ca.SX.sym("a", 2, 1)
    out, rotations = L.givens_qr([[s[0]], [s[1]]], 1)
    f = ca.Function("g", [s], [out[0][0], rotations[0][2], rotations[0][3]])
    r, c, sn = (float(v) for v in f(np.zeros(2)))
    assert (r, c, sn) == (0.0, 1.0, 0.0)


# ---------------------------------------------------------------------- tridiagonal form
CASES = {
    "random": lambda rng, n: (lambda b: (b + b.T) / 2)(rng.standard_normal((n, n))),
    "spd ill-conditioned": lambda rng, n: _symmetric_with(np.logspace(-10, 0, n), rng),
    "double cluster": lambda rng, n: _symmetric_with([1.0, 1.0] + list(np.linspace(2, 5, n - 2)), rng),
    "near-double cluster": lambda rng, n: _symmetric_with([1.0, 1.0 + 1e-7] + list(np.linspace(2, 5, n - 2)), rng),
    "sparse with exact zeros": lambda rng, n: (lambda b: b + b.T)(np.triu(rng.standard_normal((n, n))
                                                                       * (rng.random((n, n)) < 0.3))),
    "psd rank-deficient": lambda rng, n: (lambda j: j @ j.T)(rng.standard_normal((n, n - 2))),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("n", [1, 2, 3, 5, 9])
def test_tridiagonal_form_keeps_the_eigenvalues(case, n):
    rng = _rng(n)
    if case == "psd rank-deficient" and n < 3:
        pytest.skip("needs n >= 3")
    a = CASES[case](rng, n) if n > 1 else np.array([[2.5]])
    d, e = _tridiagonal(a)
    scale = np.linalg.norm(a, 2)
    np.testing.assert_allclose(np.linalg.eigvalsh(_tri_matrix(d, e)), np.linalg.eigvalsh(a),
                               rtol=0, atol=20 * n * EPS * scale)
    assert d.sum() == pytest.approx(np.trace(a), abs=20 * n * EPS * scale)


# ---------------------------------------------------------------------- polynomial and counts
@lru_cache(maxsize=None)
def _poly_function(n: int, which: str):
    d, e2, x = ca.SX.sym("d", n), ca.SX.sym("e2", n - 1), ca.SX.sym("x")
    diag, off2 = [d[i] for i in range(n)], [e2[i] for i in range(n - 1)]
    out = L.charpoly(diag, off2, x) if which == "charpoly" else (L.sturm_count(diag, off2, x),)
    return ca.Function(which, [d, e2, x], list(out))


def test_charpoly_and_its_derivatives_equal_numpy():
    rng = _rng(7)
    n = 7
    d, e = rng.standard_normal(n), rng.standard_normal(n - 1)
    coeffs = np.poly(np.linalg.eigvalsh(_tri_matrix(d, e)))  # monic: det(xI - T) = (-1)^n det(T - xI)
    f = _poly_function(n, "charpoly")
    for x in rng.uniform(-3, 3, 20):
        p, dp, ddp = (float(v) for v in f(d, e * e, x))
        sign = (-1) ** n
        assert p == pytest.approx(sign * np.polyval(coeffs, x), rel=1e-10, abs=1e-10)
        assert dp == pytest.approx(sign * np.polyval(np.polyder(coeffs), x), rel=1e-10, abs=1e-10)
        assert ddp == pytest.approx(sign * np.polyval(np.polyder(coeffs, 2), x), rel=1e-10, abs=1e-10)
        assert p == pytest.approx(np.linalg.det(_tri_matrix(d, e) - x * np.eye(n)), rel=1e-10, abs=1e-10)


@pytest.mark.parametrize("case", ["random", "double cluster", "sparse with exact zeros"])
def test_sturm_count_is_the_number_of_eigenvalues_below(case):
    rng = _rng(11)
    n = 9
    d, e = _tridiagonal(CASES[case](rng, n))
    lam = np.linalg.eigvalsh(_tri_matrix(d, e))
    f = _poly_function(n, "sturm")
    points = list(rng.uniform(lam[0] - 1, lam[-1] + 1, 40)) + list(lam[:-1] + 1e-6) + list(lam[1:] - 1e-6)
    for x in points:
        if np.min(np.abs(lam - x)) < 1e-9:
            continue  # a point on an eigenvalue: no count is meaningful there
        assert float(f(d, e * e, x)) == np.sum(lam < x)


def test_laguerre_step_from_below_never_passes_the_smallest_root():
    rng = _rng(5)
    n = 9
    d, e = _tridiagonal(CASES["double cluster"](rng, n) + 0.3 * np.diag(rng.random(n)))
    lam = np.linalg.eigvalsh(_tri_matrix(d, e))
    x = ca.SX.sym("x")
    step = ca.Function("s", [x], L.laguerre_steps(list(d), list(e * e), x, (1,), +1))
    point = lam[0] - 10.0
    for _ in range(8):
        new = float(step(point))
        assert point <= new <= lam[0] * (1 + 1e-15) + 1e-15
        point = new
    assert point == pytest.approx(lam[0], rel=1e-13)


# ---------------------------------------------------------------------- certified eigenvalues
SPECTRA = {
    "well separated": [0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0],
    "exact double": [0.8, 0.8, 0.96, 1.02, 1.02, 1.3, 2.7, 2.7, 3.7],  # the symmetric 3-RRR
    "near double 1e-3": [0.8, 0.8008, 0.96, 1.02, 1.021, 1.3, 2.7, 2.71, 3.7],
    "near double 1e-8": [0.8, 0.8 + 8e-9, 0.96, 1.02, 1.02, 1.3, 2.7, 2.7, 3.7],
    "triple": [1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0],
    "ill-conditioned": list(np.logspace(-3, 0, 9)),
    "all equal": [1.0] * 9,
}


#: spectra a kernel may leave uncertified (then the batch's SVD path decides): a triple
#: eigenvalue, and for the r0 = 0 kernel a pair closer than its iterations resolve
HARD = {("triple", "smallest"), ("triple", "above"), ("near double 1e-8", "smallest")}


@pytest.mark.parametrize("kernel", ["smallest", "above"])
@pytest.mark.parametrize("spectrum", list(SPECTRA))
def test_certified_smallest_eigenvalue_equals_numpy(spectrum, kernel):
    lam = np.array(SPECTRA[spectrum])
    for seed in range(5):
        a = _symmetric_with(lam, _rng(seed))
        ref = np.linalg.eigvalsh(a)[0]
        value, ok = _eigen(a, kernel)
        if (spectrum, kernel) in HARD and not ok:
            continue
        assert ok == 1.0, (spectrum, seed)
        # the certificate bounds the eigenvalue of the computed tridiagonal form, whose
        # distance to a's is a rounding error of the reduction (of order eps·‖a‖)
        assert abs(value - ref) <= 1e-12 * ref + 40 * EPS * lam.max(), (spectrum, seed)


def test_smallest_eigenvalue_of_random_gram_matrices():
    rng = _rng(3)
    resolvable = certified = 0
    for trial in range(300):
        m = int(rng.integers(2, 10))
        j = rng.standard_normal((m, m + int(rng.integers(0, 4))))
        a = j @ j.T
        ref = np.linalg.eigvalsh(a)[0]
        value, ok = _eigen(a)
        if ref >= 1e-3 * np.trace(a):  # well above what rounding hides
            resolvable += 1
            certified += int(ok)
        if ok:
            assert abs(value - ref) <= 1e-12 * ref + 40 * EPS * np.trace(a), trial
            assert ref >= 2 * L.ROUNDING * EPS / 1e-12 * np.trace(a) * 0.999, trial
    assert resolvable >= 200 and certified >= resolvable - 2


@pytest.mark.parametrize("kernel", ["smallest", "above"])
def test_an_eigenvalue_below_the_rounding_of_the_reduction_is_not_certified(kernel):
    """λ_1 = 1e-8·‖A‖: Sturm counts on T may succeed, but T is A only to ε‖A‖."""
    for seed in range(5):
        a = _symmetric_with(np.logspace(-8, 0, 9), _rng(seed))
        value, ok = _eigen(a, kernel)
        assert ok == 0.0
        assert value == pytest.approx(1e-8, rel=1e-6)  # still the best estimate


@pytest.mark.parametrize("kernel", ["smallest", "above"])
def test_certificate_does_not_claim_what_rounding_cannot_show(kernel):
    """Exactly singular and nearly singular Gram matrices: certified only when right."""
    for tiny in (0.0, 1e-30, 1e-20, 1e-14, 1e-10, 1e-6):
        for seed in range(5):
            lam = np.array([tiny, 0.5, 1.0, 1.5, 2.0, 2.5])
            a = _symmetric_with(lam, _rng(100 * seed + 1))
            value, ok = _eigen(a, kernel)
            ref = np.linalg.eigvalsh(a)[0]
            if ok:
                # rounding of the reduction is of order eps·‖a‖: nothing smaller is claimed
                assert abs(value - ref) <= 1e-12 * abs(ref) + 40 * EPS * 2.5, (tiny, seed)
                assert tiny >= 1e-6, (tiny, seed, value)


def test_eigenvalue_above_divides_out_the_structural_zeros():
    """λ_{r0+1} of J Jᵀ with r0 redundant rows (a rank-deficient J)."""
    rng = _rng(21)
    for r0 in (1, 2, 3):
        for seed in range(10):
            m = 8
            base = rng.standard_normal((m - r0, 11))
            mix = rng.standard_normal((r0, m - r0))
            j = np.vstack([base, mix @ base])  # r0 rows combinations of the others
            a = j @ j.T
            lam = np.linalg.eigvalsh(a)
            value, ok = _eigen(a, "above", r0)
            assert ok == 1.0, (r0, seed)
            assert abs(value - lam[r0]) <= 1e-12 * lam[r0] + 40 * EPS * lam[-1], (r0, seed)


# ---------------------------------------------------------------------- determinant
@pytest.mark.parametrize("n", [0, 1, 2, 3, 4, 5])
def test_det_equals_numpy(n):
    rng = _rng(n)
    a = rng.standard_normal((n, n))
    s = ca.SX.sym("a", n, n)
    value = float(ca.Function("det", [s], [L.det(s)])(a)) if n else float(ca.evalf(L.det(s)))
    assert value == pytest.approx(np.linalg.det(a) if n else 1.0, rel=1e-12)
