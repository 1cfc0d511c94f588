"""Whether the plots extra (matplotlib) is installed: checked before long work starts."""
from __future__ import annotations

import importlib.util

from symkin.errors import SymkinError

__all__ = ["require_matplotlib"]


def require_matplotlib(option: str = "--plot") -> None:
    """Raise a :class:`SymkinError` naming the plots extra when matplotlib cannot be imported.

    Commands call it before they compute, so a user does not wait for a path or a map that
    cannot be drawn.

    >>> require_matplotlib()  # matplotlib is installed with the test extra
    """
    try:
        found = importlib.util.find_spec("matplotlib") is not None
    except ValueError:  # sys.modules["matplotlib"] is None: not importable
        found = False
    if not found:
        raise SymkinError(f'{option} needs matplotlib, from the plots extra: pip install -e ".[plots]" '
                          '(or pip install "symkin[plots]")')
