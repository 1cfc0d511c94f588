"""Split the README's guide into the site's guide pages (run by ``conf.py`` at every build).

The README stays the one source of the guide: each of its ``##`` sections goes, verbatim, to the
page :data:`PAGES` names for it (a section not listed goes to the page "More topics", so a new
section is never lost); the text before the first ``##`` is the index's introduction.  Only
links are adapted: ``(#anchor)`` links to a section on another page, and paths relative to the
repository's root (``docs/figures/...``, ``notebooks/...``) are made relative to the page.  The
pages are written to ``docs/guide/`` (generated, not committed: ``.gitignore``).
"""
from __future__ import annotations

import re
from pathlib import Path

#: page stem → (page title or None to take the single section's own title, README section titles in order)
PAGES: dict[str, tuple[str | None, tuple[str, ...]]] = {
    "getting_started": ("Getting started", ("Set-up", "Documentation", "Ten lines of Python")),
    "command_line": (None, ("Command line",)),
    "model_files": (None, ("Model files",)),
    "computes": ("What symkin computes, and its tolerances",
                 ("What symkin computes", "Tolerances (scale invariant)")),
    "symbolic": (None, ("Symbolic conditions and generated evaluators",)),
    "paths": (None, ("Paths: finite displacements, exact singular configurations, branches",)),
    "maps": (None, ("Workspace maps",)),
    "global": ("Global solutions and every singularity",
               ("All solutions (`symkin modes`)", "Every singular configuration (`symkin singularities`)")),
    "layout": ("Layout and architecture", ("Layout",)),
}
MORE = "more"

_LINK = re.compile(r"(\]\()([^)\s]+)(\))")


def slug(title: str) -> str:
    """The GitHub (and MyST ``myst_heading_anchors``) anchor of a heading."""
    s = title.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def split_sections(text: str) -> tuple[str, list[tuple[str, list[str]]]]:
    """The introduction and the ``##`` sections ``(title, lines)`` of a Markdown text (fences respected)."""
    intro: list[str] = []
    sections: list[tuple[str, list[str]]] = []
    fence = None
    for line in text.splitlines():
        stripped = line.lstrip()
        if stripped.startswith(("```", "~~~")):
            marker = stripped[:3]
            fence = None if fence == marker else (fence or marker)
        if fence is None and line.startswith("## "):
            sections.append((line[3:].strip(), [line]))
        elif sections:
            sections[-1][1].append(line)
        elif not line.startswith("# "):
            intro.append(line)
    return "\n".join(intro).strip() + "\n", sections


def _shift_headings(lines: list[str], by: int) -> list[str]:
    """Headings outside fences raised by ``by`` levels (``##`` → ``#`` for ``by = 1``)."""
    out, fence = [], None
    for line in lines:
        stripped = line.lstrip()
        if stripped.startswith(("```", "~~~")):
            marker = stripped[:3]
            fence = None if fence == marker else (fence or marker)
        if fence is None and re.match(r"#{2,6} ", line):
            line = line[by:]
        out.append(line)
    return out


def _fix_links(text: str, anchors: dict[str, str], root: Path, depth: int) -> str:
    up = "../" * depth

    def fix(m: re.Match) -> str:
        target = m.group(2)
        if re.match(r"[a-z]+:", target):
            return m.group(0)
        if target.startswith("#"):
            page = anchors.get(target[1:])
            return f"{m.group(1)}{page}.md{target}{m.group(3)}" if page else m.group(0)
        if target.startswith("docs/_build/html/") and target.endswith(".html"):   # a page of this site
            return f"{m.group(1)}{up}{target[len('docs/_build/html/'):-len('.html')]}.md{m.group(3)}"
        if target.startswith("docs/"):
            return f"{m.group(1)}{up}{target[len('docs/'):]}{m.group(3)}"
        if (root / target.split("#")[0]).exists():
            return f"{m.group(1)}{up}../{target}{m.group(3)}"
        return m.group(0)

    return _LINK.sub(fix, text)


def write_pages(readme: Path, out: Path, extra: dict[str, str] | None = None) -> list[str]:
    """Write the guide pages of ``readme`` into ``out`` (and ``intro.md``, ``toc.md``); return the page stems in order.

    ``extra`` maps a page stem of ``out`` written by another function to the stem it follows in the table
    of contents.
    """
    intro, sections = split_sections(readme.read_text(encoding="utf-8"))
    by_title = {title: lines for title, lines in sections}
    pages = {stem: (title, [t for t in titles if t in by_title]) for stem, (title, titles) in PAGES.items()}
    listed = {t for _, titles in pages.values() for t in titles}
    more = [t for t, _ in sections if t not in listed]
    if more:
        pages[MORE] = ("More topics", more)
    anchors = {}
    for stem, (_, titles) in pages.items():
        for t in titles:
            anchors[slug(t)] = stem
            for line in by_title[t][1:]:
                if line.startswith("### "):
                    anchors[slug(line[4:])] = stem
    out.mkdir(parents=True, exist_ok=True)
    root = readme.parent
    stems = []
    for stem, (title, titles) in pages.items():
        if not titles:
            continue
        if title is None and len(titles) == 1:
            body = _shift_headings(by_title[titles[0]], 1)
        else:
            body = [f"# {title or titles[0]}", ""] + [line for t in titles for line in by_title[t] + [""]]
        text = "\n".join(body).rstrip() + "\n"
        text = _fix_links(text, {a: f"{p}" for a, p in anchors.items() if p != stem} |
                          {a: stem for a, p in anchors.items() if p == stem}, root, 1)
        _write_if_changed(out / f"{stem}.md", text)
        stems.append(stem)
    _write_if_changed(out / "intro.md", _fix_links(intro, {}, root, 1))
    for stem, after in (extra or {}).items():
        stems.insert(stems.index(after) + 1 if after in stems else len(stems), stem)
    toc = ["```{toctree}", ":maxdepth: 2", ":caption: Guide", ""] + [f"guide/{s}" for s in stems] + ["```", ""]
    _write_if_changed(out / "toc.md", "\n".join(toc))
    return stems


def _write_if_changed(path: Path, text: str) -> None:
    """Write only on change, so that Sphinx's incremental builds do not re-read unchanged pages."""
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def write_model_examples(root: Path, out: Path) -> str:
    """Write the page of the shipped model files and the catalogue into ``out``; return its stem.

    Every ``.toml`` / ``.json`` file of ``examples/`` and ``papers_examples/`` is shown whole (a
    ``literalinclude``, so the page follows the files), with the ``name`` it declares; the
    catalogue's mechanisms are listed by the name ``catalogue:NAME`` takes.
    """
    import tomllib

    from symkin import catalogue

    stem = "model_examples"
    lines = ["# Model files: the shipped examples", "",
             "The model files the guide's examples name, shown whole: `examples/` (the README's examples) "
             "and `papers_examples/` (each example of the paper, with the script that checks what the "
             "paper states). Every command and `symkin.read_model` also take `catalogue:NAME` for a "
             "mechanism of the catalogue (listed at the end; `symkin.catalogue.get(NAME)` in Python).", ""]
    for folder in ("examples", "papers_examples"):
        files = sorted(p for p in (root / folder).glob("*") if p.suffix in (".toml", ".json"))
        if not files:
            continue
        lines += [f"## `{folder}/`", ""]
        for path in files:
            try:
                name = (tomllib.loads(path.read_text(encoding="utf-8")) if path.suffix == ".toml"
                        else __import__("json").loads(path.read_text(encoding="utf-8"))).get("name", "")
            except ValueError:
                name = ""
            lines += [f"### `{folder}/{path.name}`", "", f"{name}", "",
                      "```{literalinclude} " + f"../../{folder}/{path.name}",
                      f":language: {path.suffix[1:]}", "```", ""]
    lines += ["## The catalogue", "", "| `catalogue:NAME` | mechanism |", "|---|---|"]
    lines += [f"| `catalogue:{n}` | {catalogue.get(n).name} |" for n in catalogue.names()]
    _write_if_changed(out / f"{stem}.md", "\n".join(lines) + "\n")
    return stem
