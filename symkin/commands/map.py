"""``symkin map MODEL --x LABEL=LO:HI --y LABEL=LO:HI``: a workspace or joint-space singularity map."""
from __future__ import annotations

import importlib.util
import json
import sys

from symkin.commands import Output, check_holds, in_file
from symkin.commands.outputs import check_figure_file, check_output_file, save_output
from symkin.commands.analyze import tolerance
from symkin.errors import SymkinError
from symkin.model.model_file import CATALOGUE_PREFIX, read_model

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
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--x", required=True, metavar="LABEL=LO:HI",
                   help="first axis: a coordinate label (velocity:P.x, rotation:L, slide:S) and its range; "
                        "absolute values (angles in --unit)")
    p.add_argument("--y", required=True, metavar="LABEL=LO:HI", help="second axis (as --x)")
    p.add_argument("--n", type=_count, default=201, help="grid points per axis (default 201, at least 2)")
    p.add_argument("--hold", action="append", default=[], metavar="LABEL[=VALUE]",
                   help="a held coordinate (F > 2 needs F - 2 of them); default value: the model's")
    p.add_argument("--seed", action="append", default=[], metavar="MODEL",
                   help="a model file (or catalogue:NAME) of the same mechanism in another working mode (repeatable)")
    p.add_argument("--modes", choices=("model", "all"), default="model",
                   help="model: the model's configuration and each --seed; all: every real solution at the "
                        "reference point (needs the extra symkin[global])")
    p.add_argument("--unit", choices=("deg", "rad"), default="deg",
                   help="unit of angle axes and hold values (default deg; lengths in model units)")
    p.add_argument("--tol", type=tolerance, default=None, help="relative rank tolerance (default 1e-8)")
    p.add_argument("--no-refine", action="store_true", help="grid only: no refinement to exact curves")
    p.add_argument("--json", metavar="FILE|-", default=None, help="write the map as JSON to FILE, or - for stdout")
    p.add_argument("--npz", metavar="FILE", default=None, help="write the grid arrays and curves to FILE (.npz)")
    p.add_argument("--plot", metavar="FILE.png", default=None,
                   help="write a figure of the map: one column of a paper wide (3.5 in, no text under 9 pt), "
                        "one column of panels per mode")
    p.add_argument("--panels", action="store_true",
                   help="with --plot FILE.png: one figure per panel instead, each one column wide, written to "
                        "FILE-mode<ID>-<panel>.png (panel: im_indicator, dkp_input, dkp_output, mechanism)")
    par = p.add_mutually_exclusive_group()
    par.add_argument("--workers", type=_count, default=None, help="run on a local Dask cluster of N workers")
    par.add_argument("--scheduler", metavar="ADDRESS", default=None, help="run on an existing Dask scheduler")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on the terminal")


#: the share of available memory a map may plan to use
MEMORY_SHARE = 0.5
#: a length axis must overlap what the mechanism can reach by at least this share of the box
MIN_REACHABLE = 1e-3


def _available_memory() -> int:
    """Bytes of memory available to this process (MemAvailable on Linux, else physical memory)."""
    import os

    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8 << 30


def memory_estimate(mech, n: int, modes: int) -> int:
    """Bytes a map of ``n`` × ``n`` points and ``modes`` modes holds: per point and mode the grid
    arrays (six), the configuration (free coordinates) and as much again for the work in progress."""
    free = len(mech.free_nodes) * mech.dim
    per_point = 8 * (6 + free)
    return 2 * n * n * max(modes, 1) * per_point


def _reach(mech) -> float:
    """A bound on any node coordinate the mechanism can reach (model units): the largest
    coordinate plus, per link, twice its largest distance from its first node."""
    import math

    coords = mech.coordinates()
    top = max((abs(c) for p in coords.values() for c in p), default=0.0)
    spread = 0.0
    for _, ns in mech.links:
        p0 = coords[ns[0]]
        spread += 2 * max(math.dist(p0, coords[n]) for n in ns)
    return top + spread


def _check_box(args, mech) -> None:
    """Refuse what cannot be mapped before any work: overflowing or needless windows, a grid too large."""
    import math

    from symkin.model.labels import parse_label
    from symkin.workspace.grid import parse_axis

    reachable, reach = 1.0, _reach(mech)
    turn = 360.0 if args.unit == "deg" else 2 * math.pi
    for option, text in (("--x", args.x), ("--y", args.y)):
        for part in str(text).rpartition("=")[2].split(":"):
            try:
                if not math.isfinite(float(part)):
                    raise SymkinError(f"{option} {text!r}: LO and HI must be finite numbers, got {part!r}")
            except ValueError:
                pass  # parse_axis says what is wrong
        label, lo, hi = parse_axis(text, option)
        if not math.isfinite(hi - lo):
            raise SymkinError(f"{option} {text!r}: the window's width overflows; give LO and HI of finite difference")
        try:
            kind = parse_label(mech, label, what="axis", lead="a map axis can be").kind
        except SymkinError:
            continue  # the map names the unknown label, with what it accepts
        if kind == "angle":
            if hi - lo > 2 * turn:
                raise SymkinError(f"{option} {text!r}: an angle window wider than two turns "
                                  f"({2 * turn:g} {args.unit}) repeats itself; give at most one turn")
            continue
        bound = 2 * reach
        overlap = max(0.0, min(hi, bound) - max(lo, -bound))
        reachable *= overlap / (hi - lo)
        if overlap == 0.0 or reachable < MIN_REACHABLE:
            raise SymkinError(f"{option} {text!r}: the box is far larger than the mechanism: no coordinate it "
                              f"reaches exceeds {bound:.3g} (model units), so at most "
                              f"{100 * reachable:.2g}% of the box can assemble; give a window within "
                              f"±{bound:.3g}")
    modes = 1 + len(args.seed) if args.modes == "model" else 8
    need, have = memory_estimate(mech, args.n, modes), _available_memory()
    if need > MEMORY_SHARE * have:
        raise SymkinError(f"--n {args.n}: the map would hold about {need / 2**30:.3g} GiB "
                          f"({args.n}² points × {modes} mode(s)), more than {MEMORY_SHARE:.0%} of the "
                          f"{have / 2**30:.3g} GiB of memory available; give a smaller --n")


def _progress(enabled: bool, total: int):
    if not enabled or not sys.stderr.isatty() or importlib.util.find_spec("tqdm") is None:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc="map", unit="pt", file=sys.stderr, leave=False)


def _trust(mode) -> list[str]:
    """What a mode's rejected points and branch changes mean for the map, and what to do about them."""
    lines = []
    if mode.rejected.any():
        lines.append(f"   {int(mode.rejected.sum())} rejected point(s): there the continuation from a neighbour "
                     "landed too far from its prediction, or on another DKP sign pattern, even in sub-steps, so "
                     "the point is left unassembled (a hole in the map, never a wrong value). The other points "
                     "can be trusted; a few isolated holes near a singular curve are harmless, many mean the grid "
                     "is too coarse for this mode: give a larger --n.")
    if mode.branch_changes:
        lines.append(f"   {len(mode.branch_changes)} branch change(s): between these pairs of neighbouring grid "
                     "points (--json: modes[].branch_changes) the continuation of one mode reached configurations "
                     "that do not join up, so the mode is not one sheet over the box there (two working modes meet, "
                     "usually across a singular curve) and the map shows one of them. Values away from these "
                     "points can be trusted; near them, map each working mode from its own --seed, and give a "
                     "larger --n if they lie off every singular curve.")
    return lines


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
        lines += _trust(mode)
        if mode.note:
            lines.append(f"   {mode.note}")
    if not m.assembled_anywhere:
        lines += ["", "Nothing assembles in this box: no mode reaches any grid point."]
    if m.notes:
        lines += [""] + [f"note: {n}" for n in m.notes]
    return "\n".join(lines)


def _plot(m, target, mech):
    from symkin.plots.maps import save_map_figure

    return save_map_figure(m, target, mechanism=mech)


def _plot_panels(m, target, mech) -> tuple[list[str], int]:
    """``--plot FILE --panels``: each panel's figure written whole to FILE-<panel>.EXT; (notes, exit code)."""
    from symkin.plots.maps import map_panel_figures, panel_path
    from symkin.plots.paths import DPI

    notes, code = [], 0
    for name, fig in map_panel_figures(m, mechanism=mech).items():
        out = panel_path(target, name)
        fmt = out.suffix[1:] or "png"
        saved = save_output(out, lambda tmp, fig=fig, fmt=fmt: fig.savefig(tmp, dpi=DPI, format=fmt), "--plot",
                            figure=True)
        notes.append(saved.problem or f"figure written to {saved.path}")
        code = 1 if saved.problem else code
    return notes, code


def run(args) -> Output:
    from symkin.workspace.maps import workspace_map
    from symkin.workspace.parallel import dask_client

    mech = read_model(args.model)
    if args.panels and not args.plot:
        raise SymkinError("--panels: give --plot FILE.png too (the panels go to FILE-<panel>.png)")
    if args.plot:
        check_figure_file(args.plot, "--plot")  # every output before the map is computed
    if args.npz:
        check_output_file(args.npz, "--npz")
    if args.json not in (None, "-"):
        check_output_file(args.json, "--json")
    if args.n < 2:
        raise SymkinError(f"{args.model}: --n {args.n}: the number of grid points per axis must be at least 2")
    try:
        check_holds(args.hold)
        _check_box(args, mech)
    except SymkinError as exc:
        raise in_file(exc, args.model)
    bar = _progress(not args.no_progress and args.json != "-", args.n * args.n * (1 + len(args.seed)))
    # a seed is a model file or a catalogue name (read here: the map reads files only)
    seeds = tuple(read_model(s) if s.startswith(CATALOGUE_PREFIX) else s for s in args.seed)
    try:
        # --workers N: a local Dask cluster for this run, closed afterwards; --scheduler: an existing one
        with dask_client(workers=args.workers, scheduler=args.scheduler) as client:
            m = workspace_map(mech, x=args.x, y=args.y, n=args.n, hold=tuple(args.hold), seeds=seeds,
                              modes=args.modes, refine=not args.no_refine, unit=args.unit, tol=args.tol,
                              progress=bar.update if bar is not None else None, client=client)
    except SymkinError as exc:
        raise in_file(exc, args.model)
    finally:
        if bar is not None:
            bar.close()
    notes, code = [], 0
    if args.npz:
        saved = save_output(args.npz, m.save, "--npz")
        notes.append(saved.problem or f"arrays written to {saved.path}")
        code = 1 if saved.problem else code
    if args.plot and args.panels:
        written, failed = _plot_panels(m, args.plot, mech)
        notes += written
        code = max(code, failed)
    elif args.plot:
        saved = save_output(args.plot, lambda tmp: _plot(m, tmp, mech), "--plot", figure=True)
        notes.append(saved.problem or f"figure written to {saved.path}")
        code = 1 if saved.problem else code
    if args.json is not None:
        text = json.dumps(m.to_dict(), indent=1)
        if args.json == "-":
            return Output(text, code=code, message="\n".join(notes))
        saved = save_output(args.json, lambda tmp: tmp.write_text(text + "\n"), "--json")
        notes.append(saved.problem or f"map written to {saved.path}")
        code = 1 if saved.problem else code
    return Output(_text(m), code=code, message="\n".join(notes))
