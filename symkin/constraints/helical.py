"""The helical pair H: a cylindrical pair whose slide is tied to its rotation, ``s = p·θ``.

This module is the whole of H (issue 16: a pair kind is one module, registered in
:mod:`symkin.model.pairs` and found by :mod:`symkin.constraints`):

* the joint kind ``H`` (spatial; ``axis`` and ``pitch``, the advance per radian in model
  length units, negative for a left-handed screw; its rate ``joint:H1`` is the relative
  rotation) and its compile step :func:`compile_helical`;
* the record :class:`HelicalPair` (the model dictionary's ``helicals`` tables: parse,
  ``to_dict``, ``moved``);
* the constraint :class:`Helical`, its row and position equation in every algebra.

A joint ``H1`` of pitch ``p`` between a guide and a runner compiles to a cylindrical pair
C — the runner's nodes ``H1`` and ``H1.end`` on the guide's axis line (sliders) — plus an
arm node ``H1.arm`` of the runner off the axis and, for a moving guide, an arm node
``H1.guide`` of the guide, and a :class:`HelicalPair` record; its constraint adds the one
row the paper's node sharing cannot express.

Row (dimensionless)::

    e·w0 − p·[ (e × r)·(ẋ_arm − ẋ_H1)/|e × r|² − (e × g)·(ẋ_guide − ẋ_base)/|e × g|² ] = 0

with ``e`` the unit axis (``E = x_line − x_base`` of the guide, or the fixed axis),
``w0 = ẋ_H1 − (1−t) ẋ_base − t ẋ_line`` the velocity of the runner's axis node relative to
the guide's rigid (affine along the axis) velocity field, ``r = x_arm − x_H1`` and ``g =
x_guide − x_base`` the arms of runner and guide.  ``(e × r)·(ẋ_arm − ẋ_H1)/|e × r|²`` is the
runner's angular velocity about ``e`` (exactly, for any rigid motion, while ``r ⊥ e``), so
the bracket is the relative rotation rate ``θ̇`` and the row is ``ṡ − p θ̇``; ``p/|e × r|``
is dimensionless, so the row does not depend on the unit of length.  With a ground guide
the guide's terms vanish.  It is written over the common scale ``l·l²·|E × r|²·|E × g|²``
with polynomial blocks (``l`` the guide's pair length, a symbol in the symbolic rows).

Position equation (not polynomial: ``θ`` is an angle): with ``s = e·(x_H1 − x_base)`` the
slide, ``θ = atan2(l E·(g × r), (E × g)·(E × r))`` the angle from the guide's arm to the
runner's, ``s₀, θ₀`` their values at the model's configuration and ``Δ = (s − s₀)/p −
(θ − θ₀)``, the residual is ``p·atan2(sin Δ, cos Δ)``: ``Δ`` wrapped to ``(−π, π]``, so that
the node positions (which know ``θ`` only modulo 2π) close on one thread of the helix,
every turn of it, and the gradient on the helix is the row.  It is smooth except half a
lead away from the helix (``Δ = π``), which a path corrector started on the helix does
not reach.  ``p = 0``: the residual is ``s − s₀`` (a revolute pair).  A path of more than
a full turn goes on turn after turn: the tracer ends a path as closed only where it comes
back to its start itself, not one lead ``2π|p|`` from it (:mod:`symkin.curves.tracer`;
tests/paths/test_helical_path.py).  The polynomial
backends (``modes``, ``singularities``, the exact and the locus eliminations) refuse a
model with an H: :func:`symkin.constraints.polynomial_constraints`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from symkin.constraints.algebra import FLOATS, cross, dot, sub
from symkin.constraints.base import Constraint, Equation, Row
from symkin.model.joints import GROUND, offset, unit_normal
from symkin.model.pairs import ExtraConstraint, JointKey, JointKind, register_extra, register_joint

__all__ = ["Helical", "HelicalPair", "compile_helical"]


@register_extra
@dataclass(frozen=True)
class HelicalPair(ExtraConstraint):
    """The screw constraint of a helical pair H (a record of the model dictionary's ``helicals``).

    The runner's node ``node`` on the axis and its arm node ``arm`` off the axis turn and
    slide together: slide = ``pitch`` × relative rotation (``pitch`` in model units per
    radian).  The guide is a link, with the nodes ``line = (base, tip)`` on the axis and
    the arm node ``guide_arm``, or ground, with the fixed axis ``point`` + ``direction``.
    The cylindrical pair under it is made of sliders; :class:`Helical` states the row.
    """

    key = "helicals"
    keys = ("id", "node", "arm", "pitch", "line", "link", "guide_arm", "point", "direction")

    id: str
    node: str
    arm: str
    pitch: float
    line: tuple[str, str] | None = None
    link: str | None = None
    guide_arm: str | None = None
    point: tuple[float, ...] | None = None
    direction: tuple[float, ...] | None = None

    @classmethod
    def parse(cls, item, where, ctx) -> "HelicalPair | None":
        if ctx.dim != 3:
            ctx.problem(where, "a helical pair is spatial (dim = 3)")
            return None
        names = [item.get("node"), item.get("arm")] + list(item.get("line") or []) + \
            ([item["guide_arm"]] if "guide_arm" in item else [])
        bad = [n for n in names if not isinstance(n, str) or n not in ctx.nodes]
        pitch = item.get("pitch")
        if bad or not isinstance(item.get("id"), str) or not ctx.number(pitch):
            ctx.problem(where, f"needs id, pitch (a number) and nodes of the model (unknown: {ctx.short(bad)})")
            return None
        moving = "line" in item
        if moving and (item.get("link") not in ctx.links or "guide_arm" not in item or len(item["line"]) != 2):
            ctx.problem(where, "a moving guide needs line (two nodes), link and guide_arm")
            return None
        point = None if moving else ctx.vector(item.get("point"), where, "point")
        direction = None if moving else ctx.direction(item.get("direction"), where, "direction")
        if not moving and (point is None or direction is None):
            return None
        return cls(id=item["id"], node=item["node"], arm=item["arm"], pitch=float(pitch),
                   line=tuple(item["line"]) if moving else None, link=item.get("link"),
                   guide_arm=item.get("guide_arm"), point=point, direction=direction)

    def to_dict(self) -> dict:
        out: dict = {"id": self.id, "node": self.node, "arm": self.arm, "pitch": self.pitch}
        for key in ("line", "link", "guide_arm", "point", "direction"):
            value = getattr(self, key)
            if value is not None:
                out[key] = list(value) if isinstance(value, tuple) else value
        return out

    def moved(self, turn, place, scale: float) -> "HelicalPair":
        """The pitch is a length; a fixed axis moves with the nodes."""
        return replace(self, pitch=scale * self.pitch,
                       point=place(self.point) if self.point is not None else None,
                       direction=turn(self.direction) if self.direction is not None else None)

    def constraint(self, index) -> "Helical":
        return Helical(self, index)


def compile_helical(b, joint) -> None:
    """An H: the C of the builder's :meth:`line`, an arm node on the runner (and on a moving
    guide), and the :class:`HelicalPair` record (the screw row)."""
    b.line(joint)
    guide, runner = joint.links
    sign = 1.0
    if runner == GROUND:
        guide, runner, sign = runner, guide, -1.0
    u, at, jid = joint.axis, joint.at, joint.id
    n = unit_normal(u)
    node = b.shared(joint, [runner], at, jid)
    arm = b.shared(joint, [runner], offset(at, n, b.reach), f"{jid}.arm")
    if node is None or arm is None:
        return
    out = {"id": jid, "node": node, "arm": arm, "pitch": joint.pitch}
    if guide == GROUND:
        out.update(point=list(at), direction=[sign * c for c in u])
    else:
        base = b.shared(joint, [guide], at, f"{jid}.base")
        tip = b.shared(joint, [guide], offset(at, u, b.reach), f"{jid}.line")
        w = (u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2], u[0] * n[1] - u[1] * n[0])
        garm = b.shared(joint, [guide], offset(at, w, b.reach), f"{jid}.guide")
        if base is None or tip is None or garm is None:
            return
        out.update(line=[base, tip], link=guide, guide_arm=garm)
    b.extra(HelicalPair.key, out)


register_joint(JointKind(
    "H", (3,), compile_helical, axis=(3,), motions=("rotation",), title="a helical joint H", block=True,
    keys=(JointKey("pitch", needs="the advance per radian, in model length units",
                   must="a finite number (advance per radian, model length units)"),)))


def _reference(direction) -> tuple:
    """A fixed vector normal to a fixed axis (from the coordinate axis least aligned with it)."""
    k = min(range(3), key=lambda i: abs(direction[i]))
    a = tuple(1.0 if i == k else 0.0 for i in range(3))
    return cross(tuple(map(float, direction)), a)


class Helical(Constraint):
    """The screw row of helical pair ``h`` (a :class:`HelicalPair`).

    ``index`` maps node names to positions.
    """

    kind = "helical"
    polynomial = False
    why_not_polynomial = "ties a slide to an angle (s = p·θ)"

    def __init__(self, h, index: dict):
        self.h = h
        self.node, self.arm = index[h.node], index[h.arm]
        self.moving = h.line is not None
        if self.moving:
            self.a, self.c, self.g = index[h.line[0]], index[h.line[1]], index[h.guide_arm]
        self.owner = self.element = f"helical {h.id}"
        self.where = f"joints ({h.id})"

    def size(self, dim: int) -> int:
        return 1

    def _axis(self, alg, X):
        """``(E, l, base point, guide arm g)`` in the algebra."""
        h = self.h
        if self.moving:
            e = sub(X[self.c], X[self.a])
            return e, alg.pair_length(h.link, h.line[0], h.line[1], e), X[self.a], sub(X[self.g], X[self.a])
        e = alg.direction(h.direction, f"axis of helical {h.id}")
        point = alg.point(h.point, f"point of helical {h.id}")
        ref = alg.direction(_reference(h.direction), f"reference of helical {h.id}")
        return e, alg.sqrt(dot(e, e)), point, ref

    def rows(self, alg, X, X0) -> list[Row]:
        e, length, base, g = self._axis(alg, X)
        p = alg.const(self.h.pitch, f"pitch of {self.h.id}")
        q = length * length
        big_r = cross(e, sub(X[self.arm], X[self.node]))
        r2 = dot(big_r, big_r)
        tau = dot(sub(X[self.node], base), e)
        if not self.moving:
            k = p * length * length * q
            return [Row(((self.node, q * r2, e), (self.arm, -k, big_r), (self.node, k, big_r)), length * q * r2)]
        big_g = cross(e, g)
        g2 = dot(big_g, big_g)
        kr, kg = p * length * length * q * g2, p * length * length * q * r2
        terms = ((self.node, q * r2 * g2, e), (self.a, -(q - tau) * r2 * g2, e), (self.c, -tau * r2 * g2, e),
                 (self.arm, -kr, big_r), (self.node, kr, big_r), (self.g, kg, big_g), (self.a, -kg, big_g))
        return [Row(terms, length * q * r2 * g2)]

    def _slide_angle(self, alg, X):
        e, length, base, g = self._axis(alg, X)
        r = sub(X[self.arm], X[self.node])
        s = dot(sub(X[self.node], base), e) / length
        theta = alg.atan2(length * dot(e, cross(g, r)), dot(cross(e, g), cross(e, r)))
        return s, theta

    def equations(self, alg, X, X0) -> list[Equation]:
        s, theta = self._slide_angle(alg, X)
        s0, theta0 = self._slide_angle(FLOATS, X0)
        one = alg.const(1)
        if self.h.pitch == 0:
            return [Equation(s - alg.const(s0), one)]
        p = alg.const(self.h.pitch, f"pitch of {self.h.id}")
        delta = (s - alg.const(s0)) / p - (theta - alg.const(theta0))
        return [Equation(p * alg.atan2(alg.sin(delta), alg.cos(delta)), one)]
