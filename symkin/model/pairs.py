"""Pair kinds: the registry through which a kinematic pair is defined once (issue 16).

A pair kind is **one module**.  What the model stage needs of it is declared here (standard
library only: the model stage imports neither NumPy, sympy nor CasADi, nor
:mod:`symkin.constraints`), in two parts:

* a :class:`JointKind`: the ``type`` letter of a ``[[joints]]`` entry and everything
  :mod:`symkin.model.joints` does by type: the dimensions it is allowed in, whether it needs
  ``axis`` and ``axis2``, its own keys (:class:`JointKey`, scalars such as a length) and
  their checks, a check across its keys, its compile step (given the builder of the node
  form), a second pass once every joint has placed its nodes, its rates (``motions``), how an
  input entry picks one of them and which links a rotation rate is between;
* an :class:`ExtraConstraint` record class, for a pair that adds a constraint the nodal
  method does not express with shared nodes, bars, bodies and sliders: the key of the model
  dictionary holding its records (a list of tables, like ``sliders``), the keys of a
  record, ``parse`` (a table of the model dictionary to a record, problems reported with the
  key at fault), ``to_dict``, ``moved`` (a similarity, units included) and ``constraint``
  (its rows: a :class:`symkin.constraints.base.Constraint`, the one definition every backend
  evaluates).

Where the kinds live, and how they are found
-------------------------------------------
The joints R, P, C, U and S register in :mod:`symkin.model.joints`: they compile to nodes,
links and sliders, which the paper's method already has, and add no row of their own.  A
pair with rows of its own is one module of :mod:`symkin.constraints` (which may import the
model stage; the reverse is forbidden) that defines its record, its joint kind and its
constraint and registers the first two here.  Discovery needs no list: ``import symkin``
imports :mod:`symkin.constraints`, whose ``__init__`` imports every module of its package,
so a new file there is registered before any model is parsed (any ``import symkin.…`` runs
``symkin/__init__`` first).  Kinds are kept in registration order: the built-in joints
first, then the modules of :mod:`symkin.constraints` by name; the order of the extra
records, and of their rows, follows it.

A :class:`~symkin.model.mechanism.Mechanism` holds the records of every extra kind in one
tuple, :attr:`~symkin.model.mechanism.Mechanism.extras`; ``mech.<key>`` gives those of one
kind (the records under that key of the model dictionary), and :meth:`Mechanism.to_dict` writes
them under their key, so model files and scripts read as they did when each kind had a field.

Examples
--------
>>> import symkin
>>> [k.type for k in joint_kinds()][:5], joint_types(2)
(['R', 'P', 'C', 'U', 'S'], ('R', 'P'))
>>> joint_keys()[:6]
('id', 'type', 'links', 'at', 'axis', 'axis2')
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, ClassVar, Mapping

__all__ = ["JointKey", "JointKind", "ExtraConstraint", "ItemContext", "BASE_JOINT_KEYS",
           "register_joint", "register_extra", "joint_kind", "joint_kinds", "joint_types", "joint_keys",
           "key_owners", "extra_kind", "extra_kinds", "extra_keys"]

#: the keys every joint table may have (a kind adds its own: :attr:`JointKind.keys`)
BASE_JOINT_KEYS = ("id", "type", "links", "at", "axis", "axis2")


@dataclass(frozen=True)
class JointKey:
    """A joint kind's own scalar key.

    ``needs`` is said when the key is missing (what it is), ``must`` when its value is not a
    finite number (what it must be); a key with ``length`` true is a length and scales with
    the model's unit (:meth:`Mechanism.moved`).
    """

    name: str
    needs: str
    must: str
    length: bool = True


@dataclass(frozen=True)
class JointKind:
    """What a joint ``type`` is (see the module docstring).

    Attributes
    ----------
    type : str
        The letter of ``type = "…"`` in a ``[[joints]]`` table.
    dims : tuple of int
        The model dimensions (2, 3) it is allowed in.
    compile : callable
        ``compile(builder, joint)``: adds the joint's nodes, link memberships, sliders and
        extra records to the builder of :mod:`symkin.model.joints` (its ``shared``, ``line``,
        ``extra`` methods; ``reach``, ``dim``, ``problems``); reports problems there.
    axis : tuple of int
        The dimensions in which it needs ``axis`` (elsewhere ``axis`` is an error).
    axis2 : bool
        Whether it needs ``axis2``.
    keys : tuple of JointKey
        Its own keys (each required, a finite number).
    motions : tuple of str
        Its rates: ``"rotation"``, ``"slide"`` or other names (U: ``"1"``, ``"2"``); a kind
        with one rate labels it ``joint:<id>``, with more ``joint:<id>.<motion>``; "slide" is
        the slide of the slider named after the joint.
    choice : tuple or None
        ``(key, values)``: the key of an input entry that picks the motion when there are
        several (C: ``("motion", ("rotation", "slide"))``; U: ``("axis", (1, 2))``, the motion
        being ``str(value)``).
    check : callable or None
        ``check(joint, limits)``: a problem across its keys (a message) or None.
    finish : callable or None
        ``finish(builder, joint)``: a second pass once every joint has placed its nodes.
    rate_links : callable or None
        ``rate_links(joint, motion) -> (first, second, axis)``: the links whose relative
        rotation a spatial rate is, and its axis; by default the joint's two links and ``axis``.
    title : str
        How messages name the kind (default ``"a <type> joint"``).
    article : str
        ``"a"`` or ``"an"`` before the letter (``"an S"``).
    block : bool
        How plots draw it: the runner's node as a block on the joint's line (the slider named
        after the joint) and the leg whole along that line (P, C, H).
    axes : tuple of str
        How plots draw it in space: a short axis through the joint's centre towards each added
        node ``<id>.<suffix>`` listed (R: ``("axis",)``; U: ``("axis", "axis2")``).
    """

    type: str
    dims: tuple[int, ...]
    compile: Callable[[Any, Any], None]
    axis: tuple[int, ...] = ()
    axis2: bool = False
    keys: tuple[JointKey, ...] = ()
    motions: tuple[str, ...] = ()
    choice: tuple[str, tuple] | None = None
    check: Callable[[Any, Any], str | None] | None = None
    finish: Callable[[Any, Any], None] | None = None
    rate_links: Callable[[Any, str], tuple] | None = None
    title: str = ""
    article: str = "a"
    block: bool = False
    axes: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        """The kind as messages name it: ``title``, else ``"a <type> joint"``."""
        return self.title or f"a {self.type} joint"


@dataclass(frozen=True)
class ItemContext:
    """What :meth:`ExtraConstraint.parse` may use: the model parsed so far and the checks of
    :mod:`symkin.model.validation` (so that every kind reports alike).

    ``nodes`` maps node names to coordinates (None for an invalid node), ``links`` link names
    to node tuples; ``problem(key, message)`` records a problem; ``vector(value, key, what)``
    and ``direction(value, key, what)`` return a checked tuple of ``dim`` floats (a direction
    also nonzero) or None after recording the problem; ``number(value)`` tells a real number
    (not a bool); ``short(value)`` is a ``repr`` cut for messages.
    """

    dim: int | None
    nodes: Mapping[str, Any]
    links: Mapping[str, tuple]
    problem: Callable[[str, str], None]
    vector: Callable[[Any, str, str], tuple | None]
    direction: Callable[[Any, str, str], tuple | None]
    number: Callable[[Any], bool]
    short: Callable[[Any], str]


class ExtraConstraint:
    """Base of the record classes of extra constraints (frozen dataclasses; see the module docstring).

    A subclass sets :attr:`key` and :attr:`keys` and defines the four methods; it is
    registered with :func:`register_extra`.  Records are hashable (they are part of the
    mechanism's :class:`~symkin.model.mechanism.Topology`).
    """

    #: the key of the model dictionary whose list of tables holds the records
    key: ClassVar[str] = ""
    #: the keys a record's table may have
    keys: ClassVar[tuple[str, ...]] = ()

    @classmethod
    def parse(cls, item: Mapping, where: str, ctx: ItemContext) -> "ExtraConstraint | None":
        """The record of the table ``item`` (at ``where``, ``"<key>[<k>]"``), or None
        after reporting every problem through ``ctx.problem``."""
        raise NotImplementedError

    def to_dict(self) -> dict:
        """The table of the model dictionary: ``parse(to_dict())`` gives the record back."""
        raise NotImplementedError

    def moved(self, turn: Callable, place: Callable, scale: float) -> "ExtraConstraint":
        """The record after the similarity ``x ↦ scale·R x + t``: ``turn`` maps a vector
        (``R v``), ``place`` a point, ``scale`` multiplies lengths."""
        raise NotImplementedError

    def constraint(self, index: Mapping[str, int]):
        """Its :class:`~symkin.constraints.base.Constraint` (``index``: node name → position)."""
        raise NotImplementedError


_JOINTS: dict[str, JointKind] = {}
_EXTRAS: dict[str, type] = {}


def register_joint(kind: JointKind) -> JointKind:
    """Register ``kind`` under its type letter (again: replaced, keeping its place)."""
    _JOINTS[kind.type] = kind
    return kind


def register_extra(cls: type) -> type:
    """Register the record class ``cls`` under its :attr:`~ExtraConstraint.key` (a decorator)."""
    if not (isinstance(cls, type) and issubclass(cls, ExtraConstraint) and cls.key):
        raise TypeError(f"{cls!r} is not an ExtraConstraint with a key")
    _EXTRAS[cls.key] = cls
    return cls


def joint_kind(jtype: Any) -> JointKind | None:
    """The kind of type letter ``jtype``, or None."""
    return _JOINTS.get(jtype) if isinstance(jtype, str) else None


def joint_kinds() -> tuple[JointKind, ...]:
    """Every joint kind, in registration order."""
    return tuple(_JOINTS.values())


def joint_types(dim: int) -> tuple[str, ...]:
    """The type letters allowed in a model of dimension ``dim``."""
    return tuple(k.type for k in _JOINTS.values() if dim in k.dims)


def joint_keys() -> tuple[str, ...]:
    """Every key a joint table may have: :data:`BASE_JOINT_KEYS`, then the kinds' own keys."""
    out = list(BASE_JOINT_KEYS)
    for kind in _JOINTS.values():
        out += [k.name for k in kind.keys if k.name not in out]
    return tuple(out)


def key_owners(name: str) -> tuple[JointKind, ...]:
    """The kinds that have their own key ``name``."""
    return tuple(k for k in _JOINTS.values() if any(key.name == name for key in k.keys))


def extra_kind(key: str) -> type | None:
    """The record class registered under the model-dictionary key ``key``, or None."""
    return _EXTRAS.get(key)


def extra_kinds() -> tuple[type, ...]:
    """Every extra-constraint record class, in registration order."""
    return tuple(_EXTRAS.values())


def extra_keys() -> tuple[str, ...]:
    """The model-dictionary keys of the extra constraints, in registration order."""
    return tuple(_EXTRAS)
