"""Notebooks in notebooks/ execute from top to bottom without error (headless, nbclient)."""
from __future__ import annotations

import pytest

from tests.conftest import ROOT

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

# codegen.ipynb has its own test, which also checks what it prints (tests/test_codegen_notebook.py)
NOTEBOOKS = sorted(p for p in (ROOT / "notebooks").glob("*.ipynb") if p.stem != "codegen")
# notebooks that need an optional extra: the module they import, and the extra
NEEDS = {"global_singularities": ("bertini", "symkin[global] (Bertini 2)")}


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes(path, tmp_path, monkeypatch):
    if path.stem in NEEDS:
        module, extra = NEEDS[path.stem]
        pytest.importorskip(module, reason=f"{path.name} needs the optional extra {extra}")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("SYMKIN_CACHE", str(tmp_path / "cache"))
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors
