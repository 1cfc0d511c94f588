"""The ``symkin`` command line: the only place that prints for the user or picks an exit code.

Each subcommand lives in :mod:`symkin.commands` as a module with ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``run(args) -> Output``; this file wires them, prints
their output and turns user errors into ``file: message`` with exit code 2.

Exit codes: 0 success; 1 the command ran but found a failure it reports (e.g. a paper
claim that does not hold); 2 a user error (bad file, bad option); 3 an internal error
(a bug: the traceback is printed so it can be reported).
"""
from __future__ import annotations

import argparse
import importlib
import sys
import traceback
import warnings

from symkin.commands import COMMANDS, Output
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


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    shown = warnings.formatwarning
    warnings.formatwarning = _one_line
    try:
        out: Output = args._run(args)
    except SymkinError as exc:
        print(_format_error(exc), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("symkin: interrupted", file=sys.stderr)
        return 130
    except Exception:  # a bug, not a user error: show it so it can be reported
        traceback.print_exc()
        print("symkin: internal error (this is a bug; please report it with the traceback above)",
              file=sys.stderr)
        return 3
    finally:
        warnings.formatwarning = shown
    if out.text:
        sys.stdout.write(out.text if out.text.endswith("\n") else out.text + "\n")
    if out.message:
        print(out.message, file=sys.stderr)
    return out.code


if __name__ == "__main__":
    raise SystemExit(main())
