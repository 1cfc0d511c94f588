"""Plots of a singularity map (paper §VI, Figs. 14-16): indicator maps per working mode with the
traced loci and the mode's workspace boundary, the mechanism at each mode's seed, and a 3-D
surface of the IM indicator.

Every function reads a :class:`symkin.workspace.maps.WorkspaceMap` (and, to draw the
mechanism, the :class:`~symkin.model.mechanism.Mechanism` it was built from) and draws it;
nothing is computed here but ``|values|``, colour limits and the seed's nodal coordinates.

* :func:`plot_map` — one indicator of one mode: the IM indicator ``λ_{F+1}`` (§V) on a log
  scale of its absolute value, the signed DKP-input / DKP-output test functions (the values
  ``trace`` uses) with a diverging colour map symmetric about zero, then (by default) the
  traced curves of that mode (:func:`plot_curves`), its isolated singular points and its
  workspace boundary (:func:`plot_boundary`, the contour of the assembled mask);
* :func:`plot_seed` — the mechanism at a mode's seed configuration, over that mode's
  boundary and curves when the map's axes are the x and y of one node (a workspace map);
* :func:`plot_im_surface` — the IM indicator as a 3-D surface (Fig. 15);
* :func:`map_figure` / :func:`save_map_figure` — columns = modes, rows = indicators (+ the
  mechanism), one column of a paper wide: what ``symkin map ... --plot FILE.png`` writes;
  :func:`map_panel_figures` / :func:`save_map_panels` — one figure per panel (``--panels``).

Artists carry a ``gid``: ``indicator:NAME:MODE`` (the colour mesh), ``curve:KIND:MODE``,
``point:KIND:MODE``, ``boundary:MODE``, ``seed:MODE``, ``im_surface:MODE``; the panels of
:func:`map_figure` carry ``panel:MODE:NAME`` (``NAME`` an indicator or ``mechanism``), its colour
bars ``colourbar:NAME``.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path as FilePath

import numpy as np

from symkin.kinds import Kind
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.plots.mechanism import draw_mechanism
from symkin.plots.paths import COLUMN_WIDTH, DPI, FONT, STYLE, floor_fonts
from symkin.workspace.maps import ModeMap, WorkspaceMap

__all__ = ["INDICATORS", "plot_map", "plot_curves", "plot_boundary", "plot_seed", "plot_im_surface",
           "map_figure", "map_panel_figures", "save_map_figure", "save_map_panels", "panel_path", "axis_label",
           "seed_mechanism", "colour_scale", "ColourScale", "legend_handles"]

#: the indicators of a mode that :func:`plot_map` draws: name → (title, scale)
INDICATORS = {
    "im_indicator": (r"IM indicator $|\lambda_{F+1}|$", "log"),
    "dkp_input": ("DKP-input test", "signed"),
    "dkp_output": ("DKP-output test", "signed"),
}
#: a signed indicator whose largest ``|value|`` lies in ``[RAW_RANGE[0], RAW_RANGE[1])`` is drawn as it is;
#: outside (say every value about 1e-6) it is drawn divided by that largest value, on [-1, 1], and
#: its colour bar says so: ticks without exponents or an offset text either way
RAW_RANGE = (1e-2, 1e3)
#: colour maps: sequential for ``|IM|``, diverging (zero = white) for the signed DKP functions
CMAPS = {"log": "viridis", "signed": "PuOr_r"}
#: line style per curve kind (colours from the path plots, :data:`symkin.plots.paths.STYLE`)
LINESTYLES = {Kind.DKP_INPUT: "-", Kind.DKP_OUTPUT: (0, (5, 2)), Kind.IM: ":"}
#: marker per isolated point kind: the path plots' (IM, DKP, LIM: an orange downward triangle) and a cusp
#: of a traced curve (an orange upward triangle)
POINT_STYLES = {**STYLE, Kind.CUSP: dict(colour="#ff7f0e", marker="^"),
                Kind.MEETING: dict(colour="#8c564b", marker="X"), Kind.END: dict(colour="#7f7f7f", marker="o")}
#: legend text of each curve kind and point kind (a point of another kind: ``"KIND point"``)
CURVE_LABELS = {Kind.DKP_INPUT: "DKP-input curve", Kind.DKP_OUTPUT: "DKP-output curve", Kind.IM: "IM curve"}
POINT_LABELS = {Kind.IM: "IM point", Kind.LIM: "LIM point", Kind.CUSP: str(Kind.CUSP), Kind.MEETING: "meeting point",
                Kind.END: "end of a curve"}
BOUNDARY_COLOUR = "black"


# ---------------------------------------------------------------------- small helpers
def _check(wmap: WorkspaceMap) -> None:
    if not isinstance(wmap, WorkspaceMap):
        raise SymkinError(f"expected a symkin WorkspaceMap (from symkin.workspace_map), got {type(wmap).__name__}")


def _mode(wmap: WorkspaceMap, mode) -> ModeMap:
    """The mode of id ``mode`` (an int) or the :class:`ModeMap` itself."""
    if isinstance(mode, ModeMap):
        return mode
    for m in wmap.modes:
        if m.id == mode:
            return m
    raise SymkinError(f"the map has no mode {mode!r} (modes: {', '.join(str(m.id) for m in wmap.modes) or 'none'})")


def axis_label(label: str, unit: str = "deg") -> str:
    """An axis label with its unit: ``velocity:P.x`` → ``P.x [model length]``, ``rotation:L`` → ``angle of L [deg]``.

    >>> axis_label("velocity:P.x"), axis_label("rotation:crank", "rad"), axis_label("slide:S")
    ('P.x [model length]', 'angle of crank [rad]', 'slide S [model length]')
    """
    kind, _, name = label.partition(":")
    if kind == "rotation":
        return f"angle of {name} [{unit}]"
    if kind == "slide":
        return f"slide {name} [model length]"
    return f"{name or label} [model length]"


def mode_title(m: ModeMap) -> str:
    """``mode 0 (seed: model, 16 % assembled)``."""
    return f"mode {m.id} (seed: {m.seed}, {100 * m.fraction:.0f} % assembled)"


def _point_label(kind: str) -> str:
    return POINT_LABELS.get(kind, f"{kind} point")


@dataclass(frozen=True)
class ColourScale:
    """How an indicator is coloured, the same for every mode of a map (so their panels compare).

    ``norm`` maps the drawn values (``factor`` × the indicator; ``|value|`` for the IM
    indicator) to colours; ``ticks`` (at least three, inside the norm's range) and ``label``
    (two lines: the indicator, then its scale) are the colour bar's.
    """

    indicator: str
    norm: object
    factor: float
    label: str
    ticks: tuple[float, ...]

    @property
    def normalised(self) -> bool:
        """Whether the values are drawn divided by their largest magnitude (``factor != 1``)."""
        return self.factor != 1.0


def _log_ticks(lo: float, hi: float) -> tuple[float, ...]:
    """Three to five round values (1, 2, 5 × 10^k) in [lo, hi]; three rounded geometric steps when too few fit."""
    k0, k1 = int(np.floor(np.log10(lo))), int(np.ceil(np.log10(hi)))
    inside = lambda vals: [v for v in vals if lo <= v <= hi]  # noqa: E731
    for subs in ((1.0,), (1.0, 3.0), (1.0, 2.0, 5.0)):
        ticks = inside([m * 10.0 ** k for k in range(k0, k1 + 1) for m in subs])
        if len(ticks) > 5:
            ticks = ticks[:: -(-len(ticks) // 5)]
        if len(ticks) >= 3:
            return tuple(ticks)
    mid = float(f"{np.sqrt(lo * hi):.2g}")
    return (lo, mid, hi) if lo < mid < hi else tuple(np.geomspace(lo, hi, 3))


def colour_scale(wmap: WorkspaceMap, indicator: str) -> ColourScale:
    """The colour scale of ``indicator`` over every mode's assembled points of ``wmap``.

    The IM indicator: ``|λ_{F+1}|`` on a log scale from its smallest to its largest non-zero
    value.  A signed DKP test: symmetric about zero (zero is white), as it is when its largest
    magnitude ``v`` lies in :data:`RAW_RANGE`, else divided by ``v`` (a normalised scale on
    [-1, 1], labelled with ``v``).  The ticks are at least three values inside the range.

    >>> import symkin
    >>> m = symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3.5:3.5",
    ...                          y="velocity:P.y=0.2:4.4", n=5, refine=False)
    >>> s = colour_scale(m, "dkp_input")
    >>> s.norm.vmin == -s.norm.vmax, s.factor, len(s.ticks) >= 3
    (True, 1.0, True)
    """
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.ticker import MaxNLocator

    _check(wmap)
    if indicator not in INDICATORS:
        raise SymkinError(f"indicator {indicator!r}: expected one of {', '.join(INDICATORS)}")
    name, scale = INDICATORS[indicator]
    parts = [np.asarray(getattr(m, indicator), float)[np.asarray(m.assembled, bool)] for m in wmap.modes]
    values = np.concatenate(parts) if parts else np.zeros(0)
    finite = values[np.isfinite(values)]
    if scale == "log":
        pos = np.abs(finite)[np.abs(finite) > 0]
        hi = float(pos.max()) if pos.size else 1.0
        lo = float(pos.min()) if pos.size else hi / 1000
        lo = min(lo, hi / 10) if lo >= hi / 10 else lo  # at least a decade: a flat map still has a scale
        return ColourScale(indicator, LogNorm(vmin=lo, vmax=hi), 1.0, f"{name}\n(log scale)", _log_ticks(lo, hi))
    v = float(np.abs(finite).max()) if finite.size else 0.0
    if v > 0 and not RAW_RANGE[0] <= v < RAW_RANGE[1]:
        factor, top, label = 1.0 / v, 1.0, f"{name} ÷ {v:.2g}\n(normalised, signed)"
    else:
        factor, top, label = 1.0, (v if v > 0 else 1.0), f"{name}\n(signed)"
    ticks = [t for t in MaxNLocator(nbins=4, symmetric=True, steps=[1, 2, 2.5, 5, 10]).tick_values(-top, top)
             if abs(t) <= top]
    if len(ticks) < 3:
        ticks = [-top, 0.0, top]
    return ColourScale(indicator, Normalize(vmin=-top, vmax=top), factor, label, tuple(float(t) for t in ticks))


def _colourbar(fig, mesh, axes, scale: ColourScale, font: float, location: str = "right", one_line: bool = False):
    """A colour bar of ``scale`` for ``axes`` (one Axes or a row of them): its ticks, its label, ``font`` points."""
    from matplotlib.ticker import FixedFormatter, FixedLocator, NullLocator

    horizontal = location in ("top", "bottom")
    cb = fig.colorbar(mesh, ax=axes, location=location, shrink=1.0 if horizontal else 0.9,
                      aspect=30 if horizontal else 20, pad=0.02 if not horizontal else 0.04)
    axis = cb.ax.xaxis if horizontal else cb.ax.yaxis
    axis.set_major_locator(FixedLocator(scale.ticks))
    axis.set_major_formatter(FixedFormatter([f"{t:g}" for t in scale.ticks]))
    axis.set_minor_locator(NullLocator())
    cb.ax.tick_params(labelsize=font)
    cb.set_label(scale.label.replace("\n", " ") if one_line else scale.label, fontsize=font)
    cb.ax.set_gid(f"colourbar:{scale.indicator}")
    return cb


def _node_axes(wmap: WorkspaceMap) -> str | None:
    """The node whose x and y are the map's axes (a workspace map drawn in model coordinates), else None."""
    (a, b) = (ax.label for ax in wmap.axes)
    if a.startswith("velocity:") and b.startswith("velocity:"):
        na, _, ca = a[len("velocity:"):].rpartition(".")
        nb, _, cb = b[len("velocity:"):].rpartition(".")
        if na == nb and (ca, cb) == ("x", "y"):
            return na
    return None


def seed_mechanism(wmap: WorkspaceMap, mode, mechanism: Mechanism) -> Mechanism:
    """``mechanism`` at the seed configuration of ``mode`` (the map's free coordinates ``seed_q``).

    >>> import symkin
    >>> mech = symkin.catalogue.get("five_bar")
    >>> m = symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=5, refine=False)
    >>> dict(seed_mechanism(m, 0, mech).nodes)["P"] == dict(mech.nodes)["P"]
    True
    """
    from symkin.analysis.batch import evaluators_for

    _check(wmap)
    m = _mode(wmap, mode)
    ev = evaluators_for(mechanism)
    if ev.nf != np.asarray(m.seed_q).size:
        raise SymkinError(f"{mechanism.name}: not the mechanism of the map {wmap.model!r} "
                          f"({ev.nf} free coordinates, the map's seeds have {np.asarray(m.seed_q).size})")
    return ev.mechanism_at(m.seed_q)


# ---------------------------------------------------------------------- layers
def plot_boundary(wmap: WorkspaceMap, mode=0, ax=None):
    """The workspace boundary of ``mode``: the 0.5 contour of its assembled mask (``gid`` ``boundary:MODE``).

    Nothing is drawn when the mode assembles everywhere or nowhere in the box.
    """
    _check(wmap)
    m = _mode(wmap, mode)
    ax = _axes(ax)
    mask = np.asarray(m.assembled, float)
    if 0.0 < mask.mean() < 1.0:
        cs = ax.contour(wmap.xs, wmap.ys, mask, levels=[0.5], colors=BOUNDARY_COLOUR, linewidths=1.0, zorder=3)
        cs.set_gid(f"boundary:{m.id}")
    return ax


def plot_curves(wmap: WorkspaceMap, mode=0, ax=None, *, points: bool = True, halo: bool = True, alpha: float = 1.0):
    """The traced singular curves of ``mode`` (``gid`` ``curve:KIND:MODE``, one line each) and its
    isolated singular points (``point:KIND:MODE``); colours as in the path plots, line style by kind.

    Each curve's line is labelled with its kind once per axes (for a legend).
    """
    import matplotlib.patheffects as pe

    _check(wmap)
    m = _mode(wmap, mode)
    ax = _axes(ax)
    effects = [pe.Stroke(linewidth=3.0, foreground="white"), pe.Normal()] if halo else None
    seen: set[str] = set()
    for c in wmap.curves:
        if c.mode != m.id:
            continue
        p = np.asarray(c.points, float).reshape(-1, 2)
        if c.closed and len(p) > 1:
            p = np.vstack([p, p[:1]])
        ax.plot(p[:, 0], p[:, 1], color=STYLE[c.kind]["colour"], linestyle=LINESTYLES[c.kind], linewidth=1.4,
                alpha=alpha, zorder=4, path_effects=effects, gid=f"curve:{c.kind}:{m.id}",
                label=CURVE_LABELS.get(c.kind, f"{c.kind} curve") if c.kind not in seen else "_nolegend_")
        seen.add(c.kind)
    if points:
        for p in wmap.points:
            if p.mode != m.id:
                continue
            st = POINT_STYLES.get(p.kind, STYLE[Kind.IM])
            ax.plot(*p.at, marker=st["marker"], markersize=6, markerfacecolor=st["colour"], markeredgecolor="black",
                    markeredgewidth=0.8, linestyle="none", zorder=5, gid=f"point:{p.kind}:{m.id}",
                    label=_point_label(p.kind) if f"p{p.kind}" not in seen else "_nolegend_")
            seen.add(f"p{p.kind}")
    return ax


def plot_map(wmap: WorkspaceMap, mode=0, indicator: str = "im_indicator", ax=None, *, curves: bool = True,
             boundary: bool = True, colorbar: bool = True, title: str | None = None):
    """One indicator of one working mode over the map's box (paper Figs. 14, 16).

    Parameters
    ----------
    wmap : WorkspaceMap
    mode : int or ModeMap
        The mode id (``wmap.modes[k].id``).
    indicator : ``"im_indicator"``, ``"dkp_input"`` or ``"dkp_output"``
        The IM indicator (first non-zero eigenvalue of G, §V) is drawn as ``|value|`` on a log
        colour scale; the DKP test functions (signed, normalised as in ``trace``) on a
        diverging scale symmetric about zero, so that a sign change (a type-1 / type-2 locus)
        is the white band.  Grid points where the mode does not assemble stay blank.
    curves, boundary : bool
        Draw the mode's traced curves and points (:func:`plot_curves`) and its workspace
        boundary (:func:`plot_boundary`) over the map.
    colorbar : bool
    title : str, optional
        Default: the mode and the indicator.

    Returns
    -------
    matplotlib Axes
        The colour mesh has ``gid`` ``indicator:NAME:MODE``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> m = symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3.5:3.5",
    ...                          y="velocity:P.y=0.2:4.4", n=21)
    >>> ax = plot_map(m, 0, "dkp_output")
    >>> mesh = next(a for a in ax.collections if a.get_gid() == "indicator:dkp_output:0")
    >>> mesh.norm.vmin == -mesh.norm.vmax
    True
    """
    _check(wmap)
    scale = colour_scale(wmap, indicator)  # checks the indicator's name
    m = _mode(wmap, mode)
    ax = _axes(ax)
    values = np.asarray(getattr(m, indicator), float) * scale.factor
    log = INDICATORS[indicator][1] == "log"
    shown = np.abs(values) if log else values
    shown = np.where(np.asarray(m.assembled, bool), shown, np.nan)
    if log:
        shown = np.where(shown > 0, shown, np.nan)  # an exact zero has no log: blank, the curves show it
    mesh = ax.pcolormesh(wmap.xs, wmap.ys, np.ma.masked_invalid(shown), shading="nearest",
                         cmap=CMAPS["log" if log else "signed"], norm=scale.norm, rasterized=True,
                         gid=f"indicator:{indicator}:{m.id}")
    if colorbar:
        _colourbar(ax.figure, mesh, ax, scale, FONT)
    if boundary:
        plot_boundary(wmap, m, ax=ax)
    if curves:
        plot_curves(wmap, m, ax=ax)
    _frame(wmap, ax)
    ax.set_title(title if title is not None else f"{mode_title(m)}\n{INDICATORS[indicator][0]}", fontsize=FONT)
    return ax


def plot_seed(wmap: WorkspaceMap, mode, mechanism: Mechanism, ax=None, *, title: str | None = None,
              labels: bool = True):
    """The mechanism at the seed configuration of ``mode`` (:func:`~symkin.plots.draw_mechanism`).

    When the map's axes are the x and y of one node (a workspace map), the mode's boundary
    and traced curves are drawn behind it in the same coordinates and the node is marked
    (``gid`` ``seed:MODE``): the mechanism in its workspace, as in Figs. 14 and 16; the axes
    then hold the map's box and the mechanism, at equal scales.  ``labels`` writes the node names.
    """
    _check(wmap)
    m = _mode(wmap, mode)
    mech = seed_mechanism(wmap, m, mechanism)
    ax = _axes(ax)
    node = _node_axes(wmap) if mech.dim == 2 else None
    if node is not None:
        plot_boundary(wmap, m, ax=ax)
        plot_curves(wmap, m, ax=ax, points=True, halo=False, alpha=0.55)
    draw_mechanism(mech, ax=ax, labels=labels,
                   title=title if title is not None else f"{mode_title(m)}\nthe mechanism at its seed")
    ax.title.set_fontsize(FONT)
    for t in ax.texts:
        t.set_fontsize(max(t.get_fontsize(), FONT))
    ax.tick_params(labelsize=FONT)
    ax.xaxis.label.set_fontsize(FONT)
    ax.yaxis.label.set_fontsize(FONT)
    if node is not None and node in dict(mech.nodes):
        xy = dict(mech.nodes)[node][:2]
        ax.plot(*xy, marker="*", markersize=13, color="gold", markeredgecolor="black", linestyle="none", zorder=6,
                gid=f"seed:{m.id}", label=f"{node} at the seed")
        ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit), fontsize=FONT)
        ax.set_ylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=FONT)
        pts = np.vstack([np.array([c[:2] for _, c in mech.nodes], float),
                         [(wmap.axes[0].lo, wmap.axes[1].lo), (wmap.axes[0].hi, wmap.axes[1].hi)]])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.04 * float((hi - lo).max())
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_aspect("equal", adjustable="box")
    return ax


def plot_im_surface(wmap: WorkspaceMap, mode=0, ax=None, *, log: bool = False):
    """The IM indicator of ``mode`` as a 3-D surface over the box (paper Fig. 15; ``gid`` ``im_surface:MODE``).

    Grid points where the mode does not assemble are left out.  ``log=True`` plots
    ``log10 |λ_{F+1}|``, which makes a zero (an IM singularity) a deep well.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import symkin
    >>> m = symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3.5:3.5",
    ...                          y="velocity:P.y=0.2:4.4", n=11, refine=False)
    >>> plot_im_surface(m).name
    '3d'
    """
    _check(wmap)
    m = _mode(wmap, mode)
    if ax is None:
        from symkin.plots.mechanism import new_axes

        ax = new_axes(True)
    z = np.where(np.asarray(m.assembled, bool), np.abs(np.asarray(m.im_indicator, float)), np.nan)
    if log:
        with np.errstate(divide="ignore"):
            z = np.where(z > 0, np.log10(z), np.nan)
    x, y = np.meshgrid(wmap.xs, wmap.ys)  # arrays are (ny, nx)
    ax.plot_surface(x, y, np.ma.masked_invalid(z), cmap=CMAPS["log"], linewidth=0, antialiased=True,
                    rcount=min(len(wmap.ys), 120), ccount=min(len(wmap.xs), 120), gid=f"im_surface:{m.id}")
    ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit), fontsize=FONT)
    ax.set_ylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=FONT)
    ax.set_zlabel(r"$\log_{10}|\lambda_{F+1}|$" if log else r"$|\lambda_{F+1}|$", fontsize=FONT)
    ax.tick_params(labelsize=FONT)
    ax.set_title(f"{mode_title(m)}\nIM indicator surface", fontsize=FONT)
    return ax


def _axes(ax):
    if ax is None:
        from symkin.plots.mechanism import new_axes

        return new_axes(False)
    return ax


def _frame(wmap: WorkspaceMap, ax, font: float = FONT) -> None:
    from matplotlib.ticker import MaxNLocator

    ax.set_xlim(wmap.axes[0].lo, wmap.axes[0].hi)
    ax.set_ylim(wmap.axes[1].lo, wmap.axes[1].hi)
    ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit), fontsize=font)
    ax.set_ylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=font)
    if _node_axes(wmap) is not None:
        ax.set_aspect("equal", adjustable="box")
    ax.xaxis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10]))
    ax.yaxis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10]))
    ax.tick_params(labelsize=font)


# ---------------------------------------------------------------------- the figure
#: legend text of the mechanism drawing's markers (:func:`~symkin.plots.mechanism.draw_mechanism`'s gids)
MARKER_LABELS = {"fixed": "fixed node", "nodes": "joint", "sliders": "slider block"}


def _has_marker(line) -> bool:
    return line.get_marker() not in (None, "", " ", "None", "none")


def legend_handles(axes) -> list:
    """One legend handle per kind of artist drawn on ``axes`` (a sequence of Axes), made from the
    artists themselves: every curve kind, every marker (point kinds, the seed, the mechanism's
    nodes) and the workspace boundary, each once, in the order drawn.  Lines without a marker
    other than the curves (the links) are not listed: they are the drawing."""
    from matplotlib.lines import Line2D

    handles, seen = [], set()

    def add(label, **style):
        if label not in seen:
            seen.add(label)
            handles.append(Line2D([], [], label=label, **style))

    for ax in axes:
        for ln in ax.lines:
            gid = (ln.get_gid() or "").split(":")
            if gid[0] == "curve":
                add(CURVE_LABELS.get(gid[1], f"{gid[1]} curve"), color=ln.get_color(), linewidth=1.8,
                    linestyle=LINESTYLES.get(gid[1], "-"))
            elif _has_marker(ln):
                own = ln.get_label()
                label = (_point_label(gid[1]) if gid[0] == "point" else
                         MARKER_LABELS.get(gid[0]) or (own if own and not own.startswith("_") else gid[0]))
                add(label, linestyle="none", marker=ln.get_marker(), markersize=min(ln.get_markersize(), 9),
                    markerfacecolor=ln.get_markerfacecolor(), markeredgecolor=ln.get_markeredgecolor(),
                    color=ln.get_color())
        for c in ax.collections:
            if (c.get_gid() or "").startswith("boundary:"):
                add("workspace boundary", color=BOUNDARY_COLOUR, linewidth=1.0)
    return handles


def _suptitle(wmap: WorkspaceMap, font: float, width: float, extra: str = "") -> str:
    """The figure's title: model and axes, held values, counts (and ``extra``), in lines that fit ``width``."""
    import textwrap

    hold = ", ".join(f"{lab} = {v:.4g}" for lab, v in wmap.hold)
    (a, b) = (axis_label(ax.label, wmap.unit).split(" [")[0] for ax in wmap.axes)
    parts = [f"{wmap.model}: singularity map over {a} × {b}", f"holding {hold}" if hold else "",
             f"{len(wmap.modes)} mode(s), {len(wmap.curves)} curve(s), {len(wmap.points)} point(s)", extra]
    chars = int(width * 72 / (0.6 * font))  # characters per line at this size (with a margin)
    lines: list[str] = []
    for part in filter(None, parts):  # a part stays whole on its line when it fits one
        if lines and len(lines[-1]) + 2 + len(part) <= chars:
            lines[-1] += f"; {part}"
        else:
            lines += textwrap.wrap(part, chars)
    return "\n".join(lines)


def _geometry(wmap: WorkspaceMap) -> float:
    """Height / width of a map panel: the box's when its axes are one node's x and y (equal scales)."""
    if _node_axes(wmap) is None:
        return 0.8
    (ax, ay) = wmap.axes
    return float(np.clip((ay.hi - ay.lo) / (ax.hi - ax.lo), 0.4, 1.4))


def _new_figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _legend(fig, handles, font: float, ncol: int) -> None:
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncol=ncol, fontsize=font, frameon=False,
                   handlelength=1.6, columnspacing=1.0, handletextpad=0.5)


def map_figure(wmap: WorkspaceMap, mechanism: Mechanism | None = None, indicators=tuple(INDICATORS)):
    """The figure :func:`save_map_figure` writes, on a standalone ``Figure`` (Agg canvas, pyplot untouched).

    Drawn for one column of a paper: :data:`~symkin.plots.paths.COLUMN_WIDTH` inches wide with
    no text under :data:`~symkin.plots.paths.FONT` points (a map of ``k > 2`` modes is drawn
    ``k / 2`` times wider, its text scaled by the same ratio, so it prints alike).  One
    column per mode, one row per indicator (:func:`plot_map`) and, when ``mechanism`` is
    given, a last row with the mechanism at each mode's seed (:func:`plot_seed`); a map of one
    mode puts its panels two by two.  The indicators' colour scales are the same for every
    mode (:func:`colour_scale`), one colour bar per row; the title (once, above) names the
    model, the axes, the held coordinates and the counts; the axes' labels are given once; one
    legend below lists every curve kind and every marker drawn (:func:`legend_handles`).
    """
    _check(wmap)
    unknown = [k for k in indicators if k not in INDICATORS]
    if unknown or not indicators:
        raise SymkinError(f"indicators {list(indicators)!r}: expected some of {', '.join(INDICATORS)}")
    names = list(indicators) + (["mechanism"] if mechanism is not None else [])
    modes = list(wmap.modes)
    wide = len(modes) >= 2
    ncols = len(modes) if wide else min(2, len(names))
    nrows = len(names) if wide else -(-len(names) // ncols)
    width = COLUMN_WIDTH * max(1.0, ncols / 2)
    font = FONT * width / COLUMN_WIDTH
    em = font / 72  # inches per em
    panel_h = (width - 4.5 * em) / ncols * _geometry(wmap)
    fig = _new_figure(width, nrows * (panel_h + 5 * em))  # the height is set once the legend is known
    extra = "" if wide or not modes else mode_title(modes[0])
    title = _suptitle(wmap, font, width, extra)
    fig.suptitle(title, fontsize=font)
    if not modes:
        ax = fig.add_subplot(1, 1, 1)
        ax.text(0.5, 0.5, "no working mode", ha="center", va="center", fontsize=font)
        ax.set_axis_off()
        return fig
    grid = fig.add_gridspec(nrows, ncols)
    cells = ([(r, c, m, name) for r, name in enumerate(names) for c, m in enumerate(modes)] if wide else
             [(k // ncols, k % ncols, modes[0], name) for k, name in enumerate(names)])
    share = None
    rows: dict[int, list] = {}
    last_map_row = max(r for r, _, _, name in cells if name != "mechanism")
    for r, c, m, name in cells:
        if name == "mechanism":
            ax = fig.add_subplot(grid[r, c], gid=f"panel:{m.id}:mechanism")
            plot_seed(wmap, m, mechanism, ax=ax, title="", labels=False)
            ax.set_title("the mechanism\nat its seed" if not wide else "", fontsize=font)
            node = _node_axes(wmap)
            ax.set_xlabel("")
            ax.set_ylabel("" if node else "y [model length]", fontsize=font)
            ax.xaxis.set_major_locator(_locator())
            ax.yaxis.set_major_locator(_locator())
            ax.tick_params(labelsize=font)
        else:
            ax = fig.add_subplot(grid[r, c], gid=f"panel:{m.id}:{name}", sharex=share, sharey=share)
            share = share or ax
            if m.assembled.any():
                plot_map(wmap, m, name, ax=ax, colorbar=False, title="")
                rows.setdefault(r if wide else (r, c), []).append(ax)
            else:
                _frame(wmap, ax, font)
                ax.text(0.5, 0.5, f"mode {m.id} does not\nassemble in the box", ha="center", va="center",
                        transform=ax.transAxes, fontsize=font)
            ax.set_xlabel("")
            ax.set_ylabel("")
            if wide:
                ax.tick_params(labelbottom=r == last_map_row, labelleft=c == 0)
        if wide and r == 0:
            import textwrap

            head = textwrap.fill(f"mode {m.id} (seed: {m.seed})", int(width / ncols * 72 / (0.55 * font)))
            ax.set_title(f"{head}\n{100 * m.fraction:.0f} % assembled", fontsize=font)
        if r == nrows - 1 or (not wide and r == nrows - 2 and (r + 1) * ncols + c >= len(names)):
            ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit) if name != "mechanism" or _node_axes(wmap)
                          else "x [model length]", fontsize=font)
    for axes in rows.values():
        name = axes[0].get_gid().split(":")[2]
        mesh = next(a for a in axes[0].collections if (a.get_gid() or "").startswith("indicator:"))
        _colourbar(fig, mesh, axes, colour_scale(wmap, name), font, location="bottom", one_line=wide)
    fig.supylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=font)
    handles = legend_handles(fig.axes)
    ncol = 2 if width <= COLUMN_WIDTH else 3
    _legend(fig, handles, font, ncol=ncol)
    # the rows (panel, tick labels, colour bar and its label), the title, the legend, the axis label
    lines = title.count("\n") + 1 + 1.15 * -(-len(handles) // ncol) + 1.5 + (2.6 if wide else 0)
    fig.set_size_inches(width, nrows * (panel_h + (4.6 if wide else 8.2) * em) + 1.25 * lines * em)
    floor_fonts(fig, font)
    return fig


def _locator():
    from matplotlib.ticker import MaxNLocator

    return MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10])


def map_panel_figures(wmap: WorkspaceMap, mechanism: Mechanism | None = None,
                      indicators=tuple(INDICATORS)) -> dict:
    """One figure per panel of :func:`map_figure` (``symkin map ... --panels``): ``{name: Figure}``.

    ``name`` is ``mode<ID>-<indicator>`` or ``mode<ID>-mechanism``; each figure is one column
    wide (:data:`~symkin.plots.paths.COLUMN_WIDTH` inches, no text under
    :data:`~symkin.plots.paths.FONT` points) with its own title, colour bar and legend.
    """
    _check(wmap)
    unknown = [k for k in indicators if k not in INDICATORS]
    if unknown or not indicators:
        raise SymkinError(f"indicators {list(indicators)!r}: expected some of {', '.join(INDICATORS)}")
    width, font = COLUMN_WIDTH, FONT
    em = font / 72
    out = {}
    for m in wmap.modes:
        for name in list(indicators) + (["mechanism"] if mechanism is not None else []):
            what = "the mechanism at its seed" if name == "mechanism" else INDICATORS[name][0]
            panel_h = (width - 4 * em) * _geometry(wmap)
            fig = _new_figure(width, panel_h + 14 * em)
            fig.suptitle(_suptitle(wmap, font, width, f"{mode_title(m)}: {what}"), fontsize=font)
            ax = fig.add_subplot(1, 1, 1, gid=f"panel:{m.id}:{name}")
            if name == "mechanism":
                plot_seed(wmap, m, mechanism, ax=ax, title="")
                ax.xaxis.set_major_locator(_locator())
                ax.yaxis.set_major_locator(_locator())
            elif m.assembled.any():
                plot_map(wmap, m, name, ax=ax, colorbar=False, title="")
                mesh = next(a for a in ax.collections if (a.get_gid() or "").startswith("indicator:"))
                _colourbar(fig, mesh, ax, colour_scale(wmap, name), font, location="bottom", one_line=True)
            else:
                _frame(wmap, ax, font)
                ax.text(0.5, 0.5, f"mode {m.id} does not assemble in the box", ha="center", va="center",
                        transform=ax.transAxes, fontsize=font)
            _legend(fig, legend_handles([ax]), font, ncol=2)
            floor_fonts(fig, font)
            out[f"mode{m.id}-{name}"] = fig
    return out


def panel_path(path, name: str) -> FilePath:
    """Where the panel ``name`` of :func:`map_panel_figures` goes for ``--plot path``: ``<stem>-<name><ext>``.

    >>> str(panel_path("out/map.png", "mode0-dkp_input"))
    'out/map-mode0-dkp_input.png'
    """
    target = FilePath(path)
    return target.with_name(f"{target.stem}-{name}{target.suffix}")


def _save(fig, target: FilePath, dpi: int) -> FilePath:
    try:
        fig.savefig(target, dpi=dpi, format=None if target.suffix else "png")
    except OSError as exc:
        raise SymkinError(f"{target}: cannot write the figure ({exc.strerror or exc})") from exc
    return target


def save_map_figure(wmap: WorkspaceMap, path, mechanism: Mechanism | None = None, indicators=tuple(INDICATORS),
                    dpi: int = DPI) -> FilePath:
    """Write :func:`map_figure` to ``path`` (what ``symkin map ... --plot FILE.png`` writes).

    ``mechanism`` (the model the map was built from) adds the row of the mechanism at each
    mode's seed.  ``path`` without a suffix is written as PNG.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    return _save(map_figure(wmap, mechanism, indicators), FilePath(path), dpi)


def save_map_panels(wmap: WorkspaceMap, path, mechanism: Mechanism | None = None, indicators=tuple(INDICATORS),
                    dpi: int = DPI) -> list[FilePath]:
    """Write each figure of :func:`map_panel_figures` to :func:`panel_path` ``(path, name)``
    (what ``symkin map ... --plot FILE.png --panels`` writes); returns the files written."""
    return [_save(fig, panel_path(path, name), dpi)
            for name, fig in map_panel_figures(wmap, mechanism, indicators).items()]
