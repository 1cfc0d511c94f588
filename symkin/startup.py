"""The first thing the ``symkin`` program does: a Ctrl-C while it starts exits 130 with one line.

Imports only what the interpreter has loaded before any code runs (``os``, ``sys``) and the
built-in ``signal``, so that the handler is in place a few hundred microseconds into
``import symkin``; ``symkin/__init__.py`` calls :func:`exit_on_early_interrupt` before any
other import (a SIGINT during Python's own start-up, before that line, is Python's).
"""
from __future__ import annotations

import os
import signal
import sys

__all__ = ["is_symkin_program", "exit_on_early_interrupt"]


def is_symkin_program() -> bool:
    """True when this process is the ``symkin`` program (its console script or ``python -m symkin``).

    Read from ``sys.orig_argv`` and the ``__main__`` module's file, so that it holds while the
    package is still being imported (before :func:`symkin.cli.main` runs).
    """
    main_file = getattr(sys.modules.get("__main__"), "__file__", None) or ""
    if os.path.basename(main_file).removesuffix(".exe") in ("symkin", "symkin-script.py"):
        return True
    argv = list(getattr(sys, "orig_argv", sys.argv))
    return any(a == "-m" and b in ("symkin", "symkin.cli") for a, b in zip(argv, argv[1:]))


def _exit_interrupted(signum, frame):  # pragma: no cover - ends the process
    os.write(2, b"symkin: interrupted\n")
    os._exit(130)


def exit_on_early_interrupt() -> None:
    """In the ``symkin`` program, make a Ctrl-C before :func:`symkin.cli.main` runs exit 130 with one line.

    Called first thing by ``symkin/__init__.py`` (and again by :mod:`symkin.cli` and
    ``python -m symkin``), before numpy and the model stage are imported: a SIGINT while the
    program starts writes ``symkin: interrupted`` and exits 130 at once (nothing has been
    written yet), where Python would print a ``KeyboardInterrupt`` traceback from inside an
    import.  :func:`symkin.cli.main` installs its own handler when it starts.  Does nothing
    when symkin is imported as a library (the caller's handler stays) or off the main thread.
    """
    if not is_symkin_program():
        return
    try:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _exit_interrupted)
    except ValueError:  # not the main thread
        pass
