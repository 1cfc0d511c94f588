"""Spatial mechanisms written by their joints give the path events of their node forms (issue 16).

The node and joint forms of ``tests/model/joint_forms.py`` driven by the same input over the same
range: the same stop, the same events in the same order, of the same kinds, at the same input
values (to 1e-6).  The curves use the generated corrector in-process (``in_process_corrector``):
a joint form has more nodes than its node form, and compiling its corrector is slow; the numbers
are the compiled ones (tests/numeric/test_artefact_cache.py).  The planar mechanisms' path events
are in tests/analysis/test_joint_forms.py.
"""
from __future__ import annotations

import numpy as np
import pytest

import symkin
from tests.analysis.test_joint_forms_spatial import _wrench_det
from tests.model import joint_forms as jf
from tests.workspace import truth as T


def _same_events(pn, pj) -> list:
    en, ej = pn.singular_events(), pj.singular_events()
    assert [e.kind for e in en] == [e.kind for e in ej]
    assert [e.input for e in en] == pytest.approx([e.input for e in ej], abs=1e-6)
    assert pn.stop_reason == pj.stop_reason
    return en


def test_rps_path_events(in_process_corrector):
    """Slide 1 driven from the regular pose (slides 2 and 3 held) round its loop: type-2 events where the
    locked legs' six wrench lines are dependent (the Plücker determinant of test_joint_forms_spatial)."""
    nodes = jf.rps_3_nodes(2.0, 0.2, -0.1)
    node, joint = (symkin.Mechanism.from_dict(f(nodes)) for f in (jf.rps_3_node, jf.rps_3))
    pn = symkin.trace(node, "slide:s1", 0.0, -2.5)
    pj = symkin.trace(joint, "joint:P1", 0.0, -2.5)
    _same_events(pn, pj)
    for path, at in ((pn, "C"), (pj, "S")):      # the platform joints: nodes C_k, and S_k by their joints
        type2 = [e for e in path.singular_events() if e.kind == "DKP-input"]
        assert len(type2) >= 4
        for e in type2:
            xyz = dict(zip(path.node_names, e.coordinates.reshape(-1, 3)))
            assert abs(_wrench_det({f"C{k}": xyz[f"{at}{k}"] for k in (1, 2, 3)})) < 1e-6


@pytest.mark.slow
def test_delta_path_events(in_process_corrector):
    """Arm 1 driven down from a regular pose (arms 2 and 3 held), 45°: the same events in both forms."""
    node = symkin.Mechanism.from_dict(T.Delta().model(np.array([0.1, -0.2, -2.2]), (1, 1, -1)))
    joint = symkin.Mechanism.from_dict(jf.delta(node.coordinates()))
    pn = symkin.trace(node, "rotation:arm1[A1-A1b]", 0.0, -45.0, unit="deg")
    pj = symkin.trace(joint, "joint:A1", 0.0, -45.0, unit="deg")
    assert _same_events(pn, pj)


def test_bennett_path_has_no_event_in_either_form(in_process_corrector):
    """The Bennett loop over a full turn of its input: no singular configuration, and no event candidate, in either form.

    The loop has 18 constraint rows for 11 independent constraints.  The signed tests keep a subset
    of the rows (``J_S`` of the DKP values, the rows of the bifurcation determinant), and a subset
    chosen at the start loses rank at inputs where the whole set does not (its least singular value
    falls to 0.002-0.05 of the whole J's there, asserted below); with that subset fixed, its sign
    flips there and the paths located 9 (node form) and 4 (joint form) candidates, each classified
    as no singularity.  The subset is chosen anew where it becomes ill-conditioned, its sign carried
    (``Tolerances.row_switch``): the recorded signed tests keep one sign over the whole turn, the
    DKP values away from zero (|value| >= 0.45 measured), and no candidate is located."""
    from symkin.analysis import indicators
    from symkin.model import catalogue
    from symkin.tolerances import DEFAULT

    node = catalogue.get("bennett")
    joint = symkin.Mechanism.from_dict(jf.bennett(node.coordinates()))
    pn = symkin.trace(node, None, 0.0, 360.0, unit="deg")
    pj = symkin.trace(joint, "joint:A", 0.0, 360.0, unit="deg")
    assert pn.stop_reason == pj.stop_reason == "reached"
    assert len(pn.singular_events()) == len(pj.singular_events()) == 0
    for path in (pn, pj):
        # no IM: the least singular value above the F generic zeros stays large
        assert min(pt.indicators["im_sigma"] for pt in path.points) > 0.2
        for key in ("DKP-input", "DKP-output", "bifurcation"):
            v = np.array([pt.indicators[key] for pt in path.points])
            assert np.all(np.sign(v) == np.sign(v[0])), key
        assert min(abs(pt.indicators["DKP-input"]) for pt in path.points) > 0.4
        # the row subset chosen at the start does lose rank along the path, where the whole J does not
        curve = path.curve
        start = curve.evaluators.basis_rows or indicators.basis_rows(curve.rows(curve.y0())[0], 1, DEFAULT)
        ratios = []
        for pt in path.points:
            j = curve.rows(curve.y_of(pt.coordinates.ravel()[curve.free]))[0]
            ratios.append(np.linalg.svd(j[list(start)], compute_uv=False)[-1]
                          / np.linalg.svd(j, compute_uv=False)[len(start) - 1])
        assert min(ratios) < 0.1 * DEFAULT.row_switch


def _leg_lines_det(xyz: dict, base: str, top: str) -> float:
    """det of the six unit Plücker lines of the legs (base_k → top_k): zero at a type-2 configuration."""
    rows = []
    for k in range(1, 7):
        a, c = np.asarray(xyz[f"{base}{k}"]), np.asarray(xyz[f"{top}{k}"])
        d = (c - a) / np.linalg.norm(c - a)
        rows.append(np.r_[d, np.cross(c, d)])
    return float(np.linalg.det(np.array(rows)))


@pytest.mark.slow
def test_gough_stewart_path_events(in_process_corrector):
    """Leg 1 driven (the other five held) round its loop: four type-2 events in both forms, each where
    the six leg lines are dependent (legs A_k → C_k of the node form, U_k → S_k of the joint form)."""
    node = symkin.read_model(jf.MODELS / "gough_stewart.toml")
    joint = symkin.Mechanism.from_dict(jf.ups_6(node.coordinates()))
    pn = symkin.trace(node, "slide:s1", 0.0, 4.0)
    pj = symkin.trace(joint, "joint:P1", 0.0, 4.0)
    en = _same_events(pn, pj)
    assert [str(e.kind) for e in en] == ["DKP-input"] * 4
    for path, base, top in ((pn, "A", "C"), (pj, "U", "S")):
        for e in path.singular_events():
            xyz = dict(zip(path.node_names, e.coordinates.reshape(-1, 3)))
            assert abs(_leg_lines_det(xyz, base, top)) < 1e-6
