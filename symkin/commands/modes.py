"""``symkin modes MODEL --at LABEL=VALUE [--at ...] [--unit deg|rad] [--json]``: every real solution of the position problem."""
from __future__ import annotations

import json

from symkin.commands import Output, format_outputs
from symkin.commands.analyze import tolerance
from symkin.commands import in_file
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "modes"
HELP = ("every real configuration with given input or output values (assembly / working modes), by "
        "homotopy continuation; needs the extra symkin[global]")


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--at", metavar="LABEL=VALUE", action="append", default=[],
                   help="a prescribed value, measured from the model's configuration, e.g. rotation:crank=30 "
                        "(repeat: exactly F values)")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="unit of angle values (default deg; lengths are in model units)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--analyze", action="store_true", help="classify every solution (symkin analyze)")
    p.add_argument("--max-paths", type=int, default=5000,
                   help="refuse a homotopy of more paths than this (default 5000)")
    p.add_argument("--method", choices=("auto", "parameter", "total-degree"), default="auto",
                   help="parameter: track only the solutions of the model's parameter homotopy from generic "
                        "values (made once by monodromy and cached with the model's artefacts; falls back to "
                        "total-degree when it does not apply); total-degree: Bertini 2's total-degree "
                        "homotopy (the extra symkin[global]); auto (default): parameter when its start solutions "
                        "are cached or the total-degree homotopy would track more than 1024 paths")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar on the terminal: a one-line summary on stderr every 30 s instead "
                        "(also without a terminal)")
    p.add_argument("--tol", type=tolerance, default=None,
                   help="relative rank tolerance of the DKP labels (default 1e-8)")


def parse_values(items: list[str]) -> dict[str, float]:
    """``["rotation:crank=30", ...]`` → ``{"rotation:crank": 30.0}``; a clear error for a bad item."""
    out: dict[str, float] = {}
    for item in items:
        label, sep, text = item.rpartition("=")
        if not sep or not label:
            raise SymkinError(f"--at {item!r}: expected LABEL=VALUE, e.g. rotation:crank=30")
        try:
            value = float(text)
        except ValueError:
            raise SymkinError(f"--at {item!r}: {text!r} is not a number") from None
        if label in out:
            raise SymkinError(f"--at {label}: given twice")
        out[label] = value
    return out


def _measures(result):
    """The measures of the prescribed coordinates and of the model's outputs (built once per result:
    0.4 s each on a Gough–Stewart)."""
    from symkin.paths.trace import CoordinateValues

    prescribed = CoordinateValues(result.mechanism, list(result.values))
    outputs = CoordinateValues(result.mechanism)
    return prescribed, outputs, {c.label: c.kind for c in prescribed.coordinates + outputs.coordinates}


def _values(result, solution, measures=None) -> dict:
    """The prescribed coordinates and the model's outputs at a solution, relative and absolute.

    ``{"values": {label: {"relative", "absolute"}}, "outputs": {...}, "kinds": {label: kind}}``
    in the result's unit (the convention of :func:`symkin.paths.trace.relative_angle`);
    ``measures`` from :func:`_measures` (made here when not given).
    """
    prescribed, outputs, kinds = measures or _measures(result)
    return {"values": prescribed(solution.configuration, result.unit),
            "outputs": outputs(solution.configuration, result.unit), "kinds": kinds}


def _json(result) -> dict:
    """``result.to_dict()`` with each solution's ``values`` and ``outputs`` (relative and absolute)."""
    data = result.to_dict()
    measures = _measures(result) if result.solutions else None
    for item, s in zip(data["solutions"], result.solutions):
        at = _values(result, s, measures)
        item["values"], item["outputs"] = at["values"], at["outputs"]
    return data


def _text(result) -> str:
    mech = result.mechanism
    lines = [f"{mech.name}: {len(result.solutions)} real solution(s) at "
             + ", ".join(f"{k} = {v:g}" for k, v in result.values.items())
             + f" ({result.unit} for angles); {result.complex} complex, {result.near_real} near-real, "
               f"{result.at_infinity} at infinity, {result.rejected} rejected, {result.failed} failed; "
               f"{result.paths} paths ({result.method}) tracked in {result.track_seconds:.2f} s "
               f"({result.seconds:.2f} s in all).", ""]
    measures = _measures(result) if result.solutions else None
    for k, s in enumerate(result.solutions, 1):
        signs = ", ".join(f"{key} {'' if v is None else ('+' if v > 0 else '-' if v < 0 else '0')}"
                          f"{'undefined' if v is None else ''}" for key, v in s.signs.items())
        kinds = f"; types: {', '.join(s.types)}" if s.types else ""
        lines.append(f"{k}. signs: {signs}{kinds}; residual {s.residual:.1e}")
        at = _values(result, s, measures)
        for what, key in (("at", "values"), ("outputs:", "outputs")):
            if at[key]:
                lines.append(f"   {what} {format_outputs(at[key], at['kinds'], result.unit)}")
        for n in mech.free_nodes:
            lines.append(f"   {n} = ({', '.join(f'{c:.10g}' for c in s.configuration[n])})")
        if s.analysis is not None:
            lines.append(f"   analysis: L = {s.analysis.dof}, types: {', '.join(s.analysis.types) or 'none'}")
    return "\n".join(lines)


def run(args) -> Output:
    from symkin.solutions import solve_all

    mech = read_model(args.model)
    values = parse_values(args.at)
    from symkin.solutions.progress import Progress

    progress = Progress("modes", bar=not args.no_progress)
    try:
        result = solve_all(mech, values, unit=args.unit, tol=args.tol, analyze=args.analyze,
                           max_paths=args.max_paths, method=args.method, progress=progress)
    except SymkinError as exc:
        raise in_file(exc, args.model)
    finally:
        progress.close()
    if args.json:
        return Output(json.dumps(_json(result), indent=1))
    return Output(_text(result))
