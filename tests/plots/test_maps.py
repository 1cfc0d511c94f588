"""Plots of a singularity map (symkin.plots.maps): panels, curve / boundary artists, colour norms, the CLI."""
from __future__ import annotations

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
from symkin.plots.maps import (INDICATORS, axis_label, map_figure, plot_boundary, plot_im_surface,  # noqa: E402
                               plot_map, plot_seed, save_map_figure, seed_mechanism)

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
    for m in wmap.modes:
        for k, (name, _) in INDICATORS.items():
            ax = panels[f"panel:{m.id}:{k}"]
            assert f"mode {m.id} (seed: {m.seed}" in ax.get_title() and name in ax.get_title()
            assert ax.get_xlabel() == "P.x [model length]" and ax.get_ylabel() == "P.y [model length]"
    assert "five-bar" in figure.get_suptitle() and "2 mode(s)" in figure.get_suptitle()
    assert axis_label("rotation:crank1", "deg") == "angle of crank1 [deg]"


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
    from matplotlib.colors import LogNorm

    panels = _panels(figure)
    for m in wmap.modes:
        ok = m.assembled
        for k in INDICATORS:
            ax = panels[f"panel:{m.id}:{k}"]
            (mesh,) = [c for c in ax.collections if c.get_gid() == f"indicator:{k}:{m.id}"]
            data = np.ma.filled(np.ma.asarray(mesh.get_array(), float).reshape(m.assembled.shape), np.nan)
            assert np.isnan(data[~ok]).all()  # not assembled: blank, never guessed
            if k == "im_indicator":
                assert isinstance(mesh.norm, LogNorm)
                assert np.allclose(data[ok], np.abs(m.im_indicator[ok]))
                assert mesh.norm.vmax == pytest.approx(np.nanmax(np.abs(m.im_indicator[ok])))
            else:
                assert not isinstance(mesh.norm, LogNorm)
                assert mesh.norm.vmax > 0 and mesh.norm.vmin == -mesh.norm.vmax
                assert mesh.norm.vmax == pytest.approx(np.nanmax(np.abs(getattr(m, k)[ok])))
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

    from symkin.plots.maps import POINT_STYLES, _legend_handles, plot_map
    from symkin.workspace.maps import MapPoint

    mode = wmap.modes[0].id
    cusp = MapPoint(kind="cusp", mode=mode, at=(0.5, 2.0), types=("DKP-input",))
    with_cusp = dataclasses.replace(wmap, points=wmap.points + (cusp,))
    ax = plot_map(with_cusp, mode, "dkp_input")
    drawn = [ln for ln in ax.lines if ln.get_gid() == f"point:cusp:{mode}"]
    assert len(drawn) == 1 and drawn[0].get_marker() == POINT_STYLES["cusp"]["marker"] != POINT_STYLES["IM"]["marker"]
    assert "cusp point" in [h.get_label() for h in _legend_handles(with_cusp)]
