"""The deciding evaluators (symkin.analysis.batch): shared per model, kernel built on first use."""
from __future__ import annotations

import numpy as np

import symkin
from symkin.analysis.batch import Evaluators, evaluators, evaluators_for
from symkin.model.catalogue import get
from symkin.numeric import evaluators as numeric


def test_public_evaluators_decide_and_keep_the_numeric_interface():
    ev = symkin.evaluators(get("fourbar_appendix"))
    assert isinstance(ev, symkin.Evaluators) and isinstance(ev, numeric.Evaluators)
    assert symkin.Evaluators is Evaluators
    assert ev("G", ev.q0)["G"].shape == (4, 4) and ev.map("J", [ev.q0] * 2)["J_free"].shape == (2, 3, 4)
    assert ev.batch([ev.q0] * 3).singular.tolist() == [False, False, False]
    assert not hasattr(numeric.Evaluators, "batch")  # numbers only below the analysis stage


def test_deferred_kernel_gives_the_same_numbers_and_decisions():
    mech = get("rrr_3")
    full, lazy = evaluators(mech), evaluators(mech, kernel=False)
    assert "indicators" in full.functions and not dict.__contains__(lazy.functions, "indicators")
    rng = np.random.default_rng(5)
    q = full.project(full.q0 + 0.03 * mech.length_scale * rng.standard_normal((40, full.nf)))
    a, b = full.batch(q), lazy.batch(q)
    for key in ("im_indicator", "dkp_input", "dkp_output", "dof", "path"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    assert lazy.indicators_at(q[0]) == full.indicators_at(q[0])
    assert lazy.motion is lazy.functions["motion"]


def test_evaluators_for_is_shared_per_model_content():
    a, b = evaluators_for(get("five_bar")), evaluators_for(get("five_bar"))
    assert a is b and a.mech == get("five_bar")
    moved = get("five_bar").with_coordinates(a.coordinates(a.q0 + 1e-3))
    assert evaluators_for(moved) is not a
