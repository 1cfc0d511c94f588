"""``symkin map MODEL --x LABEL=LO:HI --y LABEL=LO:HI``: a workspace or joint-space singularity map."""
from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

from symkin.commands import Output, in_file, write_output
from symkin.commands.analyze import tolerance
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "map"
HELP = ("map the singularity indicators of every working mode over two position coordinates "
        "(workspace or joint space, paper §VI)")


def _count(text: str) -> int:
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    return value


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json)")
    p.add_argument("--x", required=True, metavar="LABEL=LO:HI",
                   help="first axis: a coordinate label (velocity:P.x, rotation:L, slide:S) and its range; "
                        "absolute values (angles in --unit)")
    p.add_argument("--y", required=True, metavar="LABEL=LO:HI", help="second axis (as --x)")
    p.add_argument("--n", type=_count, default=201, help="grid points per axis (default 201, at least 2)")
    p.add_argument("--hold", action="append", default=[], metavar="LABEL[=VALUE]",
                   help="a held coordinate (F > 2 needs F - 2 of them); default value: the model's")
    p.add_argument("--seed", action="append", default=[], metavar="MODEL",
                   help="a model file of the same mechanism in another working mode (repeatable)")
    p.add_argument("--modes", choices=("model", "all"), default="model",
                   help="model: the model's configuration and each --seed; all: every real solution at the "
                        "reference point (needs the extra symkin[global])")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="unit of angle axes and hold values (default deg; lengths in model units)")
    p.add_argument("--tol", type=tolerance, default=None, help="relative rank tolerance (default 1e-8)")
    p.add_argument("--no-refine", action="store_true", help="grid only: no refinement to exact curves")
    p.add_argument("--json", metavar="FILE|-", default=None, help="write the map as JSON to FILE, or - for stdout")
    p.add_argument("--npz", metavar="FILE", default=None, help="write the grid arrays and curves to FILE (.npz)")
    p.add_argument("--plot", metavar="FILE.png", default=None, help="write a figure of the map")
    par = p.add_mutually_exclusive_group()
    par.add_argument("--workers", type=_count, default=None, help="run on a local Dask cluster of N workers")
    par.add_argument("--scheduler", metavar="ADDRESS", default=None, help="run on an existing Dask scheduler")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on the terminal")


def _progress(enabled: bool, total: int):
    if not enabled or not sys.stderr.isatty() or importlib.util.find_spec("tqdm") is None:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc="map", unit="pt", file=sys.stderr, leave=False)


def _text(m) -> str:
    ax, ay = m.axes
    lines = [f"{m.model}: map over {ax.label} = {ax.lo:g}..{ax.hi:g} ({ax.n} points) × "
             f"{ay.label} = {ay.lo:g}..{ay.hi:g} ({ay.n} points)"
             + (f", holding {', '.join(f'{lab} = {v:.6g}' for lab, v in m.hold)}" if m.hold else ""), ""]
    counts = m.counts()
    for mode in m.modes:
        c = counts[str(mode.id)]
        lines.append(f"mode {mode.id} (seed {mode.seed}): assembled at {100 * mode.fraction:.1f}% of the grid"
                     + (f", {int(mode.rejected.sum())} point(s) rejected by the jump checks"
                        if mode.rejected.any() else "")
                     + (f", {len(mode.branch_changes)} branch change(s)" if mode.branch_changes else ""))
        lines.append("   curves/points: " + ", ".join(f"{k} {v}" for k, v in c.items()))
        if mode.note:
            lines.append(f"   {mode.note}")
    if not m.assembled_anywhere:
        lines += ["", "Nothing assembles in this box: no mode reaches any grid point."]
    if m.notes:
        lines += [""] + [f"note: {n}" for n in m.notes]
    return "\n".join(lines)


def _plot(m, target: str, mech) -> str:
    from symkin.plots.maps import save_map_figure

    return f"figure written to {save_map_figure(m, target, mechanism=mech)}"


def run(args) -> Output:
    from symkin.workspace.maps import workspace_map
    from symkin.workspace.parallel import dask_client

    mech = read_model(args.model)
    if args.plot:
        from symkin.plots.extra import require_matplotlib

        require_matplotlib("--plot")  # before the map is computed
    if args.n < 2:
        raise SymkinError(f"{args.model}: --n {args.n}: the number of grid points per axis must be at least 2")
    bar = _progress(not args.no_progress and args.json != "-", args.n * args.n * (1 + len(args.seed)))
    try:
        # --workers N: a local Dask cluster for this run, closed afterwards; --scheduler: an existing one
        with dask_client(workers=args.workers, scheduler=args.scheduler) as client:
            m = workspace_map(mech, x=args.x, y=args.y, n=args.n, hold=tuple(args.hold), seeds=tuple(args.seed),
                              modes=args.modes, refine=not args.no_refine, unit=args.unit, tol=args.tol,
                              progress=bar.update if bar is not None else None, client=client)
    except SymkinError as exc:
        raise in_file(exc, args.model)
    finally:
        if bar is not None:
            bar.close()
    notes = []
    if args.npz:
        notes.append(f"arrays written to {write_output(args.npz, m.save)}")
    if args.plot:
        notes.append(_plot(m, args.plot, mech))
    if args.json is not None:
        text = json.dumps(m.to_dict(), indent=1)
        if args.json == "-":
            return Output(text, message="\n".join(notes))
        target = write_output(args.json, lambda tmp: tmp.write_text(text + "\n"))
        notes.append(f"map written to {target}")
    return Output(_text(m), message="\n".join(notes))
