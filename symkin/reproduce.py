"""Checks of what the paper states, and the runner behind ``symkin reproduce``.

Each example in ``papers_examples/`` is a model file plus a script ``check_<name>.py``
that defines ``check() -> Checklist``.  A :class:`Checklist` records *claims*: a
statement from the paper, the measured value, the expected value, and whether they
agree.  A script run directly exits 1 when a claim fails; the test suite and
``symkin reproduce`` run every script.
"""
from __future__ import annotations

import importlib.util
import json
import math
import os
import re
import shutil
import sys
import tempfile
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symkin.errors import check_interrupt, interrupts_deferred

__all__ = ["Claim", "Checklist", "find_examples_dir", "discover", "run_check", "run_all", "write_report",
           "file_slug"]


@dataclass(frozen=True)
class Claim:
    statement: str
    holds: bool
    measured: str
    expected: str


@dataclass
class Checklist:
    """Claims of one paper example.

    >>> c = Checklist("demo")
    >>> c.equal("DOF of a four-bar", 1, 1)
    True
    >>> c.ok
    True
    """

    example: str
    claims: list[Claim] = field(default_factory=list)
    analyses: dict[str, Any] = field(default_factory=dict)

    def _add(self, statement: str, holds: bool, measured: Any, expected: Any) -> bool:
        self.claims.append(Claim(statement, bool(holds), _fmt(measured), _fmt(expected)))
        return bool(holds)

    def equal(self, statement: str, measured: Any, expected: Any) -> bool:
        """Exact equality (ints, strings, sets, tuples)."""
        return self._add(statement, measured == expected, measured, expected)

    def close(self, statement: str, measured: float, expected: float, tol: float = 1e-9) -> bool:
        """``|measured − expected| <= tol·max(1, |expected|)``."""
        ok = math.isfinite(measured) and abs(measured - expected) <= tol * max(1.0, abs(expected))
        return self._add(statement, ok, measured, expected)

    def true(self, statement: str, value: bool, detail: Any = "") -> bool:
        return self._add(statement, bool(value), detail if detail != "" else bool(value), True)

    def record(self, label: str, analysis) -> None:
        """Keep an analysis for the report folder (``symkin reproduce --out``)."""
        self.analyses[label] = analysis

    @property
    def ok(self) -> bool:
        return all(c.holds for c in self.claims) and bool(self.claims)

    def summary(self) -> str:
        lines = [f"{self.example}: {sum(c.holds for c in self.claims)}/{len(self.claims)} claims hold"]
        for c in self.claims:
            mark = "ok  " if c.holds else "FAIL"
            detail = f" (measured {c.measured}, expected {c.expected})" if not c.holds else ""
            lines.append(f"  {mark} {c.statement}{detail}")
        return "\n".join(lines)

    def main(self) -> int:
        """Print the summary; exit code 0 when every claim holds (for ``__main__`` blocks)."""
        print(self.summary())
        return 0 if self.ok else 1


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.12g}"
    return str(value)


#: symbols spelled out in file names (others: Greek letters by name, accents dropped)
_SPELLED = {"−": "-", "–": "-", "—": "-", "§": "sec", "°": "deg", "×": "x", "±": "pm", "→": "to",
            "≤": "le", "≥": "ge", "∥": "parallel", "µ": "u", "′": "p", "″": "pp"}


def _ascii(ch: str) -> str:
    """An ASCII spelling of one character (empty when it has none)."""
    if ch.isascii():
        return ch
    if ch in _SPELLED:
        return _SPELLED[ch]
    base = "".join(c for c in unicodedata.normalize("NFKD", ch) if c.isascii())
    if base:
        return base                                          # é -> e
    name = unicodedata.name(ch, "")
    if name.startswith("GREEK") and "LETTER" in name:
        word = name.split()[-1].lower()
        return {"lamda": "lambda"}.get(word, word)
    return ""


def file_slug(text: str) -> str:
    """A file-name stem a shell user can type: ASCII letters, digits, ``-`` and ``_`` only.

    Symbols are spelled out (λ → lambda, − → -, § → sec, ° → deg), accents dropped, and
    every other run of characters becomes one ``_``.

    >>> file_slug("path at λ = −90° (position c)")
    'path_at_lambda_-90deg_position_c'
    >>> file_slug("§ V-B, Fig. 11")
    'sec_V-B_Fig_11'
    """
    spelled = "".join(_ascii(ch) for ch in text)
    return re.sub(r"[^A-Za-z0-9-]+", "_", spelled).strip("_") or "unnamed"


def _unique(stem: str, taken: set[str]) -> str:
    name, k = stem, 2
    while name.lower() in taken:           # case-insensitive file systems too
        name, k = f"{stem}-{k}", k + 1
    taken.add(name.lower())
    return name


def find_examples_dir(explicit: str | Path | None = None) -> Path | None:
    """``explicit``, else ``./papers_examples``, else the one beside the installed package."""
    candidates = [Path(explicit)] if explicit else [Path.cwd() / "papers_examples",
                                                    Path(__file__).resolve().parents[1] / "papers_examples"]
    for c in candidates:
        if c.is_dir() and any(c.glob("check_*.py")):
            return c
    return None


def discover(examples_dir: Path) -> list[Path]:
    """The check scripts of a folder, sorted by name."""
    return sorted(Path(examples_dir).glob("check_*.py"))


def run_check(script: Path) -> Checklist:
    """Import ``script`` and return its ``check()`` result."""
    script = Path(script)
    spec = importlib.util.spec_from_file_location(f"symkin_example_{script.stem}", script)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    result = module.check()
    if not isinstance(result, Checklist):
        raise TypeError(f"{script}: check() must return a Checklist")
    return result


def _run_guarded(script: Path) -> Checklist:
    """Run one check; a script that raises becomes a failed claim instead of stopping the run.

    An interrupt is never a failed claim: a :class:`KeyboardInterrupt`, an exception that
    wraps one (CasADi's ``SystemError ... returned a result with an exception set``), or
    any result obtained after a SIGINT arrived, stops the run.
    """
    try:
        result = run_check(script)
    except Exception as exc:  # noqa: BLE001 - any failure of an example is reported, not raised
        check_interrupt(exc)
        failed = Checklist(Path(script).stem.removeprefix("check_"))
        failed.true(f"{Path(script).name} runs to the end", False, f"{type(exc).__name__}: {exc}")
        return failed
    check_interrupt()
    return result


def run_all(examples_dir: Path, out: Path | None = None) -> list[Checklist]:
    """Run every check; with ``out``, write ``summary.md``, ``summary.json`` and one JSON per analysis.

    The report is written into a temporary folder beside ``out`` and its files moved into
    ``out`` with ``os.replace`` (``summary.md`` last) once every check has run: an
    interrupted run leaves the files of ``out`` as they were.
    """
    results = [_run_guarded(s) for s in discover(examples_dir)]
    if out is not None:
        write_report(results, Path(out))
    return results


def _report_files(results: list[Checklist]) -> dict[str, str]:
    from symkin.report import render_markdown

    files: dict[str, str] = {}
    summary, taken = [], {"summary"}
    md = ["# symkin reproduce: the paper's examples", ""]
    for res in results:
        summary.append({"example": res.example, "ok": res.ok,
                        "claims": [c.__dict__ for c in res.claims]})
        md += [f"## {res.example}: {'all claims hold' if res.ok else 'SOME CLAIMS FAIL'}", ""]
        md += [f"- {'✔' if c.holds else '✘'} {c.statement} — measured {c.measured}" for c in res.claims]
        md.append("")
        for label, analysis in res.analyses.items():
            stem = _unique(f"{file_slug(res.example)}__{file_slug(label)}", taken)
            files[f"{stem}.json"] = json.dumps(analysis.to_dict(), indent=2) + "\n"
            md += [f"### {label}", "", f"(`{stem}.json`)", "", render_markdown(analysis), ""]
    files["summary.json"] = json.dumps(summary, indent=2) + "\n"
    files["summary.md"] = "\n".join(md) + "\n"
    return files


def write_report(results: list[Checklist], out: Path) -> Path:
    """Write the report folder of ``results`` into ``out``, each file replaced whole (see :func:`run_all`)."""
    out = Path(out)
    files = _report_files(results)
    check_interrupt()
    out.mkdir(parents=True, exist_ok=True)
    staging = None
    try:
        with interrupts_deferred():  # the staging folder is made and named as one step
            staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
        for name, text in files.items():
            (staging / name).write_text(text, encoding="utf-8")
        check_interrupt()
        with interrupts_deferred():  # the files are moved in together or not at all
            for name in sorted(files, key=lambda n: n == "summary.md"):
                os.replace(staging / name, out / name)
    finally:
        if staging is not None:
            with interrupts_deferred():  # an interrupt does not cut the clean-up short
                shutil.rmtree(staging, ignore_errors=True)
    return out
