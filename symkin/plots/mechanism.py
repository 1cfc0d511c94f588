"""Draw a mechanism at its configuration, optionally with motion-space vectors as arrows.

The drawings of the paper's Figs. 4, 6, 7 and 11-13: links as lines (bars) or filled
polygons (bodies of three or more nodes), fixed nodes as black triangles, node names, and
the nodal velocities of one or several motions (eq. 9: ``{ẋ} = [V]{β}``) as arrows.

Plots only draw results: the velocities come from :func:`symkin.analyze`
(``Analysis.uncontrolled_motions``), from :func:`symkin.motion_space` or from the caller.
matplotlib is imported inside the functions, so ``import symkin`` does not import it.
"""
from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from symkin.analysis.classification import Motion
from symkin.analysis.motion_space import MotionSpace, motion_space
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.model.pairs import joint_kind
from symkin.tolerances import DEFAULT

__all__ = ["draw_mechanism", "draw_leg_lines", "added_nodes"]

#: colours: bars and bodies, ground, nodes; arrows cycle through ARROW_COLOURS
LINK_COLOUR = "#3b6ea5"
BODY_FILL = "#a9c4e0"
GROUND_COLOUR = "#7f7f7f"
ARROW_COLOURS = ("#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#bcbd22")


# ---------------------------------------------------------------------- shared helpers (also used by paths.py)
def is_3d(ax) -> bool:
    """True for an mplot3d axes."""
    return getattr(ax, "name", "") == "3d"


def new_axes(three_d: bool, figsize=(6.4, 5.2)):
    """A new pyplot figure with one (3D when asked) axes."""
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=figsize)
    return fig.add_subplot(projection="3d" if three_d else None)


def set_equal_3d(ax, points: np.ndarray) -> None:
    """Equal scales on the three axes of a 3D plot around ``points`` (k, 3)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-12) * 1.08
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def added_nodes(mech: Mechanism) -> set[str]:
    """The nodes the joints of a model added (``R1.axis``, ``P2.line``, ``U1.axis2`` ...).

    Named ``<joint id>.<role>``; a user never writes them, so plots neither draw, trace nor
    label them as joints.  Empty for a model written by its nodes.
    """
    ids = {j.id for j in mech.joints}
    return {n for n in mech.node_names if "." in n and n.split(".", 1)[0] in ids}


def coordinates(mech: Mechanism) -> np.ndarray:
    """Nodal coordinates of ``mech``, shape (n, dim), in node order."""
    return np.array([c for _, c in mech.nodes], dtype=float)


def _hull_2d(p: np.ndarray) -> list[int]:
    """Indices of the convex hull of planar points ``p`` (k, 2), counter-clockwise (monotone chain)."""
    order = sorted(range(len(p)), key=lambda k: (p[k, 0], p[k, 1]))

    def cross(o, a, b):
        return (p[a, 0] - p[o, 0]) * (p[b, 1] - p[o, 1]) - (p[a, 1] - p[o, 1]) * (p[b, 0] - p[o, 0])

    lower, upper = [], []
    for k in order:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], k) <= 0:
            lower.pop()
        lower.append(k)
    for k in reversed(order):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], k) <= 0:
            upper.pop()
        upper.append(k)
    return lower[:-1] + upper[:-1]


def _body_shape(p: np.ndarray) -> tuple[str, Any]:
    """How to draw a body with nodes ``p`` (k, dim): ``("line", (i, j))``, ``("polygon", idx)`` or
    ``("hull3d", simplices)`` (non-coplanar spatial body)."""
    centred = p - p.mean(axis=0)
    s, vt = np.linalg.svd(centred, full_matrices=False)[1:]
    size = max(float(s[0]), 1e-300)
    if s.size < 2 or s[1] <= 1e-9 * size:  # collinear: a segment between the extreme nodes
        along = centred @ vt[0]
        return "line", (int(np.argmin(along)), int(np.argmax(along)))
    if p.shape[1] == 3 and s.size >= 3 and s[2] > 1e-9 * size:
        from scipy.spatial import ConvexHull

        return "hull3d", ConvexHull(p).simplices
    plane = centred @ vt[:2].T
    return "polygon", _hull_2d(plane)


def _project(x: np.ndarray, three_d: bool) -> np.ndarray:
    """Coordinates to draw: all three in 3D, x-y otherwise (projection of a spatial mechanism)."""
    return x if three_d else x[:, :2]


# ---------------------------------------------------------------------- motions
def _as_motions(mech: Mechanism, motion) -> list[tuple[str, np.ndarray]]:
    """Normalise ``motion`` into ``[(label, velocities (n, dim))]``."""
    n, dim = len(mech.nodes), mech.dim
    idx = mech.node_index()
    if motion is None:
        return []
    if isinstance(motion, MotionSpace):
        v = motion.V
        return [(f"v{k + 1}", v[:, k].reshape(n, dim)) for k in range(v.shape[1])]
    if isinstance(motion, Motion):
        vel = np.zeros((n, dim))
        for name, vec in motion.velocities:
            vel[idx[name]] = vec
        return [("uncontrolled motion", vel)]
    if isinstance(motion, dict):
        vel = np.zeros((n, dim))
        for name, vec in motion.items():
            if name not in idx:
                raise SymkinError(f"motion: unknown node {name!r} (nodes: {', '.join(mech.node_names)})")
            vec = np.asarray(vec, dtype=float).ravel()
            if vec.size != dim:
                raise SymkinError(f"motion: the velocity of {name} needs {dim} components, got {vec.size}")
            vel[idx[name]] = vec
        return [("motion", vel)]
    if isinstance(motion, numbers.Integral):
        ms = motion_space(mech)
        k = int(motion)
        if not -ms.dof <= k < ms.dof:
            raise SymkinError(f"motion: column {k} does not exist; the motion space has {ms.dof} vector(s)")
        k %= ms.dof
        return [(f"v{k + 1}", ms.V[:, k].reshape(n, dim))]
    if isinstance(motion, np.ndarray):
        if motion.size != n * dim:
            raise SymkinError(f"motion: an array of nodal velocities needs {n * dim} values, got {motion.size}")
        return [("motion", motion.astype(float).reshape(n, dim))]
    if isinstance(motion, (list, tuple)):
        out = []
        for k, item in enumerate(motion):
            if isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):
                out += [(item[0], vel) for _, vel in _as_motions(mech, item[1])]
                continue
            for label, vel in _as_motions(mech, item):
                out.append((label if label.startswith("v") else f"{label} {k + 1}", vel))
        return out
    raise SymkinError("motion must be a symkin.Motion, a dict node -> velocity, a motion-space column index, "
                      f"a MotionSpace, an array of nodal velocities or a list of those; got {type(motion).__name__}")


# ---------------------------------------------------------------------- the drawing
def draw_mechanism(mech: Mechanism, ax=None, motion=None, scale: float | None = None, *,
                   labels: bool = True, title: str | None = None):
    """Draw ``mech`` at its configuration, with optional nodal-velocity arrows.

    Parameters
    ----------
    mech : Mechanism
        The mechanism; drawn at the coordinates of its nodes.
    ax : matplotlib Axes, optional
        Where to draw.  ``None`` creates a figure (3D axes for a spatial mechanism).  A
        spatial mechanism drawn on 2D axes is projected on the x-y plane.
    motion : optional
        Velocities to draw as arrows at the nodes (eq. 9, ``{ẋ} = [V]{β}``):

        * a :class:`symkin.Motion` (an entry of ``Analysis.uncontrolled_motions``);
        * a dict ``{node: velocity}`` (missing nodes do not move);
        * an ``int`` ``k``: column ``k`` of ``symkin.motion_space(mech).V``, labelled
          ``v{k+1}`` as the paper numbers the vectors in Figs. 7, 11-13;
        * a :class:`symkin.MotionSpace`: all its vectors, one colour each;
        * an array of all nodal velocities (node order, ``n·dim`` values);
        * a list of the above, each optionally as a ``(label, motion)`` pair for the legend.
    scale : float, optional
        Arrow length per unit of velocity (model length units).  Default: the largest
        arrow is 30 % of the mechanism's extent.  Velocities of a motion-space basis have
        no physical size (eq. 9 holds for any β), so only their directions and ratios
        are meaningful.
    labels : bool
        Write the node names.
    title : str, optional
        Axes title; default the mechanism's name when the axes has no title yet.

    Returns
    -------
    matplotlib Axes
        Artists carry a ``gid``: ``link:NAME``, ``nodes``, ``fixed``, ``sliders`` (blocks on
        fixed lines), ``slider:ID`` (the line), ``motion:LABEL`` (one quiver per motion).
        A prismatic leg (a link carrying a moving line on which a platform joint slides) is one
        segment from its base joint to the platform joint; the node that only fixes its line is
        not drawn as a joint.  A model written by its joints (``[[joints]]``) is drawn by them:
        links by the points the user gave (joint points and listed nodes), each P or C as a
        leg ``leg:ID`` (one segment over the points of its two links on its line: from the base
        joint to the platform joint) with its block ``slider:ID`` (a square on the line at the
        runner's node; a dashed ``guide:ID`` when the guide is ground), each spatial R and U
        axis as a short segment ``axis:ID`` (``axis:ID.1``, ``axis:ID.2``), S joints as balls
        ``spheres``; the nodes a joint added (``R1.axis``, ``P2.line``, ``U1.axis2`` ...) are
        neither drawn nor labelled.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> from symkin.plots import draw_mechanism
    >>> mech = symkin.catalogue.get("fourbar_flat")
    >>> ax = draw_mechanism(mech, motion=symkin.analyze(mech).uncontrolled_motions[0])
    >>> sorted(a.get_gid() for a in ax.collections)
    ['motion:uncontrolled motion']
    """
    if ax is None:
        ax = new_axes(mech.dim == 3)
    three_d = is_3d(ax) and mech.dim == 3
    x = coordinates(mech)
    xp = _project(x, three_d)
    idx = mech.node_index()
    fixed = set(mech.fixed)
    ground = set(mech.ground_links)
    extent = float(np.ptp(xp, axis=0).max()) if len(xp) > 1 else 1.0
    extent = extent if extent > 0 else mech.length_scale

    view = _JointView(mech, x) if mech.joints else None
    legs = {} if view else _prismatic_legs(mech, x)
    for name, nodes in mech.links:
        colour = GROUND_COLOUR if name in ground else LINK_COLOUR
        if view is not None:  # by the points the user gave: the joints' added nodes are not the link's shape
            shown = view.shape(name)
            if shown is None:
                continue
            pts = xp[[idx[n] for n in shown]]
        else:
            pts = _project(legs[name], three_d) if name in legs else xp[[idx[n] for n in nodes]]
        _draw_link(ax, name, pts, colour, three_d, ground=name in ground)

    extra_points = [xp if view is None else xp[[idx[n] for n in mech.node_names if n not in view.helpers]]]
    if view is not None:
        extra_points += view.draw(ax, three_d, extent)
    for s in mech.sliders:
        if s.kind != "line" or view is not None:
            continue  # moving lines are inside their link; planes are not drawn; a joint's guide: its view
        k = idx[s.node]
        d = np.asarray(s.direction, float)
        d = d / np.linalg.norm(d)
        point = np.asarray(s.point, float)
        foot = point + d * float((x[k] - point) @ d)
        half = 0.6 * mech.length_scale
        seg = _project(np.array([foot - half * d, foot + half * d]), three_d)
        ax.plot(*seg.T, linestyle="--", color=GROUND_COLOUR, linewidth=1.2, zorder=1, gid=f"slider:{s.id}")
        extra_points.append(seg)

    on_line = {s.node for s in mech.sliders if s.kind == "line"} if view is None else view.blocks
    # nodes that only carry a leg's line, or that a joint added (R1.axis, P2.line, U1.axis2 ...): not joints
    helpers = _line_helpers(mech) if view is None else view.helpers
    moving = [k for k, n in enumerate(mech.node_names) if n not in fixed and n not in on_line and n not in helpers]
    blocks = [k for k, n in enumerate(mech.node_names) if n not in fixed and n in on_line and view is None]
    ground_idx = [k for k, n in enumerate(mech.node_names) if n in fixed and n not in helpers]
    kw = dict(linestyle="none", zorder=4)
    if moving:
        ax.plot(*xp[moving].T, marker="o", markersize=7, markerfacecolor="white", markeredgecolor="black",
                markeredgewidth=1.4, gid="nodes", **kw)
    if blocks:  # sliding blocks on fixed lines
        ax.plot(*xp[blocks].T, marker="s", markersize=10, markerfacecolor="white", markeredgecolor="black",
                markeredgewidth=1.4, gid="sliders", **kw)
    if ground_idx:
        ax.plot(*xp[ground_idx].T, marker="^", markersize=11, color="black", gid="fixed", **kw)
    if labels:
        stacked = set() if view is None else view.stacked()
        for k, n in enumerate(mech.node_names):
            if n in helpers or n in stacked:
                continue
            if three_d:
                ax.text(*xp[k], f" {n}", fontsize=9, zorder=5)
            else:
                ax.annotate(n, xp[k], xytext=(5, 5), textcoords="offset points", fontsize=9, zorder=5)

    motions = _as_motions(mech, motion)
    if motions:
        vmax = max(float(np.linalg.norm(_project(v, three_d), axis=1).max()) for _, v in motions)
        if scale is None:
            scale = 0.3 * extent / vmax if vmax > 0 else 1.0
        for c, (label, vel) in enumerate(motions):
            tips = _draw_arrows(ax, xp, _project(vel, three_d) * scale, label,
                                ARROW_COLOURS[c % len(ARROW_COLOURS)], three_d, vmax * scale)
            extra_points.append(tips)
        ax.legend(loc="best", fontsize=8)

    allp = np.vstack(extra_points)
    if three_d:
        set_equal_3d(ax, allp)
        ax.set_zlabel("z")
    else:
        ax.update_datalim(allp)
        ax.set_aspect("equal", adjustable="datalim")
        ax.margins(0.12)
        ax.autoscale_view()
    ax.set_xlabel("x")
    ax.set_ylabel("y" if three_d or mech.dim == 2 else "y (x-y projection)")
    if title is not None or not ax.get_title():
        ax.set_title(mech.name if title is None else title, fontsize=10)
    return ax


def leg_lines(mech: Mechanism) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The lines of a planar parallel manipulator's legs: ``[(link, point, direction)]``.

    For each joint of the platform (``platform`` in the model file), the leg link it is in
    (a two-node link): the line through its two nodes, or, for a prismatic leg, the moving
    line its joint slides on.  Empty without a platform or for a spatial model.
    """
    if mech.platform is None or mech.dim != 2:
        return []
    x = coordinates(mech)
    idx = mech.node_index()
    links = dict(mech.links)
    joints = links.get(mech.platform, ())
    out = []
    for name, nodes in mech.links:
        if name == mech.platform or len(nodes) != 2:
            continue
        on = [n for n in nodes if n in joints]
        slid = [s for s in mech.sliders if s.kind == "moving_line" and s.link == name and s.node in joints]
        if slid:
            a, b = slid[0].line
        elif len(on) == 1:
            a, b = nodes
        else:
            continue
        d = x[idx[b]] - x[idx[a]]
        if np.linalg.norm(d) > 0:
            out.append((name, x[idx[a]], d / np.linalg.norm(d)))
    return out


def draw_leg_lines(mech: Mechanism, ax=None):
    """Draw the legs' lines of a planar parallel manipulator and their common point (a type-2 sketch).

    At a type-2 (DKP-input) configuration of a planar parallel manipulator the legs' lines
    (:func:`leg_lines`) meet in one point (or are parallel); this draws them, dashed, across
    the drawing, and their least-squares common point as a star.  It only draws: where the
    lines are parallel (no finite common point within ten extents of the drawing) the star is left out.

    Returns
    -------
    matplotlib Axes
        Lines ``gid`` ``leg-line:LINK``, the point ``gid`` ``common-point``.
    """
    if ax is None:
        ax = new_axes(False)
    lines = leg_lines(mech)
    if len(lines) < 2:
        return ax
    x = coordinates(mech)
    extent = max(float(np.ptp(x, axis=0).max()), mech.length_scale)
    centre = x.mean(axis=0)
    # least squares: the point nearest to every line, sum of (I - d d^T)(p - a) = 0
    m = sum(np.eye(2) - np.outer(d, d) for _, _, d in lines)
    r = sum((np.eye(2) - np.outer(d, d)) @ a for _, a, d in lines)
    point = np.linalg.lstsq(m, r, rcond=None)[0]
    finite = bool(np.linalg.norm(point - centre) < 10 * extent)
    reach = np.linalg.norm(point - centre) + extent if finite else extent
    for name, a, d in lines:
        t0 = float((centre - a) @ d)
        seg = np.array([a + (t0 - reach) * d, a + (t0 + reach) * d])
        ax.plot(*seg.T, linestyle=(0, (4, 3)), color="#d62728", linewidth=0.9, zorder=1, gid=f"leg-line:{name}",
                scalex=False, scaley=False)
    if finite:
        ax.plot(*point, marker="*", markersize=12, color="#d62728", markeredgecolor="black", linestyle="none",
                zorder=6, gid="common-point", label="legs' lines meet (type 2)")
    return ax


def _prismatic_legs(mech: Mechanism, x: np.ndarray) -> dict[str, np.ndarray]:
    """The whole leg of each two-node link that carries a moving line: ``{link: (2, dim) ends}``.

    A prismatic leg is modelled as a link A-D (D a node that only fixes the line) with the
    platform joint C sliding on the line A-D: it is drawn as one segment over A, D and C, from
    the base joint to the platform joint, not ending at D.
    """
    idx = mech.node_index()
    links = dict(mech.links)
    legs: dict[str, np.ndarray] = {}
    for s in mech.sliders:
        if s.kind != "moving_line" or s.link not in links or len(links[s.link]) != 2:
            continue
        ends = legs.get(s.link, x[[idx[n] for n in links[s.link]]])
        pts = np.vstack([ends, x[idx[s.node]]])
        d = x[idx[s.line[1]]] - x[idx[s.line[0]]]
        along = (pts - pts[0]) @ d
        legs[s.link] = pts[[int(np.argmin(along)), int(np.argmax(along))]]
    return legs


def _line_helpers(mech: Mechanism) -> set[str]:
    """Nodes that only define a leg's moving line: in that one link, no slider of theirs, not fixed."""
    use: dict[str, int] = {}
    for _, nodes in mech.links:
        for n in nodes:
            use[n] = use.get(n, 0) + 1
    sliding = {s.node for s in mech.sliders}
    fixed = set(mech.fixed)
    out = set()
    for s in mech.sliders:
        if s.kind == "moving_line":
            out |= {n for n in s.line if use.get(n, 0) == 1 and n not in sliding and n not in fixed}
    return out


def _draw_link(ax, name: str, pts: np.ndarray, colour: str, three_d: bool, ground: bool) -> None:
    style = dict(color=colour, linewidth=3.0, solid_capstyle="round", zorder=2, gid=f"link:{name}")
    if len(pts) == 2:
        ax.plot(*pts.T, **style)
        return
    kind, data = _body_shape(pts)
    if kind == "line":
        ax.plot(*pts[list(data)].T, **style)
        return
    face = "#d9d9d9" if ground else BODY_FILL
    if three_d:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        faces = [pts[list(data)]] if kind == "polygon" else [pts[list(s)] for s in data]
        ax.add_collection3d(Poly3DCollection(faces, facecolor=face, edgecolor=colour, linewidth=1.5, alpha=0.55,
                                             gid=f"link:{name}"))
        return
    from matplotlib.patches import Polygon

    hull = pts[list(data)] if kind == "polygon" else pts
    ax.add_patch(Polygon(hull, closed=True, facecolor=face, edgecolor=colour, linewidth=2.0, alpha=0.8,
                         hatch="///" if ground else None, zorder=2, gid=f"link:{name}"))


def _draw_arrows(ax, xp: np.ndarray, arrows: np.ndarray, label: str, colour: str, three_d: bool,
                 longest: float) -> np.ndarray:
    """Arrows from the nodes; nodes with (relatively) zero velocity get none.  Returns the tips."""
    lengths = np.linalg.norm(arrows, axis=1)
    keep = lengths > 1e-9 * max(longest, 1e-300)
    if not keep.any():  # a motion that moves no node of the drawing: mark the label only
        ax.plot([], [], color=colour, label=f"{label} (no node moves)", gid=f"motion:{label}")
        return xp
    base, vec = xp[keep], arrows[keep]
    if three_d:
        ax.quiver(*base.T, *vec.T, color=colour, arrow_length_ratio=0.18, linewidth=2.0, label=label,
                  gid=f"motion:{label}")
    else:
        ax.quiver(*base.T, *vec.T, angles="xy", scale_units="xy", scale=1.0, color=colour, width=0.006,
                  zorder=6, label=label, gid=f"motion:{label}")
    return base + vec


class _JointView:
    """How a model written by its joints is drawn (see :func:`draw_mechanism`).

    ``helpers``: the nodes a joint added (named ``<joint id>.<role>``), never drawn as joints;
    ``blocks``: the runner's node of each P and C (drawn as a block on its line).
    """

    def __init__(self, mech: Mechanism, x: np.ndarray):
        self.mech, self.x = mech, x
        self.idx = mech.node_index()
        self.helpers = added_nodes(mech)
        self.links = dict(mech.links)
        self.fixed = set(mech.fixed)
        self.lines = {}  # joint id -> (point, unit direction, slider)
        for j in mech.joints:
            if not joint_kind(j.type).block:  # drawn as a block on its line (symkin.model.pairs.JointKind)
                continue
            try:
                s = mech.slider(j.id)
            except KeyError:
                continue
            if s.kind == "moving_line":
                a, b = x[self.idx[s.line[0]]], x[self.idx[s.line[1]]]
                point, d = a, b - a
            elif s.kind == "line":
                point, d = np.asarray(s.point, float), np.asarray(s.direction, float)
            else:
                continue
            self.lines[j.id] = (point, d / np.linalg.norm(d), s)
        self.blocks = {s.node for _, _, s in self.lines.values()}
        self.tol = DEFAULT.geometry * mech.length_scale  # on a line: as the joints were placed

    def stacked(self) -> set[str]:
        """Blocks at the point of another drawn node (a slide of zero): their label would cover it."""
        others = [self.x[self.idx[n]] for n in self.mech.node_names if n not in self.helpers and n not in self.blocks]
        return {b for b in self.blocks
                if any(np.linalg.norm(self.x[self.idx[b]] - p) <= self.tol for p in others)}

    def real(self, link: str) -> list[str]:
        """The link's nodes the user gave or a joint's point stands for (not the added ones)."""
        return [n for n in self.links.get(link, ()) if n not in self.helpers]

    def _on(self, name: str, jid: str) -> bool:
        point, d, _ = self.lines[jid]
        r = self.x[self.idx[name]] - point
        return float(np.linalg.norm(r - (r @ d) * d)) <= self.tol

    def shape(self, link: str) -> list[str] | None:
        """The nodes that draw ``link``, or None (fewer than two, or a part of a leg drawn whole)."""
        nodes = self.real(link)
        if len(nodes) < 2:
            return None
        for j in self.mech.joints:
            if j.id in self.lines and link in j.links and all(self._on(n, j.id) for n in nodes):
                return None
        return nodes

    def _centre(self, j) -> str | None:
        if j.id in self.idx:
            return j.id
        pools = [self.fixed if link == "ground" else set(self.links.get(link, ())) for link in j.links]
        common = [n for n in self.links.get(j.links[1], ()) if n in pools[0] and n in pools[1]
                  and n not in self.helpers] if j.links[1] != "ground" else \
            [n for n in self.links.get(j.links[0], ()) if n in self.fixed and n not in self.helpers]
        return common[0] if common else None

    def draw(self, ax, three_d: bool, extent: float) -> list[np.ndarray]:
        """Legs, blocks' guides and joint axes; returns the drawn points (projected)."""
        x, idx, out = self.x, self.idx, []
        for j in self.mech.joints:
            if j.id not in self.lines:
                continue
            point, d, s = self.lines[j.id]
            names = [n for link in j.links if link != "ground" for n in self.real(link) if self._on(n, j.id)]
            names.append(s.node)
            t = [float((x[idx[n]] - point) @ d) for n in names]
            ends = np.array([point + min(t) * d, point + max(t) * d])
            seg = _project(ends, three_d)
            if "ground" in j.links:  # a block on a fixed guide: the guide dashed
                half = 0.6 * self.mech.length_scale
                foot = x[idx[s.node]]
                guide = _project(np.array([foot - half * d, foot + half * d]), three_d)
                ax.plot(*guide.T, linestyle="--", color=GROUND_COLOUR, linewidth=1.2, zorder=1, gid=f"guide:{j.id}")
                out.append(guide)
            if max(t) > min(t):
                ax.plot(*seg.T, color=LINK_COLOUR, linewidth=3.0, solid_capstyle="round", zorder=2,
                        gid=f"leg:{j.id}")
                out.append(seg)
            block = _project(x[[idx[s.node]]], three_d)
            ax.plot(*block.T, marker="s", markersize=10, markerfacecolor="white", markeredgecolor="black",
                    markeredgewidth=1.4, linestyle="none", zorder=4, gid=f"slider:{j.id}")
        if self.mech.dim != 3:
            return out
        half = 0.12 * extent
        for j in self.mech.joints:
            axes = joint_kind(j.type).axes  # the added nodes its drawn axes point to
            ends = tuple((f"{j.id}.{a}", f"axis:{j.id}" if len(axes) == 1 else f"axis:{j.id}.{k + 1}")
                         for k, a in enumerate(axes))
            centre = self._centre(j) if ends else None
            if centre is None:
                continue
            c = x[idx[centre]]
            for end, gid in ends:
                if end not in idx:
                    continue
                a = x[idx[end]] - c
                a = a / np.linalg.norm(a)
                seg = _project(np.array([c - half * a, c + half * a]), three_d)
                ax.plot(*seg.T, color="black", linewidth=1.6, zorder=3, gid=gid)
                out.append(seg)
        return out
