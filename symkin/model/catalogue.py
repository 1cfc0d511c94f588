"""Named mechanisms shared by tests, doctests, notebooks and benchmarks.

Each entry is a function returning the model dictionary (the model-file schema), so a
test can modify a copy before building it.  :func:`get` builds the mechanism.
Geometries are chosen so that every coordinate is exact in binary floating point where
a singular configuration depends on it.
"""
from __future__ import annotations

import math
from typing import Callable

from symkin.model.mechanism import Mechanism

__all__ = ["get", "names", "data"]

_ENTRIES: dict[str, Callable[[], dict]] = {}


def _entry(fn: Callable[[], dict]) -> Callable[[], dict]:
    _ENTRIES[fn.__name__] = fn
    return fn


@_entry
def fourbar_appendix() -> dict:
    """The four-bar of the paper's appendix (Fig. 17) in a generic configuration."""
    return {
        "name": "four-bar of the paper's appendix", "dim": 2, "fixed": ["A", "D"], "mobility": 1,
        "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "B": [0.2, 0.9], "C": [2.1, 1.3], "D": [2.0, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
    }


@_entry
def fourbar_dead_centre() -> dict:
    """Crank-rocker at the extended dead centre: crank and coupler aligned (DKP-output).

    A=(0,0), D=(4,0), crank 1, coupler 3, rocker 3: B=(1,0)·R, C on the extension of A→B
    at distance 4 from A.  With the crank along +x rotated by acos(...) the exact point
    is messy; instead the crank lies along the x axis rotated so that C is exact:
    B = (0.6, 0.8), C = 4·(0.6, 0.8) = (2.4, 3.2), |DC| = |(−1.6, 3.2)| = sqrt(12.8).
    """
    return {
        "name": "crank-rocker at a dead centre (crank and coupler aligned)", "dim": 2,
        "fixed": ["A", "D"], "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "B": [0.6, 0.8], "C": [2.4, 3.2], "D": [4.0, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
    }


@_entry
def fourbar_flat() -> dict:
    """Four-bar with all four joints on a line (IM: L = 2)."""
    return {
        "name": "flattened four-bar (increased mobility)", "dim": 2, "fixed": ["A", "D"], "mobility": 1,
        "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "B": [1.0, 0.0], "C": [3.0, 0.0], "D": [4.0, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
    }


@_entry
def slider_crank() -> dict:
    """Offset slider-crank: crank A-B, connecting rod B-C, slider C on the line y = 0.25."""
    return {
        "name": "offset slider-crank", "dim": 2, "fixed": ["A"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"slide": "piston"}],
        "nodes": {"A": [0.0, 0.0], "B": [0.6, 0.8], "C": [3.5, 0.25]},
        "links": {"crank": ["A", "B"], "rod": ["B", "C"]},
        "sliders": [{"id": "piston", "node": "C", "point": [0.0, 0.25], "direction": [1.0, 0.0]}],
    }


def _rrr_3(platform_angle: float = 0.0, name: str = "3-RRR planar parallel manipulator") -> dict:
    """3-RRR with base joints on a circle of radius 4, platform triangle of circumradius 1."""
    nodes, links = {}, {}
    r_base, r_pf, l1 = 4.0, 1.0, 2.0
    cx, cy = 0.0, 0.0
    for k in range(3):
        a = 2 * math.pi * k / 3 + math.pi / 2
        base = (r_base * math.cos(a), r_base * math.sin(a))
        pf = (cx + r_pf * math.cos(a + platform_angle), cy + r_pf * math.sin(a + platform_angle))
        # elbow: circle of radius l1 about the base meets circle about the platform joint
        dx, dy = pf[0] - base[0], pf[1] - base[1]
        d = math.hypot(dx, dy)
        l2 = 2.5
        along = (l1 * l1 - l2 * l2 + d * d) / (2 * d)
        h = math.sqrt(max(l1 * l1 - along * along, 0.0))
        ex = (base[0] + along * dx / d - h * dy / d, base[1] + along * dy / d + h * dx / d)
        nodes[f"A{k + 1}"], nodes[f"B{k + 1}"], nodes[f"C{k + 1}"] = list(base), list(ex), list(pf)
        links[f"crank{k + 1}"] = [f"A{k + 1}", f"B{k + 1}"]
        links[f"distal{k + 1}"] = [f"B{k + 1}", f"C{k + 1}"]
    links["platform"] = ["C1", "C2", "C3"]
    return {"name": name, "dim": 2, "fixed": ["A1", "A2", "A3"],
            "inputs": [{"rotation": f"crank{k}"} for k in (1, 2, 3)],
            "outputs": [{"twist": "platform"}], "platform": "platform", "platform_dof": 3,
            "nodes": nodes, "links": links}


@_entry
def rrr_3() -> dict:
    """A 3-RRR planar parallel manipulator in a regular configuration."""
    return _rrr_3(0.1)


@_entry
def five_bar() -> dict:
    """Five-bar (2RR) planar parallel manipulator, end-effector P, generic configuration."""
    return {
        "name": "five-bar (2RR)", "dim": 2, "fixed": ["A1", "A2"],
        "inputs": [{"rotation": "crank1"}, {"rotation": "crank2"}], "outputs": [{"velocity": "P"}],
        "nodes": {"A1": [-1.0, 0.0], "A2": [1.0, 0.0], "B1": [-1.6, 0.8], "B2": [1.6, 0.8],
                  "P": [0.0, 2.0]},
        "links": {"crank1": ["A1", "B1"], "crank2": ["A2", "B2"], "distal1": ["B1", "P"],
                  "distal2": ["B2", "P"]},
    }


@_entry
def rssr() -> dict:
    """Spatial RSSR four-bar: input crank about z, output rocker about x, coupler rod."""
    return {
        "name": "RSSR spatial four-bar", "dim": 3, "fixed": ["O1", "O1b", "O2", "O2b"],
        "inputs": [{"rotation": "crank", "axis": ["O1", "O1b"]}],
        "outputs": [{"rotation": "rocker", "axis": ["O2", "O2b"]}],
        "nodes": {"O1": [0.0, 0.0, 0.0], "O1b": [0.0, 0.0, 1.0], "B": [1.0, 0.0, 0.0],
                  "O2": [3.0, 0.0, 1.0], "O2b": [4.0, 0.0, 1.0], "C": [3.0, 1.0, 2.0]},
        "links": {"crank": ["O1", "O1b", "B"], "coupler": ["B", "C"], "rocker": ["O2", "O2b", "C"]},
    }


def names() -> tuple[str, ...]:
    """Names of the catalogue's mechanisms."""
    return tuple(_ENTRIES)


def data(name: str) -> dict:
    """The model dictionary of catalogue entry ``name`` (a fresh copy)."""
    try:
        return _ENTRIES[name]()
    except KeyError:
        raise KeyError(f"no mechanism {name!r} in the catalogue; known: {', '.join(_ENTRIES)}") from None


def get(name: str) -> Mechanism:
    """Build catalogue entry ``name``.

    >>> get("fourbar_appendix").dim
    2
    """
    return Mechanism.from_dict(data(name), source=f"catalogue:{name}")


# ---------------------------------------------------------------------- paths (pathsux)
@_entry
def peaucellier() -> dict:
    """Peaucellier–Lipkin inversor: P moves on a straight line while the crank turns C on a circle through O.

    Arms O-A, O-B (length 2.5), rhombus A-C-B-P (side √3.25), crank Q-C (length √0.5) whose
    circle passes through the fixed pivot O.  At the model's configuration O, C, P lie on the
    x axis, |OC|·|OP| = 1·3 = 2.5² − 3.25 (the inversion constant) and every coordinate is
    exact in binary.  The crank is a rocker: it turns back at the two flattened poses
    (A = B, O-A-C folded: |OC| = 2.5 − √3.25), where the rhombus collapses onto the line.
    """
    return {
        "name": "Peaucellier-Lipkin inversor", "dim": 2, "fixed": ["O", "Q"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"velocity": "P"}],
        "nodes": {"O": [0.0, 0.0], "Q": [0.5, 0.5], "C": [1.0, 0.0], "A": [2.0, 1.5], "B": [2.0, -1.5],
                  "P": [3.0, 0.0]},
        "links": {"crank": ["Q", "C"], "arm_a": ["O", "A"], "arm_b": ["O", "B"], "side_ac": ["A", "C"],
                  "side_bc": ["B", "C"], "side_ap": ["A", "P"], "side_bp": ["B", "P"]},
    }


# ---------------------------------------------------------------------- structures and overconstrained
# mechanisms (statics: self-stresses, redundant constraints; issue 7)
@_entry
def braced_square() -> dict:
    """Unit square with both diagonals, pinned at A and B: a rigid structure with one self-stress.

    Sides in tension ``s``, diagonals in compression ``−√2 s`` (equilibrium at a corner:
    ``s (1, 0) + s (0, 1) + d (1, 1)/√2 = 0``).  Bar A-B joins two fixed nodes: the ground
    carries its force, so the stress is reported on the other five bars.
    """
    return {
        "name": "braced square (both diagonals)", "dim": 2, "fixed": ["A", "B"], "mobility": 0,
        "nodes": {"A": [0.0, 0.0], "B": [1.0, 0.0], "C": [1.0, 1.0], "D": [0.0, 1.0]},
        "links": {"AB": ["A", "B"], "BC": ["B", "C"], "CD": ["C", "D"], "DA": ["D", "A"],
                  "AC": ["A", "C"], "BD": ["B", "D"]},
    }


@_entry
def pratt_truss() -> dict:
    """Four-panel Pratt truss on a pin (L0) and a roller (L4): statically determinate, rigid.

    8 joints, 13 bars, 3 support reactions: ``13 + 3 = 2·8`` and the truss is rigid, so
    no self-stress and no flex.
    """
    nodes = {f"L{k}": [2.0 * k, 0.0] for k in range(5)}
    nodes.update({f"U{k}": [2.0 * k, 2.0] for k in (1, 2, 3)})
    links = {f"L{k}L{k + 1}": [f"L{k}", f"L{k + 1}"] for k in range(4)}
    links.update({"U1U2": ["U1", "U2"], "U2U3": ["U2", "U3"], "L0U1": ["L0", "U1"], "L4U3": ["L4", "U3"]})
    links.update({f"U{k}L{k}": [f"U{k}", f"L{k}"] for k in (1, 2, 3)})
    links.update({"U1L2": ["U1", "L2"], "U3L2": ["U3", "L2"]})
    return {
        "name": "Pratt truss, pin and roller", "dim": 2, "fixed": ["L0"], "mobility": 0,
        "nodes": nodes, "links": links,
        "sliders": [{"id": "roller", "node": "L4", "point": [8.0, 0.0], "direction": [1.0, 0.0]}],
    }


@_entry
def collinear_truss() -> dict:
    """Two bars A-B-C on one line between fixed A and C: a structure with a flex (IM).

    Node B can move normal to the line to first order (L = 1, F = 0) and the two bars
    carry one self-stress (equal tensions).
    """
    return {
        "name": "two collinear bars between fixed nodes", "dim": 2, "fixed": ["A", "C"], "mobility": 0,
        "nodes": {"A": [0.0, 0.0], "B": [1.0, 0.0], "C": [2.0, 0.0]},
        "links": {"AB": ["A", "B"], "BC": ["B", "C"]},
    }


@_entry
def double_parallelogram() -> dict:
    """Three parallel, equal cranks A-B, D-C, E-F carrying a triangular coupler B-C-F (F = 1).

    The coupler is the ground triangle A-D-E translated by the crank vector (0.5, 1), so
    it translates on a circle.  Grübler: 5 links, 6 revolutes, ``3·4 − 2·6 = 0`` < F = 1:
    one redundant constraint.
    """
    return {
        "name": "double parallelogram (redundant third crank)", "dim": 2, "fixed": ["A", "D", "E"],
        "mobility": 1, "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "D": [2.0, 0.0], "E": [1.0, -1.0],
                  "B": [0.5, 1.0], "C": [2.5, 1.0], "F": [1.5, 0.0]},
        "links": {"crank": ["A", "B"], "middle": ["D", "C"], "rocker": ["E", "F"],
                  "coupler": ["B", "C", "F"]},
    }


@_entry
def bennett() -> dict:
    """Bennett linkage: a spatial 4R loop (F = 1) that Grübler–Kutzbach gives −2.

    The common normals of the four axes form a skew isogram A-B-C-D (opposite sides
    equal: C, D are A, B turned by 180° about z) and each axis is normal to the two sides
    meeting at its vertex.  Each revolute is two nodes on its axis (A, A2, ...); A-D is
    ground (axes A and D fixed).  Integer coordinates: every row is exact.
    """
    a, b = (2.0, 1.0, 1.0), (1.0, -2.0, -1.0)
    c, d = (-a[0], -a[1], a[2]), (-b[0], -b[1], b[2])

    def axis(p, q, r, step):  # second node on the axis at p, normal to p→q and p→r
        u = [q[k] - p[k] for k in range(3)]
        v = [r[k] - p[k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        return [p[k] + step * n[k] for k in range(3)]

    # the axes at B and D meet on the z axis: different steps keep B2 and D2 apart
    nodes = {"A": list(a), "A2": axis(a, b, d, 0.25), "B": list(b), "B2": axis(b, c, a, 0.125),
             "C": list(c), "C2": axis(c, d, b, 0.25), "D": list(d), "D2": axis(d, a, c, 0.25)}
    return {
        "name": "Bennett linkage", "dim": 3, "fixed": ["A", "A2", "D", "D2"], "mobility": 1,
        "inputs": [{"rotation": "link1", "axis": ["A", "A2"]}],
        "outputs": [{"rotation": "link3", "axis": ["D", "D2"]}],
        "nodes": nodes,
        "links": {"link1": ["A", "A2", "B", "B2"], "link2": ["B", "B2", "C", "C2"],
                  "link3": ["C", "C2", "D", "D2"]},
    }


# ---------------------------------------------------------------------- Watt six-bar (issue 7 §8)
@_entry
def watt_sixbar() -> dict:
    """Watt II six-bar in a generic configuration: two four-bars in series.

    Ground A-D-F and the rocker D-C-E are the two ternary links (they share joint D): the
    crank A-B drives the rocker through the coupler B-C, and the rocker drives the output
    F-G through the link E-G.  Coordinates are non-round on purpose (measured values), so
    that lengths and body angles have no short exact form; the transmission angles are far
    from 0 and 180° (every |sin| > 0.88).

    >>> from symkin import analyze
    >>> r = analyze(get("watt_sixbar"))
    >>> r.dof, r.types
    (1, ())
    """
    return {
        "name": "Watt II six-bar", "dim": 2, "fixed": ["A", "D", "F"], "mobility": 1,
        "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "output"}],
        "nodes": {"A": [0.0, 0.0], "B": [0.0245, 1.4049], "C": [2.7011, 2.1044], "D": [2.9, 0.0],
                  "E": [3.9079, 2.4269], "F": [5.6042, 0.3117], "G": [5.4376, 2.5769]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C", "E"],
                  "link": ["E", "G"], "output": ["F", "G"]},
    }
