"""The position problem as one family of polynomial systems whose parameters are the prescribed values, and its path tracker.

**The family.**  The equations of :func:`symkin.solutions.system.position_system` with only
the prismatic legs reduced (:func:`~symkin.solutions.system.leg_reduced_equations`: a leg's bar
node is ``A + l (C − A) / ρ``, its equations become ``|C − A|² = ρ²``; the prescribed angles keep
their original form; no linear substitution, so their shape does not depend on the values, and no
sympy elimination per sample or query) have coefficients that are affine
functions of a few features of the values (a slide or a coordinate enters linearly, an angle
by its cosine and sine).  :meth:`ParameterFamily.build` samples the equations at the model's
configuration (all values 0) and at ``2F + 1`` random real values, and takes the affine span
of the coefficient vectors, ``C(λ) = C₀ + Σ λ_k C_k`` (``λ ∈ ℂ^r``, ``r`` the numerical rank):
every query lies in it (:meth:`ParameterFamily.parameters`), so the straight line between two
members stays in the family (coefficient-parameter homotopy).  ``F(u; λ) = C(λ) M(u)`` with
``M`` the monomials; an overconstrained family is squared up by one fixed random complex
matrix ``A`` (``n × m``), and every endpoint is checked on the original equations (the bar
nodes recovered).  The Jacobian ``C ∂M/∂u`` is a sparse product (:meth:`ParameterFamily.pencil`:
each equation has a few monomials, each monomial at most its degree of factors); the general
6-6 Gough–Stewart's family has 21 unknowns and 21 equations (39 and 45 before the legs' reduction).

**The tracker** (:func:`track_parameters`): all paths at once (numpy, complex), from ``λ₀``
to ``λ₁`` along ``λ(t) = λ₀ + τ(t)(λ₁ − λ₀)`` with the γ-trick ``τ = γt / (1 + (γ − 1)t)``
(``γ`` random on the unit circle: the path avoids the discriminant for all ``t < 1`` with
probability one).  Predictor: RK4 on ``du/dt = −H_u⁻¹ H_t``; corrector: the one corrector,
:func:`symkin.curves.corrector.gauss_newton_batch` on the real form of the complex system
(:func:`~symkin.curves.corrector.real_form_batch`), at most ``CORRECTOR_ITERATIONS``
steps; step control: a step is accepted when the corrector converges (the step grows by
``GROW``), else halved; a path whose step falls below ``MIN_STEP``, that takes more than
``max_steps`` steps (a path crawling past a near-singular point), or whose coordinates exceed
``DIVERGED`` fails.  No endgame: the endpoints at ``t = 1`` are refined by Newton on the
original equations by the caller, and those that do not converge are counted as failed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symkin.curves.corrector import gauss_newton_batch, real_form_batch
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.tolerances import Tolerances

__all__ = ["ParameterFamily", "Tracked", "track_parameters"]

#: first step and largest step of the tracker (fractions of the path's parameter t ∈ [0, 1])
FIRST_STEP = 0.02
MAX_STEP = 0.1
#: a path whose step falls below this has failed (a near-singular point on the path)
MIN_STEP = 1e-9
#: steps (accepted or not) after which a path is given up
MAX_STEPS = 3000
#: growth of an accepted step, and the corrector's steps per predicted point
GROW = 1.6
CORRECTOR_ITERATIONS = 3
#: a path whose coordinates (dimensionless) exceed this has gone to infinity
DIVERGED = 1e6
#: corrector tolerance along the path (max-norm of H, dimensionless)
PATH_TOL = 1e-9
#: relative rank cut of the span of the sampled coefficient vectors, and the largest relative
#: distance of a query's coefficients from that span
SPAN_RANK = 1e-9


@dataclass(frozen=True)
class Tracked:
    """Endpoints of :func:`track_parameters`: ``u`` (P, n) complex, ``ok`` (P,) whether the path reached t = 1.

    ``steps`` is the number of batch iterations, ``tries`` (P,) the steps of each path.
    """

    u: np.ndarray
    ok: np.ndarray
    steps: int
    tries: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class ParameterFamily:
    """``F(u; λ) = A (C₀ + Σ λ_k C_k) M(u)``: the original position equations as a linear family (module docstring).

    Attributes
    ----------
    labels : tuple of str
        The prescribed labels (their order is the order of the values).
    exponents : ndarray
        (K, n) exponents of the monomials ``M``.
    base : ndarray
        (m, K) coefficients ``C₀`` (the model's configuration, all values 0).
    basis : ndarray
        (r, m·K) orthonormal directions of the span (``C_k`` flattened).
    mix : ndarray
        (n, m) complex squaring-up matrix (the identity when ``m = n``).
    start : ndarray
        (n,) the model's configuration (dimensionless ``u``): a solution at ``λ = 0``.
    pattern : ndarray or None
        (m, K) bool, the monomials each equation can have (nonzero in some sample); None: the
        nonzeros of ``base`` and ``basis``.
    kept : ndarray or None
        Indices of the family's unknowns among the position system's (the prismatic legs'
        bars are eliminated: :func:`symkin.solutions.system.leg_reduced_equations`).
    """

    labels: tuple
    exponents: np.ndarray
    base: np.ndarray
    basis: np.ndarray
    mix: np.ndarray
    start: np.ndarray
    pattern: np.ndarray | None = None
    kept: np.ndarray | None = None

    @classmethod
    def build(cls, mech: Mechanism, labels, tol: Tolerances, seed: int = 0) -> "ParameterFamily":
        """Sample the original equations at the model and at ``2F + 1`` random values; their affine span."""
        import sympy as sp

        from symkin.solutions.system import leg_reduced_equations, prescribed_coordinates

        from symkin.solutions.system import SystemBuilder

        rng = np.random.default_rng(seed)
        labels = tuple(labels)
        kinds = [c.kind for c, _ in prescribed_coordinates(mech, {k: 0.0 for k in labels})]
        scale = float(mech.length_scale)
        samples = [np.zeros(len(labels))]
        for _ in range(2 * len(labels) + 1):
            samples.append(np.array([rng.uniform(-1.0, 1.0) * (1.0 if k == "angle" else 0.2 * scale)
                                     for k in kinds]))
        # the equations with the prismatic legs reduced (their shape does not depend on the values)
        systems = [leg_reduced_equations(mech, dict(zip(labels, map(float, q))), "rad", tol) for q in samples]
        full = _symbols_of(mech)
        kept = list(systems[0][0])
        unknowns = [full[k] for k in kept]
        owners = [o for o, _ in systems[0][1]]
        if any([o for o, _ in s[1]] != owners or list(s[0]) != kept for s in systems):
            raise SymkinError(f"{mech.name}: the position equations change shape with the values; "
                              "no parameter homotopy")
        polys = [[sp.Poly(e, *unknowns).as_dict() for _, e in s[1]] for s in systems]
        monomials = sorted({m for p in polys for eq in p for m in eq})
        index = {m: k for k, m in enumerate(monomials)}
        coeffs = np.zeros((len(samples), len(owners), len(monomials)))
        for j, p in enumerate(polys):
            for i, eq in enumerate(p):
                for m, c in eq.items():
                    coeffs[j, i, index[m]] = float(c)
        base = coeffs[0]
        diff = (coeffs[1:] - base).reshape(len(samples) - 1, -1)
        _, s, vt = np.linalg.svd(diff, full_matrices=False)
        rank = int(np.sum(s > SPAN_RANK * max(float(s[0]) if s.size else 0.0, 1e-300)))
        n, m = len(unknowns), len(owners)
        if m > n:
            mix = rng.standard_normal((n, m)) + 1j * rng.standard_normal((n, m))
        else:
            mix = np.eye(n, dtype=complex)
        b = SystemBuilder(mech, tol)
        start = _model_u(mech, b.center, b.scale)[kept]
        return cls(labels, np.array(monomials, int).reshape(len(monomials), n), base, vt[:rank], mix, start,
                   np.any(coeffs != 0, axis=0), np.array(kept, int))

    @property
    def rank(self) -> int:
        """Number of parameters ``r``."""
        return int(self.basis.shape[0])

    def to_arrays(self) -> dict:
        """The arrays that define the family (for :func:`numpy.savez`)."""
        return {"exponents": self.exponents, "base": self.base, "basis": self.basis, "mix": self.mix,
                "start": self.start, "labels": np.array(self.labels), "pattern": self.support,
                "kept": np.arange(self.start.size) if self.kept is None else self.kept}

    @classmethod
    def from_arrays(cls, data) -> "ParameterFamily":
        """Inverse of :meth:`to_arrays`."""
        return cls(tuple(str(x) for x in data["labels"]), data["exponents"], data["base"], data["basis"],
                   data["mix"], data["start"], data["pattern"], data["kept"])

    @property
    def support(self) -> np.ndarray:
        """(m, K) bool: :attr:`pattern`, or the nonzeros of ``base`` and ``basis``."""
        if self.pattern is not None:
            return np.asarray(self.pattern, bool)
        return (self.base != 0) | np.any(self.basis.reshape((-1,) + self.base.shape) != 0, axis=0)

    def pencil(self, c0: np.ndarray, cd: np.ndarray):
        """Evaluator of the squared-up ``H(u, τ) = A (c0 + τ cd) M(u)`` at many points: ``(u (P, n), τ (P,))`` →
        ``(H (P, n), H_u (P, n, n), ∂H/∂τ (P, n))``.

        The Jacobian of the original equations is a sparse product (each equation has few
        monomials, each monomial few factors) before the squaring-up matrix ``A``.
        """
        import scipy.sparse as sps

        f = self.factors
        n = self.exponents.shape[1]
        kk, dd = np.nonzero(f < n)
        var = f[kk, dd]
        support = self.support
        m = support.shape[0]
        c0 = np.where(support, c0, 0)
        cd = np.where(support, cd, 0)
        # one column per true factor l (monomial kk[l], position dd[l]); row (i, var[l]) for each equation i that has it
        ii, ll = np.nonzero(support[:, kk])
        rows = ii * n + var[ll]

        def sparse(c):
            return sps.csr_matrix((c[ii, kk[ll]].astype(complex), (rows, ll)), shape=(m * n, kk.size))

        s0, sd = sparse(c0), sparse(cd)
        mix = None if (self.mix.shape[0] == m and np.array_equal(self.mix, np.eye(m))) else self.mix

        def evaluate(u, tau):
            mono, others = self.products(u)
            v = others[:, kk, dd].T  # (L, P)
            p = u.shape[0]
            j0 = np.asarray(s0 @ v).T.reshape(p, m, n)
            jd = np.asarray(sd @ v).T.reshape(p, m, n)
            hd = mono @ cd.T
            h = mono @ c0.T + tau[:, None] * hd
            hu = j0 + tau[:, None, None] * jd
            if mix is not None:
                return h @ mix.T, mix @ hu, hd @ mix.T
            return h, hu, hd

        return evaluate

    def coefficient_matrix(self, equations, unknowns) -> np.ndarray | None:
        """The (m, K) coefficients of a query's original equations on the family's monomials (None: other monomials)."""
        if len(equations) != self.base.shape[0]:
            return None
        return self.coefficient_rows(equations, unknowns)

    def coefficient_rows(self, equations, unknowns) -> np.ndarray | None:
        """The coefficients of some ``(owner, expr)`` equations on the family's monomials, one row each (None:
        other monomials); :meth:`coefficient_matrix` of all of them."""
        import sympy as sp

        c = np.zeros((len(equations), self.base.shape[1]), dtype=self.base.dtype)
        index = {tuple(int(v) for v in m): k for k, m in enumerate(self.exponents)}
        for i, (_, e) in enumerate(equations):
            for m, v in sp.Poly(e, *unknowns).as_dict().items():
                if m not in index:
                    return None
                c[i, index[m]] = float(v)
        return c

    def parameters(self, equations, unknowns) -> tuple[np.ndarray, float]:
        """``λ`` of a query's original equations and their relative distance from the family (0 when in it)."""
        c = self.coefficient_matrix(equations, unknowns)
        if c is None:
            return np.zeros(self.rank), np.inf
        return self.parameters_of(c)

    def parameters_of(self, c: np.ndarray) -> tuple[np.ndarray, float]:
        """``λ`` of the coefficients ``c`` (m, K) and their relative distance from the family."""
        d = (c - self.base).ravel()
        lam = self.basis @ d
        off = float(np.linalg.norm(d - lam @ self.basis)) / max(float(np.linalg.norm(c)), 1e-300)
        return lam, off

    def coefficients(self, lam: np.ndarray) -> np.ndarray:
        """``C(λ)`` (m, K), complex."""
        return self.base + (np.asarray(lam) @ self.basis).reshape(self.base.shape)

    @property
    def factors(self) -> np.ndarray:
        """(K, D) the unknowns multiplied in each monomial, repeated by their exponents (``n`` pads: the factor 1)."""
        cached = self.__dict__.get("_factors")
        if cached is None:
            e = np.asarray(self.exponents, int)
            n = e.shape[1]
            depth = max(1, int(e.sum(axis=1).max(initial=0)))
            cached = np.full((e.shape[0], depth), n, int)
            for k, row in enumerate(e):
                f = np.repeat(np.arange(n), row)
                cached[k, :f.size] = f
            self.__dict__["_factors"] = cached
        return cached

    def products(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``M(u)`` (P, K) and, for each factor of each monomial, the product of the others (P, K, D)."""
        f = self.factors
        p = u.shape[0]
        ext = np.concatenate([np.asarray(u, complex), np.ones((p, 1), complex)], axis=1)
        vals = ext[:, f]  # (P, K, D)
        depth = f.shape[1]
        if depth == 1:
            others = np.ones_like(vals)
        else:
            others = np.stack([np.prod(np.delete(vals, d, axis=2), axis=2) for d in range(depth)], axis=2)
        return vals[:, :, 0] * others[:, :, 0], others

    def monomials(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``M(u)`` (P, K) and ``∂M/∂u`` (P, K, n) at the rows of ``u`` (P, n): products of factors, product rule."""
        f = self.factors
        p, n = u.shape
        ext = np.concatenate([np.asarray(u, complex), np.ones((p, 1), complex)], axis=1)
        vals = ext[:, f]  # (P, K, D)
        mono = np.prod(vals, axis=2)
        dm = np.zeros((p, f.shape[0], n + 1), complex)
        rows = np.arange(f.shape[0])
        depth = f.shape[1]
        for d in range(depth):
            others = np.prod(np.delete(vals, d, axis=2), axis=2) if depth > 1 else np.ones((p, f.shape[0]), complex)
            dm[:, rows, f[:, d]] += others
        return mono, dm[:, :, :n]

    def residual(self, u: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """Max-norm of the original (not squared-up) equations at the rows of ``u``."""
        mono, _ = self.products(u)
        return np.max(np.abs(mono @ self.coefficients(lam).T), axis=1)


def _symbols_of(mech: Mechanism) -> list:
    """The position system's unknowns (:class:`symkin.solutions.system.SystemBuilder`)."""
    from symkin.solutions.system import SystemBuilder

    return SystemBuilder(mech, Tolerances.of(None)).u


def _model_u(mech: Mechanism, center, scale) -> np.ndarray:
    """The model's configuration as the dimensionless free vector ``u``."""
    x = dict(mech.nodes)
    return np.concatenate([(np.array(x[n], float) - center) / scale for n in mech.free_nodes])


def track_parameters(family: ParameterFamily, u0: np.ndarray, lam0: np.ndarray, lam1: np.ndarray,
                     rng: np.random.Generator, progress=None, max_steps: int = MAX_STEPS) -> Tracked:
    """Track every row of ``u0`` (solutions at ``λ₀``) to ``λ₁`` (module docstring); ``progress(k)`` when k more paths end."""
    u = np.array(np.atleast_2d(u0), dtype=complex)
    p = u.shape[0]
    lam0, lam1 = np.asarray(lam0, complex), np.asarray(lam1, complex)
    gamma = np.exp(2j * np.pi * rng.uniform())
    dlam = (lam1 - lam0) @ family.basis
    dc = dlam.reshape(family.base.shape)

    def tau(t):
        return gamma * t / (1 + (gamma - 1) * t)

    # H = A (C(λ₀) + τ dC) M(u)
    pencil = family.pencil(family.coefficients(lam0), dc)

    def mixed(xs, tt):
        return pencil(xs, tau(tt))

    def velocity(x, t):
        # du/dt = −H_u⁻¹ H_t, with H_t = A dC M(u) τ'(t)
        _, hu, hd = mixed(x, t)
        dtau = gamma / (1 + (gamma - 1) * t) ** 2
        ht = hd * dtau[:, None]
        try:
            return -np.linalg.solve(hu, ht[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            return np.full_like(x, np.nan)

    t = np.zeros(p)
    h = np.full(p, FIRST_STEP)
    active = np.ones(p, bool)
    ok = np.zeros(p, bool)
    steps = 0
    tries = np.zeros(p, int)
    done_before = 0
    while np.any(active):
        steps += 1
        idx = np.flatnonzero(active)
        tries[idx] += 1
        x, tt = u[idx], t[idx]
        hh = np.minimum(h[idx], 1.0 - tt)
        k1 = velocity(x, tt)
        k2 = velocity(x + 0.5 * hh[:, None] * k1, tt + 0.5 * hh)
        k3 = velocity(x + 0.5 * hh[:, None] * k2, tt + 0.5 * hh)
        k4 = velocity(x + hh[:, None] * k3, tt + hh)
        pred = x + (hh[:, None] / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
        t_new = tt + hh
        finite = np.all(np.isfinite(pred), axis=1)
        pred[~finite] = x[~finite]

        def fun(xs, rows, t_at=t_new):
            return mixed(xs, t_at[rows])[:2]

        z0 = np.concatenate([pred.real, pred.imag], axis=1)
        corr = gauss_newton_batch(real_form_batch(fun), z0, tol=PATH_TOL, max_iterations=CORRECTOR_ITERATIONS,
                                  diverge_after=1)
        n = x.shape[1]
        good = corr.converged & finite
        z = corr.z[:, :n] + 1j * corr.z[:, n:]
        good &= np.max(np.abs(z - pred), axis=1) <= np.maximum(1.0, np.max(np.abs(x), axis=1)) * hh * 10
        u[idx[good]] = z[good]
        t[idx[good]] = t_new[good]
        h[idx[good]] = np.minimum(hh[good] * GROW, MAX_STEP)
        h[idx[~good]] = hh[~good] * 0.5
        big = np.max(np.abs(u[idx]), axis=1) > DIVERGED
        arrived = t[idx] >= 1.0
        ok[idx[arrived & ~big]] = True
        stop = arrived | big | (h[idx] < MIN_STEP) | (tries[idx] >= max_steps)
        active[idx[stop]] = False
        if progress is not None and int(np.sum(~active)) != done_before:
            progress(int(np.sum(~active)) - done_before)
            done_before = int(np.sum(~active))
    return Tracked(u, ok, steps, tries)
