"""Numeric geometric matrices (paper §II, Appendix eqs. A3-A6) and kinematic-parameter rows.

Every constraint of the mechanism is one *dimensionless* row ``a`` over the nodal
velocity components; its geometric matrix is ``a aᵀ`` and the mechanism's is their
sum, ``G = Σ a aᵀ = Jᵀ J`` (eqs. 2-3).  The rows are:

* a bar i-j (eq. A3 planar, A4 spatial): ``+u`` at node i, ``-u`` at node j, with ``u``
  the unit vector along the bar, so ``a aᵀ`` is the paper's matrix entry by entry;
* a rigid body of 3+ nodes: one bar row per pair of its nodes and, when its nodes do
  not span the space (collinear nodes; coplanar nodes in 3D) and the pairwise bars
  would leave it flexible, one row per missing normal ``n`` and extra node ``m``:
  ``n·(ẋ_m − Σ c_k ẋ_k) = 0`` with ``c`` the affine coordinates of ``m`` on a frame
  of the body's nodes (a rigid velocity field is affine, so this is exact);
* a slider on a fixed line / plane: ``n·ẋ = 0`` for each normal ``n`` of the line
  (one in 2D, two in 3D) or the plane's normal;
* a slider on the moving line through nodes A, C: ``n·(ẋ_P − (1−t)ẋ_A − t ẋ_C) = 0``
  with ``t`` the position of P on A→C;
* the screw row of a helical pair (slide = pitch × relative rotation).

Each kind is defined once, in :mod:`symkin.constraints` (the same definitions give the
CasADi, sympy and polynomial forms); here the sliders and helical pairs are those
definitions evaluated in floats, and the bars are the vectorised evaluation of
:class:`symkin.constraints.Bar` (a test keeps them equal); the out-of-hull rows of a
degenerate body are :class:`symkin.constraints.Body` evaluated in floats (its decision, the
hull and frame, taken at every configuration).

Fixed nodes are boundary conditions: the analysis works on the *free* coordinates
(the reduced matrix); :func:`geometric_matrix` with ``boundary=True`` returns the
paper's A6 form, with unit rows and columns for the fixed coordinates.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from symkin.constraints import body_constraints, slider_constraint, slider_constraints
from symkin.constraints.body import affine_frame  # one definition (a degenerate body's frame)
from symkin.constraints.algebra import FLOATS
from symkin.errors import ModelError, Problem
from symkin.model.joints import GROUND
from symkin.model.mechanism import AXES, Mechanism, Parameter
from symkin.numeric.linalg import affine_hull
from symkin.tolerances import DEFAULT

__all__ = ["ConstraintRows", "constraint_rows", "geometric_matrix", "coordinate_labels",
           "free_mask", "free_columns", "parameter_rows", "parameters_matrix", "rotation_rows", "twist_rows"]


def coordinate_labels(mech: Mechanism) -> tuple[str, ...]:
    """Names of the nodal velocity components, in order: ``x_A, y_A, x_B, ...``."""
    return tuple(f"{AXES[c]}_{n}" for n in mech.node_names for c in range(mech.dim))


def free_columns(a: np.ndarray, mech: Mechanism) -> np.ndarray:
    """The columns of ``a`` (rows over all D coordinates) that belong to free coordinates."""
    return a.take(plan(mech.topology).free_index, axis=1)


def free_mask(mech: Mechanism) -> np.ndarray:
    """Boolean mask of the free (not fixed) coordinates (read-only, shared per topology)."""
    return plan(mech.topology).free


@dataclass(frozen=True)
class ConstraintRows:
    """The constraint matrix ``J`` (rows × all coordinates) and what owns each row."""

    matrix: np.ndarray
    owners: tuple[str, ...]  # e.g. "link coupler (B-C)", "slider s1"


def _xyz(mech: Mechanism) -> np.ndarray:
    return np.array([xyz for _, xyz in mech.nodes], dtype=float)


@dataclass(frozen=True, eq=False)
class _Plan:
    """What the rows of a topology need besides coordinates: indices, owners, free columns.

    Built once per :class:`~symkin.model.mechanism.Topology` (:func:`plan`), so that the
    bar rows of a configuration are one scatter into a preallocated block: every bar ``k``
    between nodes ``i`` and ``j`` puts ``+u`` in columns ``dim·i + c`` and ``−u`` in
    ``dim·j + c`` of its row (``bar_flat`` holds those flat positions).
    """

    dim: int
    ncoord: int
    index: dict            # node name → position
    links: dict            # link name → node positions
    free: np.ndarray       # boolean mask of the free coordinates
    free_index: np.ndarray # their positions (``take`` is faster than boolean indexing)
    bar_i: np.ndarray      # (n_bars,) first node of each bar
    bar_j: np.ndarray      # (n_bars,) second node
    bar_pairs: tuple       # (i, j) of each bar
    bar_flat: np.ndarray   # flat indices in a (n_bars, ncoord) block: of +u (bar by bar), then of −u
    bar_owners: tuple      # owner of each bar row
    bodies: tuple          # (link name, node positions, bar rows before its extra rows), 3+ nodes


@lru_cache(maxsize=64)
def plan(topology) -> _Plan:
    """The :class:`_Plan` of a topology (cached; ``mech.topology`` is the key)."""
    dim, node_names, links = topology.key[:3]
    fixed = set(topology.key[3])
    index = {n: i for i, n in enumerate(node_names)}
    ncoord = dim * len(node_names)
    bar_i, bar_j, owners, bodies = [], [], [], []
    for name, ns in links:
        idx = [index[n] for n in ns]
        for a in range(len(idx)):
            for b in range(a + 1, len(idx)):
                bar_i.append(idx[a])
                bar_j.append(idx[b])
                owners.append(f"link {name} ({ns[a]}-{ns[b]})")
        if len(idx) >= 3:
            bodies.append((name, tuple(idx), len(bar_i)))
    bi, bj = np.array(bar_i, dtype=int), np.array(bar_j, dtype=int)
    free = np.array([n not in fixed for n in node_names for _ in range(dim)], dtype=bool)
    free.setflags(write=False)
    rows = np.arange(bi.size)[:, None] * ncoord
    comps = np.arange(dim)[None, :]
    return _Plan(dim=dim, ncoord=ncoord, index=index,
                 links={name: tuple(index[n] for n in ns) for name, ns in links},
                 free=free, free_index=np.flatnonzero(free),
                 bar_i=bi, bar_j=bj, bar_pairs=tuple(zip(bar_i, bar_j)),
                 bar_flat=np.concatenate([(rows + dim * bi[:, None] + comps).ravel(),
                                          (rows + dim * bj[:, None] + comps).ravel()]),
                 bar_owners=tuple(owners),
                 bodies=tuple(bodies))


def _bar_block(pl: _Plan, pts: list) -> np.ndarray:
    """Rows of every bar (eq. A3 / A4, divided by the bar's length): ``+u`` at i, ``−u`` at j.

    ``pts``: the node coordinates as tuples of floats (``mech.nodes``' own); the unit
    vectors are computed in plain floats (faster than NumPy for a mechanism's few bars)
    and scattered with the plan's flat indices.
    """
    try:
        vals = _unit_vectors(pl, pts)
    except ZeroDivisionError:
        at = [o for (i, j), o in zip(pl.bar_pairs, pl.bar_owners) if tuple(pts[i]) == tuple(pts[j])]
        raise ModelError([Problem(o, "its two nodes coincide (a bar of zero length)") for o in at]) from None
    block = np.zeros((len(pl.bar_pairs), pl.ncoord))
    block.reshape(-1)[pl.bar_flat] = vals + [-v for v in vals]
    return block


def _unit_vectors(pl: _Plan, pts: list) -> list:
    """Components of the unit vector of every bar, bar by bar."""
    vals = []
    if pl.dim == 2:
        for i, j in pl.bar_pairs:
            (xi, yi), (xj, yj) = pts[i], pts[j]
            dx, dy = xj - xi, yj - yi
            n = math.sqrt(dx * dx + dy * dy)
            vals += (dx / n, dy / n)
    else:
        for i, j in pl.bar_pairs:
            (xi, yi, zi), (xj, yj, zj) = pts[i], pts[j]
            dx, dy, dz = xj - xi, yj - yi, zj - zi
            n = math.sqrt(dx * dx + dy * dy + dz * dz)
            vals += (dx / n, dy / n, dz / n)
    return vals


def _certainly_full_hull(pts: list, tol: float) -> bool:
    """Whether the body's nodes ``pts`` (k lists of dim floats) surely span ``min(dim, k − 1)`` dimensions.

    A cheap sufficient test that never contradicts :func:`affine_hull` (then the body needs
    no extra rows): with ``C = AᵀA`` of the centred points and ``m = min(dim, k − 1)``,
    ``σ_m/σ_1 ≥ sqrt(e_m(C)/tr(C)^m)`` (``e_m`` the sum of principal m×m minors, the
    product of the m nonzero eigenvalues).  When that bound exceeds ``100·tol`` the hull
    is full; otherwise ``affine_hull`` decides.  Plain floats: a body has a few nodes.
    """
    k = len(pts)
    if len(pts[0]) == 2:
        c, m = _centred_gram_2d(pts), 2
        tr = c[0] + c[2]
        e = c[0] * c[2] - c[1] * c[1]
    else:
        (xx, xy, xz, yy, yz, zz), m = _centred_gram_3d(pts), (2 if k == 3 else 3)
        tr = xx + yy + zz
        if m == 2:  # sum of the principal 2×2 minors
            e = xx * yy - xy * xy + xx * zz - xz * xz + yy * zz - yz * yz
        else:
            e = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz)
    return tr > 0.0 and e > (100.0 * tol) ** 2 * tr ** m


def _centred_gram_2d(pts: list) -> tuple[float, float, float]:
    """``(Cxx, Cxy, Cyy)`` of ``C = AᵀA``, ``A`` the points minus their mean, over its largest entry."""
    k = len(pts)
    sx = sy = 0.0
    for px, py in pts:
        sx += px
        sy += py
    mx, my = sx / k, sy / k
    h = max(max(abs(px - mx), abs(py - my)) for px, py in pts) or 1.0  # scale: no overflow at 1e100
    xx = xy = yy = 0.0
    for px, py in pts:
        dx, dy = (px - mx) / h, (py - my) / h
        xx += dx * dx
        xy += dx * dy
        yy += dy * dy
    return xx, xy, yy


def _centred_gram_3d(pts: list) -> tuple[float, ...]:
    """``(Cxx, Cxy, Cxz, Cyy, Cyz, Czz)`` of ``C = AᵀA``, ``A`` the points minus their mean, over its largest entry."""
    k = len(pts)
    sx = sy = sz = 0.0
    for px, py, pz in pts:
        sx += px
        sy += py
        sz += pz
    mx, my, mz = sx / k, sy / k, sz / k
    h = max(max(abs(px - mx), abs(py - my), abs(pz - mz)) for px, py, pz in pts) or 1.0
    return _moments_3d([((px - mx) / h, (py - my) / h, (pz - mz) / h) for px, py, pz in pts])


def _moments_3d(rows) -> tuple[float, ...]:
    """``(Σxx, Σxy, Σxz, Σyy, Σyz, Σzz)`` of 3-vectors ``rows`` (plain floats)."""
    xx = xy = xz = yy = yz = zz = 0.0
    for dx, dy, dz in rows:
        xx += dx * dx
        xy += dx * dy
        xz += dx * dz
        yy += dy * dy
        yz += dy * dz
        zz += dz * dz
    return xx, xy, xz, yy, yz, zz


def _slider_rows(mech: Mechanism, pl: _Plan, x: list) -> tuple[list[np.ndarray], list[str]]:
    """Rows and owners of the constraints after the links (sliders, then extra constraints).

    Each is its definition in :mod:`symkin.constraints` evaluated in floats; ``x`` are
    the node coordinates (tuples of floats).
    """
    rows, owners = [], []
    for c in slider_constraints(mech):
        for r in c.rows(FLOATS, x, x):
            rows.append(_dense(r, pl.dim, pl.ncoord))
            owners.append(c.owner)
    return rows, owners


def _dense(r, dim: int, ncoord: int) -> np.ndarray:
    """A :class:`~symkin.constraints.Row` of floats as a dense row over all coordinates."""
    row = np.zeros(ncoord)
    inv = 1.0 / r.scale
    for k, coef, vec in r.terms:
        w = coef * inv
        for a in range(dim):
            row[dim * k + a] += w * vec[a]
    return row


def constraint_rows(mech: Mechanism, tolerances=DEFAULT, xyz: np.ndarray | None = None) -> ConstraintRows:
    """All constraint rows of ``mech`` (see module docstring), over all coordinates.

    Rows come link by link (a link's bars, then its rows out of a degenerate hull), then
    slider by slider.  ``xyz`` (n_nodes, dim), when given, are ``mech``'s coordinates as
    an array (saves converting them again).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> rows = constraint_rows(get("fourbar_appendix"))
    >>> rows.matrix.shape, rows.owners[0]
    ((3, 8), 'link crank (A-B)')
    """
    pl = plan(mech.topology)
    pts = [c for _, c in mech.nodes]
    bars = _bar_block(pl, pts)
    pieces, owners, start = [], [], 0
    for (name, idx, end), body in zip(pl.bodies, body_constraints(mech)):
        if _certainly_full_hull([pts[k] for k in idx], tolerances.geometry):
            continue
        x = pts if xyz is None else xyz  # the body's definition, evaluated in floats
        extra = [_dense(r, pl.dim, pl.ncoord) for r in body.rows(FLOATS, x, x, tolerances.geometry)]
        if extra:
            pieces += [bars[start:end], np.array(extra)]
            owners += list(pl.bar_owners[start:end]) + [body.owner] * len(extra)
            start = end
    sliders, slider_owners = _slider_rows(mech, pl, pts) if slider_constraints(mech) else ([], [])
    if not pieces and not sliders:
        return ConstraintRows(matrix=bars, owners=pl.bar_owners)
    pieces.append(bars[start:])
    owners += list(pl.bar_owners[start:])
    if sliders:
        pieces.append(np.array(sliders))
        owners += slider_owners
    return ConstraintRows(matrix=np.vstack(pieces), owners=tuple(owners))


def geometric_matrix(mech: Mechanism, boundary: bool = False, reduced: bool = False) -> np.ndarray:
    """The geometric matrix ``G = Σ ḡ_e`` (eq. 3, the paper's A5 for the appendix four-bar).

    Parameters
    ----------
    boundary : bool
        Return the paper's A6 form: rows and columns of fixed coordinates replaced by
        the identity (eq. 4 with boundary conditions).
    reduced : bool
        Return only the free coordinates' block, the matrix whose null space is the
        motion space and whose eigenvalues the analysis uses.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> G = geometric_matrix(get("fourbar_appendix"))
    >>> G.shape, bool(abs(G - G.T).max() == 0)
    ((8, 8), True)
    """
    j = constraint_rows(mech).matrix
    g = j.T @ j
    free = free_mask(mech)
    if reduced:
        return g[np.ix_(free, free)]
    if boundary:
        g = g.copy()
        g[~free, :] = 0.0
        g[:, ~free] = 0.0
        g[~free, ~free] = 1.0
    return g


# ---------------------------------------------------------------------- parameter rows
def _pair_for_rotation(x: list, idx) -> tuple[int, int]:
    """First node of the link and the node farthest from it (best conditioned pair).

    ``x``: coordinates as nested lists; ties go to the first node in the link's order.
    """
    if len(idx) == 2:
        return idx[0], idx[1]
    first = x[idx[0]]
    dist2 = [sum((a - b) ** 2 for a, b in zip(x[k], first)) for k in idx]
    return idx[0], idx[dist2.index(max(dist2))]


def _add_planar_rotations(out: np.ndarray, terms, x: list) -> np.ndarray:
    """Add ``sign ·`` the planar angular-velocity row of each node pair to ``out``; return it.

    ``terms`` are ``(row, sign, i, j)`` and ``x`` the coordinates as nested lists.  The
    row of the pair is ``ω = n·(ẋ_j − ẋ_i)/|d|²`` with ``d = x_j − x_i`` and ``n`` = ``d``
    turned by +90°.  Plain floats: for the few terms of a mechanism this is faster than
    any NumPy expression.
    """
    for row, sign, i, j in terms:
        (xi, yi), (xj, yj) = x[i], x[j]
        dx, dy = xj - xi, yj - yi
        w = sign / (dx * dx + dy * dy)
        out[row, 2 * j] += -dy * w
        out[row, 2 * j + 1] += dx * w
        out[row, 2 * i] -= -dy * w
        out[row, 2 * i + 1] -= dx * w
    return out


def rotation_rows(mech: Mechanism, link: str, xyz: np.ndarray | None = None) -> np.ndarray:
    """Rows giving the angular velocity of ``link`` from nodal velocities.

    Planar: one row, ``ω = n·(ẋ_j − ẋ_i)/|x_j − x_i|``.  Spatial: three rows (ωx, ωy,
    ωz), the least-squares solution of ``ẋ_k − ẋ_i = ω × (x_k − x_i)`` over the link's
    nodes; for a rod (collinear nodes) this is the angular velocity normal to its axis
    (the spin about the axis does not move any node and is not defined).  ``xyz``: the
    coordinates as an (n_nodes, dim) array, when the caller has them.
    """
    pl = plan(mech.topology)
    x = _xyz(mech) if xyz is None else xyz
    dim, ncoord = pl.dim, pl.ncoord
    idx = pl.links[link]
    if dim == 2:
        xl = x.tolist()
        i, j = _pair_for_rotation(xl, idx)
        return _add_planar_rotations(np.zeros((1, ncoord)), [(0, 1.0, i, j)], xl)
    # spatial: v_k - v_i = -[r_k]x ω  for every other node k  →  ω = B⁺ (v_k - v_i)
    i = idx[0]
    others = idx[1:]
    xl = x.tolist()
    xi = xl[i]
    fast = _spatial_rotation_blocks([[a - b for a, b in zip(xl[k], xi)] for k in others])
    if fast is not None:  # node k gets its block, the first node minus their sum (plain floats)
        out = [[0.0] * ncoord for _ in range(3)]
        for block, k in zip(fast, others):
            for row, brow in zip(out, block):
                for c in range(3):
                    row[3 * k + c] += brow[c]
                    row[3 * i + c] -= brow[c]
        return np.array(out)
    blocks = []
    for k in others:
        r = x[k] - x[i]
        blocks.append(-np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]]))
    b = np.vstack(blocks)  # (3·len(others), 3)
    h, _, _ = affine_hull(x[list(idx)], DEFAULT.geometry)
    bpinv = np.linalg.pinv(b, rcond=1e-10) if h >= 2 else _rod_pinv(x[idx[-1]] - x[i], len(others))
    rows = np.zeros((3, ncoord))
    for col, k in enumerate(others):
        block = bpinv[:, 3 * col: 3 * col + 3]
        rows[:, 3 * k: 3 * k + 3] += block
        rows[:, 3 * i: 3 * i + 3] -= block
    return rows


#: the normal equations of a link's angular velocity are used when ``λ_min/λ_max`` of ``BᵀB``
#: is certainly above this (their error is then below about ``ε / _WELL_CONDITIONED``)
_WELL_CONDITIONED = 1e-4


def _spatial_rotation_blocks(r: list) -> list | None:
    """``B⁺`` of a spatial link by its normal equations, block by node, or None when not well conditioned.

    ``r`` are the other nodes relative to the first (k triples of floats); ``B`` stacks
    ``−[r_k]×``, so ``BᵀB = Σ (|r_k|² I − r_k r_kᵀ)`` (3 × 3, the link's inertia-like
    matrix, positive definite unless the nodes are collinear) and the block of node k of
    ``B⁺ = (BᵀB)⁻¹ Bᵀ`` is ``(BᵀB)⁻¹ [r_k]×`` (returned as k nested 3 × 3 lists).  Used
    when ``4 det / tr³`` (a lower bound on ``λ_min/λ_max``: ``λ_min >= det / (λ_max
    λ_mid)`` and ``λ_max λ_mid <= (tr/2)²``) exceeds :data:`_WELL_CONDITIONED`; otherwise
    the SVD-based pseudo-inverse decides (rods, nearly collinear links).  Plain floats: a
    link has a few nodes.
    """
    # in units of the largest component: no overflow or underflow at the ends of the coordinate range
    h = max(abs(v) for row in r for v in row)
    if not h > 0.0:
        return None
    r = [[v / h for v in row] for row in r]
    sxx, sxy, sxz, syy, syz, szz = _moments_3d(r)
    a, b, c = syy + szz, sxx + szz, sxx + syy  # the diagonal of |r|² I − r rᵀ summed
    d, e, f = -sxy, -sxz, -syz  # (0, 1), (0, 2), (1, 2)
    tr = a + b + c
    # cofactors of the symmetric [[a, d, e], [d, b, f], [e, f, c]]
    c00, c01, c02 = b * c - f * f, e * f - d * c, d * f - b * e
    det = a * c00 + d * c01 + e * c02
    if not (tr > 0.0 and 4.0 * det > _WELL_CONDITIONED * tr * tr * tr):
        return None
    c11, c12, c22 = a * c - e * e, d * e - a * f, a * b - d * d
    dh = det * h  # B = h B' for the scaled r': B⁺ = B'⁺ / h
    inv = [[c00 / dh, c01 / dh, c02 / dh], [c01 / dh, c11 / dh, c12 / dh], [c02 / dh, c12 / dh, c22 / dh]]
    out = []
    for x, y, z in r:  # (BᵀB)⁻¹ [r]×,  [r]× = [[0, −z, y], [z, 0, −x], [−y, x, 0]]
        out.append([[m1 * z - m2 * y, m2 * x - m0 * z, m0 * y - m1 * x] for m0, m1, m2 in inv])
    return out


def _rod_pinv(r: np.ndarray, n_others: int) -> np.ndarray:
    """ω normal to a rod from the velocity of its far node only: ω = r × v / |r|²."""
    cross = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]]) / float(r @ r)
    out = np.zeros((3, 3 * n_others))
    out[:, 3 * (n_others - 1):] = cross
    return out


def twist_rows(mech: Mechanism, link: str, xyz: np.ndarray | None = None) -> np.ndarray:
    """Velocity of the link's first node followed by its angular velocity (3 or 6 rows)."""
    pl = plan(mech.topology)
    dim = pl.dim
    i = pl.links[link][0]
    vel = np.zeros((dim, pl.ncoord))
    vel[:, dim * i: dim * i + dim] = np.eye(dim)
    return np.vstack([vel, rotation_rows(mech, link, xyz)])


def _axis_vector(mech: Mechanism, axis) -> np.ndarray:
    """Unit vector of a rotation axis: two node names (from the first to the second) or a vector."""
    if isinstance(axis[0], str):
        pl = plan(mech.topology)
        nodes = mech.nodes
        (a, ca), (b, cb) = nodes[pl.index[axis[0]]], nodes[pl.index[axis[1]]]
        vec = [q - p for p, q in zip(ca, cb)]
    else:
        vec = [float(v) for v in axis]
    n = math.sqrt(sum(v * v for v in vec))
    return np.array([v / n for v in vec])


def _link_rotation(mech: Mechanism, pl: _Plan, link: str, xyz) -> np.ndarray:
    """:func:`rotation_rows` of ``link``; zero for the fixed frame of a joint model (``ground``, no such link)."""
    if link == GROUND and link not in pl.links:
        return np.zeros((1 if pl.dim == 2 else 3, pl.ncoord))
    return rotation_rows(mech, link, xyz)


def parameter_rows(mech: Mechanism, param: Parameter, xyz: np.ndarray | None = None) -> np.ndarray:
    """Rows (physical units) of one kinematic parameter over all nodal velocity components.

    A rotation is the link's angular velocity (:func:`rotation_rows`; spatial: about the
    unit axis), a joint the second link's minus the first's (spatial: ``a·(ω₂ − ω₁)``).
    ``xyz``: the coordinates as an (n_nodes, dim) array, when the caller has them.
    """
    pl = plan(mech.topology)
    dim, ncoord, index = pl.dim, pl.ncoord, pl.index
    kind = param.kind
    if kind == "rotation":
        rows = rotation_rows(mech, param.target[0], xyz)
        return rows if dim == 2 else (_axis_vector(mech, param.axis) @ rows)[None, :]
    if kind == "joint":  # the rotation of the second link relative to the first (about the axis)
        rows = _link_rotation(mech, pl, param.target[1], xyz) - _link_rotation(mech, pl, param.target[0], xyz)
        return rows if dim == 2 else (_axis_vector(mech, param.axis) @ rows)[None, :]
    if kind == "twist":
        return twist_rows(mech, param.target[0], xyz)
    if kind == "velocity":
        i = index[param.target[0]]
        comps = [AXES.index(param.component)] if param.component else range(dim)
        rows = np.zeros((len(comps), ncoord))
        for r, c in enumerate(comps):
            rows[r, dim * i + c] = 1.0
        return rows
    if kind == "slide":  # the slider's rate row, as its definition states it (symkin.constraints)
        x = _xyz(mech) if xyz is None else xyz
        pts = [tuple(map(float, c)) for c in x]
        rows = slider_constraint(mech, param.target[0]).rate_rows(FLOATS, pts, pts)
        return np.array([_dense(r, dim, ncoord) for r in rows])
    raise ValueError(f"unknown parameter kind {kind!r}")


@dataclass(frozen=True, eq=False)
class _PlanarProgram:
    """The rows of a planar parameter list: a constant block plus signed link rotations.

    A planar rotation, joint, twist or velocity row is a constant (unit velocity
    components) plus ``±`` the rotation row of a link (:func:`rotation_rows`), so the rows
    of a whole list are a copy of one constant block and one :func:`_add_planar_rotations`.
    A test keeps it equal to the stacked :func:`parameter_rows`.
    """

    const: np.ndarray  # (k, ncoord)
    labels: tuple      # of the k rows
    terms: tuple       # (row, sign, i, j) for a two-node link, (row, sign, node positions) for a body
    static: bool       # every term has its pair


def _planar_terms(pl: _Plan, param: Parameter) -> tuple[np.ndarray, list] | None:
    """Constant rows and ``(row, sign, link)`` rotation terms of one planar parameter, or None."""
    kind, target = param.kind, param.target
    if kind == "rotation":
        return np.zeros((1, pl.ncoord)), [(0, 1.0, target[0])]
    if kind == "joint":  # the fixed frame of a joint model turns not
        return np.zeros((1, pl.ncoord)), [(0, s, link) for s, link in ((1.0, target[1]), (-1.0, target[0]))
                                          if link != GROUND or link in pl.links]
    if kind == "twist":
        const = np.zeros((3, pl.ncoord))
        i = pl.links[target[0]][0]
        const[0, 2 * i], const[1, 2 * i + 1] = 1.0, 1.0
        return const, [(2, 1.0, target[0])]
    if kind == "velocity":
        comps = [AXES.index(param.component)] if param.component else range(2)
        const = np.zeros((len(comps), pl.ncoord))
        for r, c in enumerate(comps):
            const[r, 2 * pl.index[target[0]] + c] = 1.0
        return const, []
    return None


@lru_cache(maxsize=256)
def _planar_program(topology, params: tuple) -> _PlanarProgram | None:
    """The :class:`_PlanarProgram` of ``params`` (None when one of them is a slide)."""
    pl = plan(topology)
    consts, terms = [], []
    for p in params:
        got = _planar_terms(pl, p)
        if got is None:
            return None
        start = sum(c.shape[0] for c in consts)
        consts.append(got[0])
        terms += [(start + r, sign, pl.links[link]) for r, sign, link in got[1]]
    terms = tuple((r, sign, *ln) if len(ln) == 2 else (r, sign, ln) for r, sign, ln in terms)
    return _PlanarProgram(const=np.vstack(consts) if consts else np.zeros((0, pl.ncoord)),
                          labels=tuple(lab for p in params for lab in p.labels(2)),
                          terms=terms, static=all(len(t) == 4 for t in terms))


def _run_planar(prog: _PlanarProgram, xl: list) -> np.ndarray:
    """The rows of ``prog`` at the coordinates ``xl`` (a list of (x, y) per node)."""
    terms = prog.terms if prog.static else \
        [t if len(t) == 4 else (t[0], t[1], *_pair_for_rotation(xl, t[2])) for t in prog.terms]
    return _add_planar_rotations(prog.const.copy(), terms, xl)


def parameters_matrix(mech: Mechanism, params, xyz: np.ndarray | None = None) -> tuple[np.ndarray, tuple[str, ...]]:
    """Stacked rows and labels of a list of parameters (``xyz`` as in :func:`parameter_rows`).

    Planar lists without slides run their cached :class:`_PlanarProgram`; others stack
    :func:`parameter_rows`.
    """
    params = params if isinstance(params, tuple) else tuple(params)
    prog = _planar_program(mech.topology, params) if mech.dim == 2 else None
    if prog is not None:  # plain floats: the nodes' own tuples when no array is given
        return _run_planar(prog, [c for _, c in mech.nodes] if xyz is None else xyz.tolist()), prog.labels
    x = _xyz(mech) if xyz is None else xyz
    labels = tuple(lab for p in params for lab in p.labels(mech.dim))
    blocks = [parameter_rows(mech, p, x) for p in params]
    if not blocks:
        return np.zeros((0, mech.dim * len(mech.nodes))), labels
    return (np.vstack(blocks) if len(blocks) > 1 else blocks[0]), labels
