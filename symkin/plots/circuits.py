"""The circuits of a 1-DOF mechanism in input–output space with every singular configuration numbered.

Reads a :class:`symkin.solutions.circuits.Singularities` (``symkin singularities``) and draws
it: each circuit in its own colour (all its traced branches), every singular configuration
marked by type (IM, DKP-input, DKP-output, LIM — a link locked — as in :mod:`symkin.plots.paths`)
and numbered as in the text report and the JSON ``singularities``.  Angles are absolute (the
``input_absolute`` / ``output_absolute`` of the JSON, ticks in [0°, 360°)) and a circuit is drawn
continuous: it is cut only where it turns fully.  The figure is drawn at one-column size
(:data:`~symkin.plots.paths.COLUMN_WIDTH` inches) with no text under
:data:`~symkin.plots.paths.FONT` points.  A model without an output
is drawn against the arclength along each branch instead.
"""
from __future__ import annotations

import math
from pathlib import Path as FilePath

import numpy as np

from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.plots.paths import COLUMN_WIDTH, DPI, FONT, STYLE
from symkin.solutions.circuits import Singularities

__all__ = ["LIM_STYLE", "plot_circuits", "circuits_figure", "save_circuits_figure"]

#: marker of a LIM configuration (a link locked) that is none of IM, DKP-input, DKP-output (as on path plots)
LIM_STYLE = STYLE[Kind.LIM]
#: the type that picks a configuration's marker, first match in this order
_MARKER_ORDER = (Kind.IM, Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.LIM)

_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")


def _offsets(result: Singularities, labels: list[str]) -> dict:
    """Absolute value of each angle coordinate at the model's configuration (radians), None where there is none."""
    from symkin.paths.trace import CoordinateValues

    mech = result.mechanism
    at = CoordinateValues(mech, labels)(np.array([c for _, c in mech.nodes], float), "rad")
    return {label: at[label]["absolute"] for label in labels}


def _continuous(values: np.ndarray, period: float | None) -> np.ndarray:
    """One branch's values for drawing: whole turns taken off so the branch sits in [0, period) where it can.

    A branch that spans less than a period is shifted as a whole (never cut); one that turns
    fully is wrapped into [0, period) and cut only there (:func:`_break`).
    """
    if not period or values.size == 0:
        return values
    if np.ptp(values) < period:
        centre = (values.min() + values.max()) / 2
        return values - period * np.floor(centre / period)
    return np.remainder(values, period)


def _break(x: np.ndarray, y: np.ndarray, period_x: float | None, period_y: float | None):
    """Split a polyline where x or y jumps by more than half a period (a full turn, wrapped)."""
    jumps = np.zeros(max(len(x) - 1, 0), bool)
    if period_x:
        jumps |= np.abs(np.diff(x)) > period_x / 2
    if period_y:
        jumps |= np.abs(np.diff(y)) > period_y / 2
    cut = np.flatnonzero(jumps) + 1
    return np.split(x, cut), np.split(y, cut)


def _nearest_turn(value: float, period: float | None, drawn: np.ndarray) -> float:
    """``value`` shifted by whole periods to the nearest drawn value (a marker on its curve)."""
    if not period or drawn.size == 0:
        return value
    k = np.round((drawn - value) / period)
    cand = value + period * k
    return float(cand[np.argmin(np.abs(cand - drawn))])


def _angle_formatter(period: float):
    from matplotlib.ticker import FuncFormatter

    def text(v, _):
        r = np.remainder(v, period) + 0.0
        return f"{period if (r == 0.0 and v > 0) else r:g}"  # a full turn at the right end reads 360, not 0 again

    return FuncFormatter(text)


def plot_circuits(result: Singularities, ax=None, annotate: bool = True):
    """Draw the circuits of ``result`` in input–output space with the singular configurations numbered.

    Angles are absolute (planar rotations: the link's angle, ticks in [0°, 360°)); each branch
    is drawn continuous — shifted by whole turns, never cut at a wrap — unless it turns
    fully, where it is cut only at the axis' full turn.  Every marker kind shown has a
    legend entry (LIM too), below the axes so it covers no data.  A coordinate without an
    absolute angle (a slide, a spatial rotation) is drawn relative to the model's
    configuration, as the axis label says.

    Parameters
    ----------
    result : Singularities
        From :func:`symkin.singularities`.
    ax : matplotlib Axes, optional
        Drawn into when given, else a new figure of one-column size.
    annotate : bool
        Number each singular configuration (1, 2, ... as in the report).

    Returns
    -------
    matplotlib.axes.Axes
        Curves have ``gid`` ``circuit:K``, markers ``singularity:KIND``, numbers ``singularity-label:N``.
    """
    if not isinstance(result, Singularities):
        raise SymkinError(f"expected a symkin Singularities result (symkin.singularities), got {type(result).__name__}")
    if ax is None:
        from symkin.plots.mechanism import new_axes

        ax = new_axes(False, figsize=(COLUMN_WIDTH, 3.6))
    deg = result.unit == "deg"
    conv = 180.0 / math.pi if deg else 1.0
    has_output = result.output is not None
    angle_in = result.kind == "angle"
    angle_out = has_output and _output_kind(result) == "angle"
    labels = [result.input] + ([result.output] if has_output else [])
    offsets = _offsets(result, [lab for lab, a in zip(labels, (angle_in, angle_out)) if a])
    off_in = offsets.get(result.input) if angle_in else None
    off_out = offsets.get(result.output) if angle_out else None
    period_in = 2 * math.pi * conv if angle_in else None
    period_out = 2 * math.pi * conv if angle_out else None
    drawn = {}
    for c in result.circuits:
        colour = _COLOURS[(c.index - 1) % len(_COLOURS)]
        for k, b in enumerate(c.branches):
            x = (np.asarray(b.inputs, float) + (off_in or 0.0)) * conv if angle_in else np.asarray(b.inputs, float)
            x = _continuous(x, period_in if off_in is not None else None) if angle_in else x
            if has_output and b.outputs is not None:
                y = np.asarray(b.outputs, float)
                y = _continuous((y + (off_out or 0.0)) * conv, period_out if off_out is not None else None) \
                    if angle_out else y
            else:
                y = np.array([p.s for p in b.path.points], float) if b.path is not None else np.arange(len(x), dtype=float)
            drawn[b.index] = (x, y)
            xs, ys = _break(x, y, period_in, period_out)
            for j, (xx, yy) in enumerate(zip(xs, ys)):
                ax.plot(xx, yy, color=colour, lw=1.4, gid=f"circuit:{c.index}",
                        label=f"circuit {c.index}" if (k == 0 and j == 0) else None)
    seen = set()
    for n, s in enumerate(result.singularities, 1):
        kind = next((t for t in _MARKER_ORDER if t in s.types), s.kinds[0] if s.kinds else Kind.IM)
        style = STYLE.get(kind, STYLE[Kind.IM])
        bx, by = drawn.get(s.branches[0] if s.branches else None, (np.array([]), np.array([])))
        x = (s.input * (math.pi / 180.0 if deg else 1.0) + (off_in or 0.0)) * conv if angle_in else s.input
        x = _nearest_turn(x, period_in, bx)
        if has_output:
            y = (s.output * (math.pi / 180.0 if deg else 1.0) + (off_out or 0.0)) * conv if angle_out else s.output
            y = _nearest_turn(y, period_out, by)
        else:
            y = s.arclength
        label = str(kind) if kind != Kind.LIM else f"LIM ({', '.join(s.locked_links)} locked)"
        ax.plot([x], [y], linestyle="none", marker=style["marker"], ms=7, mfc=style["colour"],
                mec="black", zorder=5, label=label if label not in seen else None, gid=f"singularity:{kind}")
        seen.add(label)
        if annotate:
            ax.annotate(str(n), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=FONT, zorder=6,
                        gid=f"singularity-label:{n}")
    unit = "deg" if deg else "rad"

    def axis_label(name, angle, offset):
        if not angle:
            return f"{name} [model length]"
        return f"{name} [{unit}], absolute" if offset is not None else f"{name} [{unit}], from the model"

    ax.set_xlabel("input " + axis_label(result.input, angle_in, off_in), fontsize=FONT)
    if angle_in and off_in is not None:
        ax.xaxis.set_major_formatter(_angle_formatter(period_in))
        _quarter_turns(ax.xaxis, deg, ax.get_xlim())
    if has_output:
        ax.set_ylabel("output " + axis_label(result.output, angle_out, off_out), fontsize=FONT)
        if angle_out and off_out is not None:
            ax.yaxis.set_major_formatter(_angle_formatter(period_out))
            _quarter_turns(ax.yaxis, deg, ax.get_ylim())
    else:
        ax.set_ylabel("arclength along the branch", fontsize=FONT)
    ax.tick_params(labelsize=FONT)
    ax.set_title(f"{result.mechanism.name}\n{len(result.circuits)} circuit(s), "
                 f"{len(result.singularities)} singular configuration(s)", fontsize=FONT)
    ax.grid(True, alpha=0.3)
    ax.margins(0.06, 0.1)  # room for the numbers at the curves' extremes
    ax.legend(fontsize=FONT, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False,
              handlelength=1.5, columnspacing=1.0)
    return ax


def _quarter_turns(axis, deg: bool, limits) -> None:
    """Ticks of an angle axis in degrees at multiples of 90° (45° on a span of 90° to 180°; else
    matplotlib's), as a kinematician reads them."""
    span = abs(limits[1] - limits[0])
    if deg and span >= 90.0:
        from matplotlib.ticker import MultipleLocator

        axis.set_major_locator(MultipleLocator(90.0 if span >= 180.0 else 45.0))


def _output_kind(result: Singularities) -> str | None:
    from symkin.solutions.frame_coordinates import output_coordinate

    c = output_coordinate(result.mechanism)
    return None if c is None else c.kind


def circuits_figure(result: Singularities):
    """A standalone ``Figure`` (Agg canvas, pyplot untouched) with :func:`plot_circuits`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(COLUMN_WIDTH, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    plot_circuits(result, ax=fig.add_subplot(1, 1, 1))
    return fig


def save_circuits_figure(result: Singularities, filename) -> FilePath:
    """Write :func:`circuits_figure` to a PNG (what ``symkin singularities ... --plot FILE.png`` writes)."""
    target = FilePath(filename)
    fig = circuits_figure(result)
    try:
        fig.savefig(target, dpi=DPI, format=None if target.suffix else "png")
    except OSError as exc:
        raise SymkinError(f"{target}: cannot write the figure ({exc.strerror or exc})") from exc
    return target
