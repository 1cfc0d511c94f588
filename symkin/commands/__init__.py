"""Subcommands of the ``symkin`` command line; see :mod:`symkin.cli`.

A command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and
``run(args) -> Output``.  It never prints: it returns what to print and the exit code,
and raises :class:`symkin.errors.SymkinError` for a user's mistake.  Add a module and
its name to ``COMMANDS`` to add a subcommand.
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from symkin.errors import ModelError, SymkinError, check_interrupt, interrupts_deferred

__all__ = ["COMMANDS", "Output", "in_file", "write_output", "finite_number", "positive_number",
           "non_negative_number", "check_holds", "check_output_folder", "format_coordinate", "format_outputs",
           "LENGTH_UNITS"]

COMMANDS = ["analyze", "reproduce", "path", "map", "modes", "singularities", "conditions", "codegen", "cache"]


#: the unit of a length coordinate in the reports
LENGTH_UNITS = "(model length units)"


def format_coordinate(label: str, relative: float, absolute: float | None, unit: str) -> str:
    """One coordinate as every command prints it: relative to the model, then absolute.

    Angles are measured from the model's configuration, wrapped to (−180°, 180°], and, for a
    planar link, given also as its absolute direction in [0°, 360°)
    (:func:`symkin.paths.trace.relative_angle`); ``unit`` is ``deg``, ``rad`` or
    :data:`LENGTH_UNITS` (a length, measured from the model, printed without a unit; its
    absolute value is the node's coordinate for ``velocity:N.x``).

    >>> format_coordinate("rotation:crank", -53.91904574, 23.55214655, "deg")
    'rotation:crank = -53.91904574 deg (absolute 23.55214655 deg)'
    """
    u = "" if unit == LENGTH_UNITS else f" {unit}"  # a length: model units, said once per line at most
    text = f"{label} = {relative:.10g}{u}"
    return text if absolute is None else f"{text} (absolute {absolute:.10g}{u})"


def format_outputs(values: dict, kinds: dict, unit: str) -> str:
    """The model's outputs ``{label: {"relative", "absolute"}}`` as ``a = …, b = …`` (see :func:`format_coordinate`).

    ``kinds`` maps each label to ``"angle"`` or ``"length"``.
    """
    return ", ".join(format_coordinate(label, v["relative"], v["absolute"],
                                       unit if kinds[label] == "angle" else LENGTH_UNITS)
                     for label, v in values.items())


@dataclass(frozen=True)
class Output:
    """What a command prints on stdout (``text``), on stderr (``message``), and its exit code."""

    text: str = ""
    code: int = 0
    message: str = ""


def in_file(exc: SymkinError, model: str) -> SymkinError:
    """``exc`` itself, told which model file it concerns (the CLI prints ``file: message``).

    The error keeps its class and its data (``ModelError.problems``,
    ``NotConvergedError.data``): a :class:`ModelError` without a source gets ``model`` as
    its source; any other error gets ``model: `` in front of its message.
    """
    if isinstance(exc, ModelError):
        if exc.source is None:
            exc.source = model
    elif not str(exc).startswith(f"{model}: "):
        exc.args = (f"{model}: {exc}",) + tuple(exc.args[1:])
    return exc


def write_output(target, write: Callable[[Path], object]) -> Path:
    """Write an output file whole or not at all: ``write(tmp)`` fills a temporary file in the
    target's folder, which then replaces ``target`` with ``os.replace``.

    An interrupt (or any error) before the replacement leaves ``target`` as it was and
    removes the temporary file.
    """
    target = Path(target)
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    _readable(tmp)
    try:
        write(tmp)
        check_interrupt()
        with interrupts_deferred():
            os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()
    return target


def _readable(path: Path) -> None:
    """Give a temporary file (``mkstemp``: mode 0600) the mode a new file gets under the umask."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(path, 0o666 & ~mask)


# ---------------------------------------------------------------------- numbers a user types
def _number(text: str, what: str, test, ok: str) -> float:
    import argparse
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value) or not test(value):
        raise argparse.ArgumentTypeError(f"{text!r}: {what} must be {ok}")
    return value


def finite_number(text: str) -> float:
    """An argparse type: a finite number (``nan``, ``inf`` and overflowing values are refused)."""
    return _number(text, "the value", lambda v: True, "a finite number")


def positive_number(text: str) -> float:
    """An argparse type: a finite number > 0."""
    return _number(text, "the value", lambda v: v > 0, "a finite number greater than 0")


def non_negative_number(text: str) -> float:
    """An argparse type: a finite number >= 0."""
    return _number(text, "the value", lambda v: v >= 0, "a finite number, 0 or more")


def check_holds(holds, option: str = "--hold") -> None:
    """Every ``LABEL=VALUE`` of ``holds`` has a finite VALUE (``LABEL`` alone: the model's value)."""
    import math

    for text in holds:
        label, eq, value = str(text).rpartition("=")
        if not eq:
            continue
        try:
            number = float(value)
        except ValueError:
            raise SymkinError(f"{option} {text!r}: VALUE must be a number") from None
        if not math.isfinite(number):
            raise SymkinError(f"{option} {text!r}: VALUE must be a finite number")


def check_output_folder(path, option: str) -> Path:
    """The folder ``path`` (created if needed) or a :class:`SymkinError` saying why it cannot be written."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SymkinError(f"{option} {folder}: cannot create the folder ({exc.strerror or exc})") from None
    if not folder.is_dir():
        raise SymkinError(f"{option} {folder}: exists and is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise SymkinError(f"{option} {folder}: the folder is not writable")
    try:
        fd, probe = tempfile.mkstemp(prefix=".symkin-probe-", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise SymkinError(f"{option} {folder}: cannot write into the folder ({exc.strerror or exc})") from None
    return folder
