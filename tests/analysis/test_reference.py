"""``symkin.analyze`` against a straightforward reference computation, on every model we ship.

The reference shares no numerics with the core: the reduced geometric matrix and the
parameter rows come from the *symbolic* model (sympy rows, evaluated at the configuration),
the motion space from ``numpy.linalg.eigh`` of the dense G (eq. 8) and every rank from
``numpy.linalg.matrix_rank`` of the restricted parameter rows, with a reference tolerance
``1e-6`` of its own (``eigh`` resolves σ = sqrt(λ) only down to about sqrt(eps) σ_max).  Every model here is either regular or exactly singular (its
deciding singular values are far from both tolerances, which the test checks first), so
the two computations must agree on the DOF, every rank, the types, the relations, the
uncontrolled motions, λ_{F+1} and the singular values.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.model import catalogue

EXAMPLES = Path(__file__).resolve().parents[2] / "papers_examples"
MODELS = [("catalogue", n) for n in catalogue.names()] + \
         [("file", p.name) for p in sorted(EXAMPLES.glob("*.toml"))]
REF_TOL = 1e-6  # relative: σ/σ_max for G, and on unit-norm restricted rows


def load(kind: str, name: str) -> symkin.Mechanism:
    return catalogue.get(name) if kind == "catalogue" else symkin.read_model(EXAMPLES / name)


class Reference:
    """Motion space and parameter rows of ``mech`` from the symbolic model and ``eigh``."""

    def __init__(self, mech: symkin.Mechanism):
        sm = symkin.symbolic_model(mech, coordinates="nodes")
        self.free = list(sm.free)
        g = sm.evaluate(sm.reduced_G)
        lam, w = np.linalg.eigh(g)
        self.lam = np.clip(lam, 0.0, None)
        self.sigma = np.sqrt(self.lam)
        self.dof = int(np.count_nonzero(self.sigma <= REF_TOL * self.sigma[-1]))
        self.V = w[:, : self.dof]
        self.sm = sm

    def rows(self, params) -> np.ndarray:
        """Physical parameter rows over the free coordinates."""
        p, _ = self.sm.parameter_rows(params)
        if p.shape[0] == 0:
            return np.zeros((0, len(self.free)))
        return self.sm.evaluate(p)[:, self.free]

    def restricted(self, params) -> np.ndarray:
        p = self.rows(params)
        return (p / np.linalg.norm(p, axis=1)[:, None]) @ self.V

    @staticmethod
    def rank(m: np.ndarray) -> int:
        return int(np.linalg.matrix_rank(m, tol=REF_TOL)) if m.size else 0


def _null(m: np.ndarray) -> np.ndarray:
    """Right null space of ``m`` (reference tolerance), columns."""
    if m.shape[0] == 0:
        return np.eye(m.shape[1])
    _, s, vt = np.linalg.svd(m)
    return vt[int(np.count_nonzero(s > REF_TOL)):].T


def reference_types(mech, ref: Reference) -> tuple[dict, tuple[str, ...]]:
    f = mech.mobility_value
    m_in, m_out = ref.restricted(mech.inputs), ref.restricted(mech.outputs)
    k_in, k_out = m_in.shape[0], m_out.shape[0]
    r_in, r_out = ref.rank(m_in), ref.rank(m_out)
    types = ["IM"] if ref.dof > f else []
    if k_in and r_in < min(f, k_in):
        types.append("DKP-input")
    if k_out and r_out < min(f, k_out):
        types.append("DKP-output")
    dim, fixed = mech.dim, set(mech.fixed)
    speed = {n: np.linalg.norm(ref.V[dim * i: dim * i + dim])
             for i, n in enumerate(mech.free_nodes)}
    locked = tuple(name for name in mech.moving_links
                   if all(speed[n] <= REF_TOL for n in mech.link_nodes(name) if n not in fixed))
    if locked and f >= 1 and ref.dof > 0:  # LIM only where there is mobility to lose (issue 7 §1)
        types.append("LIM")
    numbers = {"dof": ref.dof, "input_rank": r_in if k_in else None,
               "output_rank": r_out if k_out else None, "locked_links": locked}
    if mech.platform is not None:
        m_pf = ref.restricted([symkin.Parameter("twist", (mech.platform,))])
        numbers["platform_dof"] = ref.rank(m_pf)
        generic = mech.platform_dof if mech.platform_dof is not None else min(f, m_pf.shape[0])
        if numbers["platform_dof"] > generic:
            types.append("constraint")
    return numbers, tuple(types)


@pytest.mark.slow
@pytest.mark.parametrize("kind,name", MODELS)
def test_analyze_matches_the_reference(kind, name):
    mech = load(kind, name)
    a = symkin.analyze(mech)
    ref = Reference(mech)
    s = ref.sigma / ref.sigma[-1]
    # the models are clean: no relative singular value between the two tolerances (eigh
    # resolves σ down to about sqrt(eps) σ_max only, hence 1e-7 for the reference's zeros)
    assert not np.any((s > 1e-7) & (s < 1e-5)), s
    numbers, types = reference_types(mech, ref)
    assert a.types == types
    assert {k: getattr(a, k) for k in numbers} == numbers

    f = mech.mobility_value
    assert a.im_indicator == pytest.approx(ref.lam[f], rel=1e-8, abs=1e-12 * ref.lam[-1])
    shown = np.array(a.singular_values)
    sig = ref.sigma[: shown.size]
    nonzero = sig > REF_TOL * ref.sigma[-1]
    np.testing.assert_allclose(shown[nonzero], sig[nonzero], rtol=1e-9)
    assert np.all(shown[~nonzero] <= a.threshold)

    # relations: k - rank of them, each annihilating the physical rows on the motion space
    for params, rels, rank in ((mech.inputs, a.input_relations, a.input_rank),
                               (mech.outputs, a.output_relations, a.output_rank)):
        p = ref.rows(params)
        assert len(rels) == (p.shape[0] - rank if p.shape[0] else 0)
        labels = [lab for prm in params for lab in prm.labels(mech.dim)]
        for rel in rels:
            gamma = np.array([rel.as_dict().get(lab, 0.0) for lab in labels])
            scale = np.abs(gamma)[:, None] * np.linalg.norm(p, axis=1)[:, None]
            assert np.linalg.norm(gamma @ p @ ref.V) <= 1e-8 * max(1.0, float(scale.sum()))

    # uncontrolled motions: a basis of the motions with the inputs locked
    m_in = ref.restricted(mech.inputs)
    expected = _null(m_in).shape[1] if m_in.shape[0] else 0
    assert len(a.uncontrolled_motions) == expected
    g = ref.sm.evaluate(ref.sm.reduced_G)
    p_in = ref.rows(mech.inputs)
    for motion in a.uncontrolled_motions:
        v = np.concatenate([vel for _, vel in motion.velocities])
        assert np.linalg.norm(g @ v) <= 1e-8 * np.linalg.norm(v) * ref.lam[-1]
        assert np.linalg.norm(p_in @ v) <= 1e-8 * np.linalg.norm(v) * np.abs(p_in).max()
