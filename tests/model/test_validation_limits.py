"""Regular tests for each class of bug the model-file fuzz test found (tests/model/test_fuzz_model_files.py).

Before the fixes these inputs ended in an OverflowError, an IndexError, a ValueError, a
RecursionError, a LinAlgError, a hung SVD, or (coordinates near 1e300) a silently wrong
classification; now each is a ModelError naming the key at fault, or a correct analysis.
"""
from __future__ import annotations

import pytest

import symkin
from symkin.cli import main
from symkin.model import catalogue
from symkin.model.validation import COORDINATE_LIMIT, MIN_LENGTH


def _problems(data) -> dict[str, str]:
    with pytest.raises(symkin.ModelError) as info:
        symkin.Mechanism.from_dict(data)
    return {p.key: p.message for p in info.value.problems}


def test_an_integer_too_large_for_a_float_is_not_finite():
    data = catalogue.data("fourbar_appendix")
    data["nodes"]["B"] = [10**400, 0]
    problems = _problems(data)
    assert list(problems) == ["nodes.B"]
    assert "finite" in problems["nodes.B"]
    assert len(problems["nodes.B"]) < 200          # the 401-digit number is shortened


@pytest.mark.parametrize("value", [1e300, -1e308, 1.01e100])
def test_a_coordinate_beyond_the_limit_is_named(value):
    data = catalogue.data("fourbar_appendix")
    data["nodes"]["C"] = [value, 1.3]
    problems = _problems(data)
    assert "nodes.C" in problems and "out of range" in problems["nodes.C"]
    assert f"{COORDINATE_LIMIT:g}" in problems["nodes.C"]


def test_a_model_scaled_to_1e300_is_rejected_not_misclassified():
    # before: analysed as DOF 4 with IM, DKP-input and DKP-output (squared lengths overflowed)
    mech = catalogue.get("fourbar_appendix").moved(scale=1e300)
    problems = _problems(mech.to_dict())
    assert {"nodes.B", "nodes.C", "nodes.D"} <= set(problems)


def test_a_model_scaled_to_1e_300_is_rejected_with_its_length_scale():
    # before: LinAlgError (fourbar) or an SVD that never returned (slider-crank)
    for name in ("fourbar_appendix", "slider_crank"):
        problems = _problems(catalogue.get(name).moved(scale=1e-300).to_dict())
        assert set(problems) == {"nodes"}
        assert "length scale" in problems["nodes"] and "another unit" in problems["nodes"]


@pytest.mark.parametrize("direction, words", [([1e-200, 0.0], "too short"), ([0.0, 0.0], "zero direction"),
                                              ([1e300, 1e300], "out of range")])
def test_a_slider_direction_too_short_or_too_long_is_named(direction, words):
    data = catalogue.data("slider_crank")
    data["sliders"][0]["direction"] = direction
    problems = _problems(data)
    assert set(problems) == {"sliders[0] (piston)", "outputs[0]"}    # the output names the slider
    assert words in problems["sliders[0] (piston)"]


def test_a_spatial_axis_too_short_is_named():
    data = catalogue.data("rssr")
    data["inputs"][0]["axis"] = [0.0, 0.0, 1e-120]
    problems = _problems(data)
    assert list(problems) == ["inputs[0]"] and "too short" in problems["inputs[0]"]


@pytest.mark.parametrize("dim", [None, 1e308, "3", 2.0, 3.0])
def test_an_axis_with_a_bad_dim_reports_the_dim_only(dim):
    # before: IndexError / ValueError while testing the axis against a rod of unknown dimension
    data = catalogue.data("rssr")
    if dim is None:
        del data["dim"]
    else:
        data["dim"] = dim
    data["nodes"]["B"] = [1.0, 0.0]                 # a node of another dimension
    problems = _problems(data)
    assert list(problems) == ["dim"]


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize("value, words", [("1" * 5000, "more than 4300 digits"),
                                          ("[" * 5000 + "]" * 5000, "nested too deeply")])
def test_unreadable_numbers_and_nesting_are_file_errors(tmp_path, capsys, suffix, value, words):
    # before: tomllib's ValueError and both parsers' RecursionError escaped as internal errors (exit 3)
    path = tmp_path / f"model{suffix}"
    path.write_text(f'dim = {value}\n' if suffix == ".toml" else f'{{"dim": {value}}}\n')
    with pytest.raises(symkin.ModelFileError) as info:
        symkin.read_model(path)
    assert words in str(info.value)
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{path}: malformed") and "Traceback" not in err


@pytest.mark.parametrize("name", catalogue.names())
def test_classification_holds_at_the_edges_of_the_range(name):
    """Scaled until the largest coordinate nears COORDINATE_LIMIT, or the length scale nears MIN_LENGTH."""
    mech = catalogue.get(name)
    ref = symkin.analyze(mech)
    biggest = max(abs(c) for _, xyz in mech.nodes for c in xyz)
    for factor in (0.5 * COORDINATE_LIMIT / biggest, 2 * MIN_LENGTH / mech.length_scale):
        moved = symkin.Mechanism.from_dict(mech.moved(scale=factor).to_dict())   # passes validation
        got = symkin.analyze(moved)
        assert (got.dof, got.types) == (ref.dof, ref.types), factor


def test_flat_fourbar_is_im_with_two_dof_at_both_edges():
    # independent truth: four collinear joints give the four-bar an extra instantaneous DOF (L = 2)
    mech = catalogue.get("fourbar_flat")
    for factor in (1e99 / 4, 1e-100):
        got = symkin.analyze(mech.moved(scale=factor))
        assert got.dof == 2 and got.types == ("IM",)
