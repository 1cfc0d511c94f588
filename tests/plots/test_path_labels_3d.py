"""3-D node traces of ``symkin path --plot``: each event's number sits next to its dot as drawn.

The dot's position is read from the rendered figure (the ``events`` line's 2-D data after a draw
are its points projected in the view as drawn, mapped to pixels by the axes' transform), not
from the label's own anchor; the label's box (its rendered window extent) must lie within one
label height of it, and no two labels' boxes may meet.
"""
from __future__ import annotations

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import symkin  # noqa: E402
from symkin.paths.trace import trace  # noqa: E402
from symkin.plots import plot_traces  # noqa: E402
from symkin.plots.paths import COLUMN_WIDTH, path_figure  # noqa: E402


@pytest.fixture(scope="module", params=["rssr", "3-RPS"])
def spatial_path(request):
    if request.param == "rssr":
        return trace(symkin.catalogue.get(request.param), stop=360, unit="deg")
    # the catalogue's other spatial 1-DOF loop, the Bennett, has no event on its turn: a 3-RPS with
    # two slides held, slide 1 driven round its loop (tests/paths/test_joint_form_paths.py)
    from tests.model import joint_forms as jf

    return trace(symkin.Mechanism.from_dict(jf.rps_3_node(jf.rps_3_nodes(2.0, 0.2, -0.1))), "slide:s1", 0.0, -2.5)


def _gap(box, dot) -> float:
    """Distance (pixels, along x or y) from the point ``dot`` to the box; 0 inside it."""
    return max(box.x0 - dot[0], dot[0] - box.x1, box.y0 - dot[1], dot[1] - box.y1, 0.0)


def _check_labels(fig, ax, path):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    events = path.singular_events()
    dots_line = [line for line in ax.lines if line.get_gid() == "events"]
    assert ax.name == "3d" and len(dots_line) == 1
    # after a draw a 3-D line holds its projected points: the dots as rendered, in pixels
    dots = ax.transData.transform(np.asarray(dots_line[0].get_xydata(), float))
    per_event = len(dots) // len(events)
    assert per_event * len(events) == len(dots)
    labels = sorted((t for t in ax.texts if (t.get_gid() or "").startswith("event-label:")),
                    key=lambda t: int(t.get_gid().split(":")[1]))
    assert [int(t.get_gid().split(":")[1]) for t in labels] == list(range(1, len(events) + 1))
    boxes = []
    for t in labels:
        k = int(t.get_gid().split(":")[1]) - 1
        box = t.get_window_extent(renderer)
        dot = dots[k * per_event]  # the event's dot at the first traced node (the one numbered)
        assert _gap(box, dot) <= box.height, (t.get_text(), _gap(box, dot) / box.height)
        boxes.append(box)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a.bounds, b.bounds)
    return boxes


def test_3d_trace_labels_sit_at_their_projected_dots_in_the_path_figure(spatial_path):
    fig = path_figure(spatial_path)
    ax = fig.subfigs[0].axes[-1]
    assert ax.get_title() == "Node traces"
    _check_labels(fig, ax, spatial_path)
    # the 3-D panel is wider than it was (1.9 in of the 3.5 in column)
    width = ax.get_window_extent(fig.canvas.get_renderer()).width / fig.dpi
    assert width >= 0.57 * COLUMN_WIDTH, width


def test_3d_trace_labels_follow_a_new_view(spatial_path):
    """Standalone 3-D traces (numbered as in the path figure), then the view turned: placed again, the
    labels are at the new projections."""
    from symkin.plots.paths import place_point_labels

    ax = plot_traces(spatial_path, numbers_only=True)
    _check_labels(ax.figure, ax, spatial_path)
    ax.view_init(elev=10, azim=120)
    place_point_labels(ax)
    _check_labels(ax.figure, ax, spatial_path)
    plt.close(ax.figure)
