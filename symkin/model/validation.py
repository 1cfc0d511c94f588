"""Check a model dictionary and build a :class:`~symkin.model.mechanism.Mechanism`.

Everything is checked and every problem is reported at once (one :class:`ModelError`
whose ``problems`` name the key, node, link or slider at fault).  Nothing here raises
for a user's mistake except that single error.
"""
from __future__ import annotations

import json
import math
from collections import Counter, defaultdict
from itertools import product
from typing import Any, Mapping

from symkin.errors import ModelError, Problem
from symkin.model.joints import GROUND, Limits, compile_joints
from symkin.model.mechanism import AXES, Mechanism, Parameter, Slider, length_scale
from symkin.model.pairs import ItemContext, extra_keys, extra_kinds
from symkin.tolerances import DEFAULT

__all__ = ["parse_mechanism", "TOP_LEVEL_KEYS", "PARAMETER_KINDS", "SLIDER_KEYS", "COORDINATE_LIMIT",
           "MIN_LENGTH"]

#: the keys of a model dictionary; the keys of the registered extra constraints
#: (:func:`symkin.model.pairs.extra_keys`) are allowed too
TOP_LEVEL_KEYS = ("name", "description", "dim", "fixed", "mobility", "inputs", "outputs",
                  "platform", "platform_dof", "nodes", "links", "sliders", "joints")
PARAMETER_KINDS = ("rotation", "slide", "velocity", "twist", "joint")
PARAMETER_KEYS = PARAMETER_KINDS + ("axis", "component", "label")
SLIDER_KEYS = ("id", "node", "point", "direction", "normal", "line", "link")

#: Largest magnitude accepted for a coordinate, a slider point or a component of a direction,
#: normal or axis (in the file's unit).  Squares and products of such numbers stay far from
#: floating-point overflow, so every length the analysis forms is finite.
COORDINATE_LIMIT = 1e100
#: Smallest length scale (mean distance between the nodes of a link) and smallest norm of a
#: direction, normal or axis vector accepted: below it squared lengths underflow to zero.
#: A model outside these bounds is rejected with a message suggesting another unit; inside
#: them the analysis is scale invariant (a model and the same model scaled give one answer).
MIN_LENGTH = 1e-100
#: sine of the angle below which two directions of a model (a rotation axis, a rod) count as
#: parallel: the nodes of a file are typed or computed to about 1e-12 of the length scale, so
#: 1e-9 accepts rounding and nothing a user would draw on purpose
_ALIGNED = 1e-9


class _Collector:
    """Gathers problems while parsing continues."""

    def __init__(self):
        self.problems: list[Problem] = []

    def add(self, key: str, message: str) -> None:
        self.problems.append(Problem(key, message))


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _finite(v: int | float) -> bool:
    """Finite as a float (an integer too large for a float is not)."""
    try:
        return math.isfinite(float(v))
    except OverflowError:
        return False


def _short(value: Any, limit: int = 80) -> str:
    """``repr`` cut to ``limit`` characters, so that a huge value does not flood a message."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + f"... ({len(text)} characters)"


def _vector(value: Any, dim: int | None, key: str, out: _Collector, what: str = "coordinates"):
    """A finite numeric vector of length ``dim`` within ``±COORDINATE_LIMIT``, or None (problem recorded)."""
    if not isinstance(value, (list, tuple)) or not all(_is_number(v) for v in value):
        out.add(key, f"{what} must be a list of numbers, got {_short(value)}")
        return None
    if dim is not None and len(value) != dim:
        out.add(key, f"{what} must have {dim} components (dim = {dim}), got {len(value)}")
        return None
    if not all(_finite(v) for v in value):
        out.add(key, f"{what} must be finite, got {_short(list(value))}")
        return None
    vec = tuple(float(v) for v in value)
    if any(abs(v) > COORDINATE_LIMIT for v in vec):
        out.add(key, f"{what} {_short(list(value))} out of range: each component must lie within "
                     f"±{COORDINATE_LIMIT:g} (use another unit)")
        return None
    return vec


def _direction(value: Any, dim: int | None, key: str, out: _Collector, what: str):
    """A direction, normal or axis vector: as :func:`_vector`, and not (numerically) zero."""
    vec = _vector(value, dim, key, out, what)
    if vec is None:
        return None
    norm = math.hypot(*vec)
    if norm == 0.0:
        out.add(key, f"zero {what}")
        return None
    if norm < MIN_LENGTH:
        out.add(key, f"{what} {list(vec)!r} too short: its norm {norm:.3g} is below {MIN_LENGTH:g}")
        return None
    return vec


def _names(value: Any, key: str, out: _Collector, known: set[str] | None, what: str) -> tuple[str, ...]:
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        out.add(key, f"must be a list of {what} names, got {_short(value)}")
        return ()
    if known is not None:
        for v in value:
            if v not in known:
                out.add(key, f"unknown {what} {v!r}")
    return tuple(value)


def _unknown_keys(table: Mapping, allowed: tuple[str, ...], key: str, out: _Collector) -> None:
    extra = [k for k in table if k not in allowed]
    if extra:
        where = f"{key}: " if key else ""
        out.add(key, f"unknown key(s) {', '.join(map(repr, extra))} "
                     f"(allowed: {', '.join(allowed)})".replace(where, ""))


def parse_mechanism(data: Any, source: str | None = None, tolerances=DEFAULT) -> Mechanism:
    """Validate the model dictionary ``data`` and return the mechanism.

    Raises
    ------
    ModelError
        Listing every problem found; ``source`` (a file name) is recorded on it.
    """
    out = _Collector()
    if not isinstance(data, Mapping):
        raise ModelError([Problem("", f"a model must be a table/object, got {type(data).__name__}")], source)
    _unknown_keys(data, TOP_LEVEL_KEYS + extra_keys(), "", out)

    name = data.get("name", "unnamed mechanism")
    if not isinstance(name, str):
        out.add("name", f"must be a string, got {_short(name)}")
        name = str(name)
    description = data.get("description", "")
    if not isinstance(description, str):
        out.add("description", "must be a string")
        description = ""

    dim = data.get("dim")
    if dim is None:
        out.add("dim", "missing: 2 (planar) or 3 (spatial)")
    elif isinstance(dim, bool) or not isinstance(dim, int) or dim not in (2, 3):
        out.add("dim", f"must be 2 (planar) or 3 (spatial), got {_short(dim)}")
        dim = None

    joints, joint_rates = (), ()
    if "joints" in data:  # compiled to nodes, links and sliders, then checked as a node model
        if dim is None:
            raise ModelError(out.problems, source)
        compiled = compile_joints(data, dim, Limits(tolerances.geometry, COORDINATE_LIMIT, MIN_LENGTH))
        if compiled.problems:
            raise ModelError(out.problems + list(compiled.problems), source)
        data, joints, joint_rates = compiled.data, compiled.joints, compiled.rates

    nodes = _parse_nodes(data.get("nodes"), dim, out)
    node_set = set(nodes)
    links = _parse_links(data.get("links"), node_set, out)
    fixed = _names(data.get("fixed", []), "fixed", out, node_set, "node")
    for n, count in _repeated(fixed):
        out.add("fixed", f"node {n!r} listed {_times(count)}")

    scale = length_scale(nodes, links.values())
    if scale < MIN_LENGTH:
        out.add("nodes", f"the model's length scale (mean distance between the nodes of a link) is "
                         f"{scale:.3g}, below {MIN_LENGTH:g}: lengths this small underflow; use another unit")
    outliers = _outliers(nodes, links, scale)
    for name, coordinate, typical in outliers:
        out.add(f"nodes.{name}", f"coordinate {coordinate:.6g} is an outlier: {abs(coordinate) / typical:.3g} "
                                 f"times the model's typical size {typical:.3g}, so that every ordinary link "
                                 "would be taken for zero length (a typo, or another unit?)")
    if not outliers:
        _check_link_geometry(nodes, links, scale, tolerances.geometry, out)
    used = {n for ns in links.values() for n in ns}
    for n in nodes:
        if n not in used:
            out.add(f"nodes.{n}", "node belongs to no link")

    if nodes and fixed and len(set(fixed)) == len(nodes):
        out.add("fixed", f"every node is fixed ({len(nodes)} nodes): nothing can move")
    sliders = _parse_sliders(data.get("sliders", []), dim, nodes, links, set(fixed), scale,
                             tolerances.geometry, out)
    extras = _parse_extras(data, dim, nodes, links, out)
    link_set = set(links)
    fixed_set = set(fixed)
    ground = {l for l, ns in links.items() if all(n in fixed_set for n in ns)}
    context = dict(dim=dim, nodes=nodes, links=links, sliders=sliders, fixed=fixed_set, ground=ground)
    inputs = _parse_parameters(data.get("inputs", []), "inputs", context, out)
    outputs = _parse_parameters(data.get("outputs", []), "outputs", context, out)

    mobility = data.get("mobility")
    if mobility is not None and (isinstance(mobility, bool) or not isinstance(mobility, int) or mobility < 0):
        out.add("mobility", f"must be a non-negative integer, got {_short(mobility)}")
        mobility = None

    platform = data.get("platform")
    if platform is not None:
        if not isinstance(platform, str) or platform not in link_set:
            out.add("platform", f"unknown link {platform!r}")
            platform = None
        elif platform in ground:
            out.add("platform", f"link {platform!r} is ground (all its nodes are fixed)")
    platform_dof = data.get("platform_dof")
    if platform_dof is not None:
        top = 3 if dim == 2 else 6
        if isinstance(platform_dof, bool) or not isinstance(platform_dof, int) or not 0 <= platform_dof <= top:
            out.add("platform_dof", f"must be an integer from 0 to {top}, got {_short(platform_dof)}")
            platform_dof = None
        elif platform is None and "platform" not in data:
            out.add("platform_dof", "given without 'platform'")

    if out.problems:
        raise ModelError(out.problems, source)
    return Mechanism(name=name, dim=dim, nodes=tuple(nodes.items()), links=tuple(links.items()),
                     fixed=fixed, sliders=tuple(sliders), inputs=tuple(inputs), outputs=tuple(outputs),
                     mobility=mobility, platform=platform, platform_dof=platform_dof,
                     description=description, joints=joints, joint_rates=joint_rates,
                     extras=tuple(extras))


# ---------------------------------------------------------------------- parts
def _parse_nodes(table: Any, dim: int | None, out: _Collector) -> dict[str, tuple[float, ...]]:
    if table is None:
        out.add("nodes", "missing: a table of node coordinates")
        return {}
    if not isinstance(table, Mapping) or not table:
        out.add("nodes", "must be a non-empty table of node name = [coordinates]")
        return {}
    nodes = {}
    for name, value in table.items():
        # an invalid node stays known by name (None) so links naming it get no second complaint
        nodes[name] = _vector(value, dim, f"nodes.{name}", out)
    return nodes


def _parse_links(table: Any, node_set: set[str], out: _Collector) -> dict[str, tuple[str, ...]]:
    if table is None:
        out.add("links", "missing: a table of link name = [node names]")
        return {}
    if not isinstance(table, Mapping) or not table:
        out.add("links", "must be a non-empty table of link name = [node names]")
        return {}
    links = {}
    for name, value in table.items():
        key = f"links.{name}"
        ns = _names(value, key, out, node_set, "node")
        if not ns:
            continue
        if len(ns) < 2:
            out.add(key, f"a link needs at least 2 nodes, got {len(ns)}")
            continue
        repeated = _repeated(ns)
        if repeated:
            out.add(key, "node(s) " + ", ".join(f"{n} ({_times(c)})" if c > 2 else n for n, c in repeated)
                    + " repeated")
            continue
        links[name] = ns
    return links


def _repeated(items) -> list[tuple[Any, int]]:
    """The entries of ``items`` that occur more than once, with their count, sorted (linear time)."""
    return sorted(((k, c) for k, c in Counter(items).items() if c > 1), key=lambda kc: str(kc[0]))


def _times(count: int) -> str:
    return "twice" if count == 2 else f"{count} times"


def _coincident_groups(points: list[tuple[str, tuple[float, ...]]], radius: float) -> list[list[str]]:
    """Groups of names whose points lie within ``radius`` of another of the group.

    A grid of cells of side ``radius`` (hashing, expected linear time): two points within
    ``radius`` lie in the same or neighbouring cells.  Groups keep the order of ``points``.
    """
    if not points:
        return []
    dim = len(points[0][1])
    cells: dict[tuple[int, ...], list[int]] = defaultdict(list)
    side = radius if radius > 0 else 1.0
    keys = []
    for i, (_, p) in enumerate(points):
        key = tuple(math.floor(c / side) for c in p) if radius > 0 else tuple(p)
        keys.append(key)
        cells[key].append(i)
    parent = list(range(len(points)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    offsets = list(product((-1, 0, 1), repeat=dim)) if radius > 0 else [(0,) * dim]
    for i, (_, p) in enumerate(points):
        for off in offsets:
            for j in cells.get(tuple(k + o for k, o in zip(keys[i], off)), ()):
                if j > i and math.dist(p, points[j][1]) <= radius:
                    ri, rj = root(i), root(j)
                    if ri != rj:
                        parent[max(ri, rj)] = min(ri, rj)
    groups: dict[int, list[str]] = defaultdict(list)
    for i, (name, _) in enumerate(points):
        groups[root(i)].append(name)
    return [g for g in groups.values() if len(g) > 1]


#: a node this many times the model's typical size away from the median node is an outlier
OUTLIER_RATIO = 1e6


def _outliers(nodes, links, scale) -> list[tuple[str, float, float]]:
    """Nodes with a coordinate so far out that the length scale no longer describes the model.

    The typical size is the median distance of the nodes from their median point (robust
    to a few wild values); a node more than :data:`OUTLIER_RATIO` typical sizes from that
    point is returned as ``(name, its farthest coordinate, typical size)``.  Looked for
    only when the length scale is itself that far above the typical size.
    """
    from statistics import median

    points = [(n, p) for n, p in nodes.items() if p is not None]
    dims = {len(p) for _, p in points}
    if len(points) < 3 or len(dims) != 1:
        return []
    dim = dims.pop()
    centre = [median(p[k] for _, p in points) for k in range(dim)]
    spread = [d for d in (math.dist(p, centre) for _, p in points) if d > 0]
    if not spread:
        return []
    typical = median(spread)
    if scale <= OUTLIER_RATIO * typical:
        return []
    found = []
    for name, p in points:
        if math.dist(p, centre) > OUTLIER_RATIO * typical:
            far = max(range(dim), key=lambda k: abs(p[k] - centre[k]))
            found.append((name, p[far], typical))
    return found


def _check_link_geometry(nodes, links, scale, tol, out: _Collector) -> None:
    for name, ns in links.items():
        pts = [(n, nodes.get(n)) for n in ns]
        dims = {len(p) for _, p in pts if p is not None}
        pts = [(n, p) for n, p in pts if p is not None and len(dims) == 1]
        for group in _coincident_groups(pts, tol * scale):
            what = "zero-length bar" if len(ns) == 2 else "coincident nodes in a rigid body"
            if len(group) == 2:
                out.add(f"links.{name}", f"{what}: nodes {group[0]} and {group[1]} are at the same point")
            else:
                shown = ", ".join(group[:10]) + (f", … ({len(group)} nodes)" if len(group) > 10 else "")
                out.add(f"links.{name}", f"{what}: nodes {shown} are at the same point")


def _parse_sliders(items: Any, dim, nodes, links, fixed: set[str], scale, tol, out: _Collector) -> list[Slider]:
    if not isinstance(items, (list, tuple)):
        out.add("sliders", "must be a list of tables")
        return []
    sliders, ids = [], {}
    repeated_ids: dict[str, list[int]] = defaultdict(list)
    per_node: dict[str, int] = {}
    for item in items:
        if isinstance(item, Mapping) and isinstance(item.get("node"), str):
            per_node[item["node"]] = per_node.get(item["node"], 0) + 1
    for k, item in enumerate(items):
        key = f"sliders[{k}]"
        if not isinstance(item, Mapping):
            out.add(key, "must be a table")
            continue
        _unknown_keys(item, SLIDER_KEYS, key, out)
        node = item.get("node")
        if not isinstance(node, str) or node not in nodes:
            out.add(key, f"unknown node {node!r}")
            continue
        sid = item.get("id")
        if sid is None:
            sid = node if per_node.get(node, 0) == 1 else f"{node}#{k}"
        if not isinstance(sid, str):
            out.add(key, f"id must be a string, got {_short(sid)}")
            continue
        key = f"sliders[{k}] ({sid})"
        if sid in ids:
            repeated_ids[sid].append(k)
            continue
        ids[sid] = k
        if node in fixed:
            out.add(key, f"node {node} is fixed; a fixed node cannot slide")
        has_line = "line" in item or "link" in item
        has_point = "point" in item
        forms = [has_line, has_point]
        if sum(forms) != 1:
            out.add(key, "give either point + direction (fixed line), point + normal (fixed plane) "
                         "or line + link (moving line)")
            continue
        p = nodes.get(node)
        if has_line:
            slider = _moving_line_slider(item, sid, node, p, nodes, links, scale, tol, key, out)
        else:
            slider = _fixed_slider(item, sid, node, p, dim, scale, tol, key, out)
        if slider is not None:
            sliders.append(slider)
    for sid, where in repeated_ids.items():
        others = ", ".join(f"[{k}]" for k in where[:5]) + (", …" if len(where) > 5 else "")
        out.add(f"sliders[{ids[sid]}] ({sid})",
                f"duplicate slider id {sid!r}: {len(where) + 1} sliders have it (also sliders{others})")
    return sliders


def _parse_extras(data: Mapping, dim, nodes, links, out: _Collector) -> list:
    """The records of the extra constraints (:class:`~symkin.model.pairs.ExtraConstraint`), kind
    by kind in registration order: each kind's key holds a list of tables, each table is
    checked for unknown keys and parsed by its kind."""
    ctx = ItemContext(dim=dim, nodes=nodes, links=links, problem=out.add,
                      vector=lambda value, key, what: _vector(value, dim, key, out, what),
                      direction=lambda value, key, what: _direction(value, dim, key, out, what),
                      number=_is_number, short=_short)
    found = []
    for kind in extra_kinds():
        items = data.get(kind.key, [])
        if not isinstance(items, (list, tuple)):
            out.add(kind.key, "must be a list of tables")
            continue
        for k, item in enumerate(items):
            key = f"{kind.key}[{k}]"
            if not isinstance(item, Mapping):
                out.add(key, "must be a table")
                continue
            _unknown_keys(item, kind.keys, key, out)
            record = kind.parse(item, key, ctx)
            if record is not None:
                found.append(record)
    return found


def _fixed_slider(item, sid, node, p, dim, scale, tol, key, out) -> Slider | None:
    point = _vector(item.get("point"), dim, key, out, "point")
    if ("direction" in item) == ("normal" in item):
        out.add(key, "a fixed slider needs exactly one of 'direction' (line) or 'normal' (plane)")
        return None
    if "normal" in item and dim == 2:
        out.add(key, "'normal' (a fixed plane) is for spatial models; use 'direction' in a planar one")
        return None
    which = "direction" if "direction" in item else "normal"
    vec = _direction(item.get(which), dim, key, out, which)
    if point is None or vec is None:
        return None
    norm = math.hypot(*vec)
    if p is not None:
        u = [v / norm for v in vec]
        d = [a - b for a, b in zip(p, point)]
        along = sum(a * b for a, b in zip(d, u))
        off = math.sqrt(max(sum(a * a for a in d) - along * along, 0.0)) if which == "direction" else abs(along)
        if off > tol * scale:
            what = "line" if which == "direction" else "plane"
            out.add(key, f"node {node} is {off:.3g} away from its {what} (tolerance {tol * scale:.3g})")
    return Slider(id=sid, node=node, point=point, **{which: vec})


def _moving_line_slider(item, sid, node, p, nodes, links, scale, tol, key, out) -> Slider | None:
    line, link = item.get("line"), item.get("link")
    if "point" in item or "direction" in item or "normal" in item:
        out.add(key, "a moving-line slider takes 'line' and 'link' only")
        return None
    if not (isinstance(line, (list, tuple)) and len(line) == 2 and all(isinstance(n, str) for n in line)):
        out.add(key, f"line must be two node names, got {_short(line)}")
        return None
    if not isinstance(link, str) or link not in links:
        out.add(key, f"unknown link {link!r}")
        return None
    bad = [n for n in line if n not in links[link]]
    if bad:
        out.add(key, f"node(s) {', '.join(bad)} of the line are not nodes of link {link}")
        return None
    if node in line:
        out.add(key, f"node {node} cannot slide on a line through itself")
        return None
    a, c = nodes.get(line[0]), nodes.get(line[1])
    if p is not None and a is not None and c is not None:
        e = [ci - ai for ai, ci in zip(a, c)]
        le = math.hypot(*e)
        if le == 0.0:
            out.add(key, "the line's two nodes coincide")
            return None
        d = [pi - ai for ai, pi in zip(a, p)]
        along = sum(x * y for x, y in zip(d, e)) / le
        off = math.sqrt(max(sum(v * v for v in d) - along * along, 0.0))
        if off > tol * scale:
            out.add(key, f"node {node} is {off:.3g} away from line {line[0]}-{line[1]} "
                         f"(tolerance {tol * scale:.3g})")
    return Slider(id=sid, node=node, line=(line[0], line[1]), link=link)


def _parse_parameters(items: Any, where: str, ctx: dict, out: _Collector) -> list[Parameter]:
    if not isinstance(items, (list, tuple)):
        out.add(where, "must be a list of tables such as {rotation = \"crank\"}")
        return []
    params, first, first_raw = [], {}, {}
    repeats: dict[tuple, list[int]] = defaultdict(list)
    for k, item in enumerate(items):
        key = f"{where}[{k}]"
        try:  # the same entry again is counted, not checked again
            raw = json.dumps(item, sort_keys=True, default=repr)
        except (TypeError, ValueError):
            raw = None
        if raw is not None:
            if raw in first_raw:
                repeats[first_raw[raw]].append(k)
                continue
            first_raw[raw] = ("entry", k)
            first[("entry", k)] = k
        if not isinstance(item, Mapping):
            out.add(key, f"must be a table such as {{rotation = \"crank\"}}, got {_short(item)}")
            continue
        _unknown_keys(item, PARAMETER_KEYS, key, out)
        kinds = [kd for kd in PARAMETER_KINDS if kd in item]
        if len(kinds) != 1:
            out.add(key, f"needs exactly one of {', '.join(PARAMETER_KINDS)}")
            continue
        param = _parameter(kinds[0], item, key, ctx, out)
        if param is None:
            continue
        same = (param.kind, param.target, param.axis, param.component)  # the label aside
        if same in first:
            repeats[same].append(k)
            continue
        if raw is not None:
            first_raw[raw] = same
        first[same] = k
        params.append(param)
    for same, again in repeats.items():
        out.add(f"{where}[{first[same]}]", f"listed {_times(len(again) + 1)} (also {where}"
                + ", ".join(f"[{k}]" for k in again[:5]) + (", …" if len(again) > 5 else "") + ")")
    return params


def _parameter(kind, item, key, ctx, out) -> Parameter | None:
    dim, links, nodes, fixed, ground = ctx["dim"], ctx["links"], ctx["nodes"], ctx["fixed"], ctx["ground"]
    value = item[kind]
    label = item.get("label")
    if label is not None and not isinstance(label, str):
        out.add(key, "label must be a string")
        label = None
    for extra, allowed in (("axis", ("rotation", "joint")), ("component", ("velocity",))):
        if extra in item and kind not in allowed:
            out.add(key, f"'{extra}' goes with {' or '.join(allowed)} only")
            return None
    if kind == "joint":
        if not (isinstance(value, (list, tuple)) and len(value) == 2 and all(isinstance(v, str) for v in value)):
            out.add(key, f"joint needs two link names, got {_short(value)}")
            return None
        missing = [v for v in value if v not in links]
        if dim == 2 and missing == [GROUND] and value[0] != value[1]:  # the fixed frame of a joint model
            other = value[1] if value[0] == GROUND else value[0]
            if not set(links[other]) & set(fixed):
                out.add(key, f"link {other} has no fixed node, so it forms no joint with {GROUND}")
                return None
            return Parameter("joint", (value[0], value[1]), label=label)
        if missing:
            out.add(key, f"unknown link(s) {', '.join(missing)}")
            return None
        if dim == 2 and not set(links[value[0]]) & set(links[value[1]]):
            out.add(key, f"links {value[0]} and {value[1]} share no node, so they form no joint")
            return None
        axis = None  # spatial: the relative rotation about an axis, a·(ω₂ − ω₁)
        for link in value:
            axis = _rotation_axis(item, link, key, ctx, out)
            if axis is False:
                return None
        return Parameter("joint", (value[0], value[1]), axis=axis, label=label)
    if not isinstance(value, str):
        out.add(key, f"{kind} needs a name, got {_short(value)}")
        return None
    if kind in ("rotation", "twist"):
        if value not in links:
            out.add(key, f"unknown link {value!r}")
            return None
        if value in ground:
            out.add(key, f"link {value} is ground (all its nodes are fixed): its {kind} is always zero")
            return None
        axis = None
        if kind == "rotation":
            axis = _rotation_axis(item, value, key, ctx, out)
            if axis is False:
                return None
        return Parameter(kind, (value,), axis=axis, label=label)
    if kind == "slide":
        by_id, by_node = _slider_index(ctx)
        matches = by_id.get(value) or by_node.get(value, [])
        if not matches:
            out.add(key, f"unknown slider {value!r}")
            return None
        if len(matches) > 1:
            out.add(key, f"node {value} has {len(matches)} sliders: name one by its id")
            return None
        if matches[0].direction is None and not matches[0].carriers:  # a plane
            out.add(key, f"slider {value} is on a plane: its rate has two components; "
                         "use velocity components instead")
            return None
        return Parameter("slide", (matches[0].id,), label=label)
    # velocity
    if value not in nodes:
        out.add(key, f"unknown node {value!r}")
        return None
    if value in fixed:
        out.add(key, f"node {value} is fixed: its velocity is always zero")
        return None
    comp = item.get("component")
    if comp is not None and (dim is None or comp not in AXES[:dim]):
        out.add(key, f"component must be one of {', '.join(AXES[:dim or 3])}, got {comp!r}")
        return None
    return Parameter("velocity", (value,), component=comp, label=label)


def _slider_index(ctx) -> tuple[dict, dict]:
    """Sliders by id and by node (built once per model: lookups stay constant-time)."""
    if "_slider_index" not in ctx:
        by_id, by_node = defaultdict(list), defaultdict(list)
        for sl in ctx["sliders"]:
            by_id[sl.id].append(sl)
            by_node[sl.node].append(sl)
        ctx["_slider_index"] = (dict(by_id), dict(by_node))
    return ctx["_slider_index"]


def _rotation_axis(item, link, key, ctx, out):
    """The axis of a spatial rotation (tuple), None for planar, False after a problem."""
    dim, nodes = ctx["dim"], ctx["nodes"]
    axis = item.get("axis")
    if dim is None:  # the problem with 'dim' is recorded; an axis cannot be checked without it
        return False
    if dim == 2:
        if axis is not None:
            out.add(key, "a planar rotation has no axis")
            return False
        return None
    if axis is None:
        out.add(key, "a spatial rotation needs an axis: axis = [\"N1\", \"N2\"] or [ax, ay, az]")
        return False
    if isinstance(axis, (list, tuple)) and len(axis) == 2 and all(isinstance(a, str) for a in axis):
        missing = [a for a in axis if a not in nodes]
        if missing:
            out.add(key, f"unknown axis node(s) {', '.join(missing)}")
            return False
        pa, pb = nodes[axis[0]], nodes[axis[1]]
        if pa is None or pb is None:
            return False
        vec = tuple(b - a for a, b in zip(pa, pb))
        if math.hypot(*vec) == 0.0:
            out.add(key, "the axis nodes coincide")
            return False
        result = (axis[0], axis[1])
    else:
        vec = _direction(axis, 3, key, out, "axis")
        if vec is None:
            return False
        result = vec
    if _is_rod(link, ctx) and _parallel(vec, _rod_direction(link, ctx)):
        out.add(key, f"link {link} is a rod (its nodes are collinear) and the axis is along it: "
                     "the spin of a rod about its own axis moves no node and is not defined")
        return False
    return result


def _link_points(link, ctx):
    return [ctx["nodes"][n] for n in ctx["links"][link] if ctx["nodes"].get(n) is not None]


def _rod_direction(link, ctx):
    pts = _link_points(link, ctx)
    far = max(pts, key=lambda p: math.dist(p, pts[0]))
    return tuple(b - a for a, b in zip(pts[0], far))


def _is_rod(link, ctx) -> bool:
    """All nodes of the (spatial) link on one line."""
    pts = _link_points(link, ctx)
    if len(pts) < 2:
        return False
    d = _rod_direction(link, ctx)
    length = math.sqrt(sum(v * v for v in d))
    if length == 0.0:
        return False
    for p in pts:
        w = [b - a for a, b in zip(pts[0], p)]
        along = sum(x * y for x, y in zip(w, d)) / length
        if sum(x * x for x in w) - along * along > (_ALIGNED * length) ** 2:
            return False
    return True


def _parallel(a, b) -> bool:
    cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    na, nb = math.sqrt(sum(v * v for v in a)), math.sqrt(sum(v * v for v in b))
    return math.sqrt(sum(v * v for v in cross)) <= _ALIGNED * na * nb


# ---------------------------------------------------------------------- size of the dense analysis (issue 19)
#: bytes the dense analysis of one configuration may take (the constraint matrix in the
#: paper's pairwise form, its full SVD and a copy); a model above it that the sparse path
#: cannot take (:mod:`symkin.analysis.sparse`) is refused with its size, never a NumPy
#: memory error.  2 GiB: a dense ``J`` of about 8,000 × 8,000, beyond what the dense path
#: analyses in minutes.
DENSE_ANALYSIS_BYTES = 2 * 1024 ** 3


def dense_analysis_bytes(rows: int, columns: int) -> int:
    """Bytes of a dense analysis of ``rows`` constraint rows over ``columns`` free coordinates.

    The reduced ``J`` and a copy, its left singular vectors (rows × rows) and right ones
    (columns × columns), in float64.

    >>> dense_analysis_bytes(499_500, 2_000) > DENSE_ANALYSIS_BYTES
    True
    """
    return 8 * (2 * rows * columns + rows * rows + columns * columns)


def dense_size_problem(rows: int, columns: int, why: str) -> Problem | None:
    """A :class:`~symkin.errors.Problem` when the dense analysis would exceed :data:`DENSE_ANALYSIS_BYTES`.

    ``why`` says why the model is not taken by the sparse path.
    """
    need = dense_analysis_bytes(rows, columns)
    if need <= DENSE_ANALYSIS_BYTES:
        return None
    return Problem("model", f"too large for the dense analysis: {rows} constraint rows over {columns} free "
                            f"coordinates need about {need / 1024 ** 3:.1f} GiB, above the limit of "
                            f"{DENSE_ANALYSIS_BYTES / 1024 ** 3:.0f} GiB ({why})")
