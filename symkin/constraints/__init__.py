"""One definition per constraint kind, for every backend (issue 16).

Each kind is one module stating its velocity rows and position equations once, over an
algebra (:mod:`symkin.constraints.algebra`: floats, CasADi SX, sympy).  The nodal method's
own elements:

==========================  ==================================================================
module                      constraint
==========================  ==================================================================
:mod:`.bar`                 a pair of nodes of a link (paper eqs. A3, A4)
:mod:`.body`                the rows of a degenerate body out of its hull
:mod:`.slider_line`         a node on a fixed line
:mod:`.slider_plane`        a node on a fixed plane
:mod:`.slider_moving_line`  a node on the moving line through two nodes of a link
==========================  ==================================================================

and, each in a module of its own, the **pair kinds** whose rows the nodal method does not
have: such a module defines everything of its pair and registers it in
:mod:`symkin.model.pairs` — the joint kind (type letter, keys, compile step, rates), the
record of its extra constraint (model-dictionary key, parse, ``to_dict``, ``moved``) and its
:class:`~symkin.constraints.base.Constraint`.

**What a new pair kind touches now: one file here plus its test.**  Importing this
package (which ``import symkin`` does, before any model is parsed) imports every module of
it (:mod:`pkgutil`, by name, but those starting with ``_``; after the built-in joints of
:mod:`symkin.model.joints`), so a
new module registers itself with no other edit: the model file's parser, the joint
compiler, the numeric core, the CasADi model, the symbolic rows and the polynomial systems
(which refuse a constraint that is not :attr:`~base.Constraint.polynomial`, naming it) all
take it through the registry and :func:`constraints_of`; tests/test_pair_kinds.py proves it
with a kind written to a single new file.

:func:`constraints_of` is the list every backend iterates (the numeric core, the CasADi
model, the symbolic rows, the polynomial systems), in the core's row order: link by link
(its bars, then its body marker), then the sliders, then the extra constraints
(:attr:`Mechanism.extras <symkin.model.mechanism.Mechanism.extras>`, kind by kind in
registration order), each its record's :meth:`~symkin.model.pairs.ExtraConstraint.constraint`.

Examples
--------
>>> from symkin.model.catalogue import get
>>> [c.owner for c in constraints_of(get("slider_crank"))][-1]
'slider piston'
"""
from __future__ import annotations

import importlib
import pkgutil
from functools import lru_cache

from symkin.model import joints as _joints  # noqa: F401  (the built-in joint kinds register first: their order in messages)
from symkin.constraints.bar import Bar
from symkin.constraints.base import Constraint, Equation, Row
from symkin.constraints.body import Body
from symkin.constraints.slider_line import SliderLine
from symkin.constraints.slider_moving_line import SliderMovingLine
from symkin.constraints.slider_plane import SliderPlane
from symkin.errors import ModelError, Problem

__all__ = ["Constraint", "Row", "Equation", "Bar", "Body", "SliderLine", "SliderPlane", "SliderMovingLine",
           "constraints_of", "bar_constraint", "body_constraint", "body_constraints", "slider_constraints",
           "slider_constraint", "polynomial_constraints", "DISCOVERED"]


def _discover() -> tuple[str, ...]:
    """Import every module of this package, by name (the pair kinds register themselves)."""
    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))
    for name in names:
        importlib.import_module(f"{__name__}.{name}")
    return tuple(names)


#: the modules of the package, imported when it is (their pair kinds registered)
DISCOVERED = _discover()


def _slider(s, index: dict) -> Constraint:
    """The constraint of a :class:`~symkin.model.mechanism.Slider` (its form decides the kind)."""
    if s.line is not None:
        return SliderMovingLine(s, index[s.node], index[s.line[0]], index[s.line[1]])
    if s.normal is not None:
        return SliderPlane(s, index[s.node])
    return SliderLine(s, index[s.node])


@lru_cache(maxsize=128)
def _of_model(topology) -> tuple:
    index = {n: i for i, n in enumerate(topology.node_names)}
    out: list[Constraint] = []
    for name, ns in topology.links:
        for a in range(len(ns)):
            for b in range(a + 1, len(ns)):
                out.append(Bar(name, ns[a], ns[b], index[ns[a]], index[ns[b]]))
        if len(ns) >= 3:
            out.append(Body(name, ns, tuple(index[n] for n in ns)))
    out += [_slider(s, index) for s in topology.sliders]
    out += [r.constraint(index) for r in topology.extras]  # each pair kind's own Constraint
    return tuple(out)


def constraints_of(mech) -> tuple[Constraint, ...]:
    """Every constraint of ``mech``, in the row order of the numeric core (cached per topology)."""
    return _of_model(mech.topology)


@lru_cache(maxsize=128)
def _bars(topology) -> dict:
    return {(c.link, frozenset((c.a, c.b))): c for c in _of_model(topology) if isinstance(c, Bar)}


@lru_cache(maxsize=128)
def _body_list(topology) -> tuple:
    return tuple(c for c in _of_model(topology) if isinstance(c, Body))


def body_constraints(mech) -> tuple[Body, ...]:
    """The :class:`Body` constraints (links of 3+ nodes), in link order (cached per topology)."""
    return _body_list(mech.topology)


def body_constraint(mech, link: str) -> Body:
    """The :class:`Body` of ``link`` (a link of 3+ nodes)."""
    return next(b for b in _body_list(mech.topology) if b.link == link)


def bar_constraint(mech, link: str, a: str, b: str) -> Bar:
    """The :class:`Bar` of the pair ``a``, ``b`` (either order) of ``link``."""
    return _bars(mech.topology)[(link, frozenset((a, b)))]


@lru_cache(maxsize=128)
def _after_links(topology) -> tuple:
    return tuple(c for c in _of_model(topology) if not isinstance(c, (Bar, Body)))


def slider_constraints(mech) -> tuple[Constraint, ...]:
    """The constraints after the links' (sliders, then extra constraints), in order (cached per topology)."""
    return _after_links(mech.topology)


def slider_constraint(mech, ref: str) -> Constraint:
    """The constraint of the slider ``ref`` (by id, or by node: :meth:`Mechanism.slider`)."""
    s = mech.slider(ref)
    return next(c for c in slider_constraints(mech) if getattr(c, "slider", None) == s)


def polynomial_constraints(mech, what: str) -> tuple[Constraint, ...]:
    """:func:`constraints_of`, or a :class:`~symkin.errors.ModelError` naming every constraint
    whose position equation is not polynomial (:attr:`~base.Constraint.polynomial` false) for
    ``what`` (e.g. "the global solve")."""
    cs = constraints_of(mech)
    bad = [c for c in cs if not c.polynomial]
    if bad:
        raise ModelError([Problem(c.where, f"{what} needs polynomial position equations; the {c.kind} "
                                           f"constraint of {c.owner.split()[-1]} {c.why_not_polynomial}, "
                                           "which is not polynomial: use analyze, path, map or "
                                           "conditions for this model") for c in bad])
    return cs
