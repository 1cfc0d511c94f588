"""Subcommands of the ``symkin`` command line; see :mod:`symkin.cli`.

A command module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and
``run(args) -> Output``.  It never prints: it returns what to print and the exit code,
and raises :class:`symkin.errors.SymkinError` for a user's mistake.  Add a module and
its name to ``COMMANDS`` to add a subcommand.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["COMMANDS", "Output"]

COMMANDS = ["analyze", "reproduce", "path", "map", "modes", "singularities", "conditions", "codegen"]


@dataclass(frozen=True)
class Output:
    """What a command prints on stdout (``text``), on stderr (``message``), and its exit code."""

    text: str = ""
    code: int = 0
    message: str = ""
