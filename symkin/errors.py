"""Exceptions raised by symkin.

Every error a user can cause derives from :class:`SymkinError`; the command line turns
it into ``file: message`` and exit code 2.  Errors carry the data that locate the
problem (file, key, node, link) so that callers need not parse messages.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["SymkinError", "Problem", "ModelError", "ModelFileError", "NotConvergedError"]


class SymkinError(Exception):
    """Base class of every error caused by a user's input."""


@dataclass(frozen=True)
class Problem:
    """One problem found in a model: where it is (``key``) and what is wrong."""

    key: str
    message: str

    def __str__(self) -> str:
        return f"{self.key}: {self.message}" if self.key else self.message


class ModelError(SymkinError):
    """A mechanism description is invalid.  ``problems`` lists every problem found."""

    def __init__(self, problems: list[Problem] | tuple[Problem, ...], source: str | None = None):
        self.problems = tuple(problems)
        self.source = source
        lines = [str(p) for p in self.problems]
        head = f"{len(lines)} problem(s) in the model" if len(lines) > 1 else "invalid model"
        super().__init__(head + ":\n  " + "\n  ".join(lines) if len(lines) > 1 else lines[0])


class ModelFileError(ModelError):
    """A model file cannot be read or describes an invalid mechanism."""

    def __init__(self, path: str, problems, line: int | None = None):
        self.path = str(path)
        self.line = line
        super().__init__(problems, source=str(path))


class NotConvergedError(SymkinError):
    """An iterative solver did not converge; ``data`` holds how close it got."""

    def __init__(self, message: str, **data):
        self.data = data
        super().__init__(message)
