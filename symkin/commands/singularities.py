"""``symkin singularities MODEL [--json] [--plot FILE.png]``: every circuit and singular configuration of a 1-DOF mechanism."""
from __future__ import annotations

import json
import warnings

from symkin.commands import Output, format_outputs
from symkin.commands.analyze import tolerance
from symkin.commands.outputs import check_figure_file, save_output
from symkin.commands import in_file
from symkin.errors import SymkinError
from symkin.kinds import Kind
from symkin.model.model_file import read_model

NAME = "singularities"
HELP = ("every circuit of a 1-DOF mechanism and every DKP-input, DKP-output, IM and LIM configuration on it "
        "(traced circuits, cross-checked by homotopy); needs the extra symkin[global]")


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME of a 1-DOF mechanism")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="unit of the reported angles (default deg; lengths are in model units)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", default=None,
                   help="write the circuits in input-output space with every singular configuration numbered")
    p.add_argument("--max-paths", type=int, default=None,
                   help="do not solve a square DKP system whose homotopy would track more paths than this "
                        "(default 600): its configurations are then not cross-checked, and the seeds are placed "
                        "in rounds between the traced critical values")
    p.add_argument("--samples", type=_values, default=None, metavar="V,V,...",
                   help="input values (in --unit, from the model's configuration) at which all assembly modes "
                        "seed the traces, instead of the default ones (faster than the rounds; a circuit whose "
                        "input range holds none of them and no solution of a square system is missed)")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar on the terminal: a one-line summary on stderr every 30 s instead "
                        "(also without a terminal)")
    p.add_argument("--tol", type=tolerance, default=None,
                   help="relative rank tolerance of the events and their classification (default 1e-8)")


def _values(text: str) -> list[float]:
    """argparse type for ``--samples``: comma-separated numbers."""
    import argparse
    import math

    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a comma-separated list of numbers: {text!r}") from None
    if not values or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"need at least one finite number, got {text!r}")
    return values


def _text(result) -> str:
    from symkin.paths.trace import CoordinateValues

    mech = result.mechanism
    lines = [f"{mech.name}: {len(result.circuits)} circuit(s), {len(result.singularities)} singular "
             f"configuration(s), input {result.input} ({result.seconds:.1f} s).", ""]
    for c in result.circuits:
        what = "the input turns fully" if c.full_turn else "the input oscillates"
        lines.append(f"circuit {c.index}: {len(c.branches)} traced branch(es), {what}"
                     + ("" if c.closed else " (NOT closed)"))
    lines.append("")
    labels = [result.input] + ([] if result.output is None else [result.output])
    values = CoordinateValues(mech, labels)
    kinds = {c.label: c.kind for c in values.coordinates}
    for k, s in enumerate(result.singularities, 1):
        at = format_outputs(values(s.configuration, result.unit), kinds, result.unit)
        locked = f", locked links: {', '.join(s.locked_links)}" if s.locked_links else ""
        lines.append(f"{k}. circuit {s.circuit}: {', '.join(s.types) or 'none'} (L = {s.dof}{locked}) at {at}")
        for n in mech.free_nodes:
            lines.append(f"   {n} = ({', '.join(f'{c:.10g}' for c in s.configuration[n])})")
    lines.append("")
    for ch in result.checks:
        what = (f"{ch.name}/IM configuration(s)" if ch.kind != Kind.LIM
                else f"configuration(s) where {ch.link} is locked, or IM")
        if ch.skipped:
            lines.append(f"cross-check {ch.name}: NOT solved ({ch.skipped}); {ch.traced} traced {what}, "
                         "not cross-checked")
            continue
        how = (f"exact, msolve, instead of a homotopy of {ch.paths} paths" if ch.solver == "msolve"
               else f"{ch.paths} paths")
        lines.append(f"cross-check {ch.name}: {ch.homotopy} real solution(s) of closure + det = 0 "
                     f"({how}), {ch.traced} traced {what}: " + ("agree" if ch.agree else "DISAGREE"))
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines)


def run(args) -> Output:
    from symkin.solutions.circuits import SingularitiesWarning, singularities

    mech = read_model(args.model)
    if args.plot:
        check_figure_file(args.plot, "--plot")  # before the circuits are computed
    try:
        options = {} if args.max_paths is None else {"max_paths": args.max_paths}
        if args.samples is not None:
            options["samples"] = args.samples
        from symkin.solutions.progress import Progress

        bar = Progress("singularities", bar=not args.no_progress)
        options["progress"] = bar
        try:
            with warnings.catch_warnings():
                # the result carries every warning (the text's "warning:" lines, the JSON's "warnings")
                warnings.simplefilter("ignore", SingularitiesWarning)
                result = singularities(mech, tol=args.tol, unit=args.unit, **options)
        finally:
            bar.close()
    except SymkinError as exc:
        raise in_file(exc, args.model)
    message, code = "", 0
    if args.plot:
        from symkin.plots.circuits import save_circuits_figure

        saved = save_output(args.plot, lambda tmp: save_circuits_figure(result, tmp), "--plot", figure=True)
        message = saved.problem or f"wrote {saved.path}"
        code = 1 if saved.problem else 0
    if args.json:
        return Output(json.dumps(result.to_dict(), indent=1), code=code, message=message)
    return Output(_text(result), code=code, message=message)
