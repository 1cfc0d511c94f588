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
* :func:`map_figure` / :func:`save_map_figure` — rows = modes, columns = indicators (+ the
  mechanism): what ``symkin map ... --plot FILE.png`` writes.

Artists carry a ``gid``: ``indicator:NAME:MODE`` (the colour mesh), ``curve:KIND:MODE``,
``point:KIND:MODE``, ``boundary:MODE``, ``seed:MODE``, ``im_surface:MODE``; the panels of
:func:`map_figure` carry ``panel:MODE:NAME`` (``NAME`` an indicator or ``mechanism``).
"""
from __future__ import annotations

from pathlib import Path as FilePath

import numpy as np

from symkin.kinds import Kind
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.plots.mechanism import draw_mechanism
from symkin.plots.paths import STYLE
from symkin.workspace.maps import KINDS, ModeMap, WorkspaceMap

__all__ = ["INDICATORS", "plot_map", "plot_curves", "plot_boundary", "plot_seed", "plot_im_surface",
           "map_figure", "save_map_figure", "axis_label", "seed_mechanism"]

#: the indicators of a mode that :func:`plot_map` draws: name → (title, scale)
INDICATORS = {
    "im_indicator": (r"IM indicator $|\lambda_{F+1}|$ (log scale)", "log"),
    "dkp_input": ("DKP-input test (signed)", "signed"),
    "dkp_output": ("DKP-output test (signed)", "signed"),
}
#: colour maps: sequential for ``|IM|``, diverging (zero = white) for the signed DKP functions
CMAPS = {"log": "viridis", "signed": "PuOr_r"}
#: line style per curve kind (colours from the path plots, :data:`symkin.plots.paths.STYLE`)
LINESTYLES = {Kind.DKP_INPUT: "-", Kind.DKP_OUTPUT: (0, (5, 2)), Kind.IM: ":"}
#: marker per isolated point kind: the path plots' (IM, DKP) and a cusp of a traced curve
POINT_STYLES = {**STYLE, Kind.CUSP: dict(colour="#ff7f0e", marker="^")}
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


def _norm(values: np.ndarray, scale: str):
    """The colour norm of an indicator: log of |value| for the IM indicator, symmetric about 0 otherwise."""
    from matplotlib.colors import LogNorm, Normalize

    finite = values[np.isfinite(values)]
    if scale == "log":
        pos = finite[finite > 0]
        hi = float(pos.max()) if pos.size else 1.0
        lo = float(pos.min()) if pos.size else hi * 1e-3
        return LogNorm(vmin=min(lo, hi * (1 - 1e-12)), vmax=hi)
    v = float(np.abs(finite).max()) if finite.size else 1.0
    v = v if v > 0 else 1.0
    return Normalize(vmin=-v, vmax=v)


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
    effects = [pe.Stroke(linewidth=4.4, foreground="white"), pe.Normal()] if halo else None
    seen: set[str] = set()
    for c in wmap.curves:
        if c.mode != m.id:
            continue
        p = np.asarray(c.points, float).reshape(-1, 2)
        if c.closed and len(p) > 1:
            p = np.vstack([p, p[:1]])
        ax.plot(p[:, 0], p[:, 1], color=STYLE[c.kind]["colour"], linestyle=LINESTYLES[c.kind], linewidth=2.2,
                alpha=alpha, zorder=4, path_effects=effects, gid=f"curve:{c.kind}:{m.id}",
                label=f"{c.kind} curve" if c.kind not in seen else "_nolegend_")
        seen.add(c.kind)
    if points:
        for p in wmap.points:
            if p.mode != m.id:
                continue
            st = POINT_STYLES.get(p.kind, STYLE[Kind.IM])
            ax.plot(*p.at, marker=st["marker"], markersize=7, markerfacecolor=st["colour"], markeredgecolor="white",
                    linestyle="none", zorder=5, gid=f"point:{p.kind}:{m.id}",
                    label=f"{p.kind} point" if f"p{p.kind}" not in seen else "_nolegend_")
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
    if indicator not in INDICATORS:
        raise SymkinError(f"indicator {indicator!r}: expected one of {', '.join(INDICATORS)}")
    m = _mode(wmap, mode)
    ax = _axes(ax)
    name, scale = INDICATORS[indicator]
    values = np.asarray(getattr(m, indicator), float)
    shown = np.abs(values) if scale == "log" else values
    shown = np.where(np.asarray(m.assembled, bool), shown, np.nan)
    if scale == "log":
        shown = np.where(shown > 0, shown, np.nan)  # an exact zero has no log: blank, the curves show it
    norm = _norm(shown, scale)
    mesh = ax.pcolormesh(wmap.xs, wmap.ys, np.ma.masked_invalid(shown), shading="nearest", cmap=CMAPS[scale],
                         norm=norm, rasterized=True, gid=f"indicator:{indicator}:{m.id}")
    if colorbar:
        ax.figure.colorbar(mesh, ax=ax, shrink=0.9, pad=0.02)
    if boundary:
        plot_boundary(wmap, m, ax=ax)
    if curves:
        plot_curves(wmap, m, ax=ax)
    _frame(wmap, ax)
    ax.set_title(title if title is not None else f"{mode_title(m)}\n{name}", fontsize=9)
    return ax


def plot_seed(wmap: WorkspaceMap, mode, mechanism: Mechanism, ax=None, *, title: str | None = None):
    """The mechanism at the seed configuration of ``mode`` (:func:`~symkin.plots.draw_mechanism`).

    When the map's axes are the x and y of one node (a workspace map), the mode's boundary
    and traced curves are drawn behind it in the same coordinates and the node is marked
    (``gid`` ``seed:MODE``): the mechanism in its workspace, as in Figs. 14 and 16.
    """
    _check(wmap)
    m = _mode(wmap, mode)
    mech = seed_mechanism(wmap, m, mechanism)
    ax = _axes(ax)
    node = _node_axes(wmap) if mech.dim == 2 else None
    if node is not None:
        plot_boundary(wmap, m, ax=ax)
        plot_curves(wmap, m, ax=ax, points=True, halo=False, alpha=0.55)
    draw_mechanism(mech, ax=ax, title=title if title is not None else f"{mode_title(m)}\nthe mechanism at its seed")
    if node is not None and node in dict(mech.nodes):
        xy = dict(mech.nodes)[node][:2]
        ax.plot(*xy, marker="*", markersize=13, color="gold", markeredgecolor="black", linestyle="none", zorder=6,
                gid=f"seed:{m.id}")
        ax.update_datalim([(wmap.axes[0].lo, wmap.axes[1].lo), (wmap.axes[0].hi, wmap.axes[1].hi)])
        ax.autoscale_view()
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
    ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit), fontsize=8)
    ax.set_ylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=8)
    ax.set_zlabel(r"$\log_{10}|\lambda_{F+1}|$" if log else r"$|\lambda_{F+1}|$", fontsize=8)
    ax.set_title(f"{mode_title(m)}\nIM indicator surface", fontsize=9)
    return ax


def _axes(ax):
    if ax is None:
        from symkin.plots.mechanism import new_axes

        return new_axes(False)
    return ax


def _frame(wmap: WorkspaceMap, ax) -> None:
    ax.set_xlim(wmap.axes[0].lo, wmap.axes[0].hi)
    ax.set_ylim(wmap.axes[1].lo, wmap.axes[1].hi)
    ax.set_xlabel(axis_label(wmap.axes[0].label, wmap.unit), fontsize=8)
    ax.set_ylabel(axis_label(wmap.axes[1].label, wmap.unit), fontsize=8)
    if _node_axes(wmap) is not None:
        ax.set_aspect("equal", adjustable="box")
    ax.tick_params(labelsize=7)


# ---------------------------------------------------------------------- the figure
def _legend_handles(wmap: WorkspaceMap):
    from matplotlib.lines import Line2D

    kinds = [k for k in KINDS if any(c.kind == k for c in wmap.curves)]
    handles = [Line2D([], [], color=STYLE[k]["colour"], linestyle=LINESTYLES[k], linewidth=1.8,
                      label={Kind.DKP_INPUT: "DKP-input (type-2) curve", Kind.DKP_OUTPUT: "DKP-output (type-1) curve",
                             Kind.IM: "IM curve"}[k]) for k in kinds]
    for k in (*KINDS, Kind.CUSP):
        if any(p.kind == k for p in wmap.points):
            handles.append(Line2D([], [], marker=POINT_STYLES[k]["marker"], color=POINT_STYLES[k]["colour"],
                                  linestyle="none", label=f"{k} point"))
    if any(0 < m.fraction < 1 for m in wmap.modes):
        handles.append(Line2D([], [], color=BOUNDARY_COLOUR, linewidth=1.0, label="workspace boundary of the mode"))
    return handles


def map_figure(wmap: WorkspaceMap, mechanism: Mechanism | None = None, indicators=tuple(INDICATORS)):
    """The figure :func:`save_map_figure` writes, on a standalone ``Figure`` (Agg canvas, pyplot untouched).

    One row per mode, one column per indicator (:func:`plot_map`) and, when ``mechanism``
    is given, a last column with the mechanism at the mode's seed (:func:`plot_seed`).
    The title names the model, the held coordinates and the notes' count; one legend
    under the title explains the curve styles for every panel.
    """
    _check(wmap)
    unknown = [k for k in indicators if k not in INDICATORS]
    if unknown or not indicators:
        raise SymkinError(f"indicators {list(indicators)!r}: expected some of {', '.join(INDICATORS)}")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    rows = max(len(wmap.modes), 1)
    cols = len(indicators) + (mechanism is not None)
    fig = Figure(figsize=(4.3 * cols, 3.9 * rows + 0.9), layout="constrained")
    FigureCanvasAgg(fig)
    hold = ", ".join(f"{lab} = {v:.4g}" for lab, v in wmap.hold)
    fig.suptitle(f"{wmap.model}\nsingularity map over {wmap.axes[0].label} × {wmap.axes[1].label}"
                 + (f" (holding {hold})" if hold else "") + f"; {len(wmap.modes)} mode(s), "
                 f"{len(wmap.curves)} curve(s), {len(wmap.points)} point(s)", fontsize=11)
    if not wmap.modes:
        ax = fig.add_subplot(1, 1, 1)
        ax.text(0.5, 0.5, "no working mode", ha="center", va="center")
        ax.set_axis_off()
        return fig
    for r, m in enumerate(wmap.modes):
        for c, name in enumerate(indicators):
            ax = fig.add_subplot(rows, cols, r * cols + c + 1, gid=f"panel:{m.id}:{name}")
            if m.assembled.any():
                plot_map(wmap, m, name, ax=ax)
            else:
                _frame(wmap, ax)
                ax.set_title(f"{mode_title(m)}\n{INDICATORS[name][0]}", fontsize=9)
                ax.text(0.5, 0.5, "the mode does not assemble\nanywhere in the box", ha="center", va="center",
                        transform=ax.transAxes, fontsize=9)
        if mechanism is not None:
            ax = fig.add_subplot(rows, cols, r * cols + cols, gid=f"panel:{m.id}:mechanism")
            plot_seed(wmap, m, mechanism, ax=ax)
    handles = _legend_handles(wmap)
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8, frameon=False)
    return fig


def save_map_figure(wmap: WorkspaceMap, path, mechanism: Mechanism | None = None, indicators=tuple(INDICATORS),
                    dpi: int = 100) -> FilePath:
    """Write :func:`map_figure` to ``path`` (what ``symkin map ... --plot FILE.png`` writes).

    ``mechanism`` (the model the map was built from) adds the column of the mechanism at each
    mode's seed.  ``path`` without a suffix is written as PNG.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    target = FilePath(path)
    fig = map_figure(wmap, mechanism, indicators)
    try:
        fig.savefig(target, dpi=dpi, format=None if target.suffix else "png")
    except OSError as exc:
        raise SymkinError(f"{target}: cannot write the figure ({exc.strerror or exc})") from exc
    return target
