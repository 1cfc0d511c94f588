"""The circuits of a 1-DOF mechanism in input–output space with every singular configuration numbered.

Reads a :class:`symkin.solutions.circuits.Singularities` (``symkin singularities``) and draws
it: each circuit in its own colour (all its traced branches), every singular configuration
marked by type (IM, DKP-input, DKP-output as in :mod:`symkin.plots.paths`; LIM, a link locked, by
:data:`LIM_STYLE`) and numbered as
in the text report and the JSON ``singularities``.  Angles are wrapped to (−180°, 180°] (or
(−π, π]) and a curve is broken where it wraps.  A model without an output is drawn against
the arclength along each branch instead.
"""
from __future__ import annotations

import math
from pathlib import Path as FilePath

import numpy as np

from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.plots.paths import STYLE
from symkin.solutions.circuits import Singularities

__all__ = ["LIM_STYLE", "plot_circuits", "circuits_figure", "save_circuits_figure"]

#: marker of a LIM configuration (a link locked) that is none of IM, DKP-input, DKP-output
LIM_STYLE = dict(colour="#ff7f0e", marker="^")
#: the type that picks a configuration's marker, first match in this order
_MARKER_ORDER = (Kind.IM, Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.LIM)

_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")


def _wrapped(values: np.ndarray, angle: bool, conv: float) -> np.ndarray:
    """Values in display units, angles wrapped to (−180°, 180°]; NaN inserted where a curve wraps."""
    v = np.asarray(values, float)
    if not angle:
        return v * conv
    w = np.remainder(v + math.pi, 2 * math.pi) - math.pi
    return w * conv


def _break(x: np.ndarray, y: np.ndarray, period_x: float | None, period_y: float | None):
    """Split a polyline where x or y jumps by more than half a period (a wrap)."""
    jumps = np.zeros(max(len(x) - 1, 0), bool)
    if period_x:
        jumps |= np.abs(np.diff(x)) > period_x / 2
    if period_y:
        jumps |= np.abs(np.diff(y)) > period_y / 2
    cut = np.flatnonzero(jumps) + 1
    return np.split(x, cut), np.split(y, cut)


def plot_circuits(result: Singularities, ax=None, annotate: bool = True):
    """Draw the circuits of ``result`` in input–output space with the singular configurations numbered.

    Parameters
    ----------
    result : Singularities
        From :func:`symkin.singularities`.
    ax : matplotlib Axes, optional
        Drawn into when given, else a new figure.
    annotate : bool
        Number each singular configuration (1, 2, ... as in the report).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if not isinstance(result, Singularities):
        raise SymkinError(f"expected a symkin Singularities result (symkin.singularities), got {type(result).__name__}")
    if ax is None:
        from symkin.plots.mechanism import new_axes

        ax = new_axes(False, figsize=(7.0, 5.4))
    deg = result.unit == "deg"
    conv_in = 180.0 / math.pi if (deg and result.kind == "angle") else 1.0
    angle_in = result.kind == "angle"
    has_output = result.output is not None
    out_kind = _output_kind(result)
    angle_out = has_output and out_kind == "angle"
    conv_out = 180.0 / math.pi if (deg and angle_out) else 1.0
    period_in = 2 * math.pi * conv_in if angle_in else None
    period_out = 2 * math.pi * conv_out if angle_out else None
    for c in result.circuits:
        colour = _COLOURS[(c.index - 1) % len(_COLOURS)]
        for k, b in enumerate(c.branches):
            x = _wrapped(b.inputs, angle_in, conv_in)
            if has_output and b.outputs is not None:
                y = _wrapped(b.outputs, angle_out, conv_out)
            else:
                y = np.array([p.s for p in b.path.points], float) if b.path is not None else np.arange(len(x))
            xs, ys = _break(x, y, period_in, period_out)
            for j, (xx, yy) in enumerate(zip(xs, ys)):
                ax.plot(xx, yy, color=colour, lw=1.6, label=f"circuit {c.index}" if (k == 0 and j == 0) else None)
    seen = set()
    for n, s in enumerate(result.singularities, 1):
        kind = next((t for t in _MARKER_ORDER if t in s.types), s.kinds[0] if s.kinds else Kind.IM)
        style = LIM_STYLE if kind == Kind.LIM else STYLE.get(kind, STYLE[Kind.IM])
        y = s.output if has_output else s.arclength
        label = str(kind) if kind != Kind.LIM else f"LIM ({', '.join(s.locked_links)} locked)"
        ax.plot([s.input], [y], linestyle="none", marker=style["marker"], ms=8, mfc=style["colour"],
                mec="black", zorder=5, label=label if label not in seen else None, gid=f"singularity:{kind}")
        seen.add(label)
        if annotate:
            ax.annotate(str(n), (s.input, y), textcoords="offset points", xytext=(6, 6), fontsize=9, zorder=6)
    unit_in = ("deg" if deg else "rad") if angle_in else "model length"
    # the angle convention of every command: relative to the model's configuration, wrapped
    relative = ", from the model's configuration, in " + ("(−180°, 180°]" if deg else "(−π, π]")
    ax.set_xlabel(f"input {result.input} [{unit_in}]" + (relative if angle_in else ""))
    if has_output:
        unit_out = ("deg" if deg else "rad") if angle_out else "model length"
        ax.set_ylabel(f"output {result.output} [{unit_out}]" + (relative if angle_out else ""))
    else:
        ax.set_ylabel("arclength along the branch (model length scales)")
    ax.set_title(f"{result.mechanism.name}: {len(result.circuits)} circuit(s), "
                 f"{len(result.singularities)} singular configuration(s)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return ax


def _output_kind(result: Singularities) -> str | None:
    from symkin.solutions.frame_coordinates import output_coordinate

    c = output_coordinate(result.mechanism)
    return None if c is None else c.kind


def circuits_figure(result: Singularities):
    """A standalone ``Figure`` (Agg canvas, pyplot untouched) with :func:`plot_circuits`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    FigureCanvasAgg(fig)
    plot_circuits(result, ax=fig.add_subplot(1, 1, 1))
    return fig


def save_circuits_figure(result: Singularities, filename) -> FilePath:
    """Write :func:`circuits_figure` to a PNG (what ``symkin singularities ... --plot FILE.png`` writes)."""
    target = FilePath(filename)
    fig = circuits_figure(result)
    try:
        fig.savefig(target, dpi=110, format=None if target.suffix else "png")
    except OSError as exc:
        raise SymkinError(f"{target}: cannot write the figure ({exc.strerror or exc})") from exc
    return target
