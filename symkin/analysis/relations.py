"""Canonical sparse form of a linear dependency among labelled rows (one definition).

Used for the relations among kinematic parameters (paper eq. 13, 16-17) and for the
self-stresses among constraint rows (:mod:`symkin.analysis.statics`): a basis of the
left null space is put in reduced row echelon form over the labels' order, so the
result depends on the subspace only — each relation has pivot coefficient 1 and exact
zeros where its coefficients vanish.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from symkin.numeric.linalg import rref

__all__ = ["Relation", "canonical_relations"]


@dataclass(frozen=True)
class Relation:
    """A dependency ``Σ γ_k q_k = 0`` among labelled rows (eq. 13), physical units.

    ``coefficients`` pairs each label with its γ (the pivot's γ is 1); ``r`` is the number
    of labels involved.
    """

    coefficients: tuple[tuple[str, float], ...]

    @property
    def r(self) -> int:
        return len(self.coefficients)

    def as_dict(self) -> dict[str, float]:
        return dict(self.coefficients)

    def __str__(self) -> str:
        terms = []
        for k, (label, c) in enumerate(self.coefficients):
            sign = "-" if c < 0 else "+"
            mag = abs(c)
            coef = "" if math.isclose(mag, 1.0, rel_tol=1e-9) else f"{mag:.6g}·"
            terms.append(f"{'-' if sign == '-' else ''}{coef}{label}" if k == 0 else f" {sign} {coef}{label}")
        return "".join(terms) + " = 0"


def canonical_relations(basis: np.ndarray, labels, tol: float,
                        norms: np.ndarray | None = None) -> tuple[Relation, ...]:
    """Relations spanned by the columns of ``basis`` (k labels × d), in canonical form.

    Parameters
    ----------
    basis : ndarray (k, d)
        Any basis of the left null space of the k labelled (scaled) rows.
    labels : sequence of str
        One label per row.
    tol : float
        Entries ``<= max(tol, 1e-12) · max|entry|`` of the echelon form are exact zeros.
    norms : ndarray (k,), optional
        The norms the rows were divided by; coefficients are returned for the unscaled
        rows (``γ_k / norms_k``, rescaled so that the pivot stays 1).  Default: no scaling.

    Examples
    --------
    >>> import numpy as np
    >>> (rel,) = canonical_relations(np.array([[2.0], [-2.0], [0.0]]), ("a", "b", "c"), 1e-8)
    >>> rel.as_dict()
    {'a': 1.0, 'b': -1.0}
    """
    if basis.size == 0 or basis.shape[1] == 0:
        return ()
    scale = np.ones(basis.shape[0]) if norms is None else np.asarray(norms, dtype=float)
    r, pivots = rref(basis.T, max(tol, 1e-12))
    out = []
    for row, p in zip(r, pivots):
        phys = row / scale * scale[p]
        out.append(Relation(tuple((labels[k], float(phys[k])) for k in range(len(labels)) if row[k] != 0.0)))
    return tuple(out)
