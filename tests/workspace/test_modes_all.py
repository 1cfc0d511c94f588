"""``modes="all"``: every real solution at the map's reference point is a mode (issue 8 via issue 9 §1)."""
from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import symkin
from symkin.errors import SymkinError


def test_a_five_bar_has_its_four_working_modes():
    pytest.importorskip("bertini", reason="the global solver (symkin[global]) is not installed")
    mech = symkin.catalogue.get("five_bar")
    m = symkin.workspace_map(mech, x="velocity:P.x=-3:3", y="velocity:P.y=0.2:3.5", n=21, modes="all",
                             refine=False)
    d = m.to_dict()
    assert [md["seed"] for md in d["modes"]] == [f"solution {k}" for k in range(1, 5)]
    # elementary geometry: at P the elbows B_i lie on the two intersections of the circles
    # |B_i - A_i| = l1 and |B_i - P| = l2, so the four modes are the four elbow choices
    xyz = mech.coordinates()
    l1 = math.dist(xyz["A1"], xyz["B1"])
    l2 = math.dist(xyz["B1"], xyz["P"])
    ev = symkin.evaluators(mech)
    names = mech.node_names
    elbows = set()
    for mode in m.modes:
        conf = ev.coordinates(mode.seed_q)
        b1, b2, p = (conf[names.index(n)] for n in ("B1", "B2", "P"))
        for a, b in (("A1", b1), ("A2", b2)):
            assert math.dist(xyz[a], b) == pytest.approx(l1, rel=1e-9)
            assert math.dist(b, p) == pytest.approx(l2, rel=1e-9)
        assert np.allclose(p, xyz["P"], rtol=0, atol=1e-9 * l1)  # all at the reference point

        def side(a, b):
            u, w = np.subtract(p, xyz[a]), np.subtract(b, xyz[a])
            return int(np.sign(u[0] * w[1] - u[1] * w[0]))
        elbows.add((side("A1", b1), side("A2", b2)))
    assert elbows == {(1, 1), (1, -1), (-1, 1), (-1, -1)}
    assert all(md["assembled"] > 0.1 for md in d["modes"])


def test_without_the_solver_the_error_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "bertini", None)
    with pytest.raises(SymkinError, match=r"global"):
        symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3:3", y="velocity:P.y=0.2:3.5",
                             n=5, modes="all", refine=False)


def test_seeds_and_all_do_not_mix():
    with pytest.raises(SymkinError, match="no --seed"):
        symkin.workspace_map(symkin.catalogue.get("five_bar"), x="velocity:P.x=-3:3", y="velocity:P.y=0.2:3.5",
                             n=5, modes="all", seeds=[symkin.catalogue.get("five_bar")], refine=False)
