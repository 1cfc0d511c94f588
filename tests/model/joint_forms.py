"""Joint forms (``[[joints]]``) of node-form mechanisms, built from the same coordinates.

Shared by :mod:`tests.model.test_joints` and :mod:`tests.analysis.test_joint_forms`: each
function takes the node coordinates of the node form (a catalogue entry or a file of
``tests/workspace/models``) and returns the model dictionary of the same mechanism written
by its joints.
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "workspace" / "models"


def node_form(name: str) -> dict:
    """A model file of ``tests/workspace/models`` as a dictionary."""
    return tomllib.loads((MODELS / f"{name}.toml").read_text())


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def fourbar(nodes: dict) -> dict:
    """Four-bar A-B-C-D (A, D fixed): four R joints; input R1 (crank), output R4 (rocker)."""
    return {
        "name": "four-bar by its joints", "dim": 2, "mobility": 1,
        "inputs": [{"joint": "R1"}], "outputs": [{"joint": "R4"}],
        "links": {"crank": [], "coupler": [], "rocker": []},
        "joints": [{"type": "R", "links": ["ground", "crank"], "at": nodes["A"]},
                   {"type": "R", "links": ["crank", "coupler"], "at": nodes["B"]},
                   {"type": "R", "links": ["coupler", "rocker"], "at": nodes["C"]},
                   {"type": "R", "links": ["ground", "rocker"], "at": nodes["D"]}],
    }


def slider_crank(nodes: dict, slider_point, direction) -> dict:
    """Slider-crank: R, R, R and a P to ground along ``direction``; output the P's slide."""
    return {
        "name": "slider-crank by its joints", "dim": 2,
        "inputs": [{"joint": "R1"}], "outputs": [{"joint": "P1"}],
        "links": {"crank": [], "rod": [], "block": []},
        "joints": [{"type": "R", "links": ["ground", "crank"], "at": nodes["A"]},
                   {"type": "R", "links": ["crank", "rod"], "at": nodes["B"]},
                   {"type": "R", "links": ["rod", "block"], "at": nodes["C"]},
                   {"type": "P", "links": ["ground", "block"], "at": nodes["C"], "axis": list(direction)}],
    }


def rpr_3(nodes: dict) -> dict:
    """3-RPR: per leg R (ground-cylinder), P (cylinder-rod along the leg), R (rod-platform)."""
    joints = []
    for k in (1, 2, 3):
        a, c = nodes[f"A{k}"], nodes[f"C{k}"]
        joints += [{"id": f"A{k}", "type": "R", "links": ["ground", f"cyl{k}"], "at": a},
                   {"id": f"P{k}", "type": "P", "links": [f"cyl{k}", f"rod{k}"], "at": a, "axis": _sub(c, a)},
                   {"id": f"C{k}", "type": "R", "links": [f"rod{k}", "platform"], "at": c}]
    links = {name: [] for k in (1, 2, 3) for name in (f"cyl{k}", f"rod{k}")}
    links["platform"] = ["O"]
    return {"name": "3-RPR by its joints", "dim": 2, "mobility": 3,
            "inputs": [{"joint": f"P{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3, "nodes": {"O": nodes["O"]}, "links": links,
            "joints": joints}


def rssr(nodes: dict) -> dict:
    """RSSR: R to ground about O1→O1b, S, S, R to ground about O2→O2b."""
    return {
        "name": "RSSR by its joints", "dim": 3,
        "inputs": [{"joint": "R1"}], "outputs": [{"joint": "R2"}],
        "links": {"crank": [], "coupler": [], "rocker": []},
        "joints": [{"type": "R", "links": ["ground", "crank"], "at": nodes["O1"],
                    "axis": _sub(nodes["O1b"], nodes["O1"])},
                   {"type": "S", "links": ["crank", "coupler"], "at": nodes["B"]},
                   {"type": "S", "links": ["coupler", "rocker"], "at": nodes["C"]},
                   {"type": "R", "links": ["ground", "rocker"], "at": nodes["O2"],
                    "axis": _sub(nodes["O2b"], nodes["O2"])}],
    }


def ups_6(nodes: dict) -> dict:
    """6-UPS Gough-Stewart: per leg U (ground-cylinder, axes normal to the leg), P, S."""
    joints = []
    for k in range(1, 7):
        a, c = nodes[f"A{k}"], nodes[f"C{k}"]
        d = _unit(_sub(c, a))
        axis = _unit(_cross(d, [0.0, 0.0, 1.0]))
        joints += [{"id": f"U{k}", "type": "U", "links": ["ground", f"cyl{k}"], "at": a,
                    "axis": axis, "axis2": _unit(_cross(d, axis))},
                   {"id": f"P{k}", "type": "P", "links": [f"cyl{k}", f"rod{k}"], "at": a, "axis": d},
                   {"id": f"S{k}", "type": "S", "links": [f"rod{k}", "platform"], "at": c}]
    links = {name: [] for k in range(1, 7) for name in (f"cyl{k}", f"rod{k}")}
    links["platform"] = ["O"]
    return {"name": "6-UPS by its joints", "dim": 3, "mobility": 6,
            "inputs": [{"joint": f"P{k}"} for k in range(1, 7)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 6, "nodes": {"O": nodes["O"]}, "links": links,
            "joints": joints}
