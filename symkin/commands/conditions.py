"""``symkin conditions MODEL [--coordinates angles|nodes] [--latex]``: singularity conditions.

With ``--in LABEL_X,LABEL_Y [--hold LABEL[=VALUE] ...]`` it gives instead the singularity *loci*:
every other coordinate eliminated, each locus a factored polynomial in the two variables
(``x_P``, ``y_P``; ``t_L`` = tan(θ_L/2) for a rotation, ``s_S`` for a slide), see
:func:`symkin.symbolic.loci.implicit_loci`.  ``--json`` prints ``{"variables": [...], "loci":
[{"kind", "factors": [{"polynomial", "degree", "meaning"}]}]}``.

Derives, for the mechanism of a model file, the IM condition (the characteristic-polynomial
coefficient of the geometric matrix that vanishes exactly where ``L > F``) and the DKP
conditions of the declared inputs and outputs (determinants of the velocity equation
augmented with their rows), each factored with the trivial factors (constants, lengths)
separated and every geometric factor in a readable form.
"""
from __future__ import annotations

import json

from symkin.commands import Output, check_holds, non_negative_number
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "conditions"
HELP = ("derive the IM, DKP-input and DKP-output singularity conditions of a model symbolically "
        "(factored, geometric factors in readable form)")


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--coordinates", choices=("angles", "nodes"), default=None,
                   help="configuration variables: link angles theta_<link> (planar only; the default "
                        "for planar models) or node coordinates x_<node>, y_<node> (the default in space)")
    p.add_argument("--design-symbols", action="store_true",
                   help="keep lengths (and internal angles of bodies) as symbols l_<link>, beta_<body>_<i>_<j>")
    p.add_argument("--latex", action="store_true", help="print each condition in LaTeX")
    p.add_argument("--time-limit", type=non_negative_number, default=120.0, metavar="SECONDS",
                   help="give up on a condition after this many seconds (default 120; 0 = no limit)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--in", dest="variables", metavar="LABEL_X,LABEL_Y", default=None,
                   help="give the singularity loci as implicit polynomials in these two coordinates "
                        "(labels as symkin map --x takes them, e.g. velocity:P.x,velocity:P.y)")
    p.add_argument("--hold", action="append", default=[], metavar="LABEL[=VALUE]",
                   help="with --in: a held coordinate (F - 2 of them; default value: the model's), as symkin "
                        "map --hold takes them; a spatial link's orientation as rotation:<link>[x], [y], [z]")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="with --in: unit of held angle values (default deg)")


def _values_line(sm) -> str:
    parts = [f"{s.name} = {v:.6g}" for s, v in sm.values.items()]
    return "  " + ", ".join(parts)


def run(args) -> Output:
    from symkin.symbolic import symbolic_model

    mech = read_model(args.model)
    if args.variables is not None:
        return _run_loci(args, mech)
    if args.hold:
        raise SymkinError("--hold needs --in LABEL_X,LABEL_Y (the held coordinates of a locus)")
    coordinates = args.coordinates or ("angles" if mech.dim == 2 else "nodes")
    if coordinates == "angles" and mech.dim != 2:
        raise SymkinError(f"{args.model}: angle coordinates are for planar models; use --coordinates nodes")
    sm = symbolic_model(mech, coordinates=coordinates, design_symbols=args.design_symbols)
    limit = args.time_limit if args.time_limit and args.time_limit > 0 else None
    conditions, skipped = [], []
    try:
        conditions.append(sm.im_condition(time_limit=limit))
    except SymkinError as exc:  # too large or too long: report it, go on with the others
        skipped.append(str(exc))
    for which, params in (("input", mech.inputs), ("output", mech.outputs)):
        if not params:
            skipped.append(f"DKP-{which}: the model declares no {which}s")
            continue
        try:
            conditions.append(sm.dkp_condition(which, time_limit=limit))
        except SymkinError as exc:
            skipped.append(str(exc))
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
    failed = len(conditions) < 1 + sum(1 for p in (mech.inputs, mech.outputs) if p)
    return Output("\n".join(lines), code=1 if failed else 0,
                  message="some conditions were not derived (see above)" if failed else "")


def _run_loci(args, mech) -> Output:
    from symkin.symbolic.loci import implicit_loci

    check_holds(args.hold)
    labels = [t.strip() for t in str(args.variables).split(",") if t.strip()]
    if len(labels) != 2:
        raise SymkinError(f"{args.model}: --in needs two labels LABEL_X,LABEL_Y, got {args.variables!r}")
    limit = args.time_limit if args.time_limit and args.time_limit > 0 else None
    try:
        loci = implicit_loci(mech, tuple(labels), hold=tuple(args.hold), time_limit=limit, unit=args.unit)
    except SymkinError as exc:
        raise type(exc)(f"{args.model}: {exc}") if type(exc) is SymkinError else exc
    if args.json:
        text = json.dumps(dict(loci.as_dict(), model=str(args.model), name=mech.name), indent=2)
    elif args.latex:
        text = loci.latex()
    else:
        text = str(loci)
    failed = bool(loci.skipped)
    return Output(text, code=1 if failed else 0,
                  message="some loci were not derived (see above)" if failed else "")


__all__ = ["NAME", "HELP", "add_arguments", "run"]
