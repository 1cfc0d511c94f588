"""Time limits of symbolic derivations.

``time_limit=`` of :func:`~symkin.symbolic.conditions.im_condition` and
:func:`~symkin.symbolic.conditions.dkp_condition` sets a deadline for the current context
(:func:`with_time_limit`); the long loops of a derivation call :func:`check_deadline`, which
raises :class:`DerivationTimeout` once it has passed (the loci of
:mod:`symkin.symbolic.loci` raise the same exception).
"""
from __future__ import annotations

import contextvars
import time

from symkin.errors import SymkinError

__all__ = ["DerivationTimeout", "check_deadline", "with_time_limit"]

_DEADLINE: contextvars.ContextVar = contextvars.ContextVar("symkin_symbolic_deadline", default=None)


class DerivationTimeout(SymkinError):
    """A derivation ran past its time limit (``time_limit=`` of the condition functions)."""


def check_deadline() -> None:
    """Raise when the current derivation has run past its time limit.

    Raises
    ------
    DerivationTimeout
        When a deadline set by :func:`with_time_limit` has passed.
    """
    deadline = _DEADLINE.get()
    if deadline is not None and time.perf_counter() > deadline[0]:
        raise DerivationTimeout(f"{deadline[1]}: not derived within the time limit of {deadline[2]:g} s "
                                "(this mechanism is large for an exact symbolic derivation)")


def with_time_limit(kind: str, time_limit: float | None, fn):
    """Call ``fn()`` with a deadline ``time_limit`` seconds from now.

    Parameters
    ----------
    kind : str
        What is derived, named in the message of :class:`DerivationTimeout`, e.g. ``"IM"``.
    time_limit : float or None
        Seconds allowed; None calls ``fn`` without a limit.
    fn : callable
        The derivation, without arguments.

    Returns
    -------
    object
        What ``fn()`` returns.
    """
    if time_limit is None:
        return fn()
    token = _DEADLINE.set((time.perf_counter() + float(time_limit), kind, float(time_limit)))
    try:
        return fn()
    finally:
        _DEADLINE.reset(token)
