"""``symkin.trace(..., tol=)``, ``follow_branch(..., tol=)`` and ``symkin path --tol``: one tolerance for events."""
from __future__ import annotations

import json

import pytest

from symkin.cli import main
from symkin.model.catalogue import get
from symkin.paths.system import make_curve
from symkin.paths.trace import event_types, trace
from symkin.tolerances import Tolerances
from tests.conftest import EXAMPLES


def test_event_thresholds_come_from_the_tolerance():
    curve = make_curve(get("fourbar_appendix"))
    for tol in (Tolerances(), Tolerances.of(1e-6), Tolerances(rank=1e-8, event=100.0)):
        tests = {t.name: t for t in event_types(curve, curve.y0(), tol)}
        assert tests["IM"].threshold == tol.event * tol.rank
        assert tests["DKP-output"].signed and tests["DKP-input"].signed


@pytest.mark.parametrize("tol", [1e-6, Tolerances(rank=1e-5)])
def test_events_are_classified_with_the_tolerance_of_the_trace(tol):
    path = trace(get("fourbar_appendix"), stop=360, unit="deg", tol=tol)
    rank = Tolerances.of(tol).rank
    events = path.singular_events()
    assert [e.kind for e in events] == ["DKP-output", "DKP-output"]
    assert all(e.analysis.tolerance == rank and e.confirmed for e in events)


def test_a_bad_tolerance_is_refused():
    with pytest.raises(TypeError):
        trace(get("fourbar_appendix"), stop=10, unit="deg", tol="tight")
    with pytest.raises(ValueError):
        trace(get("fourbar_appendix"), stop=10, unit="deg", tol=2.0)


def test_path_command_passes_tol(capsys):
    code = main(["path", str(EXAMPLES / "fourbar_appendix.toml"), "--to", "360", "--tol", "1e-6", "--json",
                 "--no-progress"])
    out = capsys.readouterr().out
    assert code == 0
    events = [e for e in json.loads(out)["events"] if e["kind"] != "end"]
    assert events and all(e["analysis"]["tolerance"] == 1e-6 for e in events)
    with pytest.raises(SystemExit) as info:
        main(["path", str(EXAMPLES / "fourbar_appendix.toml"), "--to", "360", "--tol", "2"])
    assert info.value.code == 2


def test_follow_branch_classifies_with_its_tolerance():
    from tests.paths.test_trace import fourbar
    from symkin.paths.trace import follow_branch

    m = fourbar([0.0, 0.0], [0.0, 1.0], [2.0, 1.0], [2.0, 0.0], "parallelogram")
    path = trace(m, stop=360, unit="deg", tol=1e-7)
    ims = [e for e in path.singular_events() if e.kind == "IM"]
    assert len(ims) == 2 and all(e.analysis.tolerance == 1e-7 and e.analysis.dof == 2 for e in ims)
    sub = follow_branch(path, ims[0], 0, max_arclength=4.0, tol=1e-6)
    events = sub.singular_events()
    assert events and all(e.analysis.tolerance == 1e-6 for e in events)
    assert sub.points[0].indicators["im_indicator"] == pytest.approx(0.0, abs=1e-20)  # the branch point
