"""``python -m symkin`` runs the command line (a Ctrl-C while it starts exits 130: see ``symkin/__init__.py``)."""
from symkin.startup import exit_on_early_interrupt

exit_on_early_interrupt()  # before the command line's modules load

from symkin.cli import main  # noqa: E402

raise SystemExit(main())
