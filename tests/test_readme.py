"""The README's Python examples run, and print what their comments say."""
from __future__ import annotations

import contextlib
import io
import os
import re

from tests.conftest import ROOT

BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)


def test_readme_has_python_examples():
    assert BLOCKS


def test_readme_python_examples_run_and_print_what_they_say():
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        for block in BLOCKS:
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(block, "README.md", "exec"), {})
            printed = out.getvalue().splitlines()
            expected = [m.group(1).strip() for line in block.splitlines()
                        if line.lstrip().startswith("print(") and (m := re.search(r"#\s*(.+)$", line))
                        and "report" not in m.group(1)]
            for text in expected:
                assert any(text in line for line in printed), (text, printed)
    finally:
        os.chdir(cwd)
