"""Joint forms (``[[joints]]``) of node-form mechanisms, built from the same coordinates.

Shared by :mod:`tests.model.test_joints`, :mod:`tests.analysis.test_joint_forms` (and
``test_joint_forms_spatial``), ``tests/paths/test_joint_form_paths.py`` and
``tests/workspace/test_map_joint_forms.py``: each function takes the node coordinates of the
node form (a catalogue entry, a file of ``tests/workspace/models``, ``truth.Delta``) and
returns the model dictionary of the same mechanism written by its joints.  The 3-PRR and the
3-RPS have no node form elsewhere: theirs are written here from their geometry
(:func:`prr_3_node`, :func:`rps_3_node`, configurations by closed form).
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


def delta(nodes: dict) -> dict:
    """Delta 3-R(SS)² (tests/workspace/truth.Delta): per leg an R to ground about A_k → A_kb (the input),
    the arm carrying a parallelogram of two bars, each an S at the elbow B_ka/B_kb and at the platform C_ka/C_kb."""
    joints = []
    for k in (1, 2, 3):
        a = nodes[f"A{k}"]
        joints.append(_r(f"A{k}", "ground", f"arm{k}", a, _sub(nodes[f"A{k}b"], a)))
        for s in "ab":
            joints += [{"id": f"B{k}{s}", "type": "S", "links": [f"arm{k}", f"bar{k}{s}"], "at": nodes[f"B{k}{s}"]},
                       {"id": f"C{k}{s}", "type": "S", "links": [f"bar{k}{s}", "platform"], "at": nodes[f"C{k}{s}"]}]
    links = {f"arm{k}": [] for k in (1, 2, 3)}
    links.update({f"bar{k}{s}": [] for k in (1, 2, 3) for s in "ab"})
    links["platform"] = ["P"]
    return {"name": "Delta by its joints", "dim": 3, "mobility": 3,
            "inputs": [{"joint": f"A{k}"} for k in (1, 2, 3)], "outputs": [{"velocity": "P"}],
            "nodes": {"P": list(nodes["P"])}, "links": links, "joints": joints}


# ------------------------------------------------------------------------------ 3-PRR (planar)
#: guide k of the 3-PRR runs from vertex V_k of an equilateral triangle of circumradius 4 (V_k at
#: 90° + 120° (k − 1)) towards V_{k+1}; distal links of length 2.2; platform joints c_k on a circle of
#: radius 1 at 90° + 120° (k − 1) + 20° in the platform frame (reference point O)
PRR_BASE = 4.0
PRR_DISTAL = 2.2
PRR_PLATFORM = 1.0


def prr_guides() -> list[tuple[list[float], list[float]]]:
    """``(point V_k, unit direction d_k)`` of the three guides of the 3-PRR."""
    ang = [math.radians(90.0 + 120.0 * k) for k in range(3)]
    v = [[PRR_BASE * math.cos(a), PRR_BASE * math.sin(a)] for a in ang]
    return [(v[k], _unit(_sub(v[(k + 1) % 3], v[k]))) for k in range(3)]


def prr_3_nodes(o, phi: float, mode=(1, 1, 1)) -> dict | None:
    """Node positions of the 3-PRR with its platform at ``o``, turned by ``phi`` (closed form), or None.

    ``C_k = O + R(φ) c_k``; slider ``B_k = V_k + s d_k`` with ``|B_k − C_k| = l``:
    ``s = d·(C − V) + mode_k √((d·(C − V))² − |C − V|² + l²)``.
    """
    out = {"O": [float(o[0]), float(o[1])]}
    c, s_ = math.cos(phi), math.sin(phi)
    for k, (v, d) in enumerate(prr_guides()):
        a = math.radians(90.0 + 120.0 * k + 20.0)
        ck = [PRR_PLATFORM * math.cos(a), PRR_PLATFORM * math.sin(a)]
        C = [o[0] + c * ck[0] - s_ * ck[1], o[1] + s_ * ck[0] + c * ck[1]]
        w = _sub(C, v)
        along = w[0] * d[0] + w[1] * d[1]
        disc = along ** 2 - (w[0] ** 2 + w[1] ** 2) + PRR_DISTAL ** 2
        if disc < 0:
            return None
        t = along + mode[k] * math.sqrt(disc)
        out[f"B{k + 1}"] = [v[0] + t * d[0], v[1] + t * d[1]]
        out[f"C{k + 1}"] = C
    return out


def prr_3_node(nodes: dict) -> dict:
    """3-PRR in node form: slider B_k on the fixed guide k (input ``slide:s_k``), distal bar B_k–C_k,
    platform body O-C1-C2-C3 (O first: the twist's point)."""
    return {"name": "3-PRR planar parallel manipulator", "dim": 2, "mobility": 3,
            "inputs": [{"slide": f"s{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3,
            "nodes": {n: list(p) for n, p in nodes.items()},
            "links": {**{f"distal{k}": [f"B{k}", f"C{k}"] for k in (1, 2, 3)},
                      "platform": ["O", "C1", "C2", "C3"]},
            "sliders": [{"id": f"s{k}", "node": f"B{k}", "point": v, "direction": d}
                        for k, (v, d) in enumerate(prr_guides(), 1)]}


def prr_3(nodes: dict) -> dict:
    """3-PRR by its joints: per leg P (ground-block along guide k, the input), R (block-distal at B_k),
    R (distal-platform at C_k)."""
    joints = []
    for k, (_, d) in enumerate(prr_guides(), 1):
        joints += [{"id": f"P{k}", "type": "P", "links": ["ground", f"block{k}"], "at": nodes[f"B{k}"], "axis": d},
                   _r(f"B{k}", f"block{k}", f"distal{k}", nodes[f"B{k}"]),
                   _r(f"C{k}", f"distal{k}", "platform", nodes[f"C{k}"])]
    links = {name: [] for k in (1, 2, 3) for name in (f"block{k}", f"distal{k}")}
    links["platform"] = ["O"]
    return {"name": "3-PRR by its joints", "dim": 2, "mobility": 3,
            "inputs": [{"joint": f"P{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3, "nodes": {"O": nodes["O"]}, "links": links,
            "joints": joints}


# ------------------------------------------------------------------------------ 3-RPS (spatial)
#: the 3-RPS of Lee & Shah (1988): base joints A_k on a circle of radius 2 at 90° + 120° (k − 1), each R
#: axis u_k tangent to that circle (in the base plane), so leg k moves in the vertical plane through A_k
#: and the centre; platform joints c_k on a circle of radius 1 at the same angles in the platform frame
RPS_BASE = 2.0
RPS_PLATFORM = 1.0


def _rot(axis: int, angle: float):
    c, s = math.cos(angle), math.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m = [[1.0 if r == q else 0.0 for q in range(3)] for r in range(3)]
    m[i][i], m[i][j], m[j][i], m[j][j] = c, -s, s, c
    return m


def _mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def _apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def rps_frames():
    """``(A_k, u_k, c_k)``: base joints, their R axes (tangent), platform joints in the platform frame."""
    out = []
    for k in range(3):
        a = math.radians(90.0 + 120.0 * k)
        radial = [math.cos(a), math.sin(a), 0.0]
        out.append(([RPS_BASE * radial[0], RPS_BASE * radial[1], 0.0], [-radial[1], radial[0], 0.0],
                    [RPS_PLATFORM * radial[0], RPS_PLATFORM * radial[1], 0.0]))
    return out


def rps_3_nodes(height: float, tilt_x: float, tilt_y: float) -> dict:
    """Node positions of the 3-RPS at ``height`` with the platform tilted by Rx(tilt_x) Ry(tilt_y).

    Leg k keeps C_k in the plane through A_k normal to u_k: ``(O + R c_k)·u_k = 0`` (``A_k·u_k = 0``).
    As ``u_1 + u_2 + u_3 = 0`` the three equations in ``O_x, O_y`` are compatible only when
    ``Σ (R c_k)·u_k = 0``, which fixes the turn γ of ``R = Rz(γ) Rx Ry`` (the parasitic motion, solved
    here by bisection near 0); then two of them give ``O_x, O_y`` (a 2×2 solve).  ``D_k`` (the cylinder's
    point on the leg) is the midpoint of ``A_k C_k``, ``A_k.u = A_k + u_k`` a second point of its R axis.
    """
    frames = rps_frames()
    tilt = _mul(_rot(0, tilt_x), _rot(1, tilt_y))

    def gap(g):
        r = _mul(_rot(2, g), tilt)
        return sum(sum(x * y for x, y in zip(_apply(r, c), u)) for _, u, c in frames)

    lo, hi = -0.5, 0.5
    assert gap(lo) * gap(hi) < 0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gap(lo) * gap(mid) <= 0:
            hi = mid
        else:
            lo = mid
    r = _mul(_rot(2, 0.5 * (lo + hi)), tilt)
    rc = [_apply(r, c) for _, _, c in frames]
    (u1, u2) = (frames[0][1], frames[1][1])
    b1 = -sum(x * y for x, y in zip(rc[0], u1))
    b2 = -sum(x * y for x, y in zip(rc[1], u2))
    det = u1[0] * u2[1] - u1[1] * u2[0]
    o = [(b1 * u2[1] - b2 * u1[1]) / det, (u1[0] * b2 - u2[0] * b1) / det, height]
    out = {"O": o}
    for k, ((a, u, _), c) in enumerate(zip(frames, rc), 1):
        ck = [o[i] + c[i] for i in range(3)]
        out[f"A{k}"], out[f"A{k}u"], out[f"C{k}"] = a, [a[i] + u[i] for i in range(3)], ck
        out[f"D{k}"] = [0.5 * (a[i] + ck[i]) for i in range(3)]
    return out


def rps_3_node(nodes: dict) -> dict:
    """3-RPS in node form: cylinder body A_k-A_k.u-D_k turning about its fixed axis A_k → A_k.u (R), the
    platform joint C_k sliding on the cylinder's line A_k-D_k (P, input ``slide:s_k``; a single shared
    point: S), platform body O-C1-C2-C3."""
    return {"name": "3-RPS parallel manipulator", "dim": 3, "mobility": 3,
            "fixed": [f"A{k}{s}" for k in (1, 2, 3) for s in ("", "u")],
            "inputs": [{"slide": f"s{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3,
            "nodes": {n: list(p) for n, p in nodes.items()},
            "links": {**{f"cyl{k}": [f"A{k}", f"A{k}u", f"D{k}"] for k in (1, 2, 3)},
                      "platform": ["O", "C1", "C2", "C3"]},
            "sliders": [{"id": f"s{k}", "node": f"C{k}", "line": [f"A{k}", f"D{k}"], "link": f"cyl{k}"}
                        for k in (1, 2, 3)]}


def rps_3(nodes: dict) -> dict:
    """3-RPS by its joints: per leg R (ground-cylinder about A_k → A_k.u), P (cylinder-rod along the leg,
    the input), S (rod-platform at C_k)."""
    joints = []
    for k in (1, 2, 3):
        a, c = nodes[f"A{k}"], nodes[f"C{k}"]
        joints += [_r(f"A{k}", "ground", f"cyl{k}", a, _sub(nodes[f"A{k}u"], a)),
                   {"id": f"P{k}", "type": "P", "links": [f"cyl{k}", f"rod{k}"], "at": a, "axis": _sub(c, a)},
                   {"id": f"S{k}", "type": "S", "links": [f"rod{k}", "platform"], "at": c}]
    links = {name: [] for k in (1, 2, 3) for name in (f"cyl{k}", f"rod{k}")}
    links["platform"] = ["O"]
    return {"name": "3-RPS by its joints", "dim": 3, "mobility": 3,
            "inputs": [{"joint": f"P{k}"} for k in (1, 2, 3)], "outputs": [{"twist": "platform"}],
            "platform": "platform", "platform_dof": 3, "nodes": {"O": nodes["O"]}, "links": links,
            "joints": joints}
