"""Symbolic geometric matrices against the paper's printed formulas and the numeric core.

* A3, A4, A5 (bar 2-3 at ψ, see papers_examples) and A6 are typed in from the paper and
  compared by *structural* equality with what :mod:`symkin.symbolic` builds.
* For every catalogue mechanism (and extra models with sliders and degenerate bodies) the
  symbolic G, reduced G, A6 form and parameter rows evaluate to the numeric core's.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from symkin import Mechanism, geometric_matrix, motion_space
from symkin.errors import SymkinError
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import constraint_rows, parameters_matrix
from symkin.symbolic import LAMBDA, symbolic_model

EXTRA_MODELS = {
    "collinear_coupler": {
        "name": "four-bar with a 3-node collinear coupler", "dim": 2, "fixed": ["A", "D"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"joint": ["crank", "coupler"]}],
        "nodes": {"A": [0, 0], "B": [0.2, 0.9], "M": [1.15, 1.1], "C": [2.1, 1.3], "D": [2, 0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "M", "C"], "rocker": ["D", "C"]}},
    "quad_coupler": {
        "name": "four-bar with a 4-node coupler", "dim": 2, "fixed": ["A", "D"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"twist": "coupler"}],
        "nodes": {"A": [0, 0], "B": [0.2, 0.9], "E": [1.0, 2.0], "F": [1.6, 1.9], "C": [2.1, 1.3],
                  "D": [2, 0]},
        "links": {"crank": ["A", "B"], "coupler": ["B", "E", "F", "C"], "rocker": ["D", "C"]}},
    "inverted_slider_crank": {
        "name": "inverted slider-crank (node on a moving line)", "dim": 2, "fixed": ["A", "D"],
        "inputs": [{"rotation": "crank"}], "outputs": [{"slide": "s"}],
        "nodes": {"A": [0, 0], "B": [0.6, 0.8], "D": [3, 0], "E": [1.8, 0.4]},
        "links": {"crank": ["A", "B"], "cyl": ["D", "E"]},
        "sliders": [{"id": "s", "node": "B", "line": ["D", "E"], "link": "cyl"}]},
    "spatial_plane_slider": {
        "name": "spatial: a node on a fixed plane", "dim": 3, "fixed": ["O"],
        "inputs": [{"velocity": "P", "component": "x"}, {"velocity": "P", "component": "y"}],
        "nodes": {"O": [0, 0, 0], "P": [1.0, 0.5, 0.25], "Q": [2.0, 1.5, 0.5]},
        "links": {"r1": ["O", "P"], "r2": ["P", "Q"]},
        "sliders": [{"id": "pl", "node": "Q", "point": [2.0, 1.5, 0.5], "normal": [0, 0.2, 1]}]},
    "spatial_line_slider": {
        "name": "spatial: a node on a fixed line", "dim": 3, "fixed": ["O"], "inputs": [{"slide": "ln"}],
        "nodes": {"O": [0, 0, 0], "P": [1.0, 0.5, 0.25], "Q": [2.0, 1.5, 0.5]},
        "links": {"r1": ["O", "P"], "r2": ["P", "Q"]},
        "sliders": [{"id": "ln", "node": "Q", "point": [2.0, 1.5, 0.5], "direction": [1, 0.3, 0.2]}]},
    "spatial_degenerate_bodies": {
        "name": "spatial coplanar plate and collinear rod", "dim": 3, "fixed": ["O", "O2"],
        "inputs": [{"rotation": "plate", "axis": [0, 0, 1]}], "outputs": [{"twist": "plate"}],
        "nodes": {"O": [0, 0, 0], "O2": [0, 0, 1], "P": [1, 0, 0.5], "Q": [1, 1, 0.5], "R": [0, 1, 0.5],
                  "S": [0.5, 0.5, 0.5], "T": [2, 0, 0], "U": [3, 0, 0], "V": [4, 0, 0]},
        "links": {"plate": ["P", "Q", "R", "S"], "leg1": ["O", "P"], "leg2": ["O2", "Q"], "leg3": ["O", "R"],
                  "rod": ["T", "U", "V"], "l4": ["Q", "T"], "l5": ["O", "V"]}},
    "spatial_moving_line": {
        "name": "spatial: a node on a moving line", "dim": 3, "fixed": ["O", "O2"], "inputs": [{"slide": "m"}],
        "nodes": {"O": [0, 0, 0], "O2": [0, 0, 1], "A": [1, 0, 0], "C": [1, 1, 1], "P": [1, 0.5, 0.5],
                  "X": [2, 0.5, 0]},
        "links": {"b1": ["O", "A"], "b2": ["O2", "C"], "b3": ["A", "C"], "b4": ["P", "X"], "b5": ["O", "X"]},
        "sliders": [{"id": "m", "node": "P", "line": ["A", "C"], "link": "b3"}]},
}


def all_models():
    out = [(name, catalogue.get(name)) for name in catalogue.names()]
    out += [(name, Mechanism.from_dict(data)) for name, data in EXTRA_MODELS.items()]
    return out


CASES = [(name, mech, mode, design) for name, mech in all_models()
         for mode in (("nodes", "angles") if mech.dim == 2 else ("nodes",)) for design in (False, True)]


# ---------------------------------------------------------------------- the paper's formulas
def c(t):
    return sp.cos(t)


def s(t):
    return sp.sin(t)


def a3_block(t):
    return sp.Matrix([[c(t) ** 2, c(t) * s(t)], [c(t) * s(t), s(t) ** 2]])


def paper_order(mech) -> list[int]:
    """Coordinates in the paper's numbering of Fig. 17: 1 = B, 2 = C, 3 = D, 4 = A."""
    idx = mech.node_index()
    return [2 * idx[n] + k for n in ("B", "C", "D", "A") for k in (0, 1)]


@pytest.fixture
def appendix():
    mech = catalogue.get("fourbar_appendix")
    sm = symbolic_model(mech, coordinates="angles")
    return mech, sm, sm.symbol("theta_coupler"), sm.symbol("theta_crank"), sm.symbol("theta_rocker")


def test_a3_element_matrix_of_each_bar(appendix):
    mech, sm, *_ = appendix
    idx = mech.node_index()
    elements = sm.element_matrices()
    assert set(elements) == {"crank", "coupler", "rocker"}
    for link, (i, j) in mech.links:
        t = sm.symbol(f"theta_{link}")
        cols = [2 * idx[i], 2 * idx[i] + 1, 2 * idx[j], 2 * idx[j] + 1]
        g = a3_block(t)
        a3 = sp.Matrix(sp.BlockMatrix([[g, -g], [-g, g]]))  # eq. (A3) as printed
        assert elements[link].extract(cols, cols) == a3, link  # structural equality
        # and nothing outside the element's own coordinates (eq. 2)
        others = [k for k in range(8) if k not in cols]
        assert elements[link].extract(others, list(range(8))).is_zero_matrix


def test_a5_assembled_matrix_structurally(appendix):
    mech, sm, theta, phi, psi = appendix
    t, f, p = a3_block(theta), a3_block(phi), a3_block(psi)
    z = sp.zeros(2, 2)
    a5 = sp.Matrix(sp.BlockMatrix([[t + f, -t, z, -f], [-t, t + p, -p, z], [z, -p, p, z], [-f, z, z, f]]))
    order = paper_order(mech)
    g = sm.G.extract(order, order)
    assert g == a5
    # as printed, with φ on bar 2-3, it is a different matrix (the paper's misprint)
    f2 = a3_block(phi)
    printed = sp.Matrix(sp.BlockMatrix([[t + f, -t, z, -f], [-t, t + f2, -f2, z], [z, -f2, f2, z], [-f, z, z, f]]))
    assert g != printed and sp.simplify(g - printed) != sp.zeros(8, 8)


def test_a6_boundary_form_structurally(appendix):
    mech, sm, theta, phi, psi = appendix
    t, f, p = a3_block(theta), a3_block(phi), a3_block(psi)
    z = sp.zeros(2, 2)
    eye = sp.eye(2)
    a6 = sp.Matrix(sp.BlockMatrix([[t + f, -t, z, z], [-t, t + p, z, z], [z, z, eye, z], [z, z, z, eye]]))
    order = paper_order(mech)
    assert sm.boundary_G.extract(order, order) == a6
    # the reduced matrix is A6's free block (B, C)
    assert sm.reduced_G == a6.extract(list(range(4)), list(range(4)))


def test_a4_spatial_rod_element():
    mech = catalogue.get("rssr")
    sm = symbolic_model(mech, coordinates="nodes", design_symbols=True)
    idx = mech.node_index()
    x1, y1, z1 = (sm.symbol(f"{a}_B") for a in "xyz")
    x2, y2, z2 = (sm.symbol(f"{a}_C") for a in "xyz")
    length = sm.symbol("l_coupler")
    dx, dy, dz = x2 - x1, y2 - y1, z2 - z1
    def m(u, v):  # −Δu Δv as printed: minus the product
        return -(u * v)

    a4 = sp.Matrix([
        [dx ** 2, dx * dy, dx * dz, -dx ** 2, m(dx, dy), m(dx, dz)],
        [dx * dy, dy ** 2, dy * dz, m(dx, dy), -dy ** 2, m(dy, dz)],
        [dx * dz, dy * dz, dz ** 2, m(dx, dz), m(dy, dz), -dz ** 2],
        [-dx ** 2, m(dx, dy), m(dx, dz), dx ** 2, dx * dy, dx * dz],
        [m(dx, dy), -dy ** 2, m(dy, dz), dx * dy, dy ** 2, dy * dz],
        [m(dx, dz), m(dy, dz), -dz ** 2, dx * dz, dy * dz, dz ** 2]]) / length ** 2
    cols = [3 * idx["B"] + k for k in range(3)] + [3 * idx["C"] + k for k in range(3)]
    assert sm.element_matrices()["coupler"].extract(cols, cols) == a4
    # without design symbols the length is the distance of the nodes
    sm0 = symbolic_model(mech, coordinates="nodes")
    g0 = sm0.element_matrices()["coupler"].extract(cols, cols)
    assert sp.simplify(g0 - a4.subs(length, sp.sqrt(dx ** 2 + dy ** 2 + dz ** 2))) == sp.zeros(6, 6)


def test_elements_sum_to_g_and_g_is_jtj():
    sm = symbolic_model(catalogue.get("rrr_3"), coordinates="angles")
    total = sum(sm.element_matrices().values(), sp.zeros(sm.ncoord, sm.ncoord))
    assert (total - sm.G).applyfunc(sp.expand) == sp.zeros(sm.ncoord, sm.ncoord)
    assert (sm.J.T * sm.J - sm.G).applyfunc(sp.expand) == sp.zeros(sm.ncoord, sm.ncoord)


# ---------------------------------------------------------------------- numeric agreement
@pytest.mark.parametrize("name,mech,mode,design", CASES,
                         ids=[f"{n}-{m}-{'design' if d else 'plain'}" for n, _, m, d in CASES])
def test_symbolic_g_equals_numeric_core(name, mech, mode, design):
    sm = symbolic_model(mech, coordinates=mode, design_symbols=design)
    assert set(sm.G.free_symbols) <= set(sm.symbols)
    g = sm.evaluate(sm.G)
    np.testing.assert_allclose(g, geometric_matrix(mech), rtol=0, atol=1e-12)
    np.testing.assert_allclose(sm.evaluate(sm.reduced_G), geometric_matrix(mech, reduced=True), rtol=0, atol=1e-12)
    np.testing.assert_allclose(sm.evaluate(sm.boundary_G), geometric_matrix(mech, boundary=True), rtol=0,
                               atol=1e-12)
    if mech.dim == 2:  # planar rows are the core's rows, one by one (up to the sign of a normal)
        j, jn = sm.evaluate(sm.J), constraint_rows(mech).matrix
        sign = np.where(np.sum(j * jn, axis=1) < 0, -1.0, 1.0)
        np.testing.assert_allclose(j * sign[:, None], jn, rtol=0, atol=1e-12)
        assert sm.row_owners == constraint_rows(mech).owners
        flipped = [o for o, sg in zip(sm.row_owners, sign) if sg < 0]
        assert all("rigidity out of its hull" in o for o in flipped)


@pytest.mark.parametrize("name,mech", all_models(), ids=[n for n, _ in all_models()])
def test_parameter_rows_equal_numeric_core_on_the_motion_space(name, mech):
    params = list(mech.inputs) + list(mech.outputs)
    if mech.platform is not None:
        params.append(symbolic_params_twist(mech))
    num, labels = parameters_matrix(mech, params)
    v = motion_space(mech).V
    for mode in (("nodes", "angles") if mech.dim == 2 else ("nodes",)):
        sm = symbolic_model(mech, coordinates=mode)
        rows, sym_labels = sm.parameter_rows(params)
        assert sym_labels == labels
        p = sm.evaluate(rows)
        np.testing.assert_allclose(p @ v, num @ v, rtol=0, atol=1e-12)
        if mech.dim == 2:
            np.testing.assert_allclose(p, num, rtol=0, atol=1e-12)


def symbolic_params_twist(mech):
    from symkin.model.mechanism import Parameter

    return Parameter("twist", (mech.platform,))


@pytest.mark.parametrize("name", ["fourbar_appendix", "rrr_3", "slider_crank", "rssr"])
def test_values_at_other_configurations(name):
    """G at random coordinates (lengths change: design symbols) equals the core's G there."""
    mech = catalogue.get(name)
    rng = np.random.default_rng(7)
    xyz = np.array([p for _, p in mech.nodes])
    for mode in (("nodes", "angles") if mech.dim == 2 else ("nodes",)):
        sm = symbolic_model(mech, coordinates=mode, design_symbols=True)
        for _ in range(2):
            moved = mech.with_coordinates(xyz + rng.normal(scale=0.3, size=xyz.shape))
            g = sm.evaluate(sm.G, sm.values_at(moved))
            np.testing.assert_allclose(g, geometric_matrix(moved), rtol=0, atol=1e-12)


def test_symbol_names_follow_their_owners():
    sm = symbolic_model(catalogue.get("rrr_3"), coordinates="angles", design_symbols=True)
    names = {s.name for s in sm.symbols}
    assert {"theta_crank1", "theta_distal2", "theta_platform", "l_crank1", "beta_platform_C1_C3"} <= names
    nodes = symbolic_model(catalogue.get("fourbar_appendix"), coordinates="nodes")
    assert [s.name for s in nodes.config_symbols] == ["x_A", "y_A", "x_B", "y_B", "x_C", "y_C", "x_D", "y_D"]
    assert all(s.is_real for s in nodes.symbols)
    assert sm.symbol("l_crank1").is_positive


def test_angle_coordinates_are_planar_only_and_options_are_checked():
    with pytest.raises(SymkinError, match="planar"):
        symbolic_model(catalogue.get("rssr"), coordinates="angles")
    with pytest.raises(SymkinError, match="coordinates"):
        symbolic_model(catalogue.get("fourbar_appendix"), coordinates="polar")


# ---------------------------------------------------------------------- characteristic polynomial
@pytest.mark.slow
@pytest.mark.parametrize("name,mode", [("fourbar_appendix", "angles"), ("fourbar_appendix", "nodes"),
                                       ("five_bar", "angles"), ("slider_crank", "nodes"), ("rrr_3", "angles")])
def test_characteristic_polynomial_matches_eigenvalues_and_im_condition(name, mode):
    mech = catalogue.get(name)
    sm = symbolic_model(mech, coordinates=mode, design_symbols=True)
    poly = sm.characteristic_polynomial()
    n = len(sm.free)
    assert poly.gens == (LAMBDA,) and poly.degree() == n
    f = mech.mobility_value
    r = n - f
    im = sm.im_condition()
    coeffs = sp.Matrix(poly.all_coeffs())
    rng = np.random.default_rng(3)
    xyz = np.array([p for _, p in mech.nodes])
    for k in range(3):
        values = sm.values_at(xyz + (rng.normal(scale=0.2, size=xyz.shape) if k else 0.0))
        c = sm.evaluate(coeffs, values).ravel()
        eig = np.linalg.eigvalsh(sm.evaluate(sm.reduced_G, values))
        np.testing.assert_allclose(c, np.poly(eig), rtol=1e-9, atol=1e-9)
        # the coefficient of λ^F is (−1)^r times the IM condition, nonzero here ...
        lowest = c[n - f]
        assert lowest == pytest.approx((-1) ** r * im.evaluate(values), rel=1e-9)
        assert abs(lowest) > 1e-3
        # ... and every lower coefficient vanishes identically (L ≥ F everywhere)
        assert np.all(np.abs(c[n - f + 1:]) < 1e-9)
