"""Plots of a traced path: indicators with located events (Figs. 3c, 10), node traces (Fig. 5)
and the mechanism at each located singular configuration (small multiples).

Every function reads a :class:`symkin.paths.trace.Path` and draws it; nothing is computed
here but unit conversions.  Events are numbered as in the text report and the JSON
``events`` and labelled with the link's absolute angle where there is one
(:func:`event_label`).  :func:`save_path_figures` writes all of them in one PNG (what
``symkin path ... --plot FILE.png`` writes) with matplotlib's Agg canvas, without touching
pyplot's global state.
"""
from __future__ import annotations

import math
from pathlib import Path as FilePath

import numpy as np

from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.paths.trace import Path
from symkin.plots.mechanism import added_nodes, coordinates, draw_leg_lines, draw_mechanism, is_3d, new_axes, set_equal_3d

__all__ = ["plot_indicators", "plot_traces", "plot_input_output", "plot_event_configurations", "path_figure",
           "save_path_figures", "abscissa", "event_label", "place_labels", "place_point_labels", "COLUMN_WIDTH", "FONT", "DPI",
           "floor_fonts"]

#: one-column print width (inches) and the smallest text at that width (points): the figures of
#: :mod:`symkin.plots` are drawn at ``COLUMN_WIDTH`` wide (or wider with text scaled by the same
#: ratio), so none of their text prints under ``FONT`` points in one column of a paper
COLUMN_WIDTH = 3.5
FONT = 9
#: resolution of the PNGs the commands write (a one-column figure is then ~1050 pixels wide)
DPI = 300

#: colour and marker of each test function and of its located events
STYLE = {
    Kind.IM: dict(colour="#d62728", marker="o"),
    Kind.DKP_INPUT: dict(colour="#1f77b4", marker="s"),
    Kind.DKP_OUTPUT: dict(colour="#2ca02c", marker="D"),
    Kind.BRANCH_POINT: dict(colour="#9467bd", marker="o"),
    Kind.LIM: dict(colour="#ff7f0e", marker="v"),  # a link stops: a downward triangle
}
_CURVES = (  # indicator key, style key, legend label
    ("im_indicator", Kind.IM, r"IM indicator $\lambda_{F+1}$ (eigenvalue of G)"),
    (str(Kind.DKP_INPUT), Kind.DKP_INPUT, "DKP-input test (signed determinant)"),
    (str(Kind.DKP_OUTPUT), Kind.DKP_OUTPUT, "DKP-output test"),
)
_EVENT_KINDS = (Kind.IM, Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.LIM)
_ZOOM_3D = 1.25  # the 3-D node traces of path_figure: the cube's size in its axes (matplotlib's default: 1)
_PANELS_PER_ROW = 3  # small multiples of save_path_figures: panels per row (one column wide)
_LINESTYLE = {str(Kind.DKP_OUTPUT): (0, (5, 2)), str(Kind.BRANCH_POINT): ":"}  # dashed: visible where it overlaps DKP-input


def _check(path: Path) -> None:
    if not isinstance(path, Path):
        raise SymkinError(f"expected a symkin Path (from symkin.paths.trace.trace), got {type(path).__name__}")
    if not path.points:
        raise SymkinError("the path has no points to plot")


def _unit_factor(path: Path, unit: str) -> tuple[float, str]:
    if unit not in ("deg", "rad"):
        raise SymkinError(f"unit must be 'deg' or 'rad', got {unit!r}")
    if path.kind != "angle":
        return 1.0, "model length"
    return (180.0 / math.pi, "deg") if unit == "deg" else (1.0, "rad")


def abscissa(path: Path, unit: str = "deg", x: str = "auto") -> tuple[np.ndarray, str, str]:
    """The horizontal coordinate of :func:`plot_indicators`: ``(values, "input"|"arclength", label)``.

    ``x="auto"`` uses the input when it is strictly monotone along the path, and the
    arclength ``s`` otherwise (the input turns back at a DKP-input turning point of a
    1-DOF mechanism, where a plot against the input would fold over itself).
    """
    if x not in ("auto", "input", "arclength"):
        raise SymkinError(f"x must be 'auto', 'input' or 'arclength', got {x!r}")
    conv, name = _unit_factor(path, unit)
    inputs = np.array([p.input for p in path.points], float) * conv
    steps = np.diff(inputs)
    monotone = bool(np.all(steps > 0) or np.all(steps < 0)) if steps.size else True
    if x == "input" or (x == "auto" and monotone):
        along = ",\nfrom the model's configuration" if path.kind == "angle" else ""
        return inputs, "input", f"input {path.drive} [{name}]{along}"
    s = np.array([p.s for p in path.points], float)
    why = "\n(the input turns back)" if x == "auto" else ""
    return s, "arclength", (f"arclength s [model lengths]{why}" if why else "arclength s along the path [model lengths]")


def plot_indicators(path: Path, ax=None, unit: str = "deg", *, x: str = "auto", bifurcation: bool = False,
                    annotate: bool = True, yscale: str = "linear", linthresh: float = 1e-4,
                    numbers_only: bool = False):
    """Plot the indicators along ``path`` with its located singular events (paper Figs. 3c, 10).

    Drawn against the driving input when it is monotone along the path, else against the
    arclength (see :func:`abscissa`; ``x`` forces one):

    * the IM indicator ``λ_{F+1}``, the first eigenvalue of the reduced geometric matrix
      above the F generic zeros (eq. 8, §IV-A, Fig. 10).  G is positive semidefinite, so
      it touches zero at an IM configuration without changing sign;
    * the signed DKP test functions, determinants of the velocity equations augmented by
      the unit input (output) rows (eqs. 12, 16): they change sign at a DKP-input
      (DKP-output) configuration;
    * with ``bifurcation=True``, the determinant of the continuation's augmented Jacobian,
      which changes sign at a simple branch point (IM);
    * every located event (kinds IM, DKP-input, DKP-output, LIM) as a marker on the zero line,
      in the colour of its test function, annotated with its number (as in the text report
      and the JSON ``events``), its kind, its input value and, for a planar rotation, the
      link's absolute angle.

    All indicators are dimensionless, so one axis shows them together: linear by default (a
    log scale would hide the sign changes of the determinants); ``yscale="symlog"`` magnifies
    values near zero while keeping their signs.

    Parameters
    ----------
    path : symkin.paths.trace.Path
    ax : matplotlib Axes, optional
        ``None`` creates a figure.
    unit : {"deg", "rad"}
        Unit of angle inputs on the axis and in the annotations.
    x : {"auto", "input", "arclength"}
    bifurcation : bool
        Also draw the bifurcation test function.
    annotate : bool
        Write each event's input value next to its marker.
    numbers_only : bool
        Write the event's number alone (the figure of :func:`path_figure` gives the rest in
        its event panels).
    yscale : {"linear", "symlog"}
        Vertical scale; ``"symlog"`` is linear within ``±linthresh`` and logarithmic outside.
    linthresh : float
        Linear range of the symlog scale.

    Returns
    -------
    matplotlib Axes
        Curves have ``gid`` ``indicator:KEY``; event markers ``event:KIND`` (one artist
        per kind, one marker per event).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> from symkin.paths.trace import trace
    >>> from symkin.plots import plot_indicators
    >>> p = trace(symkin.catalogue.get("fourbar_appendix"), stop=360, unit="deg")
    >>> ax = plot_indicators(p)
    >>> [l.get_gid() for l in ax.lines if l.get_gid().startswith("event")]
    ['event:DKP-output']
    """
    _check(path)
    if yscale not in ("linear", "symlog"):
        raise SymkinError(f"yscale must be 'linear' or 'symlog', got {yscale!r}")
    if ax is None:
        ax = new_axes(False, figsize=(7.5, 4.8))
    xs, mode, xlabel = abscissa(path, unit, x)
    conv, uname = _unit_factor(path, unit)
    curves = list(_CURVES) + ([(str(Kind.BRANCH_POINT), Kind.BRANCH_POINT, "bifurcation test det[J; t]")] if bifurcation else [])
    for key, style, label in curves:
        vals = np.array([_num(p.indicators.get(key)) for p in path.points], float)
        if not np.isfinite(vals).any():
            continue
        ax.plot(xs, vals, color=STYLE[style]["colour"], linewidth=1.6, label=label, gid=f"indicator:{key}",
                linestyle=_LINESTYLE.get(key, "-"))
    ax.axhline(0.0, color="black", linewidth=0.8, zorder=1, gid="zero")

    for kind, chosen in _events_by_kind(path):
        ex = [(e.input * conv) if mode == "input" else e.s for _, e in chosen]
        st = STYLE[kind]
        ax.plot(ex, [0.0] * len(ex), linestyle="none", marker=st["marker"], markersize=8,
                markerfacecolor=st["colour"], markeredgecolor="black", zorder=5,
                label=f"{kind} event{'s' if len(ex) > 1 else ''} (located)", gid=f"event:{kind}")
        if annotate:
            for (k, e), xe in zip(chosen, ex):
                ax.annotate(str(k) if numbers_only else event_label(path, k, e, unit, lines=True), (xe, 0.0),
                            xytext=(0, 12), textcoords="offset points", ha="center", va="bottom", fontsize=FONT,
                            color=st["colour"],
                            zorder=6, gid=f"event-label:{k}",
                            bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.8))
    if yscale == "symlog":
        ax.set_yscale("symlog", linthresh=linthresh)
    place_labels(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("indicator (dimensionless)")
    if not ax.get_title():
        ax.set_title(f"Indicators along the path ({path.stop_reason})", fontsize=FONT)
    ax.grid(True, alpha=0.3)
    lines = len(ax.get_xlabel().splitlines())  # under the tick labels and the axis label
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=2.2 + 1.3 * lines,
              ncol=1 if numbers_only else 2, fontsize=FONT, frameon=False)
    return ax


def _renderer(ax):
    """The renderer of the canvas ``ax`` is drawn on (an Agg canvas is attached when there is none)."""
    fig = ax.get_figure(root=True)
    if fig.canvas is None or not hasattr(fig.canvas, "get_renderer"):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
    return fig.canvas.get_renderer()


def floor_fonts(fig, size: float = FONT) -> None:
    """Raise every text of ``fig`` under ``size`` points to ``size`` (tick labels included, also
    those drawn later): the last step of a figure meant for print, for the texts that helpers
    such as :func:`~symkin.plots.mechanism.draw_mechanism` write at their own sizes."""
    from matplotlib.text import Text

    for ax in fig.get_axes():
        for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
            if axis is None:
                continue
            for which, ticks in (("major", axis.get_major_ticks()), ("minor", axis.get_minor_ticks())):
                if any(t.label1.get_fontsize() < size or t.label2.get_fontsize() < size for t in ticks):
                    axis.set_tick_params(which=which, labelsize=size)
    for t in fig.findobj(Text):
        if t.get_fontsize() < size:
            t.set_fontsize(size)


def place_labels(ax, prefix: str = "event-label:", gap: float = 3.0) -> list:
    """Stack the event labels of ``ax`` (annotations whose ``gid`` starts with ``prefix``) so no two overlap.

    Labels are taken from left to right (by the abscissa of their marker); each goes to the
    lowest tier above its marker where its box, as rendered, meets no label already placed
    (``gap`` points apart), centred on the marker's abscissa.  The vertical limits
    then grow so the highest label stays inside the axes (linear scales).  The placement
    depends on the axes' size: :func:`path_figure` calls it again once the layout is fixed.

    Returns
    -------
    list of matplotlib.text.Annotation
        The labels, in the order placed.
    """
    labels = sorted((t for t in ax.texts if (t.get_gid() or "").startswith(prefix)), key=lambda t: t.xy[0])
    if not labels:
        return labels
    renderer = _renderer(ax)
    px = renderer.points_to_pixels(1.0)
    for t in labels:
        t.xyann = (0.0, 12.0)
    height = max(t.get_window_extent(renderer).height for t in labels) / px  # points
    placed = []
    for t in labels:
        tier, last = 0, None
        while True:
            t.xyann = (0.0, 12.0 + tier * (height + gap))
            box = t.get_window_extent(renderer).padded(gap * px / 2)
            if not any(box.overlaps(b) for b in placed) or (last is not None and box.bounds == last.bounds):
                break  # free, or a label that is not drawn (its box does not move): leave it
            tier, last = tier + 1, box
        placed.append(box)
    if ax.get_yscale() == "linear":  # room above the highest label: y1 so that 0 + its offset fits
        y0, y1 = ax.get_ylim()
        h = ax.get_window_extent(renderer).height
        need = max(b.y1 for b in placed) - ax.transData.transform((0.0, 0.0))[1]  # pixels above the zero line
        free = h - 6 * px - need
        if y0 < 0 < y1 and free > 0 and (-y0) * h / free > y1 - y0:
            ax.set_ylim(y0, y0 + (-y0) * h / free)
    return labels


#: where :func:`place_point_labels` tries a label around its point: sixteen directions, the four
#: diagonals first, then the sides, then between them (unit vectors)
_AROUND = tuple((math.cos(a), math.sin(a)) for a in np.radians(
    [45, -45, 135, -135, 0, 180, 90, -90, 22.5, -22.5, 157.5, -157.5, 67.5, -67.5, 112.5, -112.5]))


def _alignment(dx: float, dy: float) -> tuple[str, str]:
    """The text alignment that puts a label's box on the side ``(dx, dy)`` of its anchor."""
    ha = "left" if dx > 0.3 else ("right" if dx < -0.3 else "center")
    va = "bottom" if dy > 0.3 else ("top" if dy < -0.3 else "center")
    return ha, va


def _project_3d_labels(ax, labels) -> None:
    """Anchor each label with a 3-D point (attribute ``point_3d``) at that point's projection in the current view."""
    from mpl_toolkits.mplot3d import proj3d

    m = ax.get_proj()
    for t in labels:
        p = getattr(t, "point_3d", None)
        if p is not None:
            x, y, _ = proj3d.proj_transform(*np.asarray(p, float), m)
            t.xy = (float(x), float(y))


def place_point_labels(ax, prefix: str = "event-label:", gap: float = 2.0, rings: int = 8) -> list:
    """Move the point labels of ``ax`` (annotations whose ``gid`` starts with ``prefix``) so no two overlap.

    Each label, from left to right, takes the nearest place to its point — sixteen directions
    around it, at distances growing by a quarter of the label's height up to ``rings`` heights,
    then straight up, tier after tier — where its box, as rendered, meets no label placed before
    (``gap`` points apart) and stays inside the axes when it can.  On 3-D axes a label that
    carries its 3-D point (attribute ``point_3d``, as :func:`plot_traces` writes them) is first
    anchored at that point's projection in the axes' current view.  The placement depends on
    the axes' size and view: :func:`path_figure` calls it again once the layout is fixed.

    Returns
    -------
    list of matplotlib.text.Annotation
        The labels, in the order placed.
    """
    labels = [t for t in ax.texts if (t.get_gid() or "").startswith(prefix) and hasattr(t, "xyann")]
    if not labels:
        return labels
    renderer = _renderer(ax)
    ax.get_xlim()  # the limits and the aspect as they will be drawn
    ax.apply_aspect()
    if is_3d(ax):
        _project_3d_labels(ax, labels)
    labels.sort(key=lambda t: tuple(t.xy))
    px = renderer.points_to_pixels(1.0)
    frame = ax.get_window_extent(renderer)
    placed = []
    for t in labels:
        # the label's box for each alignment at its anchor, once; a candidate's box is that one moved
        # by its offset (an annotation's offset in points moves its box rigidly)
        t.xyann = (0.0, 0.0)
        boxes = {}
        for dx, dy in _AROUND:
            key = _alignment(dx, dy)
            if key not in boxes:
                t.set_horizontalalignment(key[0])
                t.set_verticalalignment(key[1])
                boxes[key] = t.get_window_extent(renderer)
        height = max(b.height for b in boxes.values()) / px  # points
        steps = int(rings * 4) + 1
        candidates = [(d * dx, d * dy) for d in (1.0 + k * height / 4 for k in range(steps)) for dx, dy in _AROUND]
        candidates += [(0.0, 1.0 + rings * height + j * (height + gap)) for j in range(len(labels) + 1)]
        choice = None
        for inside in (True, False):
            for dx, dy in candidates:
                box = boxes[_alignment(dx, dy)].translated(dx * px, dy * px).padded(gap * px / 2)
                if any(box.overlaps(b) for b in placed):
                    continue
                if inside and not (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0
                                   and box.y1 <= frame.y1):
                    continue
                choice = (dx, dy), box
                break
            if choice is not None:
                break
        (dx, dy), box = choice if choice is not None else (candidates[0], None)
        ha, va = _alignment(dx, dy)
        t.set_horizontalalignment(ha)
        t.set_verticalalignment(va)
        t.xyann = (dx, dy)
        placed.append(box if box is not None else t.get_window_extent(renderer))
    return labels


def _events_by_kind(path: Path):
    """``[(kind, [(number, event), ...])]`` for each kind of :data:`_EVENT_KINDS` that occurs, numbered as the report."""
    numbered = [(k, e) for k, e in enumerate(path.singular_events(), 1) if e.kind in _EVENT_KINDS]
    out = [(kind, [(k, e) for k, e in numbered if e.kind == kind]) for kind in _EVENT_KINDS]
    return [(kind, chosen) for kind, chosen in out if chosen]


def _num(v) -> float:
    return math.nan if v is None else float(v)


def plot_traces(path: Path, nodes=None, ax=None, *, show_mechanism: bool = True, annotate: bool = True,
                numbers_only: bool = False):
    """Plot the traces of nodes along ``path``, with the located singular configurations (Fig. 5).

    Parameters
    ----------
    path : symkin.paths.trace.Path
    nodes : sequence of str, optional
        Nodes to trace; default every node that is not fixed and moves along the path.
    ax : matplotlib Axes, optional
        ``None`` creates a figure (3D axes for a spatial mechanism).  A spatial path drawn
        on 2D axes is projected on the x-y plane.
    show_mechanism : bool
        Draw the mechanism at the path's first point in light grey, fixed nodes as
        triangles.
    annotate : bool
        Write the number and kind of each singular event next to its dot (numbered as in
        the text report and the JSON ``events``), placed so that no two labels overlap
        (:func:`place_point_labels`).
    numbers_only : bool
        Write the number alone (the figure of :func:`path_figure` names the kinds elsewhere).

    Returns
    -------
    matplotlib Axes
        One line per node (``gid`` ``trace:NODE``); the singular events (IM, DKP-input,
        DKP-output) are black dots at the traced nodes (one artist, ``gid`` ``events``,
        ``len(nodes)`` dots per event); the start positions ``gid`` ``start``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> from symkin.paths.trace import trace
    >>> from symkin.plots import plot_traces
    >>> p = trace(symkin.catalogue.get("fourbar_appendix"), stop=360, unit="deg")
    >>> ax = plot_traces(p)
    >>> sorted(l.get_gid() for l in ax.lines if l.get_gid().startswith("trace"))
    ['trace:B', 'trace:C']
    """
    _check(path)
    mech = path.mechanism
    names = list(path.node_names or mech.node_names)
    xyz_all = np.array([p.coordinates for p in path.points], float)
    if nodes is None:  # the nodes that move along the path (held legs of an F > 1 mechanism do not)
        fixed = set(mech.fixed)
        extent = np.ptp(xyz_all, axis=0).max(axis=1)
        fixed |= added_nodes(mech)  # a joint's added nodes (R1.axis, P2.line ...) are not the user's
        nodes = [n for k, n in enumerate(names) if n not in fixed and extent[k] > 1e-9 * mech.length_scale]
    elif isinstance(nodes, str):
        nodes = [nodes]
    unknown = [n for n in nodes if n not in names]
    if unknown:
        raise SymkinError(f"unknown node(s) {', '.join(map(repr, unknown))}; nodes: {', '.join(names)}")
    if ax is None:
        ax = new_axes(mech.dim == 3)
    three_d = is_3d(ax) and mech.dim == 3
    ncoord = 3 if three_d else 2
    cols = [names.index(n) for n in nodes]
    xyz = xyz_all[:, :, :ncoord]  # (points, nodes, dims)
    everything = [xyz.reshape(-1, ncoord)]

    if show_mechanism:
        first = xyz[0]
        idx = {n: k for k, n in enumerate(names)}
        for lname, lnodes in mech.links:
            pts = first[[idx[n] for n in lnodes]]
            if len(pts) > 2:
                pts = np.vstack([pts, pts[:1]])
            ax.plot(*pts.T, color="#b0b0b0", linewidth=2.0, zorder=1, gid=f"start-link:{lname}")
        fixed_idx = [idx[n] for n in mech.fixed]
        if fixed_idx:
            ax.plot(*first[fixed_idx].T, linestyle="none", marker="^", markersize=8, color="black", zorder=3,
                    gid="fixed", label="fixed nodes")
        everything.append(coordinates(mech)[:, :ncoord])

    for n, k in zip(nodes, cols):
        ax.plot(*xyz[:, k, :].T, linewidth=1.6, label=f"trace of {n}", gid=f"trace:{n}", zorder=2)
    ax.plot(*xyz[0, cols, :].T, linestyle="none", marker="o", markersize=5, markerfacecolor="white",
            markeredgecolor="black", zorder=4, gid="start", label="start")

    events = path.singular_events()
    pending = []  # (number, text, point): labelled once the limits are set (3-D: at the projected point)
    if events:
        dots = np.vstack([np.asarray(e.coordinates, float)[cols, :ncoord] for e in events])
        ax.plot(*dots.T, linestyle="none", marker="o", markersize=5, color="black", zorder=5, gid="events",
                label="nodes at the events")
        if annotate:
            for k, e in enumerate(events, 1):
                pending.append((k, str(k) if numbers_only else f"{k}. {e.kind}",
                                np.asarray(e.coordinates, float)[cols[0], :ncoord]))

    allp = np.vstack(everything)
    if three_d:
        set_equal_3d(ax, allp)
        ax.set_zlabel("z")
    else:
        ax.set_aspect("equal", adjustable="datalim")
    for k, text, p in pending:
        # 3-D: a 2-D annotation at the point's projection in the view (as matplotlib's 3-D examples do);
        # place_point_labels projects it again in the view as drawn (its point_3d)
        ann = ax.annotate(text, tuple(p[:2]), xytext=(4, 4), textcoords="offset points", fontsize=FONT, zorder=6,
                          gid=f"event-label:{k}",
                          bbox=dict(boxstyle="round,pad=0.1", facecolor="white", edgecolor="none", alpha=0.8))
        if three_d:
            ann.point_3d = tuple(float(c) for c in p)
    ax.set_xlabel("x")
    ax.set_ylabel("y" if (three_d or mech.dim == 2) else "y (x-y projection)")
    if not ax.get_title():
        ax.set_title(f"Node traces: {mech.name}", fontsize=FONT)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=FONT, borderaxespad=0.0)
    if annotate:
        place_point_labels(ax)
    return ax


def _output(path: Path):
    """The model's scalar output: ``(label, kind)`` or ``None`` (no output, a twist, several scalars)."""
    from symkin.solutions.frame_coordinates import output_coordinate

    c = output_coordinate(path.mechanism)
    return None if c is None else (c.label, c.kind)


def _unwrap_near(values: np.ndarray, period: float | None, s_values: np.ndarray, s_curve: np.ndarray,
                 curve: np.ndarray) -> np.ndarray:
    """Shift wrapped ``values`` by whole periods to the (unwrapped) ``curve`` at the same arclength."""
    if not period:
        return values
    near = np.interp(s_values, s_curve, curve)
    return values + period * np.round((near - values) / period)


def plot_input_output(path: Path, ax=None, unit: str = "deg", *, annotate: bool = True):
    """The input–output curve of ``path``: the model's output against its input, with the events on it.

    The first figure a kinematician draws of a 1-DOF loop.  Both values are in the
    convention of the path (and of its text report): the input along the path from the
    model's configuration, the output relative to the model's configuration, angles in
    ``unit`` (lengths in model units); the output angle is unwrapped along the path, so the
    curve is not cut at ±180°.  Every singular event is marked in the style of
    :func:`plot_indicators` and numbered as in the report; a DKP-input event is where the
    curve has a vertical tangent (the input turns back), a DKP-output event a horizontal one.

    Parameters
    ----------
    path : symkin.paths.trace.Path
        Of a model with one scalar output (``outputs`` in the model file).
    ax : matplotlib Axes, optional
        ``None`` creates a figure.
    unit : {"deg", "rad"}
    annotate : bool
        Number the events.

    Returns
    -------
    matplotlib Axes
        The curve has ``gid`` ``input-output``, the markers ``event:KIND``, the numbers
        ``event-label:K``.

    Examples
    --------
    >>> import matplotlib, symkin.paths.trace
    >>> matplotlib.use("Agg")
    >>> ax = plot_input_output(symkin.paths.trace.trace(symkin.catalogue.get("fourbar_appendix"), stop=360,
    ...                                                 unit="deg"))
    >>> ax.get_ylabel()
    "output rotation:rocker [deg]\\nfrom the model's configuration"
    """
    _check(path)
    out = _output(path)
    if out is None:
        raise SymkinError(f"{path.mechanism.name} has no scalar output: an input–output curve needs one "
                          "(outputs = [...] in the model file)")
    label, kind = out
    if ax is None:
        ax = new_axes(False, figsize=(3.5, 3.0))
    conv_in, name_in = _unit_factor(path, unit)
    conv_out = (180.0 / math.pi if unit == "deg" else 1.0) if kind == "angle" else 1.0
    name_out = ("deg" if unit == "deg" else "rad") if kind == "angle" else "model length"
    period = 360.0 if (kind == "angle" and unit == "deg") else (2 * math.pi if kind == "angle" else None)
    xs = np.array([p.input for p in path.points], float) * conv_in
    s_pts = np.array([p.s for p in path.points], float)
    ys = np.array([path.outputs(p, unit)[label]["relative"] for p in path.points], float)
    if period:
        ys = np.unwrap(ys, period=period)
    ax.plot(xs, ys, color="black", linewidth=1.4, gid="input-output", label="output vs input")
    for kind_, chosen in _events_by_kind(path):
        ex = np.array([e.input * conv_in for _, e in chosen])
        ey = np.array([path.outputs(e, unit)[label]["relative"] for _, e in chosen], float)
        ey = _unwrap_near(ey, period, np.array([e.s for _, e in chosen]), s_pts, ys)
        st = STYLE[kind_]
        ax.plot(ex, ey, linestyle="none", marker=st["marker"], markersize=7, markerfacecolor=st["colour"],
                markeredgecolor="black", zorder=5, label=str(kind_), gid=f"event:{kind_}")
        if annotate:
            for (k, _), x_, y_ in zip(chosen, ex, ey):
                ax.annotate(str(k), (x_, y_), xytext=(5, 4), textcoords="offset points", fontsize=9, zorder=6,
                            gid=f"event-label:{k}")
    ax.set_xlabel(f"input {path.drive} [{name_in}]")
    ax.set_ylabel(f"output {label} [{name_out}]\nfrom the model's configuration")
    if not ax.get_title():
        ax.set_title("Input–output curve", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=9, loc="best")
    return ax


def event_label(path: Path, number: int, event, unit: str = "deg", lines: bool = False) -> str:
    """``"1. IM at 210.9225° (absolute 165.9225°)"``: an event's number, kind, input and absolute angle.

    ``number`` counts the singular events from 1, as the text report and the JSON
    ``events`` do; the input is the value along the path (the plot's abscissa), the absolute
    angle (planar rotations, in [0°, 360°), as every command gives it) is shown where there is one.
    ``lines=True`` breaks it over three short lines for a marker's annotation.
    """
    conv, uname = _unit_factor(path, unit)
    sign = "°" if uname == "deg" else (" rad" if uname == "rad" else "")
    value = f"{event.input * conv:.4f}{sign}"
    absolute = None
    if event.absolute is not None:
        absolute = f"{event.absolute * conv:.4f}{sign}"
    if lines:
        return f"{number}. {event.kind}\n{value}" + (f"\nabs {absolute}" if absolute else "")
    return f"{number}. {event.kind} at {value}" + (f" (absolute {absolute})" if absolute else "")


def _panel_limits(path: Path, three_d: bool) -> np.ndarray:
    """(2, k) lower and upper corners around every point of the path (shared by all panels)."""
    ncoord = 3 if three_d else 2
    pts = np.vstack([np.asarray(p.coordinates, float)[:, :ncoord] for p in path.points]
                    + [np.asarray(e.coordinates, float)[:, :ncoord] for e in path.events])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = (lo + hi) / 2, np.maximum((hi - lo) / 2, 1e-12) * 1.1 + 0.04 * float((hi - lo).max())
    return np.vstack([centre - half, centre + half])


def plot_event_configurations(path: Path, axes=None, unit: str = "deg", *, traces: bool = True,
                              compact: bool = False):
    """Draw the mechanism at each located singular configuration, one small panel per event.

    Small multiples: every panel has the same axes limits (the extent of the whole path), so
    the panels compare at a glance; each is titled with :func:`event_label` (numbered as in
    the text report and the JSON) and its types and DOF from the event's analysis.  At a
    DKP-input (type-2) event of a planar parallel manipulator the legs' lines are drawn with
    their common point (:func:`~symkin.plots.mechanism.draw_leg_lines`).

    Parameters
    ----------
    path : symkin.paths.trace.Path
    axes : sequence of matplotlib Axes, optional
        One per singular event; ``None`` creates a figure with a row of panels.
    unit : {"deg", "rad"}
        Unit of angle inputs in the titles.
    traces : bool
        Draw the node traces of the whole path in light grey behind each mechanism.
    compact : bool
        For small panels: the title over short lines (:func:`event_label` with ``lines=True``,
        then the types and DOF) and no node names.

    Returns
    -------
    list of matplotlib Axes
        One per singular event (empty when there is none); each panel's links have ``gid``
        ``link:NAME`` (:func:`~symkin.plots.mechanism.draw_mechanism`), its traces
        ``context-trace:NODE``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> from symkin.paths.trace import trace
    >>> from symkin.plots.paths import plot_event_configurations
    >>> p = trace(symkin.catalogue.get("fourbar_appendix"), stop=360, unit="deg")
    >>> [ax.get_title().splitlines()[0] for ax in plot_event_configurations(p)]
    ['1. DKP-output at 137.5622° (absolute 215.0333°)', '2. DKP-output at 306.0810° (absolute 23.5521°)']
    """
    _check(path)
    _unit_factor(path, unit)
    events = path.singular_events()
    mech = path.mechanism
    if axes is None:
        if not events:
            return []
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(3.2 * len(events), 3.4), layout="constrained")
        axes = [fig.add_subplot(1, len(events), k + 1, projection="3d" if mech.dim == 3 else None)
                for k in range(len(events))]
    axes = list(axes)
    if len(axes) != len(events):
        raise SymkinError(f"{len(events)} singular event(s) but {len(axes)} axes")
    xyz = np.array([p.coordinates for p in path.points], float)
    moving = [k for k, n in enumerate(path.node_names) if n not in set(mech.fixed) | added_nodes(mech)]
    for k, (ax, e) in enumerate(zip(axes, events), 1):
        three_d = is_3d(ax) and mech.dim == 3
        ncoord = 3 if three_d else 2
        if traces:
            for j in moving:
                ax.plot(*xyz[:, j, :ncoord].T, color="#d0d0d0", linewidth=1.0, zorder=0,
                        gid=f"context-trace:{path.node_names[j]}")
        a = e.analysis
        detail = f"\n{', '.join(a.types) or 'regular'}; L = {a.dof}" if a is not None else ""
        if compact and a is not None:  # short lines; the kind is on the first line already
            import textwrap

            types = ", ".join(t for t in a.types if t != e.kind)
            detail = "\n" + "\n".join(textwrap.wrap((f"also {types}; " if types else "") + f"L = {a.dof}", 16))
        at = mech.with_coordinates(e.coordinates)
        title = event_label(path, k, e, unit, lines=compact) + detail
        draw_mechanism(at, ax=ax, labels=not compact, title=title)
        if e.kind == Kind.DKP_INPUT and not three_d:  # type 2: the legs' lines are concurrent
            draw_leg_lines(at, ax=ax)
        ax.title.set_fontsize(FONT)
        lim = _panel_limits(path, three_d)
        if three_d:
            set_equal_3d(ax, lim)
        else:
            ax.set_xlim(lim[0, 0], lim[1, 0])
            ax.set_ylim(lim[0, 1], lim[1, 1])
            ax.set_aspect("equal", adjustable="box")
        ax.tick_params(labelsize=FONT)
    return axes


def path_figure(path: Path, unit: str = "deg"):
    """The figure that :func:`save_path_figures` writes, on a standalone ``Figure`` (Agg canvas).

    Drawn for one column of a paper (:data:`COLUMN_WIDTH` inches wide, no text under
    :data:`FONT` points), one panel under another: the indicators (:func:`plot_indicators`),
    the input–output curve when the model has one output (:func:`plot_input_output`) and the
    node traces (:func:`plot_traces`), the events numbered on each as in the text report;
    below, in a subfigure, the mechanism at each singular event
    (:func:`plot_event_configurations`, ``compact``), three per row, titled with the event's
    kind, input, absolute angle, types and DOF.  pyplot is not touched.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig.subfigs`` is ``(top, events)`` when the path has singular events.
    """
    import textwrap

    _check(path)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    n_ev = len(path.singular_events())
    rows = -(-n_ev // _PANELS_PER_ROW) if n_ev else 0
    three_d = path.mechanism.dim == 3
    io = _output(path) is not None
    # inches: each top panel with its labels and legend; the 3-D traces (a square axes whose cube
    # fills only part of it) get more height and a zoomed cube, so they span the column
    heights = [3.3] + ([2.9] if io else []) + [4.6 if three_d else 3.6]
    events_h = (1.8 * rows + 0.35) if rows else 0.0
    fig = Figure(figsize=(COLUMN_WIDTH, sum(heights) + events_h + 0.55), layout="constrained")
    FigureCanvasAgg(fig)
    top, bottom = fig.subfigures(2, 1, height_ratios=[sum(heights), events_h]) if rows else (fig, None)
    grid = top.add_gridspec(len(heights), 1, height_ratios=heights)
    left = top.add_subplot(grid[0])
    if io:
        middle = plot_input_output(path, ax=top.add_subplot(grid[1]), unit=unit)
        middle.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=3.4, ncol=2, fontsize=FONT,
                      frameon=False, handlelength=1.5, columnspacing=1.0)  # under the axes: it covers no data
    right = top.add_subplot(grid[-1], projection="3d" if three_d else None)
    left.set_title("Indicators along the path", fontsize=FONT)
    right.set_title("Node traces", fontsize=FONT)
    plot_indicators(path, ax=left, unit=unit, numbers_only=True)
    plot_traces(path, ax=right, numbers_only=True)
    if three_d:
        right.set_box_aspect((1, 1, 1), zoom=_ZOOM_3D)
    # under the axes, below the tick labels (a zoomed 3-D cube's reach further down)
    right.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=6.0 if three_d else 3.5, ncol=2,
                 fontsize=FONT,
                 frameon=False, handlelength=1.5, columnspacing=1.0)
    if rows:
        panels = [bottom.add_subplot(rows, _PANELS_PER_ROW, k + 1, projection="3d" if three_d else None)
                  for k in range(n_ev)]
        plot_event_configurations(path, axes=panels, unit=unit, compact=True)
        for ax in panels:  # small multiples at one scale, the traces' axes give it: no ticks
            ax.set_xlabel("")
            ax.set_ylabel("")
            if three_d:
                ax.set_zlabel("")
            ax.tick_params(labelbottom=False, labelleft=False)
        bottom.suptitle("The mechanism at each singular event (same scale)", fontsize=FONT)
    title = (f"{path.mechanism.name}, driven by {path.drive}: {n_ev} singular event(s); "
             f"stopped: {path.stop_reason}")
    fig.suptitle("\n".join(textwrap.wrap(title, int(COLUMN_WIDTH * 72 / (0.52 * FONT)))), fontsize=FONT)
    floor_fonts(fig, FONT)
    # the labels' places depend on the axes' sizes: place them again once the layout is done, then keep it
    for _ in range(2):
        fig.canvas.draw()
        place_labels(left)
        place_point_labels(right)
    fig.canvas.draw()
    fig.set_layout_engine("none")
    return fig


def save_path_figures(path: Path, filename, unit: str = "deg") -> FilePath:
    """Write :func:`path_figure` to a PNG (what ``symkin path ... --plot FILE.png`` writes).

    Uses matplotlib's non-interactive Agg canvas on a standalone ``Figure`` (pyplot and
    its backend are not touched), so it works headless.  ``filename`` without a suffix is
    written as PNG.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    target = FilePath(filename)
    fig = path_figure(path, unit)
    try:
        fig.savefig(target, dpi=DPI, format=None if target.suffix else "png")
    except OSError as exc:
        raise SymkinError(f"{target}: cannot write the figure ({exc.strerror or exc})") from exc
    return target
