"""The circuit plot draws what the result holds: one colour per circuit, every singular configuration numbered."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symkin.errors import SymkinError
from symkin.model import catalogue

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
pytest.importorskip("bertini", reason="singularities need the optional extra symkin[global]")

from symkin.plots.circuits import plot_circuits, save_circuits_figure  # noqa: E402
from symkin.solutions.circuits import singularities  # noqa: E402


@pytest.fixture(scope="module")
def result():
    return singularities(catalogue.get("fourbar_appendix"), unit="deg")


@pytest.mark.slow
def test_plot_circuits_marks_and_numbers_every_singular_configuration(result):
    ax = plot_circuits(result)
    labels = sorted(t.get_text() for t in ax.texts)
    assert labels == [str(k) for k in range(1, len(result.singularities) + 1)]
    colours = {line.get_color() for line in ax.lines if line.get_marker() in ("None", None, "")}
    assert len(colours) == len(result.circuits) == 2
    markers = [line for line in ax.lines if line.get_marker() == "D"]  # DKP-output diamonds
    assert len(markers) == 4
    # absolute angles, as the JSON's input_absolute / output_absolute (up to whole turns: ticks read modulo 360°)
    for line, s in zip(markers, result.to_dict()["singularities"]):
        for drawn, value in ((line.get_xdata()[0], s["input_absolute"]), (line.get_ydata()[0], s["output_absolute"])):
            assert math.remainder(drawn - value, 360.0) == pytest.approx(0.0, abs=1e-9)
    assert "rotation:crank" in ax.get_xlabel() and "rotation:rocker" in ax.get_ylabel()
    assert "absolute" in ax.get_xlabel() and "absolute" in ax.get_ylabel()


@pytest.mark.slow
def test_save_circuits_figure_writes_a_png(result, tmp_path):
    target = save_circuits_figure(result, tmp_path / "c.png")
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(SymkinError, match="cannot write"):
        save_circuits_figure(result, tmp_path / "missing" / "c.png")


def test_plot_circuits_refuses_another_result():
    with pytest.raises(SymkinError, match="Singularities"):
        plot_circuits(object())


def test_circuits_are_not_cut_at_the_wrap_and_every_marker_kind_has_a_legend_entry(result):
    from symkin.plots.circuits import circuits_figure

    fig = circuits_figure(result)
    (ax,) = fig.axes
    # the rocker turns less than a full turn on each circuit: one unbroken curve per circuit
    for c in result.circuits:
        pieces = [line for line in ax.lines if line.get_gid() == f"circuit:{c.index}"]
        xs = [np.asarray(p.get_xdata()) for p in pieces]
        ys = [np.asarray(p.get_ydata()) for p in pieces]
        for y in ys:
            assert np.abs(np.diff(y)).max() < 30.0
        # the crank turns fully: the curve spans one turn, in [0°, 360°), and is cut only where it wraps
        x = np.concatenate(xs)
        assert 0.0 <= x.min() and x.max() < 360.0 and np.ptp(x) > 350.0
        for (x0, y0), (x1, y1) in zip(zip(xs, ys), zip(xs[1:], ys[1:])):
            assert abs(abs(x0[-1] - x1[0]) - 360.0) < 20.0 and abs(y0[-1] - y1[0]) < 20.0
    # a legend entry for every circuit and every marker kind drawn
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    kinds = {line.get_gid().split(":", 1)[1] for line in ax.lines if (line.get_gid() or "").startswith("singularity:")}
    assert all(any(lab.startswith(k) for lab in legend) for k in kinds)
    assert {f"circuit {c.index}" for c in result.circuits} <= set(legend)
    # the legend is below the axes: it covers no data
    fig.canvas.draw()
    assert ax.get_legend().get_window_extent().y1 <= ax.get_window_extent().y0
    # every text is at least 9 pt when the figure is printed one column (3.5 in) wide
    scale = 3.5 / fig.get_figwidth()
    texts = [t for t in fig.findobj(matplotlib.text.Text) if t.get_text() and t.get_visible()]
    assert texts and min(t.get_fontsize() for t in texts) * scale >= 9.0
    # an angle axis reads in quarter turns, each tick label once (the full turn at the right end is 360, not 0)
    lo, hi = ax.get_xlim()
    ticks = [(t.get_position()[0], t.get_text()) for t in ax.get_xticklabels() if lo <= t.get_position()[0] <= hi]
    assert [v % 90 for v, _ in ticks] == [0.0] * len(ticks) and len(ticks) >= 4
    assert len({label for _, label in ticks}) == len(ticks)
