"""Report files of ``symkin reproduce``: names a shell user can type, unique (issue 7 §8)."""
from __future__ import annotations

import json
import re
import textwrap

import pytest

from symkin.cli import main
from symkin.reproduce import file_slug, run_all
from tests.conftest import EXAMPLES

TYPABLE = re.compile(r"^[A-Za-z0-9._-]+$")
LABELS = ["path at λ = −90° (position c)", "§ IV-B: Fig. 11, position (a)", "a b", "a_b", "A B",
          "θ/ψ ∥ φ", "naïve — ünïcode", "🦾", "analysis"]


def _demo_examples(folder):
    folder.mkdir()
    (folder / "check_démo ex.py").write_text(textwrap.dedent(f"""
        import symkin
        from symkin.reproduce import Checklist

        def check():
            c = Checklist("démo (ex) §1")
            res = symkin.analyze(symkin.catalogue.get("fourbar_flat"))
            c.equal("flat four-bar DOF", res.dof, 2)
            for label in {LABELS!r}:
                c.record(label, res)
            return c
        """), encoding="utf-8")
    return folder


def test_slugs_spell_symbols_and_keep_only_typable_characters():
    assert file_slug("path at λ = −90° (position c)") == "path_at_lambda_-90deg_position_c"
    assert file_slug("Fig. 12, position (b)") == "Fig_12_position_b"
    assert file_slug("path event at (a), rank tolerance 1e-6") == "path_event_at_a_rank_tolerance_1e-6"
    assert file_slug("🦾") == "unnamed"
    assert all(TYPABLE.match(file_slug(label)) for label in LABELS)


def test_every_report_file_name_is_typable_and_unique(tmp_path):
    out = tmp_path / "rep"
    results = run_all(_demo_examples(tmp_path / "ex"), out)
    assert [r.ok for r in results] == [True]
    names = sorted(p.name for p in out.iterdir())
    assert all(TYPABLE.match(n) for n in names), names
    assert len({n.lower() for n in names}) == len(names) == len(LABELS) + 2     # + summary.md/json
    assert "demo_ex_sec1__path_at_lambda_-90deg_position_c.json" in names
    assert {"demo_ex_sec1__a_b.json", "demo_ex_sec1__a_b-2.json", "demo_ex_sec1__A_B-3.json"} <= set(names)
    # the titles inside the files stay as the checks wrote them
    md = (out / "summary.md").read_text(encoding="utf-8")
    assert all(f"### {label}" in md for label in LABELS)
    for name in names:
        if name.startswith("d") and name.endswith(".json"):
            assert json.loads((out / name).read_text())["dof"] == 2


@pytest.mark.slow
def test_the_paper_examples_report_names_are_typable(capsys, tmp_path, paper_checks_once):
    out = tmp_path / "rep"
    assert main(["reproduce", "--examples", str(EXAMPLES), "--out", str(out)]) == 0
    capsys.readouterr()
    names = [p.name for p in out.iterdir()]
    assert len(names) > 10 and all(TYPABLE.match(n) for n in names), names
    assert "3rsr_path__path_at_lambda_-90deg_position_c.json" in names
