"""``python -m symkin`` runs the command line."""
from symkin.cli import main

raise SystemExit(main())
