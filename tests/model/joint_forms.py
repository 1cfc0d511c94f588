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


def _r(jid, a, b, at, axis=None):
    out = {"id": jid, "type": "R", "links": [a, b], "at": at}
    if axis is not None:
        out["axis"] = axis
    return out


def five_bar(nodes: dict) -> dict:
    """Five-bar (2RR): R to ground at A1, A2, R at B1, B2 and the distal links' R at P (the output)."""
    return {"name": "five-bar by its joints", "dim": 2,
            "inputs": [{"joint": "A1"}, {"joint": "A2"}], "outputs": [{"velocity": "P"}],
            "links": {"crank1": [], "crank2": [], "distal1": [], "distal2": []},
            "joints": [_r("A1", "ground", "crank1", nodes["A1"]), _r("A2", "ground", "crank2", nodes["A2"]),
                       _r("B1", "crank1", "distal1", nodes["B1"]), _r("B2", "crank2", "distal2", nodes["B2"]),
                       _r("P", "distal1", "distal2", nodes["P"])]}


def rrr_3(nodes: dict) -> dict:
    """3-RRR: per leg R to ground at A_k (the input), R at B_k, R on the platform at C_k."""
    joints = [_r(f"{n}{k}", a, b, nodes[f"{n}{k}"]) for k in (1, 2, 3)
              for n, a, b in (("A", "ground", f"crank{k}"), ("B", f"crank{k}", f"distal{k}"),
                              ("C", f"distal{k}", "platform"))]
    joints.sort(key=lambda j: j["id"][0] != "C")      # the platform's first node is C1, as in the node form
    links = {name: [] for k in (1, 2, 3) for name in (f"crank{k}", f"distal{k}")}
    links["platform"] = []
    return {"name": "3-RRR by its joints", "dim": 2, "inputs": [{"joint": f"A{k}"} for k in (1, 2, 3)],
            "outputs": [{"twist": "platform"}], "platform": "platform", "platform_dof": 3,
            "links": links, "joints": joints}


def bennett(nodes: dict) -> dict:
    """Bennett 4R loop: four spatial R on the node form's axes (X → X2); ground at A and D."""
    ax = {n: _sub(nodes[f"{n}2"], nodes[n]) for n in "ABCD"}
    return {"name": "Bennett by its joints", "dim": 3, "mobility": 1,
            "inputs": [{"joint": "A"}], "outputs": [{"joint": "D"}],
            "links": {"link1": [], "link2": [], "link3": []},
            "joints": [_r("A", "ground", "link1", nodes["A"], ax["A"]), _r("B", "link1", "link2", nodes["B"], ax["B"]),
                       _r("C", "link2", "link3", nodes["C"], ax["C"]), _r("D", "ground", "link3", nodes["D"], ax["D"])]}


def rsr_3(nodes: dict) -> dict:
    """3-RSR of the paper's Fig. 11-13: per leg R to ground (G_k1 → G_k2), S at S_k, R on the platform."""
    joints = []
    for k in (1, 2, 3):
        g, u = nodes[f"G{k}1"], nodes[f"U{k}1"]
        joints += [_r(f"G{k}", "ground", f"lower{k}", g, _sub(nodes[f"G{k}2"], g)),
                   {"id": f"S{k}", "type": "S", "links": [f"lower{k}", f"upper{k}"], "at": nodes[f"S{k}"]},
                   _r(f"U{k}", f"upper{k}", "platform", u, _sub(nodes[f"U{k}2"], u))]
    links = {name: [] for k in (1, 2, 3) for name in (f"lower{k}", f"upper{k}")}
    links["platform"] = []
    return {"name": "3-RSR by its joints", "dim": 3, "mobility": 3,
            "inputs": [{"joint": f"G{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3, "links": links, "joints": joints}
