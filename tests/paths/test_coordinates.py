"""Finite input coordinates: their gradients are the kinematic-parameter rows on the motion space."""
from __future__ import annotations

import numpy as np
import pytest

from symkin import motion_space
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import free_mask, parameter_rows
from symkin.paths.coordinates import LinearInput, input_coordinates
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
