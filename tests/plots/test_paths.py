"""Plots draw what the results say: curves at the path's points, events where they were located,
arrows equal to the motion vectors; matplotlib is imported only when a plot is drawn."""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import symkin  # noqa: E402
from symkin.errors import SymkinError  # noqa: E402
from symkin.paths.trace import trace  # noqa: E402
from symkin.plots import draw_mechanism, plot_indicators, plot_traces, save_path_figures  # noqa: E402
from symkin.plots.paths import abscissa  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def fourbar_path():
    return trace(symkin.catalogue.get("fourbar_appendix"), stop=360, unit="deg")


@pytest.fixture(scope="module")
def rrr_path():
    return trace(symkin.catalogue.get("rrr_3"), stop=360, unit="deg")


@pytest.fixture(scope="module")
def figure_of():
    """``path_figure(path)`` drawn once per path for this module (the tests only read the figures)."""
    from symkin.plots.paths import path_figure

    drawn = {}

    def get(path):
        if id(path) not in drawn:
            drawn[id(path)] = (path, path_figure(path))  # the path kept: its id stays its own
        return drawn[id(path)][1]

    return get


@pytest.fixture(scope="module")
def rssr_path():
    return trace(symkin.catalogue.get("rssr"), stop=360, unit="deg")


def by_gid(artists, gid):
    found = [a for a in artists if a.get_gid() == gid]
    assert len(found) == 1, f"{gid}: {len(found)} artists"
    return found[0]


def gids(artists, prefix=""):
    return sorted(a.get_gid() for a in artists if (a.get_gid() or "").startswith(prefix))


def dead_centre_inputs(mech) -> list[float]:
    """Crank angles (from the model's configuration, radians in (−π, π]) where crank and coupler
    align, by the law of cosines in triangle A-C-D: |AC| = coupler ± crank."""
    x = mech.coordinates()
    a_, b_, c_, d_ = (np.array(x[n]) for n in "ABCD")
    crank, coupler, rocker = np.linalg.norm(b_ - a_), np.linalg.norm(c_ - b_), np.linalg.norm(c_ - d_)
    ground = d_ - a_
    g, base = np.linalg.norm(ground), math.atan2(ground[1], ground[0])
    theta0 = math.atan2(*(b_ - a_)[::-1])
    out = []
    for ac, flip in ((coupler + crank, 0.0), (coupler - crank, math.pi)):
        phi = math.acos((ac * ac + g * g - rocker * rocker) / (2 * ac * g))
        for sgn in (1, -1):
            out.append(math.remainder(base + sgn * phi + flip - theta0, 2 * math.pi))
    return out


# ---------------------------------------------------------------------- import hygiene
def test_import_symkin_does_not_import_matplotlib():
    code = ("import sys, symkin, symkin.plots, symkin.plots.paths, symkin.plots.mechanism\n"
            "print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"


# ---------------------------------------------------------------------- indicators
def test_indicators_curves_follow_the_path_and_events_sit_at_the_dead_centres(fourbar_path):
    path = fourbar_path
    fig, ax = plt.subplots()
    assert plot_indicators(path, ax=ax) is ax
    assert gids(ax.lines, "indicator:") == ["indicator:DKP-input", "indicator:DKP-output", "indicator:im_indicator"]
    inputs_deg = np.degrees([p.input for p in path.points])
    for key in ("im_indicator", "DKP-input", "DKP-output"):
        line = by_gid(ax.lines, f"indicator:{key}")
        np.testing.assert_allclose(line.get_xdata(), inputs_deg, rtol=0, atol=1e-12)
        np.testing.assert_allclose(line.get_ydata(), [p.indicators[key] for p in path.points], rtol=0, atol=0)
    # the four-bar's input is monotone: the axis is the input, in degrees
    assert "rotation:crank" in ax.get_xlabel() and "deg" in ax.get_xlabel()
    markers = by_gid(ax.lines, "event:DKP-output")
    assert gids(ax.lines, "event:") == ["event:DKP-output"]
    xs = np.asarray(markers.get_xdata(), float)
    assert xs.size == 2 and np.all(np.asarray(markers.get_ydata()) == 0.0)
    np.testing.assert_allclose(xs, [math.degrees(e.input) for e in path.events if e.kind == "DKP-output"],
                               rtol=0, atol=1e-12)
    # independent truth: the law of cosines (closed-form dead centres), to 1e-9 rad
    closed = dead_centre_inputs(path.mechanism)
    for xe in np.radians(xs):
        assert min(abs(math.remainder(xe - c, 2 * math.pi)) for c in closed) < 1e-9
    # labels: numbered as in the text report and the JSON, input and absolute angle (4 decimals, degrees)
    texts = [t.get_text() for t in ax.texts]
    sing = path.singular_events()
    for k, e in enumerate(sing, 1):
        (label,) = [t.get_text() for t in ax.texts if t.get_gid() == f"event-label:{k}"]
        assert label.splitlines() == [f"{k}. DKP-output", f"{math.degrees(e.input):.4f}°",
                                      f"abs {math.degrees(e.absolute):.4f}°"]
    assert len(texts) == len(sing)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("IM indicator" in lab for lab in labels) and any("DKP-output event" in lab for lab in labels)


def test_indicators_in_radians_and_bifurcation_curve(fourbar_path):
    ax = plot_indicators(fourbar_path, unit="rad", bifurcation=True)
    assert "[rad]" in ax.get_xlabel()
    np.testing.assert_allclose(by_gid(ax.lines, "event:DKP-output").get_xdata(),
                               [e.input for e in fourbar_path.events if e.kind == "DKP-output"], atol=1e-15)
    assert "indicator:bifurcation" in gids(ax.lines)
    assert plot_indicators(fourbar_path, yscale="symlog").get_yscale() == "symlog"
    with pytest.raises(SymkinError):
        plot_indicators(fourbar_path, unit="grad")
    with pytest.raises(SymkinError):
        plot_indicators(fourbar_path, yscale="log")


def test_indicators_use_arclength_when_the_input_turns_back(rrr_path):
    path = rrr_path
    kinds = [e.kind for e in path.singular_events()]
    assert kinds.count("DKP-input") == 2  # the input turns back twice on this loop
    values, mode, label = abscissa(path)
    assert mode == "arclength" and "arclength" in label
    ax = plot_indicators(path)
    np.testing.assert_allclose(by_gid(ax.lines, "indicator:im_indicator").get_xdata(), [p.s for p in path.points])
    for kind in ("DKP-input", "DKP-output"):
        np.testing.assert_allclose(by_gid(ax.lines, f"event:{kind}").get_xdata(),
                                   [e.s for e in path.events if e.kind == kind])
    # forced: the input axis, folded at the turning points
    forced, mode, _ = abscissa(path, x="input")
    assert mode == "input" and np.any(np.diff(forced) > 0) and np.any(np.diff(forced) < 0)


# ---------------------------------------------------------------------- traces
def test_traces_are_the_node_paths_with_black_dots_at_events(fourbar_path):
    path = fourbar_path
    fig, ax = plt.subplots()
    assert plot_traces(path, ax=ax) is ax
    assert gids(ax.lines, "trace:") == ["trace:B", "trace:C"]
    coords = np.array([p.coordinates for p in path.points])
    for k, n in enumerate(path.node_names):
        if n in ("B", "C"):
            line = by_gid(ax.lines, f"trace:{n}")
            np.testing.assert_allclose(line.get_xdata(), coords[:, k, 0], atol=0)
            np.testing.assert_allclose(line.get_ydata(), coords[:, k, 1], atol=0)
    dots = by_gid(ax.lines, "events")
    assert dots.get_color() == "black" and len(dots.get_xdata()) == 2 * 2  # 2 events x 2 nodes
    expected = np.vstack([e.coordinates[[1, 2]] for e in path.singular_events()])
    np.testing.assert_allclose(np.column_stack([dots.get_xdata(), dots.get_ydata()]), expected, atol=0)
    # at a dead centre, A, B, C are collinear: the dots are where crank and coupler align
    for e in path.singular_events():
        a_, b_, c_ = e.coordinates[0], e.coordinates[1], e.coordinates[2]
        u, w = b_ - a_, c_ - b_
        assert abs(u[0] * w[1] - u[1] * w[0]) < 1e-9
    assert len(by_gid(ax.lines, "fixed").get_xdata()) == 2


def test_traces_of_chosen_nodes_and_unknown_node(fourbar_path):
    ax = plot_traces(fourbar_path, nodes=["C"], show_mechanism=False)
    assert gids(ax.lines, "trace:") == ["trace:C"]
    assert len(by_gid(ax.lines, "events").get_xdata()) == 2
    assert not gids(ax.lines, "start-link")
    with pytest.raises(SymkinError, match="unknown node"):
        plot_traces(fourbar_path, nodes=["Z"])


def test_traces_skip_the_held_legs_of_a_3dof_platform(rrr_path):
    ax = plot_traces(rrr_path)
    # crank1 drives, crank2 and crank3 are held: B2 and B3 do not move
    assert gids(ax.lines, "trace:") == ["trace:B1", "trace:C1", "trace:C2", "trace:C3"]


def test_spatial_traces_in_3d_or_projected(rssr_path):
    ax = plot_traces(rssr_path)
    assert ax.name == "3d"
    x, y, z = by_gid(ax.lines, "trace:C").get_data_3d()
    k = rssr_path.node_names.index("C")
    coords = np.array([p.coordinates for p in rssr_path.points])
    np.testing.assert_allclose(np.column_stack([x, y, z]), coords[:, k, :], atol=0)
    fig, flat = plt.subplots()
    plot_traces(rssr_path, ax=flat)
    line = by_gid(flat.lines, "trace:C")
    np.testing.assert_allclose(line.get_xdata(), coords[:, k, 0], atol=0)
    np.testing.assert_allclose(line.get_ydata(), coords[:, k, 1], atol=0)
    assert "projection" in flat.get_ylabel()


# ---------------------------------------------------------------------- mechanism drawing
def test_draw_flattened_fourbar_with_its_uncontrolled_motion():
    mech = symkin.catalogue.get("fourbar_flat")
    analysis = symkin.analyze(mech)
    assert analysis.types == ("IM",) and analysis.dof == 2
    (motion,) = analysis.uncontrolled_motions
    fig, ax = plt.subplots()
    assert draw_mechanism(mech, ax=ax, motion=motion, scale=0.5) is ax
    assert gids(ax.lines, "link:") == ["link:coupler", "link:crank", "link:rocker"]
    np.testing.assert_allclose(by_gid(ax.lines, "link:coupler").get_xdata(), [1.0, 3.0])
    assert len(by_gid(ax.lines, "fixed").get_xdata()) == 2
    assert len(by_gid(ax.lines, "nodes").get_xdata()) == 2
    assert sorted(t.get_text() for t in ax.texts) == ["A", "B", "C", "D"]
    q = by_gid(ax.collections, "motion:uncontrolled motion")
    # with the crank locked only C moves, perpendicular to the flattened line
    np.testing.assert_allclose(q.get_offsets(), [[3.0, 0.0]])
    assert q.U[0] == 0.0 and abs(q.V[0]) == pytest.approx(0.5 * 1.0)


def test_draw_motion_space_vectors_scaled_as_asked():
    mech = symkin.catalogue.get("fourbar_flat")
    ms = symkin.motion_space(mech)
    ax = draw_mechanism(mech, motion=ms, scale=2.0)
    assert gids(ax.collections, "motion:") == ["motion:v1", "motion:v2"]
    for k in range(ms.dof):
        q = by_gid(ax.collections, f"motion:v{k + 1}")
        vel = ms.V[:, k].reshape(4, 2)
        moving = np.linalg.norm(vel, axis=1) > 1e-9 * np.abs(vel).max()
        np.testing.assert_allclose(q.get_offsets(), np.array([c for _, c in mech.nodes])[moving])
        np.testing.assert_allclose(np.column_stack([q.U, q.V]), 2.0 * vel[moving], atol=1e-15)
    # labelled pairs name the legend entries
    ax = draw_mechanism(mech, motion=[("B up", {"B": [0.0, 1.0]}), ("C down", {"C": [0.0, -1.0]})], scale=1.0)
    assert gids(ax.collections, "motion:") == ["motion:B up", "motion:C down"]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["B up", "C down"]
    np.testing.assert_allclose(by_gid(ax.collections, "motion:C down").get_offsets(), [[3.0, 0.0]])
    # a single column by index
    ax = draw_mechanism(mech, motion=1)
    assert gids(ax.collections, "motion:") == ["motion:v2"]
    # default scale: the longest arrow is 30 % of the drawing's extent (4 model units here)
    q = by_gid(ax.collections, "motion:v2")
    assert float(np.hypot(q.U, q.V).max()) == pytest.approx(0.3 * 4.0)


def test_draw_bodies_sliders_and_dict_motion():
    rrr = symkin.catalogue.get("rrr_3")
    ax = draw_mechanism(rrr, motion={"C1": [1.0, 0.0], "C2": [0.0, 1.0]})
    platform = by_gid(ax.patches, "link:platform")
    xyz = rrr.coordinates()
    verts = platform.get_xy()[:3]
    assert sorted(map(tuple, np.round(verts, 12))) == sorted(tuple(np.round(xyz[n], 12)) for n in ("C1", "C2", "C3"))
    q = by_gid(ax.collections, "motion:motion")
    np.testing.assert_allclose(q.get_offsets(), [xyz["C1"], xyz["C2"]])
    slider = symkin.catalogue.get("slider_crank")
    ax = draw_mechanism(slider)
    line = by_gid(ax.lines, "slider:piston")
    np.testing.assert_allclose(line.get_ydata(), [0.25, 0.25])
    np.testing.assert_allclose(by_gid(ax.lines, "sliders").get_xdata(), [3.5])


def test_draw_spatial_platform_at_increased_mobility():
    from tests.conftest import EXAMPLES

    mech = symkin.read_model(EXAMPLES / "fig13_3rsr_c.toml")
    ms = symkin.motion_space(mech)
    assert ms.dof == 4  # the paper's Fig. 13: four motion-space vectors
    ax = draw_mechanism(mech, motion=ms)
    assert ax.name == "3d"
    assert gids(ax.collections, "motion:") == ["motion:v1", "motion:v2", "motion:v3", "motion:v4"]
    assert "link:platform" in gids(ax.collections, "link:")


def test_draw_rejects_bad_motions():
    mech = symkin.catalogue.get("fourbar_appendix")
    with pytest.raises(SymkinError, match="unknown node"):
        draw_mechanism(mech, motion={"Q": [0.0, 1.0]})
    with pytest.raises(SymkinError, match="motion space has 1"):
        draw_mechanism(mech, motion=3)
    with pytest.raises(SymkinError, match="motion must be"):
        draw_mechanism(mech, motion="up")


# ---------------------------------------------------------------------- the PNG of `symkin path --plot`
def test_save_path_figures_writes_a_png_without_pyplot(fourbar_path, rssr_path, tmp_path):
    before = plt.get_fignums()
    for path, name in ((fourbar_path, "fourbar.png"), (rssr_path, "rssr")):
        written = save_path_figures(path, tmp_path / name)
        data = written.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000
    assert written.name == "rssr"
    assert plt.get_fignums() == before
    with pytest.raises(SymkinError, match="cannot write"):
        save_path_figures(fourbar_path, tmp_path / "missing" / "x.png")


# ---------------------------------------------------------------------- numbered events, small multiples
@pytest.fixture(scope="module")
def peaucellier_path():
    return trace(symkin.catalogue.get("peaucellier"), stop=360, unit="deg")


def test_event_panels_draw_the_mechanism_at_each_event_with_the_same_limits(fourbar_path, peaucellier_path):
    from symkin.plots.paths import event_label, plot_event_configurations

    for path in (fourbar_path, peaucellier_path):
        sing = path.singular_events()
        axes = plot_event_configurations(path)
        assert len(axes) == len(sing) and len([e for e in sing if e.kind != "LIM"]) == 2  # + the arms' LIM events
        idx = {n: k for k, n in enumerate(path.node_names)}
        for k, (ax, e) in enumerate(zip(axes, sing), 1):
            title = ax.get_title().splitlines()
            assert title == [event_label(path, k, e), f"{', '.join(e.analysis.types)}; L = {e.analysis.dof}"]
            assert title[0].startswith(f"{k}. {e.kind} at {math.degrees(e.input):.4f}°")
            assert f"(absolute {math.degrees(e.absolute):.4f}°)" in title[0]
            # the links are drawn at the event's configuration, not at the start
            for name, nodes in path.mechanism.links:
                if len(nodes) == 2:
                    line = by_gid(ax.lines, f"link:{name}")
                    np.testing.assert_allclose(line.get_xdata(), [e.coordinates[idx[n]][0] for n in nodes], atol=0)
                    np.testing.assert_allclose(line.get_ydata(), [e.coordinates[idx[n]][1] for n in nodes], atol=0)
            assert gids(ax.lines, "context-trace:")
        # small multiples: the same limits on every panel, holding the whole path
        assert len({(ax.get_xlim(), ax.get_ylim()) for ax in axes}) == 1
        xyz = np.array([p.coordinates for p in path.points])
        (x0, x1), (y0, y1) = axes[0].get_xlim(), axes[0].get_ylim()
        assert x0 < xyz[:, :, 0].min() and xyz[:, :, 0].max() < x1
        assert y0 < xyz[:, :, 1].min() and xyz[:, :, 1].max() < y1
    # the Peaucellier–Lipkin flattened poses: A = B, the rhombus on the line O-C-P
    first_im = next(k for k, e in enumerate(peaucellier_path.singular_events()) if e.kind == "IM")
    t0 = plot_event_configurations(peaucellier_path)[first_im].get_title()
    assert t0.startswith(f"{first_im + 1}. IM at ") and t0.endswith("IM, DKP-input, LIM; L = 3")
    with pytest.raises(SymkinError, match="6 singular event"):
        fig, ax = plt.subplots()
        plot_event_configurations(peaucellier_path, axes=[ax])


def test_traces_number_their_events(fourbar_path):
    ax = plot_traces(fourbar_path)
    assert sorted(t.get_text() for t in ax.texts) == ["1. DKP-output", "2. DKP-output"]


def test_path_figure_has_one_panel_per_event_and_says_when_the_axis_is_arclength(rrr_path, fourbar_path, figure_of):
    from symkin.plots.paths import path_figure

    fig = figure_of(rrr_path)
    top, events = fig.subfigs
    assert len(top.axes) == 2 and len(events.axes) == len(rrr_path.singular_events()) == 4
    assert [ax.get_title().split(" ")[0] for ax in events.axes] == ["1.", "2.", "3.", "4."]
    indicators = top.axes[0]
    assert "turns back" in indicators.get_xlabel() and "arclength" in indicators.get_xlabel()
    labels = sorted(t.get_gid() for t in indicators.texts)
    assert labels == [f"event-label:{k}" for k in (1, 2, 3, 4)]
    # the four-bar's input is monotone: the axis is the input and says nothing of arclength
    top, events = figure_of(fourbar_path).subfigs
    assert "arclength" not in top.axes[0].get_xlabel() and len(events.axes) == 2
    # no singular event: no panels, one figure
    quiet = trace(symkin.catalogue.get("fourbar_appendix"), stop=30, unit="deg")
    assert not quiet.singular_events()
    fig = path_figure(quiet)
    assert not fig.subfigs and len(fig.axes) == 3  # indicators, input–output, traces


# ---------------------------------------------------------------------- labels that do not overlap, input–output
def _label_boxes(fig, ax):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    return [(t.get_gid(), t.get_window_extent(renderer)) for t in ax.texts
            if (t.get_gid() or "").startswith("event-label:")]


def _assert_no_two_intersect(boxes):
    for i, (ga, a) in enumerate(boxes):
        for gb, b in boxes[i + 1:]:
            assert not a.overlaps(b), f"{ga} and {gb} overlap: {a.bounds} / {b.bounds}"


@pytest.mark.parametrize("name", ["rrr_3", "peaucellier"])
def test_event_labels_do_not_overlap_in_the_rendered_figure(name, rrr_path, peaucellier_path, figure_of):
    path = {"rrr_3": rrr_path, "peaucellier": peaucellier_path}[name]
    fig = figure_of(path)
    indicators = fig.subfigs[0].axes[0]
    boxes = _label_boxes(fig, indicators)
    assert len(boxes) == len(path.singular_events())
    _assert_no_two_intersect(boxes)
    # every label is inside the indicator axes (none runs into the title)
    frame = indicators.get_window_extent()
    assert all(frame.y0 <= b.y0 and b.y1 <= frame.y1 for _, b in boxes)
    # standalone, on a narrow axes where the events are close together (peaucellier: 1 and 3 coincide)
    fig, ax = plt.subplots(figsize=(3.5, 2.8))
    plot_indicators(path, ax=ax)
    _assert_no_two_intersect(_label_boxes(fig, ax))


def test_input_output_curve_is_the_output_against_the_input_with_the_events_on_it(fourbar_path, figure_of):
    from symkin.plots.paths import plot_input_output

    ax = plot_input_output(fourbar_path)
    line = by_gid(ax.lines, "input-output")
    np.testing.assert_allclose(line.get_xdata(), np.degrees([p.input for p in fourbar_path.points]), atol=1e-12)
    rel = np.array([fourbar_path.outputs(p, "deg")["rotation:rocker"]["relative"] for p in fourbar_path.points])
    y = np.asarray(line.get_ydata())
    np.testing.assert_allclose(np.remainder(y - rel + 180, 360) - 180, 0, atol=1e-9)  # same angles, unwrapped
    assert np.abs(np.diff(y)).max() < 90  # not cut at ±180°
    ev = by_gid(ax.lines, "event:DKP-output")
    sing = fourbar_path.singular_events()
    np.testing.assert_allclose(ev.get_xdata(), [math.degrees(e.input) for e in sing], atol=1e-12)
    # a DKP-output event is a turning point of the output: the marker sits at an extremum of the curve
    for xe, ye in zip(ev.get_xdata(), ev.get_ydata()):
        near = np.abs(line.get_xdata() - xe) < 15
        assert ye >= y[near].max() - 1e-6 or ye <= y[near].min() + 1e-6
    assert "[deg]" in ax.get_xlabel() and "rotation:rocker" in ax.get_ylabel()
    assert len(figure_of(fourbar_path).subfigs[0].axes) == 3  # indicators, input–output, traces
    with pytest.raises(SymkinError, match="no scalar output"):
        plot_input_output(trace(symkin.catalogue.get("rrr_3"), stop=30, unit="deg"))


@pytest.mark.parametrize("model", ["rpr_3", "gough_stewart"])
def test_prismatic_legs_are_drawn_whole_from_base_joint_to_platform_joint(model):
    from tests.conftest import ROOT

    mech = symkin.read_model(ROOT / "examples" / f"{model}.toml")
    ax = draw_mechanism(mech)
    assert ax.name == ("3d" if mech.dim == 3 else "rectilinear")  # spatial models in 3-D
    xyz = mech.coordinates()
    legs = [s for s in mech.sliders if s.kind == "moving_line"]
    assert legs
    for s in legs:
        line = by_gid(ax.lines, f"link:{s.link}")
        data = line.get_data_3d() if mech.dim == 3 else line.get_data()
        ends = sorted(map(tuple, np.round(np.column_stack(data), 12)))
        base = s.line[0]
        assert ends == sorted([tuple(np.round(xyz[base], 12)), tuple(np.round(xyz[s.node], 12))])
    # the node that only carries the line is not drawn as a joint nor named
    helpers = {s.line[1] for s in legs}
    assert not helpers & {t.get_text().strip() for t in ax.texts}


def test_type_2_panels_draw_the_legs_lines_meeting_in_one_point(rrr_path):
    from symkin.plots.paths import plot_event_configurations

    axes = plot_event_configurations(rrr_path)
    for ax, e in zip(axes, rrr_path.singular_events()):
        lines = [line for line in ax.lines if (line.get_gid() or "").startswith("leg-line:")]
        if e.kind != "DKP-input":
            assert not lines and not gids(ax.lines, "common-point")
            continue
        assert gids(lines) == ["leg-line:distal1", "leg-line:distal2", "leg-line:distal3"]
        (point,) = [np.array([line.get_xdata()[0], line.get_ydata()[0]]) for line in ax.lines
                    if line.get_gid() == "common-point"]
        # independent check: the distal links' lines B_k-C_k (at the event) all pass through the point
        idx = {n: k for k, n in enumerate(rrr_path.node_names)}
        for k in (1, 2, 3):
            b, c = e.coordinates[idx[f"B{k}"]], e.coordinates[idx[f"C{k}"]]
            d = (c - b) / np.linalg.norm(c - b)
            w = point - b
            assert abs(w[0] * d[1] - w[1] * d[0]) < 1e-3 * rrr_path.mechanism.length_scale


# ---------------------------------------------------------------------- print size, trace labels
def test_path_figures_print_at_9_points_or_more_in_one_column(fourbar_path, rrr_path, peaucellier_path, rssr_path,
                                                              figure_of):
    from tests.plots.print_size import COLUMN, assert_printable

    for path in (fourbar_path, rrr_path, peaucellier_path, rssr_path):
        fig = figure_of(path)
        assert fig.get_size_inches()[0] == pytest.approx(COLUMN)
        assert_printable(fig)


@pytest.mark.parametrize("name", ["rrr_3", "peaucellier", "rssr"])
def test_trace_labels_do_not_overlap_in_the_rendered_figure(name, rrr_path, peaucellier_path, rssr_path, figure_of):
    """The node-traces panel numbers every event at its dot; close events (peaucellier: 1 and 3 at
    one configuration, the 3-RRR's 2 and 4 side by side) still give labels that do not overlap; on a
    spatial mechanism's 3-D traces (the RSSR) the labels sit at the dots' projections."""
    path = {"rrr_3": rrr_path, "peaucellier": peaucellier_path, "rssr": rssr_path}[name]
    fig = figure_of(path)
    traces = fig.subfigs[0].axes[-1]
    assert traces.get_title() == "Node traces"
    boxes = _label_boxes(fig, traces)
    assert sorted(g for g, _ in boxes) == sorted(f"event-label:{k}" for k in range(1, len(path.singular_events()) + 1))
    _assert_no_two_intersect(boxes)
    frame = traces.get_window_extent()
    assert all(frame.x0 <= b.x0 and b.x1 <= frame.x1 and frame.y0 <= b.y0 and b.y1 <= frame.y1 for _, b in boxes)
    # each label is next to its dot: within a few label heights of the node it numbers
    renderer = fig.canvas.get_renderer()
    for t in traces.texts:
        box = t.get_window_extent(renderer)
        dot = traces.transData.transform(t.xy)
        gap = max(box.x0 - dot[0], dot[0] - box.x1, box.y0 - dot[1], dot[1] - box.y1, 0.0)
        assert gap < 6 * box.height
    # standalone, full labels on a small axes (a spatial path: projected on x-y, and in 3-D)
    fig, ax = plt.subplots(figsize=(3.5, 3.0))
    plot_traces(path, ax=ax)
    _assert_no_two_intersect(_label_boxes(fig, ax))
    if path.mechanism.dim == 3:
        ax = plot_traces(path)
        assert ax.name == "3d" and len(ax.texts) == len(path.singular_events())
        _assert_no_two_intersect(_label_boxes(ax.figure, ax))


def test_place_point_labels_separates_labels_of_one_point():
    """Five labels at one point: five places, no two boxes meeting."""
    from symkin.plots.paths import place_point_labels

    fig, ax = plt.subplots(figsize=(3.5, 3.0))
    ax.plot([0, 1], [0, 1])
    for k in range(1, 6):
        ax.annotate(f"{k}. DKP-output", (0.5, 0.5), xytext=(4, 4), textcoords="offset points", fontsize=9,
                    gid=f"event-label:{k}")
    before = _label_boxes(fig, ax)
    assert before[0][1].overlaps(before[1][1])  # drawn where they were asked: on one another
    place_point_labels(ax)
    _assert_no_two_intersect(_label_boxes(fig, ax))
