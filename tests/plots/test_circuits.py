"""The circuit plot draws what the result holds: one colour per circuit, every singular configuration numbered."""
from __future__ import annotations

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
    for line, s in zip(markers, result.singularities):
        assert line.get_xdata()[0] == pytest.approx(s.input) and line.get_ydata()[0] == pytest.approx(s.output)
    assert "rotation:crank" in ax.get_xlabel() and "rotation:rocker" in ax.get_ylabel()


@pytest.mark.slow
def test_save_circuits_figure_writes_a_png(result, tmp_path):
    target = save_circuits_figure(result, tmp_path / "c.png")
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(SymkinError, match="cannot write"):
        save_circuits_figure(result, tmp_path / "missing" / "c.png")


def test_plot_circuits_refuses_another_result():
    with pytest.raises(SymkinError, match="Singularities"):
        plot_circuits(object())
