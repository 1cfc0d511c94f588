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
  Laguerre iterations on its characteristic polynomial, safeguarded by Sturm counts
  (:func:`~symkin.numeric.sx_linalg.smallest_eigenvalue` when ``r0 = 0``, each
  evaluation also giving the Sturm count; :func:`~symkin.numeric.sx_linalg.eigenvalue_above`
  otherwise); ``im_certified = 1`` when Sturm counts prove ``λ_{F+1}`` lies within a
  relative 1e-12 of ``im``, half of that width left for the rounding of the reduction
  (``ε·tr A``), so nothing is certified where double precision cannot resolve it.
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

``V`` (Function ``motion``) comes from a QR factorisation of ``J_Sᵀ`` by Givens rotations
(which skip the structural zeros of ``J``), and the DKP values from ``P̂ V``.  The SX linear
algebra (QR, tridiagonal form, certified eigenvalues, determinants) is in
:mod:`symkin.numeric.sx_linalg`.

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

import casadi as ca
import numpy as np

from symkin.curves.corrector import gauss_newton_batch
from symkin.model.mechanism import Mechanism
from symkin.numeric.casadi_model import CasadiModel, build
from symkin.numeric.linalg import independent_rows
from symkin.numeric.sx_linalg import (det, eigenvalue_above, givens_qr, householder_tridiagonal,
                                      reciprocal, smallest_eigenvalue)
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

# ---------------------------------------------------------------------- indicator helpers
def _im_kernel(gram: ca.SX, r0: int) -> tuple[ca.SX, ca.SX]:
    """IM indicator ``λ_{r0+1}`` of ``A = J_e J_eᵀ`` and its 0/1 Sturm certificate.

    ``A`` is reduced to tridiagonal form (:func:`~symkin.numeric.sx_linalg.householder_tridiagonal`);
    ``r0 = 0`` uses :func:`~symkin.numeric.sx_linalg.smallest_eigenvalue`, redundant rows
    (``r0 > 0``) :func:`~symkin.numeric.sx_linalg.eigenvalue_above`.
    """
    diag, off = householder_tridiagonal(gram)
    if r0 == 0:
        return smallest_eigenvalue(diag, off)
    return eigenvalue_above(diag, off, r0)


def _motion_basis(rotations: list[tuple], nf: int, f: int) -> ca.SX:
    """The last ``f`` columns of ``Q = G_1ᵀ ... G_Nᵀ`` for the Givens rotations of :func:`givens_qr`.

    For the QR of ``J_Sᵀ`` (``nf × (nf - f)``) these columns are an orthonormal basis of
    the null space of ``J_S``: the motion space of eq. 9.
    """
    m = nf - f
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
    return vmat


def _unit_rows(p: ca.SX) -> ca.SX:
    """Rows scaled to unit norm (a zero row is left as is, as the core does)."""
    rows = []
    for i in range(p.shape[0]):
        nr = ca.sqrt(ca.sumsqr(p[i, :]))
        rows.append(p[i, :] * reciprocal(nr, 1))
    return ca.vertcat(*rows) if rows else p


def _dkp(x: ca.SX, sign: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Signed determinant (square) or product of singular values, and a λ_min lower bound."""
    f, k = x.shape
    s = min(f, k)
    if s == 0:
        return ca.SX(np.nan), ca.SX(np.nan)
    gram = ca.mtimes(x, x.T) if f <= k else ca.mtimes(x.T, x)
    det_g = det(gram)
    tr_g = ca.trace(gram)
    bound = det_g / tr_g ** (s - 1) if s > 1 else det_g
    value = sign * det(x) if f == k else ca.sqrt(ca.fmax(det_g, 0))
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


#: a generic configuration near the model's, for choosing the independent rows J_S: the model's
#: perturbed by this many length scales (random, seeded), then projected onto the closure
_GENERIC_OFFSET = 1e-3

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
    q0, ell = cm.q0(), cm.mech.length_scale
    rng = np.random.default_rng(0)

    def closure(q_batch, index):  # model units; the tolerance below carries the length scale
        phi, jac = f_cl(q_batch[0], cm.p0)
        return np.array(phi).reshape(1, -1), np.array(jac)[None]

    fit = gauss_newton_batch(closure, q0 + _GENERIC_OFFSET * ell * rng.standard_normal(q0.size),
                             tol=DEFAULT.closure * ell, max_iterations=30, diverge_after=31, rcond=DEFAULT.pinv)
    qg = fit.z[0] if fit.converged[0] else q0
    jn = np.array(f_je(qg))
    chosen = independent_rows(jn, tol)
    if len(chosen) != rank:
        return None  # the generic rank is not nf - F: the declared mobility is not the generic one
    return tuple(effective[i] for i in chosen)


#: instructions above which a Function is built without common-subexpression elimination: CasADi's
#: CSE pass grows faster than linearly with the graph (20 s of the 6-UPS joint form's 1.9 million
#: instructions, for 1.3 % fewer of them); below it, CSE as always.  CSE merges identical
#: operations only, so the values are the same bit for bit either way.
CSE_LIMIT = 400_000


def _function(name: str, ins: list, outs: list, in_names: list, out_names: list) -> ca.Function:
    """``ca.Function`` with CSE when the graph has at most :data:`CSE_LIMIT` instructions."""
    f = ca.Function(name, ins, outs, in_names, out_names)
    if f.n_instructions() <= CSE_LIMIT:
        f = ca.Function(name, ins, outs, in_names, out_names, {"cse": True})
    return f


def _functions(cm: CasadiModel, mobility: int, tol: float, kernel: bool = True):
    q, p = cm.q, cm.p
    free_cols = np.flatnonzero(cm.free).tolist()
    jf = cm.J[:, free_cols]
    dense = ca.densify
    funcs = {}
    g_full = ca.mtimes(cm.J.T, cm.J)
    funcs["G"] = _function("G", [q], [dense(ca.mtimes(jf.T, jf)), dense(g_full)], ["q"], ["G", "G_full"])
    funcs["J"] = _function("J", [q], [dense(cm.J), dense(jf)], ["q"], ["J", "J_free"])
    funcs["closure"] = _function("closure", [q, p], [dense(cm.closure)], ["q", "p"], ["phi"])
    funcs["closure_jacobian"] = _function(
        "closure_jacobian", [q, p], [dense(cm.closure), dense(ca.jacobian(cm.closure, q))],
        ["q", "p"], ["phi", "dphi_dq"])
    funcs["parameters"] = _function(
        "parameters", [q], [dense(cm.inputs), dense(cm.outputs), dense(cm.platform)],
        ["q"], ["inputs", "outputs", "platform"])

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
        m = nf - f
        # Givens QR of J_Sᵀ; the motion space V (eq. 9) is the last F columns of
        # Q = G_1ᵀ ... G_Nᵀ (rotations G applied in order), so Vᵀ P̂ᵀ is the bottom block
        # of Qᵀ [J_Sᵀ | P̂ᵀ] and det([J_S; P̂]) = ±det(R) det(P̂ V)
        cols = [[js[j, i] for j in range(m)] for i in range(nf)]
        qr, rotations = givens_qr(cols, m)
        sign = ca.SX(1)
        for k in range(m):
            sign = sign * ca.sign(qr[k][k])
        vmat = _motion_basis(rotations, nf, f)
        d_in, b_in = _dkp(ca.mtimes(vmat.T, p_in.T), sign)
        d_out, b_out = _dkp(ca.mtimes(vmat.T, p_out.T), sign)
        if r0:
            # the chosen independent rows must keep their rank for V to span the motion space
            r2min = qr[0][0] * qr[0][0]
            for k in range(1, m):
                r2min = ca.fmin(r2min, qr[k][k] * qr[k][k])
            valid = r2min > 1e-10 * ca.sumsqr(js)
            b_in = ca.if_else(valid, b_in, 0)
            b_out = ca.if_else(valid, b_out, 0)
        gram = ca.mtimes(je, je.T)
        lam, ok = _im_kernel(gram, r0)
        outs = [lam, ok, ca.trace(gram), d_in, b_in, d_out, b_out]
        funcs["indicators"] = _function("indicators", [q], outs, ["q"], list(INDICATOR_NAMES))
        # the same over BATCH configurations (columns of q), a loop in the generated C
        funcs["indicators_batch"] = funcs["indicators"].map("indicators_batch", "serial", BATCH, [], [])
        funcs["motion"] = _function("motion", [q], [dense(vmat)], ["q"], ["V"])
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
