"""A pair kind is one file (issue 16): the proof that the abstraction holds.

* :func:`test_a_new_file_in_constraints_is_a_new_pair_kind` copies the package into a
  temporary folder, writes ONE new module there, ``symkin/constraints/tether.py`` (a test-only
  pair, the tether ``T``: two links whose points stay at a fixed distance, :data:`TETHER`), and
  runs in a fresh interpreter everything a pair goes through: the model file's parser and the
  joint compiler, the numeric ``G``, the CasADi model, the sympy rows and the polynomial
  closure, the CLI's bad-input path.  No other file is edited.  The truth it is checked
  against is independent of the new code: a distance held between two points is a bar, so a
  four-bar whose coupler is a tether and an RSSR whose S–S rod is a tether must have the
  node form's ``G = JᵀJ`` (the existing bar rows), its DOF, ranks and types.
* :func:`test_only_its_module_names_the_helical_pair` counts, for the helical pair H, the
  modules of ``symkin/`` outside ``symkin/constraints/helical.py`` that name it: none in code;
  in docstrings and comments only those of :data:`DOC_MENTIONS`, each with its reason.
  :func:`test_the_scan_finds_what_it_looks_for` shows that the scan fails on a mention.
"""
from __future__ import annotations

import ast
import io
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "symkin"

# ---------------------------------------------------------------------- a pair kind in one file
#: the whole of a test-only pair kind, written as symkin/constraints/tether.py of a copy of the package
TETHER = '''
"""The tether T (test-only): a point of one link held at a fixed distance from a point of another.

Joint ``T1`` joins links ``[a, b]`` at ``at`` with an ``axis`` and a ``length``: node ``T1`` of
``a`` at ``at`` and node ``T1.far`` of ``b`` at ``at + length·axis`` stay ``length`` apart.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from symkin.constraints.algebra import dot, sub
from symkin.constraints.base import Constraint, Equation, Row
from symkin.model.joints import offset
from symkin.model.pairs import ExtraConstraint, JointKey, JointKind, register_extra, register_joint


class Tether(Constraint):
    kind = "tether"

    def __init__(self, t, index):
        self.t, self.i, self.j = t, index[t.a], index[t.b]
        self.owner = self.element = f"tether {t.id}"
        self.where = f"joints ({t.id})"

    def size(self, dim):
        return 1

    def rows(self, alg, X, X0):
        d = sub(X[self.j], X[self.i])
        one = alg.const(1)
        return [Row(((self.i, one, d), (self.j, -one, d)), alg.sqrt(dot(d, d)))]

    def equations(self, alg, X, X0):
        d, d0 = sub(X[self.j], X[self.i]), sub(X0[self.j], X0[self.i])
        square = dot(d0, d0)
        return [Equation(alg.const(square) - dot(d, d), alg.const(2 * square ** 0.5))]


@register_extra
@dataclass(frozen=True)
class TetherRecord(ExtraConstraint):
    key = "tethers"
    keys = ("id", "a", "b")

    id: str
    a: str
    b: str

    @classmethod
    def parse(cls, item, where, ctx):
        if not all(isinstance(item.get(k), str) for k in cls.keys) or not {item["a"], item["b"]} <= set(ctx.nodes):
            ctx.problem(where, "needs id and two nodes a, b of the model")
            return None
        return cls(item["id"], item["a"], item["b"])

    def to_dict(self):
        return {"id": self.id, "a": self.a, "b": self.b}

    def moved(self, turn, place, scale):
        return self

    def constraint(self, index):
        return Tether(self, index)


def _compile(b, joint):
    first, second = joint.links
    near = b.shared(joint, [first], joint.at, joint.id)
    far = b.shared(joint, [second], offset(joint.at, joint.axis, joint.length), f"{joint.id}.far")
    if near is not None and far is not None:
        b.extra(TetherRecord.key, {"id": joint.id, "a": near, "b": far})


register_joint(JointKind("T", (2, 3), _compile, axis=(2, 3),
                         keys=(JointKey("length", needs="the distance held, in model length units",
                                        must="a finite number (model length units)"),)))
'''

#: run in the copy: every stage a pair goes through, with the node form as the truth
CHECK = '''
import contextlib, io, json, math, sys
import numpy as np
import casadi as ca
import symkin
from symkin.model.pairs import joint_types, extra_keys
from symkin.numeric.geometric_matrix import constraint_rows
from symkin.numeric.casadi_model import build
from symkin.symbolic.rows import RowBuilder
from symkin.symbolic.loci import closure_polynomials
from symkin.errors import ModelError

out = {"file": symkin.__file__, "types2": joint_types(2), "types3": joint_types(3), "extra_keys": extra_keys()}

def G(m):
    j = constraint_rows(m).matrix
    return j.T @ j

def permuted(m, ref):
    """G of m with its nodes reordered as ref's (matched by coordinates)."""
    x = np.array([c for _, c in m.nodes]); y = np.array([c for _, c in ref.nodes])
    order = [int(np.argmin(np.linalg.norm(x - p, axis=1))) for p in y]
    assert sorted(order) == list(range(len(order))), "nodes do not match"
    d = m.dim
    cols = [d * k + a for k in order for a in range(d)]
    return G(m)[np.ix_(cols, cols)]

def summary(m):
    a = symkin.analyze(m)
    return [a.dof, a.input_rank, a.output_rank, [str(t) for t in a.types]]

def backends(m):
    core = constraint_rows(m)
    cm = build(m)
    f = ca.Function("f", [cm.q, cm.p], [cm.J, cm.closure, ca.jacobian(cm.closure, cm.q)])
    j, phi, dphi = (np.array(v) for v in f(cm.q0(), cm.p0))
    rb = RowBuilder(m)
    values = dict(rb.values)
    sym = []
    for r in rb.rows:
        got = np.zeros(core.matrix.shape[1])
        scale = float(r.scale.xreplace(values))
        for col, e in r.entries(m.dim).items():
            got[col] = float(e.xreplace(values)) / scale
        sym.append(got)
    sym = np.array(sym)
    return {"owners": list(core.owners), "casadi_owners": list(cm.owners),
            "sympy_owners": [r.owner for r in rb.rows],
            "casadi_J": float(np.abs(j - core.matrix).max()),
            "sympy_rows": float(np.abs(sym - core.matrix).max()),
            "closure": float(np.abs(phi).max()) / m.length_scale,
            "closure_gradient": float(np.abs(dphi - j[:, np.flatnonzero(cm.free)]).max()),
            "polynomials": [o for _, o in closure_polynomials(m)]}

# planar: the four-bar of the paper's appendix, its coupler B-C a tether
node = symkin.catalogue.get("fourbar_appendix")
p = node.coordinates()
bc = [p["C"][k] - p["B"][k] for k in range(2)]
length = math.hypot(*bc)
planar = {"name": "four-bar with a tether", "dim": 2, "mobility": 1,
          "inputs": [{"joint": "R1"}], "outputs": [{"joint": "R2"}],
          "links": {"crank": [], "rocker": []},
          "joints": [{"id": "R1", "type": "R", "links": ["ground", "crank"], "at": list(p["A"])},
                     {"id": "T1", "type": "T", "links": ["crank", "rocker"], "at": list(p["B"]),
                      "axis": [c / length for c in bc], "length": length},
                     {"id": "R2", "type": "R", "links": ["ground", "rocker"], "at": list(p["D"])}]}
m = symkin.Mechanism.from_dict(planar)
out["planar"] = {
    "records": [r.to_dict() for r in m.tethers], "nodes": list(m.node_names),
    "to_dict_keys": list(m.to_dict()), "round_trip": symkin.Mechanism.from_dict(m.to_dict()) == m,
    "G": float(np.abs(permuted(m, node) - G(node)).max()),
    "G_mm": float(np.abs(G(m.moved(scale=1000.0)) - G(m)).max()),
    "analysis": summary(m), "node_analysis": summary(node), **backends(m)}

# spatial: an RSSR by its joints, its S-S rod a tether
r = symkin.catalogue.get("rssr").coordinates()
def axis(a, b):
    return [r[b][k] - r[a][k] for k in range(3)]
rod = axis("B", "C")
length = math.sqrt(sum(c * c for c in rod))
def rssr(middle):
    return {"name": "RSSR", "dim": 3, "inputs": [{"joint": "R1"}], "outputs": [{"joint": "R2"}],
            "links": {"crank": [], "rocker": [], **({"rod": []} if len(middle) == 2 else {})},
            "joints": [{"id": "R1", "type": "R", "links": ["ground", "crank"], "at": list(r["O1"]), "axis": axis("O1", "O1b")},
                       *middle,
                       {"id": "R2", "type": "R", "links": ["ground", "rocker"], "at": list(r["O2"]), "axis": axis("O2", "O2b")}]}
with_s = symkin.Mechanism.from_dict(rssr([{"id": "S1", "type": "S", "links": ["crank", "rod"], "at": list(r["B"])},
                                          {"id": "S2", "type": "S", "links": ["rod", "rocker"], "at": list(r["C"])}]))
# the rocker's node at C given, so that both forms have the same points (O1, B, C, O2) and so the
# same model length, the distance of the R joints' axis nodes
tethered = rssr([{"id": "T1", "type": "T", "links": ["crank", "rocker"], "at": list(r["B"]),
                  "axis": [c / length for c in rod], "length": length}])
tethered["nodes"], tethered["links"]["rocker"] = {"C": list(r["C"])}, ["C"]
spatial = symkin.Mechanism.from_dict(tethered)
out["spatial"] = {"G": float(np.abs(permuted(spatial, with_s) - G(with_s)).max()),
                  "G_mm": float(np.abs(G(spatial.moved(scale=1000.0)) - G(spatial)).max()),
                  "analysis": summary(spatial), "node_analysis": summary(with_s), **backends(spatial)}

# bad input: the parser of the kind's own key, the joint's id named; the CLI exits 2
bad = []
for change in ({"length": None}, {"length": "far"}):
    d = json.loads(json.dumps(planar))
    t = d["joints"][1]
    for k, v in change.items():
        if v is None:
            del t[k]
        else:
            t[k] = v
    try:
        symkin.Mechanism.from_dict(d)
    except ModelError as e:
        bad.append(str(e))
d = json.loads(json.dumps(planar))
d["joints"][0]["length"] = 1.0
try:
    symkin.Mechanism.from_dict(d)
except ModelError as e:
    bad.append(str(e))
out["bad"] = bad
path = sys.argv[1]
d = json.loads(json.dumps(planar))
del d["joints"][1]["length"]
with open(path, "w") as f:
    json.dump(d, f)
from symkin.cli import main
err = io.StringIO()
with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
    try:
        code = main(["analyze", path])
    except SystemExit as e:
        code = e.code
out["cli"] = [code, err.getvalue()]
print(json.dumps(out))
'''


@pytest.fixture(scope="module")
def tether_run(tmp_path_factory):
    """The package copied with ``constraints/tether.py`` added, :data:`CHECK` run against it."""
    tmp = tmp_path_factory.mktemp("one_file")
    shutil.copytree(PACKAGE, tmp / "symkin", ignore=shutil.ignore_patterns("__pycache__"))
    (tmp / "symkin" / "constraints" / "tether.py").write_text(textwrap.dedent(TETHER))
    (tmp / "check.py").write_text(textwrap.dedent(CHECK))
    env = dict(os.environ, PYTHONPATH=str(tmp), SYMKIN_CACHE=str(tmp / "cache"))
    run = subprocess.run([sys.executable, str(tmp / "check.py"), str(tmp / "bad.json")], cwd=tmp,
                         capture_output=True, text=True, env=env, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["file"] == str(tmp / "symkin" / "__init__.py")  # the copy, not the worktree
    out["changed"] = sorted(str(f.relative_to(tmp)) for f in (tmp / "symkin").rglob("*.py")
                            if not (ROOT / f.relative_to(tmp)).is_file()
                            or (ROOT / f.relative_to(tmp)).read_bytes() != f.read_bytes())
    return out


def test_the_copy_differs_from_the_package_by_one_file(tether_run, tmp_path_factory):
    """The kind was found with no other edit: the copy is the package plus one module."""
    assert tether_run["changed"] == ["symkin/constraints/tether.py"]
    assert "T" in tether_run["types2"] and "T" in tether_run["types3"]
    assert tether_run["types3"][:6] == ["R", "P", "C", "U", "S", "H"]  # the built-in order kept
    assert tether_run["extra_keys"] == ["helicals", "tethers"]         # modules by name
    assert not (PACKAGE / "constraints" / "tether.py").exists()


@pytest.mark.parametrize("form", ["planar", "spatial"])
def test_a_new_file_in_constraints_is_a_new_pair_kind(tether_run, form):
    """Parsing and the joint compiler took the T; the numeric G is the node form's (a held
    distance is a bar), in mm too; the analyses agree; CasADi, sympy and the polynomial closure
    state the tether's row and equation."""
    r = tether_run[form]
    assert r["G"] <= 1e-12 and r["G_mm"] <= 1e-12
    assert r["analysis"] == r["node_analysis"] == [1, 1, 1, []]
    assert r["owners"][-1] == "tether T1" and r["owners"].count("tether T1") == 1
    assert r["casadi_owners"] == r["sympy_owners"] == r["owners"]
    assert r["casadi_J"] <= 1e-12 and r["sympy_rows"] <= 1e-12
    assert r["closure"] <= 1e-12 and r["closure_gradient"] <= 1e-9
    assert "tether T1" in r["polynomials"]


def test_the_new_kind_in_the_model_dictionary(tether_run):
    r = tether_run["planar"]
    assert r["records"] == [{"id": "T1", "a": "T1", "b": "T1.far"}]
    assert {"T1", "T1.far"} <= set(r["nodes"])
    assert r["to_dict_keys"][-1] == "tethers"
    assert r["round_trip"]


def test_the_new_kind_bad_input(tether_run):
    missing, wrong, elsewhere = tether_run["bad"]
    assert "joints[1] (T1)" in missing and "a T joint needs 'length' (the distance held" in missing
    assert "joints[1] (T1)" in wrong and "length must be a finite number (model length units), got 'far'" in wrong
    assert "joints[0] (R1)" in elsewhere and "'length' goes with a T joint, not with a R joint" in elsewhere
    code, err = tether_run["cli"]
    assert code == 2 and "T1" in err and "needs 'length'" in err and "Traceback" not in err


# ---------------------------------------------------------------------- H is named by its module only
HELICAL = "symkin/constraints/helical.py"
#: what names the helical pair: its words, and its type letter as a string
WORDS = re.compile(r"helical|screw|pitch", re.IGNORECASE)
LETTER = re.compile(r"""^[rRbBuUfF]*(['"])H\1$""")
#: docstrings and comments that may name it (at most this many lines per file), and why
DOC_MENTIONS = {
    "symkin/numeric/geometric_matrix.py": (2, "the module docstring lists the rows the core assembles"),
    "symkin/numeric/casadi_model.py": (2, "the module docstring lists the rows the CasADi model states"),
    "symkin/symbolic/rows.py": (3, "the module docstring lists the rows the symbolic model states; known_nodes "
                                   "names its measured example (the screw jack) and that example's test"),
    "symkin/symbolic/polynomials.py": (1, "constant_rows' docstring names the test of its measured example"),
    "symkin/curves/tracer.py": (1, "the docstring of the closed-curve test gives a screw's path as its example"),
}
#: code that spells the letter H for something else, and what
CODE_MENTIONS = {
    ("symkin/paths/system.py", '"H"'): "the name of a CasADi function's output (the curve's residual H)",
}


def _docstring_lines(tree: ast.AST) -> set[int]:
    lines = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) \
                    and isinstance(first.value.value, str):
                lines.update(range(first.lineno, first.end_lineno + 1))
    return lines


def mentions(source: str) -> tuple[list[tuple[int, str]], list[tuple[int, str]]]:
    """``(code, doc)``: the lines whose tokens name the helical pair, in code and in docstrings or comments."""
    docs = _docstring_lines(ast.parse(source))
    code, doc = [], []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        text = tok.string
        # the lines of the token that name it (a docstring spans many)
        named = [(tok.start[0] + k, line) for k, line in enumerate(text.split("\n")) if WORDS.search(line)]
        if tok.type == tokenize.COMMENT or (tok.type == tokenize.STRING and tok.start[0] in docs):
            doc += named
        elif tok.type in (tokenize.NAME, tokenize.STRING, getattr(tokenize, "FSTRING_MIDDLE", -1)):
            code += named
            if tok.type == tokenize.STRING and LETTER.match(text):
                code.append((tok.start[0], text))
    return code, doc


def test_only_its_module_names_the_helical_pair():
    """Outside ``symkin/constraints/helical.py`` no code names H (its words, its letter), and
    only the docstrings of :data:`DOC_MENTIONS` do, as many lines as listed at most."""
    in_code, in_docs, seen = [], [], {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel == HELICAL:
            continue
        code, doc = mentions(path.read_text())
        in_code += [f"{rel}:{line}: {text[:60]}" for line, text in code if (rel, text) not in CODE_MENTIONS]
        lines = sorted({line for line, _ in doc})
        if lines:
            seen[rel] = len(lines)
            allowed = DOC_MENTIONS.get(rel, (0, ""))[0]
            if len(lines) > allowed:
                in_docs.append(f"{rel}: {len(lines)} docstring/comment lines name it (allowed {allowed}): {lines}")
    assert not in_code, "code outside its module names the helical pair: " + "; ".join(in_code)
    assert not in_docs, "; ".join(in_docs)
    # the module itself does, of course: the scan reads it
    code, _ = mentions((ROOT / HELICAL).read_text())
    assert any(text == "HelicalPair" for _, text in code) and any(LETTER.match(t) for _, t in code)


def test_the_scan_finds_what_it_looks_for():
    """The scan fails on the code this issue removed, and sorts docstrings from code."""
    removed = textwrap.dedent('''
        """Module docstring naming the helical pair."""
        def rows(mech):
            # a comment on screws
            out = list(mech.sliders)
            if mech.helicals:
                out += [Helical(h) for h in mech.helicals]
            return out if joint.type != "H" else f"{joint.pitch}"
        ''')
    code, doc = mentions(removed)
    assert [line for line, _ in doc] == [2, 4]
    assert sorted({line for line, _ in code}) == [6, 7, 8]
    assert [t for _, t in code if LETTER.match(t)] == ['"H"']
