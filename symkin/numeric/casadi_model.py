"""The geometric matrix and kinematic-parameter rows as CasADi SX expressions.

This module mirrors :mod:`symkin.numeric.geometric_matrix` row by row, but builds
CasADi ``SX`` expressions of the *free* nodal coordinates ``q`` (free nodes in node
order, ``x, y[, z]`` each) instead of numbers at one configuration.  The fixed nodes
enter as constants taken from the model.  Every row is the same dimensionless row
``a`` of the core (paper eqs. 1-2, A3-A4) and ``G = Jᵀ J = Σ a aᵀ`` (eq. 3, A5):

* bar i-j: ``+u`` at i, ``-u`` at j, ``u = (x_j - x_i)/|x_j - x_i|`` (eq. A3, A4);
* degenerate rigid body (collinear nodes; coplanar nodes in 3D): ``n·(ẋ_m - Σ c_k ẋ_k)``
  for each normal ``n`` of the affine hull and each node ``m`` off the frame;
* slider on a fixed line / plane: ``n·ẋ_P``; on the moving line A-C:
  ``n·(ẋ_P - (1-t) ẋ_A - t ẋ_C)``; the screw row of a helical pair.

Bars, degenerate bodies, sliders and helical pairs are their definitions of
:mod:`symkin.constraints` evaluated in SX (rows and closure equations alike).

Discrete choices the core makes at every configuration (the node of a link farthest
from its first node, the coordinate axis least aligned with a line) are reproduced with
``if_else`` so that the expressions agree with the core at *any* node positions.  Two
choices are made once, at the model's configuration, because they are constant on the
closure manifold: whether a body is degenerate (its frame of nodes and the dimension of
its hull) and, for spatial bodies, whether they are rods.  The normals of a degenerate
body are smooth functions of its frame, with the core's sign at the model's
configuration; elsewhere the core's SVD may flip a sign (or, for a collinear spatial
body, rotate the pair of normals), which changes no product ``a aᵀ`` and so no G.  The
core also picks the frame again at every configuration; where two nodes of a symmetric
body tie in its greedy search (the 3-RSR platform), rounding decides and its G can then
differ from ours by a change of the body's out-of-hull rows, with the same row space:
the motion space and every decision agree, ``λ_{F+1}`` may not exactly.

The closure residual ``Φ(q, p)`` has one row per row of ``J``, in the same order, with
``∂Φ/∂q = J_f`` row for row at every configuration that closes (``Φ = 0``); for bars
``∂Φ/∂q`` is the ``J`` row times ``|x_j - x_i|/L > 0`` everywhere.  Its parameters ``p``
(bar lengths, slider offsets, affine coordinates in degenerate bodies) default to the
model's configuration.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from symkin.constraints import Body, constraints_of, slider_constraint
from symkin.constraints.algebra import Casadi
from symkin.model.joints import GROUND
from symkin.model.mechanism import AXES, Mechanism, Parameter
from symkin.numeric.geometric_matrix import coordinate_labels, free_mask
from symkin.numeric.linalg import affine_hull
from symkin.tolerances import DEFAULT

__all__ = ["CasadiModel", "build"]


# ---------------------------------------------------------------------- small SX helpers
def _dot(a: ca.SX, b: ca.SX) -> ca.SX:
    out = a[0] * b[0]
    for k in range(1, a.numel()):
        out = out + a[k] * b[k]
    return out


def _norm(a: ca.SX) -> ca.SX:
    return ca.sqrt(_dot(a, a))


def _skew(r: ca.SX) -> ca.SX:
    """``[r]×`` with ``[r]× v = r × v``."""
    z = ca.SX(0)
    return ca.vertcat(ca.horzcat(z, -r[2], r[1]), ca.horzcat(r[2], z, -r[0]), ca.horzcat(-r[1], r[0], z))


def _inv3_sym(m: ca.SX) -> ca.SX:
    """Inverse of a symmetric 3×3 matrix by its adjugate."""
    a, b, c = m[0, 0], m[0, 1], m[0, 2]
    d, e, f = m[1, 1], m[1, 2], m[2, 2]
    c00 = d * f - e * e
    c01 = c * e - b * f
    c02 = b * e - c * d
    c11 = a * f - c * c
    c12 = b * c - a * e
    c22 = a * d - b * b
    det = a * c00 + b * c01 + c * c02
    return ca.vertcat(ca.horzcat(c00, c01, c02), ca.horzcat(c01, c11, c12),
                      ca.horzcat(c02, c12, c22)) / det


# ---------------------------------------------------------------------- the model
@dataclass(frozen=True, eq=False)
class CasadiModel:
    """SX expressions of one mechanism (see the module docstring).

    Attributes
    ----------
    mech : Mechanism
    q : SX (nf, 1)
        Free nodal coordinates, free nodes in node order, ``x, y[, z]`` each.
    x : SX (D, 1)
        All nodal coordinates (fixed ones are constants).
    p : SX (np, 1)
        Closure parameters (see :attr:`p_labels`); :attr:`p0` are the model's values.
    J : SX (m, D)
        Constraint rows over all coordinates, same rows and order as
        :func:`symkin.numeric.geometric_matrix.constraint_rows`.
    owners : tuple of str
        What owns each row of ``J`` (same strings as the core's).
    closure : SX (m, 1)
        Position residual ``Φ(q, p)``, one row per row of ``J``.
    inputs, outputs, platform : SX (k, D)
        Kinematic-parameter rows in physical units (core's ``parameter_rows``);
        ``platform`` is the platform's twist rows (empty when there is no platform).
    structural : tuple of str
        Notes on choices fixed at the model's configuration (degenerate bodies, rods).
    """

    mech: Mechanism
    q: ca.SX
    x: ca.SX
    p: ca.SX
    p0: np.ndarray
    p_labels: tuple[str, ...]
    J: ca.SX
    owners: tuple[str, ...]
    closure: ca.SX
    inputs: ca.SX
    input_labels: tuple[str, ...]
    outputs: ca.SX
    output_labels: tuple[str, ...]
    platform: ca.SX
    platform_labels: tuple[str, ...]
    free: np.ndarray
    structural: tuple[str, ...]

    @property
    def nf(self) -> int:
        return int(self.free.sum())

    @property
    def D(self) -> int:
        return int(self.free.size)

    @property
    def Jf(self) -> ca.SX:
        """Constraint rows restricted to the free coordinates."""
        return self.J[:, np.flatnonzero(self.free).tolist()]

    @property
    def q_labels(self) -> tuple[str, ...]:
        labels = coordinate_labels(self.mech)
        return tuple(lab for lab, f in zip(labels, self.free) if f)

    def q0(self) -> np.ndarray:
        """Free coordinates of the model's configuration."""
        xyz = np.array([c for _, c in self.mech.nodes], dtype=float).ravel()
        return xyz[self.free]


class _Builder:
    def __init__(self, mech: Mechanism, tolerances=DEFAULT):
        self.mech = mech
        self.dim = mech.dim
        self.tol = tolerances.geometry
        self.index = mech.node_index()
        self.xyz0 = np.array([c for _, c in mech.nodes], dtype=float)
        self.free = free_mask(mech)
        nf = int(self.free.sum())
        self.q = ca.SX.sym("q", nf)
        entries = []
        k = 0
        flat0 = self.xyz0.ravel()
        for c in range(flat0.size):
            if self.free[c]:
                entries.append(self.q[k])
                k += 1
            else:
                entries.append(ca.SX(float(flat0[c])))
        self.x = ca.vertcat(*entries)
        self.D = flat0.size
        self.p_syms: list[ca.SX] = []
        self.p_vals: list[float] = []
        self.p_labels: list[str] = []
        self.structural: list[str] = []

    # -- coordinates
    def node(self, i: int) -> ca.SX:
        d = self.dim
        return self.x[d * i: d * i + d]

    def nodes(self) -> list[tuple]:
        """Every node's position as a tuple of SX scalars (the algebra's vectors)."""
        d = self.dim
        return [tuple(self.x[d * i + a] for a in range(d)) for i in range(len(self.mech.nodes))]

    def nodes0(self) -> list[tuple]:
        """Every node's position at the model's configuration (floats)."""
        return [tuple(map(float, c)) for c in self.xyz0]

    def param(self, label: str, value: float) -> ca.SX:
        s = ca.SX.sym(f"p{len(self.p_syms)}")
        self.p_syms.append(s)
        self.p_vals.append(float(value))
        self.p_labels.append(label)
        return s

    def row(self, blocks: dict[int, ca.SX]) -> ca.SX:
        """A (1, D) row with ``blocks[node] = vector`` (accumulated)."""
        d = self.dim
        cols = [ca.SX(1, d) for _ in range(len(self.mech.nodes))]
        for i, v in blocks.items():
            cols[i] = cols[i] + ca.reshape(v, 1, d)
        return ca.horzcat(*cols)

    # -- constraint rows: the definitions of symkin.constraints evaluated in SX
    def constraints(self):
        rows, owners, closure = [], [], []
        alg = Casadi(self.param)
        X, X0 = self.nodes(), self.nodes0()
        for con in constraints_of(self.mech):
            extra = {}
            if isinstance(con, Body):  # decided once, at the model's configuration
                hull = con.hull(X0, self.tol)
                if hull is None:
                    continue
                self.structural.append(con.frame_note(hull))
                extra = {"tol": self.tol}
            for r in con.rows(alg, X, X0, **extra):  # divided by the scale (not times its inverse): the core's rounding
                rows.append(self.row({k: ca.vertcat(*[v / r.scale for v in vec]) for k, vec in r.blocks().items()}))
                owners.append(con.owner)
            closure += [eq.numerator / eq.denominator for eq in con.equations(alg, X, X0, **extra)]
        j = ca.vertcat(*rows) if rows else ca.SX(0, self.D)
        phi = ca.vertcat(*closure) if closure else ca.SX(0, 1)
        return j, tuple(owners), phi

    def q_model(self) -> np.ndarray:
        return self.xyz0.ravel()[self.free]

    # -- parameter rows (mirrors geometric_matrix.parameter_rows)
    def rotation_rows(self, link: str) -> ca.SX:
        dim = self.dim
        idx = [self.index[n] for n in self.mech.link_nodes(link)]
        i = idx[0]
        xi = self.node(i)
        if dim == 2:
            # j = node farthest from the first one (np.argmax: first maximum)
            best = None
            row = None
            for k in idx[1:]:
                d = self.node(k) - xi
                length2 = _dot(d, d)
                perp = ca.vertcat(-d[1], d[0]) / length2
                cand = self.row({k: perp, i: -perp})
                if row is None:
                    row, best = cand, ca.sqrt(length2)
                else:
                    dist = ca.sqrt(length2)
                    better = dist > best
                    row = ca.if_else(better, cand, row)
                    best = ca.if_else(better, dist, best)
            return row
        others = idx[1:]
        h, _, _ = affine_hull(self.xyz0[idx], DEFAULT.geometry)
        blocks: dict[int, ca.SX] = {}
        if h >= 2:
            btb = ca.SX(3, 3)
            rs = []
            for k in others:
                r = self.node(k) - xi
                rs.append(r)
                btb = btb + _dot(r, r) * ca.SX.eye(3) - ca.mtimes(r, r.T)
            inv = _inv3_sym(btb)
            for k, r in zip(others, rs):
                blk = ca.mtimes(inv, _skew(r))
                blocks[k] = blocks.get(k, ca.SX(3, 3)) + blk
                blocks[i] = blocks.get(i, ca.SX(3, 3)) - blk
        else:
            self.structural.append(f"link {link}: a rod (collinear nodes); its angular velocity "
                                   "normal to the axis is taken from its last node")
            r = self.node(idx[-1]) - xi
            blk = _skew(r) / _dot(r, r)
            blocks[idx[-1]] = blk
            blocks[i] = -blk
        cols = [ca.SX(3, 3) for _ in range(len(self.mech.nodes))]
        for k, b in blocks.items():
            cols[k] = cols[k] + b
        return ca.horzcat(*cols)

    def link_rotation(self, link: str) -> ca.SX:
        """:meth:`rotation_rows`; zero for the fixed frame of a joint model (``ground``, no such link)."""
        if link == GROUND and link not in dict(self.mech.links):
            return ca.SX(1 if self.dim == 2 else 3, self.D)
        return self.rotation_rows(link)

    def axis_vector(self, axis) -> ca.SX:
        if isinstance(axis[0], str):
            v = self.node(self.index[axis[1]]) - self.node(self.index[axis[0]])
            return v / _norm(v)
        vec = np.array(axis, dtype=float)
        return ca.SX(ca.DM(vec / np.linalg.norm(vec)))

    def parameter_rows(self, param: Parameter) -> ca.SX:
        dim = self.dim
        kind = param.kind
        if kind == "rotation":
            rows = self.rotation_rows(param.target[0])
            return rows if dim == 2 else ca.mtimes(self.axis_vector(param.axis).T, rows)
        if kind == "joint":  # the second link's rotation minus the first's (spatial: about the axis)
            rows = self.link_rotation(param.target[1]) - self.link_rotation(param.target[0])
            return rows if dim == 2 else ca.mtimes(self.axis_vector(param.axis).T, rows)
        if kind == "twist":
            return self.twist_rows(param.target[0])
        if kind == "velocity":
            i = self.index[param.target[0]]
            comps = [AXES.index(param.component)] if param.component else range(dim)
            out = []
            for c in comps:
                e = np.zeros(dim)
                e[c] = 1.0
                out.append(self.row({i: ca.SX(ca.DM(e))}))
            return ca.vertcat(*out)
        if kind == "slide":  # the slider's rate row, as its definition states it (symkin.constraints)
            con = slider_constraint(self.mech, param.target[0])
            return ca.vertcat(*[self.row({k: ca.vertcat(*[v / r.scale for v in vec]) for k, vec in r.blocks().items()})
                                for r in con.rate_rows(Casadi(), self.nodes(), self.nodes0())])
        raise ValueError(f"unknown parameter kind {kind!r}")

    def twist_rows(self, link: str) -> ca.SX:
        dim = self.dim
        i = self.index[self.mech.link_nodes(link)[0]]
        vel = [self.row({i: ca.SX(ca.DM(np.eye(dim)[c]))}) for c in range(dim)]
        return ca.vertcat(*vel, self.rotation_rows(link))

    def parameters(self, params) -> tuple[ca.SX, tuple[str, ...]]:
        blocks, labels = [], []
        for prm in params:
            blocks.append(self.parameter_rows(prm))
            labels += list(prm.labels(self.dim))
        return (ca.vertcat(*blocks) if blocks else ca.SX(0, self.D)), tuple(labels)


def build(mech: Mechanism, tolerances=DEFAULT) -> CasadiModel:
    """Build the SX expressions of ``mech`` (see :class:`CasadiModel`).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> cm = build(get("fourbar_appendix"))
    >>> cm.J.shape, cm.nf, cm.p_labels[0]
    ((3, 8), 4, 'length crank (A-B)')
    """
    b = _Builder(mech, tolerances)
    j, owners, phi = b.constraints()
    p_in, lab_in = b.parameters(mech.inputs)
    p_out, lab_out = b.parameters(mech.outputs)
    if mech.platform is not None:
        p_pf, lab_pf = b.parameters([Parameter("twist", (mech.platform,))])
    else:
        p_pf, lab_pf = ca.SX(0, b.D), ()
    p = ca.vertcat(*b.p_syms) if b.p_syms else ca.SX(0, 1)
    return CasadiModel(mech=mech, q=b.q, x=b.x, p=p, p0=np.array(b.p_vals, dtype=float),
                       p_labels=tuple(b.p_labels), J=j, owners=owners, closure=phi,
                       inputs=p_in, input_labels=lab_in, outputs=p_out, output_labels=lab_out,
                       platform=p_pf, platform_labels=lab_pf, free=b.free,
                       structural=tuple(dict.fromkeys(b.structural)))
