"""``symkin path MODEL --input LABEL --from A --to B``: trace a path and locate its singular configurations."""
from __future__ import annotations

import csv
import io
import json
import math
import sys
from dataclasses import replace

from symkin.commands import (LENGTH_UNITS, Output, finite_number, format_coordinate, format_outputs, in_file,
                             positive_number)
from symkin.commands.outputs import check_figure_file, check_output_file, save_output
from symkin.commands.analyze import tolerance
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "path"
HELP = ("move a mechanism along one input (finite displacements), locate every singular configuration "
        "on the way, and classify it")


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--input", default=None,
                   help="driving input label, e.g. rotation:crank (default: the model's first input); "
                        "with F > 1 the model's other inputs are held at their values")
    p.add_argument("--from", dest="start", type=finite_number, default=0.0,
                   help="start value, measured from the model's configuration (default 0)")
    p.add_argument("--to", dest="stop", type=finite_number, required=True, help="end value (same unit)")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="unit of --from/--to for angle inputs (default deg; lengths are in model units)")
    p.add_argument("--steps", type=int, default=None,
                   help="at least this many points over the range (bounds the input change per step; "
                        "1 to 10000: the tracer stops after 20000 steps)")
    p.add_argument("--max-arclength", type=positive_number, default=None,
                   help="stop after this arclength, in units of the model's length scale (default 60)")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true", help="print one JSON object (points and events)")
    out.add_argument("--csv", metavar="FILE", default=None,
                     help="write the points (input, indicators, coordinates) as CSV to FILE")
    p.add_argument("--plot", metavar="FILE.png", default=None,
                   help="write a figure of the indicators along the path and the node traces")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on the terminal")
    p.add_argument("--tol", type=tolerance, default=None,
                   help="relative rank tolerance for the events and their classification (default 1e-8)")


def _progress_bar(enabled: bool):
    """A tqdm bar on stderr when it is a terminal (never mixed into stdout / --json)."""
    if not enabled or not sys.stderr.isatty():
        return None, None
    try:
        from tqdm import tqdm
    except ImportError:
        return None, None
    bar = tqdm(total=1000, desc="tracing", unit="‰", file=sys.stderr, leave=False)

    def update(fraction: float) -> None:
        target = int(1000 * fraction)
        if target > bar.n:
            bar.update(target - bar.n)
    return bar, update


def _text(path, unit: str) -> str:
    from symkin.paths.trace import CoordinateValues

    u = unit if path.kind == "angle" else LENGTH_UNITS
    outputs = CoordinateValues(path.mechanism)
    kinds = {c.label: c.kind for c in outputs.coordinates}
    lines = [f"{path.mechanism.name}: {path.drive} traced, {len(path.points)} points; "
             f"stopped: {path.message}.", ""]
    sing = path.singular_events()
    if not sing:
        lines.append("No singular configuration on the way.")
    for k, e in enumerate(sing, 1):
        a = e.analysis
        v = path.values(e, unit)
        along = f", {v['input']:.10g} {u} along the path" if v["input"] != v["relative"] else ""
        lines.append(f"{k}. {e.kind} at {format_coordinate(path.drive, v['relative'], v['absolute'], u)}{along} "
                     f"(found by {', '.join(e.tests)})")
        if kinds:
            lines.append(f"   outputs: {format_outputs(outputs(e.coordinates, unit), kinds, unit)}")
        if e.reason:
            lines.append(f"   {e.reason}")
        if e.confirmed is False:
            lines.append("   not confirmed: at the located configuration the classifier does not find this "
                         "singularity at its tolerance (see the types below)")
        if a is not None:
            lines.append(f"   types: {', '.join(a.types) or 'none'}; L = {a.dof}, F = {a.mobility}"
                         + (f"; locked links: {', '.join(a.locked_links)}" if a.locked_links else ""))
            for r in a.input_relations:
                lines.append(f"   input relation (r = {r.r}): {r}")
            for r in a.output_relations:
                lines.append(f"   output relation (r = {r.r}): {r}")
        if e.bifurcation is not None:
            lines.append(f"   branches: {e.bifurcation.status} — {e.bifurcation.message}")
    lines += ["", f"{path.residual_evaluations} residual evaluations."]
    return "\n".join(lines)


def _csv(path, unit: str) -> str:
    """The points as CSV: ``input`` (along the path), ``absolute`` ([0°, 360°)), ``s``, ``relative``
    ((−180°, 180°]), the indicators, each output (relative, and ``<label> absolute`` for a planar
    angle or a node's coordinate), then the node coordinates."""
    from symkin.paths.trace import CoordinateValues

    outputs = CoordinateValues(path.mechanism)
    keys = sorted({k for p in path.points for k in p.indicators})
    dim = path.mechanism.dim
    coords = [f"{c}_{n}" for n in path.node_names for c in "xyz"[:dim]]
    rows = [(path.values(p, unit), outputs(p.coordinates, unit)) for p in path.points]
    has_absolute = [label for label in outputs.labels if any(o[label]["absolute"] is not None for _, o in rows)]
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["input", "absolute", "s", "relative"] + keys + list(outputs.labels)
               + [f"{label} absolute" for label in has_absolute] + coords)
    for p, (v, o) in zip(path.points, rows):
        w.writerow([v["input"], "" if v["absolute"] is None else v["absolute"], p.s, v["relative"]]
                   + [p.indicators.get(k, "") for k in keys] + [o[label]["relative"] for label in outputs.labels]
                   + [o[label]["absolute"] for label in has_absolute] + list(p.coordinates.ravel()))
    return buf.getvalue()


def run(args) -> Output:
    from symkin.paths.trace import trace

    from symkin.curves.stepper import Settings

    mech = read_model(args.model)
    settings = Settings()
    most = settings.max_steps
    limit = most // 2  # room for the steps that are halved and retried
    if args.steps is not None and args.steps < 1:
        raise SymkinError(f"{args.model}: --steps must be a positive integer")
    if args.steps is not None and args.steps > limit:
        raise SymkinError(f"{args.model}: --steps {args.steps}: give 1 to {limit} (the tracer stops after "
                          f"{most} steps, so more points could not all be reached)")
    if not math.isfinite(args.stop - args.start):
        raise SymkinError(f"{args.model}: --from {args.start:g} --to {args.stop:g}: the range overflows; "
                          "give a range of finite width")
    if args.start == args.stop:
        raise SymkinError(f"{args.model}: --from and --to are equal: nothing to trace")
    if args.plot:
        check_figure_file(args.plot, "--plot")  # before the path is traced
    if args.csv:
        check_output_file(args.csv, "--csv")
    bar, update = _progress_bar(not args.no_progress and not args.json)
    try:
        path = trace(mech, input=args.input, start=args.start, stop=args.stop, unit=args.unit,
                     max_arclength=args.max_arclength, progress=update, steps=args.steps, tol=args.tol,
                     settings=settings)
    except SymkinError as exc:
        raise in_file(exc, args.model)
    finally:
        if bar is not None:
            bar.close()
    if path.stop_reason == "max_steps":
        path = replace(path, message=f"the step budget ran out: {most} accepted steps were taken before the input "
                                     "reached its target; give fewer --steps, or split --from/--to into shorter "
                                     "ranges")
    notes, code = [], 0
    if args.plot:
        from symkin.plots import save_path_figures

        saved = save_output(args.plot, lambda tmp: save_path_figures(path, tmp, unit=args.unit), "--plot", figure=True)
        notes.append(saved.problem or f"figure written to {saved.path}")
        code = 1 if saved.problem else code
    if args.csv:
        text = _csv(path, args.unit)
        saved = save_output(args.csv, lambda tmp: tmp.write_text(text), "--csv")
        notes.append(saved.problem or f"{len(path.points)} points written to {saved.path}")
        code = 1 if saved.problem else code
    if args.json:
        return Output(json.dumps(path.to_dict(args.unit), indent=1), code=code, message="\n".join(notes))
    return Output(_text(path, args.unit), code=code, message="\n".join(notes))
