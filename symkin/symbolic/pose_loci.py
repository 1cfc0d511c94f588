"""Singularity loci of a spatial platform at a held orientation, in its pose coordinates (issue 17 §5).

``symkin conditions MODEL --in velocity:O.x,velocity:O.y --hold velocity:O.z --hold
'rotation:platform[x]' --hold 'rotation:platform[y]' --hold 'rotation:platform[z]'`` (O a node
of the platform link): the holds enter the velocity problem *before* any determinant is
formed.  The configuration is written in the platform's pose: ``O = (x, y, z_h)`` and every
platform node ``X_n = O + R_h (X_n⁰ − O⁰)`` (``R_h`` the held rotation from the model's
orientation, the rotation vector of :class:`symkin.model.labels.OrientationLabel`), so each
is linear in ``(x, y)``.  The motion space is parametrised by the platform's twist
``(v, ω)`` at O: a platform node moves with ``v + ω × (X_n − O)``.  A leg node that is not on
the platform — the far end ``D`` of a bar ``A-D`` from a fixed joint ``A`` that carries the
line of a slider whose node ``C`` is on the platform (a prismatic leg) — is
``D = A + λ (C − A)`` with ``λ² |C − A|² = l²``, and moves with
``λ (Ċ − u (u·Ċ)/(u·u))``, ``u = C − A``.  These columns ``V`` span the motion space.

The DKP condition of the inputs (type 2) is then ``det(P V) = 0``, ``P`` the model's input
rows over the nodal velocities (the one definition, :mod:`symkin.symbolic.rows`): a 6 × 6
determinant whose rows are polynomials in ``(x, y)`` once ``λ`` is reduced with its
relation (``λ²`` → ``l²/(u·u)``) and each row's content (a product of nonzero factors such
as ``u·u`` and ``λ``) is taken out; the contents' factors are kept as factors of the locus
(a trivial one has no real point).  For a Gough–Stewart platform the rows are the legs'
Plücker lines ``(u_k, (C_k − O) × u_k)`` and the locus is the cubic of Mayer St-Onge &
Gosselin (2000) for a general 6-6, a conic when the base joints are coplanar (the plane of
constant height parallel to theirs).  The DKP condition of the outputs is ``det(P_out V)``
likewise.  The IM locus is not derived on this route (``V`` has full rank wherever the pose
places the mechanism; an IM configuration needs ``|C − A| = 0``).

A platform held to translation (a Delta: three arms on fixed axes, each joined to it by a
parallelogram of two bars; :func:`translation_slice`) is sliced at a held height with no
orientation hold: ``V`` is its translation, each arm's nodes are written in ``(c, s)`` of its
angle (:class:`ArmLeg`) and move with the platform through their bar.  ``det(P V)`` is then
linear in each arm's ``(c, s)``, and :func:`eliminate_arms` removes the angles with the arms'
closures, leaving one polynomial in ``(x, y)`` that holds every working mode's type-2 curve (the
norm of ``det`` over both placements of every arm: the product over the 8 working modes, times
powers of nonzero factors).

Elimination by values
---------------------
The norm is computed at integer points ``(x, y)`` and interpolated
(:func:`_eliminate_by_values`, the default): with ``x``, ``y`` numbers, each arm's step is a
resultant of a quadratic in ``s`` with a polynomial in the other arms' ``(c, s)`` only, all points
at once (numpy arrays of integers, exact); a degree bound comes from the same steps on degrees, the
result is interpolated on a triangle of ``(n + 1)(n + 2)/2`` points (``n = 48``: 1225) and checked
at points off it.  The symbolic elimination (:func:`_eliminate_by_resultants`) swells: its
intermediate polynomials in ``x, y`` and the other arms' ``(c, s)`` carry the data's digits in every
coefficient.  Measured on the 120° Delta of ``tests/workspace/truth.py`` (16-digit cos/sin of
120°, 240°, arm angles from ``arccos``; 2 shared cores): resultants 1 s, 32 s and 85 s for the three
arms; by values 1.2 s for the norm at 1225 points, about 2.5 s in all (``benchmarks/bench_delta_locus.py``).
The curve is the same (tested: proportional polynomials on ``examples/delta.json``).

sympy then factors the degree-48 polynomial (coefficients of ~950 digits) by Wang's algorithm,
whose search for a prime above the Mignotte bound alone took 25 s; :func:`factor_list` first
certifies irreducibility (distinct-degree factorisations of ``F(x, a)`` modulo small primes,
0.4 s) and leaves only polynomials it cannot certify to sympy.  ``symkin conditions`` on that
Delta: 5–8 s in all (it stopped at its 120 s limit before, the DKP-input locus not derived).

Choices weighed (issue 17 §5): snapping the model's numbers first
(:mod:`symkin.symbolic.snapping`) does not serve this route: its numbers are node coordinates
(axes, arm and platform offsets), each snapped to its own denominator near 10³ (711, 811, 1142,
…) whose common multiple exceeds the floats' common 10¹⁶, and the parallelogram check (each arm's
two closures equal to the geometry tolerance) already fails on coordinates snapped at 2e-7 of the
length scale.  python-flint (``fmpz_mpoly``) was not needed, and installing it switches sympy's
ground types for the whole process.  Fewer eliminations: the chain already uses the rows' arm-wise
structure (one 2 × 2 resultant per arm); the cost was the symbolic swell, not their number.

IM: where the three parallelograms' moments ``wᵢ × uᵢ`` are dependent the platform can also turn
(:func:`constraint_condition`; eliminated the same way, one curve of degree 48).

The numbers are the model's as written (exact rationals of its floats, no snapping): the
locus does not rest on rational relations between them, and it equals the float model's
locus exactly (a model in mm is not exactly 1000 times the one in m once its floats are rounded:
the same curve to the rounding, tested on the roots).
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.model.labels import CoordinateLabel, OrientationLabel
from symkin.model.mechanism import AXES, Mechanism
from symkin.symbolic.symbols import coordinate_symbol, length_symbol
from symkin.symbolic.symbols import decimal_rational as _q
from symkin.tolerances import Tolerances

__all__ = ["ArmLeg", "PoseSlice", "constraint_condition", "eliminate_arms", "factor_list", "pose_condition", "pose_rows",
           "pose_slice", "translation_slice"]


def _rotation(vector) -> list[list[float]]:
    """Rodrigues: the rotation matrix of the rotation vector ``θ·n`` (radians)."""
    th = math.sqrt(sum(c * c for c in vector))
    if th == 0.0:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    n = [c / th for c in vector]
    k = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]]
    kk = [[sum(k[i][m] * k[m][j] for m in range(3)) for j in range(3)] for i in range(3)]
    s, c = math.sin(th), 1.0 - math.cos(th)
    return [[(1.0 if i == j else 0.0) + s * k[i][j] + c * kk[i][j] for j in range(3)] for i in range(3)]


class PoseSlice:
    """The slice of a spatial mechanism at a held platform orientation and height, in its pose.

    Attributes: ``link`` (the platform), ``node`` (O, whose coordinates are the variables and
    the held one), ``variables`` (the two symbols ``x_O``, ``y_O``), ``position`` (node → its
    exact position, polynomials in the variables and the leg symbols ``lam_<node>``),
    ``velocity`` (node → 3 × 6 matrix: its velocity over the platform twist ``(v, ω)`` at O, with
    the denominators ``den`` of leg nodes), ``relations`` (``lam`` → ``(l², u·u)``).
    """

    def __init__(self, mech: Mechanism, link: str, node: str, coords: list[CoordinateLabel],
                 height: CoordinateLabel, height_value, rotation_vector, arms: list[str] | None = None,
                 geometry: float | None = None):
        self.mech, self.link, self.node = mech, link, node
        self.geometry = Tolerances().geometry if geometry is None else geometry
        self.legs: list[ArmLeg] = []
        self.arm_rows: list = []  # (leg, (C − B)·τ): zero where the arm turns with the platform still
        face = {n: tuple(_q(v) for v in xyz) for n, xyz in mech.nodes}
        self.face = face
        self.variables = tuple(coordinate_symbol(AXES[c.axis], node) for c in coords)
        o = list(face[node])
        for c, s in zip(coords, self.variables):
            o[c.axis] = s
        o[height.axis] = face[node][height.axis] if height_value is None else _q(height_value)
        rot = _rotation(rotation_vector)
        turned = any(v != 0.0 for v in rotation_vector)
        platform = set(mech.link_nodes(link))
        self.position: dict = {}
        self.velocity: dict = {}
        self.den: dict = {}
        self.relations: dict = {}
        for n in mech.fixed:
            self.position[n] = sp.Matrix(face[n])
        for n in platform:
            d0 = [face[n][a] - face[node][a] for a in range(3)]
            if turned:
                d0 = [_q(sum(rot[a][b] * float(d0[b]) for b in range(3))) for a in range(3)]
            d = sp.Matrix(d0)
            self.position[n] = sp.Matrix(o) + d
            skew = sp.Matrix([[0, d[2], -d[1]], [-d[2], 0, d[0]], [d[1], -d[0], 0]])  # ω × d = −[d]× ω
            self.velocity[n] = sp.eye(3) if arms else sp.Matrix.hstack(sp.eye(3), skew)
            self.den[n] = sp.Integer(1)
        for k, arm in enumerate(arms or ()):
            self._arm(arm, k + 1, face, platform)
        for n in mech.free_nodes if not arms else ():
            if n in platform:
                continue
            self._leg_node(n, face)

    def _arm(self, arm: str, k: int, face, platform) -> None:
        """The nodes of an arm turning about its two fixed nodes, over the platform's translation."""
        mech = self.mech
        fixed = set(mech.fixed)
        ns = mech.link_nodes(arm)
        a, a2 = [n for n in ns if n in fixed]
        free = [n for n in ns if n not in fixed]
        c, s = sp.symbols(f"c_{k} s_{k}", real=True)
        e = sp.Matrix([face[a2][i] - face[a][i] for i in range(3)])
        e2 = e.dot(e)
        pa = sp.Matrix(face[a])
        taus = {}
        for n in free:
            d = sp.Matrix([face[n][i] - face[a][i] for i in range(3)])
            par = e * (e.dot(d) / e2)
            perp = d - par
            w = e.cross(d)
            self.position[n] = pa + par + c * perp + s * w
            taus[n] = -s * e2 * perp + c * w  # |e| dB/dθ
        bars = [(n, m) for name, ends in mech.links if len(ends) == 2
                for n, m in (ends, ends[::-1]) if n in free and m in platform]
        if len(bars) < 2:
            raise _NotTranslating(f"arm {arm!r} has {len(bars)} bar(s) to {self.link!r}, not a parallelogram")
        leg = None
        for n, m in bars:
            l2 = sum((face[m][i] - face[n][i]) ** 2 for i in range(3))
            u = self.position[m] - self.position[n]
            probe = ArmLeg(arm, c, s, e2, sp.Integer(0))
            closure = probe.reduce(u.dot(u) - l2)
            if leg is None:
                leg = ArmLeg(arm, c, s, e2, closure)
                n0, u0 = n, u
            elif _differ(closure - leg.closure, (c, s), self.variables, mech.length_scale, self.geometry):
                raise _NotTranslating(f"the bars of arm {arm!r} to {self.link!r} do not form a parallelogram")
        leg.bars = bars
        self.legs.append(leg)
        # θ̇ |e|-scaled: μ = u·v / (u·τ), u = C − B of the first bar; each arm node moves with μ τ
        den = leg.reduce(u0.dot(taus[n0]))
        self.arm_rows.append((leg, den))
        for n in free:
            self.velocity[n] = (taus[n] * u0.T).applyfunc(sp.expand)
            self.den[n] = den

    def _leg_node(self, n: str, face) -> None:
        """``D = A + λ (C − A)``: the end of a bar from a fixed joint carrying a slider's line to the platform."""
        mech = self.mech
        fixed = set(mech.fixed)
        for s in mech.sliders:
            if s.line is None or n not in s.line or s.node not in self.velocity:
                continue
            a = s.line[0] if s.line[1] == n else s.line[1]
            if a not in fixed:
                continue
            bar = [name for name, ns in mech.links if set(ns) == {a, n}]
            if not bar:
                continue
            e0 = [face[n][k] - face[a][k] for k in range(3)]
            l2 = sum(c * c for c in e0)
            lam = sp.Symbol(f"lam_{n}", positive=True)
            pa, pc = self.position[a], self.position[s.node]
            u = pc - pa
            uu = sp.expand(u.dot(u))
            self.position[n] = pa + lam * u
            vc = self.velocity[s.node]  # Ċ over the twist
            # Ḋ·(u·u) = λ ((u·u) Ċ − u (u·Ċ)): D keeps its distance l from A on the line A-C
            self.velocity[n] = (lam * (uu * vc - u * (u.T * vc))).applyfunc(sp.expand)
            self.den[n] = uu
            self.relations[lam] = (l2, uu, bar[0])
            return
        raise SymkinError(f"node {n} is neither on the platform {self.link!r} nor the end of a bar from a fixed "
                          "joint that carries a slider's line to the platform: the pose route places legs of "
                          "prismatic (SPS, UPS) type only")

    def substitutions(self) -> dict:
        """Node coordinate symbols → their expressions in the pose."""
        out = {}
        for n, p in self.position.items():
            for a in range(3):
                out[coordinate_symbol(AXES[a], n)] = p[a]
        return out


def pose_slice(mech: Mechanism, coords: list[CoordinateLabel], holds: list, unit_factor: float) -> PoseSlice | None:
    """The pose slice named by ``coords`` (two labels) and ``holds`` (``(label object, value)``), or
    None when the holds do not hold a spatial link's whole orientation.

    ``holds`` pairs a :class:`CoordinateLabel` or :class:`OrientationLabel` with its value in the
    user's unit (None: the model's).  The variables must be two coordinates of one node O of the
    held link; the third held.
    """
    orient = [(h, v) for h, v in holds if isinstance(h, OrientationLabel)]
    if mech.dim != 3 or not orient:
        return None
    links = {h.link for h, _ in orient}
    if len(links) != 1 or sorted(h.axis for h, _ in orient) != [0, 1, 2]:
        raise SymkinError("a locus at constant orientation holds all three components rotation:<link>[x], "
                          "rotation:<link>[y], rotation:<link>[z] of one link; got "
                          + ", ".join(h.label for h, _ in orient))
    link = links.pop()
    others = [(h, v) for h, v in holds if not isinstance(h, OrientationLabel)]
    nodes = {c.parameter.target[0] for c in coords if c.parameter.kind == "velocity"}
    if len(nodes) != 1 or len(coords) != 2 or any(c.parameter.kind != "velocity" for c in coords):
        raise SymkinError(f"at a held orientation of {link!r} the two variables are coordinates of one of its "
                          "nodes (velocity:O.x,velocity:O.y)")
    node = nodes.pop()
    if node not in mech.link_nodes(link):
        raise SymkinError(f"node {node} is not a node of the held link {link!r}")
    third = [(c, v) for c, v in others if c.parameter.kind == "velocity" and c.parameter.target[0] == node
             and c.axis not in {k.axis for k in coords}]
    if len(others) != 1 or len(third) != 1:
        raise SymkinError(f"at a held orientation of {link!r} the holds are its three orientation components and "
                          f"the third coordinate of {node} (e.g. velocity:{node}.z); got "
                          + ", ".join(h.label for h, _ in holds))
    height, hv = third[0]
    vec = [0.0, 0.0, 0.0]
    for h, v in orient:
        vec[h.axis] = 0.0 if v is None else float(v) * unit_factor
    return PoseSlice(mech, link, node, coords, height, hv, vec)


def _reduce_lambda(entries: list, relations: dict) -> list:
    """``λ² → l²/(u·u)`` in a row (the same power of ``u·u`` multiplies every entry); an odd power
    common to the row is taken out."""
    for lam, (l2, uu, _) in relations.items():
        if not any(e.has(lam) for e in entries):
            continue
        polys = [sp.Poly(e, lam) for e in entries]
        top = max(p.degree() // 2 for p in polys)
        out, odd = [], set()
        for p in polys:
            acc = sp.Integer(0)
            for (k,), c in p.terms():
                m, r = divmod(k, 2)
                acc += c * lam ** r * l2 ** m * uu ** (top - m)
                if c != 0:
                    odd.add(r)
            out.append(sp.expand(acc))
        if odd == {1}:
            out = [sp.expand(e / lam) for e in out]
        elif odd == {0, 1}:
            raise SymkinError(f"a row mixes even and odd powers of {lam}: the pose route cannot reduce it")
        entries = out
    return entries


def pose_rows(sm, ps: PoseSlice, params) -> tuple[list[list[sp.Expr]], list[sp.Expr]]:
    """The rows of ``params`` over the platform twist, ``P V``, as polynomials in the variables.

    Returns ``(rows, contents)``: each row divided by its content (the gcd of its entries, a
    nonzero factor wherever the row is defined, kept in ``contents`` to be factored).
    """
    subs = ps.substitutions()
    lengths = {length_symbol(name): sp.sqrt(sum((ps.face[ns[1]][a] - ps.face[ns[0]][a]) ** 2 for a in range(3)))
               for name, ns in ps.mech.links}
    names = ps.mech.node_names
    rows, contents = [], []
    for r in sm.parameter_symrows(params):
        acc = sp.zeros(1, 3 if ps.legs else 6)
        dens = []
        blocks = r.block_vectors()
        for k, vec in blocks.items():
            n = names[k]
            if n not in ps.velocity:
                continue
            dens.append(ps.den[n])
        common = sp.Mul(*dens)
        for k, vec in blocks.items():
            n = names[k]
            if n not in ps.velocity:
                continue
            v = sp.Matrix([[sp.sympify(c).xreplace(lengths) for c in vec]]).xreplace(subs)
            acc += v * ps.velocity[n] * sp.cancel(common / ps.den[n])
        entries = [sp.expand(sm.substitute_design(e)) for e in acc]
        legs = {x for leg in ps.legs for x in (leg.c, leg.s)}
        extra = set().union(*[e.free_symbols for e in entries]) - set(ps.variables) - set(ps.relations) - legs
        if extra:
            raise SymkinError(f"row {r.owner}: symbols {', '.join(sorted(map(str, extra)))} left in the pose")
        entries = _reduce_lambda(entries, ps.relations)
        for leg in ps.legs:
            entries = [leg.reduce(e) for e in entries]
        gens = ps.variables + tuple(x for leg in ps.legs for x in (leg.c, leg.s))
        polys = [sp.Poly(e, *gens, domain="QQ") for e in entries]
        nonzero = [p for p in polys if not p.is_zero]
        if not nonzero:
            rows.append([sp.Integer(0)] * len(entries))
            contents.append(sp.Integer(1))
            continue
        g = nonzero[0]
        for p in nonzero[1:]:
            g = g.gcd(p)
        rows.append([p.exquo(g).as_expr() if not p.is_zero else sp.Integer(0) for p in polys])
        contents.append(g.as_expr())
    return rows, contents


def pose_condition(sm, ps: PoseSlice, kind: str) -> tuple[sp.Expr, list[sp.Expr]]:
    """``det(P V)`` of the inputs (``DKP-input``) or outputs (``DKP-output``) over the twist:
    ``(determinant of the reduced rows, the rows' contents)``, polynomials in the variables."""
    mech = ps.mech
    params = mech.inputs if kind == Kind.DKP_INPUT else mech.outputs
    rows, contents = pose_rows(sm, ps, params)
    n = 3 if ps.legs else 6
    if len(rows) != n:
        raise SymkinError(f"{kind}: {len(rows)} rows over the platform's {n} twist components; the pose route "
                          "forms a square determinant only")
    gens = ps.variables + tuple(x for leg in ps.legs for x in (leg.c, leg.s))
    dom = sp.QQ[gens]
    m = DomainMatrix([[dom.from_sympy(sp.sympify(e)) for e in row] for row in rows], (n, n), dom)
    det = dom.to_sympy(m.det())
    return sp.expand(det), contents


# ------------------------------------------------------------------ translating platform (Delta)


def _differ(diff: sp.Expr, leg, xs, length: float, tol: float) -> bool:
    """A closure difference (a length²) larger than rounding: each coefficient, in units of the
    model's ``length`` scale (``x``, ``y``: a length; ``c``: 1; ``s``: 1/length), against ``tol``."""
    p = sp.Poly(sp.expand(diff), *xs, *leg)
    return any(abs(float(coeff)) > tol * length ** (2 - i - j + k) for (i, j, _, k), coeff in p.terms())


class _NotTranslating(Exception):
    """The mechanism is not a platform held to translation by parallelograms (the route does not apply)."""


class ArmLeg:
    """One leg of a translating platform: an arm turning about a fixed axis ``A-A'`` whose node ``B``
    carries a bar ``B-C`` to the platform.  Its nodes are ``A + d_par + c d_perp + s (e × d)``
    (``e = A' − A``, ``d`` a node's model offset from ``A``), with ``c² + E s² = 1``, ``E = e·e``
    (``c = cos θ``, ``s = sin θ / |e|``).  ``closure`` is ``|C − B|² − l²``, linear in ``(c, s)``
    once reduced with the relation."""

    def __init__(self, link: str, c: sp.Symbol, s: sp.Symbol, e2: sp.Rational, closure: sp.Expr):
        self.link, self.c, self.s, self.e2, self.closure = link, c, s, e2, closure
        self.bars: list = []  # (arm node, platform node) of each bar of its parallelogram

    def reduce(self, expr: sp.Expr) -> sp.Expr:
        """``c² → 1 − E s²`` until ``expr`` has degree ≤ 1 in ``c``."""
        p = sp.Poly(sp.expand(expr), self.c)
        out = sp.Integer(0)
        for (k,), coeff in p.terms():
            m, r = divmod(k, 2)
            out += coeff * self.c ** r * (1 - self.e2 * self.s ** 2) ** m
        return sp.expand(out)


def translation_slice(mech: Mechanism, coords: list[CoordinateLabel], holds: list,
                      geometry: float) -> PoseSlice | None:
    """The slice of a translating platform (a Delta: three arms on fixed axes, each joined to the
    platform by a parallelogram of two bars) at a held height of one of its nodes, in its pose; None
    when the mechanism is not of that kind (then the node-coordinate route applies).

    The platform is taken at its model orientation; that it only translates rests on the
    parallelograms, checked here: the closures of an arm's bars must be the same polynomial (to
    ``geometry``, the relative tolerance of model geometry: the model's numbers are rounded).
    """
    if mech.dim != 3 or len(coords) != 2 or len(holds) != 1 or mech.sliders:
        return None
    if any(c.parameter.kind != "velocity" for c in coords) or holds[0][0].parameter.kind != "velocity":
        return None
    nodes = {c.parameter.target[0] for c in coords} | {holds[0][0].parameter.target[0]}
    if len(nodes) != 1 or sorted([c.axis for c in coords] + [holds[0][0].axis]) != [0, 1, 2]:
        return None
    node = nodes.pop()
    fixed = set(mech.fixed)
    owners = [name for name, ns in mech.links if node in ns and not set(ns) & fixed]
    if len(owners) != 1:
        return None
    platform = set(mech.link_nodes(owners[0]))
    arms = [name for name, ns in mech.links if len(set(ns) & fixed) == 2 and set(ns) - fixed]
    arm_nodes = {n for a in arms for n in mech.link_nodes(a)} - fixed
    if not arms or set(mech.free_nodes) != platform | arm_nodes or platform & arm_nodes:
        return None
    if mech.mobility_value != 3:
        return None
    try:
        return PoseSlice(mech, owners[0], node, coords, holds[0][0], holds[0][1], (0.0, 0.0, 0.0), arms=arms,
                         geometry=geometry)
    except _NotTranslating:
        return None


def constraint_condition(ps: PoseSlice) -> sp.Expr:
    """The condition under which a translating platform can also turn: ``det[wᵢ × uᵢ]``, rows per arm,
    ``uᵢ = C − B`` along its first bar and ``wᵢ`` the parallelogram's side ``C' − C`` on the platform.

    With the inputs locked, the two bars of parallelogram i allow a platform twist ``(v, ω)`` with
    ``uᵢ·(v + ω × (Cᵢ − O)) = 0`` for both ``C``, so ``ω·(wᵢ × uᵢ) = 0``: where the three moments
    ``wᵢ × uᵢ`` are dependent the platform turns (the Delta's constraint singularity); the mechanism
    then has one motion more than its mobility: ``symkin.analyze`` reports IM there (4 motions;
    tested on an asymmetric float Delta).  The determinant is linear in each arm's ``(c, s)``, and
    :func:`eliminate_arms` gives its curve in ``(x, y)`` over every working mode (degree 48,
    irreducible, for the test models).  The translation-only ``det(P V)`` does not contain this
    curve.  ``symkin conditions`` gives it as the IM locus of this route.
    """
    if not ps.legs or any(len(leg.bars) < 2 for leg in ps.legs):
        raise SymkinError("the constraint condition is defined for a platform held to translation by parallelograms")
    rows = []
    for leg in ps.legs:
        (b, c), (_, c2) = leg.bars[:2]
        u = ps.position[c] - ps.position[b]
        w = ps.position[c2] - ps.position[c]
        rows.append(list(w.cross(u)))
    gens = ps.variables + tuple(x for leg in ps.legs for x in (leg.c, leg.s))
    dom = sp.QQ[gens]
    m = DomainMatrix([[dom.from_sympy(sp.expand(e)) for e in row] for row in rows], (3, 3), dom)
    return sp.expand(dom.to_sympy(m.det()))


def _by_power(p, i: int, ring) -> dict:
    """``p = Σ_k C_k g_i^k``: ``{k: C_k}`` (ring elements free of generator ``i``)."""
    out: dict = {}
    for m, coeff in p.terms():
        mm = list(m)
        k, mm[i] = m[i], 0
        out[k] = out.get(k, ring.zero) + ring({tuple(mm): coeff})
    return out


def _eliminate_by_resultants(det: sp.Expr, ps: PoseSlice, poll=lambda: None) -> tuple[sp.Expr, list[sp.Expr]]:
    """The polynomial in the variables whose zeros are the points where ``det`` vanishes for some
    real or complex placement of the arms, and the nonzero factors divided out.

    Leg by leg: its closure ``p c + q s + r = 0`` gives ``c = −(q s + r)/p``; ``det`` (reduced to
    degree ≤ 1 in ``c``) becomes ``G(s)`` times a power of ``p``, and the relation
    ``Q(s) = (q s + r)² + E p² s² − p² = 0``; ``G`` is reduced modulo ``Q`` (pseudo-remainder, a
    power of ``Q``'s leading coefficient ``q² + E p²``) to ``a s + b`` and their resultant
    ``Q₂ b² − Q₁ a b + Q₀ a²`` replaces ``det``.  Powers of ``p`` (the substitution's
    denominator) and of ``q² + E p²`` (positive at every real point where the leg's closure
    depends on its angle) that divide the result are divided out and returned.
    """
    from sympy.polys.rings import ring

    xs = ps.variables
    syms = list(xs) + [x for leg in ps.legs for x in (leg.c, leg.s)]
    rng, *gens = ring(syms, sp.QQ)
    f = rng(sp.expand(det))
    removed: list = []
    for leg in ps.legs:
        ci, si = syms.index(leg.c), syms.index(leg.s)
        if f.degree(gens[ci]) <= 0 and f.degree(gens[si]) <= 0:
            continue
        e2 = sp.QQ(leg.e2.p, leg.e2.q)
        s = gens[si]
        by_c = _by_power(rng(sp.expand(leg.closure)), ci, rng)
        if set(by_c) - {0, 1}:
            raise SymkinError(f"the closure of arm {leg.link!r} is not linear in its angle's cosine")
        p = by_c.get(1, rng.zero)
        by_s = _by_power(by_c.get(0, rng.zero), si, rng)
        q, r = by_s.get(1, rng.zero), by_s.get(0, rng.zero)
        if p == 0:
            raise SymkinError(f"the closure of arm {leg.link!r} does not depend on its angle's cosine")
        fk = _by_power(f, ci, rng)
        top = max(fk)
        g = rng.zero
        for k, coeff in fk.items():
            g += coeff * (-(q * s + r)) ** k * p ** (top - k)
        poll()
        qk = _by_power((q * s + r) ** 2 + e2 * p ** 2 * s ** 2 - p ** 2, si, rng)
        q2, q1, q0 = (qk.get(k, rng.zero) for k in (2, 1, 0))
        gk = _by_power(g, si, rng)
        d = max(gk)
        while d >= 2:
            lead = gk.pop(d)
            gk = {k: v * q2 for k, v in gk.items()}
            gk[d - 1] = gk.get(d - 1, rng.zero) - lead * q1
            gk[d - 2] = gk.get(d - 2, rng.zero) - lead * q0
            d -= 1
            poll()
        a, b = gk.get(1, rng.zero), gk.get(0, rng.zero)
        f = q2 * b ** 2 - q1 * a * b + q0 * a ** 2
        poll()
        for h in (p, q2):
            if h.is_ground:
                continue
            while True:
                quo, rem = f.div(h)
                if rem != 0:
                    break
                f = quo
                removed.append(h.as_expr())
    return f.as_expr(), removed


# ------------------------------------------------------- the arms' elimination by values (the default)

METHODS = ("values", "resultants")


def eliminate_arms(det: sp.Expr, ps: PoseSlice, poll=lambda: None,
                   method: str = "values") -> tuple[sp.Expr, list[sp.Expr]]:
    """The polynomial in the variables whose zeros are the points where ``det`` vanishes for some
    real or complex placement of the arms, and the factors divided out.

    ``method="values"`` (the default): the same norm computed at integer points and interpolated
    (:func:`_eliminate_by_values`); ``"resultants"``: the symbolic elimination
    (:func:`_eliminate_by_resultants`), kept as the reference the tests and the benchmark compare
    with.  Both give the same curve up to a constant factor.
    """
    if method == "resultants":
        return _eliminate_by_resultants(det, ps, poll)
    if method != "values":
        raise ValueError(f"unknown elimination method {method!r}; use one of {', '.join(METHODS)}")
    try:
        return _eliminate_by_values(det, ps, poll)
    except _ByValuesFailed:  # not met on any model so far; the reference is slower but symbolic throughout
        return _eliminate_by_resultants(det, ps, poll)


class _Degree:
    """A degree bound standing in for a value in :func:`_norm_chain`: ``+``/``−`` take the maximum,
    ``×`` adds, ``//`` (by an exact divisor of known degree) subtracts; an integer factor keeps it."""

    __slots__ = ("d",)

    def __init__(self, d: int):
        self.d = d

    def __add__(self, other):
        return _Degree(max(self.d, other.d)) if isinstance(other, _Degree) else self

    __radd__ = __sub__ = __rsub__ = __add__

    def __mul__(self, other):
        return _Degree(self.d + other.d) if isinstance(other, _Degree) else self

    __rmul__ = __mul__

    def __neg__(self):
        return self

    def __floordiv__(self, other):
        return _Degree(self.d - other.d)


def _integral(expr: sp.Expr, gens) -> dict:
    """``expr`` times the lcm of its coefficients' denominators: ``{monomial: int}``."""
    rng, *_ = sp.ring(gens, sp.QQ)
    f = rng(sp.expand(expr))
    den = math.lcm(*[int(c.denominator) for c in f.values()]) if f else 1
    return {m: int(c * den) for m, c in f.items()}


def _integers(values) -> np.ndarray:
    """An object array of the ground integers of sympy's ``ZZ`` (gmpy2's ``mpz`` when installed: faster
    products of long integers than Python's ``int``)."""
    from sympy.polys.domains import ZZ
    out = np.empty(len(values), dtype=object)
    out[:] = [ZZ.dtype(int(v)) for v in values]
    return out


def _poly_mul(a: dict, b: dict) -> dict:
    out: dict = {}
    for ma, va in a.items():
        for mb, vb in b.items():
            m = tuple(i + j for i, j in zip(ma, mb))
            out[m] = out[m] + va * vb if m in out else va * vb
    return out


def _poly_add(a: dict, b: dict, ka=1, kb=1) -> dict:
    """``ka a + kb b`` (``ka``, ``kb`` values)."""
    out = {m: ka * v for m, v in a.items()}
    for m, v in b.items():
        out[m] = out[m] + kb * v if m in out else kb * v
    return out


class _ByValuesFailed(Exception):
    """The elimination by values met what its derivation excludes (a quotient not exact, an
    interpolant that misses a value): :func:`eliminate_arms` then takes the resultants."""


def _exact_div(value, divisor):
    """``value / divisor`` for values known to be multiples (object arrays of integers, or degrees);
    checked."""
    if isinstance(value, _Degree):
        return value // divisor
    q = value // divisor
    if not (q * divisor == value).all():
        raise _ByValuesFailed("a quotient that should be exact is not")
    return q


def _norm_chain(terms: dict, arms: list, poll) -> object:
    """``Π_k Q₂ₖ^{d_k} G(pt₁)G(pt₂)`` arm after arm: the norm of ``det`` over both placements of
    every arm, as a value (an array over points, or a :class:`_Degree`).

    ``terms``: ``{exponents of (c₁, s₁, …, cₙ, sₙ): value}``; ``arms``: per arm ``(p, q, r, Q₂, Q₁,
    Q₀)`` values, the closure ``p c + q s + r`` and ``Q(s) = Q₂ s² + Q₁ s + Q₀`` (its relation with
    ``c = −(q s + r)/p``).  With ``d`` the degree of the form in the arm's ``(c, s)``, homogenised by
    ``(c, s, 1) → (−(q s + r), p s, p)`` to ``g(s) = pᵈ G``, reduced modulo ``Q`` to ``a s + b``
    (times ``Q₂^{d−1}``): ``Q₀ a² − Q₁ a b + Q₂ b² = Q₂^{2d−1} Π g(sₖ)``, divided by
    ``Q₂^{d−1} p^{2d}`` (exactly: a polynomial in the data and the other arms' variables).
    """
    f = dict(terms)
    for i, (p, q, r, q2, q1, q0) in enumerate(arms):
        ci, si = 2 * i, 2 * i + 1
        d = max((m[ci] + m[si] for m in f), default=0)
        if d == 0:
            continue
        pw = {"p": [1, p], "q": [1, q], "r": [1, r]}
        for k in range(2, d + 1):
            for key, base in (("p", p), ("q", q), ("r", r)):
                pw[key].append(pw[key][-1] * base)
        # (−(q s + r))^a (p s)^b p^(d−a−b) = Σ_k (−1)^a C(a, k) q^k r^(a−k) p^(d−a) s^(k+b)
        w = {}
        for a in range(d + 1):
            for k in range(a + 1):
                w[a, k] = (-1) ** a * math.comb(a, k) * (pw["q"][k] * pw["r"][a - k]) * pw["p"][d - a]
        g: list[dict] = [{} for _ in range(d + 1)]
        for m, v in f.items():
            a, b = m[ci], m[si]
            rest = m[:ci] + (0, 0) + m[si + 1:]
            for k in range(a + 1):
                term = v * w[a, k]
                acc = g[k + b]
                acc[rest] = acc[rest] + term if rest in acc else term
        poll()
        for j in range(d, 1, -1):  # Q₂^{d−1} g ≡ g₁ s + g₀ (mod Q)
            lead = g[j]
            for k in range(j):
                g[k] = {m: q2 * v for m, v in g[k].items()}
            g[j - 1] = _poly_add(g[j - 1], lead, 1, -q1)
            g[j - 2] = _poly_add(g[j - 2], lead, 1, -q0)
            poll()
        a1, b0 = g[1], g[0]
        aa, ab, bb = _poly_mul(a1, a1), _poly_mul(a1, b0), _poly_mul(b0, b0)
        poll()
        res = _poly_add(_poly_add(aa, ab, q0, -q1), bb, 1, q2)
        divisor = pw["p"][d] * pw["p"][d]
        for _ in range(d - 1):
            divisor = divisor * q2
        f = {m: _exact_div(v, divisor) for m, v in res.items()}
        poll()
    (value,) = f.values() if f else (None,)
    return value


def _evaluate(poly: dict, powers) -> object:
    """A polynomial ``{(i, j): int}`` in the variables at the points whose powers ``powers`` holds."""
    xp, yp = powers
    out = None
    for (i, j), c in poly.items():
        v = c * (xp[i] * yp[j])
        out = v if out is None else out + v
    return out if out is not None else 0 * xp[0]


class _Powers:
    """Powers of the points' coordinates (object arrays of ints), made on demand."""

    def __init__(self, x, y):
        self.x, self.y = [np.ones_like(x), x], [np.ones_like(y), y]

    def __getitem__(self, axis):
        return _PowerList(self.x if axis == 0 else self.y)


class _PowerList:
    def __init__(self, lst):
        self.lst = lst

    def __getitem__(self, k):
        while len(self.lst) <= k:
            self.lst.append(self.lst[-1] * self.lst[1])
        return self.lst[k]


def _newton_1d(values: list) -> list:
    """The coefficients (lowest first, fractions) of the polynomial through ``(t, values[t])``, ``t = 0, 1, …``."""
    from fractions import Fraction
    n = len(values) - 1
    a = [Fraction(v) for v in values]
    for k in range(1, n + 1):
        for j in range(n, k - 1, -1):
            a[j] = (a[j] - a[j - 1]) / k
    coeffs = [a[n]]
    for i in range(n - 1, -1, -1):  # Horner in the Newton basis, nodes 0, 1, …
        coeffs = [Fraction(0)] + coeffs
        for k in range(len(coeffs) - 1):
            coeffs[k] -= i * coeffs[k + 1]
        coeffs[0] += a[i]
    return coeffs


def _interpolate_triangle(values, n: int, x0: int, y0: int) -> dict:
    """``{(i, j): int}``: an integer multiple of the polynomial of total degree ≤ ``n`` taking
    ``values[i, j]`` (an object array) at ``(x0 + i, y0 + j)``, ``i + j ≤ n``.

    Newton's formula on the triangle: forward differences along y then x give
    ``Δₓⁱ Δᵧʲ``, the coefficient of ``Π_{k<i}(x − x₀ − k) Π_{l<j}(y − y₀ − l)`` times ``i! j!``;
    everything is scaled by ``n!²`` to stay in the integers, and the Newton basis is expanded by
    Horner's scheme.
    """
    a = values.copy()
    for k in range(1, n + 1):
        a[:, k:] = a[:, k:] - a[:, k - 1:-1]
    for k in range(1, n + 1):
        a[k:, :] = a[k:, :] - a[k - 1:-1, :]
    fact = [math.factorial(k) for k in range(n + 1)]
    scale = [fact[n] // fact[k] for k in range(n + 1)]
    xpolys = []  # P_j(x) = Σ_i c_ij Π_{k<i}(x − x0 − k), dense, lowest first
    for j in range(n + 1):
        m = n - j
        poly = [int(a[m, j]) * scale[m] * scale[j]]
        for i in range(m - 1, -1, -1):
            node = x0 + i
            poly = [0] + poly
            for k in range(len(poly) - 1):
                poly[k] -= node * poly[k + 1]
            poly[0] += int(a[i, j]) * scale[i] * scale[j]
        xpolys.append(poly)
    out = [list(xpolys[n])]  # Horner in y over x-polynomials: out[l] = coefficient of y^l
    for j in range(n - 1, -1, -1):
        node = y0 + j
        out = [[0] * len(xpolys[j])] + out
        for l in range(len(out) - 1):
            nxt = out[l + 1]
            cur = out[l]
            if len(cur) < len(nxt):
                cur.extend([0] * (len(nxt) - len(cur)))
            for k, v in enumerate(nxt):
                cur[k] -= node * v
        base = out[0]
        for k, v in enumerate(xpolys[j]):
            base[k] += v
    return {(i, l): c for l, row in enumerate(out) for i, c in enumerate(row) if c}


def _eliminate_by_values(det: sp.Expr, ps: PoseSlice, poll=lambda: None) -> tuple[sp.Expr, list[sp.Expr]]:
    """:func:`eliminate_arms` by values: the norm at integer points, interpolated.

    The norm ``V`` of ``det`` over both placements of every arm (:func:`_norm_chain`, the same
    resultants as :func:`_eliminate_by_resultants`, the extraneous powers of ``p`` divided out
    exactly at each step) is a polynomial in ``(x, y)`` with integer coefficients once the data are
    scaled to integers.  It is computed at integer points only, all points at once (numpy arrays
    of Python integers: exact).  Its degree is bounded by the same computation on degrees; the
    powers of each arm's ``q² + E p²`` (no real curve: zero only where ``p = q = 0``) that divide
    ``V`` are found on a random line (``V`` there interpolated exactly, divided as a univariate
    polynomial), divided out point by point, and the quotient ``W`` is interpolated on a triangle
    of ``(n + 1)(n + 2)/2`` points, ``n`` its degree on that line.  ``W`` is then checked at
    points off the triangle against the values; a mismatch (a line along which ``W`` has a lower
    degree, or which meets another factor where it meets ``q² + E p²``) retries with the degree
    bound, and a second one raises :class:`_ByValuesFailed` (then the resultants are used).
    """
    import random

    xs = ps.variables
    legs = ps.legs
    syms = [x for leg in legs for x in (leg.c, leg.s)]
    rng, *_ = sp.ring(list(xs) + syms, sp.QQ)
    f = rng(sp.expand(det))
    if not f:
        return sp.Integer(0), []
    den = math.lcm(*[int(c.denominator) for c in f.values()])
    # {arm exponents: {(i, j): int}}
    by_arm: dict = {}
    for m, c in f.items():
        by_arm.setdefault(m[2:], {})[m[:2]] = int(c * den)
    arm_polys = []
    q2s = []
    for leg in legs:
        by_c = _integral(leg.closure, (leg.c, leg.s) + tuple(xs))
        parts = {"p": {}, "q": {}, "r": {}}
        for (ec, es, i, j), c in by_c.items():
            key = "p" if ec == 1 and es == 0 else "q" if ec == 0 and es == 1 else "r" if ec == es == 0 else None
            if key is None:
                raise SymkinError(f"the closure of arm {leg.link!r} is not linear in its angle's (cos, sin)")
            parts[key][i, j] = c
        p, q, r = parts["p"], parts["q"], parts["r"]
        if not p:
            raise SymkinError(f"the closure of arm {leg.link!r} does not depend on its angle's cosine")
        e2 = sp.Rational(leg.e2)
        num, dn = int(e2.p), int(e2.q)
        q2 = _poly_add(_poly_mul(q, q), _poly_mul(p, p), dn, num)  # dn (q² + E p²)
        q1 = {m: 2 * dn * v for m, v in _poly_mul(q, r).items()}
        q0 = _poly_add(_poly_mul(r, r), _poly_mul(p, p), dn, -dn)
        arm_polys.append((p, q, r, q2, q1, q0))
        g = math.gcd(*q2.values())
        q2s.append({m: v // g for m, v in q2.items() if v})

    def values(x, y):
        pw = _Powers(_integers(x), _integers(y))
        powers = (pw[0], pw[1])
        terms = {m: _evaluate(poly, powers) for m, poly in by_arm.items()}
        arms = [tuple(_evaluate(h, powers) for h in polys) for polys in arm_polys]
        return _norm_chain(terms, arms, poll), powers

    def degree(poly: dict) -> int:
        return max((i + j for (i, j), v in poly.items() if v), default=0)

    # a degree bound of V
    bound = _norm_chain({m: _Degree(degree(poly)) for m, poly in by_arm.items()},
                        [tuple(_Degree(degree(h)) for h in polys) for polys in arm_polys], poll).d
    chooser = random.Random(20041)

    def admissible(x, y) -> bool:  # every arm's p nonzero at the points (the norm divides by it)
        pw = _Powers(np.array(x, dtype=object), np.array(y, dtype=object))
        return all((_evaluate(pp[0], (pw[0], pw[1])) != 0).all() for pp in arm_polys)

    # V on a random line: its exact restriction, the powers of each q² + E p² that divide it
    t = sp.Symbol("t")
    for _ in range(50):
        x0, y0 = chooser.randint(-40, 40), chooser.randint(-40, 40)
        dx, dy = chooser.randint(1, 9), chooser.randint(-9, 9)
        lx = [x0 + dx * k for k in range(bound + 1)]
        ly = [y0 + dy * k for k in range(bound + 1)]
        if admissible(lx, ly):
            break
    else:
        raise SymkinError("no admissible line for the arms' elimination")
    v_line, _ = values(lx, ly)
    poll()
    line = sp.Poly([sp.Rational(c.numerator, c.denominator) for c in reversed(_newton_1d(list(v_line)))], t,
                   domain="QQ")
    sub = {xs[0]: x0 + dx * t, xs[1]: y0 + dy * t}
    exps = []
    for h in q2s:
        hl = sp.Poly(sp.expand(sp.Poly.from_dict(h, *xs).as_expr().xreplace(sub)), t, domain="QQ")
        e = 0
        while hl.degree() > 0:
            quo, rem = line.div(hl)
            if not rem.is_zero:
                break
            line, e = quo, e + 1
        exps.append(e)
    removed = [sp.Poly.from_dict(h, *xs).as_expr() for h, e in zip(q2s, exps) for _ in range(e)]
    poll()

    def quotient(x, y):
        v, powers = values(x, y)
        div = None
        for h, e in zip(q2s, exps):
            for _ in range(e):
                hv = _evaluate(h, powers)
                div = hv if div is None else div * hv
        return v if div is None else _exact_div(v, div)

    for n in dict.fromkeys((line.degree(), bound - sum(e * degree(h) for h, e in zip(q2s, exps)))):
        for _ in range(50):
            gx, gy = chooser.randint(-30, 10), chooser.randint(-30, 10)
            ii, jj = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
            mask = (ii + jj) <= n
            px, py = [int(gx + i) for i in ii[mask]], [int(gy + j) for j in jj[mask]]
            if admissible(px, py):
                break
        else:
            raise SymkinError("no admissible grid for the arms' elimination")
        tri = np.zeros((n + 1, n + 1), dtype=object)
        tri[mask] = quotient(px, py)
        poll()
        coeffs = _interpolate_triangle(tri, n, gx, gy)
        poll()
        # check off the triangle
        while True:
            cx = [chooser.randint(-1000, 1000) for _ in range(3)]
            cy = [chooser.randint(-1000, 1000) for _ in range(3)]
            if admissible(cx, cy):
                break
        want = quotient(cx, cy)
        scale = math.factorial(n) ** 2
        got = [sum(c * X ** i * Y ** j for (i, j), c in coeffs.items()) for X, Y in zip(cx, cy)]
        if all(g == scale * w for g, w in zip(got, want)):
            break
    else:
        raise _ByValuesFailed("the interpolated polynomial does not reproduce the values off its triangle")
    g = math.gcd(*coeffs.values())
    out = sp.Poly.from_dict({m: c // g for m, c in coeffs.items()}, *xs).as_expr()
    return out, removed


# ------------------------------------------------------------------ factoring the locus


def factor_list(poly: sp.Poly) -> tuple:
    """``sp.factor_list(poly)`` for a bivariate locus, with a fast exit for an irreducible one.

    sympy factors a bivariate polynomial by Wang's algorithm, which first searches a prime above
    the polynomial's Mignotte bound: for the degree-48 Delta locus of a float model (coefficients
    of ~1000 digits) that search alone takes ~25 s.  Irreducibility is certified first instead
    (:func:`_certified_irreducible`); only a polynomial not certified goes to sympy.
    """
    if len(poly.gens) == 2 and poly.total_degree() > 2 and _certified_irreducible(poly):
        _, prim = poly.clear_denoms()[1].primitive()
        if prim.LC() < 0:
            prim = -prim
        return poly.LC() / prim.LC(), [(prim.set_domain(poly.domain), 1)]
    return sp.factor_list(poly)


def _certified_irreducible(poly: sp.Poly, primes: int = 20) -> bool:
    """True when ``poly`` (two generators, rational coefficients) is proved irreducible over ℚ.

    With ``n = deg_x F`` and the coefficient of ``xⁿ`` a constant, a factorisation ``F = G H``
    has ``deg_x G, deg_x H ≥ 1`` (a factor free of x would divide that constant) and constant
    leading coefficients, so it survives ``y = a``: ``F(x, a)`` irreducible over ℚ proves ``F``
    irreducible.  ``F(x, a)`` is irreducible when no degree ``0 < k < n`` is a sum of the degrees
    of its irreducible factors modulo every one of a few primes (distinct-degree factorisation
    over GF(ℓ), ℓ not dividing the leading coefficient, ``F(x, a)`` squarefree modulo ℓ).  False
    means "not proved" (then sympy factors it).
    """
    from sympy.polys.domains import ZZ
    from sympy.polys.galoistools import gf_ddf_zassenhaus, gf_from_int_poly, gf_monic, gf_sqf_p

    f = poly.clear_denoms()[1].set_domain(ZZ)
    n = f.degree(f.gens[0])
    terms = f.terms()
    if any(i == n and j > 0 for (i, j), _ in terms) or n < 2:
        return False
    possible = None
    full = (1 << (n + 1)) - 1
    ell = 100
    for a in (1, -1, 2, 3):
        tried = stable = 0
        while tried < primes and stable < 8:  # a degree left possible by 8 primes in a row: likely a factor
            ell = int(sp.nextprime(ell))
            tried += 1
            coeffs = [0] * (n + 1)
            for (i, j), c in terms:
                coeffs[n - i] = (coeffs[n - i] + int(c) % ell * pow(a, j, ell)) % ell
            if coeffs[0] == 0:
                continue
            g = gf_monic(gf_from_int_poly(coeffs, ell), ell, ZZ)[1]
            if not gf_sqf_p(g, ell, ZZ):
                continue
            sums = 1
            for h, d in gf_ddf_zassenhaus(g, ell, ZZ):
                for _ in range((len(h) - 1) // d):
                    sums |= (sums << d) & full
            before, possible = possible, sums if possible is None else possible & sums
            if possible == 1 | (1 << n):
                return True
            stable = stable + 1 if possible == before else 0
        possible = None
    return False
