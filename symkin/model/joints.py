"""Joints (kinematic pairs) of a model file, compiled to the nodal method's nodes, links and sliders.

A model may describe a mechanism by its pairs (``[[joints]]``, README "Model files"): each
joint joins two links (``"ground"`` is the fixed frame) at a point ``at``, with an ``axis``
(R, P, C in space; P in the plane), for U a second axis ``axis2``, and the keys of its kind.
Each type is a :class:`~symkin.model.pairs.JointKind` of the registry
:mod:`symkin.model.pairs`; this module registers those the nodal method of the paper
expresses with what it already has (Altuzarra et al. 2004, §II: shared nodes, bars, bodies;
the README's sliders).  A pair with a constraint of its own is one module of
:mod:`symkin.constraints` that registers its kind (its compilation is documented there):

======  ==================================================================================
type    compiled to
======  ==================================================================================
R (2D)  one node shared by both links, named after the joint (``R1``)
S (3D)  one node shared by both links (``S1``)
R (3D)  two nodes shared by both links, on the axis: ``R1`` at ``at`` and ``R1.axis`` at
        ``at + ℓ·axis`` (two spatial bodies sharing two nodes turn about that axis)
U (3D)  an added cross link ``U1.cross`` with three nodes: the centre ``U1`` (shared by
        the three links), ``U1.axis`` on ``axis`` (shared with the first link: an R) and
        ``U1.axis2`` on ``axis2`` (shared with the second link: an R)
C (3D)  the second link (the runner) gets two nodes on the joint's line, ``C1`` at ``at``
        and ``C1.end`` at ``at + ℓ·axis``, each a slider on the moving line through
        ``C1.base`` (at ``at``) and ``C1.line`` (at ``at + ℓ·axis``) of the first link (the
        guide); with ground as a link, sliders on the fixed line
P (2D)  as C: in the plane two nodes on a line leave only the slide
P (3D)  as C, plus the key that stops the rotation about the line when neither link is a
        rod along the line (a rod's spin about its own line is no coordinate of the nodal
        method): ``P1.keyed`` of the runner slides on the line ``P1.key``-``P1.keyline`` of
        the guide, parallel to the joint's line; its row across the two lines repeats one
        of the main sliders' rows, so the statics count one self-stress per keyed P
======  ==================================================================================

``ℓ`` is the model's own length (the mean distance between all given points: nodes and
joint points), so that a model in millimetres and the same model in metres compile alike.
A node is reused rather than added when its link already has one at the point (within the
geometric tolerance): an R and a P at the same point of a cylinder share its node.  A link
listed with its nodes keeps them and gains the joints' nodes; a link listed as a bar (two
nodes) must be joined on its line (else it would be a body).

Joint rates are expressed as the existing kinematic parameters (:class:`Parameter`),
labelled ``joint:<id>``: a planar R between two moving links is the planar ``joint``
parameter (ω₂ − ω₁), a joint to ground the rotation of the moving link (about ``axis`` in
space; about ``-axis`` when ground is the second link; in the plane,
ground second, the planar ``joint`` parameter from the link to ``ground``, whose rotation is zero), P and the slide of C the slide of
the slider ``<id>`` (relative slide of the second link along ``axis``).  The rotation rate of
a spatial joint between two moving links (R, the rotation of C, either axis of U) is the
spatial ``joint`` parameter ``a·(ω₂ − ω₁)`` about the joint's axis ``a`` given by two of its
nodes (``R1``-``R1.axis``; ``U1``-``U1.axis`` for axis 1, the cross turning on the first
link; ``U1``-``U1.axis2`` for axis 2, the second link turning on the cross; ``C1.base``-``C1.line``
of the guide for C), so that the axis moves with the links.  A link whose nodes all lie on
that axis (a rod along it) has no spin the nodes can measure: asking for such a rate is a
model error naming the joint.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace
from typing import Any, Mapping

from symkin.errors import Problem
from symkin.model.mechanism import Parameter, length_scale
from symkin.model.pairs import BASE_JOINT_KEYS, JointKind, joint_keys, joint_kind, joint_kinds, joint_types, key_owners, register_joint

__all__ = ["Joint", "CompiledJoints", "Limits", "GROUND", "compile_joints", "unit_normal", "offset"]

#: the name of the fixed frame in a joint's ``links``
GROUND = "ground"


@dataclass(frozen=True)
class Joint:
    """One kinematic pair of a model file, as given (``axis`` and ``axis2`` normalised)."""

    id: str
    type: str
    links: tuple[str, str]
    at: tuple[float, ...]
    axis: tuple[float, ...] | None = None
    axis2: tuple[float, ...] | None = None
    #: the values of its kind's own keys (:attr:`~symkin.model.pairs.JointKind.keys`) as
    #: ``(name, value)``, in the order of :func:`~symkin.model.pairs.joint_keys`; read them as
    #: attributes (``joint.<name>``)
    params: tuple[tuple[str, float], ...] = ()

    def __getattr__(self, name: str):
        """A key of a joint kind (:func:`~symkin.model.pairs.joint_keys`): its value, None when
        this joint's kind has no such key."""
        if name.startswith("__") or name not in joint_keys():
            raise AttributeError(f"'Joint' object has no attribute {name!r}")
        return dict(self.__dict__.get("params", ())).get(name)

    def to_dict(self) -> dict:
        out: dict = {"id": self.id, "type": self.type, "links": list(self.links), "at": list(self.at)}
        if self.axis is not None:
            out["axis"] = list(self.axis)
        if self.axis2 is not None:
            out["axis2"] = list(self.axis2)
        for name, value in self.params:
            out[name] = value
        return out

    def moved(self, turn, place, scale: float) -> "Joint":
        """The joint after the similarity ``x ↦ scale·R x + t`` (``turn``: ``v ↦ R v``; ``place``: a
        point's image); the kind's length keys scale."""
        kind = joint_kind(self.type)
        lengths = {k.name for k in kind.keys if k.length} if kind is not None else set()
        return replace(self, at=place(self.at), axis=self.axis and turn(self.axis),
                       axis2=self.axis2 and turn(self.axis2),
                       params=tuple((n, scale * v if n in lengths else v) for n, v in self.params))


@dataclass(frozen=True)
class CompiledJoints:
    """The node form of a joint model and what the joints became.

    ``data`` is the model dictionary with nodes, links, fixed nodes and sliders of the
    joints added and the ``joints`` key removed; ``joints`` the parsed joints;
    ``rates`` the joint rates that existing parameters express, as ``(label, Parameter)``;
    ``problems`` every problem found (the key names the joint).
    """

    data: dict
    joints: tuple[Joint, ...]
    rates: tuple[tuple[str, Parameter], ...]
    problems: tuple[Problem, ...]


@dataclass(frozen=True)
class Limits:
    """The bounds of a model's numbers (:mod:`symkin.model.validation` passes its own).

    ``coordinate``: largest magnitude of a coordinate or an axis component;
    ``length``: smallest norm of an axis.
    """

    geometry: float
    coordinate: float
    length: float

    def number(self, v: Any) -> bool:
        """A finite number within ``±coordinate`` (an integer too large for a float is not)."""
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            return False
        try:
            return math.isfinite(float(v)) and abs(float(v)) <= self.coordinate
        except OverflowError:
            return False


def _unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def _dot(a, b) -> float:
    return sum(x * y for x, y in zip(a, b))


def offset(p, v, s: float = 1.0):
    """The point ``p + s·v``."""
    return tuple(a + s * b for a, b in zip(p, v))


def unit_normal(u):
    """A unit vector normal to the unit vector ``u`` (3D), picked from the axis least along it."""
    k = min(range(3), key=lambda i: abs(u[i]))
    e = [0.0, 0.0, 0.0]
    e[k] = 1.0
    w = (u[1] * e[2] - u[2] * e[1], u[2] * e[0] - u[0] * e[2], u[0] * e[1] - u[1] * e[0])
    return _unit(w)


def _parse_joint(item: Any, k: int, dim: int, links: Mapping, counts: dict, limits: Limits,
                 problems: list) -> Joint | None:
    key = f"joints[{k}]"

    def bad(message: str, where: str = key) -> None:
        problems.append(Problem(where, message))

    if not isinstance(item, Mapping):
        bad("must be a table with type, links and at")
        return None
    jtype = item.get("type")
    jid = item.get("id")
    if jid is not None and (not isinstance(jid, str) or not jid or "." in jid):
        bad(f"id must be a non-empty string without '.', got {jid!r}")
        return None
    if isinstance(jtype, str) and jid is None:
        counts[jtype] = counts.get(jtype, 0) + 1
        jid = f"{jtype}{counts[jtype]}"
    where = f"{key} ({jid})" if jid else key
    keys = joint_keys()
    extra = [x for x in item if x not in keys]
    if extra:
        bad(f"unknown key(s) {', '.join(map(repr, extra))} (allowed: {', '.join(keys)})", where)
    allowed = joint_types(dim)
    kind = joint_kind(jtype)
    if kind is None:
        bad(f"type must be one of {', '.join(allowed)} (dim = {dim}), got {jtype!r}", where)
        return None
    if jtype not in allowed:
        what = "planar" if dim == 2 else "spatial"
        bad(f"type {jtype!r} is not allowed in a {what} model (dim = {dim}): "
            f"{what} joints are {', '.join(allowed)}", where)
        return None
    pair = item.get("links")
    if not (isinstance(pair, (list, tuple)) and len(pair) == 2 and all(isinstance(x, str) for x in pair)):
        bad(f"links must be the two link names it joins (\"{GROUND}\" = the fixed frame), got {pair!r}", where)
        return None
    ok = True
    for name in pair:
        if name != GROUND and name not in links:
            bad(f"unknown link {name!r} (the links are {', '.join(map(repr, links)) or 'none'}; "
                f"\"{GROUND}\" is the fixed frame)", where)
            ok = False
    if pair[0] == pair[1]:
        bad(f"joins link {pair[0]!r} to itself", where)
        ok = False
    at = item.get("at")
    if not (isinstance(at, (list, tuple)) and len(at) == dim and all(limits.number(v) for v in at)):
        bad(f"at must be {dim} finite numbers (the joint's point), got {at!r}", where)
        ok = False
    axes = []
    for name in ("axis", "axis2"):
        needed = (dim in kind.axis) if name == "axis" else kind.axis2
        value = item.get(name)
        if value is None:
            if needed:
                bad(f"a {jtype} joint needs '{name}'", where)
                ok = False
            axes.append(None)
            continue
        if not needed:
            bad(f"'{name}' does not go with a {'planar ' if dim == 2 else ''}{jtype} joint", where)
            ok = False
            axes.append(None)
            continue
        if not (isinstance(value, (list, tuple)) and len(value) == dim and all(limits.number(v) for v in value)):
            bad(f"{name} must be {dim} finite numbers, got {value!r}", where)
            ok = False
            axes.append(None)
            continue
        norm = math.sqrt(sum(float(v) ** 2 for v in value))
        if not norm >= limits.length:
            bad(f"zero {name} {list(value)!r}: a joint axis needs a direction", where)
            ok = False
            axes.append(None)
            continue
        axes.append(_unit(tuple(float(v) for v in value)))
    params = []
    own = {k.name: k for k in kind.keys}
    for name in keys[len(BASE_JOINT_KEYS):]:  # the kinds' own keys
        value = item.get(name)
        spec = own.get(name)
        if spec is None:
            if value is not None:
                owners = " or ".join(k.name for k in key_owners(name))
                bad(f"'{name}' goes with {owners}, not with a {jtype} joint", where)
                ok = False
        elif value is None:
            bad(f"{kind.name} needs '{name}' ({spec.needs})", where)
            ok = False
        elif not limits.number(value):
            bad(f"{name} must be {spec.must}, got {value!r}", where)
            ok = False
        else:
            params.append((name, float(value)))
    if not ok:
        return None
    return Joint(id=jid, type=jtype, links=(pair[0], pair[1]), at=tuple(float(v) for v in at),
                 axis=axes[0], axis2=axes[1], params=tuple(params))


class _Builder:
    """Nodes, links, fixed nodes, sliders and extra records of the node form, built joint by joint.

    What a kind's compile step (:attr:`~symkin.model.pairs.JointKind.compile`) uses:
    :meth:`shared` (a node of some links at a point, made if new), :meth:`line` (the two
    runner nodes of a P or C on the guide's line), :meth:`extra` (a record of an extra
    constraint, as a table of the model dictionary), :meth:`along`; ``reach`` (the model's
    length, the distance of added axis nodes), ``dim``, ``tol``, ``links``, ``nodes`` and
    ``problems`` (a list of :class:`~symkin.errors.Problem`).
    """

    def __init__(self, data: Mapping, dim: int, reach: float, tol: float, problems: list):
        self.nodes = {n: tuple(float(c) for c in p) for n, p in (data.get("nodes") or {}).items()}
        self.links = {n: list(ns) for n, ns in data["links"].items()}
        self.given = {n: tuple(ns) for n, ns in self.links.items() if ns}  # links listed with their nodes
        self.fixed = list(data.get("fixed", []))
        self.sliders: list[dict] = []
        self.extras: dict[str, list[dict]] = {}
        self.dim, self.reach, self.tol, self.problems = dim, reach, tol, problems

    def extra(self, key: str, item: dict) -> None:
        """Add ``item`` to the list of tables under ``key`` (an extra constraint's model-dictionary key)."""
        self.extras.setdefault(key, []).append(item)

    def near(self, names, point):
        return [n for n in names if n in self.nodes and len(self.nodes[n]) == len(point)
                and math.dist(self.nodes[n], point) <= self.tol]

    def shared(self, joint: Joint, links, point, name: str) -> str | None:
        """The one node at ``point`` of every link in ``links`` (``GROUND``: a fixed node), made if new."""
        found: list[str] = []
        for link in links:
            pool = self.fixed if link == GROUND else self.links[link]
            for n in self.near(pool, point):
                if n not in found:
                    found.append(n)
        where = f"joints ({joint.id})"
        if len(found) > 1:
            self.problems.append(Problem(where, f"links {' and '.join(links)} have different nodes "
                                                f"({', '.join(found)}) at the joint's point"))
            return None
        if found:
            node = found[0]
        else:
            if name in self.nodes:
                self.problems.append(Problem(where, f"node {name!r} already exists elsewhere: "
                                                    "rename the node or the joint"))
                return None
            node, self.nodes[name] = name, tuple(point)
        for link in links:
            if link == GROUND:
                if node not in self.fixed:
                    self.fixed.append(node)
            elif node not in self.links[link]:
                self.links[link].append(node)
        return node

    def check_on(self, joint: Joint) -> bool:
        """A link given as a bar (two nodes listed) is joined on its line: otherwise it would be a body."""
        ok = True
        for link in joint.links:
            ns = self.given.get(link, ())
            if len(ns) == 2 and ns[0] in self.nodes and ns[1] in self.nodes:
                a, c = self.nodes[ns[0]], self.nodes[ns[1]]
                if math.dist(a, c) == 0.0:  # a zero-length bar: the node checks report it
                    continue
                u = _unit(tuple(y - x for x, y in zip(a, c)))
                if not self.along_line(joint.at, a, u):
                    self.problems.append(Problem(f"joints ({joint.id})", (
                        f"the point {list(joint.at)!r} is not on link {link}, the bar {ns[0]}-{ns[1]} "
                        f"(beyond {self.tol:.3g}): join a bar on its line, or list the link as a body")))
                    ok = False
        return ok

    def along_line(self, point, at, u) -> bool:
        d = tuple(a - b for a, b in zip(point, at))
        t = _dot(d, u)
        return _dot(d, d) - t * t <= self.tol ** 2

    def line(self, joint: Joint) -> None:
        """A P or C: two runner nodes on the guide's line (the key of a spatial P: :func:`_key`)."""
        guide, runner = joint.links
        sign = 1.0
        if runner == GROUND:
            guide, runner, sign = runner, guide, -1.0
        u, at, jid = joint.axis, joint.at, joint.id
        end = offset(at, u, self.reach)
        if guide == GROUND:
            way = {"point": list(at), "direction": [sign * c for c in u]}
        else:
            base = self.shared(joint, [guide], at, f"{jid}.base")
            tip = self.shared(joint, [guide], end, f"{jid}.line")
            if base is None or tip is None:
                return
            way = {"line": [base, tip], "link": guide}
        for name, point in ((jid, at), (f"{jid}.end", end)):
            node = self.shared(joint, [runner], point, name)
            if node is None:
                return
            self.sliders.append({"id": name, "node": node, **way})

    def along(self, link: str, at, u) -> bool:
        """Every node of ``link`` on the line through ``at`` along ``u`` (a rod on that line)."""
        return all(self.along_line(self.nodes[n], at, u) for n in self.links[link])


def _rate(joint: Joint, dim: int, motion: str, where: str, problems: list,
          axes: Mapping | None = None) -> Parameter | None:
    """The rate ``motion`` ("rotation" or "slide"; U: "1", "2") of ``joint`` as an existing parameter.

    ``axes`` maps ``(joint id, motion)`` to the two nodes on the joint's axis (see
    :func:`_axis_nodes`) for a spatial rotation between two moving links; without it such a
    rate is not made (and nothing is reported).
    """
    first, second = joint.links
    label = f"joint:{joint.id}" if len(_motions(joint)) == 1 else f"joint:{joint.id}.{motion}"
    if motion == "slide":
        return Parameter("slide", (joint.id,), label=label)
    if dim == 2:
        if GROUND not in joint.links:
            return Parameter("joint", (first, second), label=label)
        if first == GROUND:
            return Parameter("rotation", (second,), label=label)
        return Parameter("joint", (first, GROUND), label=label)  # ground's rotation (zero) minus first's
    first, second, axis = _rate_links(joint, motion)
    if first == GROUND:
        return Parameter("rotation", (second,), axis=axis, label=label)
    if second == GROUND:
        return Parameter("rotation", (first,), axis=tuple(-c for c in axis), label=label)
    if axes is None:
        return None
    got = axes.get((joint.id, motion))
    if got is None:  # not placed: the model has other problems, reported already
        return None
    if isinstance(got, str):  # a problem found while placing the axis
        problems.append(Problem(where, got))
        return None
    return Parameter("joint", (first, second), axis=got, label=label)


def _rate_links(joint: Joint, motion: str) -> tuple[str, str, tuple]:
    """The two links whose relative rotation is the rate ``motion`` of a spatial joint, and its axis.

    The kind's :attr:`~symkin.model.pairs.JointKind.rate_links` (U: :func:`_u_rate_links`), by
    default the second link turning on the first about ``axis`` (R, C).
    """
    kind = joint_kind(joint.type)
    if kind.rate_links is not None:
        return kind.rate_links(joint, motion)
    first, second = joint.links
    return first, second, joint.axis


def _axis_nodes(b: "_Builder", joint: Joint, motion: str):
    """The two nodes on the axis of a spatial rotation between two moving links, or a problem.

    The nodes at ``at`` and ``at + ℓ·axis`` (``axis2`` for U's axis 2) of the rate's first
    link (for R and U shared with the second link; for C the guide's line), from the first
    to the second (the axis' direction).  A problem (a string) when one of the two links is a
    rod along that axis: the nodes do not measure its spin about its own line.
    """
    first, second, axis = _rate_links(joint, motion)
    ends = []
    for point in (joint.at, offset(joint.at, axis, b.reach)):
        found = b.near(b.links[first], point)
        if not found:
            return f"joint {joint.id}: no node of link {first} on its axis"
        ends.append(found[0])
    for link in (first, second):
        if b.along(link, joint.at, axis):
            return (f"the rotation rate of joint {joint.id} is not defined: link {link} is a rod along "
                    f"the joint's axis (all its nodes on it), so its spin about the axis moves no node")
    return (ends[0], ends[1])


def _motions(joint: Joint) -> tuple[str, ...]:
    """The rates a joint has (its kind's :attr:`~symkin.model.pairs.JointKind.motions`)."""
    return joint_kind(joint.type).motions


def _and(words) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    words = list(words)
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def _joint_parameter(item: Mapping, where: str, by_id: dict, dim: int, problems: list,
                     axes: Mapping | None = None):
    """A ``{joint = "R1", ...}`` entry → the parameter dictionary it stands for, or None.

    ``axes``: the axis nodes of spatial rotations between moving links (see :func:`_rate`).
    """
    joint = by_id.get(item["joint"])
    if joint is None:
        problems.append(Problem(where, f"unknown joint {item['joint']!r}"))
        return None
    choosers = [k for k in joint_kinds() if k.choice is not None]
    choice_keys = list(dict.fromkeys(k.choice[0] for k in choosers))
    extra = [k for k in item if k not in ["joint", "label"] + choice_keys]
    if extra:
        problems.append(Problem(where, f"unknown key(s) {', '.join(map(repr, extra))} for a joint rate"))
        return None
    kind = joint_kind(joint.type)
    if kind.choice is not None:
        key, values = kind.choice
        value = item.get(key)
        if value not in values or isinstance(value, bool):
            problems.append(Problem(where, f"joint {joint.id} is {kind.article} {joint.type}: give {key} = "
                                           + " or ".join(json.dumps(v) for v in values)))
            return None
        motion = str(value)
    elif not kind.motions:
        problems.append(Problem(where, f"joint {joint.id} is {kind.article} {joint.type}: it has no single "
                                       "rate; use rotations of its links"))
        return None
    else:
        if any(k in item for k in choice_keys):
            problems.append(Problem(where, f"{_and(repr(k) for k in choice_keys)} go with "
                                           f"{_and(k.type for k in choosers)} joints, not with "
                                           f"{joint.type} joint {joint.id}"))
            return None
        motion = kind.motions[0]
    p = _rate(joint, dim, motion, where, problems, axes)
    if p is None:
        return None
    out = p.to_dict()
    if "label" in item:
        out["label"] = item["label"]
    return out


def compile_joints(data: Mapping, dim: int, limits: Limits) -> CompiledJoints:
    """The node form of a model with ``joints`` (see the module docstring).

    ``data`` is the model dictionary as read; ``dim`` its (valid) dimension; ``limits``
    the relative tolerance of geometric checks (:attr:`symkin.Tolerances.geometry`) and the
    bounds of numbers.  Nothing is raised: problems are returned.

    Examples
    --------
    >>> c = compile_joints({"dim": 2, "links": {"crank": [], "rocker": []},
    ...                     "joints": [{"type": "R", "links": ["ground", "crank"], "at": [0, 0]},
    ...                                {"type": "R", "links": ["crank", "rocker"], "at": [1, 0]}]},
    ...                    2, Limits(geometry=1e-6, coordinate=1e100, length=1e-100))
    >>> c.data["links"], c.data["fixed"]
    ({'crank': ['R1', 'R2'], 'rocker': ['R2']}, ['R1'])
    """
    problems: list[Problem] = []
    items = data.get("joints")
    links = data.get("links")
    if not isinstance(items, (list, tuple)):
        return CompiledJoints(dict(data), (), (), (Problem("joints", "must be a list of tables ([[joints]])"),))
    if not isinstance(links, Mapping) or not all(
            isinstance(v, (list, tuple)) and all(isinstance(n, str) for n in v) for v in links.values()):
        return CompiledJoints(dict(data), (), (), (Problem("links", "must be a table of link name = "
                                                                    "[node names] (or [] for a link its "
                                                                    "joints define)"),))
    if GROUND in links:
        problems.append(Problem(f"links.{GROUND}", f"\"{GROUND}\" names the fixed frame in joints: "
                                                   "rename the link"))
    nodes = data.get("nodes") or {}
    if not isinstance(nodes, Mapping) or not all(
            isinstance(p, (list, tuple)) and len(p) == dim and all(limits.number(v) for v in p) for p in nodes.values()):
        return CompiledJoints(dict(data), (), (), (Problem("nodes", f"with joints, nodes must be a table of "
                                                                    f"name = [{dim} finite numbers within "
                                                                    f"±{limits.coordinate:g}]"),))
    fixed = data.get("fixed", [])
    if not isinstance(fixed, (list, tuple)) or not all(isinstance(n, str) and n in nodes for n in fixed):
        return CompiledJoints(dict(data), (), (), (Problem("fixed", "must be a list of node names"),))
    counts: dict[str, int] = {}
    joints, seen = [], {}
    for k, item in enumerate(items):
        j = _parse_joint(item, k, dim, links, counts, limits, problems)
        if j is None:
            continue
        if j.id in seen:
            problems.append(Problem(f"joints[{k}] ({j.id})", f"duplicate joint id {j.id!r} "
                                                              f"(also joints[{seen[j.id]}])"))
            continue
        seen[j.id] = k
        joints.append(j)
    for j in joints:
        check = joint_kind(j.type).check
        message = check(j, limits) if check is not None else None
        if message is not None:
            problems.append(Problem(f"joints ({j.id})", message))
    if problems:
        return CompiledJoints(dict(data), tuple(joints), (), tuple(problems))

    points = [tuple(map(float, p)) for p in nodes.values()] + [j.at for j in joints]
    reach = length_scale(dict(enumerate(points)), [range(len(points))])
    b = _Builder(data, dim, reach, limits.geometry * reach, problems)
    for j in joints:
        if b.check_on(j):
            joint_kind(j.type).compile(b, j)
    for j in joints:  # second passes (the key of a spatial P), once every joint has placed its nodes
        finish = joint_kind(j.type).finish
        if finish is not None and not problems:
            finish(b, j)

    axes = {(j.id, m): _axis_nodes(b, j, m) for j in joints if dim == 3 and not problems
            for m in _motions(j) if m != "slide" and GROUND not in _rate_links(j, m)[:2]}
    rates = []
    for j in joints:
        for motion in _motions(j):
            p = _rate(j, dim, motion, "", [], axes)
            if p is not None:
                rates.append((p.label, p))
    by_id = {j.id: j for j in joints}
    out = {k: v for k, v in data.items() if k != "joints"}
    for where in ("inputs", "outputs"):
        params = data.get(where)
        if not isinstance(params, (list, tuple)):
            continue
        new = []
        for k, item in enumerate(params):
            if isinstance(item, Mapping) and isinstance(item.get("joint"), str):
                item = _joint_parameter(item, f"{where}[{k}]", by_id, dim, problems, axes)
                if item is None:
                    continue
            new.append(item)
        out[where] = new
    out["nodes"] = {n: list(p) for n, p in b.nodes.items()}
    out["links"] = {n: ns for n, ns in b.links.items()}
    out["fixed"] = b.fixed
    sliders = data.get("sliders", [])
    out["sliders"] = list(sliders) + b.sliders if isinstance(sliders, (list, tuple)) else sliders
    for key, items in b.extras.items():  # the records of extra constraints (kinds of symkin.constraints)
        given = data.get(key, [])
        out[key] = list(given) + items if isinstance(given, (list, tuple)) else given
    return CompiledJoints(out, tuple(joints), tuple(rates), tuple(problems))


def _key(b: _Builder, j: Joint) -> None:
    """The key of a spatial P between two links that are not rods along its line."""
    guide, runner = j.links
    sign = 1.0
    if runner == GROUND:
        guide, runner, sign = runner, guide, -1.0
    u, at, reach = j.axis, j.at, b.reach
    off = offset(at, unit_normal(u), reach)
    if guide == GROUND:
        way = {"point": list(off), "direction": [sign * c for c in u]}
    else:
        a = b.shared(j, [guide], off, f"{j.id}.key")
        c = b.shared(j, [guide], offset(off, u, reach), f"{j.id}.keyline")
        if a is None or c is None:
            return
        way = {"line": [a, c], "link": guide}
    node = b.shared(j, [runner], off, f"{j.id}.keyed")
    if node is not None:
        b.sliders.append({"id": f"{j.id}.keyed", "node": node, **way})


# ---------------------------------------------------------------------- the built-in joint kinds
def _point(b: _Builder, j: Joint) -> None:
    """S, planar R: one node shared by both links."""
    b.shared(j, list(j.links), j.at, j.id)


def _revolute(b: _Builder, j: Joint) -> None:
    """R: in the plane a shared node; in space two shared nodes on the axis."""
    if b.dim == 2:
        _point(b, j)
    elif b.shared(j, list(j.links), j.at, j.id) is not None:
        b.shared(j, list(j.links), offset(j.at, j.axis, b.reach), f"{j.id}.axis")


def _universal(b: _Builder, j: Joint) -> None:
    """U: the cross link, sharing the centre with both links and one axis node with each."""
    first, second = j.links
    cross = f"{j.id}.cross"
    if cross in b.links:
        b.problems.append(Problem(f"joints ({j.id})", f"link {cross!r} exists: rename the link or the joint"))
        return
    b.links[cross] = []
    if b.shared(j, [first, cross, second], j.at, j.id) is not None:
        b.shared(j, [first, cross], offset(j.at, j.axis, b.reach), f"{j.id}.axis")
        b.shared(j, [cross, second], offset(j.at, j.axis2, b.reach), f"{j.id}.axis2")


def _perpendicular(j: Joint, limits: Limits) -> str | None:
    """U: the two axes normal to each other (within the geometric tolerance, in the cosine)."""
    if abs(_dot(j.axis, j.axis2)) <= limits.geometry:
        return None
    angle = math.degrees(math.acos(max(-1.0, min(1.0, _dot(j.axis, j.axis2)))))
    return (f"the axes of U joint {j.id} are not perpendicular ({angle:.6g}°; tolerance "
            f"{limits.geometry:g} in the cosine)")


def _u_rate_links(j: Joint, motion: str) -> tuple[str, str, tuple]:
    """U's axis 1 is the cross turning on the first link about ``axis``, axis 2 the second link
    turning on the cross about ``axis2``."""
    first, second = j.links
    cross = f"{j.id}.cross"
    return (first, cross, j.axis) if motion == "1" else (cross, second, j.axis2)


def _keyed(b: _Builder, j: Joint) -> None:
    """Spatial P: the key, unless one of its links is a rod along the line."""
    if b.dim == 3 and not any(link != GROUND and b.along(link, j.at, j.axis) for link in j.links):
        _key(b, j)


for _kind in (JointKind("R", (2, 3), _revolute, axis=(3,), motions=("rotation",), axes=("axis",)),
              JointKind("P", (2, 3), _Builder.line, axis=(2, 3), motions=("slide",), finish=_keyed, block=True),
              JointKind("C", (3,), _Builder.line, axis=(3,), motions=("rotation", "slide"),
                        choice=("motion", ("rotation", "slide")), block=True),
              JointKind("U", (3,), _universal, axis=(3,), axis2=True, motions=("1", "2"), choice=("axis", (1, 2)),
                        check=_perpendicular, rate_links=_u_rate_links, axes=("axis", "axis2")),
              JointKind("S", (3,), _point, article="an")):
    register_joint(_kind)
