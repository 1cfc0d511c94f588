"""The helical pair H: a cylindrical pair whose slide is tied to its rotation, ``s = p·θ``.

A joint ``H1`` of pitch ``p`` (advance per radian, model units) between a guide and a
runner compiles (:mod:`symkin.model.joints`) to a cylindrical pair C — the runner's nodes
``H1`` and ``H1.end`` on the guide's axis line (sliders) — plus an arm node ``H1.arm`` of
the runner off the axis and, for a moving guide, an arm node ``H1.guide`` of the guide;
this constraint adds the one row the paper's node sharing cannot express.

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

from symkin.constraints.algebra import FLOATS, cross, dot, sub
from symkin.constraints.base import Constraint, Equation, Row

__all__ = ["Helical"]


def _reference(direction) -> tuple:
    """A fixed vector normal to a fixed axis (from the coordinate axis least aligned with it)."""
    k = min(range(3), key=lambda i: abs(direction[i]))
    a = tuple(1.0 if i == k else 0.0 for i in range(3))
    return cross(tuple(map(float, direction)), a)


class Helical(Constraint):
    """The screw row of helical pair ``h`` (a :class:`~symkin.model.mechanism.Helical`).

    ``index`` maps node names to positions.
    """

    kind = "helical"
    polynomial = False

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
