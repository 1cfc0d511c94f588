"""``symkin codegen MODEL --out DIR``: C code of a model's evaluators, a header, a library.

Writes ``DIR/STEM.c`` (CasADi-generated C of the Functions G, J, closure,
closure_jacobian, parameters, indicators, motion), ``DIR/STEM.h`` (their declarations,
preceded by a comment documenting every argument and result, their order, shapes and
labels), ``DIR/STEM.json`` (the same as data) and ``DIR/STEM.so`` compiled by the system
C compiler, which ``casadi.external(name, "DIR/STEM.so")`` loads.  Exit code 1 when the
library cannot be compiled (the sources are written all the same).
"""
from __future__ import annotations

import json
import re
import shlex
import time
from pathlib import Path

from symkin.commands import Output, write_output
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "codegen"
HELP = "generate C for a model's evaluators (G, J, closure, indicators), a documented header and a library"


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json)")
    p.add_argument("--out", required=True, metavar="DIR", help="directory to write into (created if needed)")
    p.add_argument("--name", default=None, metavar="STEM",
                   help="file stem (default: <model file stem>_evaluators)")
    p.add_argument("--compiler", default=None, metavar="CC",
                   help="C compiler (default: $SYMKIN_CC, $CC, or cc)")
    p.add_argument("--flags", default=None, metavar="FLAGS",
                   help="compiler flags as one string (default: '-O3 -fno-math-errno -fPIC -shared "
                        "-ffp-contract=off')")
    p.add_argument("--no-compile", action="store_true", help="write the sources only")


def _stem(text: str) -> str:
    stem = re.sub(r"\W", "_", text)
    if not stem or not (stem[0].isalpha() or stem[0] == "_"):
        stem = "m_" + stem
    return stem


def run(args) -> Output:
    from symkin.numeric import codegen
    from symkin.numeric.evaluators import evaluators

    mech = read_model(args.model)
    stem = _stem(args.name if args.name else f"{Path(args.model).stem}_evaluators")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise SymkinError(f"--out {out}: exists and is not a directory")
    ev = evaluators(mech)
    c_path, h_path = codegen.generate_sources(ev, out, stem)
    man = codegen.manifest(ev)
    json_path = out / f"{stem}.json"
    write_output(json_path, lambda tmp: tmp.write_text(json.dumps(man, indent=1)))
    lines = [f"{mech.name}: evaluators written to {out}/",
             f"  {c_path.name}  C sources (CasADi {man['casadi']})",
             f"  {h_path.name}  header: argument order, shapes and names of every function",
             f"  {json_path.name}  the same as JSON"]
    code, message = 0, ""
    if not args.no_compile:
        flags = tuple(shlex.split(args.flags)) if args.flags is not None else codegen.DEFAULT_FLAGS
        cc = codegen.find_compiler(args.compiler)
        so_path = out / f"{stem}.so"
        start = time.perf_counter()
        try:
            codegen.build_library(c_path, so_path, cc, flags)
        except codegen.CompilerError as exc:
            code = 1
            message = f"symkin codegen: {exc}; the sources are written, the library is not"
        else:
            lines.append(f"  {so_path.name}  library ({cc} {' '.join(flags)}, "
                         f"{time.perf_counter() - start:.2f} s)")
    lines.append("functions (q = " + ", ".join(man["q"]) + "):")
    for name, spec in man["functions"].items():
        ins = ", ".join(f"{a['name']}[{a['shape'][0]}x{a['shape'][1]}]" for a in spec["inputs"])
        outs = ", ".join(f"{a['name']}[{a['shape'][0]}x{a['shape'][1]}]" for a in spec["outputs"])
        lines.append(f"  {name}({ins}) -> {outs}")
    if code == 0 and not args.no_compile:
        lines.append(f'load with: casadi.external("indicators", "{out / (stem + ".so")}")')
    return Output("\n".join(lines), code, message)
