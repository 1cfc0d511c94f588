"""Tiled and Dask maps (:mod:`symkin.workspace.parallel`): a Dask run equals the serial tiled run.

Independent truth for the grid: the catalogue five-bar (A = (∓1, 0), |A_i B_i| = 1, |B_i P| = 2)
assembles where 1 <= |P − A_i| <= 3 for both legs, and its traced type-1 curves are the
circles |P − A_i| = 1, 3.
"""
from __future__ import annotations

import sys

import numpy as np
import pytest

import symkin
from symkin.cli import main
from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.model.model_file import write_model
from symkin.workspace.maps import GRID_ARRAYS
from symkin.workspace.parallel import MapSpec, system_of, tile_bounds, tiled_mode

X, Y = "velocity:P.x=-3.5:3.5", "velocity:P.y=0.2:4.4"
N, TILE = 41, 10


def _workspace_truth(xs, ys):
    """Closed form of the five-bar's reachable set: 1 <= |P - A_i| <= 3 (i = 1, 2)."""
    px, py = np.meshgrid(xs, ys)
    inside = np.ones(px.shape, bool)
    for ax in (-1.0, 1.0):
        r = np.hypot(px - ax, py)
        inside &= (r >= 1) & (r <= 3)
    return inside


def _distance_to_circles(pts):
    return np.min([np.abs(np.hypot(pts[:, 0] - a, pts[:, 1]) - r) for a in (-1, 1) for r in (1, 3)], axis=0)


@pytest.fixture(scope="module")
def serial():
    return symkin.workspace_map(get("five_bar"), x=X, y=Y, n=N, tile=TILE)


def test_tile_bounds_cover_the_grid():
    for n, t in ((41, 10), (20, 10), (5, 64), (2001, 64), (11, 2)):
        b = tile_bounds(n, t)
        assert b[0] == 0 and b[-1] == n and all(hi - lo >= 2 for lo, hi in zip(b, b[1:]))


@pytest.mark.slow
def test_tiled_serial_map_is_the_five_bar_workspace(serial):
    m = serial.modes[0]
    truth = _workspace_truth(serial.xs, serial.ys)
    # away from the boundary circles (half a cell) the mode assembles exactly where the closed form says
    px, py = np.meshgrid(serial.xs, serial.ys)
    margin = np.min([np.abs(np.hypot(px - a, py) - r) for a in (-1, 1) for r in (1, 3)], axis=0)
    clear = margin > 0.5 * (serial.xs[1] - serial.xs[0])
    assert np.array_equal(m.assembled[clear], truth[clear])
    assert m.assembled.sum() > 100
    assert [c.kind for c in serial.curves] == ["DKP-output"] * 4
    for c in serial.curves:
        assert _distance_to_circles(c.points).max() < 1e-9


@pytest.mark.slow
def test_tiles_agree_with_one_continuation():
    """Tiling changes the route of the continuation, not the configurations: same values to roundoff."""
    mech = get("five_bar")
    spec = MapSpec.of(mech, "velocity:P.x", "velocity:P.y")
    s = system_of(spec)
    xs, ys = np.linspace(-3.5, 3.5, N), np.linspace(0.2, 4.4, N)
    from symkin.workspace.grid import continue_mode

    one = continue_mode(s, xs, ys, s.q0)
    tiled = tiled_mode(spec, xs, ys, s.q0, tile=TILE)
    both = one.assembled & tiled.assembled
    assert both.sum() >= 0.98 * one.assembled.sum()
    for name in ("im_indicator", "dkp_input", "dkp_output"):
        a, b = getattr(one, name)[both], getattr(tiled, name)[both]
        assert np.max(np.abs(a - b)) < 1e-9
    assert np.array_equal(one.types[both], tiled.types[both])


@pytest.fixture(scope="module")
def client():
    pytest.importorskip("distributed", reason="needs the dask extra: pip install -e '.[dask]'")
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.mark.slow
def test_dask_run_equals_serial_run(client, serial):
    d = symkin.workspace_map(get("five_bar"), x=X, y=Y, n=N, tile=TILE, client=client)
    for a, b in zip(serial.modes, d.modes):
        for name in GRID_ARRAYS:
            assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
        assert a.branch_changes == b.branch_changes
    assert len(d.curves) == len(serial.curves) == 4
    for a, b in zip(serial.curves, d.curves):
        assert a.kind == b.kind and a.closed == b.closed and a.points.shape == b.points.shape
        assert np.max(np.abs(a.points - b.points)) <= 1e-9
    assert d.to_dict()["points"] == serial.to_dict()["points"]
    assert d.to_dict()["counts"] == serial.to_dict()["counts"]


@pytest.mark.slow
def test_dask_two_modes_and_keep_configurations(client):
    """Two working modes (the other elbow as a seed) and every configuration kept: the same on Dask."""
    mech = get("five_bar")
    kw = dict(x=X, y=Y, n=21, tile=8, refine=False, keep_configurations=True)
    a = symkin.workspace_map(mech, **kw)
    b = symkin.workspace_map(mech, client=client, **kw)
    assert len(a.modes) == len(b.modes)
    for ma, mb in zip(a.modes, b.modes):
        assert np.array_equal(ma.q, mb.q, equal_nan=True)
        assert np.array_equal(ma.assembled, mb.assembled)
    # the kept configurations close the loop at the grid's axis values
    s = system_of(MapSpec.of(mech, "velocity:P.x", "velocity:P.y"))
    j, i = np.argwhere(a.modes[0].assembled)[len(np.argwhere(a.modes[0].assembled)) // 2]
    assert np.allclose(s.axis_values(a.modes[0].q[j, i][None])[0], [a.xs[i], a.ys[j]], atol=1e-12)


@pytest.mark.slow
def test_cli_workers(capsys, tmp_path):
    pytest.importorskip("distributed", reason="needs the dask extra: pip install -e '.[dask]'")
    model = write_model(get("five_bar"), tmp_path / "fivebar.toml")
    code = main(["map", str(model), f"--x={X}", f"--y={Y}", "--n", "21", "--no-refine", "--workers", "2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "mode 0 (seed model): assembled at" in out and "Traceback" not in err


def test_without_dask_is_a_clear_error(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(SymkinError, match=r'pip install -e "\.\[dask\]"'):
        symkin.workspace_map(get("five_bar"), x=X, y=Y, n=5, refine=False, workers=2)
    model = write_model(get("five_bar"), tmp_path / "fivebar.toml")
    for opt in (["--workers", "2"], ["--scheduler", "tcp://127.0.0.1:1"]):
        code = main(["map", str(model), f"--x={X}", f"--y={Y}", "--n", "5", "--no-refine", *opt])
        out, err = capsys.readouterr()
        assert code == 2 and 'pip install -e ".[dask]"' in err and "Traceback" not in err


@pytest.mark.slow
def test_cli_scheduler_equals_serial_tiles(client, capsys, tmp_path):
    """``--scheduler ADDRESS`` runs on an existing cluster; its --json equals the serial tiled map's."""
    import json

    model = write_model(get("five_bar"), tmp_path / "fivebar.toml")
    code = main(["map", str(model), f"--x={X}", f"--y={Y}", "--n", "21", "--json", "-",
                 "--scheduler", client.scheduler.address])
    out, err = capsys.readouterr()
    assert code == 0, err
    from symkin.workspace.parallel import TILE

    serial = symkin.workspace_map(get("five_bar"), x=X, y=Y, n=21, tile=TILE)
    assert json.loads(out) == json.loads(json.dumps(serial.to_dict()))
    assert json.loads(out)["counts"]["0"]["DKP-output"] >= 4


@pytest.mark.slow
def test_default_one_process_run_equals_dask_run(client):
    """No tile given: one process and Dask continue over the same tiles (default TILE), so the grid
    arrays are identical and the curves equal, on a grid of several tiles (and the closed form holds)."""
    from symkin.workspace.parallel import TILE

    n = (TILE + 17, 33)  # two tiles along x
    one = symkin.workspace_map(get("five_bar"), x=X, y=Y, n=n)
    dsk = symkin.workspace_map(get("five_bar"), x=X, y=Y, n=n, client=client)
    for a, b in zip(one.modes, dsk.modes):
        for name in GRID_ARRAYS:
            assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert len(one.curves) == len(dsk.curves) == 4
    for a, b in zip(one.curves, dsk.curves):
        assert a.kind == b.kind and a.points.shape == b.points.shape
        assert np.max(np.abs(a.points - b.points)) <= 1e-9
        assert _distance_to_circles(a.points).max() < 1e-9
    truth = _workspace_truth(one.xs, one.ys)
    px, py = np.meshgrid(one.xs, one.ys)
    margin = np.min([np.abs(np.hypot(px - a, py) - r) for a in (-1, 1) for r in (1, 3)], axis=0)
    clear = margin > 0.5 * (one.xs[1] - one.xs[0])
    assert np.array_equal(one.modes[0].assembled[clear], truth[clear])


def test_tile_argument_is_checked():
    for bad in (1, -3, 2.5):
        with pytest.raises(SymkinError, match="tile"):
            symkin.workspace_map(get("five_bar"), x=X, y=Y, n=5, refine=False, tile=bad)
    with pytest.raises(SymkinError, match="one process"):
        symkin.workspace_map(get("five_bar"), x=X, y=Y, n=5, refine=False, tile=0, workers=2)
    untiled = symkin.workspace_map(get("five_bar"), x=X, y=Y, n=21, refine=False, tile=0)
    assert round(untiled.modes[0].fraction, 3) == 0.156
