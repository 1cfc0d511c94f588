"""Labels of the constraint rows, from the owners the core gives them.

A bar of a two-node link is labelled by its link (``crank``), a pair of a body by the link and
its nodes (``platform[C1-C2]``), a body's rows out of its hull ``link:rigidity[k]``, a large
model's affine rows ``link:affine[N]``, a slider's rows ``slider:ID`` (``slider:ID[k]`` when it
has several).  The statics (:mod:`symkin.analysis.statics`) and the sparse path
(:mod:`symkin.analysis.sparse`) name their self-stresses with them.
"""
from __future__ import annotations

import re
from functools import lru_cache

from symkin.model.mechanism import Mechanism

__all__ = ["constraint_labels", "PAIR_OWNER", "RIGIDITY_OWNER", "SLIDER_OWNER", "AFFINE_OWNER"]

PAIR_OWNER = re.compile(r"^link (?P<link>.+) \((?P<a>[^()]+)-(?P<b>[^()]+)\)$")
RIGIDITY_OWNER = re.compile(r"^link (?P<link>.+) \(rigidity out of its hull\)$")
SLIDER_OWNER = re.compile(r"^slider (?P<id>.+)$")
AFFINE_OWNER = re.compile(r"^link (?P<link>.+) \(affine (?P<node>[^()]+)\)$")


def constraint_labels(mech: Mechanism, owners) -> tuple[str, ...]:
    """Labels of the constraint rows (see module docstring) from their ``owners``.

    >>> from symkin.model.catalogue import get
    >>> from symkin.numeric.geometric_matrix import constraint_rows
    >>> m = get("slider_crank")
    >>> constraint_labels(m, constraint_rows(m).owners)
    ('crank', 'rod', 'slider:piston')
    """
    return _labels(tuple((name, len(ns)) for name, ns in mech.links), tuple(owners))


@lru_cache(maxsize=1024)
def _labels(sizes: tuple, owners: tuple) -> tuple[str, ...]:
    """Cached on the topology: a mechanism moved along a path keeps its owners."""
    sizes = dict(sizes)
    counts: dict[str, int] = {}
    for o in owners:
        counts[o] = counts.get(o, 0) + 1
    seen: dict[str, int] = {}
    out = []
    for o in owners:
        seen[o] = seen.get(o, 0) + 1
        k = seen[o]
        if m := PAIR_OWNER.match(o):
            link = m["link"]
            out.append(link if sizes.get(link) == 2 else f"{link}[{m['a']}-{m['b']}]")
        elif m := RIGIDITY_OWNER.match(o):
            out.append(f"{m['link']}:rigidity[{k}]")
        elif m := AFFINE_OWNER.match(o):
            out.append(f"{m['link']}:affine[{m['node']}]")
        elif m := SLIDER_OWNER.match(o):
            out.append(f"slider:{m['id']}" if counts[o] == 1 else f"slider:{m['id']}[{k}]")
        else:  # a new kind of row in the core: keep its owner as the label
            out.append(o if counts[o] == 1 else f"{o}[{k}]")
    return tuple(out)
