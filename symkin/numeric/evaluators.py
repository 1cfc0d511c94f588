"""Named CasADi Functions of a mechanism: G, J, closure residual, parameter rows, indicators.

:func:`evaluators` turns a :class:`~symkin.model.mechanism.Mechanism` into CasADi
``Function`` objects of the free nodal coordinates ``q`` (free nodes in node order,
``x, y[, z]`` each; :attr:`Evaluators.q_labels` names them).  The expressions are built
directly in CasADi ``SX`` by :mod:`symkin.numeric.casadi_model`, row by row as the numeric
core builds its matrices, so the three sides (sympy, NumPy core, CasADi) can be compared.

Functions (``ev.functions[name]``, also attributes), inputs → outputs:

``G``                ``q`` → ``G`` (nf×nf, reduced: free coordinates, the matrix of eq. 8),
                     ``G_full`` (D×D, the assembled matrix of eq. 3 / A5)
``J``                ``q`` → ``J`` (m×D constraint rows, ``G = JᵀJ``), ``J_free`` (m×nf)
``closure``          ``q, p`` → ``phi`` (m): position residual, one row per row of ``J``
``closure_jacobian`` ``q, p`` → ``phi``, ``dphi_dq`` (m×nf); ``dphi_dq = J_free`` where ``phi = 0``
``parameters``       ``q`` → ``inputs``, ``outputs``, ``platform`` (rows over all D coordinates,
                     physical units, as :func:`symkin.numeric.geometric_matrix.parameter_rows`)
``indicators``       ``q`` → ``im``, ``im_certified``, ``trace``, ``dkp_input``,
                     ``dkp_input_bound``, ``dkp_output``, ``dkp_output_bound`` (scalars)
``indicators_batch`` the same for :data:`BATCH` configurations (columns of ``q``; rows of
                     the outputs), evaluated in a loop inside the generated C
``motion``           ``q`` → ``V`` (nf×F): orthonormal basis of the motion space (eq. 9) when L = F

``p`` holds the closure parameters (bar lengths, slider offsets, affine coordinates in
degenerate bodies; :attr:`Evaluators.p_labels`), by default the model's (:attr:`Evaluators.p0`).

The indicators exist when the ``m_e`` constraint rows that touch free coordinates
(``J_e``) reach rank ``nf - F`` at a generic configuration (:attr:`Evaluators.fast`);
``r0 = m_e - (nf - F)`` of them are then redundant (bodies of 4+ nodes, degenerate bodies)
and ``nf - F`` independent ones (``J_S``, :attr:`Evaluators.basis_rows`) are chosen once:

* ``im`` — the IM indicator ``λ_{F+1}`` of the reduced G (§IV-A, Fig. 3, Fig. 10): the
  eigenvalue ``λ_{r0+1}`` of ``A = J_e J_eᵀ``, whose nonzero eigenvalues are those of
  ``G = J_eᵀ J_e``.  It is computed by Householder tridiagonalisation of ``A`` and
  Laguerre iterations on its characteristic polynomial, safeguarded by Sturm counts;
  ``im_certified = 1`` when Sturm counts prove ``λ_{F+1}`` lies within a relative
  1e-12 of ``im``.
* ``trace`` — ``tr(A) = ‖J_free‖_F²`` (bounds ``λ_max``: ``tr/m ≤ λ_max ≤ tr``).
* ``dkp_input`` / ``dkp_output`` — for ``k = F`` unit-normalised parameter rows ``P̂``
  (eq. 12, 16): ``det([J_S; P̂]) / sqrt(det(J_S J_Sᵀ))``, dimensionless and signed, equal to
  ``±det(P̂ V)`` for an orthonormal basis ``V`` of the motion space, i.e. ± the product of
  the singular values of the restricted matrix whose rank the core tests.  It vanishes
  exactly at the DKP configurations (away from IM, where it is not defined).  For
  ``k ≠ F`` it is that product of the ``min(k, F)`` singular values (unsigned).
* ``dkp_*_bound`` — a lower bound on the smallest squared singular value of ``P̂ V``
  (``det / tr^{s-1}`` of its ``s×s`` Gram matrix), used to decide DKP safely; 0 when
  the rows ``J_S`` lose rank (then ``V`` is not the motion space).

``V`` (Function ``motion``) and the DKP values come from a QR factorisation of
``[J_Sᵀ | P̂ᵀ]`` by Givens rotations (which skip the structural zeros of ``J``).

:mod:`symkin.numeric.mapping` evaluates the Functions over many configurations.  These are
numbers only: the indicators' one definition and the IM / DKP decisions live in the analysis
stage (:mod:`symkin.analysis.indicators`); ``symkin.evaluators(mech)`` returns the
deciding subclass :class:`symkin.analysis.batch.Evaluators`, whose ``batch`` and
``indicators_at`` decide exactly as :func:`symkin.analyze` does, and the tests keep the
kernel above equal to that definition.  :meth:`Evaluators.compile` generates and loads C
code (see :mod:`symkin.numeric.codegen`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from symkin.model.mechanism import Mechanism
from symkin.numeric.casadi_model import CasadiModel, build
from symkin.numeric.linalg import independent_rows
from symkin.tolerances import DEFAULT, Tolerances

__all__ = ["Evaluators", "evaluators", "INDICATOR_NAMES", "FUNCTION_NAMES"]

#: outputs of the ``indicators`` Function, in order
INDICATOR_NAMES = ("im", "im_certified", "trace", "dkp_input", "dkp_input_bound",
                   "dkp_output", "dkp_output_bound")
#: the named Functions of every :class:`Evaluators`
FUNCTION_NAMES = ("G", "J", "closure", "closure_jacobian", "parameters", "indicators",
                  "indicators_batch", "motion")
#: Functions of the indicator kernel: built with the others, or on first use (``kernel=False``)
KERNEL_FUNCTIONS = ("indicators", "indicators_batch", "motion")
#: configurations per call of ``indicators_batch``
BATCH = 1024

#: iterations of the eigenvalue kernel (Laguerre with multiplicity-2 trial steps, then plain)
_PHASE1, _PHASE2 = 4, 3
#: relative width of the Sturm certificate of ``im``
_CERT = 1e-12


# ---------------------------------------------------------------------- SX linear algebra
def _givens_qr(cols: list[list[Any]], m: int) -> tuple[list[list[Any]], list[tuple]]:
    """QR by Givens rotations of the first ``m`` columns of an (n × c) SX array.

    ``cols[i][j]`` is entry (i, j); rotations skip structural zeros, so the sparsity of
    the constraint rows is used.  Every rotation has determinant +1 and leaves a
    non-negative diagonal entry.  Returns the transformed array (``R`` on top of the first
    ``m`` columns) and the rotations ``(k, i, c, s)`` in the order applied.
    """
    a = [row[:] for row in cols]
    n, width = len(a), len(a[0]) if a else 0
    rotations = []
    for k in range(m):
        for i in range(k + 1, n):
            b = a[i][k]
            if b.is_zero():
                continue
            top = a[k][k]
            r = ca.sqrt(top * top + b * b)
            zero = r == 0  # both entries zero: the identity rotation
            c = (top + zero) / (r + zero)
            s = b / (r + zero)
            rotations.append((k, i, c, s))
            for j in range(k, width):
                akj, aij = a[k][j], a[i][j]
                if akj.is_zero() and aij.is_zero():
                    continue
                a[k][j] = c * akj + s * aij
                a[i][j] = c * aij - s * akj
            a[i][k] = ca.SX(0)
    return a, rotations


def _tridiagonal(sym: ca.SX) -> tuple[list[Any], list[Any]]:
    """Householder tridiagonalisation of a symmetric SX matrix: diagonal and off-diagonal."""
    n = sym.shape[0]
    a = [[sym[i, j] for j in range(n)] for i in range(n)]
    for k in range(n - 2):
        x = [a[i][k] for i in range(k + 1, n)]
        nx = ca.sqrt(sum((xi * xi for xi in x[1:]), x[0] * x[0]))
        s = ca.if_else(x[0] < 0, -1, 1)
        alpha = -s * nx
        v = [x[0] - alpha] + x[1:]
        vv = sum((vi * vi for vi in v[1:]), v[0] * v[0])
        beta = 2 / ca.fmax(vv, 1e-300)
        idx = list(range(k + 1, n))
        size = len(idx)
        p = [beta * sum((a[idx[r]][idx[t]] * v[t] for t in range(1, size)), a[idx[r]][idx[0]] * v[0])
             for r in range(size)]
        kk = beta / 2 * sum((v[r] * p[r] for r in range(1, size)), v[0] * p[0])
        w = [p[r] - kk * v[r] for r in range(size)]
        for r in range(size):
            for t in range(r, size):
                val = a[idx[r]][idx[t]] - v[r] * w[t] - w[r] * v[t]
                a[idx[r]][idx[t]] = val
                a[idx[t]][idx[r]] = val
        a[k + 1][k] = alpha
        a[k][k + 1] = alpha
    diag = [a[i][i] for i in range(n)]
    off = [a[i + 1][i] for i in range(n - 1)]
    return diag, off


def _charpoly(diag, off2, x):
    """``p(x) = det(T - xI)`` and its first two derivatives (three-term recurrence)."""
    p0, p1 = ca.SX(1), diag[0] - x
    d0, d1 = ca.SX(0), ca.SX(-1)
    s0, s1 = ca.SX(0), ca.SX(0)
    for i in range(1, len(diag)):
        t = diag[i] - x
        p2 = t * p1 - off2[i - 1] * p0
        d2 = t * d1 - p1 - off2[i - 1] * d0
        s2 = t * s1 - 2 * d1 - off2[i - 1] * s0
        p0, p1, d0, d1, s0, s1 = p1, p2, d1, d2, s1, s2
    return p1, d1, s1


def _sturm(diag, off2, x):
    """Number of eigenvalues of T below ``x`` (sign changes of the leading minors)."""
    p0, p1 = ca.SX(1), diag[0] - x
    count = (p1 < 0)
    for i in range(1, len(diag)):
        p2 = (diag[i] - x) * p1 - off2[i - 1] * p0
        count = count + (p2 * p1 < 0)
        p0, p1 = p1, p2
    return count


def _laguerre_steps(diag, off2, x, mults=(1,), direction=+1, zeros: int = 0):
    """Laguerre steps for the roots of ``det(T - xI) / x^zeros`` from ``x``, one per multiplicity.

    ``zeros`` known zero roots are divided out (deflated).  ``direction`` is +1 (the step
    to the right) or -1 (to the left), or an SX ±1.  A step that is not finite (``x`` on a
    root) leaves ``x`` unchanged.
    """
    n = len(diag) - zeros
    p, dp, ddp = _charpoly(diag, off2, x)
    g = dp / p
    h = g * g - ddp / p
    if zeros:
        g = g - zeros / x
        h = h - zeros / (x * x)
    spread = n * h - g * g
    out = []
    for mult in mults:
        disc = ca.sqrt(ca.fmax((n / mult - 1) * spread, 0))
        new = x - n / (g - direction * disc)
        out.append(ca.if_else(ca.fabs(new) < ca.inf, new, x))  # false for inf and NaN
    return out


def _eigenvalue_above(diag, off, r0: int) -> tuple[Any, Any]:
    """Eigenvalue ``λ_{r0+1}`` (ascending) of a symmetric tridiagonal matrix, and a 0/1 certificate.

    The ``r0`` smallest eigenvalues are the structural zeros of ``J_e J_eᵀ`` (redundant
    constraint rows); they are divided out of the characteristic polynomial, and
    ``r0 = 0`` asks for the smallest.  Laguerre's iteration from a point between
    ``λ_{r0}`` and ``λ_{r0+1}`` converges monotonically to ``λ_{r0+1}`` and never
    passes it.  Trial steps for a double root (clusters are common: the legs of a
    symmetric mechanism give near-double eigenvalues) are accepted when a Sturm count
    shows they stay below ``λ_{r0+1}``, and otherwise kept as an upper bound when exactly
    one more eigenvalue lies below them; that bound is then refined by left Laguerre
    steps, which converge to the root just below it.  The certificate is 1 when Sturm
    counts prove the start lay below ``λ_{r0+1}`` and the result within a relative
    ``1e-12`` of it.
    """
    n = len(diag)
    off2 = [b * b for b in off]
    trace = sum(diag[1:], diag[0])
    if n == 1:
        return diag[0], ca.SX(1)
    lo = (-1e-12 if r0 == 0 else 1e-6) * ca.fabs(trace)
    start_ok = _sturm(diag, off2, lo) == r0
    up = ca.SX(ca.inf)
    have = ca.SX(0)
    for _ in range(_PHASE1):
        r1, r2 = _laguerre_steps(diag, off2, lo, (1, 2), +1, r0)
        count = _sturm(diag, off2, r2)
        inside = ca.logic_and(count == r0 + 1, r2 < up)
        up = ca.if_else(inside, r2, up)
        have = ca.logic_or(have, count == r0 + 1)
        lo = ca.if_else(count == r0, ca.fmax(r1, r2), r1)
    # refine the upper bound from above when there is one, else the lower bound from below
    est = ca.if_else(have, up, lo)
    direction = ca.if_else(have, -1, 1)
    for _ in range(_PHASE2):
        est = _laguerre_steps(diag, off2, est, (1,), direction, r0)[0]
    width = _CERT * ca.fabs(est)
    ok = ca.logic_and(_sturm(diag, off2, est - width) == r0, _sturm(diag, off2, est + width) >= r0 + 1)
    if r0:
        ok = ca.logic_and(ok, start_ok)
    return est, ok


def _det(m: ca.SX) -> ca.SX:
    n = m.shape[0]
    if n == 0:
        return ca.SX(1)
    if n == 1:
        return m[0, 0]
    if n == 2:
        return m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    if n == 3:
        return (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
                - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
                + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]))
    return ca.det(m)


def _unit_rows(p: ca.SX) -> ca.SX:
    """Rows scaled to unit norm (a zero row is left as is, as the core does)."""
    rows = []
    for i in range(p.shape[0]):
        nr = ca.sqrt(ca.sumsqr(p[i, :]))
        rows.append(p[i, :] / ca.if_else(nr > 0, nr, 1))
    return ca.vertcat(*rows) if rows else p


def _dkp(x: ca.SX, sign: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Signed determinant (square) or product of singular values, and a λ_min lower bound."""
    f, k = x.shape
    s = min(f, k)
    if s == 0:
        return ca.SX(np.nan), ca.SX(np.nan)
    gram = ca.mtimes(x, x.T) if f <= k else ca.mtimes(x.T, x)
    det_g = _det(gram)
    tr_g = ca.trace(gram)
    bound = det_g / tr_g ** (s - 1) if s > 1 else det_g
    value = sign * _det(x) if f == k else ca.sqrt(ca.fmax(det_g, 0))
    return value, bound


# ---------------------------------------------------------------------- the evaluators
class _Functions(dict):
    """Functions by name; when the kernel was deferred, its Functions are built on first access."""

    def __init__(self, funcs, build=None):
        super().__init__(funcs)
        self._build = build

    def ensure(self) -> None:
        """Build the deferred kernel Functions now (no-op when they exist)."""
        build, self._build = self._build, None
        if build is not None:
            build()

    def __missing__(self, key):
        if self._build is not None and key in KERNEL_FUNCTIONS:
            self.ensure()
            if dict.__contains__(self, key):
                return dict.__getitem__(self, key)
        raise KeyError(key)


@dataclass(eq=False)
class Evaluators:
    """Named CasADi Functions of one mechanism (see the module docstring).

    Attributes
    ----------
    mech : Mechanism
    functions : dict of str → casadi.Function
        ``G``, ``J``, ``closure``, ``closure_jacobian``, ``parameters`` and, when
        :attr:`fast`, ``indicators``, ``indicators_batch`` and ``motion``.  In-process SX
        Functions until :meth:`compile` replaces them by generated C.
    q_labels : tuple of str
        Names of the entries of ``q`` (``x_B, y_B, ...``: free nodes in node order).
    p_labels, p0
        Names and model values of the closure parameters ``p``.
    row_owners : tuple of str
        What owns each row of ``J`` and of ``phi`` (same strings as the core).
    effective_rows, basis_rows : tuple of int
        Rows of ``J`` that touch free coordinates (``J_e``), and the independent ones the
        motion space and the DKP values are built from (``J_S``).
    fast : bool
        Whether the indicator kernel exists (``nf - F`` effective constraint rows).
    compiled : bool
        Whether :attr:`functions` are generated C loaded with ``casadi.external``.
    """

    mech: Mechanism
    model: CasadiModel = field(repr=False)
    functions: dict
    q_labels: tuple[str, ...]
    p_labels: tuple[str, ...]
    p0: np.ndarray = field(repr=False)
    row_owners: tuple[str, ...]
    effective_rows: tuple[int, ...]
    basis_rows: tuple[int, ...]
    fast: bool
    compiled: bool = False
    library: str | None = None
    _symbolic: dict = field(default_factory=dict, repr=False)
    _cache: dict = field(default_factory=dict, repr=False)

    # -- access
    def __getattr__(self, name: str):
        functions = self.__dict__.get("functions", {})
        if name in functions or (name in KERNEL_FUNCTIONS and self.__dict__.get("fast")):
            return functions[name]
        if name in FUNCTION_NAMES:
            raise AttributeError(f"{name!r} is not available for {self.mech.name!r}: the indicator "
                                 "kernel needs nf - F constraint rows (see Evaluators.fast)")
        raise AttributeError(name)

    @property
    def nf(self) -> int:
        return len(self.q_labels)

    @property
    def mobility(self) -> int:
        return self.mech.mobility_value

    @property
    def q0(self) -> np.ndarray:
        """Free coordinates of the model's configuration."""
        return self.model.q0()

    @property
    def input_labels(self) -> tuple[str, ...]:
        return self.model.input_labels

    @property
    def output_labels(self) -> tuple[str, ...]:
        return self.model.output_labels

    @property
    def platform_labels(self) -> tuple[str, ...]:
        return self.model.platform_labels

    @property
    def free(self) -> np.ndarray:
        """Boolean mask of the free coordinates among all D coordinates."""
        return self.model.free

    def symbolic_function(self, name: str) -> ca.Function:
        """The in-process SX Function ``name`` (also after :meth:`compile`)."""
        return self._symbolic[name]

    # -- configurations
    def coordinates(self, q) -> np.ndarray:
        """All nodal coordinates (n_nodes, dim) for free coordinates ``q``."""
        xyz = np.array([c for _, c in self.mech.nodes], dtype=float).ravel()
        xyz[self.free] = np.asarray(q, dtype=float).ravel()
        return xyz.reshape(-1, self.mech.dim)

    def mechanism_at(self, q) -> Mechanism:
        """The mechanism at free coordinates ``q`` (for :func:`symkin.analyze`)."""
        return self.mech.with_coordinates(self.coordinates(q))

    def free_coordinates(self, mech: Mechanism) -> np.ndarray:
        """``q`` of another configuration of the same mechanism."""
        return np.array([c for _, c in mech.nodes], dtype=float).ravel()[self.free]

    # -- evaluation
    def __call__(self, name: str, *args) -> dict[str, np.ndarray]:
        """Evaluate Function ``name`` at one point; a dict of NumPy arrays by output name."""
        f = self.functions[name]
        if name in ("closure", "closure_jacobian") and len(args) == 1:
            args = (args[0], self.p0)
        out = f.call([ca.DM(np.asarray(a, dtype=float)) for a in args])
        return {f.name_out(i): np.array(out[i].full()) for i in range(f.n_out())}

    def map(self, name: str, configurations, p=None) -> dict[str, np.ndarray]:
        """Evaluate Function ``name`` at N configurations (rows of ``configurations``).

        One ``Function.map`` call per chunk (no Python loop per configuration).  Returns
        a dict of arrays of shape ``(N,) + output shape``.
        """
        from symkin.numeric.mapping import map_function

        return map_function(self, name, configurations, p)

    def project(self, configurations, p=None, tol: float = 1e-12, max_iter: int = 25) -> np.ndarray:
        """Project configurations onto the closure manifold ``phi(q, p) = 0`` (batched Newton).

        Minimum-norm Gauss-Newton steps ``Δq = -J⁺ φ``; raises
        :class:`symkin.errors.NotConvergedError` when a configuration does not close.
        """
        from symkin.numeric.mapping import project

        return project(self, configurations, p=p, tol=tol, max_iter=max_iter)

    def compile(self, cache_dir=None, compiler: str | None = None, flags=None, force: bool = False) -> "Evaluators":
        """Generate C for every Function, compile, load with ``casadi.external``; cached on disk.

        See :func:`symkin.numeric.codegen.compile_evaluators`.  Returns ``self`` (now with
        compiled Functions), or ``self`` unchanged with a warning when no compiler works.
        """
        from symkin.numeric.codegen import compile_evaluators

        for funcs in (self._symbolic, self.functions):
            if isinstance(funcs, _Functions):
                funcs.ensure()
        return compile_evaluators(self, cache_dir=cache_dir, compiler=compiler, flags=flags, force=force)


def _basis_rows(cm: CasadiModel, jf: ca.SX, effective: tuple[int, ...], rank: int, tol: float):
    """Constraint rows to build the motion space from: ``rank`` independent rows of ``J_e``.

    Well-conditioned independent rows (:func:`symkin.numeric.linalg.independent_rows`,
    relative ``tol``, the one choice of ``J_S``), taken at a generic configuration near the
    model's (perturbed, then projected onto the closure manifold).  All effective rows
    when there are exactly ``rank``.  ``None`` when the rank of ``J_e`` there is not
    ``rank`` (the declared mobility is not the generic one).
    """
    if len(effective) == rank:
        return effective
    q, p = cm.q, cm.p
    je = ca.densify(jf[list(effective), :])
    f_je = ca.Function("je", [q], [je])
    f_cl = ca.Function("cl", [q, p], [ca.densify(cm.closure), ca.densify(ca.jacobian(cm.closure, q))])
    q0 = cm.q0()
    rng = np.random.default_rng(0)
    qg = q0 + 1e-3 * cm.mech.length_scale * rng.standard_normal(q0.size)
    for _ in range(30):
        phi, jac = (np.array(v) for v in f_cl(qg, cm.p0))
        if np.max(np.abs(phi)) <= 1e-13 * cm.mech.length_scale:
            break
        qg = qg - np.linalg.pinv(jac, rcond=1e-12) @ phi.ravel()
    else:
        qg = q0
    jn = np.array(f_je(qg))
    chosen = independent_rows(jn, tol)
    if len(chosen) != rank:
        return None  # the generic rank is not nf - F: the declared mobility is not the generic one
    return tuple(effective[i] for i in chosen)


def _functions(cm: CasadiModel, mobility: int, tol: float, kernel: bool = True):
    q, p = cm.q, cm.p
    free_cols = np.flatnonzero(cm.free).tolist()
    jf = cm.J[:, free_cols]
    dense = ca.densify
    opts = {"cse": True}
    funcs = {}
    g_full = ca.mtimes(cm.J.T, cm.J)
    funcs["G"] = ca.Function("G", [q], [dense(ca.mtimes(jf.T, jf)), dense(g_full)], ["q"], ["G", "G_full"], opts)
    funcs["J"] = ca.Function("J", [q], [dense(cm.J), dense(jf)], ["q"], ["J", "J_free"], opts)
    funcs["closure"] = ca.Function("closure", [q, p], [dense(cm.closure)], ["q", "p"], ["phi"], opts)
    funcs["closure_jacobian"] = ca.Function(
        "closure_jacobian", [q, p], [dense(cm.closure), dense(ca.jacobian(cm.closure, q))],
        ["q", "p"], ["phi", "dphi_dq"], opts)
    funcs["parameters"] = ca.Function(
        "parameters", [q], [dense(cm.inputs), dense(cm.outputs), dense(cm.platform)],
        ["q"], ["inputs", "outputs", "platform"], opts)

    effective = tuple(i for i in range(jf.shape[0])
                      if any(not jf[i, j].is_zero() for j in range(jf.shape[1])))
    nf, m_e, f = len(free_cols), len(effective), mobility
    r0 = m_e - (nf - f)
    basis_rows = _basis_rows(cm, jf, effective, nf - f, tol) if (nf - f >= 1 and r0 >= 0) else None
    fast = basis_rows is not None
    if fast and kernel:
        je = jf[list(effective), :]
        js = jf[list(basis_rows), :]
        p_in = _unit_rows(cm.inputs[:, free_cols]) if cm.inputs.shape[0] else ca.SX(0, nf)
        p_out = _unit_rows(cm.outputs[:, free_cols]) if cm.outputs.shape[0] else ca.SX(0, nf)
        k_in, k_out = p_in.shape[0], p_out.shape[0]
        m = nf - f
        big = ca.horzcat(js.T, p_in.T, p_out.T)
        cols = [[big[i, j] for j in range(big.shape[1])] for i in range(nf)]
        qr, rotations = _givens_qr(cols, m)
        sign = ca.SX(1)
        for k in range(m):
            sign = sign * ca.sign(qr[k][k])
        x_in = ca.SX(f, k_in)
        x_out = ca.SX(f, k_out)
        for i in range(f):
            for j in range(k_in):
                x_in[i, j] = qr[m + i][m + j]
            for j in range(k_out):
                x_out[i, j] = qr[m + i][m + k_in + j]
        d_in, b_in = _dkp(x_in, sign)
        d_out, b_out = _dkp(x_out, sign)
        if r0:
            # the chosen independent rows must keep their rank for V to span the motion space
            r2min = qr[0][0] * qr[0][0]
            for k in range(1, m):
                r2min = ca.fmin(r2min, qr[k][k] * qr[k][k])
            valid = r2min > 1e-10 * ca.sumsqr(js)
            b_in = ca.if_else(valid, b_in, 0)
            b_out = ca.if_else(valid, b_out, 0)
        gram = ca.mtimes(je, je.T)
        diag, off = _tridiagonal(gram)
        lam, ok = _eigenvalue_above(diag, off, r0)
        outs = [lam, ok, ca.trace(gram), d_in, b_in, d_out, b_out]
        funcs["indicators"] = ca.Function("indicators", [q], outs, ["q"], list(INDICATOR_NAMES), opts)
        # the same over BATCH configurations (columns of q), a loop in the generated C
        funcs["indicators_batch"] = funcs["indicators"].map("indicators_batch", "serial", BATCH, [], [])
        # motion space: the last F columns of Q = G_1ᵀ ... G_Nᵀ (rotations G applied in order)
        basis = [[ca.SX(1.0 if i == m + j else 0.0) for j in range(f)] for i in range(nf)]
        for k, i, c, s in reversed(rotations):
            for j in range(f):
                bk, bi = basis[k][j], basis[i][j]
                if bk.is_zero() and bi.is_zero():
                    continue
                basis[k][j] = c * bk - s * bi
                basis[i][j] = s * bk + c * bi
        vmat = ca.SX(nf, f)
        for i in range(nf):
            for j in range(f):
                vmat[i, j] = basis[i][j]
        funcs["motion"] = ca.Function("motion", [q], [dense(vmat)], ["q"], ["V"], opts)
    return funcs, effective, basis_rows, fast


def evaluators(mech: Mechanism, tolerances: Tolerances = DEFAULT, kernel: bool = True) -> Evaluators:
    """CasADi evaluators of ``mech`` (G, J, closure residual, parameter rows, indicators).

    Parameters
    ----------
    mech : Mechanism
        Its configuration supplies the fixed nodes, the closure parameters ``p0`` and the
        choices made once (degenerate bodies, rods).
    tolerances : Tolerances
        ``geometry`` recognises degenerate bodies (as the core does); ``rank`` chooses
        the independent rows ``J_S`` at a generic configuration.
    kernel : bool
        Build the indicator kernel (``indicators``, ``indicators_batch``, ``motion``) now;
        with False it is built on first use (paths, which need only the closure and the
        rows, do not pay for it).

    Returns
    -------
    Evaluators

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> ev = evaluators(get("fourbar_appendix"))
    >>> ev.q_labels
    ('x_B', 'y_B', 'x_C', 'y_C')
    >>> G = ev("G", ev.q0)["G"]
    >>> G.shape, ev.fast
    ((4, 4), True)
    >>> ind = ev("indicators", ev.q0)
    >>> bool(abs(ind["im"][0, 0] - __import__("symkin").analyze(ev.mech).im_indicator) < 1e-12)
    True
    """
    cm = build(mech, tolerances)
    funcs, effective, basis, fast = _functions(cm, mech.mobility_value, tolerances.rank, kernel)
    functions, symbolic = _Functions(funcs), _Functions(funcs)
    if fast and not kernel:
        def build_kernel() -> None:
            full = _functions(cm, mech.mobility_value, tolerances.rank)[0]
            for target in (functions, symbolic):
                target._build = None
                target.update({k: full[k] for k in KERNEL_FUNCTIONS if k in full})
        functions._build = symbolic._build = build_kernel
    return Evaluators(mech=mech, model=cm, functions=functions, q_labels=cm.q_labels,
                      p_labels=cm.p_labels, p0=cm.p0, row_owners=cm.owners,
                      effective_rows=effective, basis_rows=basis or (), fast=fast,
                      _symbolic=symbolic)
