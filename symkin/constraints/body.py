"""A rigid body of three or more nodes: its pairs are :class:`~symkin.constraints.bar.Bar`\\ s.

What a body adds to its bars are, when its nodes do not span the space (collinear nodes;
coplanar nodes in 3D), the rows that keep it rigid out of its affine hull:
``n·(ẋ_m − Σ c_k ẋ_k) = 0`` for each normal ``n`` of the hull and each node ``m`` off a
frame of the body's nodes, ``c`` the affine coordinates of ``m`` on the frame.  These
stay written per backend (``_body_extra_rows`` of the numeric core, ``body_extra`` of the
CasADi model, ``_body_extra_rows`` of the symbolic rows), and the registry yields a
:class:`Body` marker at their place in the row order, because they do not fit the
one-expression pattern: the hull's dimension, the frame and the normals are decided by
an SVD and a greedy search (:func:`symkin.numeric.linalg.affine_hull`, ``affine_frame``,
which live above this package) at *every* configuration by the numeric core, once at the
model's configuration by the others (with the core's signs), and the polynomial systems
express a body by frame equations (a distance and affine coordinates, not rows).  Moving
those decisions here would move the numeric linear algebra below the model's users; the
backends' agreement on bodies is kept by ``tests/numeric`` and ``tests/symbolic``.
"""
from __future__ import annotations

from symkin.constraints.base import Constraint

__all__ = ["Body"]


class Body(Constraint):
    """Marker: the out-of-hull rows of link ``link`` (node positions ``idx``) come here."""

    kind = "body"

    def __init__(self, link: str, names: tuple, idx: tuple):
        self.link, self.names, self.idx = link, names, idx
        self.owner = f"link {link} (rigidity out of its hull)"
        self.element = link
        self.where = f"links.{link}"
