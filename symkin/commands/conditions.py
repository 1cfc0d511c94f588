"""``symkin conditions MODEL [--coordinates angles|nodes] [--latex]``: singularity conditions.

Derives, for the mechanism of a model file, the IM condition (the characteristic-polynomial
coefficient of the geometric matrix that vanishes exactly where ``L > F``) and the DKP
conditions of the declared inputs and outputs (determinants of the velocity equation
augmented with their rows), each factored with the trivial factors (constants, lengths)
separated and every geometric factor in a readable form.
"""
from __future__ import annotations

import json

from symkin.commands import Output
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "conditions"
HELP = ("derive the IM, DKP-input and DKP-output singularity conditions of a model symbolically "
        "(factored, geometric factors in readable form)")


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json)")
    p.add_argument("--coordinates", choices=("angles", "nodes"), default=None,
                   help="configuration variables: link angles theta_<link> (planar only; the default "
                        "for planar models) or node coordinates x_<node>, y_<node> (the default in space)")
    p.add_argument("--design-symbols", action="store_true",
                   help="keep lengths (and internal angles of bodies) as symbols l_<link>, beta_<body>_<i>_<j>")
    p.add_argument("--latex", action="store_true", help="print each condition in LaTeX")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _values_line(sm) -> str:
    parts = [f"{s.name} = {v:.6g}" for s, v in sm.values.items()]
    return "  " + ", ".join(parts)


def run(args) -> Output:
    from symkin.symbolic import symbolic_model

    mech = read_model(args.model)
    coordinates = args.coordinates or ("angles" if mech.dim == 2 else "nodes")
    if coordinates == "angles" and mech.dim != 2:
        raise SymkinError(f"{args.model}: angle coordinates are for planar models; use --coordinates nodes")
    sm = symbolic_model(mech, coordinates=coordinates, design_symbols=args.design_symbols)
    conditions = [sm.im_condition()]
    skipped = []
    for which, params in (("input", mech.inputs), ("output", mech.outputs)):
        if params:
            conditions.append(sm.dkp_condition(which))
        else:
            skipped.append(f"DKP-{which}: the model declares no {which}s")
    if args.json:
        data = {"model": str(args.model), "name": mech.name, "coordinates": coordinates,
                "design_symbols": bool(args.design_symbols),
                "symbols": [s.name for s in sm.symbols],
                "values": {s.name: v for s, v in sm.values.items()},
                "conditions": [dict(c.as_dict(), value_at_model=c.evaluate()) for c in conditions],
                "skipped": skipped}
        return Output(json.dumps(data, indent=2))
    lines = [f"conditions of {mech.name} ({args.model})",
             f"coordinates: {coordinates} ({', '.join(s.name for s in sm.config_symbols)})"]
    if sm.design_symbols:
        lines.append(f"design symbols: {', '.join(s.name for s in sm.design_symbols)}")
    lines.append(f"mobility F = {mech.mobility_value}; the model's configuration:")
    lines.append(_values_line(sm))
    for c in conditions:
        lines.append("")
        if args.latex:
            lines.append(c.latex())
        else:
            lines.append(str(c))
        lines.append(f"  value at the model's configuration: {c.evaluate():.6g}")
    for text in skipped:
        lines.append("")
        lines.append(text)
    return Output("\n".join(lines))


__all__ = ["NAME", "HELP", "add_arguments", "run"]
