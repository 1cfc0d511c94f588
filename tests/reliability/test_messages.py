"""Messages that name the real cause; margins of every decision (issue 20 §5)."""
from __future__ import annotations

import pytest

from symkin import Mechanism, analyze
from symkin.errors import ModelError
from symkin.model.catalogue import data, get
from symkin.report import render_markdown, render_text


def test_an_outlier_coordinate_is_reported_not_zero_length_bars():
    d = data("fourbar_appendix")
    d["nodes"]["C"] = [2.0 ** 63, 1.3]
    with pytest.raises(ModelError) as info:
        Mechanism.from_dict(d)
    text = str(info.value)
    assert "nodes.C" in text and "outlier" in text and "9.22337e+18" in text
    assert "zero-length" not in text


def test_a_real_zero_length_bar_is_still_reported():
    d = data("fourbar_appendix")
    d["nodes"]["B"] = [1e-12, 0.0]
    with pytest.raises(ModelError, match="zero-length bar: nodes A and B"):
        Mechanism.from_dict(d)


def test_every_decision_has_its_margin_and_the_dkp_values_are_printed():
    a = analyze(get("fourbar_dead_centre"))
    names = [d[0] for d in a.decisions]
    assert names == ["rank", "IM", "DKP-input", "DKP-output"]
    by = {d[0]: d for d in a.decisions}
    _, value, threshold, margin = by["DKP-output"]
    assert value < threshold and margin == pytest.approx(threshold / value)
    _, value, threshold, margin = by["DKP-input"]
    assert value > threshold and margin == pytest.approx(value / threshold)
    # the DKP margins are their own, not the constraint matrix's
    assert by["DKP-input"][3] != a.margin and by["DKP-output"][3] != a.margin
    text = render_text(a)
    assert f"input {a.dkp_input:+.6g}" in text and f"output {a.dkp_output:+.6g}" in text
    for name in ("IM:", "DKP-input:", "DKP-output:"):
        assert name in text
    assert "DKP values" in render_markdown(a)
    js = a.to_dict()["decisions"]
    assert [d["decision"] for d in js] == names and all(d["threshold"] > 0 for d in js)
