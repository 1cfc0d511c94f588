"""Singularity loci as implicit polynomials in two workspace coordinates (issue 9 §3).

For two coordinates named by labels (``velocity:P.x``, ``velocity:P.y``; ``rotation:L``;
``slide:S``, as ``symkin map --x`` takes them) and the held ones (``--hold``), every other
nodal coordinate is eliminated from

* the closure in nodal coordinates (bars ``|x_j − x_i|² = l²``; a body of 3+ nodes as its
  first two nodes and the others at fixed affine coordinates in their frame, which keeps
  its orientation — no mirror image; sliders as linear or cross-product conditions),
* the equations of the two variables and of the held coordinates, and
* one factor of a singularity condition (:mod:`symkin.symbolic.conditions`, §III, eq. 12):
  DKP-input, DKP-output, and for IM the minors of the velocity equation (eq. 8),

leaving the *locus* of each kind: a polynomial in the two variables, factored over ℚ, its
trivial factors (nonzero constants, curves without a real point) separated and each
geometric factor named (a circle with its centre and radius, recognised as ``l1 ± l2`` of
two links at a pivot, a conic, a tricircular sextic such as Watt's curve, else
"degree-d curve").

Variables are named after their owners: ``x_P``, ``y_P`` for node coordinates, ``s_S`` for
a slide, and ``t_L = tan(θ_L/2)`` for the direction angle of link L (first node → second
node), the tangent half-angle, so that a locus stays one polynomial in two variables
(``cos θ = (1 − t²)/(1 + t²)``, ``sin θ = 2t/(1 + t²)``).

How (and why not a Gröbner basis)
---------------------------------
A lexicographic Gröbner basis in sympy does not finish within minutes even for the
five-bar's type-2 locus (4 unknowns, 5 quadrics).  The structure of a closure makes
elimination cheap instead:

1. equations linear in an unknown with a constant coefficient are solved and substituted
   (bodies, held orientations and node coordinates, fixed-line sliders): exact, no factor;
2. the rest split into *blocks*: the equations connected through shared unknowns.  With the
   variables and holds fixing the mechanism (checked: the square system is regular at the
   model's configuration), every block is square and, given the variables, has finitely
   many solutions — the elbow of a leg, the cylinder of a 3-RPR leg.  A block the condition
   does not touch constrains nothing (its projection is dense);
3. the condition factor ``g`` is replaced by its *norm* over each block it touches,
   ``N(g) = Π g(branch)`` over the block's solutions: in a block two circles through one
   node differ by a linear equation (their radical axis), a linear equation with
   coefficient ``β`` is solved for one unknown, and the last quadratic ``q(u)`` leaves
   ``N(g) = Res_u(q, ĝ) / (lc(q)^{deg ĝ} β^{…})`` — a resultant whose extraneous factors
   are *known* and divided out exactly, so no spurious factor is left.

``N(g) = 0`` is where some branch of the mechanism at ``(x, y)`` satisfies the condition:
the locus, exactly (the Zariski closure of the projection).  The IM locus is contained in
the DKP-input and DKP-output loci (their zero sets contain every IM configuration): when
they share no factor, the IM locus has no curve; otherwise the shared factors are checked
against the norms of two random combinations of the IM minors.  Isolated IM points are not
listed (a locus here is a curve).

Every step polls a deadline and a ``SIGALRM`` timer (main thread) stops a long sympy call:
``time_limit`` stops a locus with :class:`~symkin.symbolic.conditions.DerivationTimeout`
naming it.
"""
from __future__ import annotations

import contextlib
import itertools
import math
import random
import signal
import threading
import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from symkin.constraints import SliderMovingLine, bar_constraint, body_constraint, polynomial_constraints, slider_constraint, slider_constraints
from symkin.constraints.algebra import Sympy
from symkin.errors import SymkinError
from symkin.kinds import LOCUS_KINDS, Kind
from symkin.kinds import latex as latex_name
from symkin.model.labels import CoordinateLabel, OrientationLabel, parse_holds, parse_label, parse_orientation_label
from symkin.model.mechanism import AXES, Mechanism
from symkin.numeric.linalg import independent_rows
from symkin.symbolic.conditions import DerivationTimeout
from symkin.symbolic.real_points import isolated_real_points
from symkin.symbolic.snapping import ModelSnap, snap_model
from symkin.symbolic.symbols import coordinate_symbol, exact, length_symbol, offset_symbol
from symkin.symbolic.symbols import decimal_rational as _q
from symkin.tolerances import Tolerances

#: the lead of the list of accepted labels in a bad-label message
_LOCUS_LABELS = "a locus can be written in"

__all__ = ["LociError", "LocusFactor", "Locus", "Loci", "implicit_loci", "closure_polynomials", "KINDS"]

#: the kinds of loci, in the order derived
KINDS = LOCUS_KINDS
#: most IM minors whose common zeros are eliminated
MAX_IM_MINORS = 200
#: angle units of hold values, factor to radians
UNITS = {"deg": math.pi / 180.0, "rad": 1.0}


class LociError(SymkinError):
    """A locus cannot be derived by this elimination (the message says which and why)."""


# ====================================================================== results
@dataclass(frozen=True)
class LocusFactor:
    """One irreducible factor of a locus over ℚ.

    Attributes
    ----------
    polynomial : sympy.Expr
        Primitive polynomial with integer coefficients in the two variables.
    degree : int
        Total degree.
    meaning : str
        What the curve is, e.g. ``"circle centred at A1 (-1, 0), radius 3 = l_crank1 + l_distal1"``.
    exponent : int
        Multiplicity in the eliminated polynomial.
    trivial : bool
        True for nonzero constants and curves with no real point.
    """

    polynomial: sp.Expr
    degree: int
    meaning: str
    exponent: int = 1
    trivial: bool = False

    def as_dict(self) -> dict:
        return {"polynomial": sp.sstr(self.polynomial), "degree": self.degree, "meaning": self.meaning,
                "exponent": self.exponent}


@dataclass(frozen=True)
class Locus:
    """The locus of one kind: ``Π factors = 0`` in the two variables.

    ``factors`` are the geometric factors, ``trivial`` the separated ones; ``seconds`` the
    derivation time (condition and elimination); ``note`` what the zero set contains.
    """

    kind: str
    factors: tuple[LocusFactor, ...]
    trivial: tuple[LocusFactor, ...] = ()
    seconds: float = 0.0
    note: str = ""
    everywhere: bool = False

    @property
    def polynomial(self) -> sp.Expr:
        """Product of the geometric factors (with multiplicity)."""
        return sp.Mul(*[f.polynomial ** f.exponent for f in self.factors])

    def as_dict(self) -> dict:
        return {"kind": self.kind, "factors": [f.as_dict() for f in self.factors],
                "trivial_factors": [f.as_dict() for f in self.trivial], "everywhere": self.everywhere,
                "seconds": self.seconds, "note": self.note}


@dataclass(frozen=True, eq=False)
class Loci:
    """Loci of every kind derived, in the variables ``variables`` (symbols) named by ``labels``."""

    variables: tuple[sp.Symbol, sp.Symbol]
    labels: tuple[str, str]
    holds: tuple[str, ...]
    loci: tuple[Locus, ...]
    skipped: tuple[str, ...] = ()
    model: str = field(default="")
    snap: ModelSnap | None = None

    def __getitem__(self, kind: str) -> Locus:
        for locus in self.loci:
            if locus.kind == kind:
                return locus
        raise KeyError(f"no {kind} locus (derived: {', '.join(l.kind for l in self.loci) or 'none'})")

    def as_dict(self) -> dict:
        """The JSON of ``symkin conditions --in … --json``."""
        return {"variables": [s.name for s in self.variables], "labels": list(self.labels),
                "holds": list(self.holds), "loci": [l.as_dict() for l in self.loci], "skipped": list(self.skipped),
                "snapping": self.snap.as_dict() if self.snap is not None else None}

    def __str__(self) -> str:
        x, y = self.variables
        lines = [f"singularity loci of {self.model} in ({x}, {y}) = ({self.labels[0]}, {self.labels[1]})"
                 + (f", holding {', '.join(self.holds)}" if self.holds else "")]
        if self.snap is not None and self.snap.snapped:
            lines.append(self.snap.note())
        for locus in self.loci:
            lines.append("")
            lines.append(f"{locus.kind} locus — eliminated in {locus.seconds:.3g} s")
            if locus.everywhere:
                lines.append("  holds everywhere (the condition vanishes on the whole slice)")
            elif not locus.factors:
                lines.append("  no curve")
            for f in locus.factors:
                power = f"  (power {f.exponent})" if f.exponent != 1 else ""
                lines.append(f"  {sp.sstr(f.polynomial)} = 0{power}   [{f.meaning}]")
            if locus.trivial:
                lines.append("  trivial factors: " + "; ".join(f"{sp.sstr(f.polynomial)} ({f.meaning})"
                                                               for f in locus.trivial))
            if locus.note:
                lines.append(f"  note: {locus.note}")
        for text in self.skipped:
            lines += ["", text]
        return "\n".join(lines)

    def latex(self) -> str:
        """One LaTeX line per locus: ``\\mathrm{DKP}_{in}: (f_1)(f_2) = 0``."""
        out = []
        for locus in self.loci:
            if not locus.factors:
                out.append(latex_name(locus.kind) + (r":\; 0 = 0" if locus.everywhere else r":\; \text{no curve}"))
                continue
            body = " ".join(rf"\left({sp.latex(f.polynomial)}\right)" + (f"^{{{f.exponent}}}" if f.exponent != 1 else "")
                            for f in locus.factors)
            out.append(latex_name(locus.kind) + r":\; " + body + " = 0")
        return "\n".join(out)


# ====================================================================== time limit
@contextlib.contextmanager
def _limit(kind: str, seconds: float | None):
    """Stop the block after ``seconds`` with :class:`DerivationTimeout` naming ``kind``."""
    if not seconds:
        yield None
        return
    deadline = time.perf_counter() + seconds

    def message():
        return (f"{kind} locus: elimination not finished within the time limit of {seconds:g} s "
                "(raise --time-limit, or hold more coordinates)")

    use_alarm = threading.current_thread() is threading.main_thread() and hasattr(signal, "SIGALRM")
    if use_alarm:
        def handler(signum, frame):
            raise DerivationTimeout(message())
        old = signal.signal(signal.SIGALRM, handler)
        signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield (deadline, message)
    finally:
        if use_alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)


def _poll(limit) -> None:
    if limit is not None and time.perf_counter() > limit[0]:
        raise DerivationTimeout(limit[1]())


# ====================================================================== exact model data
def _nodes_exact(mech: Mechanism, snap: ModelSnap) -> dict[str, tuple[sp.Rational, ...]]:
    """Pivots as snapped (:mod:`symkin.symbolic.snapping`), free nodes at their face value (used
    only to choose frames and to check the variables numerically, never in an equation)."""
    return {n: snap.pivots.get(n) or tuple(_q(v) for v in xyz) for n, xyz in mech.nodes}


def _dot(a, b):
    return sp.Add(*[p * q for p, q in zip(a, b)])


def _sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def _cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _sqrt_rational(v: sp.Rational, what: str) -> sp.Rational:
    r = sp.sqrt(v)
    if not r.is_Rational:
        raise LociError(f"{what}: its length sqrt({v}) is irrational; this elimination works over the "
                        "rationals (use a node coordinate instead)")
    return r


@dataclass
class _System:
    """The polynomial closure of one mechanism in nodal coordinates (exact rationals)."""

    mech: Mechanism
    coord: dict  # node -> tuple of symbols (free) or rationals (fixed)
    x0: dict     # node -> exact model coordinates
    equations: list  # list of (expr, owner)
    frames: dict  # link -> (n0, n1) the pair whose distance equation is listed, with its index
    snap: ModelSnap  # the exact (snapped) numbers of the model
    affine: dict = field(default_factory=dict)  # (link, node) -> exact coordinates in the link's frame


def closure_polynomials(mech: Mechanism) -> list[tuple[sp.Expr, str]]:
    """The closure as polynomials in the free nodal coordinates ``x_B, y_B, …`` (exact).

    One equation per independent constraint, named by its owner: the distance of a bar,
    for a body of 3+ nodes the distance of its first two nodes (and of a third in space)
    and every other node at its fixed affine coordinates in their frame (planar:
    ``x_m = x_0 + a e + b e⊥``; this keeps the body's orientation), a slider as
    ``n · (x_P − p) = 0`` or ``(x_C − x_A) × (x_P − x_A) = 0``.  They vanish exactly where
    the numeric closure (:mod:`symkin.numeric.casadi_model`) does, which a test checks.

    >>> from symkin.model.catalogue import get
    >>> [(str(e), owner) for e, owner in closure_polynomials(get("five_bar"))][:2]
    [('x_B1**2 + 2*x_B1 + y_B1**2', 'link crank1 (A1-B1)'), ('x_B2**2 - 2*x_B2 + y_B2**2', 'link crank2 (A2-B2)')]
    """
    return [(e, o) for e, o in _build(mech).equations]


def _build(mech: Mechanism, snap: ModelSnap | None = None) -> _System:
    polynomial_constraints(mech, "the locus elimination")
    snap = snap_model(mech) if snap is None else snap
    fixed = set(mech.fixed)
    x0 = _nodes_exact(mech, snap)
    affine: dict = {}
    coord = {n: (x0[n] if n in fixed else tuple(coordinate_symbol(AXES[a], n) for a in range(mech.dim)))
             for n in mech.node_names}
    eqs: list = []
    frames: dict = {}
    dim = mech.dim
    for name, ns in mech.links:
        n0 = ns[0]
        n1 = ns[1] if any(v != 0 for v in _sub(x0[ns[1]], x0[n0])) else \
            max(ns, key=lambda n: _dot(_sub(x0[n], x0[n0]), _sub(x0[n], x0[n0])))
        e, e0 = _sub(coord[n1], coord[n0]), _sub(x0[n1], x0[n0])
        frames[name] = (n0, n1, len(eqs))
        eqs.append((_distance(mech, coord, snap, name, n0, n1), f"link {name} ({n0}-{n1})"))
        others = [n for n in ns if n not in (n0, n1)]
        if not others:
            continue
        if dim == 2:
            basis = [e, (-e[1], e[0])]
            basis0 = [e0, (-e0[1], e0[0])]
        else:
            off = max(others, key=lambda n: _dot(_cross3(e0, _sub(x0[n], x0[n0])), _cross3(e0, _sub(x0[n], x0[n0]))))
            c0 = _cross3(e0, _sub(x0[off], x0[n0]))
            if _dot(c0, c0) == 0:  # a rod: every node on the line of the first two
                basis, basis0 = [e], [e0]
            else:
                f, f0 = _sub(coord[off], coord[n0]), _sub(x0[off], x0[n0])
                eqs.append((_distance(mech, coord, snap, name, n0, off), f"link {name} ({n0}-{off})"))
                eqs.append((_distance(mech, coord, snap, name, n1, off), f"link {name} ({n1}-{off})"))
                basis, basis0 = [e, f, _cross3(e, f)], [e0, f0, c0]
                others = [n for n in others if n != off]
        m0 = sp.Matrix([list(b) for b in basis0]).T
        for m in others:
            d0 = sp.Matrix(_sub(x0[m], x0[n0]))
            frame = math.sqrt(float(_dot(e0, e0)))
            coef = [snap.number(float(v), f"coordinate {k + 1} of node {m} in the frame of {name}", frame)
                    for k, v in enumerate((m0.T * m0).LUsolve(m0.T * d0))]  # affine coordinates, snapped
            affine[(name, m)] = tuple(coef)
            body = body_constraint(mech, name)  # x_m = x_n0 + Σ c_k b_k: the body's frame equations
            at = dict(zip(body.names, body.idx))
            eqs += [(q, f"link {name} (node {m} in its frame)") for q in body.frame_equations(
                {at[n]: coord[n] for n in ns}, [at[n0], at[n1]] + ([at[off]] if len(basis) == 3 else []), at[m], coef)]
    alg = _algebra(snap, x0)
    X = [coord[n] for n in mech.node_names]
    X0 = [tuple(map(float, c)) for _, c in mech.nodes]
    for con in slider_constraints(mech):  # the sliders' polynomial equations (symkin.constraints)
        eqs += [(eq.numerator, con.owner) for eq in con.equations(alg, X, X0)]
    eqs = [(sp.expand(e), o) for e, o in eqs if sp.expand(e) != 0]
    return _System(mech, coord, x0, eqs, frames, snap, affine)


def _distance(mech: Mechanism, coord: dict, snap: ModelSnap, link: str, p: str, q: str) -> sp.Expr:
    """``|x_q − x_p|² − L²``, ``L²`` snapped exactly: :meth:`symkin.constraints.Bar.polynomial`."""
    bar = bar_constraint(mech, link, p, q)
    alg = Sympy(squared_hook=lambda *_: snap.squared_length(link, p, q))
    # d = x_q − x_p (the equation is symmetric in the pair): the expressions of the closure as they were
    return bar.polynomial(alg, {bar.i: coord[p], bar.j: coord[q]}, {bar.i: None, bar.j: None})


def _algebra(snap: ModelSnap, x0: dict) -> Sympy:
    """The sympy algebra of the closure's constraints: points and directions snapped, a rigid pair's
    length its snapped length (exact: a rational square root, else a :class:`LociError`)."""
    def length(link, a, b, _d):
        square = snap.squared_length(link, a, b) if link else _dot(_sub(x0[b], x0[a]), _sub(x0[b], x0[a]))
        return _sqrt_rational(square, f"the length of {a}-{b}" + (f" (link {link})" if link else ""))

    return Sympy(point_hook=lambda v, what: tuple(snap.number(c, f"coordinate {AXES[a]} of the {what}")
                                                  for a, c in enumerate(v)),
                 direction_hook=lambda v, what: _snapped_vector(snap, v, what), length_hook=length)


def _snapped_vector(snap: ModelSnap, vec, what: str) -> tuple:
    """A direction or normal (``what``: "direction of slider s"), snapped relative to its norm."""
    which, _, rest = what.partition(" ")
    norm = math.sqrt(sum(float(v) ** 2 for v in vec))
    return tuple(snap.number(v, f"{which} {AXES[a]} {rest}", snap.mech.length_scale / norm) for a, v in enumerate(vec))


# ====================================================================== variables and holds
def _variable_symbol(mech: Mechanism, c: CoordinateLabel) -> sp.Symbol:
    p = c.parameter
    if p.kind == "velocity":
        return coordinate_symbol(AXES[c.axis], p.target[0])
    if p.kind == "rotation" and mech.dim == 2:
        return sp.Symbol(f"t_{p.target[0]}", real=True)
    if p.kind == "slide":
        return sp.Symbol(f"s_{p.target[0]}", real=True)
    raise LociError(f"{c.label}: a locus variable must be a node coordinate (velocity:<node>.<axis>), a planar "
                    "link rotation (rotation:<link>) or a slide (slide:<slider>)")


def _coordinate_equations(sys: _System, c: CoordinateLabel, value, hold: bool) -> list[tuple[sp.Expr, str]]:
    """Equations fixing coordinate ``c`` at ``value`` (a symbol for a variable, a number or None
    for the model's value when held); for a held rotation the link's distance equation is dropped
    (the direction fixes the vector)."""
    mech, p = sys.mech, c.parameter
    owner = f"{'hold' if hold else 'variable'} {c.label}"
    if p.kind == "velocity":
        node = p.target[0]
        if value is None:
            v = sys.x0[node][c.axis] if node in sys.snap.pivots else \
                sys.snap.number(float(sys.x0[node][c.axis]), f"held value of {c.label}")
        else:
            v = value if isinstance(value, sp.Basic) else _q(value)
        return [(sys.coord[node][c.axis] - v, owner)]
    if p.kind == "rotation" and mech.dim == 2:
        link = p.target[0]
        ns = mech.link_nodes(link)
        e = _sub(sys.coord[ns[1]], sys.coord[ns[0]])
        e0 = _sub(sys.x0[ns[1]], sys.x0[ns[0]])
        if hold:
            if value is None:
                target = tuple(sys.snap.number(float(v), f"held {AXES[a]} of link {link}'s vector")
                               for a, v in enumerate(e0))
            else:
                ll = math.sqrt(float(_dot(e0, e0)))
                target = (_q(ll * math.cos(value)), _q(ll * math.sin(value)))
                sys.equations = [(eq, o) for eq, o in sys.equations if o != f"link {link} ({ns[0]}-{ns[1]})"]
            return [(e[0] - target[0], owner), (e[1] - target[1], owner)]
        ll = _sqrt_rational(sys.snap.squared_length(link, ns[0], ns[1]),
                            f"{c.label} as a locus variable (link {link})")
        t = value  # the direction fixes the link's vector: its distance equation is implied
        sys.equations = [(eq, o) for eq, o in sys.equations if o != f"link {link} ({ns[0]}-{ns[1]})"]
        return [(e[0] * (1 + t ** 2) - ll * (1 - t ** 2), owner), (e[1] * (1 + t ** 2) - 2 * ll * t, owner)]
    if p.kind == "slide":  # the slider's own slide (symkin.constraints: slide_equation), exact
        con = slider_constraint(mech, p.target[0])
        alg = _algebra(sys.snap, sys.x0)
        try:
            eq = con.slide_equation(alg, [sys.coord[n] for n in mech.node_names])
            at_model = con.slide_equation(alg, [sys.x0[n] for n in mech.node_names])
        except SymkinError as exc:
            raise LociError(f"{c.label}: {exc}") from None
        scale = _sqrt_rational(eq.denominator ** 2, f"{c.label} ({con.owner})")
        if value is None:  # the model's slide (snapped, as a held node coordinate is)
            value = sys.snap.number(float(at_model.numerator / scale), f"held value of {c.label}")
        return [(eq.numerator - scale * (value if isinstance(value, sp.Basic) else _q(value)), owner)]
    raise LociError(f"{c.label}: only node coordinates, planar rotations and slides can be held or used as "
                    "locus variables here")


# ====================================================================== conditions in nodal coordinates
def _to_nodal(expr: sp.Expr, sm, sys: _System) -> sp.Expr:
    """A condition factor of the symbolic model (angle or nodal coordinates) as a polynomial
    in the free nodal coordinates: ``cos θ_L = (x_1 − x_0)/l_L``, ``sin θ_L = (y_1 − y_0)/l_L``
    (first → second node of L, valid on the closure) and ``s_S = (x_P − x_A)·(x_C − x_A)/l``."""
    mech = sys.mech
    expr = sm.substitute_design(expr)
    if sm.coordinates == "angles":
        expr = sp.expand(sp.expand_trig(expr))
        expr = sp.expand(expr.xreplace(_design_values(sys)))
        subs = {}
        for name, ns in mech.links:
            e = _sub(sys.coord[ns[1]], sys.coord[ns[0]])
            e0 = _sub(sys.x0[ns[1]], sys.x0[ns[0]])
            ll = sys.snap.length(name, ns[0], ns[1])
            th = sm.symbol(f"theta_{name}")
            subs[sp.cos(th)] = e[0] / ll
            subs[sp.sin(th)] = e[1] / ll
        for con in slider_constraints(mech):
            if isinstance(con, SliderMovingLine):
                s = con.slider
                a, b = s.line
                e = _sub(sys.coord[b], sys.coord[a])
                e0 = _sub(sys.x0[b], sys.x0[a])
                ll = sys.snap.length(s.link, a, b) if s.link else sp.sqrt(_dot(e0, e0))
                subs[sm.symbol(f"s_{s.id}")] = _dot(_sub(sys.coord[s.node], sys.coord[a]), e) / ll
        expr = expr.xreplace(subs)
    else:
        expr = expr.xreplace({coordinate_symbol(AXES[a], n): sys.x0[n][a] for n in mech.fixed
                              for a in range(mech.dim)})
    return _rational_primitive(sp.expand(expr), what="a condition factor")


def _design_values(sys: _System) -> dict:
    """The design symbols of a planar angle model (``l_<link>``, ``l_<link>_<i>_<j>``, and
    ``cos``, ``sin`` of ``beta_<link>_<i>_<j>``) at the snapped numbers the closure uses: a pair
    ``i → j`` of a body is ``Δa e + Δb e⊥`` in its frame (``e`` = first → second node, snapped
    length ``l``; ``Δa``, ``Δb`` of the snapped affine coordinates), so ``l_ij = l √(Δa² + Δb²)``
    and ``β_ij = atan2(Δb, Δa)``."""
    out: dict = {}
    for name, ns in sys.mech.links:
        l01 = sys.snap.length(name, ns[0], ns[1])
        out[length_symbol(name)] = l01
        frame = {ns[0]: (0, 0), ns[1]: (1, 0)}
        frame.update({m: sys.affine[(name, m)] for m in ns[2:] if (name, m) in sys.affine})
        for i, j in itertools.combinations(ns, 2):
            if (i, j) == (ns[0], ns[1]) or i not in frame or j not in frame:
                continue
            da, db = frame[j][0] - frame[i][0], frame[j][1] - frame[i][1]
            norm = sp.sqrt(da ** 2 + db ** 2)
            out[length_symbol(name, i, j)] = l01 * norm
            beta = offset_symbol(name, i, j)
            out[sp.cos(beta)], out[sp.sin(beta)] = da / norm, db / norm
    return out


def _rational_primitive(expr: sp.Expr, what: str) -> sp.Expr:
    """``expr`` divided by its leading coefficient, with rational coefficients: an irrational
    one (a model whose nodes are floats of irrational numbers) is taken at its float value."""
    if expr == 0:
        return expr
    gens = sorted(expr.free_symbols, key=lambda s: s.name)
    if not gens:
        return sp.Integer(1)
    poly = sp.Poly(expr, *gens)
    lc = poly.LC()
    terms = []
    for monom, coeff in poly.terms():
        c = sp.radsimp(coeff / lc)
        if not c.is_Rational:
            # irrational constants (sqrt(3) of a model built from cos 30°) against node coordinates
            # that are floats: the model is taken at its floats, as the closure is
            c = _q(float(c))
        terms.append(c * sp.Mul(*[g ** k for g, k in zip(gens, monom)]))
    p = sp.Poly(sp.Add(*terms), *gens, domain="QQ")
    return p.clear_denoms()[1].primitive()[1].as_expr()


# ====================================================================== elimination
def _is_const(e) -> bool:
    return e.is_number and e != 0


def _substitute_linear(equations: list, unknowns: list, limit) -> tuple[dict, list]:
    """Solve equations linear in an unknown with a constant coefficient; substitute them."""
    subs: dict = {}
    eqs = [sp.expand(e) for e, _ in equations]
    owners = [o for _, o in equations]
    changed = True
    while changed:
        changed = False
        for k, e in enumerate(eqs):
            _poll(limit)
            if e == 0:
                continue
            for u in unknowns:
                if u in subs or not e.has(u):
                    continue
                p = sp.Poly(e, u)
                if p.degree() == 1 and _is_const(p.LC()):
                    value = sp.expand(-p.coeff_monomial(1) / p.LC())
                    subs = {s: sp.expand(v.xreplace({u: value})) for s, v in subs.items()}
                    subs[u] = value
                    eqs = [sp.expand(q.xreplace({u: value})) for q in eqs]
                    changed = True
                    break
            if changed:
                break
    for e, owner in zip(eqs, owners):
        if e.is_number and e != 0:
            raise LociError(f"the equation of {owner} reduces to the nonzero constant {float(e):.3g} once the "
                            "variables, holds and the equations linear in one coordinate are substituted: either "
                            "the held values place no configuration, or that equation is redundant (a rigid link "
                            "with more nodes than fix it, a parallelogram) and the model's numbers, snapped to exact "
                            "values, make it disagree with the others by rounding")
    return subs, [e for e in eqs if e != 0]


def _blocks(eqs: list, unknowns: set) -> list[tuple[list, list]]:
    """Connected components of equations through shared unknowns: ``[(equations, unknowns)]``."""
    groups: list[tuple[list, set]] = []
    for e in eqs:
        mine = e.free_symbols & unknowns
        merged = [g for g in groups if g[1] & mine]
        keep = [g for g in groups if not (g[1] & mine)]
        new = ([e] + [q for g in merged for q in g[0]], set(mine).union(*[g[1] for g in merged]))
        groups = keep + [new]
    return [(g[0], sorted(g[1], key=lambda s: s.name)) for g in groups]


def _P(expr, gens) -> sp.Poly:
    return sp.Poly(expr, *gens, domain="QQ")


def _by_degree(p: sp.Poly, i: int) -> dict[int, sp.Poly]:
    """``p = Σ_k c_k · gen_i^k``: ``{k: c_k}`` (the ``c_k`` free of generator ``i``)."""
    parts: dict[int, dict] = {}
    for m, c in p.terms():
        parts.setdefault(m[i], {})[m[:i] + (0,) + m[i + 1:]] = c
    return {k: sp.Poly.from_dict(d, *p.gens, domain=p.domain) for k, d in parts.items()}


def _substitute(p: sp.Poly, i: int, value: sp.Poly, beta: sp.Poly) -> tuple[sp.Poly, int]:
    """``β^d · p(gen_i = value/β)`` with ``d = deg_i p``, and ``d``."""
    parts = _by_degree(p, i)
    d = max(parts) if parts else 0
    if d == 0:
        return p, 0
    out = p.mul_ground(0)
    for k, c in parts.items():
        out = out + c * value ** k * beta ** (d - k)
    return out, d


def _degree_in(e: sp.Poly, us: list) -> int:
    return max((sum(m[i] for i in us) for m in e.monoms()), default=0)


def _quadratic_part(e: sp.Poly, us: list) -> sp.Poly:
    """The terms of ``e`` of degree 2 in the unknowns ``us`` (coefficients in the other symbols)."""
    return sp.Poly.from_dict({m: c for m, c in e.terms() if sum(m[i] for i in us) == 2}, *e.gens,
                             domain=e.domain)


def _radical_axis(a: sp.Poly, b: sp.Poly, us: list) -> sp.Poly | None:
    """``c_b a − c_a b`` when the quadratic parts of ``a`` and ``b`` in ``us`` are proportional
    (``c_a``, ``c_b`` their coefficients of one quadratic monomial): an equation of degree 1."""
    qa, qb = _quadratic_part(a, us), _quadratic_part(b, us)
    if qa.is_zero or qb.is_zero:
        return None
    pivot = next(m for m in qa.monoms())
    # the coefficient of the pivot monomial of the unknowns, as a polynomial in the other symbols
    def coeff(q):
        key = tuple(pivot[k] if k in us else None for k in range(len(pivot)))
        return sp.Poly.from_dict({tuple(0 if k in us else m[k] for k in range(len(m))): c for m, c in q.terms()
                                  if all(m[k] == key[k] for k in us)}, *q.gens, domain=q.domain)
    ca, cb = coeff(qa), coeff(qb)
    if ca.is_zero or cb.is_zero or not (cb * qa - ca * qb).is_zero:
        return None
    out = cb * a - ca * b
    return None if out.is_zero else out


def _block_norm(f: sp.Poly, eqs: list, us: list, limit) -> tuple[sp.Poly, sp.Poly]:
    """``N(f) = Π f(branch)`` over the solutions of the square block ``eqs`` (polys) in the
    unknowns ``us`` (generator indices), as ``(numerator, denominator)`` (see the module docstring)."""
    us = list(us)
    gens = f.gens
    one = f.mul_ground(0) + 1
    den_power = []  # (β, power of β in f): divided out once per branch
    num = f
    while len(us) > 1:
        _poll(limit)

        done = False
        for i, j in itertools.combinations(range(len(eqs)), 2):
            combo = _radical_axis(eqs[i], eqs[j], us)
            if combo is not None:  # two circles through one node: their radical axis
                eqs[j] = combo
                done = True
                break
        pick = None
        for k, e in enumerate(eqs):
            if e.is_zero or _degree_in(e, us) != 1:
                continue
            for u in us:
                parts = _by_degree(e, u)
                beta = parts.get(1)
                if beta is not None and not beta.is_zero and (pick is None or len(beta.terms()) < len(pick[2].terms())):
                    pick = (k, u, beta, -parts.get(0, e.mul_ground(0)))
        if pick is None:
            if done:
                continue
            raise LociError(f"a block of {len(us)} unknowns ({', '.join(str(gens[i]) for i in us)}) has no "
                            "linear equation after differencing its circles; it is beyond this elimination")
        k, u, beta, value = pick
        eqs.pop(k)
        us.remove(u)
        eqs = [e2 for e2 in (_substitute(e, u, value, beta)[0] for e in eqs) if not e2.is_zero]
        num, d = _substitute(num, u, value, beta)
        den_power.append((beta, d))
    if not eqs:
        raise LociError("a block has fewer equations than unknowns: the variables and holds do not fix it")
    u = us[0]
    eqs = [e for e in eqs if e.degree(gens[u]) > 0]
    if not eqs:
        raise LociError(f"a block leaves {gens[u]} undetermined: the variables and holds do not fix it")
    q = min(eqs, key=lambda e: (e.degree(gens[u]), len(e.terms())))
    _poll(limit)
    order = (gens[u],) + tuple(g for k, g in enumerate(gens) if k != u)
    qq, gg = q.reorder(*order), num.reorder(*order)
    dq, dg = qq.degree(gens[u]), gg.degree(gens[u])
    if dg > 0:
        res = qq.resultant(gg)  # Res_u(q, g) = lc(q)^deg g · Π g(roots)
        res = sp.Poly.from_dict({m[:u] + (0,) + m[u:]: c for m, c in res.terms()}, *gens, domain=f.domain)
        den = _by_degree(q, u)[dq] ** dg
    else:
        res, den = num ** dq, one
    _poll(limit)
    for beta, d in den_power:
        den = den * beta ** (d * dq)
    return res, den


def _eliminate(g: sp.Expr, blocks: list, limit) -> sp.Expr:
    """The numerator of ``N(g)`` over every block that ``g`` (or what it became) touches."""
    gens = tuple(sorted(set().union(g.free_symbols, *[e.free_symbols for eqs, _ in blocks for e in eqs]),
                        key=lambda s: s.name))
    index = {s: k for k, s in enumerate(gens)}
    num = _P(g, gens)
    den = num.mul_ground(0) + 1
    for eqs, us in blocks:
        _poll(limit)
        idx = [index[u] for u in us]

        def touches(p):
            return any(p.degree(gens[i]) > 0 for i in idx)

        if not touches(num) and not touches(den):
            continue
        peqs = [_P(e, gens) for e in eqs]
        n1, d1 = _block_norm(num, list(peqs), idx, limit)
        if touches(den):
            n2, d2 = _block_norm(den, list(peqs), idx, limit)
            num, den = n1 * d2, d1 * n2
        else:
            num, den = n1, d1 * den ** _branch_count(peqs, idx)
    if num.is_zero:
        return sp.Integer(0)
    common = num.gcd(den)
    return num.exquo(common).as_expr()


def _branch_count(eqs, idx) -> int:
    """A bound on the number of a block's solutions (Bézout: the product of the degrees)."""
    return int(np.prod([_degree_in(e, idx) for e in eqs if not e.is_zero]))


# ====================================================================== meanings
def _length_names(sys: _System) -> list[tuple[sp.Expr, str]]:
    """Every length of a link's node pair (snapped, as the closure has it) with its symbol's name."""
    out = []
    planar = _design_values(sys) if sys.mech.dim == 2 else {}
    for name, ns in sys.mech.links:
        for i, j in itertools.combinations(ns, 2):
            sym = length_symbol(name) if (i, j) == (ns[0], ns[1]) else length_symbol(name, i, j)
            if sym in planar:
                value = planar[sym]
            elif (i, j) == (ns[0], ns[1]) or len(ns) == 2:
                value = sys.snap.length(name, i, j)
            else:
                d = _sub(sys.x0[j], sys.x0[i])
                value = sp.sqrt(_dot(d, d))
            out.append((value, sym.name))
    return out


def _meaning(f: sp.Expr, xs, sys: _System) -> tuple[str, bool]:
    """What the curve ``f(x, y) = 0`` is, and whether it is trivial (no real point)."""
    mech, x0 = sys.mech, sys.x0
    x, y = xs
    p = sp.Poly(f, x, y)
    d = p.total_degree()
    if d == 0:
        return "nonzero constant", True
    names = [str(v) for v in xs]
    if all(n.startswith("t_") for n in names):  # two tangent half-angles: relations of the two angles
        t1, t2 = xs
        l1, l2 = names[0][2:], names[1][2:]
        if sp.expand(f - (t1 - t2)) == 0 or sp.expand(f + (t1 - t2)) == 0:
            return f"theta_{l1} = theta_{l2} (links {l1} and {l2} parallel, same direction)", False
        if sp.expand(f - (t1 * t2 + 1)) == 0:
            return f"theta_{l1} = theta_{l2} + pi (links {l1} and {l2} parallel, opposite directions)", False
    if d == 1:
        return f"line {sp.sstr(f)} = 0", False
    c = {m: p.coeff_monomial(x ** m[0] * y ** m[1]) for m in itertools.product(range(d + 1), repeat=2)
         if sum(m) <= d}
    if d == 2:
        a, b, cc = c[(2, 0)], c[(1, 1)], c[(0, 2)]
        if b == 0 and a == cc:
            h, k = -c[(1, 0)] / (2 * a), -c[(0, 1)] / (2 * a)
            r2 = h ** 2 + k ** 2 - c[(0, 0)] / a
            where = _node_at(mech, x0, (h, k), xs)
            if r2 < 0:
                return f"circle of imaginary radius centred at {where}: no real point", True
            if r2 == 0:
                return f"the point {where} (a circle of radius 0: one real point)", False
            r = sp.sqrt(r2)
            centre = where.split()[1] if where.startswith("pivot ") else None
            return f"circle centred at {where}, radius {_radius_text(r, sys, centre)}", False
        disc = b ** 2 - 4 * a * cc
        kind = "ellipse" if disc < 0 else ("hyperbola" if disc > 0 else "parabola")
        return _points_only(f, xs, f"conic ({kind})", mech, x0)
    top = sp.Add(*[c[m] * x ** m[0] * y ** m[1] for m in c if sum(m) == d])
    if d % 2 == 0 and sp.expand(top - top.coeff(x, d) * (x ** 2 + y ** 2) ** (d // 2)) == 0:
        k = d // 2
        name = {3: "tricircular sextic (the class of Watt's curve)"}.get(k, f"{k}-circular curve of degree {d}")
        return _points_only(f, xs, name, mech, x0)
    return _points_only(f, xs, f"degree-{d} curve", mech, x0)


def _points_only(f, xs, name: str, mech, x0) -> tuple[str, bool]:
    """``name``, unless the factor has no real curve: then "no real point" (trivial) or its
    isolated real points, as a circle of radius 0 is named (:mod:`symkin.symbolic.real_points`)."""
    points = isolated_real_points(f, xs)
    if points is None:
        return name, False
    if not points:
        return f"{name} with no real point", True
    where = [_node_at(mech, x0, (exact(px), exact(py)), xs) for px, py in points]
    if len(where) == 1:
        return f"the point {where[0]} (a {name} with one real point)", False
    return f"the {len(where)} points {', '.join(where)} (a {name} with isolated real points only)", False


def _num(v) -> str:
    """A number for a meaning: exact when short (``19/4``, ``sqrt(2)``), else 6 digits."""
    text = sp.sstr(v)
    return text if len(text) <= 12 else f"{float(v):.6g}"


def _node_at(mech, x0, point, xs) -> str:
    """``"A1 (-1, 0)"`` when a node of the model (in the two variables' axes) is there."""
    txt = f"({_num(point[0])}, {_num(point[1])})"
    names = [str(s) for s in xs]
    if all(n[:2] in ("x_", "y_", "z_") for n in names):
        axes = [AXES.index(n[0]) for n in names]
        for node in mech.fixed:
            if all(x0[node][a] == point[k] for k, a in enumerate(axes)):
                return f"pivot {node} {txt}"
    return txt


def _radius_text(r, sys: _System, centre: str | None = None) -> str:
    """``"3 = l_crank1 + l_distal1"``: the radius as one length, or the sum or difference of
    two lengths of links in a chain from ``centre`` (a node) when there is one."""
    out = _num(r)
    lengths = _length_names(sys)
    links = dict(sys.mech.links)

    def score(pair):
        (_, n1), (_, n2) = pair
        a, b = n1[2:].split("_")[0], n2[2:].split("_")[0]
        chained = bool(set(links.get(a, ())) & set(links.get(b, ())))
        at_centre = centre is not None and (centre in links.get(a, ()) or centre in links.get(b, ()))
        return (not at_centre, not chained)

    candidates = []
    for (l1, n1), (l2, n2) in itertools.combinations(lengths, 2):
        if sp.simplify(l1 + l2 - r) == 0:
            candidates.append((score(((l1, n1), (l2, n2)))[0], 0 if not score(((l1, n1), (l2, n2)))[1] else 2,
                               f"{out} = {n1} + {n2}"))
        if sp.simplify(abs(l1 - l2) - r) == 0:
            candidates.append((score(((l1, n1), (l2, n2)))[0], 0 if not score(((l1, n1), (l2, n2)))[1] else 2,
                               f"{out} = |{n1} - {n2}|"))
    for ll, n in lengths:
        if sp.simplify(ll - r) == 0:
            candidates.append((centre is None or centre not in links.get(n[2:].split("_")[0], ()), 1, f"{out} = {n}"))
    if candidates:
        return min(candidates)[2]
    return out


# ====================================================================== the entry point
def _factors(poly: sp.Expr, xs, sys: _System, factor_list=sp.factor_list) -> tuple[list, list]:
    geometric, trivial = [], []
    _, fl = factor_list(sp.Poly(poly, *xs, domain="QQ"))
    for f, m in fl:
        expr = f.as_expr()
        lc = sp.Poly(expr, *xs).LC()
        if lc < 0:
            expr = sp.expand(-expr)
        meaning, is_trivial = _meaning(expr, xs, sys)
        item = LocusFactor(expr, int(sp.Poly(expr, *xs).total_degree()), meaning, int(m), is_trivial)
        (trivial if is_trivial else geometric).append(item)
    order = (lambda f: (f.degree, sp.default_sort_key(f.polynomial)))
    return sorted(geometric, key=order), sorted(trivial, key=order)


def implicit_loci(mech: Mechanism, variables=("velocity:P.x", "velocity:P.y"), hold=(),
                  kinds=KINDS, time_limit: float | None = 120.0, unit: str = "deg",
                  tolerances: Tolerances | float | None = None) -> Loci:
    """Singularity loci of ``mech`` as implicit polynomials in two coordinates (issue 9 §3).

    Parameters
    ----------
    mech : Mechanism
        Any model; planar conditions are derived in angle coordinates and rewritten in
        nodal ones, spatial ones in nodal coordinates.
    variables : (str, str)
        Two labels as ``symkin map --x/--y`` takes them: ``velocity:P.x`` (variable
        ``x_P``), ``rotation:L`` (``t_L = tan(θ_L/2)``, θ_L the direction of L's first node →
        second node), ``slide:S`` (``s_S``).
    hold : sequence of str or (str, float | None)
        The ``F − 2`` held coordinates: ``"LABEL"`` (the model's value), ``"LABEL=VALUE"``
        or ``(label, value)``; angle values in ``unit``.
    kinds : sequence of str
        Which loci: ``"DKP-input"``, ``"DKP-output"``, ``"IM"`` (IM needs the others).
    time_limit : float or None
        Seconds per locus (condition and elimination); past it the locus is skipped with a
        message naming it (``Loci.skipped``).  None: no limit.
    tolerances : Tolerances, optional
        The rank tolerance of the check that the variables and holds fix the mechanism.

    Returns
    -------
    Loci
        ``loci[kind].factors``: the geometric factors (primitive integer polynomials), each
        with its degree and meaning; ``trivial`` the separated ones.

    Examples
    --------
    The five-bar's type-1 (DKP-output) locus: the circles ``|P − A_i| = l1 ± l2`` (§III-B).

    >>> from symkin.model.catalogue import get
    >>> loci = implicit_loci(get("five_bar"), kinds=("DKP-output",))
    >>> for f in loci["DKP-output"].factors:
    ...     print(f.polynomial, "|", f.meaning)
    x_P**2 - 2*x_P + y_P**2 | circle centred at pivot A2 (1, 0), radius 1 = |l_crank2 - l_distal2|
    x_P**2 + 2*x_P + y_P**2 | circle centred at pivot A1 (-1, 0), radius 1 = |l_crank1 - l_distal1|
    x_P**2 - 2*x_P + y_P**2 - 8 | circle centred at pivot A2 (1, 0), radius 3 = l_crank2 + l_distal2
    x_P**2 + 2*x_P + y_P**2 - 8 | circle centred at pivot A1 (-1, 0), radius 3 = l_crank1 + l_distal1
    """
    from symkin.symbolic.model import symbolic_model

    if unit not in UNITS:
        raise SymkinError(f"unknown angle unit {unit!r}; use one of {', '.join(UNITS)}")
    if len(variables) != 2:
        raise SymkinError(f"--in needs two labels LABEL_X,LABEL_Y, got {len(variables)}: {', '.join(variables)}")
    unknown = [k for k in kinds if k not in KINDS]
    if unknown:
        raise SymkinError(f"unknown locus kind(s) {', '.join(unknown)}; use {', '.join(KINDS)}")
    tol = Tolerances.of(tolerances)
    coords = [parse_label(mech, v, "coordinate", _LOCUS_LABELS) for v in variables]
    pairs = parse_holds(hold)
    held = [parse_orientation_label(mech, label) or parse_label(mech, label, "coordinate", _LOCUS_LABELS)
            for label, _ in pairs]
    labels = [c.label for c in coords + held]
    twice = sorted({lab for lab in labels if labels.count(lab) > 1})
    if twice:
        raise SymkinError(f"{', '.join(twice)} named twice (as variable or hold); each coordinate can be fixed once")
    f = mech.mobility_value
    if f < 2:
        raise SymkinError(f"{mech.name}: F = {f}: the configurations of a mechanism with fewer than 2 degrees of "
                          "freedom do not fill a plane of two coordinates, so there is no singularity curve in "
                          "it (its singular configurations are isolated points: symkin singularities MODEL "
                          "finds them all for F = 1)")
    if len(held) != f - 2:
        raise SymkinError(f"{mech.name}: F = {f}, so two variables need {f - 2} held coordinate(s) (--hold LABEL); "
                          f"{len(held)} given")
    if any(isinstance(h, OrientationLabel) for h in held):
        from symkin.symbolic.pose_loci import pose_slice
        ps = pose_slice(mech, coords, [(h, v) for h, (_, v) in zip(held, pairs)], UNITS[unit])
        return _pose_loci(mech, ps, coords, held, kinds, time_limit, tol)
    if mech.dim == 3:
        from symkin.symbolic.pose_loci import translation_slice
        ps = translation_slice(mech, coords, [(h, v) for h, (_, v) in zip(held, pairs)], tol.geometry)
        if ps is not None:
            return _pose_loci(mech, ps, coords, held, kinds, time_limit, tol)
    sys = _build(mech, snap_model(mech, tol))
    xs = tuple(_variable_symbol(mech, c) for c in coords)
    extra = []
    for c, s in zip(coords, xs):
        extra += _coordinate_equations(sys, c, s, hold=False)
    for c, (_, v) in zip(held, pairs):
        value = None if v is None else v * (UNITS[unit] if c.kind == "angle" else 1.0)
        extra += _coordinate_equations(sys, c, value, hold=True)
    equations = sys.equations + extra
    free = [s for n in mech.free_nodes for s in sys.coord[n]]
    unknowns = [s for s in free if s not in xs]
    _check_square(sys, equations, unknowns + list(xs), coords, held, tol)
    subs, rest = _substitute_linear(equations, unknowns, None)
    remaining = set(unknowns) - set(subs)
    blocks = _blocks(rest, remaining)

    # planar: lengths and body angles kept as symbols, given the snapped values of the closure
    sm = symbolic_model(mech, coordinates="angles" if mech.dim == 2 else "nodes", design_symbols=mech.dim == 2)
    loci: list[Locus] = []
    skipped: list[str] = []
    for kind in [k for k in KINDS if k in kinds]:
        t0 = time.perf_counter()
        try:
            with _limit(kind, time_limit) as limit:
                if kind == Kind.IM:
                    locus = _im_locus(sm, sys, subs, blocks, xs, loci, time_limit, limit, t0)
                else:
                    locus = _dkp_locus(sm, sys, subs, blocks, xs, kind, time_limit, limit, t0)
        except DerivationTimeout as exc:
            skipped.append(str(exc) if "locus" in str(exc) else f"{kind} locus: {exc}")
            continue
        except (LociError, SymkinError) as exc:
            skipped.append(f"{kind} locus: {exc}")
            continue
        loci.append(locus)
    return Loci(xs, tuple(c.label for c in coords), tuple(c.label for c in held), tuple(loci), tuple(skipped),
                mech.name, sys.snap)


def _pose_loci(mech, ps, coords, held, kinds, time_limit, tol) -> Loci:
    """The loci of a spatial platform at a held orientation (:mod:`symkin.symbolic.pose_loci`)."""
    from symkin.symbolic.model import symbolic_model
    from symkin.symbolic.pose_loci import constraint_condition, eliminate_arms, factor_list, pose_condition

    xs = ps.variables
    face = {n: tuple(_q(v) for v in xyz) for n, xyz in mech.nodes}
    snap = snap_model(mech, tol)
    sys = _System(mech, {}, face, [], {}, snap)
    sm = symbolic_model(mech, coordinates="nodes")
    loci: list[Locus] = []
    skipped: list[str] = []
    for kind in [k for k in KINDS if k in kinds]:
        t0 = time.perf_counter()
        if kind == Kind.IM:
            text = ("no curve: every configuration of the slice is placed by the pose, each leg node in closed "
                    "form where its leg has a length (|C - A| > 0), and moves with the platform's six twists: "
                    "L = F on the slice")
            if not ps.legs:
                loci.append(Locus(kind, (), (), time.perf_counter() - t0, text))
                continue
        try:
            with _limit(kind, time_limit) as limit:
                if kind == Kind.IM:  # a translating platform: where it can also turn (its parallelograms)
                    det, contents = constraint_condition(ps), ()
                else:
                    det, contents = pose_condition(sm, ps, kind)
                _poll(limit)
                if ps.legs and kind == Kind.DKP_OUTPUT and det.is_number and det != 0:
                    # outputs locked (the platform still): arm i turns alone where its bar is normal to its motion
                    det = sp.Mul(*[eliminate_arms(den, ps, lambda: _poll(limit))[0] for _, den in ps.arm_rows])
                eliminated = ps.legs and det != 0 and any(det.has(leg.c, leg.s) for leg in ps.legs)
                if eliminated:
                    det, _ = eliminate_arms(det, ps, lambda: _poll(limit))  # its divided-out factors are no locus
                if det == 0:
                    loci.append(Locus(kind, (), (), time.perf_counter() - t0,
                                      "the condition holds on the whole slice", True))
                    continue
                total = sp.Mul(det, *contents)
                geometric, trivial = (_with_normalised(fs, xs) for fs in _factors(total, xs, sys, factor_list))
        except DerivationTimeout as exc:
            text = str(exc) if "locus" in str(exc) else f"{kind} locus: {exc}"
            if ps.legs:
                text += ("; the arms' elimination grows with the digits of the model's numbers (exact rationals of "
                         "its floats)")
            skipped.append(text)
            continue
        except (LociError, SymkinError) as exc:
            skipped.append(f"{kind} locus: {exc}")
            continue
        which = kind.split("-")[1] if kind != Kind.IM else ""
        if ps.legs and kind == Kind.IM:
            note = (f"det[w_i x u_i] = 0: the moments of the three parallelograms (u_i along an arm's bar, w_i "
                    f"its side on {ps.link!r}) dependent, where {ps.link!r} can also turn (a motion more than "
                    f"the mobility, with the inputs locked); each arm's angle eliminated as for DKP-input: "
                    f"every working mode's curve")
        elif ps.legs and kind == Kind.DKP_OUTPUT:
            note = (f"{ps.link!r} still (outputs locked): arm i turns alone where (C_i - B_i).(dB_i/dtheta_i)"
                    f" = 0, its angle eliminated with its closure (resultant); one factor set per arm")
        elif ps.legs:
            note = (f"det(P V) = 0: the {which} rows over the translation of {ps.link} (its parallelograms keep "
                    f"its orientation), each arm's nodes in (cos, sin) of its angle, the angles eliminated with "
                    f"the arms' closures (resultants; powers of each closure's cos coefficient and of q^2 + E p^2 "
                    f"divided out): every working mode's curve; zero where a motion is left with the {which}s "
                    f"locked")
        else:
            note = (f"det(P V) = 0: the {which} rows over the platform's twist at {ps.node} (orientation of "
                    f"{ps.link} held), each leg placed in closed form; zero where a motion is left with the "
                    f"{which}s locked")
        loci.append(Locus(kind, tuple(geometric), tuple(trivial), time.perf_counter() - t0, note))
    return Loci(xs, tuple(c.label for c in coords), tuple(h.label for h in held), tuple(loci), tuple(skipped),
                mech.name, None)


def _with_normalised(factors: list, xs) -> list:
    """Factors whose integer coefficients are long get their monic form (6 digits) in the meaning."""
    out = []
    for f in factors:
        p = sp.Poly(f.polynomial, *xs)
        if max(len(str(abs(c))) for c in p.coeffs()) > 12:
            lc = max(p.coeffs(), key=abs)
            text = " + ".join(f"{float(c / lc):.6g}*{sp.sstr(sp.Mul(*[g ** k for g, k in zip(xs, m)]))}"
                              for m, c in p.terms()).replace("*1 ", " ").replace("+ -", "- ")
            text = text[:-2] if text.endswith("*1") else text
            f = LocusFactor(f.polynomial, f.degree, f"{f.meaning}; normalised: {text}", f.exponent, f.trivial)
        out.append(f)
    return out


def _check_square(sys, equations, symbols, coords, held, tol: Tolerances) -> None:
    """The variables and holds must fix the mechanism: the equations' Jacobian in the free
    coordinates (and variables) has full rank at the model's configuration."""
    mech = sys.mech
    values = {s: float(sys.x0[n][a]) for n in mech.free_nodes for a, s in enumerate(sys.coord[n])}
    # variable values at the model: solve each variable's equations for it numerically
    eqs = [e for e, _ in equations]
    for s in symbols:
        if s not in values:
            own = [e for e in eqs if e.has(s) and e.free_symbols <= set(values) | {s}]
            roots = [complex(r) for r in sp.Poly(own[0].xreplace(values), s).nroots()] if own else []
            real = [r.real for r in roots if abs(r.imag) < 1e-9 and
                    all(abs(float(e.xreplace(values).xreplace({s: r.real}))) < 1e-9 for e in own)]
            values[s] = real[0] if real else 0.0
    jac = np.array([[float(sp.diff(e, s).xreplace(values)) for s in symbols] for e in eqs], dtype=float)
    rank = len(independent_rows(jac, tol.rank)) if jac.size else 0
    # the variables are free: the Jacobian in (unknowns, variables) minus the 2 variable columns must be regular
    n_unknown = len(symbols) - 2
    sub = jac[:, :n_unknown]
    rank_u = len(independent_rows(sub, tol.rank)) if sub.size else 0
    if rank_u < n_unknown or rank < n_unknown:
        names = ", ".join(c.label for c in list(coords) + list(held))
        raise SymkinError(f"{mech.name}: the variables and holds ({names}) do not fix the mechanism: they are not "
                          "independent coordinates of its configuration (the position problem is singular)")


def _condition_polys(cond, sm, sys, subs) -> list[sp.Expr]:
    out = []
    for fac in cond.geometric_factors:
        g = _to_nodal(fac.expr, sm, sys)
        g = sp.expand(g.xreplace(subs))
        if g != 0:
            out.append(g)
        else:
            out.append(sp.Integer(0))
    return out


def _dkp_locus(sm, sys, subs, blocks, xs, kind, time_limit, limit, t0) -> Locus:
    which = kind.split("-")[1]
    cond = sm.dkp_condition(which, time_limit=time_limit)
    if cond.identically_zero:
        return Locus(kind, (), (), time.perf_counter() - t0, "the condition holds at every configuration", True)
    total = sp.Integer(1)
    for g in _condition_polys(cond, sm, sys, subs):
        _poll(limit)
        if g == 0:
            return Locus(kind, (), (), time.perf_counter() - t0,
                         "a factor vanishes on the whole slice (every configuration with these holds)", True)
        total = total * _eliminate(g, blocks, limit)
    if total == 0:
        return Locus(kind, (), (), time.perf_counter() - t0, "the condition holds on the whole slice", True)
    geometric, trivial = _factors(total, xs, sys)
    note = (f"zero where some motion is left with the {which}s locked (and at every IM configuration)")
    return Locus(kind, tuple(geometric), tuple(trivial), time.perf_counter() - t0, note)


def _one_real_point(f, xs) -> bool:
    """Whether the factor ``f`` has one real point and no real curve: ``a((x − h)² + (y − k)²)`` (a
    circle of radius 0), or any factor with one isolated real point (:func:`isolated_real_points`)."""
    x, y = xs
    p = sp.Poly(f, x, y)
    if p.total_degree() != 2:
        points = isolated_real_points(f, xs)
        return points is not None and len(points) == 1
    a, b, cc = (p.coeff_monomial(m) for m in (x ** 2, x * y, y ** 2))
    if b != 0 or a != cc or a == 0:
        points = isolated_real_points(f, xs)
        return points is not None and len(points) == 1
    h, k = -p.coeff_monomial(x) / (2 * a), -p.coeff_monomial(y) / (2 * a)
    return sp.simplify(h ** 2 + k ** 2 - p.coeff_monomial(1) / a) == 0


def _im_locus(sm, sys, subs, blocks, xs, done: list, time_limit, limit, t0) -> Locus:
    dkp = {l.kind: l for l in done}
    if Kind.DKP_INPUT in dkp and Kind.DKP_OUTPUT in dkp:
        a = {sp.srepr(f.polynomial) for f in dkp[Kind.DKP_INPUT].factors}
        shared = [f for f in dkp[Kind.DKP_OUTPUT].factors if sp.srepr(f.polynomial) in a]
        curves = [f for f in shared if not _one_real_point(f.polynomial, xs)]
        if not curves:
            which = "share no factor" if not shared else "share only factors with one real point each"
            return Locus(Kind.IM, (), (), time.perf_counter() - t0,
                         f"no curve: the IM locus lies in the DKP-input and DKP-output loci, which {which} "
                         "(isolated IM points are not listed)")
    cond = sm.im_condition(time_limit=time_limit)
    if cond.identically_zero:
        return Locus(Kind.IM, (), (), time.perf_counter() - t0, "IM at every configuration", True)
    if not cond.minors:
        raise LociError("the IM condition was derived as one Gram determinant (no minors): its locus "
                        "is not eliminated here")
    if len(cond.minors) > MAX_IM_MINORS:
        raise LociError(f"the IM condition has {len(cond.minors)} distinct maximal minors (more than "
                        f"{MAX_IM_MINORS}); their common zeros are not eliminated here")
    minors = [_to_nodal(m, sm, sys) for m in cond.minors]  # each primitive over the rationals
    minors = [sp.expand(m.xreplace(subs)) for m in minors]
    rng = random.Random(0)
    norms = []
    for _ in range(2):  # two random combinations of the minors
        combo = sp.expand(sp.Add(*[rng.randint(1, 97) * m for m in minors]))
        _poll(limit)
        norms.append(_eliminate(combo, blocks, limit) if combo != 0 else sp.Integer(0))
    common = sp.gcd(norms[0], norms[1])
    if common == 0:
        return Locus(Kind.IM, (), (), time.perf_counter() - t0, "IM on the whole slice", True)
    geometric, trivial = _factors(common, xs, sys)
    return Locus(Kind.IM, tuple(geometric), tuple(trivial), time.perf_counter() - t0,
                 "curves on which every maximal minor of the velocity equation vanishes on some branch "
                 "(gcd of the norms of two random combinations of the minors; isolated IM points are not listed)")
