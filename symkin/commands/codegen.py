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
import os
import re
import shlex
import time
from pathlib import Path

from symkin.commands import Output, check_output_folder, write_output
from symkin.errors import SymkinError
from symkin.model.model_file import read_model

NAME = "codegen"
HELP = "generate C for a model's evaluators (G, J, closure, indicators), a documented header and a library"


def add_arguments(p) -> None:
    p.add_argument("model", help="model file (.toml or .json) or catalogue:NAME")
    p.add_argument("--out", required=True, metavar="DIR", help="directory to write into (created if needed)")
    p.add_argument("--name", default=None, metavar="STEM",
                   help="file stem (default: <model file stem>_evaluators); it also names the C functions, "
                        "so characters other than ASCII letters and digits become _ (no leading or double _)")
    p.add_argument("--compiler", default=None, metavar="CC",
                   help="C compiler (default: $SYMKIN_CC, $CC, or cc)")
    p.add_argument("--flags", default=None, metavar="FLAGS",
                   help="compiler flags as one string (default: '-O3 -fno-math-errno -fPIC -shared "
                        "-ffp-contract=off')")
    p.add_argument("--no-compile", action="store_true", help="write the sources only")


#: a file stem that is also a C identifier CasADi accepts: ASCII, a letter first, no "__"
_STEM = re.compile(r"[A-Za-z](?:_?[A-Za-z0-9])*_?")


def _stem(text: str) -> str:
    """A stem that is a C identifier CasADi accepts: every other character becomes ``_``,
    runs of ``_`` one, no ``_`` at the ends, ``m_`` in front of a leading digit.

    >>> _stem("4-bar model"), _stem("_x"), _stem("x__y"), _stem("élan"), _stem("∆")
    ('m_4_bar_model', 'x', 'x_y', 'lan', 'm')
    """
    stem = re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", text)).strip("_")
    if not stem:
        return "m"
    if not stem[0].isalpha():
        stem = "m_" + stem
    return stem


def _check_name(name: str) -> str:
    """``--name``: a stem, not a path; made a C identifier by :func:`_stem`."""
    if "/" in name or os.sep in name or (os.altsep and os.altsep in name) or not name.strip():
        raise SymkinError(f"--name {name!r}: give a file stem, not a path (the folder is --out); the stem "
                          "also names the C functions, so other characters than ASCII letters and digits "
                          "become _")
    return _stem(name)


def _flags(text: str) -> tuple[str, ...]:
    try:
        return tuple(shlex.split(text))
    except ValueError as exc:
        raise SymkinError(f"--flags {text!r}: cannot split into compiler flags ({exc})") from None


def run(args) -> Output:
    from symkin.numeric import codegen
    from symkin.numeric.evaluators import evaluators

    stem = _check_name(args.name) if args.name is not None else _stem(f"{Path(args.model).stem}_evaluators")
    flags = _flags(args.flags) if args.flags is not None else codegen.DEFAULT_FLAGS
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise SymkinError(f"--out {out}: exists and is not a directory")
    mech = read_model(args.model)
    check_output_folder(out, "--out")
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
