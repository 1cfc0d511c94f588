"""The files a command writes: checked before the work, written whole, never lost after it.

Every command that writes files (``path --csv/--plot``, ``map --json/--npz/--plot``,
``singularities --plot``, ``reproduce --out``, ``codegen --out``) calls these helpers:

* before it computes, :func:`check_output_file` (a file: its folder exists and is writable,
  the path is not a folder), :func:`check_figure_file` (also: matplotlib is installed and
  knows the extension) or :func:`check_output_folder` (a folder, created if needed) — a
  :class:`~symkin.errors.SymkinError` ``--option PATH: why`` (exit 2) before any work;
* after it, :func:`save_output`: :func:`write_output` (a temporary file in the target's
  folder, renamed into place), and when that still fails (the folder went away, the disk
  is full), the same content into the current folder (or the temporary folder) under a
  printed name: a :class:`Saved` whose ``problem`` the command reports, exiting 1.

>>> import tempfile
>>> folder = tempfile.mkdtemp()
>>> check_output_file(f"{folder}/x.csv", "--csv").name
'x.csv'
>>> check_output_file(f"{folder}/missing/x.csv", "--csv")  # doctest: +ELLIPSIS
Traceback (most recent call last):
    ...
symkin.errors.SymkinError: --csv .../missing/x.csv: the folder .../missing does not exist
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from symkin.errors import SymkinError, check_interrupt, interrupts_deferred

__all__ = ["check_output_file", "check_figure_file", "check_output_folder", "figure_formats", "write_output",
           "save_output", "Saved"]


def check_output_folder(path, option: str) -> Path:
    """The folder ``path`` (created if needed) or a :class:`SymkinError` saying why it cannot be written."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SymkinError(f"{option} {folder}: cannot create the folder ({exc.strerror or exc})") from None
    if not folder.is_dir():
        raise SymkinError(f"{option} {folder}: exists and is not a folder")
    _writable_folder(folder, f"{option} {folder}")
    return folder


def _writable_folder(folder: Path, what: str) -> None:
    """A :class:`SymkinError` naming ``what`` unless a file can be created in ``folder``."""
    if not os.access(folder, os.W_OK | os.X_OK):
        raise SymkinError(f"{what}: the folder {folder} is not writable")
    try:
        fd, probe = tempfile.mkstemp(prefix=".symkin-probe-", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise SymkinError(f"{what}: cannot write into the folder {folder} ({exc.strerror or exc})") from None


def check_output_file(path, option: str) -> Path:
    """The file ``path`` if it can be written, else a :class:`SymkinError` ``option path: why``.

    Its folder must exist (it is not created: a typo in a folder name is an error) and be
    writable; ``path`` must not be a folder.
    """
    target = Path(path)
    what = f"{option} {target}"
    if target.is_dir():
        raise SymkinError(f"{what}: is a folder; give a file name")
    folder = target.parent
    if not folder.exists():
        raise SymkinError(f"{what}: the folder {folder} does not exist")
    if not folder.is_dir():
        raise SymkinError(f"{what}: {folder} is not a folder")
    _writable_folder(folder, what)
    return target


def figure_formats() -> dict[str, str]:
    """The file extensions matplotlib writes (without the dot) and their descriptions (imports matplotlib)."""
    from matplotlib.backend_bases import FigureCanvasBase

    return dict(FigureCanvasBase.get_supported_filetypes())


def check_figure_file(path, option: str = "--plot") -> Path:
    """:func:`check_output_file` for a figure: matplotlib installed (the plots extra), its extension known.

    A name without an extension is written as PNG.
    """
    from symkin.plots.extra import require_matplotlib

    require_matplotlib(option)
    target = check_output_file(path, option)
    ext = target.suffix[1:].lower()
    if ext:
        formats = figure_formats()
        if ext not in formats:
            raise SymkinError(f"{option} {target}: unknown figure format {target.suffix!r}; use one of "
                              + ", ".join(f".{e}" for e in sorted(formats)))
    return target


def write_output(target, write: Callable[[Path], object], suffix: str = ".tmp") -> Path:
    """Write an output file whole or not at all: ``write(tmp)`` fills a temporary file in the
    target's folder (its name ends with ``suffix``), which then replaces ``target`` with ``os.replace``.

    An interrupt (or any error) before the replacement leaves ``target`` as it was and
    removes the temporary file.
    """
    target = Path(target)
    tmp = None
    try:
        with interrupts_deferred():  # the temporary file is made and named as one step
            fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
            os.close(fd)
            tmp = Path(name)
        _readable(tmp)
        write(tmp)
        check_interrupt()
        with interrupts_deferred():
            os.replace(tmp, target)
    finally:
        if tmp is not None:
            with interrupts_deferred():  # an interrupt does not cut the clean-up short
                tmp.unlink(missing_ok=True)
    return target


def _readable(path: Path) -> None:
    """Give a temporary file (``mkstemp``: mode 0600) the mode a new file gets under the umask."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(path, 0o666 & ~mask)


@dataclass(frozen=True)
class Saved:
    """Where :func:`save_output` wrote: ``path``; ``problem`` why not where asked (None: it was), for the user."""

    path: Path
    problem: str | None = None


def save_output(target, write: Callable[[Path], object], option: str, figure: bool = False) -> Saved:
    """:func:`write_output`, and when that fails after the work, the same output in the current folder.

    The fallback is ``symkin-<name>`` in the current folder (``symkin-<k>-<name>`` if taken),
    else in the temporary folder; a :class:`SymkinError` only when nothing can be written.
    ``figure`` keeps the extension (or ``.png``) at the end of the temporary file's name,
    where matplotlib reads the format.
    """
    target = Path(target)
    suffix = ".tmp" + (target.suffix or ".png") if figure else ".tmp"
    try:
        return Saved(write_output(target, write, suffix))
    except (OSError, SymkinError) as exc:
        check_interrupt(exc)
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
    tried = []
    for folder in (Path.cwd(), Path(tempfile.gettempdir())):
        fallback = folder / f"symkin-{target.name}"
        k = 1
        while fallback.exists():
            fallback, k = folder / f"symkin-{k}-{target.name}", k + 1
        try:
            write_output(fallback, write, suffix)
        except (OSError, SymkinError) as exc:
            check_interrupt(exc)
            tried.append(f"{fallback} ({exc.strerror if isinstance(exc, OSError) and exc.strerror else exc})")
            continue
        return Saved(fallback, f"{option} {target}: could not be written ({reason}); written to {fallback} instead")
    raise SymkinError(f"{option} {target}: could not be written ({reason}), nor " + ", nor ".join(tried))
