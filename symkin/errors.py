"""Exceptions raised by symkin.

Every error a user can cause derives from :class:`SymkinError`; the command line turns
it into ``file: message`` and exit code 2.  Errors carry the data that locate the
problem (file, key, node, link) so that callers need not parse messages.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["SymkinError", "Problem", "ModelError", "ModelFileError", "NotConvergedError",
           "caused_by_interrupt", "note_interrupt", "interrupt_seen", "check_interrupt", "clear_interrupt",
           "interrupts_deferred"]


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


# ---------------------------------------------------------------------- interrupts
#: state of Ctrl-C for the running command: ``seen`` once a SIGINT arrived (set by the
#: command line's handler, :func:`note_interrupt`); ``deferred`` while outputs are moved into place
_INTERRUPT = {"seen": False, "deferred": 0, "pending": False}


def caused_by_interrupt(exc: BaseException | None) -> bool:
    """True when ``exc`` is a :class:`KeyboardInterrupt` or wraps one (``__cause__``/``__context__``).

    An interrupt raised inside a C extension can surface as another exception, e.g. CasADi's
    ``SystemError: <function DM.__array__> returned a result with an exception set`` whose
    cause is the ``KeyboardInterrupt``; such an exception is an interrupt, never a result.

    >>> try:
    ...     try:
    ...         raise KeyboardInterrupt
    ...     except KeyboardInterrupt as ki:
    ...         raise SystemError("returned a result with an exception set") from ki
    ... except SystemError as exc:
    ...     caused_by_interrupt(exc)
    True
    >>> caused_by_interrupt(ValueError("x"))
    False
    """
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def note_interrupt() -> bool:
    """Record that a SIGINT arrived; return True when it must be raised now (not deferred)."""
    _INTERRUPT["seen"] = True
    if _INTERRUPT["deferred"]:
        _INTERRUPT["pending"] = True
        return False
    return True


def interrupt_seen() -> bool:
    """True once a SIGINT arrived during this command (even if some code swallowed the exception)."""
    return _INTERRUPT["seen"]


def clear_interrupt() -> None:
    """Forget a recorded SIGINT (the command line calls it before each command)."""
    _INTERRUPT.update(seen=False, deferred=0, pending=False)


def check_interrupt(exc: BaseException | None = None) -> None:
    """Raise :class:`KeyboardInterrupt` when a SIGINT arrived or ``exc`` wraps one.

    Call it where an exception is about to be recorded as a result (a failed check), and
    before outputs are written: an interrupted run then never writes or reports anything.
    """
    if _INTERRUPT["seen"] or caused_by_interrupt(exc):
        raise KeyboardInterrupt from exc


@contextmanager
def interrupts_deferred():
    """A SIGINT inside the block (with the command line's handler) is raised when the block ends.

    Used while finished outputs are moved into place, so that a set of files is replaced
    whole or not at all.
    """
    _INTERRUPT["deferred"] += 1
    try:
        yield
    finally:
        _INTERRUPT["deferred"] -= 1
    if not _INTERRUPT["deferred"] and _INTERRUPT["pending"]:
        _INTERRUPT["pending"] = False
        raise KeyboardInterrupt
