"""A rigid body of three or more nodes: its pairs are :class:`~symkin.constraints.bar.Bar`\\ s, plus the
rows that keep it rigid out of its affine hull when its nodes do not span the space.

Collinear nodes, or coplanar nodes in 3D, leave the pairwise bars flexible: a node can move
normal to the hull.  A rigid velocity field is affine, so for each node ``m`` off a *frame*
``f0, …, f_h`` of the body's nodes (``h`` the hull's dimension) and each normal ``n`` of the
hull the row ::

    n·(ẋ_m − (1 − Σ c_k) ẋ_f0 − Σ c_k ẋ_fk) = 0

holds, ``c`` the affine coordinates of ``m`` on the frame (``x_m − x_f0 = Σ c_k e_k``,
``e_k = x_fk − x_f0``).  :meth:`Body.rows` states it once, as ``(D ẋ_m − (D − Σ N_k) ẋ_f0 −
Σ N_k ẋ_fk)·n / (D |n|)`` with ``c_k = N_k / D``; its position equation (the CasADi closure)
is ``n·(x_m − (1 − Σ c⁰_k) x_f0 − Σ c⁰_k x_fk)``, ``c⁰`` the model's affine coordinates (closure
parameters).

Decisions (:meth:`Body.hull`, made once here for every backend): the hull's dimension and its
normals by an SVD (:func:`affine_hull`), the frame by a greedy search (:func:`affine_frame`).
The numeric core decides at every configuration (``alg.per_configuration``), the CasADi and
sympy forms once, at the model's configuration (the hull's dimension and the frame are constant
on the closure manifold).  What each algebra supplies (module docstring of
:mod:`symkin.constraints.algebra`):

==================  ================================  ==============================  ===========================
                    floats (the core)                 CasADi                          sympy
==================  ================================  ==============================  ===========================
normals ``n``       the SVD's, at the configuration   smooth in the frame (``e⊥``,    polynomial (``e⊥``,
                    (unit)                            ``e1 × e2``, the line's normal  ``e1 × e2``, ``e × a``,
                                                      basis), unit, the SVD's sign    ``e × (e × a)``)
                                                      at the model
``c = N / D``       least squares on the edges        ``Gram⁻¹ (e_k·(x_m − x_f0))``   ``D = l²`` or
                    (``D = 1``)                       (``D = 1``)                     ``|e1 × e2|²``, Cramer
==================  ================================  ==============================  ===========================

The floats keep the SVD's normals and the least-squares coordinates, the numbers the core
always had (bit for bit); on a rigid configuration every choice gives the same products
``a aᵀ`` summed over the normals, hence the same ``G``.  ``tests/constraints/test_body.py``
keeps the three equal (1e-12, random configurations, mm and m).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from symkin.constraints.algebra import cross, dot, perp, sub
from symkin.constraints.base import Constraint, Equation, Row
from symkin.tolerances import DEFAULT

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Body", "Hull", "affine_hull", "affine_frame"]

# NumPy is imported where it is used, not with the module: ``import symkin`` imports every
# constraint module (the pair kinds' discovery) and stays free of NumPy.


def affine_hull(points: np.ndarray, tol: float) -> tuple[int, np.ndarray, np.ndarray]:
    """Dimension ``h`` of the affine hull of ``points`` (k, d), its directions and normals.

    Directions (h, d) and normals (d-h, d) are orthonormal rows; ``tol`` is relative to
    the spread of the points.
    """
    import numpy as np

    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=True)
    scale = s[0] if s.size and s[0] > 0 else 1.0
    h = int(np.count_nonzero(s > tol * scale))
    return h, vt[:h], vt[h:]


def affine_frame(pts: np.ndarray, h: int) -> list[int]:
    """Indices of h+1 affinely independent points, chosen greedily for conditioning.

    Near-ties (within a relative 1e-9) go to the lowest index, so that a symmetric body gets
    the same frame at neighbouring configurations instead of one decided by rounding.
    """
    import numpy as np

    frame = [0]
    for _ in range(h):
        base = pts[frame[0]]
        span = np.array([pts[k] - base for k in frame[1:]]).reshape(-1, pts.shape[1])
        best, best_d = None, -1.0
        for k in range(len(pts)):
            if k in frame:
                continue
            d = pts[k] - base
            if span.size:
                q, _ = np.linalg.qr(span.T)
                d = d - q @ (q.T @ d)
            dist = float(np.linalg.norm(d))
            # ties within rounding go to the lower index, so symmetric bodies get one frame
            if best is None or dist > best_d * (1.0 + 1e-9):
                best, best_d = k, dist
        frame.append(best)
    return frame


class Hull(NamedTuple):
    """A degenerate body's decision: hull dimension, frame (positions in the body's node list), SVD normals."""

    h: int
    frame: tuple
    normals: np.ndarray


class Body(Constraint):
    """The out-of-hull rows of link ``link`` (node names ``names`` at node positions ``idx``)."""

    kind = "body"

    def __init__(self, link: str, names: tuple, idx: tuple):
        self.link, self.names, self.idx = link, names, idx
        self.owner = f"link {link} (rigidity out of its hull)"
        self.element = link
        self.where = f"links.{link}"

    def size(self, dim: int) -> int:
        raise NotImplementedError("a body's row count depends on its configuration: len(rows(...))")

    # ------------------------------------------------------------------ the decision
    def hull(self, X, tol: float = DEFAULT.geometry) -> Hull | None:
        """The :class:`Hull` of the body's nodes at positions ``X``, or None when they span the space
        (or are too few to need a row: ``k <= h + 1``)."""
        import numpy as np

        pts = np.array([X[k] for k in self.idx], dtype=float)
        h, _, normals = affine_hull(pts, tol)
        if h == pts.shape[1] or len(self.idx) <= h + 1:
            return None
        return Hull(h, tuple(affine_frame(pts, h)), normals)

    def frame_note(self, hull: Hull) -> str:
        """The sentence a backend that fixes the decision at the model reports."""
        return (f"link {self.link}: nodes span a {hull.h}-dimensional hull (frame "
                f"{', '.join(self.names[k] for k in hull.frame)}) — fixed at the model's configuration")

    def _decided(self, alg, X, X0, tol):
        hull = self.hull(X if alg.per_configuration else X0, tol)
        if hull is None:
            return None, (), ()
        f = [self.idx[k] for k in hull.frame]
        others = [self.idx[m] for m in range(len(self.idx)) if m not in hull.frame]
        return hull, f, others

    # ------------------------------------------------------------------ rows and equations
    def rows(self, alg, X, X0, tol: float = DEFAULT.geometry) -> list[Row]:
        hull, f, others = self._decided(alg, X, X0, tol)
        if hull is None:
            return []
        edges = [sub(X[k], X[f[0]]) for k in f[1:]]
        normals = self._normals(alg, edges, hull, X, X0, f)
        out = []
        for m in others:
            den, nums, total = self._affine(alg, X, f, m, edges)
            for n, nn in normals:
                terms = ((m, den, n), (f[0], -(den - total), n)) + tuple((f[k + 1], -nums[k], n)
                                                                        for k in range(hull.h))
                out.append(Row(terms, den * nn))
        return out

    def equations(self, alg, X, X0, tol: float = DEFAULT.geometry) -> list[Equation]:
        hull, f, others = self._decided(alg, X, X0, tol)
        if hull is None:
            return []
        edges = [sub(X[k], X[f[0]]) for k in f[1:]]
        normals = self._normals(alg, edges, hull, X, X0, f)
        names = dict(zip(self.idx, self.names))
        edges0 = [sub(X0[k], X0[f[0]]) for k in f[1:]]
        out = []
        for m in others:
            _, c0, _ = self._affine(_MODEL, X0, f, m, edges0)  # the model's affine coordinates
            cp = [alg.param(f"affine {self.link} ({names[m]} on {names[f[k + 1]]})", c0[k]) for k in range(hull.h)]
            target = X[m]
            for k, w in [(f[0], 1 - sum(cp))] + [(f[k + 1], cp[k]) for k in range(hull.h)]:
                target = tuple(t - w * x for t, x in zip(target, X[k]))
            out += [Equation(dot(n, target), nn) for n, nn in normals]
        return out

    def frame_equations(self, X, frame, m, coef) -> tuple:
        """The polynomial systems' form of the body: node ``m`` at the affine coordinates ``coef`` in
        the frame of the nodes ``frame`` (positions ``f0, f1[, f2]``), one equation per axis::

            x_m − (x_f0 + Σ c_k b_k) = 0,   b = (e, e⊥) planar, (e) a rod in space,
                                             (e1, e2, e1 × e2) in space,  e_k = x_fk − x_f0

        (with the distances of the frame's pairs, :meth:`~symkin.constraints.Bar.polynomial`, a
        rigid body whose orientation is kept: no mirror image).  The frame and the numbers
        ``coef`` (exact, snapped or scaled) are the caller's decision.
        """
        edges = [sub(X[k], X[frame[0]]) for k in frame[1:]]
        if len(edges[0]) == 2:
            basis = [edges[0], perp(edges[0])]
        elif len(edges) == 2:
            basis = edges + [cross(edges[0], edges[1])]
        else:
            basis = edges
        base = X[frame[0]]
        return tuple(X[m][a] - (base[a] + _weighted(coef, [b[a] for b in basis])) for a in range(len(base)))

    # ------------------------------------------------------------------ what the algebras supply
    def _normals(self, alg, edges, hull: Hull, X, X0, f) -> list[tuple]:
        """The hull's normals as ``(vector, norm)`` pairs (module docstring's table)."""
        if alg.per_configuration:  # the SVD's, decided with the hull at this configuration
            one = alg.const(1)
            return [(tuple(float(c) for c in n), one) for n in hull.normals]
        if alg.exact:
            return _exact_normals(alg, edges, [sub(X0[k], X0[f[0]]) for k in f[1:]], self, f)
        normals = _smooth_normals(alg, edges)
        if len(normals) == 1:  # the core's sign at the model
            model = _smooth_normals(alg, [sub(X0[k], X0[f[0]]) for k in f[1:]])[0][0]
            import numpy as np

            if float(np.dot(np.array(model, dtype=float), hull.normals[0])) < 0:
                normals = [(tuple(-c for c in normals[0][0]), normals[0][1])]
        return normals

    def _affine(self, alg, X, f, m, edges) -> tuple:
        """``(D, N, Σ N)``: the affine coordinates ``N_k / D`` of node ``m`` on the frame ``f``."""
        d = sub(X[m], X[f[0]])
        h = len(edges)
        if alg.per_configuration:  # least squares, as the core always did
            import numpy as np

            coef, *_ = np.linalg.lstsq(np.array(edges, dtype=float).T, np.array(d, dtype=float), rcond=None)
            return alg.const(1), tuple(coef), coef.sum()
        if alg.exact:  # polynomial: over l² (a rod) or |e1 × e2|² (Cramer)
            if h == 1:
                length = alg.pair_length(self.link, self.names[self.idx.index(f[0])],
                                         self.names[self.idx.index(f[1])], edges[0])
                tau = dot(d, edges[0])
                return length * length, (tau,), tau
            e1, e2 = edges
            n = cross(e1, e2)
            c1 = dot(e2, e2) * dot(e1, d) - dot(e1, e2) * dot(e2, d)
            c2 = dot(e1, e1) * dot(e2, d) - dot(e1, e2) * dot(e1, d)
            return dot(n, n), (c1, c2), c1 + c2
        # the Gram matrix's inverse times the edges' products (CasADi's closure and rows)
        g = [[dot(edges[a], edges[b]) for b in range(h)] for a in range(h)]
        r = [dot(edges[a], d) for a in range(h)]
        if h == 1:
            c = ((1 / g[0][0]) * r[0],)
            return 1.0, c, c[0]
        det = g[0][0] * g[1][1] - g[0][1] * g[1][0]
        inv = [[g[1][1] / det, (-g[0][1]) / det], [(-g[1][0]) / det, g[0][0] / det]]
        c = tuple(inv[k][0] * r[0] + inv[k][1] * r[1] for k in range(2))
        return 1.0, c, c[0] + c[1]


def _weighted(coef, values):
    """``Σ c_k v_k`` from 0 (the polynomial systems' order of terms)."""
    out = 0
    for c, v in zip(coef, values):
        out = out + c * v
    return out


class _ModelFloats:
    """Python floats for the model's affine coordinates, with the CasADi form's operations
    (``per_configuration`` and ``exact`` False: the Gram branch), so the closure's parameters
    are the values its expressions take at the model."""

    per_configuration = False
    exact = False


_MODEL = _ModelFloats()


def _smooth_normals(alg, edges) -> list[tuple]:
    """Unit normals of the hull as smooth functions of the frame's edges (CasADi; floats at the model)."""
    e = edges[0]
    if len(e) == 2:
        length = alg.norm(e)
        return [(tuple(c / length for c in perp(e)), 1.0)]
    if len(edges) == 2:
        n = cross(edges[0], edges[1])
        length = alg.norm(n)
        return [(tuple(c / length for c in n), 1.0)]
    length = alg.norm(e)
    return [(n, 1.0) for n in alg.unit_normals(tuple(c / length for c in e))]


def _exact_normals(alg, edges, edges0, body: Body, f) -> list[tuple]:
    """Polynomial normals with their norms: ``e⊥`` (norm ``l``); ``e1 × e2``; for a line in space
    ``e × a`` and ``e × (e × a)`` (``a`` the axis least aligned with ``e`` at the model), so that
    ``Σ n nᵀ / |n|² = I − ê êᵀ`` exactly."""
    e = edges[0]
    if len(edges) == 2:
        n = cross(edges[0], edges[1])
        return [(n, alg.sqrt(dot(n, n)))]
    length = alg.pair_length(body.link, body.names[body.idx.index(f[0])], body.names[body.idx.index(f[1])], e)
    if len(e) == 2:
        return [(perp(e), length)]
    n1 = cross(e, alg.least_aligned(e, edges0[0]))
    norm1 = alg.sqrt(alg.sp.expand(dot(n1, n1)))
    return [(n1, norm1), (cross(e, n1), length * norm1)]

