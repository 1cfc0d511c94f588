"""The factors :func:`symkin.motion_space` keeps: J_r, its rank, U (left null space) and V."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import symkin
from symkin.model import catalogue
from symkin.numeric.geometric_matrix import constraint_rows, free_mask

EXAMPLES = Path(__file__).resolve().parents[2] / "papers_examples"
MODELS = [catalogue.get(n) for n in catalogue.names()] + \
         [symkin.read_model(p) for p in sorted(EXAMPLES.glob("*.toml"))]


@pytest.mark.parametrize("mech", MODELS, ids=[m.name for m in MODELS])
def test_factors_of_the_reduced_constraint_matrix(mech):
    ms = symkin.motion_space(mech)
    j = constraint_rows(mech).matrix[:, free_mask(mech)]
    np.testing.assert_array_equal(ms.J, j)
    m, n = j.shape
    assert ms.U.shape == (m, m) and ms.V.shape == (free_mask(mech).size, n - ms.rank)
    np.testing.assert_allclose(ms.U.T @ ms.U, np.eye(m), atol=1e-12)
    # J_r V = 0 on the free rows, yᵀ J_r = 0 for the trailing columns of U (self-stresses)
    scale = np.abs(j).max()
    assert np.abs(j @ ms.V[free_mask(mech)]).max(initial=0.0) <= 1e-10 * scale
    assert np.abs(ms.U[:, ms.rank:].T @ j).max(initial=0.0) <= 1e-10 * scale
    # rank + nullity = number of free coordinates; m - rank independent self-stresses
    assert ms.rank + ms.dof == n
    assert np.linalg.matrix_rank(j, tol=ms.threshold) == ms.rank


def test_redundant_rows_give_self_stresses():
    """Fig. 12's 3-RSR has more constraint rows than its rank: U keeps their stresses."""
    ms = symkin.motion_space(symkin.read_model(EXAMPLES / "fig12_3rsr_b.toml"))
    assert ms.J.shape[0] > ms.rank
    assert ms.U[:, ms.rank:].shape[1] == ms.J.shape[0] - ms.rank


def test_motion_space_built_fast_has_every_field():
    """``motion_space`` fills the frozen dataclass without its ``__init__``: every field is set."""
    import dataclasses

    from symkin.analysis.motion_space import MotionSpace

    ms = symkin.motion_space(catalogue.get("rrr_3"))
    assert {f.name for f in dataclasses.fields(MotionSpace)} <= set(ms.__dict__)
    with pytest.raises(dataclasses.FrozenInstanceError):
        ms.dof = 0
