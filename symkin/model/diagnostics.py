"""Warnings for legal models that a user probably got wrong (plain data, no numerics).

A model can be valid and still odd: a part connected to nothing fixed floats (its rigid
motions are counted in the DOF), a model may have no fixed node at all, or the same bar
may be listed twice under two names.  These depend on the topology only (names, links,
fixed nodes, which sliders exist), so :func:`topology_warnings` is cached on it: a
mechanism moved along a path (:meth:`Mechanism.with_coordinates`) reuses the answer.

The warning that needs the analysis (the mobility taken from the number of inputs) is
:func:`mobility_warning`; :func:`symkin.analysis.classification.analyze` gathers both.
"""
from __future__ import annotations

from functools import lru_cache

from symkin.model.mechanism import Mechanism

__all__ = ["topology_warnings", "mobility_warning"]


def _names(items) -> str:
    return ", ".join(items)


def topology_warnings(mech: Mechanism) -> tuple[str, ...]:
    """Sentences about odd topology, each naming the nodes or links concerned.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> topology_warnings(get("fourbar_appendix"))
    ()
    >>> d = get("fourbar_appendix").to_dict(); d["links"]["tie"] = ["C", "B"]
    >>> print(topology_warnings(Mechanism.from_dict(d))[0])
    Links coupler and tie join the same nodes (B, C): the same bar is listed twice (it carries a self-stress).
    """
    sliders = tuple((s.node, s.carriers) for s in mech.sliders)
    return _topology_warnings(mech.node_names, mech.links, mech.fixed, sliders)


@lru_cache(maxsize=1024)
def _topology_warnings(node_names, links, fixed, sliders) -> tuple[str, ...]:
    out = []
    grounded_by_slider = {node for node, carriers in sliders if not carriers}
    if not fixed:
        where = (f"; only the sliders on fixed lines or planes ({_names(sorted(grounded_by_slider))}) hold it"
                 if grounded_by_slider else "")
        out.append("The model has no fixed node: its rigid motions as a whole are counted in the "
                   f"instantaneous DOF L{where}; declare 'fixed' nodes for the ground.")
    if fixed or grounded_by_slider:
        out += _floating_parts(node_names, links, set(fixed), grounded_by_slider, sliders)
    out += _duplicates(links)
    return tuple(out)


def _floating_parts(node_names, links, fixed, grounded, sliders) -> list[str]:
    """Connected components (through links and moving-line sliders) with nothing fixed."""
    parent = {n: n for n in node_names}

    def find(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    def join(a, b):
        parent[find(a)] = find(b)

    for _, ns in links:
        for n in ns[1:]:
            join(ns[0], n)
    for node, carriers in sliders:
        for other in carriers:
            join(node, other)
    parts: dict[str, list[str]] = {}
    for n in node_names:
        parts.setdefault(find(n), []).append(n)
    out = []
    for nodes in parts.values():
        if any(n in fixed or n in grounded for n in nodes):
            continue
        members = set(nodes)
        names = [name for name, ns in links if ns[0] in members]
        out.append(f"Nodes {_names(nodes)} (links {_names(names)}) are connected to nothing fixed: "
                   "this part floats, and its rigid motions are counted in the instantaneous DOF L.")
    return out


def _duplicates(links) -> list[str]:
    """Two links (bars, or bodies) on exactly the same set of nodes."""
    seen: dict[frozenset, str] = {}
    out = []
    for name, ns in links:
        key = frozenset(ns)
        if key in seen:
            what = "bar" if len(ns) == 2 else "body"
            out.append(f"Links {seen[key]} and {name} join the same nodes ({_names(sorted(ns))}): "
                       f"the same {what} is listed twice (it carries a self-stress).")
        else:
            seen[key] = name
    return out


def mobility_warning(mech: Mechanism, dof: int) -> str | None:
    """A sentence when F was taken from the number of inputs and the DOF ``dof`` differs.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> d = get("five_bar").to_dict(); d["inputs"] = d["inputs"][:1]
    >>> print(mobility_warning(Mechanism.from_dict(d), 2))
    No 'mobility' is declared, so F = 1 was taken from the 1 scalar input(s) (rotation:crank1), but the instantaneous DOF is L = 2: if the mechanism's full-cycle mobility is 2, declare mobility = 2 (or list 2 inputs); if L differs from F only at this configuration (a singularity), declare mobility = 1 to silence this warning.
    """
    if mech.mobility is not None or dof == mech.n_inputs:
        return None
    n = mech.n_inputs
    labels = [lab for p in mech.inputs for lab in p.labels(mech.dim)]
    which = f" ({_names(labels)})" if labels else ""
    return (f"No 'mobility' is declared, so F = {n} was taken from the {n} scalar input(s){which}, "
            f"but the instantaneous DOF is L = {dof}: if the mechanism's full-cycle mobility is {dof}, "
            f"declare mobility = {dof} (or list {dof} inputs); if L differs from F only at this "
            f"configuration (a singularity), "
            f"declare mobility = {n} to silence this warning.")
