"""The ``symkin`` command line: the only place that prints for the user or picks an exit code.

Each subcommand lives in :mod:`symkin.commands` as a module with ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``run(args) -> Output``; this file wires them, prints
their output and turns user errors into ``file: message`` with exit code 2.

Exit codes: 0 success; 1 the command ran but found a failure it reports (e.g. a paper
claim that does not hold); 2 a user error (bad file, bad option); 3 an internal error
(a bug: the traceback is printed so it can be reported); 130 interrupted (SIGINT, one
line; also when the interrupt surfaced wrapped in another exception, or was swallowed).
A Ctrl-C before :func:`main` runs (while Python imports the package) also exits 130 with one
line: ``import symkin`` installs that handling first of all when the process is the ``symkin``
program (:func:`symkin.startup.exit_on_early_interrupt`), and :func:`main` replaces it.
"""
from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import traceback
import warnings

from symkin.commands import COMMANDS, Output
from symkin import errors
from symkin.errors import ModelError, ModelFileError, SymkinError

__all__ = ["main", "build_parser"]


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse exits 2 on its own; keep its message short
        self.print_usage(sys.stderr)
        self.exit(2, f"symkin: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    from symkin import __version__

    parser = _Parser(prog="symkin", description="Singular configurations of mechanisms "
                     "(geometric-matrix method of Altuzarra et al., IEEE T-RO 2004).")
    parser.add_argument("--version", action="version", version=f"symkin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMANDS:
        module = importlib.import_module(f"symkin.commands.{name}")
        p = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def _format_error(exc: SymkinError) -> str:
    if isinstance(exc, ModelFileError):
        return "\n".join(f"{exc.path}: {p}" for p in exc.problems)
    if isinstance(exc, ModelError):
        prefix = f"{exc.source}: " if exc.source else ""
        return "\n".join(f"{prefix}{p}" for p in exc.problems)
    return str(exc)


def _one_line(message, category, filename, lineno, line=None) -> str:
    """A warning as the user reads it: one line, no source location."""
    return f"{category.__name__}: {message}\n"


def _on_sigint(signum, frame):
    """Ctrl-C: remember it (code that swallows the exception cannot hide it) and raise."""
    if errors.note_interrupt():
        raise KeyboardInterrupt


def _unraisable(hook):
    """``sys.unraisablehook`` that passes over a KeyboardInterrupt: a Ctrl-C that arrived inside a
    weakref callback (e.g. importlib's module-lock clean-up) cannot propagate; it is noted and
    ends the command with 130, and is not printed as an ignored exception's traceback."""
    def unraisable(u):
        if not isinstance(u.exc_value, KeyboardInterrupt):
            hook(u)
    return unraisable


def _interrupted() -> int:
    print("symkin: interrupted", file=sys.stderr)
    return 130


#: the program's first garbage-collector threshold (Python's default 700): sympy and SciPy allocate
#: millions of objects while they load and the collector walked them 240 times, a tenth of a
#: ``symkin modes`` query (issue 17)
GC_THRESHOLD = 10_000


def main(argv: list[str] | None = None) -> int:
    errors.clear_interrupt()
    if argv is None:  # the program (not a caller's process): fewer collections, see GC_THRESHOLD
        import gc

        first, *rest = gc.get_threshold()
        gc.set_threshold(max(first, GC_THRESHOLD), *rest)
    try:  # first of all: a Ctrl-C while the command modules load is an interrupt too
        previous = signal.signal(signal.SIGINT, _on_sigint)
    except ValueError:  # not the main thread: keep Python's handler
        previous = None
    shown, unraisable = warnings.formatwarning, sys.unraisablehook
    warnings.formatwarning = _one_line
    sys.unraisablehook = _unraisable(unraisable)
    try:
        code = _main(argv)
    except KeyboardInterrupt:
        code = _interrupted()
    finally:
        warnings.formatwarning = shown
        sys.unraisablehook = unraisable
        if previous is not None:
            # the program (argv None) has done its work and picked its exit code: a late
            # Ctrl-C no longer changes it; called from Python, the caller's handler comes back
            signal.signal(signal.SIGINT, signal.SIG_IGN if argv is None else previous)
    if argv is None:
        # the program has done its work: what is left is freed at exit without the cyclic garbage
        # collector walking every object first (0.1 s after a command that used sympy; issue 17)
        import gc

        gc.freeze()
    if code == 130 and argv is None:
        # the program was interrupted and has cleaned up: exit now with 130.  (CPython kills
        # itself with SIGINT at exit when an interrupt once passed through code run by an
        # extension's PyRun_String, although it was caught: exit code -2 instead of 130.)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(130)
    return code


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        out: Output = args._run(args)
        if errors.interrupt_seen():  # interrupted, and some code swallowed the exception
            return _interrupted()
    except KeyboardInterrupt:
        return _interrupted()
    except SymkinError as exc:
        if errors.interrupt_seen() or errors.caused_by_interrupt(exc):
            return _interrupted()
        print(_format_error(exc), file=sys.stderr)
        return 2
    except Exception as exc:  # a bug, not a user error: show it so it can be reported
        if errors.interrupt_seen() or errors.caused_by_interrupt(exc):  # an interrupt inside C code
            return _interrupted()
        traceback.print_exc()
        print("symkin: internal error (this is a bug; please report it with the traceback above)",
              file=sys.stderr)
        return 3
    if out.text:
        sys.stdout.write(out.text if out.text.endswith("\n") else out.text + "\n")
    if out.message:
        print(out.message, file=sys.stderr)
    return out.code


if __name__ == "__main__":
    raise SystemExit(main())
