"""Finite input coordinates: their gradients are the kinematic-parameter rows on the motion space."""
from __future__ import annotations

import numpy as np
import pytest

from symkin import motion_space
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import free_mask, parameter_rows
from symkin.numeric.coordinates import LinearInput, input_coordinates
from symkin.paths.system import MechanismCurve


@pytest.mark.parametrize("name", ["fourbar_appendix", "slider_crank", "five_bar", "rrr_3", "rssr"])
def test_gradient_is_the_parameter_row_on_the_motion_space(name):
    mech = catalogue.get(name)
    ms = motion_space(mech)
    free = free_mask(mech)
    for c in input_coordinates(mech):
        curve = MechanismCurve(mech, LinearInput.single(c))
        y = curve.y0()
        grad = np.array(curve._drive(y)[1]).ravel()  # d value / d y, value in rad or model units
        grad = grad / curve.scale  # d value / d q
        row = parameter_rows(mech, c.parameter)[c.component if c.parameter.kind == "velocity" else 0]
        np.testing.assert_allclose(grad @ ms.V[free], row[free] @ ms.V[free], atol=1e-12, err_msg=c.label)


def test_values_are_measured_from_the_model():
    mech = catalogue.get("fourbar_appendix")
    (c,) = input_coordinates(mech)
    curve = MechanismCurve(mech, LinearInput.single(c))
    assert curve.input_value(curve.y0()) == 0.0


def test_every_accepted_label_parses_and_an_unknown_one_lists_them():
    from symkin.errors import SymkinError
    from symkin.numeric.coordinates import accepted_input_labels, parse_input_label

    mech = catalogue.get("slider_crank")
    accepted = accepted_input_labels(mech)
    assert accepted == {"inputs": ("rotation:crank",), "outputs": ("slide:piston",), "rotation": ("crank", "rod"),
                        "slide": ("piston",), "velocity": ("B", "C")}
    labels = list(accepted["inputs"] + accepted["outputs"]) + [f"rotation:{k}" for k in accepted["rotation"]] \
        + [f"slide:{k}" for k in accepted["slide"]] + [f"velocity:{n}.{a}" for n in accepted["velocity"] for a in "xy"]
    for label in labels:
        assert parse_input_label(mech, label).label == label
    # a fixed node's velocity, a ground or unknown link, a z component in the plane: rejected with the list
    for bad in ("velocity:A.x", "rotation:ground", "velocity:B.z", "slide:nope", "rocker"):
        with pytest.raises(SymkinError) as info:
            parse_input_label(mech, bad)
        text = str(info.value)
        assert text.startswith(f"unknown input {bad!r}; a path can be driven by")
        for part in ("rotation:crank", "its outputs (slide:piston)", "rotation:<link> for a moving link (crank, rod)",
                     "slide:<slider> (piston)", "velocity:<node>.<x|y> for a free node (B, C)"):
            assert part in text
    # a spatial model: its outputs (rotations about fixed axes) drive a path; no planar rotation form
    rssr = catalogue.get("rssr")
    assert accepted_input_labels(rssr)["outputs"] == ("rotation:rocker[O2-O2b]",)
    assert accepted_input_labels(rssr)["rotation"] == ()
    assert parse_input_label(rssr, "rotation:rocker[O2-O2b]").kind == "angle"
