"""Plots of a singularity map (symkin.plots.maps): panels, curve / boundary artists, colour norms, the CLI."""
from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import symkin  # noqa: E402
from symkin.cli import main  # noqa: E402
from symkin.errors import SymkinError  # noqa: E402
from symkin.model.catalogue import get  # noqa: E402
from symkin.model.model_file import write_model  # noqa: E402
from symkin.plots.maps import (INDICATORS, axis_label, map_figure, map_panel_figures, plot_boundary,  # noqa: E402
                               plot_im_surface, plot_map, plot_seed, save_map_figure, seed_mechanism)

X, Y = "velocity:P.x=-3.5:3.5", "velocity:P.y=0.2:4.4"
N = 31
#: the catalogue five-bar: A1 = (-1, 0), A2 = (1, 0), cranks l1 = 1, distal links l2 = 2
BASES, L1, L2 = (np.array([-1.0, 0.0]), np.array([1.0, 0.0])), 1.0, 2.0


def _other_elbow(mech):
    """Leg 1 in its other elbow: B1 reflected across the line A1-P."""
    x = dict(mech.nodes)
    a, p, b = (np.array(x[k]) for k in ("A1", "P", "B1"))
    d = (p - a) / np.linalg.norm(p - a)
    r = b - a
    return mech.with_coordinates({"B1": a + 2 * (r @ d) * d - r})


@pytest.fixture(scope="module")
def five_bar():
    return get("five_bar")


@pytest.fixture(scope="module")
def wmap(five_bar):
    """Two working modes (the model and leg 1's other elbow), refined to curves."""
    return symkin.workspace_map(five_bar, x=X, y=Y, n=N, seeds=[_other_elbow(five_bar)])


@pytest.fixture(scope="module")
def figure(wmap, five_bar):
    return map_figure(wmap, five_bar)


@pytest.fixture(scope="module")
def one_mode(wmap):
    """The model's mode alone (the map of the README's example)."""
    return dataclasses.replace(wmap, modes=wmap.modes[:1], curves=tuple(c for c in wmap.curves if c.mode == 0),
                               points=tuple(p for p in wmap.points if p.mode == 0))


@pytest.fixture(scope="module")
def one_mode_figure(one_mode, five_bar):
    return map_figure(one_mode, five_bar)


def _panels(fig):
    return {a.get_gid(): a for a in fig.axes if (a.get_gid() or "").startswith("panel:")}


def test_the_map_has_two_modes_and_curves(wmap):
    assert len(wmap.modes) == 2 and wmap.curves  # what the figure tests below rely on


def test_one_panel_per_mode_and_indicator_plus_mechanism(figure, wmap, five_bar):
    panels = _panels(figure)
    expected = {f"panel:{m.id}:{k}" for m in wmap.modes for k in (*INDICATORS, "mechanism")}
    assert set(panels) == expected
    assert len(_panels(map_figure(wmap))) == len(wmap.modes) * len(INDICATORS)  # no mechanism given
    assert len(_panels(map_figure(wmap, indicators=("im_indicator",)))) == len(wmap.modes)


def test_titles_and_axis_labels_say_mode_seed_indicator_and_units(figure, wmap):
    panels = _panels(figure)
    for m in wmap.modes:  # one column per mode, named once at its top
        top = panels[f"panel:{m.id}:im_indicator"].get_title()
        assert f"mode {m.id} (seed:" in top and m.seed.split()[0] in top and "% assembled" in top
        for k in (*INDICATORS, "mechanism"):
            if k != "im_indicator":
                assert panels[f"panel:{m.id}:{k}"].get_title() == ""
        # the axes' labels once: x under the bottom row, y for the figure
        assert panels[f"panel:{m.id}:mechanism"].get_xlabel() == "P.x [model length]"
        assert all(panels[f"panel:{m.id}:{k}"].get_xlabel() == "" for k in INDICATORS)
    assert figure.get_supylabel() == "P.y [model length]"
    # each indicator is named by its colour bar (one per row, shared by the modes)
    bars = {a.get_gid(): a for a in figure.axes if (a.get_gid() or "").startswith("colourbar:")}
    assert set(bars) == {f"colourbar:{k}" for k in INDICATORS}
    for k, (name, _) in INDICATORS.items():
        assert bars[f"colourbar:{k}"].get_xlabel().startswith(name)
    assert "five-bar" in figure.get_suptitle() and "2 mode(s)" in figure.get_suptitle()
    assert axis_label("rotation:crank1", "deg") == "angle of crank1 [deg]"


def test_the_title_is_given_once(figure, one_mode_figure):
    """The figure's title is its suptitle; no two panels repeat a title, none repeats the suptitle."""
    for fig in (figure, one_mode_figure):
        sup = fig.get_suptitle()
        assert sup
        titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
        assert len(titles) == len(set(titles))
        assert not any(t in sup or sup in t for t in titles)


def test_every_curve_is_one_line_with_its_gid_in_its_modes_panels(figure, wmap):
    panels = _panels(figure)
    for m in wmap.modes:
        mine = [c for c in wmap.curves if c.mode == m.id]
        for k in (*INDICATORS, "mechanism"):
            lines = [ln for ln in panels[f"panel:{m.id}:{k}"].lines if (ln.get_gid() or "").startswith("curve:")]
            assert sorted(ln.get_gid() for ln in lines) == sorted(f"curve:{c.kind}:{m.id}" for c in mine)
        ax = panels[f"panel:{m.id}:im_indicator"]
        lines = [ln for ln in ax.lines if (ln.get_gid() or "").startswith("curve:")]
        for ln, c in zip(lines, mine):  # drawn in the map's order, through the traced points
            drawn = np.column_stack(ln.get_data())
            assert np.allclose(drawn[:len(c.points)], c.points)


def test_points_are_drawn_with_their_gid(figure, wmap):
    panels = _panels(figure)
    for p in wmap.points:
        ax = panels[f"panel:{p.mode}:dkp_output"]
        hits = [ln for ln in ax.lines if ln.get_gid() == f"point:{p.kind}:{p.mode}"]
        assert any(np.allclose(np.ravel(ln.get_data()), p.at) for ln in hits)


def test_boundary_is_the_mask_contour_on_the_type1_circles(figure, wmap):
    """The five-bar's workspace boundary: the circles |P - A_i| = l1 ± l2 (elementary geometry)."""
    h = max(np.diff(wmap.xs).max(), np.diff(wmap.ys).max())
    for m in wmap.modes:
        ax = _panels(figure)[f"panel:{m.id}:dkp_input"]
        (cs,) = [c for c in ax.collections if c.get_gid() == f"boundary:{m.id}"]
        verts = np.vstack([p.vertices for p in cs.get_paths() if len(p.vertices)])
        dist = np.min([np.abs(np.linalg.norm(verts - a, axis=1) - r)
                       for a in BASES for r in (L1 + L2, L2 - L1)], axis=0)
        inside_box = (verts[:, 1] > wmap.ys[0] + h) & (np.abs(verts[:, 0]) < wmap.xs[-1] - h)
        assert len(verts) > 20 and dist[inside_box].max() < h


def test_colour_norms_log_for_im_symmetric_for_dkp(figure, wmap):
    """One scale per indicator for every mode (the panels of a row compare): its extremes are
    those of all modes' assembled values."""
    from matplotlib.colors import LogNorm

    panels = _panels(figure)
    for k in INDICATORS:
        every = np.concatenate([np.asarray(getattr(m, k))[m.assembled] for m in wmap.modes])
        for m in wmap.modes:
            ok = m.assembled
            ax = panels[f"panel:{m.id}:{k}"]
            (mesh,) = [c for c in ax.collections if c.get_gid() == f"indicator:{k}:{m.id}"]
            data = np.ma.filled(np.ma.asarray(mesh.get_array(), float).reshape(m.assembled.shape), np.nan)
            assert np.isnan(data[~ok]).all()  # not assembled: blank, never guessed
            if k == "im_indicator":
                assert isinstance(mesh.norm, LogNorm)
                assert np.allclose(data[ok], np.abs(m.im_indicator[ok]))
                assert mesh.norm.vmax == pytest.approx(np.nanmax(np.abs(every)))
                assert mesh.norm.vmin <= np.nanmin(np.abs(every[every != 0]))
            else:
                assert not isinstance(mesh.norm, LogNorm)
                assert mesh.norm.vmax > 0 and mesh.norm.vmin == -mesh.norm.vmax
                assert mesh.norm.vmax == pytest.approx(np.nanmax(np.abs(every)))  # of order 1: as it is
                assert np.allclose(data[ok], getattr(m, k)[ok])


def test_seed_panel_draws_the_mechanism_at_each_modes_seed(figure, wmap, five_bar):
    panels = _panels(figure)
    b1 = []
    for m in wmap.modes:
        ax = panels[f"panel:{m.id}:mechanism"]
        seed = dict(seed_mechanism(wmap, m.id, five_bar).nodes)
        (star,) = [ln for ln in ax.lines if ln.get_gid() == f"seed:{m.id}"]
        assert np.allclose(np.ravel(star.get_data()), seed["P"])
        (crank,) = [ln for ln in ax.lines if ln.get_gid() == "link:crank1"]
        assert np.allclose(np.column_stack(crank.get_data())[1], seed["B1"])
        b1.append(seed["B1"])
    assert np.allclose(b1[0], dict(five_bar.nodes)["B1"])
    assert np.allclose(b1[1], dict(_other_elbow(five_bar).nodes)["B1"])  # the other elbow, not the model's


def test_seed_of_another_mechanism_is_a_clear_error(wmap):
    with pytest.raises(SymkinError, match="not the mechanism of the map"):
        seed_mechanism(wmap, 0, get("fourbar_flat"))


def test_single_axes_functions_take_ax_none(wmap):
    ax = plot_map(wmap, 1, "dkp_input", colorbar=False, curves=False)
    assert [c.get_gid() for c in ax.collections] == ["indicator:dkp_input:1", "boundary:1"]
    assert plot_boundary(wmap, 0).collections[0].get_gid() == "boundary:0"
    surf = plot_im_surface(wmap, 0)
    assert surf.name == "3d" and [c.get_gid() for c in surf.collections] == ["im_surface:0"]
    assert plot_seed(wmap, 0, get("five_bar")).get_title().startswith("mode 0")
    with pytest.raises(SymkinError, match="indicator 'types'"):
        plot_map(wmap, 0, "types")
    with pytest.raises(SymkinError, match="no mode 7"):
        plot_map(wmap, 7)


def test_save_map_figure_writes_a_png(wmap, tmp_path):
    target = save_map_figure(wmap, tmp_path / "map", indicators=("dkp_input",))  # no suffix: PNG
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(SymkinError, match="cannot write the figure"):
        save_map_figure(wmap, tmp_path / "no" / "such" / "dir.png", indicators=("dkp_input",))


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    return write_model(get("five_bar"), tmp_path_factory.mktemp("m") / "fivebar.toml")


def test_cli_map_plot_writes_a_png(model_file, tmp_path, capsys):
    target = tmp_path / "out.png"
    code = main(["map", str(model_file), f"--x={X}", f"--y={Y}", "--n", "9", "--no-refine", "--plot", str(target),
                 "--no-progress"])
    _, err = capsys.readouterr()
    assert code == 0, err
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_plot_without_matplotlib_names_the_extra(model_file, tmp_path, capsys, monkeypatch):
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if it were not installed
    target = tmp_path / "out.png"
    code = main(["map", str(model_file), f"--x={X}", f"--y={Y}", "--n", "5", "--no-refine", "--plot", str(target),
                 "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert "--plot needs" in err and "plots" in err and "Traceback" not in err
    assert not target.exists()


def test_a_cusp_point_has_its_own_marker_and_legend_entry(wmap):
    """Cusps of traced curves (``kind: "cusp"``) are drawn with the cusp marker, not the IM one."""
    import dataclasses

    from symkin.plots.maps import POINT_STYLES, legend_handles, plot_map
    from symkin.workspace.maps import MapPoint

    mode = wmap.modes[0].id
    cusp = MapPoint(kind="cusp", mode=mode, at=(0.5, 2.0), types=("DKP-input",))
    with_cusp = dataclasses.replace(wmap, points=wmap.points + (cusp,))
    ax = plot_map(with_cusp, mode, "dkp_input")
    drawn = [ln for ln in ax.lines if ln.get_gid() == f"point:cusp:{mode}"]
    assert len(drawn) == 1 and drawn[0].get_marker() == POINT_STYLES["cusp"]["marker"] != POINT_STYLES["IM"]["marker"]
    assert "cusp" in [h.get_label() for h in legend_handles([ax])]


# ---------------------------------------------------------------------- figures for print
from tests.plots.print_size import COLUMN, assert_printable  # noqa: E402


def test_printed_points_sees_a_small_text():
    """The measure fails on a text of 7 pt in a figure printed at its own width (the old maps' ticks)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(COLUMN, 2.0))
    fig.add_subplot().tick_params(labelsize=7)
    with pytest.raises(AssertionError, match="under 9"):
        assert_printable(fig)
    fig = Figure(figsize=(2 * COLUMN, 2.0))  # twice as wide: 12 pt print as 6
    ax = fig.add_subplot()
    ax.tick_params(labelsize=18)
    ax.set_title("x", fontsize=12)
    with pytest.raises(AssertionError, match="under 9"):
        assert_printable(fig)


def test_map_figures_print_at_9_points_or_more_in_one_column(figure, one_mode_figure, wmap, five_bar):
    for fig in (figure, one_mode_figure):
        assert fig.get_size_inches()[0] == pytest.approx(COLUMN)
        assert_printable(fig)
    for fig in map_panel_figures(wmap, five_bar).values():
        assert fig.get_size_inches()[0] == pytest.approx(COLUMN)
        assert_printable(fig)
    # three modes: drawn wider, its text scaled alike
    three = dataclasses.replace(wmap, modes=wmap.modes + (dataclasses.replace(wmap.modes[1], id=2),))
    fig = map_figure(three, five_bar)
    assert fig.get_size_inches()[0] > COLUMN
    assert_printable(fig)


def _drawn_markers(fig) -> set:
    """(marker, face colour) of every marker drawn on the figure's panels (not in its legend)."""
    from matplotlib.colors import to_hex

    out = set()
    for ax in fig.axes:
        for ln in ax.lines:
            if ln.get_visible() and ln.get_marker() not in (None, "", " ", "None", "none") and len(ln.get_xdata()):
                out.add((ln.get_marker(), to_hex(ln.get_markerfacecolor())))
        for c in ax.collections:  # scatter markers, if any
            if type(c).__name__ == "PathCollection" and len(c.get_offsets()):
                out.add(("scatter", to_hex(c.get_facecolor()[0])))
    return out


def _legend_markers(fig) -> set:
    from matplotlib.colors import to_hex

    (legend,) = fig.legends
    return {(h.get_marker(), to_hex(h.get_markerfacecolor())) for h in legend.legend_handles
            if h.get_marker() not in (None, "", " ", "None", "none")}


@pytest.fixture(scope="module")
def every_point_kind(wmap):
    """The map with a point of every kind a map reports (IM, LIM, meeting, cusp) added to mode 0."""
    from symkin.workspace.maps import MapPoint

    extra = tuple(MapPoint(kind=k, mode=0, at=(0.4 * j - 0.6, 2.0), types=t)
                  for j, (k, t) in enumerate([("IM", ("IM",)), ("LIM", ("LIM",)),
                                              ("meeting", ("DKP-input", "DKP-output")), ("cusp", ("DKP-input",))]))
    return dataclasses.replace(wmap, points=wmap.points + extra)


def test_the_legend_covers_every_marker_and_curve_kind_drawn(figure, every_point_kind, five_bar):
    from matplotlib.colors import to_hex

    from symkin.plots.maps import POINT_STYLES

    fig = map_figure(every_point_kind, five_bar)
    drawn = _drawn_markers(fig)
    kinds = {(POINT_STYLES[k]["marker"], to_hex(POINT_STYLES[k]["colour"])) for k in ("IM", "LIM", "meeting", "cusp")}
    assert kinds <= drawn and len(kinds) == 4  # four kinds, four distinct markers
    for f in (figure, fig, *map_panel_figures(every_point_kind, five_bar).values()):
        missing = _drawn_markers(f) - _legend_markers(f)
        assert not missing, f"markers drawn without a legend entry: {missing}"
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    for text in ("IM point", "LIM point", "meeting point", "cusp", "P at the seed", "fixed node", "joint",
                 "DKP-output curve", "workspace boundary"):
        assert text in labels
    # every curve kind drawn has a legend line of its colour
    curve_colours = {to_hex(ln.get_color()) for ax in fig.axes for ln in ax.lines
                     if (ln.get_gid() or "").startswith("curve:")}
    legend_lines = {to_hex(h.get_color()) for h in fig.legends[0].legend_handles if h.get_marker() in ("None", None, "")}
    assert curve_colours and curve_colours <= legend_lines


def _colourbar_ticks(fig) -> dict:
    """{indicator: [(value, label), ...]} of each colour bar, the ticks inside its range."""
    fig.canvas.draw()
    out = {}
    for ax in fig.axes:
        gid = ax.get_gid() or ""
        if gid.startswith("colourbar:"):
            axis = ax.xaxis if ax.get_xlabel() else ax.yaxis
            lo, hi = sorted(axis.get_view_interval())
            out[gid.split(":")[1]] = [(t.get_loc(), t.label1.get_text()) for t in axis.get_major_ticks()
                                      if lo <= t.get_loc() <= hi and t.label1.get_text()]
            assert not axis.get_offset_text().get_text()  # no "1e-6" floating above the bar
    return out


def test_colour_bars_have_at_least_three_ticks(figure, one_mode_figure, wmap, five_bar):
    for fig in (figure, one_mode_figure, *map_panel_figures(wmap, five_bar).values()):
        for name, ticks in _colourbar_ticks(fig).items():
            assert len(ticks) >= 3, f"{name}: {ticks}"


def test_tiny_dkp_values_get_a_normalised_scale_labelled_as_such(wmap, five_bar):
    """DKP tests of about 1e-6 everywhere: drawn divided by their largest magnitude, on [-1, 1],
    the colour bar naming that magnitude; the IM indicator's log scale keeps its values."""
    from symkin.plots.maps import colour_scale

    tiny = dataclasses.replace(wmap, modes=tuple(dataclasses.replace(m, dkp_input=m.dkp_input * 1e-6,
                                                                       im_indicator=m.im_indicator * 1e-6)
                                                 for m in wmap.modes))
    top = max(np.nanmax(np.abs(m.dkp_input[m.assembled])) for m in tiny.modes)
    scale = colour_scale(tiny, "dkp_input")
    assert scale.normalised and scale.factor == pytest.approx(1 / top)
    assert (scale.norm.vmin, scale.norm.vmax) == (-1.0, 1.0)
    assert "normalised" in scale.label and f"{top:.2g}" in scale.label
    assert not colour_scale(tiny, "dkp_output").normalised  # its values are of order 1
    assert not colour_scale(tiny, "im_indicator").normalised
    fig = map_figure(tiny, five_bar)
    m = tiny.modes[0]
    (mesh,) = [c for ax in fig.axes for c in ax.collections if c.get_gid() == f"indicator:dkp_input:{m.id}"]
    data = np.ma.filled(np.ma.asarray(mesh.get_array(), float).reshape(m.assembled.shape), np.nan)
    assert np.allclose(data[m.assembled], m.dkp_input[m.assembled] / top)
    ticks = _colourbar_ticks(fig)
    assert [v for v, _ in ticks["dkp_input"]][0] >= -1.0 and len(ticks["dkp_input"]) >= 3
    assert all("e-" not in label for _, label in ticks["dkp_input"])
    bar = next(a for a in fig.axes if a.get_gid() == "colourbar:dkp_input")
    assert "normalised" in bar.get_xlabel()
    assert len(ticks["im_indicator"]) >= 3  # a log scale of 1e-8 .. 1e-6: its ticks say so
    assert_printable(fig)


def test_panels_one_figure_per_panel_named_after_it(wmap, five_bar, tmp_path):
    from symkin.plots.maps import save_map_panels

    figs = map_panel_figures(wmap, five_bar)
    names = {f"mode{m.id}-{k}" for m in wmap.modes for k in (*INDICATORS, "mechanism")}
    assert set(figs) == names
    for name, fig in figs.items():
        (panel,) = [a for a in fig.axes if (a.get_gid() or "").startswith("panel:")]
        mode, kind = name[len("mode"):].split("-", 1)
        assert panel.get_gid() == f"panel:{mode}:{kind}"
        assert f"mode {mode}" in fig.get_suptitle() and panel.get_title() == ""
    written = save_map_panels(wmap, tmp_path / "fig.png", five_bar)
    assert sorted(p.name for p in written) == sorted(f"fig-{n}.png" for n in names)
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in written)


def test_cli_map_panels_writes_one_file_per_panel(model_file, tmp_path, capsys):
    target = tmp_path / "out.pdf"
    code = main(["map", str(model_file), f"--x={X}", f"--y={Y}", "--n", "9", "--no-refine", "--plot", str(target),
                 "--panels", "--no-progress"])
    _, err = capsys.readouterr()
    assert code == 0, err
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == sorted(f"out-mode0-{k}.pdf" for k in (*INDICATORS, "mechanism"))
    assert all((tmp_path / f).read_bytes()[:5] == b"%PDF-" for f in files)
    code = main(["map", str(model_file), f"--x={X}", f"--y={Y}", "--n", "5", "--panels", "--no-progress"])
    assert code == 2 and "--panels" in capsys.readouterr().err


def test_cli_map_help_documents_panels(capsys):
    with pytest.raises(SystemExit):
        main(["map", "--help"])
    out = "".join(capsys.readouterr().out.split())  # argparse wraps lines, at hyphens too
    assert "--panels" in out and "FILE-mode<ID>-<panel>.png" in out
