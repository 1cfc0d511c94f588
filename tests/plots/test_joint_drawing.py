"""Plots draw a model written by its joints as joints (issue 16): sliders as blocks, R and U axes
as axes, prismatic legs whole (base joint to platform joint), and no added node as a joint."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from symkin.plots import draw_mechanism
from tests.model import joint_forms as jf


@pytest.fixture(autouse=True)
def _close():
    import matplotlib.pyplot as plt

    yield
    plt.close("all")


def _lines(ax) -> dict[str, np.ndarray]:
    """The drawn lines by gid, as (k, dim) point arrays (3-D lines with their z)."""
    out = {}
    for line in ax.lines:
        data = line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_data()
        out[str(line.get_gid())] = np.column_stack([np.asarray(v, float) for v in data])
    return out


def _texts(ax) -> set[str]:
    return {t.get_text().strip() for t in ax.texts}


def _ends_are(seg: np.ndarray, p, q) -> bool:
    return (np.allclose(seg[0], p, atol=1e-9) and np.allclose(seg[-1], q, atol=1e-9)) or \
        (np.allclose(seg[0], q, atol=1e-9) and np.allclose(seg[-1], p, atol=1e-9))


def _ups() -> symkin.Mechanism:
    return symkin.Mechanism.from_dict(jf.ups_6(symkin.read_model(jf.MODELS / "gough_stewart.toml").coordinates()))


def test_ups_legs_are_whole_from_base_joint_to_platform_joint_in_3d():
    m = _ups()
    ax = draw_mechanism(m)
    assert ax.name == "3d"
    lines = _lines(ax)
    x = dict(m.nodes)
    for k in range(1, 7):
        assert _ends_are(lines[f"leg:P{k}"], x[f"U{k}"], x[f"S{k}"]), k       # not ending at P{k}.line
        assert np.allclose(lines[f"slider:P{k}"], [x[f"P{k}"]])                 # the block on the leg
        for end, gid in ((f"U{k}.axis", f"axis:U{k}.1"), (f"U{k}.axis2", f"axis:U{k}.2")):
            seg = lines[gid]                                                    # each U axis: a segment on it
            a = np.subtract(x[end], x[f"U{k}"])
            assert np.allclose(seg.mean(axis=0), x[f"U{k}"])
            assert abs(abs(np.dot(seg[1] - seg[0], a)) - np.linalg.norm(seg[1] - seg[0]) * np.linalg.norm(a)) < 1e-9
    assert not any(g.startswith(("link:cyl", "link:rod")) or "cross" in g for g in lines)


def test_added_nodes_are_neither_labelled_nor_marked():
    m = _ups()
    ax = draw_mechanism(m)
    added = {n for n in m.node_names if "." in n}
    assert added and {"U1.axis", "U1.axis2", "P1.line", "P1.end"} <= added
    texts = _texts(ax)
    assert not texts & added and not any("." in t for t in texts)
    assert {"U1", "S1", "O"} <= texts
    idx = m.node_index()
    x = np.array([c for _, c in m.nodes])
    marked = np.vstack([v for g, v in _lines(ax).items() if g in ("nodes", "fixed")])
    for n in added:
        assert not np.any(np.all(np.isclose(marked, x[idx[n]]), axis=1)), n


def test_planar_rpr_after_a_move_keeps_whole_legs_and_blocks():
    m = symkin.Mechanism.from_dict(jf.rpr_3(symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates()))
    path = symkin.trace(m, "joint:P1", 0.0, 0.4, steps=8, branch_analysis=False)
    moved = m.with_coordinates(path.points[-1].coordinates.reshape(-1, 2))
    ax = draw_mechanism(moved)
    lines = _lines(ax)
    x = dict(moved.nodes)
    for k in (1, 2, 3):
        assert _ends_are(lines[f"leg:P{k}"], x[f"A{k}"], x[f"C{k}"])
        assert np.allclose(lines[f"slider:P{k}"], [x[f"P{k}"]])
    slid = np.linalg.norm(np.subtract(x["P1"], x["A1"]))
    assert slid == pytest.approx(0.4, abs=1e-6)                           # the block moved along leg 1
    assert "P1" in _texts(ax) and "P1.line" not in _texts(ax)


def test_spatial_r_axes_and_bars_by_the_joints_points():
    m = symkin.Mechanism.from_dict(jf.bennett(catalogue.get("bennett").coordinates()))
    ax = draw_mechanism(m)
    lines = _lines(ax)
    x = dict(m.nodes)
    for j in "ABCD":
        seg = lines[f"axis:{j}"]
        a = np.subtract(x[f"{j}.axis"], x[j])
        assert np.allclose(seg.mean(axis=0), x[j])
        assert np.linalg.norm(np.cross(seg[1] - seg[0], a)) < 1e-9 * np.linalg.norm(a)
    assert _ends_are(lines["link:link2"], x["B"], x["C"])                 # the link from joint to joint
    assert _texts(ax) == {"A", "B", "C", "D"}


def test_a_block_on_a_fixed_guide_and_node_models_unchanged():
    sc = catalogue.get("slider_crank")
    m = symkin.Mechanism.from_dict(jf.slider_crank(sc.coordinates(), (0.0, 0.25), (1.0, 0.0)))
    lines = _lines(draw_mechanism(m))
    block = m.slider("P1").node
    assert np.allclose(lines["slider:P1"], [dict(m.nodes)[block]])
    guide = lines["guide:P1"]
    assert np.allclose(guide[:, 1], dict(m.nodes)[block][1])              # the dashed guide along x through it
    node_form = _lines(draw_mechanism(symkin.read_model(jf.MODELS / "rpr_3.toml")))
    assert not any(g.startswith(("leg:", "axis:", "guide:")) for g in node_form)


def test_traces_leave_out_the_added_nodes():
    from symkin.plots import plot_traces

    m = symkin.Mechanism.from_dict(jf.bennett(catalogue.get("bennett").coordinates()))
    path = symkin.trace(m, "joint:A", 0.0, 0.5, steps=10, branch_analysis=False)
    gids = {str(line.get_gid()) for line in plot_traces(path).lines}
    assert {"trace:B", "trace:C"} <= gids
    assert not any(g.startswith("trace:") and "." in g for g in gids)    # no trace:B.axis, trace:C.axis


def test_drawing_follows_the_joint_kind_screw_jack():
    """How a joint is drawn is its kind's (symkin.model.pairs.JointKind: ``block``, ``axes``): the
    screw jack's H nut is a block on the screw's axis (like its P), its R an axis along z."""
    from pathlib import Path

    from symkin.model.pairs import joint_kind

    m = symkin.read_model(Path(__file__).resolve().parents[1] / "constraints" / "models" / "screw_jack.toml")
    lines = _lines(draw_mechanism(m))
    x = dict(m.nodes)
    assert joint_kind("H").block and joint_kind("P").block and joint_kind("R").axes == ("axis",)
    assert np.allclose(lines["slider:H1"], [x[m.slider("H1").node]])
    seg = lines["axis:R1"]
    assert np.allclose(seg.mean(axis=0), x["R1"])
    assert np.linalg.norm(np.cross(seg[1] - seg[0], [0.0, 0.0, 1.0])) < 1e-9 * np.linalg.norm(seg[1] - seg[0])
    assert not any(g.startswith("axis:H1") for g in lines)               # H has no axes of its own listed
