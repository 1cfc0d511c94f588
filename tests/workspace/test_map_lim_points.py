"""LIM points of a map (F = 2) against elementary geometry (issue 15 §2, :mod:`symkin.workspace.lim_points`).

The mechanism (``models/fivebar_rocker.toml``): a 2-DOF five-bar, pivots ``A1 = (−1, 0)``,
``A2 = (1, 0)``, cranks ``|A_i B_i| = 1`` at angles ``θ1``, ``θ2``, distal links ``|B_i P| = 2``;
the left distal link is ternary (``B1``, ``P``, ``C``) and a coupler ``C–D`` drives a rocker
``D0–D`` about the fixed pivot ``D0 = (−2, 3)``.  In the file's pose ``θ1 = θ2 = 90°``:
``B1 = (−1, 1)``, ``B2 = (1, 1)``, ``P = (0, 1 + √3)`` (``|B_i P| = 2``), ``C = (−1, 2)``,
``D = (−1, 3)``.

Derivation of the LIM point.  For any motion (rates ``ω1``, ``ω2`` of the cranks, ``ω_d`` of
the distal link): ``v_B1 = ω1 × (B1 − A1) = ω1 × (0, 1) = (−ω1, 0)`` and
``v_C = v_B1 + ω_d × (C − B1) = (−ω1 − ω_d, 0)``: ``C`` lies on the line ``A1 B1`` (``x = −1``),
so ``v_C`` is horizontal whatever the motion.  The rocker ``D0 D`` is horizontal, so
``v_D = (0, w)``; the coupler ``C D`` is vertical, so its length is kept when
``(D − C)·(v_D − v_C) = w − v_C,y = 0``: ``w = 0``.  The rocker cannot turn for any motion of
the two-dimensional motion space (LIM, paper §III-B.3), while the five-bar itself is regular
there (``A1 B1 P`` and ``B1 P B2`` are not collinear).  The two conditions "C on the line
``A1 B1``" and "D on it" fix both ``θ1`` and ``θ2``: the point ``θ1 = θ2 = 90°`` (``π/2``) is
an isolated LIM point of the joint-space map, and ``P = (0, 1 + √3)`` of the workspace map.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.kinds import Kind
from symkin.model.catalogue import get

MODEL = Path(__file__).resolve().parent / "models" / "fivebar_rocker.toml"


@pytest.fixture(scope="module")
def mech():
    return symkin.read_model(MODEL)


def lim_points(wmap):
    return [p for p in wmap.points if p.kind == Kind.LIM]


def test_the_core_says_lim_at_the_hand_derived_pose(mech):
    res = symkin.analyze(mech)
    assert res.dof == 2
    assert res.types == (Kind.LIM,)
    assert res.locked_links == ("rocker",)


@pytest.mark.parametrize("n", [21, 16])  # 90° on a grid node, and between nodes
def test_joint_space_map_reports_the_lim_point(mech, n):
    wmap = symkin.workspace_map(mech, x="rotation:crank1=70:110", y="rotation:crank2=70:110", n=n)
    (p,) = lim_points(wmap)
    assert np.max(np.abs(np.asarray(p.at) - 90.0)) <= 1e-8
    assert p.types == ("LIM",) and p.locked_links == ("rocker",)
    assert wmap.counts()["0"][Kind.LIM] == 1
    d = wmap.to_dict()
    (pj,) = [q for q in d["points"] if q["kind"] == "LIM"]
    assert pj["types"] == ["LIM"] and pj["locked_links"] == ["rocker"]
    assert json.loads(json.dumps(d))["counts"]["0"]["LIM"] == 1


def test_radian_map_finds_it_in_a_sloping_valley_too(mech):
    """On this coarse grid the indicator's zero at (π/2, π/2) lies in a valley whose floor slopes
    through it (no minimum among eight neighbours): the minima along grid lines still reach it.
    The box also holds a second LIM configuration, on a DKP-output curve (the core's types)."""
    wmap = symkin.workspace_map(mech, x="rotation:crank1=1.2:1.9", y="rotation:crank2=1.3:2", n=15, unit="rad")
    found = lim_points(wmap)
    near = [p for p in found if np.max(np.abs(np.asarray(p.at) - math.pi / 2)) <= 1e-8]
    assert len(near) == 1 and near[0].types == ("LIM",) and near[0].locked_links == ("rocker",)
    for p in found:  # every reported LIM point is the core's LIM with the rocker locked
        assert Kind.LIM in p.types and p.locked_links == ("rocker",)


def test_workspace_map_reports_the_lim_point(mech):
    wmap = symkin.workspace_map(mech, x="velocity:P.x=-0.5:0.6", y="velocity:P.y=2.2:3.2", n=17)
    (p,) = lim_points(wmap)
    assert np.max(np.abs(np.asarray(p.at) - (0.0, 1.0 + math.sqrt(3.0)))) <= 1e-8
    assert p.types == ("LIM",) and p.locked_links == ("rocker",)


def test_saved_map_keeps_locked_links(mech, tmp_path):
    wmap = symkin.workspace_map(mech, x="rotation:crank1=70:110", y="rotation:crank2=70:110", n=11)
    back = symkin.load_map(wmap.save(tmp_path / "m.npz"))
    assert [(p.kind, p.locked_links) for p in back.points if p.kind == Kind.LIM] == [("LIM", ("rocker",))]


def test_map_plot_draws_the_lim_point(mech, tmp_path):
    from symkin.plots.maps import map_figure

    wmap = symkin.workspace_map(mech, x="rotation:crank1=70:110", y="rotation:crank2=70:110", n=11)
    fig = map_figure(wmap, mech)
    lines = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == "point:LIM:0"]
    assert lines and all(ln.get_marker() == "v" for ln in lines)


def test_catalogue_five_bar_over_p_has_no_lim_point():
    """Its pivoted links are the cranks, the inputs: they turn for every motion, nowhere locked."""
    wmap = symkin.workspace_map(get("five_bar"), x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=41)
    assert lim_points(wmap) == []
    assert Kind.LIM not in wmap.counts()["0"]


def test_lim_indicator_is_zero_for_the_locked_link_only(mech):
    """The grid's per-link indicator (norm of the link's free-node rows of an orthonormal motion basis)
    vanishes for the rocker at the LIM pose and not for the cranks, the inputs."""
    from symkin.workspace.lim_points import LimIndicator

    ev = symkin.evaluators(mech)
    ind = LimIndicator(ev)
    names = [link.name for link in ind.links]
    assert names == ["crank1", "crank2", "rocker"]  # the moving links with one fixed pivot
    v = ind.many(ev.q0[None])[0]
    assert v[names.index("rocker")] <= 1e-12
    assert min(v[names.index("crank1")], v[names.index("crank2")]) > 0.1
