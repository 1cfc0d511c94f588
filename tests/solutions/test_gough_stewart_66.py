"""The general 6-6 Gough–Stewart platform's forward kinematics (issue 17 §1): 40 complex solutions.

40 is the theory (Raghavan 1993; Wampler 1996: the forward kinematics of a general 6-6 platform
has 40 complex solutions).  The real ones are compared with PHCpack's blackbox solve of an
independent formulation (platform position ``p`` and rotation matrix ``R``: six orthogonality
equations and six legs ``|p + R b_k − a_k|² = L_k²``, written here from the model's nodes; its
solutions with ``det R = −1`` are the mirror problem's and are left out).
"""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from symkin import Mechanism
from symkin.model.model_file import read_model
from symkin.solutions import solve_all

HERE = Path(__file__).resolve().parent
MODEL = HERE.parents[1] / "examples" / "gough_stewart_66.toml"
#: the leg changes of the queries (model units of the m model)
QUERIES = ({f"slide:s{k}": 0.0 for k in range(1, 7)},
           {f"slide:s{k}": v for k, v in zip(range(1, 7), (0.08, -0.05, 0.03, 0.1, -0.07, 0.02))})


def scaled(m: Mechanism, factor: float) -> Mechanism:
    """The model with every node's coordinates × ``factor`` (m → mm)."""
    data = m.to_dict()
    data["nodes"] = {n: [c * factor for c in x] for n, x in data["nodes"].items()}
    return Mechanism.from_dict(data)


def leg_lengths(m: Mechanism, values: dict) -> list[float]:
    """|C_k − A_k| + s_k: the slide moves C_k along the line A_k → D_k."""
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    return [float(np.linalg.norm(x[f"C{k}"] - x[f"A{k}"])) + values[f"slide:s{k}"] for k in range(1, 7)]


def platform_joints(result) -> list[np.ndarray]:
    """C1..C6 of each real solution, one flat vector each."""
    return [np.concatenate([s.configuration[f"C{k}"] for k in range(1, 7)]) for s in result.solutions]


@pytest.mark.slow
@pytest.mark.parametrize("factor", [1.0, 1000.0], ids=["m", "mm"])
def test_forty_complex_solutions_by_parameter_homotopy(factor, tmp_path, monkeypatch):
    pytest.importorskip("casadi")
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path))
    m = scaled(read_model(MODEL), factor)
    counts = []
    for values in QUERIES:
        values = {k: v * factor for k, v in values.items()}
        r = solve_all(m, values, method="parameter")
        assert r.method == "parameter" and r.paths == 40
        assert r.failed == r.rejected == r.near_real == r.unverified == r.filtered == 0
        # every real solution closes the model and has the leg lengths asked for
        for c in platform_joints(r):
            got = [float(np.linalg.norm(c[3 * (k - 1):3 * k] - np.array(m.coordinates()[f"A{k}"])))
                   for k in range(1, 7)]
            assert got == pytest.approx(leg_lengths(m, values), rel=1e-9)
        counts.append((len(r.solutions), r.complex))
        assert len(r.solutions) + r.complex == 40  # distinct, verified on the original equations
    # the first query built the start solutions, the second was answered from the cache
    assert len(list((tmp_path / "parameter-homotopy").glob("*.npz"))) == 1
    assert counts[0][0] % 2 == 0 and counts[1][0] % 2 == 0  # complex solutions come in conjugate pairs


def phc_real_platforms(m: Mechanism, values: dict, tmp_path) -> tuple[list[np.ndarray], int]:
    """PHCpack's blackbox on (p, R): the real solutions with det R = +1 as C1..C6, and their total count."""
    x = {n: np.array(c) for n, c in m.coordinates().items()}
    o = x["O"]
    a = [x[f"A{k}"] for k in range(1, 7)]
    b = [x[f"C{k}"] - o for k in range(1, 7)]
    lengths = leg_lengths(m, values)
    p = ["p1", "p2", "p3"]
    r = [[f"r{i}{j}" for j in range(1, 4)] for i in range(1, 4)]
    eqs = []
    for i in range(3):  # columns orthonormal
        for j in range(i, 3):
            eqs.append("+".join(f"{r[t][i]}*{r[t][j]}" for t in range(3)) + ("-1;" if i == j else ";"))
    for k in range(6):
        # |p − a|² + 2 (p − a)·R b + |b|² − L² = 0   (|R b| = |b|)
        terms = [f"({p[t]}{-a[k][t]:+.16E})^2" for t in range(3)]
        for t in range(3):
            rb = "+".join(f"{b[k][j]:+.16E}*{r[t][j]}" for j in range(3))
            terms.append(f"2*({p[t]}{-a[k][t]:+.16E})*({rb})")
        eqs.append("+".join(terms) + f"{float(b[k] @ b[k]) - lengths[k] ** 2:+.16E};")
    (tmp_path / "in").write_text(f"{len(eqs)}\n" + "\n".join(eqs) + "\n")
    subprocess.run(["phc", "-b", "-t2", str(tmp_path / "in"), str(tmp_path / "out")], check=True,
                   capture_output=True, timeout=1800)
    text = (tmp_path / "out").read_text()
    real, seen = [], []
    for block in text.split("the solution for t :")[1:]:
        head, _, tail = block.partition("==")
        values_ = {n: complex(float(re_), float(im))
                   for n, re_, im in re.findall(r"^\s*(\w+)\s*:\s*(\S+)\s+(\S+)\s*$", head, re.M)}
        if not set(p) | {v for row in r for v in row} <= set(values_):
            continue
        rot = np.array([[values_[r[i][j]] for j in range(3)] for i in range(3)])
        if abs(np.linalg.det(rot) - 1) > 1e-6:
            continue  # the mirror problem's solution
        point = np.concatenate([np.array([values_[n] for n in p]) + rot @ bk for bk in b])
        if any(float(np.max(np.abs(point - q))) < 1e-6 for q in seen):
            continue  # the same solution listed again (phc's output repeats its solution list)
        seen.append(point)
        if "real" in tail.split("==")[0]:
            real.append(point.real)
    return real, len(seen)


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("phc") is None, reason="PHCpack (Debian package phcpack) is not installed")
def test_real_solutions_against_phcpack(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path / "cache"))
    m = read_model(MODEL)
    values = QUERIES[1]
    ours = platform_joints(solve_all(m, values, method="parameter"))
    theirs, total = phc_real_platforms(m, values, tmp_path)
    assert total == 40
    assert len(ours) == len(theirs)
    for c in theirs:
        assert min(float(np.max(np.abs(c - mine))) for mine in ours) < 1e-6
