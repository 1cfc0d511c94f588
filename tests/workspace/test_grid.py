"""Continuation of working modes over a map's grid, checked against the five-bar's closed forms.

Five-bar (catalogue ``five_bar``): pivots A1 = (-1, 0), A2 = (1, 0), cranks l1 = 1, distal
links l2 = 2.  P is reachable by a working mode iff 1 = |l1 - l2| <= |P - A_i| <= l1 + l2 = 3
for both legs (each leg's elbow exists on either side there); type-1 (DKP-output) loci are
where a leg is folded or stretched, ``cross(B_i - A_i, P - B_i) = 0``; type-2 (DKP-input)
loci where B1, P, B2 are aligned, ``cross(P - B1, P - B2) = 0``.
"""
from __future__ import annotations

import numpy as np
import pytest

from symkin.errors import SymkinError
from symkin.model.catalogue import get
from symkin.workspace.grid import continue_mode, make_axes, parse_axis, type_names
from symkin.workspace.system import map_system

A1, A2 = np.array([-1.0, 0.0]), np.array([1.0, 0.0])


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _reachable(x, y):
    r1, r2 = np.hypot(x + 1, y), np.hypot(x - 1, y)
    return (r1 >= 1) & (r1 <= 3) & (r2 >= 1) & (r2 <= 3)


def _distance_to_boundary(x, y):
    r1, r2 = np.hypot(x + 1, y), np.hypot(x - 1, y)
    return np.min([abs(r1 - 1), abs(r1 - 3), abs(r2 - 1), abs(r2 - 3)], axis=0)


@pytest.mark.parametrize("n", [41, 81])
def test_assembled_region_is_the_closed_form(n):
    s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    xs, ys = np.linspace(-3.5, 3.5, n), np.linspace(0.2, 4.4, n)
    g = continue_mode(s, xs, ys, s.q0)
    x, y = np.meshgrid(xs, ys)
    truth = _reachable(x, y)
    assert 0.1 < truth.mean() < 0.5  # the box is partly outside the workspace
    # never assembled where no configuration exists
    assert not np.any(g.assembled & ~truth)
    # a reachable point missed lies within one cell of the boundary (a fold or a thin sliver)
    cell = max(xs[1] - xs[0], ys[1] - ys[0])
    missed = truth & ~g.assembled
    assert np.all(_distance_to_boundary(x[missed], y[missed]) < cell)
    assert missed.sum() <= 0.03 * truth.sum()
    # indicators exactly where assembled
    assert np.all(np.isfinite(g.dkp_input[g.assembled])) and np.all(np.isnan(g.dkp_input[~g.assembled]))
    assert not g.rejected.any() and g.branch_changes == ()


@pytest.mark.slow
def test_joint_space_dkp_sign_changes_are_the_closed_form_loci():
    m = get("five_bar")
    s = map_system(m, "rotation:crank1", "rotation:crank2", unit="rad")
    n = 61
    xs, ys = np.linspace(0.5, 3.6, n), np.linspace(-0.5, 2.5, n)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    assert g.fraction > 0.99
    x = np.full((n, n, 5, 2), np.nan)
    ok = g.assembled
    x[ok] = np.array([s.evaluators.coordinates(q) for q in g.q[ok]])
    b1, b2, p = x[..., 2, :], x[..., 3, :], x[..., 4, :]
    type1 = _cross(b1 - A1, p - b1) * _cross(b2 - A2, p - b2)
    type2 = _cross(p - b1, p - b2)
    for values, truth in ((g.dkp_output, type1), (g.dkp_input, type2)):
        for axis in (0, 1):
            both = np.isfinite(np.diff(values, axis=axis)) & np.isfinite(np.diff(truth, axis=axis))
            ours = (np.diff(np.sign(values), axis=axis) != 0) & both
            theirs = (np.diff(np.sign(truth), axis=axis) != 0) & both
            assert np.array_equal(ours, theirs)
    assert (np.diff(np.sign(g.dkp_output), axis=1) != 0).sum() > 50  # the type-1 loci cross this box
    # bracket points of the sign changes keep their configurations for refinement
    j, i = np.argwhere((np.diff(np.sign(g.dkp_output), axis=1) != 0))[0]
    g2 = continue_mode(s, xs, ys, s.q0)
    assert g2.q is None and g2.config(j, i) is not None
    assert np.allclose(g2.config(j, i), g.q[j, i], atol=1e-12)
    assert np.array_equal(g2.assembled, g.assembled) and np.allclose(g2.dkp_output, g.dkp_output, equal_nan=True)


def test_workspace_dkp_input_sign_changes_are_the_aligned_distal_links():
    s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    n = 61
    xs, ys = np.linspace(-3.5, 3.5, n), np.linspace(0.2, 4.4, n)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    x = np.full((n, n, 5, 2), np.nan)
    x[g.assembled] = np.array([s.evaluators.coordinates(q) for q in g.q[g.assembled]])
    type2 = _cross(x[..., 4, :] - x[..., 2, :], x[..., 4, :] - x[..., 3, :])
    assert (np.diff(np.sign(g.dkp_input), axis=1) != 0).sum() > 10  # the type-2 loci cross this box
    for axis in (0, 1):
        both = np.isfinite(np.diff(g.dkp_input, axis=axis)) & np.isfinite(np.diff(type2, axis=axis))
        assert np.array_equal((np.diff(np.sign(g.dkp_input), axis=axis) != 0) & both,
                              (np.diff(np.sign(type2), axis=axis) != 0) & both)


def test_nothing_assembles_far_away():
    s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    g = continue_mode(s, np.linspace(10, 12, 5), np.linspace(10, 12, 5), s.q0)
    assert not g.assembled.any() and g.note


def test_seed_outside_the_box_marches_in():
    s = map_system(get("five_bar"), "velocity:P.x", "velocity:P.y")
    # the model's P = (0, 2) is outside this box; the mode reaches it by continuation
    xs, ys = np.linspace(0.1, 0.4, 7), np.linspace(1.2, 1.6, 9)
    assert _reachable(*np.meshgrid(xs, ys)).all()
    g = continue_mode(s, xs, ys, s.q0)
    assert g.assembled.all()
    # the same configurations as when the mode is continued over a box that holds the seed
    h = continue_mode(s, np.linspace(-0.2, 0.4, 13), np.linspace(1.2, 2.0, 17), s.q0)
    for name in ("dkp_output", "dkp_input", "im_indicator"):
        assert np.allclose(getattr(g, name), getattr(h, name)[0:9, 6:13], rtol=1e-9, atol=1e-12)


def test_axis_parsing_errors():
    assert parse_axis("rotation:crank1=-30:120") == ("rotation:crank1", -30.0, 120.0)
    with pytest.raises(SymkinError, match="LO must be less than HI"):
        parse_axis("velocity:P.x=3:1", "--x")
    with pytest.raises(SymkinError, match="--y .*LABEL=LO:HI"):
        parse_axis("velocity:P.y", "--y")
    with pytest.raises(SymkinError, match="numbers"):
        parse_axis("velocity:P.y=a:b")
    with pytest.raises(SymkinError, match=">= 2"):
        make_axes("velocity:P.x=0:1", "velocity:P.y=0:1", 1)
    assert type_names(5) == ("IM", "DKP-output")


@pytest.mark.parametrize("n", [15, 21])
def test_no_silent_jump_between_assembly_modes(n):
    """A coarse joint-space grid over nearly a full turn of both cranks.

    The five-bar (l1 = 1, l2 = 2, |A1A2| = 2) assembles at every pair of crank angles; its two
    assembly modes are the sides of the line B1B2 on which P lies, and a continuous path keeps
    the side (it changes only where B1, P, B2 align, at the single point where the cranks point
    outward).  Every grid point found on the other side must be announced: next to a reported
    branch change or a rejected point.
    """
    s = map_system(get("five_bar"), "rotation:crank1", "rotation:crank2", unit="rad")
    c1, c2 = s.axis_values(s.q0[None])[0]
    xs, ys = np.linspace(c1 - 3.1, c1 + 3.1, n), np.linspace(c2 - 3.1, c2 + 3.1, n)
    g = continue_mode(s, xs, ys, s.q0, keep_configurations=True)
    assert g.fraction > 0.97
    x = np.full((n, n, 5, 2), np.nan)
    x[g.assembled] = np.array([s.evaluators.coordinates(q) for q in g.q[g.assembled]])
    x0 = s.evaluators.coordinates(s.q0)
    side = np.sign(_cross(x[..., 3, :] - x[..., 2, :], x[..., 4, :] - x[..., 2, :]))
    seed_side = np.sign(_cross(x0[3] - x0[2], x0[4] - x0[2]))
    marks = {tuple(p) for pair in g.branch_changes for p in pair} | {tuple(p) for p in np.argwhere(g.rejected)}
    for j, i in np.argwhere(side == -seed_side):
        assert any(abs(j - a) + abs(i - b) <= 1 for a, b in marks), (j, i)
