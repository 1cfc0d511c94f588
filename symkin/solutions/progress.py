"""Progress of the global solves (``symkin modes``, ``symkin singularities``; issue 17 §3).

A solve is a sequence of *stages* (a homotopy of ``N`` paths, the monodromy loops, a trace,
a square system); each stage has a description and, when known, a total (paths, loops).
:class:`Progress` shows them

* on a terminal: a tqdm bar over the stage's units (paths, loops, steps) on stderr;
* otherwise (``--no-progress``, or stderr not a terminal): one summary line on stderr every
  ``every`` seconds (default :data:`SUMMARY_EVERY` = 30), ``symkin NAME: <stage> <k>/<total>
  <unit>, <elapsed> elapsed``, printed by a daemon timer thread, so it comes even while one long
  homotopy runs without telling anyone.

:meth:`Progress.note` prints a line at once in both modes (the estimate of a large homotopy).
The functions of :mod:`symkin.solutions` take ``progress`` as a :class:`Progress`, a plain
callable ``progress(message)`` (told each stage's description) or None; :func:`as_progress`
turns either into an object with the three methods.
"""
from __future__ import annotations

import sys
import threading
import time

__all__ = ["NullProgress", "Progress", "SUMMARY_EVERY", "as_progress", "format_seconds"]

#: seconds between the summary lines of ``--no-progress``
SUMMARY_EVERY = 30.0


def format_seconds(seconds: float) -> str:
    """``42 s``, ``3 min 05 s``, ``2 h 10 min``."""
    s = max(0.0, float(seconds))
    if s < 60:
        return f"{s:.0f} s" if s >= 10 else f"{s:.1f} s"
    if s < 3600:
        return f"{int(s // 60)} min {int(s % 60):02d} s"
    return f"{int(s // 3600)} h {int(s % 3600 // 60):02d} min"


class NullProgress:
    """Tells nobody (``progress=None``)."""

    def stage(self, description: str, total: int | None = None, unit: str = "step") -> None:
        """Start a stage of ``total`` units (None: unknown)."""

    def advance(self, n: int = 1) -> None:
        """``n`` more units of the current stage are done."""

    def describe(self, description: str) -> None:
        """New description of the current stage (its count goes on)."""

    def note(self, message: str) -> None:
        """A line printed at once."""


class _Callable(NullProgress):
    """A plain ``progress(message)``: told each stage's description and each note."""

    def __init__(self, function):
        self.function = function

    def stage(self, description: str, total: int | None = None, unit: str = "step") -> None:
        self.function(description if total is None else f"{description}: {total} {unit}s")

    def describe(self, description: str) -> None:
        self.function(description)

    def note(self, message: str) -> None:
        self.function(message)


class Progress(NullProgress):
    """A tqdm bar per stage on a terminal, else a summary line every ``every`` seconds (module docstring).

    Parameters
    ----------
    name : str
        The command (``modes``), at the start of each summary line.
    bar : bool
        Draw a tqdm bar when ``stream`` is a terminal (False: summary lines only).
    stream : file, optional
        Default ``sys.stderr``.
    every : float, optional
        Seconds between summary lines (default :data:`SUMMARY_EVERY`).
    clock : callable
        ``clock()`` in seconds (a fake one in tests).
    timer : bool
        Start the daemon thread that prints the summary lines (tests call :meth:`tick` instead).
    """

    def __init__(self, name: str, bar: bool = True, stream=None, every: float | None = None,
                 clock=time.monotonic, timer: bool = True):
        self.name = name
        self.stream = sys.stderr if stream is None else stream
        self.every = float(SUMMARY_EVERY if every is None else every)
        self.clock = clock
        self.started = self.last = clock()
        self.description, self.total, self.unit, self.done = "starting", None, "step", 0
        self.lock = threading.Lock()
        self.tqdm = None
        if bar and hasattr(self.stream, "isatty") and self.stream.isatty():
            from tqdm import tqdm

            self.tqdm = tqdm
        self.bar = None
        self._stop = threading.Event()
        self._thread = None
        if self.tqdm is None and timer:
            self._thread = threading.Thread(target=self._run, name=f"symkin-{name}-progress", daemon=True)
            self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(min(self.every, 1.0) if self.every > 0 else 0.05):
            self.tick()

    def summary(self) -> str:
        """``symkin NAME: <stage> k/total units, <elapsed> elapsed``."""
        with self.lock:
            count = (f" {self.done}/{self.total} {self.unit}s" if self.total is not None
                     else f" ({self.done} {self.unit}s)" if self.done else "")
            elapsed = self.clock() - self.started
            return f"symkin {self.name}: {self.description}{count}, {format_seconds(elapsed)} elapsed"

    def tick(self) -> bool:
        """Print the summary line when ``every`` seconds have passed since the last one; whether it did."""
        if self.tqdm is not None:
            return False
        now = self.clock()
        if now - self.last < self.every:
            return False
        self.last = now
        self._print(self.summary())
        return True

    def _print(self, line: str) -> None:
        if self.bar is not None:
            self.bar.write(line, file=self.stream)
        else:
            print(line, file=self.stream, flush=True)

    def stage(self, description: str, total: int | None = None, unit: str = "step") -> None:
        with self.lock:
            self.description, self.total, self.unit, self.done = description, total, unit, 0
        if self.tqdm is not None:
            if self.bar is not None:
                self.bar.close()
            self.bar = self.tqdm(desc=description, total=total, unit=f" {unit}", file=self.stream, leave=False)

    def _bar(self):
        """The current tqdm bar (made for a step counter when no stage was started), or None."""
        if self.tqdm is not None and self.bar is None:
            self.bar = self.tqdm(desc=self.description, total=self.total, unit=f" {self.unit}", file=self.stream,
                                 leave=False)
        return self.bar

    def advance(self, n: int = 1) -> None:
        with self.lock:
            self.done += int(n)
        if self._bar() is not None:
            self.bar.update(int(n))

    def describe(self, description: str) -> None:
        with self.lock:
            self.description = description
        if self._bar() is not None:
            self.bar.set_description_str(description, refresh=False)

    def note(self, message: str) -> None:
        self._print(f"symkin {self.name}: {message}")

    def __call__(self, message: str) -> None:
        """One more step, described by ``message`` (the callable form: ``symkin singularities`` counts its
        homotopies and traces so)."""
        self.describe(message)
        self.advance(1)

    def close(self) -> None:
        """Stop the timer and close the bar."""
        self._stop.set()
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def as_progress(progress) -> NullProgress:
    """``progress`` as an object with ``stage``, ``advance`` and ``note`` (module docstring)."""
    if progress is None:
        return NullProgress()
    if isinstance(progress, NullProgress):
        return progress
    if callable(progress):
        return _Callable(progress)
    raise TypeError(f"progress must be a Progress, a callable or None, not {type(progress).__name__}")
