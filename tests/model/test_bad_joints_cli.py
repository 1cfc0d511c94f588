"""Every bad joint of issue 16's list exits 2 from the command line, naming the joint, no traceback.

The list: an unknown link, a zero axis, U axes not perpendicular, a point that does not lie on a
link's geometry where that is required (a bar joined off its line), a type not allowed in
``dim = 2``, and H in a global solve (``modes``/``singularities``:
tests/constraints/test_helical.py runs those as a subprocess).  Each bad file is a good joint model
(3-RPR, 6-UPS, RSSR of tests/model/joint_forms.py) with one edit.
"""
from __future__ import annotations

import contextlib
import copy
import io
import json

import pytest

import symkin
from symkin.cli import main
from symkin.model import catalogue
from tests.model import joint_forms as jf


def _rpr() -> dict:
    return jf.rpr_3(symkin.read_model(jf.MODELS / "rpr_3.toml").coordinates())


def _ups() -> dict:
    return jf.ups_6(symkin.read_model(jf.MODELS / "gough_stewart.toml").coordinates())


def _rssr() -> dict:
    return jf.rssr(catalogue.get("rssr").coordinates())


def _unknown_link(d):
    d["joints"][1]["links"] = ["cyl1", "rod9"]


def _zero_axis(d):
    d["joints"][1]["axis"] = [0.0, 0.0, 0.0]


def _u_not_perpendicular(d):
    d["joints"][0]["axis2"] = [1.0, 1.0, 0.3]


def _off_the_bar(d):
    d["links"]["platform"] = ["O", "X"]          # the platform a bar O-X: C1 is not on its line
    d["nodes"]["X"] = [9.0, 9.0]


def _spatial_type_in_the_plane(d):
    d["joints"][0]["type"] = "U"


def _s_in_the_plane(d):
    d["joints"][0]["type"] = "S"


@pytest.mark.parametrize("base, edit, joint, message", [
    (_rpr, _unknown_link, "P1", "unknown link 'rod9'"),
    (_ups, _zero_axis, "P1", "zero axis"),
    (_ups, _u_not_perpendicular, "U1", "the axes of U joint U1 are not perpendicular"),
    (_rpr, _off_the_bar, "C1", "is not on link platform, the bar O-X"),
    (_rpr, _spatial_type_in_the_plane, "A1", "type 'U' is not allowed in a planar model"),
    (_rpr, _s_in_the_plane, "A1", "type 'S' is not allowed in a planar model"),
], ids=["unknown-link", "zero-axis", "u-axes", "off-the-bar", "u-in-2d", "s-in-2d"])
def test_bad_joint_exits_2_naming_the_joint(tmp_path, base, edit, joint, message):
    data = copy.deepcopy(base())
    edit(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["analyze", str(path)])
    text = err.getvalue()
    assert code == 2, text
    assert f"({joint})" in text and message in text, text
    assert "Traceback" not in text and str(path) in text


def test_a_good_joint_model_exits_0(tmp_path):
    """The unedited models are valid (so each exit 2 above is the edit's)."""
    for base in (_rpr, _ups, _rssr):
        path = tmp_path / "good.json"
        path.write_text(json.dumps(base()))
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            assert main(["analyze", str(path)]) == 0
