"""The code-generation notebook runs headless (issue 3, requirement 8)."""
from __future__ import annotations

from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOK = Path(__file__).resolve().parent.parent / "notebooks" / "codegen.ipynb"


@pytest.mark.slow
def test_codegen_notebook_executes(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path / "cache"))  # the kernel inherits it
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=180, kernel_name="python3",
                                     resources={"metadata": {"path": str(NOTEBOOK.parent)}})
    client.execute()
    text = "\n".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    assert "generated == in-process: True" in text
    assert "first 200 decisions identical to symkin.analyze: True" in text
    assert "DKP-output at x = [-1.  1.]" in text
    assert list((tmp_path / "cache").glob("*.so"))
