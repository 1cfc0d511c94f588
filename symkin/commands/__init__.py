"""Subcommands of the ``symkin`` command line; see :mod:`symkin.cli`.

A command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and
``run(args) -> Output``.  It never prints: it returns what to print and the exit code,
and raises :class:`symkin.errors.SymkinError` for a user's mistake.  Add a module and
its name to ``COMMANDS`` to add a subcommand.
"""
from __future__ import annotations

from dataclasses import dataclass

from symkin.errors import ModelError, SymkinError

__all__ = ["COMMANDS", "Output", "in_file"]

COMMANDS = ["analyze", "reproduce", "path", "map", "modes", "singularities", "conditions", "codegen", "cache"]


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
