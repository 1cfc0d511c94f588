"""Sphinx configuration of symkin's documentation site.

Build (from the repository's root, with ``pip install -e ".[docs]"``)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

The guide pages are the README's sections (``readme_pages.py`` splits them at every build), the
API reference is generated from the docstrings (autodoc + autosummary, NumPy-style sections by
napoleon), and the gallery's examples (``docs/gallery/``) are executed by sphinx-gallery.
"""
import importlib
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))       # import symkin from this tree, installed or not
sys.path.insert(0, str(DOCS))
os.environ.setdefault("MPLBACKEND", "agg")

import symkin  # noqa: E402
from readme_pages import write_model_examples, write_pages  # noqa: E402

(DOCS / "guide").mkdir(exist_ok=True)
GUIDE_PAGES = write_pages(ROOT / "README.md", DOCS / "guide",
                          extra={write_model_examples(ROOT, DOCS / "guide"): "model_files"})

project = "symkin"
author = "symkin developers"
copyright = "symkin developers"
release = version = symkin.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "guide/intro.md", "guide/toc.md", "gallery/README.rst", "auto_examples/*.ipynb",
                    "auto_examples/*.py", "auto_examples/*.zip", "**.codeobj.json"]
templates_path = ["_templates"]

# Markdown (the README's sections)
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 3

# API reference
autosummary_generate = True
autosummary_imported_members = False
#: the packages documented module by module: each object is described once, on the page of the module
#: that defines it (``:ignore-module-all:``), and a package's page lists what its ``__all__`` exports,
#: linked to there
PACKAGES = ("symkin.plots", "symkin.paths", "symkin.solutions", "symkin.workspace", "symkin.curves")


def _defined_at(package: str, name: str) -> str:
    obj = getattr(importlib.import_module(package), name)
    return f"{obj.__module__}.{obj.__qualname__}" if hasattr(obj, "__qualname__") else f"{package}.{name}"


def _shadowed_modules() -> list[str]:
    """Submodules hidden by a name of their package (``symkin.solutions.solve_all`` is a function there).

    autosummary would document the function under the module's name; these modules get a page of their
    own, written here (``api/shadowed/``, generated), linked from their package's page.
    """
    import pkgutil
    import types

    found = []
    for package in PACKAGES:
        module = importlib.import_module(package)
        for info in pkgutil.iter_modules(module.__path__):
            if info.name.startswith("_"):
                continue
            importlib.import_module(f"{package}.{info.name}")      # sets the package's attribute, unless shadowed
            if not isinstance(getattr(module, info.name, None), types.ModuleType):
                found.append(f"{package}.{info.name}")
    folder = DOCS / "api" / "shadowed"
    folder.mkdir(exist_ok=True)
    for name in found:
        text = f"{name}\n{'=' * len(name)}\n\n.. automodule:: {name}\n   :ignore-module-all:\n"
        path = folder / f"{name}.rst"
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
    return found


SHADOWED = _shadowed_modules()
autosummary_context = {"shadowed": SHADOWED, "exported": {
    package.split(".")[1]: [_defined_at(package, name) for name in getattr(importlib.import_module(package), "__all__", ())]
    for package in PACKAGES}}
autodoc_default_options = {"members": True, "show-inheritance": True, "member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_typehints_format = "short"
autodoc_preserve_defaults = True
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

# Gallery: every example runs at every build (a few seconds each)
sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "run_stale_examples": True,     # run even when the example did not change: symkin may have
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "show_memory": False,
}

#: objects whose docstrings are shown verbatim (a literal block) until their reST markup is fixed: they
#: live in modules being edited elsewhere, so the site tolerates them instead of editing them
#: (each one's problem in a comment; fix the docstring, then remove it from this set)
VERBATIM_DOCSTRINGS = {
    "symkin.workspace.system",                    # a title underline too short; an aligned table read as
                                                  # a definition list
    "symkin.workspace.loci.refine",               # |A_i B_i|, |P − A_i| read as substitutions: write ``|P − A_i|``
    "symkin.workspace.quadtree.subdivide_many",   # a paragraph after "Parameters" without a section of its own
    "symkin.curves.tracer.trace_curve",           # the same: a paragraph after "Parameters"
    "symkin.curves.locate.SIGN_CHANGE_XTOL",      # |y| read as a substitution: write ``|y|``
}


def _verbatim_docstring(app, what, name, obj, options, lines):
    """Show the docstring of a :data:`VERBATIM_DOCSTRINGS` object as a literal block (before napoleon)."""
    if name in VERBATIM_DOCSTRINGS and lines:
        lines[:] = ["::", ""] + ["    " + line for line in lines] + [""]


def setup(app):
    app.connect("autodoc-process-docstring", _verbatim_docstring, priority=400)


html_theme = "furo"
html_title = f"symkin {release}"
html_static_path = []
