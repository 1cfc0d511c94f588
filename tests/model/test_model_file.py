"""Reading and writing model files: TOML and JSON share one schema; bad files are named."""
from __future__ import annotations

import json

import pytest

import symkin
from symkin import ModelFileError, read_model, write_model
from symkin.model import catalogue


def test_toml_and_json_give_the_same_mechanism(tmp_path, catalogue_name):
    m = catalogue.get(catalogue_name)
    a = read_model(write_model(m, tmp_path / "m.toml"))
    b = read_model(write_model(m, tmp_path / "m.json"))
    assert a == m and b == m


def test_example_file_matches_catalogue(fourbar):
    from tests.conftest import EXAMPLES

    assert read_model(EXAMPLES / "fourbar_appendix.toml") == fourbar


def test_missing_file(tmp_path):
    with pytest.raises(ModelFileError) as info:
        read_model(tmp_path / "nope.toml")
    assert info.value.path.endswith("nope.toml") and "no such file" in str(info.value)


def test_malformed_toml_names_the_line(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('name = "x"\ndim = 2\nnodes = {A = [0, 0]\n')
    with pytest.raises(ModelFileError) as info:
        read_model(p)
    assert info.value.line == 3 and "malformed TOML" in str(info.value)


def test_malformed_json_names_the_line(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text('{\n "dim": 2,\n "nodes": [\n}')
    with pytest.raises(ModelFileError) as info:
        read_model(p)
    assert info.value.line == 4 and "malformed JSON" in str(info.value)


def test_duplicate_json_keys_are_an_error(tmp_path, fourbar_data):
    text = json.dumps(fourbar_data).replace('"B": [0.2, 0.9]', '"B": [0.2, 0.9], "B": [0.3, 0.9]')
    p = tmp_path / "dup.json"
    p.write_text(text)
    with pytest.raises(ModelFileError, match="duplicate key 'B'"):
        read_model(p)


def test_unknown_suffix(tmp_path):
    p = tmp_path / "model.yaml"
    p.write_text("dim: 2")
    with pytest.raises(ModelFileError, match="use .toml or .json"):
        read_model(p)


def test_file_problems_carry_the_path(tmp_path, fourbar_data):
    fourbar_data["links"]["crank"] = ["A", "Q"]
    p = tmp_path / "m.json"
    p.write_text(json.dumps(fourbar_data))
    with pytest.raises(ModelFileError) as info:
        read_model(p)
    assert info.value.path == str(p)
    assert [str(x) for x in info.value.problems] == ["links.crank: unknown node 'Q'"]


def test_name_defaults_to_file_stem(tmp_path, fourbar_data):
    del fourbar_data["name"]
    p = tmp_path / "my_linkage.json"
    p.write_text(json.dumps(fourbar_data))
    assert read_model(p).name == "my_linkage"


def test_write_is_atomic(tmp_path, fourbar):
    target = tmp_path / "m.toml"
    write_model(fourbar, target)
    assert not list(tmp_path.glob("*.tmp"))
    assert symkin.read_model(target) == fourbar
