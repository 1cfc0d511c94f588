"""``symkin reproduce``: run every paper example's checks and write a report folder."""
from __future__ import annotations

from pathlib import Path

from symkin.commands import Output
from symkin.commands.outputs import check_output_folder
from symkin.errors import SymkinError
from symkin.reproduce import find_examples_dir, run_all

NAME = "reproduce"
HELP = "run every example of the paper in papers_examples/, print a summary, write a report folder"


def add_arguments(p) -> None:
    p.add_argument("--examples", default=None,
                   help="folder of model files and check_*.py scripts (default: ./papers_examples, "
                        "else the one beside the installed package)")
    p.add_argument("--out", default="reports/reproduce",
                   help="report folder to write (default: reports/reproduce)")


def run(args) -> Output:
    folder = find_examples_dir(args.examples)
    if folder is None:
        where = args.examples or "./papers_examples"
        raise SymkinError(f"{where}: no papers_examples folder with check_*.py scripts found "
                          "(run from the repository, or pass --examples DIR)")
    check_output_folder(args.out, "--out")  # before the checks run (created if needed)
    results = run_all(folder, Path(args.out))
    lines = [r.summary() for r in results]
    n_ok = sum(r.ok for r in results)
    n_claims = sum(len(r.claims) for r in results)
    n_hold = sum(c.holds for r in results for c in r.claims)
    lines.append("")
    lines.append(f"{n_ok}/{len(results)} examples reproduced, {n_hold}/{n_claims} claims hold; "
                 f"report written to {args.out}/summary.md")
    return Output("\n".join(lines), code=0 if n_ok == len(results) else 1)
