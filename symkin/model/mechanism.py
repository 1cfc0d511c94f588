"""The mechanism as plain, hashable data: nodes, links, sliders, kinematic parameters.

Nothing here knows about matrices; :mod:`symkin.numeric` and :mod:`symkin.symbolic`
turn a :class:`Mechanism` into geometric matrices.  A mechanism is built from a model
file (:func:`symkin.read_model`) or from the same dictionary in Python
(:meth:`Mechanism.from_dict`); both go through :func:`symkin.model.validation.parse_mechanism`,
which checks everything and reports every problem at once.
"""
from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from itertools import chain
from typing import Iterable, Mapping

from symkin.errors import ModelError, Problem
from symkin.model.pairs import extra_kind, extra_kinds

__all__ = ["Slider", "Parameter", "ParameterList", "Mechanism", "Topology", "AXES", "TWIST_COMPONENTS", "length_scale"]

AXES = ("x", "y", "z")
#: component names of a twist (velocity of the link's first node, then angular velocity)
TWIST_COMPONENTS = {2: ("vx", "vy", "wz"), 3: ("vx", "vy", "vz", "wx", "wy", "wz")}


@dataclass(frozen=True)
class Slider:
    """A node constrained to a line or a plane.

    Exactly one of three forms (see the README's model-file reference):

    * ``point`` + ``direction``: the node slides on a fixed line;
    * ``line = (A, C)`` + ``link``: the node slides on the moving line through nodes A and C
      of ``link`` (combined with a second such slider it makes a prismatic pair);
    * ``point`` + ``normal`` (spatial only): the node slides on a fixed plane.
    """

    id: str
    node: str
    point: tuple[float, ...] | None = None
    direction: tuple[float, ...] | None = None
    normal: tuple[float, ...] | None = None
    line: tuple[str, str] | None = None
    link: str | None = None

    @property
    def kind(self) -> str:
        """``"line"`` (fixed line), ``"moving_line"`` or ``"plane"``: the name of its form.

        The stages do not dispatch on it: the constraint registry
        (:func:`symkin.constraints.constraints_of`) maps each form to its definition.
        """
        if self.line is not None:
            return "moving_line"
        if self.normal is not None:
            return "plane"
        return "line"

    @property
    def carriers(self) -> tuple[str, ...]:
        """The nodes of the moving line it slides on; ``()`` when the fixed frame holds it."""
        return self.line or ()

    def to_dict(self) -> dict:
        out: dict = {"id": self.id, "node": self.node}
        for key in ("point", "direction", "normal"):
            value = getattr(self, key)
            if value is not None:
                out[key] = list(value)
        if self.line is not None:
            out["line"] = list(self.line)
            out["link"] = self.link
        return out


@dataclass(frozen=True)
class Parameter:
    """A kinematic parameter: a linear functional (or a few) of the nodal velocities.

    ``kind`` is one of ``rotation``, ``slide``, ``velocity``, ``twist``, ``joint``;
    ``target`` names what it belongs to (a link, a slider, a node, or two links for a
    joint: the rate of the second relative to the first; ``"ground"``, when no link has that
    name, is the fixed frame of a model written by its joints, whose rotation is zero).  ``axis`` is a pair of node names
    or a vector (spatial rotations and joints: the rate about it, a spatial joint's
    ``a·(ω₂ − ω₁)``);
    ``component`` picks one axis of a velocity (``"x"``, ``"y"``, ``"z"``).
    """

    kind: str
    target: tuple[str, ...]
    axis: tuple | None = None
    component: str | None = None
    label: str | None = None

    def labels(self, dim: int) -> tuple[str, ...]:
        """Labels of the scalar rows, e.g. ``rotation:crank`` or ``twist:platform.wz``."""
        base = self.label or self._base_label()
        if self.kind == "velocity":
            comps = (self.component,) if self.component else AXES[:dim]
            return tuple(f"{base}.{c}" for c in comps)
        if self.kind == "twist":
            return tuple(f"{base}.{c}" for c in TWIST_COMPONENTS[dim])
        return (base,)

    def _base_label(self) -> str:
        if self.kind == "joint":
            about = "" if self.axis is None else f"[{self.axis[0]}-{self.axis[1]}]" \
                if isinstance(self.axis[0], str) else f"[{','.join(f'{a:g}' for a in self.axis)}]"
            return f"joint:{self.target[0]}-{self.target[1]}{about}"
        if self.kind == "rotation" and self.axis is not None and isinstance(self.axis[0], str):
            return f"rotation:{self.target[0]}[{self.axis[0]}-{self.axis[1]}]"
        if self.kind == "rotation" and self.axis is not None:
            return f"rotation:{self.target[0]}[{','.join(f'{a:g}' for a in self.axis)}]"
        return f"{self.kind}:{self.target[0]}"

    def size(self, dim: int) -> int:
        """Number of scalar rows."""
        return len(self.labels(dim))

    def to_dict(self) -> dict:
        out: dict = {self.kind: list(self.target) if self.kind == "joint" else self.target[0]}
        if self.axis is not None:
            out["axis"] = list(self.axis)
        if self.component is not None:
            out["component"] = self.component
        if self.label is not None:
            out["label"] = self.label
        return out


class ParameterList(tuple):
    """A tuple of :class:`Parameter` whose hash is computed once (it keys per-configuration caches)."""

    def __hash__(self) -> int:
        try:
            return self.__dict__["_hash"]
        except KeyError:
            h = self.__dict__["_hash"] = tuple.__hash__(self)
            return h


class Topology:
    """Everything of a mechanism but its node coordinates: the key of per-topology caches.

    Two mechanisms at different configurations of the same model have equal topologies
    (dimension, node names, links, fixed nodes, sliders, inputs, outputs, mobility,
    platform).  The hash is computed once, so a cache lookup costs a dictionary probe.
    """

    __slots__ = ("key", "_hash")

    def __init__(self, key: tuple):
        self.key = key
        self._hash = hash(key)

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other) -> bool:
        return self is other or (isinstance(other, Topology) and self._hash == other._hash
                                 and self.key == other.key)

    def __reduce__(self):
        return Topology, (self.key,)  # the hash of strings differs between processes

    def __repr__(self) -> str:
        return f"Topology(dim={self.key[0]}, nodes={len(self.key[1])}, links={len(self.key[2])})"

    # named parts of the key (built by :attr:`Mechanism.topology`; the extras are present only
    # when there are some, so that a model without them keeps the key it always had)
    @property
    def dim(self) -> int:
        return self.key[0]

    @property
    def node_names(self) -> tuple[str, ...]:
        return self.key[1]

    @property
    def links(self) -> tuple:
        return self.key[2]

    @property
    def sliders(self) -> tuple:
        return self.key[4]

    @property
    def extras(self) -> tuple:
        """The mechanism's :attr:`~Mechanism.extras` (records of extra constraints)."""
        return self.key[10] if len(self.key) > 10 else ()


def _float_array_nodes(mech: "Mechanism", coords) -> tuple | None:
    """``mech.nodes`` at the coordinates of a float (n, dim) array, or None for other input.

    The fast path of :meth:`Mechanism.with_coordinates` (NumPy's ``tolist`` gives Python
    floats of the right shape, so only finiteness is left to check).
    """
    if getattr(coords, "shape", None) != (len(mech.nodes), mech.dim) or \
            getattr(getattr(coords, "dtype", None), "kind", None) != "f":
        return None
    xyz = list(map(tuple, coords.tolist()))
    if not all(map(math.isfinite, chain.from_iterable(xyz))):
        raise ModelError(_coordinate_problems(mech, xyz))
    return tuple(zip(mech.node_names, xyz))


def _coordinate_rows(mech: "Mechanism", coords) -> list:
    """Rows of new coordinates in node order, from a mapping or an (n, dim) array."""
    if isinstance(coords, Mapping):
        names = set(mech.node_names)
        unknown = [n for n in coords if n not in names]
        if unknown:
            raise ModelError([Problem(f"nodes.{n}", f"no such node in {mech.name!r}") for n in unknown])
        return [coords.get(n, xyz) for n, xyz in mech.nodes]
    rows = coords.tolist() if hasattr(coords, "tolist") else list(coords)
    if len(rows) != len(mech.nodes):
        raise ModelError([Problem("nodes", f"{len(rows)} coordinate rows given for the "
                                           f"{len(mech.nodes)} nodes of {mech.name!r}")])
    return rows


def _checked_nodes(mech: "Mechanism", rows: list) -> tuple:
    """``mech.nodes`` with the coordinates ``rows``: finite numbers, ``dim`` per node."""
    try:
        xyz = [tuple(map(float, row)) for row in rows]
    except (TypeError, ValueError):
        xyz = None
    if xyz is not None and all(len(c) == mech.dim for c in xyz) \
            and all(map(math.isfinite, chain.from_iterable(xyz))):
        return tuple(zip(mech.node_names, xyz))
    raise ModelError(_coordinate_problems(mech, rows))


def _coordinate_problems(mech: "Mechanism", rows: list) -> list:
    """Every node whose new coordinates are not ``dim`` finite numbers."""
    problems = []
    for (name, _), row in zip(mech.nodes, rows):
        try:
            xyz = tuple(map(float, row))
        except (TypeError, ValueError):
            problems.append(Problem(f"nodes.{name}", f"coordinates must be numbers, got {row!r}"))
            continue
        if len(xyz) != mech.dim:
            problems.append(Problem(f"nodes.{name}", f"coordinates must have {mech.dim} components "
                                                     f"(dim = {mech.dim}), got {len(xyz)}"))
        elif not all(map(math.isfinite, xyz)):
            problems.append(Problem(f"nodes.{name}", f"coordinates must be finite, got {list(xyz)!r}"))
    return problems



#: a link with more node pairs than this gets the mean over this many pairs drawn by a
#: fixed-seed generator (relative error about 1e-3; the same number on every run)
EXACT_PAIRS = 1 << 19


def length_scale(coordinates: Mapping, links: Iterable) -> float:
    """Mean distance between the node pairs inside links (node lists); 1 when there is none.

    The model's own unit of length (:mod:`symkin.tolerances`): the Mechanism's
    ``length_scale`` and the validation of model files use this one definition.  Pairs
    with a missing node or coordinates of different lengths are skipped (a file being
    validated may have both).  A rigid body of k nodes has k(k-1)/2 pairs: above
    :data:`EXACT_PAIRS` of them, the mean is taken over that many pairs drawn by a
    generator seeded with k, so that a body of 30,000 nodes costs what one of 1,000 does.

    >>> length_scale({"A": (0.0, 0.0), "B": (3.0, 4.0)}, [("A", "B")])
    5.0
    """
    total, count = 0.0, 0
    for ns in links:
        pts = [p for p in (coordinates.get(n) for n in ns) if p is not None]
        k = len(pts)
        if k * (k - 1) // 2 <= EXACT_PAIRS:
            pairs = ((i, j) for i in range(k) for j in range(i + 1, k))
        else:
            import random

            rng = random.Random(k)
            pairs = ((i, j + (j >= i)) for i, j in ((rng.randrange(k), rng.randrange(k - 1))
                                                    for _ in range(EXACT_PAIRS)))
        for i, j in pairs:
            if len(pts[i]) == len(pts[j]):
                total += math.dist(pts[i], pts[j])
                count += 1
    return total / count if count and total > 0 else 1.0


@dataclass(frozen=True)
class Mechanism:
    """A mechanism at one configuration.

    Attributes are tuples so that a mechanism is hashable and can key caches.  Use
    :meth:`coordinates`, :meth:`link_nodes` and friends rather than the raw tuples.

    Examples
    --------
    >>> from symkin import Mechanism
    >>> m = Mechanism.from_dict({
    ...     "name": "four-bar", "dim": 2, "fixed": ["A", "D"],
    ...     "inputs": [{"rotation": "crank"}],
    ...     "nodes": {"A": [0, 0], "B": [0.2, 0.9], "C": [2.1, 1.3], "D": [2, 0]},
    ...     "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})
    >>> m.mobility_value, m.free_nodes
    (1, ('B', 'C'))
    """

    name: str
    dim: int
    nodes: tuple[tuple[str, tuple[float, ...]], ...]
    links: tuple[tuple[str, tuple[str, ...]], ...]
    fixed: tuple[str, ...] = ()
    sliders: tuple[Slider, ...] = ()
    inputs: tuple[Parameter, ...] = ()
    outputs: tuple[Parameter, ...] = ()
    mobility: int | None = None
    platform: str | None = None
    platform_dof: int | None = None
    description: str = field(default="", compare=False)
    #: the joints the model was written with (:mod:`symkin.model.joints`), as given; the
    #: fields above hold their node form, which is what every stage analyses
    joints: tuple = field(default=(), compare=False)
    #: ``(label, Parameter)`` of every joint rate an existing parameter expresses (``joint:R1``)
    joint_rates: tuple = field(default=(), compare=False)
    #: the records of the extra constraints (:class:`~symkin.model.pairs.ExtraConstraint`:
    #: pairs whose rows the nodal method does not have, compiled from their joints), grouped
    #: by kind in registration order; ``mech.<key>`` gives one kind's (see :meth:`__getattr__`)
    extras: tuple = ()

    def __getattr__(self, name: str):
        """``mech.<key>``: the records of the extra-constraint kind registered under the model
        key ``<key>`` (:func:`symkin.model.pairs.extra_kind`), a read-only tuple."""
        kind = extra_kind(name) if not name.startswith("__") else None
        if kind is None:
            raise AttributeError(f"'Mechanism' object has no attribute {name!r}")
        return tuple(r for r in self.__dict__.get("extras", ()) if isinstance(r, kind))

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_dict(cls, data: Mapping, source: str | None = None) -> "Mechanism":
        """Build and validate a mechanism from the model-file dictionary (README schema)."""
        from symkin.model.validation import parse_mechanism

        return parse_mechanism(data, source=source)

    def to_dict(self) -> dict:
        """The model-file dictionary; ``Mechanism.from_dict(m.to_dict()) == m``."""
        out: dict = {"name": self.name, "dim": self.dim, "fixed": list(self.fixed)}
        if self.description:
            out["description"] = self.description
        if self.mobility is not None:
            out["mobility"] = self.mobility
        out["inputs"] = [p.to_dict() for p in self.inputs]
        out["outputs"] = [p.to_dict() for p in self.outputs]
        if self.platform is not None:
            out["platform"] = self.platform
        if self.platform_dof is not None:
            out["platform_dof"] = self.platform_dof
        out["nodes"] = {name: list(xyz) for name, xyz in self.nodes}
        out["links"] = {name: list(ns) for name, ns in self.links}
        if self.sliders:
            out["sliders"] = [s.to_dict() for s in self.sliders]
        for kind in extra_kinds():
            records = [r.to_dict() for r in self.extras if isinstance(r, kind)]
            if records:
                out[kind.key] = records
        return out

    def with_coordinates(self, coords: Mapping[str, Iterable[float]] | Iterable) -> "Mechanism":
        """A copy at another configuration (same topology, parameters, sliders).

        ``coords`` maps node names to coordinates (nodes not named keep theirs), or is an
        (n, dim) array in node order.  This is the fast path used along paths, meshes and
        notebook loops: the topology is not validated again (and the copy shares its
        :attr:`topology`), only the coordinates are checked: finite numbers, ``dim`` per
        node; a :class:`~symkin.errors.ModelError` names the node at fault.

        Examples
        --------
        >>> from symkin.model.catalogue import get
        >>> m = get("fourbar_appendix")
        >>> m.with_coordinates({"B": (0.0, 1.0)}).coordinates()["B"]
        (0.0, 1.0)
        >>> m.with_coordinates({"B": (0.0, float("nan"))})
        Traceback (most recent call last):
        ...
        symkin.errors.ModelError: nodes.B: coordinates must be finite, got [0.0, nan]
        """
        nodes = _float_array_nodes(self, coords)
        if nodes is None:
            nodes = _checked_nodes(self, _coordinate_rows(self, coords))
        topology = self.topology
        # a copy of every field but the nodes, with the cached topology-only properties
        # (topology, node names, mobility, ...); nothing cached depends on coordinates
        new = object.__new__(Mechanism)
        new.__dict__.update(self.__dict__)
        new.__dict__["nodes"] = nodes
        new.__dict__["topology"] = topology
        return new

    def moved(self, rotation=None, translation=None, scale: float = 1.0) -> "Mechanism":
        """The same mechanism after ``x ↦ scale · R x + t`` (a similarity).

        ``rotation`` is a (dim, dim) orthogonal matrix (nested lists or an array);
        slider points, directions and normals and vector rotation axes move with the
        nodes.  Units change by a scale alone: ``m.moved(scale=1000)`` is ``m`` in mm.
        """
        dim = self.dim
        rot = [[float(rotation[i][j]) for j in range(dim)] for i in range(dim)] if rotation is not None \
            else [[1.0 if i == j else 0.0 for j in range(dim)] for i in range(dim)]
        shift = [float(v) for v in translation] if translation is not None else [0.0] * dim

        def turn(v):
            return tuple(sum(rot[i][j] * v[j] for j in range(dim)) for i in range(dim))

        def place(v):
            return tuple(scale * c + t for c, t in zip(turn(v), shift))

        sliders = tuple(replace(s, point=place(s.point) if s.point is not None else None,
                                direction=turn(s.direction) if s.direction is not None else None,
                                normal=turn(s.normal) if s.normal is not None else None)
                        for s in self.sliders)

        def param(p: Parameter) -> Parameter:
            if p.axis is not None and not isinstance(p.axis[0], str):
                return replace(p, axis=turn(p.axis))
            return p

        return replace(self, nodes=tuple((n, place(x)) for n, x in self.nodes), sliders=sliders,
                       extras=tuple(r.moved(turn, place, scale) for r in self.extras),
                       inputs=tuple(param(p) for p in self.inputs),
                       outputs=tuple(param(p) for p in self.outputs),
                       joint_rates=tuple((lab, param(p)) for lab, p in self.joint_rates),
                       joints=tuple(j.moved(turn, place, scale) for j in self.joints))

    # ------------------------------------------------------------------ queries
    @cached_property
    def topology(self) -> Topology:
        """The mechanism without its coordinates (see :class:`Topology`)."""
        return Topology((self.dim, self.node_names, self.links, self.fixed, self.sliders,
                         self.inputs, self.outputs, self.mobility, self.platform, self.platform_dof)
                        + ((self.extras,) if self.extras else ()))

    @cached_property
    def node_names(self) -> tuple[str, ...]:
        return tuple(n for n, _ in self.nodes)

    @property
    def link_names(self) -> tuple[str, ...]:
        return tuple(n for n, _ in self.links)

    def coordinates(self) -> dict[str, tuple[float, ...]]:
        """Node name → coordinates."""
        return dict(self.nodes)

    def link_nodes(self, link: str) -> tuple[str, ...]:
        return self._link_table[link]

    @cached_property
    def _link_table(self) -> dict[str, tuple[str, ...]]:
        return dict(self.links)

    def node_index(self) -> dict[str, int]:
        return {n: i for i, (n, _) in enumerate(self.nodes)}

    @cached_property
    def free_nodes(self) -> tuple[str, ...]:
        fixed = set(self.fixed)
        return tuple(n for n in self.node_names if n not in fixed)

    @cached_property
    def ground_links(self) -> tuple[str, ...]:
        """Links whose nodes are all fixed."""
        fixed = set(self.fixed)
        return tuple(name for name, ns in self.links if all(n in fixed for n in ns))

    @cached_property
    def moving_links(self) -> tuple[str, ...]:
        ground = set(self.ground_links)
        return tuple(name for name in self.link_names if name not in ground)

    def slider(self, ref: str) -> Slider:
        """The slider named ``ref``: by id, or by node when the node has one slider."""
        by_id, by_node = self._slider_table
        if ref in by_id:
            return by_id[ref]
        on_node = by_node.get(ref, ())
        if len(on_node) == 1:
            return on_node[0]
        raise KeyError(ref)

    @cached_property
    def _slider_table(self) -> tuple[dict[str, Slider], dict[str, list[Slider]]]:
        by_id: dict[str, Slider] = {}
        by_node: dict[str, list[Slider]] = {}
        for s in self.sliders:
            by_id.setdefault(s.id, s)
            by_node.setdefault(s.node, []).append(s)
        return by_id, by_node

    @cached_property
    def io_parameters(self) -> ParameterList:
        """The inputs then the outputs, as one :class:`ParameterList`."""
        return ParameterList(tuple(self.inputs) + tuple(self.outputs))

    @cached_property
    def n_inputs(self) -> int:
        return sum(p.size(self.dim) for p in self.inputs)

    @cached_property
    def n_outputs(self) -> int:
        return sum(p.size(self.dim) for p in self.outputs)

    @cached_property
    def mobility_value(self) -> int:
        """Full-cycle mobility F: ``mobility`` if given, else the number of scalar inputs."""
        return self.mobility if self.mobility is not None else self.n_inputs

    @property
    def length_scale(self) -> float:
        """Mean distance between the node pairs inside links: the model's own unit of length."""
        return length_scale(self.coordinates(), (ns for _, ns in self.links))

    def content_hash(self) -> str:
        """SHA-256 of the canonical JSON form (keys caches of generated code)."""
        text = json.dumps(self.to_dict(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()
