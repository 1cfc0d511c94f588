"""``symkin analyze MODEL [--json] [--tol T]``: classify the configuration in a model file."""
from __future__ import annotations

import json

from symkin.commands import Output
from symkin.model.model_file import read_model

NAME = "analyze"
HELP = "analyse the configuration of a model file (DOF, IM, DKP, LIM, constraint singularities)"


def tolerance(text: str) -> float:
    """argparse type for ``--tol``: a number strictly between 0 and 1."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(f"must be between 0 and 1 (relative), got {text}")
    return value


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of the text report")
    p.add_argument("--tol", type=tolerance, default=None,
                   help="relative rank tolerance on singular values (default 1e-8; see README)")


def run(args) -> Output:
    from symkin.analysis.classification import analyze
    from symkin.report import render_text

    mech = read_model(args.model)
    result = analyze(mech, tol=args.tol)
    if args.json:
        return Output(json.dumps(result.to_dict(), indent=2))
    return Output(render_text(result))
