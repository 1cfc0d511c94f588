"""WorkspaceMap: the --json object, the npz round trip, modes and seeds, scale invariance."""
from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest

import symkin
from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.model.model_file import write_model

X, Y = "velocity:P.x=-3.5:3.5", "velocity:P.y=0.2:4.4"


@pytest.fixture(scope="module")
def five_bar():
    return get("five_bar")


@pytest.fixture(scope="module")
def grid_map(five_bar):
    return symkin.workspace_map(five_bar, x=X, y=Y, n=31, refine=False)


def _other_elbow(mech):
    """Leg 1 in its other elbow: B1 reflected across the line A1-P, which is (0, 0) here."""
    x = dict(mech.nodes)
    a, p, b = (np.array(x[k]) for k in ("A1", "P", "B1"))
    d = (p - a) / np.linalg.norm(p - a)
    r = b - a
    return mech.with_coordinates({"B1": a + 2 * (r @ d) * d - r})


def test_json_object_keys(grid_map):
    d = json.loads(json.dumps(grid_map.to_dict()))
    assert {"axes", "modes", "curves", "points", "counts"} <= set(d)
    assert d["axes"] == [{"label": "velocity:P.x", "lo": -3.5, "hi": 3.5, "n": 31},
                         {"label": "velocity:P.y", "lo": 0.2, "hi": 4.4, "n": 31}]
    (mode,) = d["modes"]
    assert {"id", "seed", "assembled"} <= set(mode) and mode["id"] == 0 and mode["seed"] == "model"
    assert mode["assembled"] == pytest.approx(grid_map.modes[0].fraction)
    assert d["curves"] == [] and d["points"] == []
    assert d["counts"] == {"0": {"DKP-input": 0, "DKP-output": 0, "IM": 0}}


def test_npz_round_trip(grid_map, tmp_path):
    path = grid_map.save(tmp_path / "map.npz")
    back = symkin.load_map(path)
    assert back.to_dict() == grid_map.to_dict()
    for a, b in zip(back.modes, grid_map.modes):
        for name in ("assembled", "rejected", "im_indicator", "dkp_input", "dkp_output", "types"):
            assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True)
    with np.load(path, allow_pickle=False) as data:
        assert "mode0_dkp_output" in data.files


def test_npz_round_trip_with_curves(five_bar, tmp_path):
    m = symkin.workspace_map(five_bar, x=X, y=Y, n=31)
    if any("not available" in n for n in m.notes):
        pytest.skip("refinement (symkin.workspace.loci) is not installed")
    assert m.curves
    back = symkin.load_map(m.save(tmp_path / "c.npz"))
    assert back.to_dict() == m.to_dict()
    # type-1 loci of the five-bar: |P - A_i| = l1 + l2 = 3 or |l1 - l2| = 1
    for c in m.curves:
        p = np.asarray(c.points)
        r = np.column_stack([np.hypot(p[:, 0] + 1, p[:, 1]), np.hypot(p[:, 0] - 1, p[:, 1])])
        if c.kind == "DKP-output":
            assert np.min(np.abs(r[..., None] - np.array([1.0, 3.0])), axis=(1, 2)).max() < 1e-9


def test_load_map_refuses_other_files(tmp_path):
    bad = tmp_path / "x.npz"
    np.savez(bad, a=np.zeros(2))
    with pytest.raises(SymkinError, match="not a symkin map"):
        symkin.load_map(bad)


def test_to_xarray(grid_map):
    if importlib.util.find_spec("xarray") is None:
        with pytest.raises(SymkinError, match="needs xarray"):
            grid_map.to_xarray()
    else:
        ds = grid_map.to_xarray()
        assert ds["dkp_output"].shape == (1, 31, 31)


def test_two_working_modes(five_bar, tmp_path):
    seed = _other_elbow(five_bar)
    assert np.allclose(dict(seed.nodes)["B1"], [0.0, 0.0], atol=1e-12)
    path = tmp_path / "elbow.toml"
    write_model(seed, path)
    m = symkin.workspace_map(five_bar, x=X, y=Y, n=31, refine=False, seeds=[path, five_bar])
    assert [mode.seed for mode in m.modes] == ["model", str(path)]
    assert any("merged" in n for n in m.notes)  # the model given again as a seed
    a, b = m.modes
    # both elbows of leg 1 reach the same region (both annuli); the DKP-output values differ
    assert np.array_equal(a.assembled, b.assembled)
    both = a.assembled
    assert not np.allclose(a.dkp_output[both], b.dkp_output[both])


def test_seed_errors(five_bar, tmp_path):
    other = get("fourbar_appendix")
    with pytest.raises(SymkinError, match="not the same mechanism"):
        symkin.workspace_map(five_bar, x=X, y=Y, n=5, refine=False, seeds=[other])
    longer = five_bar.with_coordinates({"B1": [-1.7, 0.8]})
    with pytest.raises(SymkinError, match="does not close"):
        symkin.workspace_map(five_bar, x=X, y=Y, n=5, refine=False, seeds=[longer])
    rrr = get("rrr_3")
    with pytest.raises(SymkinError, match="not on the held values: rotation:platform"):
        symkin.workspace_map(rrr, x="velocity:C1.x=-1:1", y="velocity:C1.y=-1:1", n=5, refine=False,
                             hold=["rotation:platform=10"], seeds=[rrr])
    with pytest.raises(SymkinError, match="no --seed"):  # modes="all" takes its modes from the solver
        symkin.workspace_map(five_bar, x=X, y=Y, n=5, refine=False, modes="all", seeds=[five_bar])
    with pytest.raises(SymkinError, match="use one of model, all"):
        symkin.workspace_map(five_bar, x=X, y=Y, n=5, refine=False, modes="every")
    with pytest.raises(SymkinError, match="number of workers must be at least 1"):
        symkin.workspace_map(five_bar, x=X, y=Y, n=5, refine=False, workers=-1)


def test_nothing_assembles(five_bar):
    m = symkin.workspace_map(five_bar, x="velocity:P.x=10:12", y="velocity:P.y=10:12", n=5, refine=False)
    assert not m.assembled_anywhere and m.modes[0].fraction == 0.0
    assert any("no mode assembles" in n for n in m.notes)


def test_scale_invariance(five_bar):
    a = symkin.workspace_map(five_bar, x=X, y=Y, n=21, refine=False)
    b = symkin.workspace_map(five_bar.moved(scale=1000.0), x="velocity:P.x=-3500:3500",
                             y="velocity:P.y=200:4400", n=21, refine=False)
    ma, mb = a.modes[0], b.modes[0]
    assert np.array_equal(ma.assembled, mb.assembled) and np.array_equal(ma.types, mb.types)
    for name in ("dkp_input", "dkp_output", "im_indicator"):
        assert np.allclose(getattr(ma, name), getattr(mb, name), rtol=1e-8, atol=1e-12, equal_nan=True)


def test_degrees_and_radians_agree(five_bar):
    deg = symkin.workspace_map(five_bar, x="rotation:crank1=60:150", y="rotation:crank2=10:80", n=11,
                               refine=False)
    rad = symkin.workspace_map(five_bar, x=f"rotation:crank1={np.radians(60)}:{np.radians(150)}",
                               y=f"rotation:crank2={np.radians(10)}:{np.radians(80)}", n=11, refine=False,
                               unit="rad")
    assert np.allclose(deg.modes[0].dkp_output, rad.modes[0].dkp_output, rtol=1e-9, equal_nan=True)
    assert deg.modes[0].fraction == rad.modes[0].fraction == 1.0
