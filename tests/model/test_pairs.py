"""The registry of pair kinds (:mod:`symkin.model.pairs`) as the model stage sees it.

The names a model file and a script use are the ones they were before the registry: the
joint types and keys in the order messages list them, the ``helicals`` key of the model
dictionary and ``mech.helicals``, ``joint.pitch``; a mechanism with extra constraints pickles,
copies and compares as one without.
"""
from __future__ import annotations

import copy
import pickle
from pathlib import Path

import pytest

import symkin
from symkin.errors import ModelError
from symkin.model.pairs import extra_keys, joint_keys, joint_kind, joint_types

MODELS = Path(__file__).resolve().parents[1] / "constraints" / "models"


def test_the_registered_kinds_in_their_order():
    assert joint_types(2) == ("R", "P")
    assert joint_types(3) == ("R", "P", "C", "U", "S", "H")
    assert joint_keys() == ("id", "type", "links", "at", "axis", "axis2", "pitch")
    assert extra_keys() == ("helicals",)
    assert joint_kind("X") is None and joint_kind(["R"]) is None


def test_messages_list_the_registered_names():
    with pytest.raises(ModelError, match=r"allowed: name, description, dim, fixed, mobility, inputs, outputs, "
                                         r"platform, platform_dof, nodes, links, sliders, joints, helicals\)"):
        symkin.Mechanism.from_dict({**symkin.catalogue.get("fourbar_appendix").to_dict(), "gears": []})
    planar = {"name": "x", "dim": 2, "links": {"a": []},
              "joints": [{"id": "Q1", "type": "Q", "links": ["ground", "a"], "at": [0, 0]}]}
    with pytest.raises(ModelError, match=r"joints\[0\] \(Q1\): type must be one of R, P \(dim = 2\), got 'Q'"):
        symkin.Mechanism.from_dict(planar)


def test_extras_read_as_before():
    """``mech.helicals`` (the records under the model key), ``joint.pitch`` (None for a kind
    without it), the records after a similarity; other names are no attributes."""
    mech = symkin.read_model(MODELS / "screw_jack.toml")
    assert mech.helicals == mech.extras and [h.id for h in mech.helicals] == ["H1"]
    joints = {j.id: j for j in mech.joints}
    assert joints["H1"].pitch == 0.004 and joints["R1"].pitch is None
    assert joints["H1"].to_dict()["pitch"] == 0.004 and "pitch" not in joints["R1"].to_dict()
    with pytest.raises(AttributeError):
        mech.gears  # noqa: B018
    with pytest.raises(AttributeError):
        joints["H1"].gear  # noqa: B018
    mm = mech.moved(scale=1000.0)
    assert mm.helicals[0].pitch == pytest.approx(4.0) and {j.id: j for j in mm.joints}["H1"].pitch == pytest.approx(4.0)
    assert "helicals" in mech.to_dict() and "helicals" not in symkin.catalogue.get("rssr").to_dict()


def test_a_mechanism_with_extras_pickles_copies_and_compares():
    mech = symkin.read_model(MODELS / "rhss.toml")
    for again in (pickle.loads(pickle.dumps(mech)), copy.deepcopy(mech), copy.copy(mech),
                  symkin.Mechanism.from_dict(mech.to_dict())):
        assert again == mech and again.topology == mech.topology and again.helicals == mech.helicals
    assert mech.with_coordinates(mech.coordinates()).topology is mech.topology
    joint = mech.joints[0]
    assert pickle.loads(pickle.dumps(joint)) == joint and copy.deepcopy(joint) == joint
    # a node model's topology key has no part for extras (the key it always had)
    assert len(symkin.catalogue.get("rssr").topology.key) == 10 and len(mech.topology.key) == 11
