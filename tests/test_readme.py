"""Every example of the README runs verbatim, from a clean folder, and prints what it says.

The README's examples are found by reading it, so an example added there is run here:

* every fenced ``python`` block, executed as printed; a ``print(...)  # TEXT`` line must print
  a line containing TEXT;
* every ``symkin ...`` line of a fenced shell block (``$ symkin ...`` or a bare ``symkin ...``,
  ``\\`` continuations joined; in a ``bash`` block the ``symkin`` part of a ``&&`` chain), run by
  the shell as printed; the lines printed under a ``$`` command in the README are its output, in
  order (``...`` alone skips lines, a line ending in ``...`` is a prefix);
* every inline code span that is a concrete command (``symkin`` and a model, no placeholders).

Each runs in a fresh temporary folder holding what a clone ships and the examples name
(``examples/``, ``papers_examples/``, an empty ``docs/figures/``); a command whose model file has
no folder runs in the copy of ``examples/``, as the README says.  What an example prints when the
README shows no output is in :data:`STATED` (the "Workspace maps" section states it in prose).
"""
from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT

README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"```python\n(.*?)```", README, re.S)
#: commands that take longer than ~20 s: run with the slow tests
SLOW = ("symkin reproduce",)
#: commands that need the optional extra ``global`` (Bertini 2)
NEEDS_BERTINI = ("symkin modes", "symkin singularities")
#: what a command prints (and writes) where the README shows no output: substrings, in order
STATED = {
    "symkin map fivebar.toml": ["five-bar (2RR): map over velocity:P.x = -3.5..3.5 (201 points)",
                                "curves/points: DKP-input 0, DKP-output 5, IM 0"],
    "symkin map gough_stewart.toml": ["Gough-Stewart 6-6 platform: map over velocity:O.x",
                                      "curves/points: DKP-input 1"],
    "symkin analyze catalogue:five_bar": ["five-bar (2RR) (planar)", "The configuration is not singular."],
    "symkin reproduce": ["examples reproduced", "report written to reports/reproduce/summary.md"],
    "symkin conditions delta.json": ["DKP-input locus — eliminated", "DKP-output locus — eliminated",
                                     "IM locus — eliminated"],
}
#: exit codes other than 0 that the README states for a command (a locus it says is not derived)
EXIT: dict[str, int] = {}
#: files a command writes (relative to the folder it runs in)
WRITES = {"symkin reproduce": ["reports/reproduce/summary.md"],
          "symkin singularities papers_examples/fourbar_appendix.toml --plot circuits.png": ["circuits.png"]}


def _shell_examples() -> list[tuple[str, list[str]]]:
    """``(command, expected output lines)`` for every concrete ``symkin`` command of the README."""
    found = []
    for lang, body in re.findall(r"```(\w*)\n(.*?)```", README, re.S):
        if lang not in ("", "bash", "console", "shell"):
            continue
        lines = body.replace("\\\n", " ").splitlines()
        i = 0
        while i < len(lines):
            line = lines[i].strip()
            i += 1
            prompt = line.startswith("$ ")
            command = line[2:] if prompt else line
            if lang == "bash":
                command = next((part.strip() for part in command.split("&&")
                                if part.strip().startswith("symkin ")), "")
            if not command.startswith("symkin "):
                continue
            expected = []
            while prompt and i < len(lines) and not lines[i].startswith("$ "):
                expected.append(lines[i].rstrip())
                i += 1
            found.append((" ".join(command.split()), [e for e in expected if e]))
    for span in re.findall(r"`(symkin [^`]*)`", README):
        if re.search(r"\.(toml|json)\b|catalogue:", span) and not re.search(r"\[|\.\.\.|…|MODEL|FILE", span):
            found.append((span, []))
    return found


EXAMPLES = _shell_examples()


def _model(command: str) -> str | None:
    """The model a command names (its first argument after the subcommand), if any."""
    words = command.split()
    return words[2] if len(words) > 2 and not words[2].startswith("-") else None


def _stated(command: str) -> tuple[list[str], list[str]]:
    said = [text for prefix, texts in STATED.items() if command.startswith(prefix) for text in texts]
    wrote = [f for prefix, files in WRITES.items() if command.startswith(prefix) for f in files]
    return said, wrote


@pytest.fixture
def clone(tmp_path) -> Path:
    """A clean folder with what a clone ships that the examples name."""
    for folder in ("examples", "papers_examples"):
        shutil.copytree(ROOT / folder, tmp_path / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    (tmp_path / "docs" / "figures").mkdir(parents=True)
    return tmp_path


def _matches(expected: list[str], printed: list[str]) -> None:
    """Every expected line, in order, is a printed line (``...`` skips; ``X...`` is a prefix)."""
    at = 0
    for line in expected:
        if line.strip() == "...":
            continue
        prefix = line.endswith("...")
        text = line[:-3].rstrip() if prefix else line
        for j in range(at, len(printed)):
            if (printed[j].startswith(text) if prefix else printed[j].rstrip() == text):
                at = j + 1
                break
        else:
            raise AssertionError(f"the README says the command prints {line!r}; it printed:\n"
                                 + "\n".join(printed))


def test_readme_has_examples():
    assert BLOCKS
    assert len(EXAMPLES) >= 6, EXAMPLES
    assert all(said or expected for (cmd, expected), said in
               ((e, _stated(e[0])[0]) for e in EXAMPLES)), "every command says what it prints"


def test_readme_models_exist():
    """Every model file a README example names is shipped (or is a catalogue name)."""
    for command, _ in EXAMPLES:
        model = _model(command)
        if model is None or model.startswith("catalogue:"):
            continue
        where = ROOT / model if "/" in model else ROOT / "examples" / model
        assert where.is_file(), f"{command}: {model} is not shipped"


@pytest.mark.parametrize("command,expected", [
    pytest.param(c, e, id=c[:60], marks=[pytest.mark.slow] if c.startswith(SLOW) else [])
    for c, e in EXAMPLES])
def test_readme_command_runs_verbatim(command, expected, clone):
    if command.startswith(NEEDS_BERTINI) and importlib.util.find_spec("bertini") is None:
        pytest.skip("needs the optional extra symkin[global] (bertini)")
    model = _model(command) or ""
    cwd = clone / "examples" if model.endswith((".toml", ".json")) and "/" not in model else clone
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    run = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True,
                         timeout=600)
    printed = (run.stdout + run.stderr).splitlines()
    code = next((c for prefix, c in EXIT.items() if command.startswith(prefix)), 0)
    assert run.returncode == code, "\n".join(printed)
    said, wrote = _stated(command)
    _matches(expected, printed)
    text = "\n".join(printed)
    at = 0
    for piece in said:
        found = text.find(piece, at)
        assert found >= 0, (piece, text)
        at = found + len(piece)
    for name in wrote:
        assert (cwd / name).is_file(), f"{command} did not write {name}"


@pytest.mark.parametrize("block", BLOCKS, ids=[f"python-{i + 1}" for i in range(len(BLOCKS))])
def test_readme_python_example_runs_and_prints_what_it_says(block, clone):
    cwd = os.getcwd()
    os.chdir(clone)
    try:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(block, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    printed = out.getvalue().splitlines()
    expected = [m.group(1).strip() for line in block.splitlines()
                if line.lstrip().startswith("print(") and (m := re.search(r"#\s*(.+)$", line))]
    for text in expected:
        if text.startswith("the report"):  # a whole report: the text says what it is
            assert len(printed) > 3
            continue
        assert any(text in line for line in printed), (text, printed)
