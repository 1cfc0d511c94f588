"""The generated IM indicator (``im``, ``im_certified``) against independent references.

``im`` is ``λ_{F+1}`` of the reduced geometric matrix G (eq. 8, §IV-A).  References: the
NumPy core's reduced G (:func:`symkin.numeric.geometric_matrix.geometric_matrix`) with
``numpy.linalg.eigvalsh``, :func:`symkin.analyze`, and, near increased mobility where
double precision cannot resolve the eigenvalue, the exact eigenvalue (mpmath, 60 digits)
of the matrix ``J_e J_eᵀ`` of the kernel's own constraint rows.
"""
from __future__ import annotations

import math
import zlib

import casadi as ca
import mpmath as mp
import numpy as np
import pytest

import symkin
from symkin import Mechanism
from symkin.model.catalogue import get, names
from symkin.numeric import geometric_matrix as gm
from symkin.numeric import sx_linalg
from symkin import evaluators
from symkin.errors import NotConvergedError


def _rng(name: str) -> np.random.Generator:
    return np.random.default_rng(zlib.crc32(name.encode()))


@pytest.fixture(scope="module")
def evs():
    return {name: evaluators(get(name)) for name in names()}


def _configurations(ev, n: int, rng) -> np.ndarray:
    """Perturbations of 5 % and 20 % of the length scale, projected onto the closure."""
    if ev.mech.name.startswith("flattened"):  # a single configuration: stay close to it
        return ev.project(ev.q0 + 0.01 * rng.standard_normal((n, ev.nf)))
    scale = np.where(np.arange(n) % 2 == 0, 0.05, 0.2)[:, None] * ev.mech.length_scale
    q = ev.q0 + scale * rng.standard_normal((n, ev.nf))
    for _ in range(3):  # keep the perturbations that close (an overconstrained model may not)
        try:
            return ev.project(q, tol=1e-14)
        except NotConvergedError as exc:
            q = np.delete(q, exc.data["indices"], axis=0)
    return ev.project(q, tol=1e-14)


def _core_im(ev, q) -> float:
    g = gm.geometric_matrix(ev.mechanism_at(q), reduced=True)
    return float(np.linalg.eigvalsh(g)[ev.mobility])


#: catalogue mechanisms whose only closed configuration has increased mobility
_IM_ONLY = {"fourbar_flat", "collinear_truss"}
#: fewer certified values where eigenvalues cluster (refusing is the safe side: the batch then
#: takes the exact path): the Peaucellier rhombus, the redundant rows of the double parallelogram
_MIN_CERTIFIED = {"peaucellier": 0.9, "double_parallelogram": 0.85}


@pytest.mark.parametrize("name", names())
def test_im_equals_the_cores_eigenvalue_at_many_valid_configurations(name, evs):
    ev = evs[name]
    q = _configurations(ev, 300, _rng(name + "kernel"))
    ind = ev.map("indicators", q)
    im, ok = ind["im"].ravel(), ind["im_certified"].ravel()
    ref = np.array([_core_im(ev, x) for x in q])
    certified = ok == 1.0
    assert set(np.unique(ok)) <= {0.0, 1.0}
    np.testing.assert_allclose(im[certified], ref[certified], rtol=1e-12, atol=0)
    if name in _IM_ONLY:  # its only configuration has increased mobility: λ_{F+1} = 0
        assert not certified.any()
        assert np.all(np.abs(im) <= 1e-10 * ind["trace"].ravel())
    else:
        assert certified.mean() >= _MIN_CERTIFIED.get(name, 0.99), certified.mean()
    for k in range(0, 300, 30):  # and the classification's own indicator
        a = symkin.analyze(ev.mechanism_at(q[k]))
        if certified[k]:
            assert im[k] == pytest.approx(a.im_indicator, rel=1e-12)


def test_generic_3rrr_configurations_are_certified(evs):
    """The 3-RRR's two smallest eigenvalues are a few % apart (3-fold symmetry), often less."""
    ev = evs["rrr_3"]
    q = _configurations(ev, 2000, _rng("rrr_3 cert"))
    ind = ev.map("indicators", q)
    jf = ev.map("J", q)["J_free"]
    lam = np.linalg.eigvalsh(jf @ jf.transpose(0, 2, 1))
    gap = lam[:, 1] / lam[:, 0] - 1
    assert np.median(gap) < 0.05 and np.mean(gap < 1e-2) > 0.1  # the clusters are there
    ok = ind["im_certified"].ravel() == 1.0
    assert ok.mean() >= 0.999  # the rest goes to the batch's SVD path (1 of 2000 here)
    np.testing.assert_allclose(ind["im"].ravel()[ok], lam[ok, 0], rtol=1e-12)


def _reference_kernel(ev):
    """The previous kernel for r0 = 0 (:func:`sx_linalg.eigenvalue_above`) on the same rows."""
    cm = ev.model
    free = np.flatnonzero(cm.free).tolist()
    je = cm.J[:, free][list(ev.effective_rows), :]
    diag, off = sx_linalg.householder_tridiagonal(ca.mtimes(je, je.T))
    return ca.Function("previous", [cm.q], list(sx_linalg.eigenvalue_above(diag, off, 0)))


@pytest.mark.parametrize("name", ["rrr_3", "rssr", "five_bar", "fourbar_dead_centre"])
def test_both_kernels_agree_where_both_are_certified(name, evs):
    ev = evs[name]
    q = _configurations(ev, 200, _rng(name + "both"))
    new = ev.map("indicators", q)
    old = _reference_kernel(ev).map(q.shape[0])(q.T)
    old_im, old_ok = (np.array(v).ravel() for v in old)
    both = (old_ok == 1.0) & (new["im_certified"].ravel() == 1.0)
    assert both.mean() >= 0.99
    np.testing.assert_allclose(new["im"].ravel()[both], old_im[both], rtol=2e-12)


# ---------------------------------------------------------------------- near increased mobility
def parallelogram(angle: float) -> Mechanism:
    """Parallelogram four-bar (1, 4, 1, 4); all joints collinear (IM, change point) at angle 0."""
    b = [math.cos(angle), math.sin(angle)]
    return Mechanism.from_dict({
        "name": "parallelogram four-bar", "dim": 2, "fixed": ["A", "D"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"rotation": "rocker"}],
        "nodes": {"A": [0.0, 0.0], "B": b, "C": [4.0 + b[0], b[1]], "D": [4.0, 0.0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]}})


def radial_3rrr(angle: float) -> Mechanism:
    """3-RRR whose straight legs meet at the centre at ``angle = 0`` (a self-stress: IM).

    Base joints on a circle of radius 4, platform circumradius 1, crank and distal link
    1.5 each; the platform is turned by ``angle`` and the elbows close the legs.
    """
    nodes, links = {}, {}
    for k in range(3):
        a = 2 * math.pi * k / 3 + math.pi / 2
        base = np.array([4 * math.cos(a), 4 * math.sin(a)])
        pf = np.array([math.cos(a + angle), math.sin(a + angle)])
        d = pf - base
        dist = np.linalg.norm(d)
        along = dist / 2  # equal link lengths
        h = math.sqrt(max(1.5 ** 2 - along ** 2, 0.0))
        e = d / dist
        elbow = base + along * e + h * np.array([-e[1], e[0]])
        nodes[f"A{k}"], nodes[f"B{k}"], nodes[f"C{k}"] = base.tolist(), elbow.tolist(), pf.tolist()
        links[f"crank{k}"] = [f"A{k}", f"B{k}"]
        links[f"distal{k}"] = [f"B{k}", f"C{k}"]
    links["platform"] = ["C0", "C1", "C2"]
    return Mechanism.from_dict({
        "name": "radial 3-RRR", "dim": 2, "fixed": ["A0", "A1", "A2"],
        "inputs": [{"rotation": f"crank{k}"} for k in range(3)], "outputs": [{"twist": "platform"}],
        "platform": "platform", "platform_dof": 3, "nodes": nodes, "links": links})


def _exact_smallest(ev, q) -> float:
    """λ_min of J_e J_eᵀ for the kernel's own (double) rows, in 60-digit arithmetic."""
    j = ev("J", q)["J_free"][list(ev.effective_rows)]
    with mp.workdps(60):
        jm = mp.matrix(j.tolist())
        return float(min(mp.eigsy(jm * jm.T, eigvals_only=True)))


@pytest.mark.parametrize("factory", [parallelogram, radial_3rrr], ids=["parallelogram", "radial_3rrr"])
def test_certificate_does_not_lie_near_increased_mobility(factory):
    ev = evaluators(factory(0.3))
    assert ev.fast and len(ev.effective_rows) == ev.nf - ev.mobility  # the r0 = 0 kernel
    angles = [s * 10.0 ** -e for e in np.arange(1, 9, 0.5) for s in (1, -1)]
    seen = set()
    for angle in angles:
        q = ev.free_coordinates(factory(angle))  # closed by construction (to rounding)
        ind = ev("indicators", q)
        im, ok = ind["im"][0, 0], ind["im_certified"][0, 0]
        exact = _exact_smallest(ev, q)
        seen.add(ok)
        if ok == 1.0:
            assert abs(im - exact) <= 1e-12 * exact, (angle, im, exact)
    assert seen == {0.0, 1.0}  # the sweep reaches where double precision gives up
    # at the singular pose itself nothing is certified, and the batch finds IM by its SVD path
    q0 = ev.free_coordinates(factory(0.0))
    assert ev("indicators", q0)["im_certified"][0, 0] == 0.0
    res = ev.batch(q0)
    assert res.im[0] and res.path[0] == 2 and res.dof[0] == symkin.analyze(factory(0.0)).dof > ev.mobility
