"""Labels of position-level coordinates: ``rotation:crank``, ``slide:piston``, ``velocity:P.x``.

The pure part of what ``symkin path --input``, ``symkin map --x/--hold`` and
``symkin conditions --in/--hold`` accept: a label names a kinematic parameter of the model
(one of its inputs or outputs, or a rotation of a moving link, a slide of a slider, a
coordinate of a free node), and a scalar *coordinate* whose rate is that parameter.  Plain
data, no numerics: the stages to the right give the coordinate its value (CasADi in
:mod:`symkin.numeric.coordinates`, polynomials in :mod:`symkin.symbolic.loci`).
"""
from __future__ import annotations

from dataclasses import dataclass

from symkin.errors import SymkinError
from symkin.model.mechanism import AXES, Mechanism, Parameter
from symkin.tolerances import DEFAULT

__all__ = ["CoordinateLabel", "coordinate_labels", "accepted_labels", "parse_label", "parse_hold",
           "OrientationLabel", "parse_orientation_label", "parse_holds", "ORIENTATION_AXES"]


@dataclass(frozen=True)
class CoordinateLabel:
    """One scalar coordinate named by a label.

    ``kind`` is ``"angle"`` (radians) or ``"length"`` (model units); ``component`` picks the
    axis of a whole-node velocity parameter (``velocity: P`` gives ``velocity:P.x`` and
    ``velocity:P.y``).
    """

    label: str
    kind: str
    parameter: Parameter
    component: int = 0

    @property
    def axis(self) -> int:
        """For a velocity coordinate: the index of its axis (0 = x, 1 = y, 2 = z)."""
        p = self.parameter
        return AXES.index(p.component) if p.component else self.component


def coordinate_labels(mech: Mechanism, params=None) -> tuple[CoordinateLabel, ...]:
    """Scalar coordinates of ``params`` (default: the model's inputs); a twist raises."""
    out = []
    for p in (mech.inputs if params is None else params):
        labels = p.labels(mech.dim)
        if p.kind == "twist" or (p.kind == "velocity" and p.component is None):
            if p.kind == "twist":
                raise SymkinError(f"{labels[0]}: a twist cannot drive a path; use velocity components and a rotation")
            out += [CoordinateLabel(lab, "length", p, k) for k, lab in enumerate(labels)]
            continue
        kind = "angle" if p.kind in ("rotation", "joint") else "length"
        out.append(CoordinateLabel(labels[0], kind, p))
    return tuple(out)


def driving_labels(mech: Mechanism, params) -> list[CoordinateLabel]:
    """The scalar coordinates of ``params`` that can drive a path (twists and the like are skipped)."""
    out = []
    for p in params:
        try:
            out += coordinate_labels(mech, [p])
        except SymkinError:
            pass
    return out


def accepted_labels(mech: Mechanism) -> dict[str, tuple[str, ...]]:
    """What :func:`parse_label` accepts for ``mech``, by kind (what an error message lists).

    Keys: ``"inputs"`` and ``"outputs"`` (the model's parameter labels that can drive a
    path), ``"rotation"`` (planar: ``rotation:<link>`` for every moving link), ``"slide"``
    (``slide:<slider>``) and ``"velocity"`` (``velocity:<node>.<axis>`` for every free node).
    The joint rates of a model written by its joints (``joint:R1``) are
    ``mech.joint_rates``.

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> accepted = accepted_labels(get("fourbar_appendix"))
    >>> accepted["inputs"], accepted["outputs"], accepted["rotation"]
    (('rotation:crank',), ('rotation:rocker',), ('crank', 'coupler', 'rocker'))
    """
    inputs = tuple(c.label for c in coordinate_labels(mech))
    taken = set(inputs)
    outputs = tuple(c.label for c in driving_labels(mech, mech.outputs) if c.label not in taken)
    return {"inputs": inputs, "outputs": outputs,
            "rotation": tuple(mech.moving_links) if mech.dim == 2 else (),
            "slide": tuple(s.id for s in mech.sliders),
            "velocity": tuple(mech.free_nodes)}


def parse_label(mech: Mechanism, label: str, what: str = "input",
                lead: str = "a path can be driven by") -> CoordinateLabel:
    """The coordinate named ``label`` (``rotation:crank``, ``slide:piston``, ``velocity:P.x`` ...).

    Matches the model's input labels first, then its output labels, then any rotation of a
    moving link (planar), slide of a slider or velocity component of a free node (see
    :func:`accepted_labels`); an unknown label raises a :class:`SymkinError` that lists
    what is accepted: "unknown ``what`` 'label'; ``lead`` ..." (a path's input by default).

    >>> from symkin.model.catalogue import get
    >>> c = parse_label(get("five_bar"), "velocity:P.y")
    >>> c.kind, c.parameter.target, c.axis
    ('length', ('P',), 1)
    """
    for c in coordinate_labels(mech) + tuple(driving_labels(mech, mech.outputs)):
        if c.label == label:
            return c
    kind, _, rest = label.partition(":")
    target, _, comp = rest.partition(".")
    if kind == "rotation" and target in mech.moving_links and mech.dim == 2:
        return coordinate_labels(mech, [Parameter("rotation", (target,))])[0]
    if kind == "slide":
        try:
            return coordinate_labels(mech, [Parameter("slide", (mech.slider(target).id,))])[0]
        except KeyError:
            pass
    if kind == "velocity" and target in mech.free_nodes and comp in AXES[: mech.dim]:
        return coordinate_labels(mech, [Parameter("velocity", (target,), component=comp)])[0]
    for name, p in mech.joint_rates:
        if name == label:
            return coordinate_labels(mech, [p])[0]
    raise SymkinError(f"unknown {what} {label!r}; {accepted_text(mech, lead)}")


def accepted_text(mech: Mechanism, lead: str = "a path can be driven by") -> str:
    """The accepted labels of ``mech`` in words (for error messages), after ``lead``."""
    a = accepted_labels(mech)
    parts = [f"the model's inputs ({', '.join(a['inputs']) or 'none'})"]
    if a["outputs"]:
        parts.append(f"its outputs ({', '.join(a['outputs'])})")
    if a["rotation"]:
        parts.append(f"rotation:<link> for a moving link ({', '.join(a['rotation'])})")
    if a["slide"]:
        parts.append(f"slide:<slider> ({', '.join(a['slide'])})")
    if a["velocity"]:
        parts.append(f"velocity:<node>.<{'|'.join(AXES[: mech.dim])}> for a free node ({', '.join(a['velocity'])})")
    joints = [name for name, _ in mech.joint_rates if name not in a["inputs"]]
    if joints:
        parts.append(f"the joints' rates ({', '.join(joints)})")
    return f"{lead} " + "; ".join(parts)


#: the components of a spatial link's orientation label ``rotation:<link>[x|y|z]``
ORIENTATION_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class OrientationLabel:
    """``rotation:<link>[x|y|z]``: a component of the rotation vector of a spatial link.

    The rotation vector ``θ·n`` (fixed frame, an angle) of the rotation that takes the link
    from its orientation in the model file to its current one, so that 0 is the model's
    orientation.  ``nodes`` are the three nodes whose frame defines the orientation: the
    link's first node, the node farthest from it, and the node farthest from their line.
    ``symkin map --hold`` and ``symkin conditions --hold`` both read these labels here.
    """

    label: str
    link: str
    axis: int
    nodes: tuple[str, str, str]
    kind: str = "angle"


def parse_orientation_label(mech: Mechanism, label: str) -> OrientationLabel | None:
    """``rotation:<link>[x|y|z]`` of a spatial moving link, else None (not such a label).

    Raises a :class:`SymkinError` when the label has this form but names no moving link,
    an unknown component, or a link whose nodes are collinear (no orientation about their
    line).

    >>> from symkin.model.catalogue import get
    >>> parse_orientation_label(get("five_bar"), "rotation:crank1") is None
    True
    """
    kind, _, rest = str(label).partition(":")
    if kind != "rotation" or mech.dim != 3 or not rest.endswith("]") or "[" not in rest:
        return None
    link, _, comp = rest[:-1].partition("[")
    if link not in mech.moving_links:
        raise SymkinError(f"{label!r}: {link!r} is not a moving link of {mech.name}")
    if comp not in ORIENTATION_AXES:
        raise SymkinError(f"{label!r}: the component must be one of x, y, z (rotation:{link}[x])")
    xyz = dict(mech.nodes)
    ns = list(mech.link_nodes(link))

    def sub(a, b):
        return [p - q for p, q in zip(xyz[a], xyz[b])]

    def norm2(v):
        return sum(c * c for c in v)

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    n0 = ns[0]
    n1 = max(ns, key=lambda n: norm2(sub(n, n0)))
    e = sub(n1, n0)
    off = [norm2(cross(e, sub(n, n0))) ** 0.5 for n in ns]
    n2 = ns[max(range(len(ns)), key=lambda k: off[k])]
    if max(off) <= DEFAULT.geometry * norm2(e):
        raise SymkinError(f"{label!r}: the nodes of link {link!r} are collinear; its orientation about "
                          "their line is not defined")
    return OrientationLabel(str(label), link, ORIENTATION_AXES.index(comp), (n0, n1, n2))


def parse_hold(text: str) -> tuple[str, float | None]:
    """``"LABEL[=VALUE]"`` → ``(label, value or None)`` (the value in the user unit).

    >>> parse_hold("rotation:platform=30"), parse_hold("rotation:platform")
    (('rotation:platform', 30.0), ('rotation:platform', None))
    """
    label, eq, value = str(text).partition("=")
    label = label.strip()
    if not label:
        raise SymkinError(f"--hold {text!r}: no label (expected LABEL or LABEL=VALUE)")
    if not eq:
        return label, None
    try:
        return label, float(value)
    except ValueError:
        raise SymkinError(f"--hold {text!r}: {value!r} is not a number") from None


def parse_holds(hold) -> list[tuple[str, float | None]]:
    """``--hold`` items (``"LABEL[=VALUE]"`` strings or ``(label, value)`` pairs) → ``(label, value)`` pairs.

    The one reading of holds shared by ``symkin map`` and ``symkin conditions``.

    >>> parse_holds(["velocity:O.z", ("rotation:platform[x]", 5)])
    [('velocity:O.z', None), ('rotation:platform[x]', 5.0)]
    """
    return [parse_hold(h) if isinstance(h, str) else (str(h[0]), None if h[1] is None else float(h[1]))
            for h in hold]
