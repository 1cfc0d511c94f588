"""The documentation site (docs/, README "Documentation") builds with warnings as errors.

The build itself is slow (about 15 s on an idle 2-core machine, up to a minute on a loaded one:
it imports every documented module and executes the gallery) and needs the docs extra
(``pip install -e ".[docs]"``); it skips, saying so, without it.  The README split into guide
pages is checked without Sphinx.
"""
from __future__ import annotations

import importlib.util
import re
import subprocess
import sys

import pytest

from tests.conftest import ROOT

DOCS = ROOT / "docs"


def _readme_pages():
    spec = importlib.util.spec_from_file_location("readme_pages", DOCS / "readme_pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_readme_section_is_on_a_guide_page(tmp_path):
    """Each ``##`` section of the README appears, whole, on one guide page; cross-page anchors are rewritten."""
    pages = _readme_pages()
    stems = pages.write_pages(ROOT / "README.md", tmp_path)
    text = {stem: (tmp_path / f"{stem}.md").read_text(encoding="utf-8") for stem in stems}
    _, sections = pages.split_sections((ROOT / "README.md").read_text(encoding="utf-8"))
    assert sections
    for title, lines in sections:
        # a sentence of the section's body (links may be rewritten, so take a line without one)
        body = [line for line in lines[1:] if line.strip() and "](" not in line and not line.startswith("#")]
        assert any(title in page and all(line in page for line in body) for page in text.values()), title
    for page in text.values():
        for target in re.findall(r"\]\(#([^)]+)\)", page):
            # an in-page anchor must be a heading of the same page
            assert target in {pages.slug(line.lstrip("#")) for line in page.splitlines() if line.startswith("#")}


@pytest.mark.slow
def test_site_builds_with_warnings_as_errors(tmp_path):
    for module in ("sphinx", "myst_parser", "sphinx_gallery", "furo", "matplotlib"):
        pytest.importorskip(module, reason=f'the docs extra is not installed (pip install -e ".[docs]"): no {module}')
    out = tmp_path / "html"
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          "-d", str(tmp_path / "doctrees"), str(DOCS), str(out)],
                         cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-5000:]
    for page in ("index.html", "guide/getting_started.html", "guide/model_files.html", "guide/model_examples.html",
                 "api/index.html", "api/symkin.html", "api/generated/symkin.workspace.maps.html",
                 "auto_examples/index.html", "auto_examples/plot_path_fourbar.html"):
        assert (out / page).is_file(), page
    # the gallery ran: its figures are in the site
    assert list((out / "_images").glob("sphx_glr_plot_path_fourbar_*.png"))
    # every public name is in the API reference
    from sphinx.util.inventory import InventoryFile

    with open(out / "objects.inv", "rb") as f:
        inventory = InventoryFile.load(f, "", lambda base, uri: uri)
    data = inventory.data if hasattr(inventory, "data") else inventory
    documented = {name for kind, entries in data.items() if kind.startswith("py:") for name in entries}
    missing = sorted(" or ".join(alternatives) for alternatives in _public_names()
                     if not documented.intersection(alternatives) and not UNDOCUMENTED.intersection(alternatives))
    assert not missing, f"public names missing from the API reference (no docstring?): {missing}"


#: public functions without a docstring (so autodoc leaves them out): give them one, then remove them here
UNDOCUMENTED = {"symkin.workspace.tracing.segment_distance", "symkin.workspace.tracing.polyline_distance"}


def _public_names() -> list[tuple[str, ...]]:
    """Every public name the site documents, each as the names it may be documented under: the
    ``__all__`` of the top modules (the exported or the defining name), and the public functions and
    classes (and the modules) of the packages documented module by module."""
    import inspect
    import pkgutil

    def defined(module_name, name, obj):
        if inspect.isfunction(obj) or inspect.isclass(obj):
            return f"{obj.__module__}.{obj.__qualname__}"
        return f"{module_name}.{name}"

    names = []
    for module_name in ("symkin", "symkin.kinds", "symkin.tolerances", "symkin.catalogue"):
        module = importlib.import_module(module_name)
        names += [(f"{module_name}.{n}", defined(module_name, n, getattr(module, n))) for n in module.__all__
                  if not n.startswith("__")]
    for package in ("symkin.plots", "symkin.paths", "symkin.solutions", "symkin.workspace", "symkin.curves"):
        for info in pkgutil.iter_modules(importlib.import_module(package).__path__):
            module_name = f"{package}.{info.name}"
            module = importlib.import_module(module_name)
            names.append((module_name,))
            names += [(f"{module_name}.{n}",) for n, obj in vars(module).items()
                      if not n.startswith("_") and (inspect.isfunction(obj) or inspect.isclass(obj))
                      and obj.__module__ == module_name]
    return names
