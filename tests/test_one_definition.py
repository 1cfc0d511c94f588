"""One concept, one definition: a source scan for second Newton loops, tolerance literals and kind strings.

* **Newton loops.** A loop that solves a linear system (``lstsq``, ``solve``, ``pinv``,
  ``inv`` or the corrector's step functions) and adds the result to an iterate is a
  Newton-type iteration.  There is one: :mod:`symkin.curves.corrector` (one point and a
  batch).  Every other stage calls it.  The loop of the generated corrector
  (:mod:`symkin.paths.generated`) calls compiled code and is not a solve in Python: it is the
  corrector's generated form, kept equal by its tests.
* **Tolerance literals.** A number below ``1e-3`` written in the code is a tolerance (a
  threshold, a step size, a guard).  They belong in :mod:`symkin.tolerances` (fields of
  ``Tolerances``, each with why its default is what it is) or in the curve toolkit, which
  owns its numerical constants.  The exceptions are listed below, per file and value, with
  the reason; a new one makes this test fail until it is moved or listed.
* **Kind strings.** The JSON strings of the singularity and event kinds are spelled in
  :mod:`symkin.kinds` only; code compares with :class:`symkin.kinds.Kind` members.
"""
from __future__ import annotations

import ast
import io
import tokenize
from collections import Counter
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "symkin"
FILES = sorted(PACKAGE.rglob("*.py"))

# ---------------------------------------------------------------------- Newton loops
SOLVES = {"lstsq", "solve", "pinv", "inv", "least_squares_step", "stacked_steps"}
LOOP_OWNERS = {"symkin/curves/corrector.py"}
NOT_NEWTON = {
    ("symkin/constraints/body.py", "_affine"):
        "one least-squares solve per node of a degenerate body (its affine coordinates), accumulated "
        "into rows: no iterate",
    ("symkin/solutions/system.py", "_bodies"):
        "the affine coordinates of a body's nodes on its frame, one least-squares solve per node, "
        "written into the polynomial system: no iterate",
}


def _root(node):
    while isinstance(node, (ast.Subscript, ast.Attribute)):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _additive_updates(loop) -> set[str]:
    """Names that the loop sets by adding to a name (``z = z + dz``, ``z_new = z + dz``, ``z += dz``, tuples too)."""
    out = set()
    for n in ast.walk(loop):
        if isinstance(n, ast.AugAssign) and isinstance(n.op, (ast.Add, ast.Sub)):
            out.add(_root(n.target))
        elif isinstance(n, ast.Assign):
            pairs = []
            if isinstance(n.value, ast.Tuple) and n.targets and isinstance(n.targets[0], ast.Tuple):
                pairs = list(zip(n.targets[0].elts, n.value.elts))
            else:
                pairs = [(t, n.value) for t in n.targets]
            for target, value in pairs:
                # z = z + dz, and z_new = z + dz (a trial iterate)
                if isinstance(value, ast.BinOp) and isinstance(value.op, (ast.Add, ast.Sub)) \
                        and isinstance(value.left, ast.Name):
                    out.add(_root(target))
    out.discard(None)
    return out


def newton_loops(path: Path) -> list[tuple[str, int]]:
    """``(function, line)`` of every loop in ``path`` that solves a linear system and updates an iterate."""
    tree = ast.parse(path.read_text())
    owner = {}
    for f in ast.walk(tree):
        if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for n in ast.walk(f):
                owner[id(n)] = f.name
    found = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.For, ast.While)):
            calls = {getattr(c.func, "attr", getattr(c.func, "id", None))
                     for c in ast.walk(node) if isinstance(c, ast.Call)}
            if calls & SOLVES and _additive_updates(node):
                found.append((owner.get(id(node), "<module>"), node.lineno))
    return found


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def test_one_newton_loop():
    extra = []
    for path in FILES:
        rel = _rel(path)
        if rel in LOOP_OWNERS:
            continue
        for function, line in newton_loops(path):
            if (rel, function) not in NOT_NEWTON:
                extra.append(f"{rel}:{line} ({function})")
    assert not extra, ("a Newton-type loop outside symkin/curves/corrector.py — call "
                       "symkin.curves.corrector.gauss_newton / gauss_newton_batch instead: " + ", ".join(extra))


def test_the_scan_sees_a_newton_loop():
    """The scan itself: the corrector's loops are found, and a hand-written one would be."""
    assert [f for f, _ in newton_loops(PACKAGE / "curves" / "corrector.py")] == ["gauss_newton", "gauss_newton_batch"]
    probe = ROOT / "tests" / "_probe_newton.py"
    probe.write_text("import numpy as np\n\ndef f(z, r, j):\n    for _ in range(5):\n"
                     "        z = z - np.linalg.solve(j(z), r(z))\n    return z\n")
    try:
        assert newton_loops(probe) == [("f", 4)]
    finally:
        probe.unlink()


# ---------------------------------------------------------------------- tolerance literals
LITERAL_OWNERS = ("symkin/tolerances.py", "symkin/curves/")

_GUARD = "a floor that keeps a division or a relative comparison defined at zero (not a tolerance)"
_PLOT = "drawing only: a minimum extent or collinearity test for laying out a figure, no decision"
_EXACT = "recognising exact numbers (sympy nsimplify / ulp checks) in the symbolic stage"
_IDENTITY = "a numeric check that two symbolic expressions agree at random points (identity test)"

ALLOWED_LITERALS: dict[str, dict[str, tuple[int, str]]] = {
    "symkin/analysis/batch.py": {"1e-12": (1, "_CERTIFICATE: the kernel's certified eigenvalue width, the same "
                                                "constant as numeric/sx_linalg.CERTIFICATE_WIDTH")},
    "symkin/analysis/classification.py": {"1e-12": (1, "rref pivot floor below the rank tolerance (rounding)"),
                                          "1e-300": (1, _GUARD)},
    "symkin/analysis/relations.py": {"1e-9": (1, "printing: a coefficient of 1 is not written"),
                                     "1e-12": (1, "rref pivot floor below the rank tolerance (rounding)")},
    "symkin/model/validation.py": {"1e-100": (1, "MIN_LENGTH: the smallest length scale whose squares do not "
                                                  "underflow (the README's unit range)"),
                                   "1e-9": (1, "_ALIGNED: cosine slack of a geometric alignment check")},
    "symkin/numeric/evaluators.py": {"1e-12": (1, "Evaluators.project's default residual (= Tolerances.newton)"),
                                     "1e-10": (1, "a generated kernel's validity bound on J_S (SX expression)")},
    "symkin/constraints/body.py": {"1e-9": (1, "tie-break of the affine frame's greedy choice")},
    "symkin/numeric/geometric_matrix.py": {"1e-10": (1, "pseudo-inverse cutoff of a body's frame"),
                                           "1e-4": (1, "_WELL_CONDITIONED: the normal-equations fast path")},
    "symkin/numeric/sx_linalg.py": {"1e-12": (3, "certified eigenvalue width and the bracket below λ_1 "
                                                 "(generated SX code)"),
                                    "1e-300": (1, _GUARD), "1e-6": (1, "bracket of a redundant eigenvalue")},
    "symkin/paths/branching.py": {"1e-5": (1, "finite-difference step of the second derivative fallback"),
                                  "1e-6": (1, "degenerate quadratic form of the branch directions"),
                                  "1e-12": (1, "Brent's xatol on the branch directions' angle")},
    "symkin/paths/trace.py": {"1e-9": (1, "START_CLOSURE: a model configuration that closes to this is on the "
                                          "curve (checked before tracing)")},
    "symkin/plots/mechanism.py": {"1e-12": (1, _PLOT), "1e-300": (2, _GUARD), "1e-9": (3, _PLOT)},
    "symkin/plots/paths.py": {"1e-4": (1, "symlog's linear threshold (an axis scale)"), "1e-9": (1, _PLOT),
                              "1e-12": (1, _PLOT)},
    "symkin/reproduce.py": {"1e-9": (1, "default relative tolerance of a paper claim's number")},
    "symkin/solutions/circuit_search.py": {"1e-10": (1, "a half-branch start on the closure"),
                                           "1e-12": (1, "a located branch point's residual"),
                                           "1e-300": (1, _GUARD)},
    "symkin/solutions/circuits.py": {"1e-12": (1, "clustering of critical input values (radians)"),
                                     "1e-9": (1, "a full turn's span")},
    "symkin/solutions/dkp_system.py": {"1e-15": (1, "POLISH_TARGET: residual of a square system's polish"),
                                       "1e-16": (1, "POLISH_STEP: its last step"),
                                       "1e-13": (1, "CURVE_POINT: projection onto the closure curve"),
                                       "1e-9": (1, "a factor constant on the curve (relative)")},
    "symkin/solutions/solve_all.py": {"1e-12": (1, "NEWTON_TARGET"), "1e-10": (3, "NEWTON_ACCEPT, a "
                                      "prescribed value's check and an endpoint at infinity"), "1e-15": (1, "NEWTON_STEP"),
                                      "1e-8": (3, "VERIFY, the imaginary part of a real solution and SPAN_OFF "
                                                  "(a query's distance from the parameter family)"),
                                      "1e-6": (1, "DISTINCT: two complex solutions found by the two "
                                                  "homotopies are one"),
                                      "1e-4": (1, "near-real solutions, refined")},
    "symkin/solutions/square_solutions.py": {"1e-4": (1, "NEAR_REAL"), "1e-10": (1, "AT_INFINITY")},
    "symkin/solutions/monodromy.py": {"1e-8": (1, "VERIFY: a monodromy endpoint solves the original equations"),
                                      "1e-6": (1, "DISTINCT: two monodromy solutions are one (as "
                                                  "Tolerances.same_configuration)")},
    "symkin/solutions/parameter_homotopy.py": {"1e-9": (3, "MIN_STEP and PATH_TOL of the path tracker, "
                                                           "SPAN_RANK of the sampled coefficients"),
                                               "1e-300": (2, _GUARD)},
    "symkin/solutions/system.py": {"1e-300": (1, _GUARD)},
    "symkin/symbolic/conditions.py": {"1e-300": (1, _GUARD)},
    "symkin/symbolic/loci.py": {"1e-9": (2, "a real root of a univariate elimination (imaginary part, residual)")},
    "symkin/symbolic/real_points.py": {"1e-9": (1, "ZERO: a polynomial's value at a numerical critical point, "
                                                   "relative to its terms (real points of a locus factor)"),
                                       "1e-6": (1, "ROOT: a companion-matrix root of a resultant is real / a "
                                                   "gradient vanishes (about the square root of the rounding)"),
                                       "1e-300": (1, _GUARD)},
    "symkin/symbolic/readable_forms.py": {"1e-300": (1, _GUARD), "1e-9": (3, _IDENTITY), "1e-12": (1, _IDENTITY)},
    "symkin/symbolic/rows.py": {"1e-12": (1, _EXACT)},
    "symkin/symbolic/symbols.py": {"1e-300": (1, _GUARD), "1e-13": (1, _EXACT), "1e-12": (1, _EXACT)},
    "symkin/workspace/locate.py": {"1e-6": (1, "Brent's xtol on a grid edge (fraction of the edge)"),
                                   "1e-9": (2, "Brent's xtol and the slack of a fold's parameter")},
    "symkin/workspace/loci.py": {"1e-6": (1, "smallest continuation step, in cells")},
    "symkin/workspace/locus_problems.py": {"1e-12": (2, "LOCUS_NEWTON_TOL and _JACOBIAN_BUMP"),
                                           "1e-10": (1, "POLISH_STEP")},
    "symkin/workspace/maps.py": {"1e-8": (1, "comparing two maps' arrays (WorkspaceMap equality)"),
                                 "1e-10": (1, "comparing two maps' arrays (WorkspaceMap equality)")},
    "symkin/workspace/quadtree.py": {"1e-12": (1, "_BOX_SLACK: a cell corner on the box edge is inside")},
    "symkin/workspace/system.py": {"1e-11": (1, "NEWTON_TOL: the map's batched Newton residual"),
                                   "1e-5": (1, "_SERIES_BELOW: series form of an angle near zero")},
}


def tolerance_literals(path: Path) -> Counter:
    """Count the numbers below 1e-3 written in the code of ``path`` (not in strings or comments)."""
    found = Counter()
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type == tokenize.NUMBER:
            try:
                value = float(tok.string.replace("_", ""))
            except ValueError:
                continue
            if 0 < value < 1e-3:
                found[tok.string] += 1
    return found


def test_tolerance_literals_live_in_tolerances_or_the_toolkit():
    extra = []
    for path in FILES:
        rel = _rel(path)
        if rel.startswith(LITERAL_OWNERS):
            continue
        allowed = ALLOWED_LITERALS.get(rel, {})
        for literal, count in tolerance_literals(path).items():
            if count > allowed.get(literal, (0, ""))[0]:
                extra.append(f"{rel}: {literal} × {count} (allowed {allowed.get(literal, (0, ''))[0]})")
    assert not extra, ("tolerance literals outside symkin/tolerances.py and symkin/curves/ — make them "
                       "Tolerances fields, or list them here with the reason: " + "; ".join(extra))


def test_the_allow_list_has_no_stale_entries():
    """Every listed exception still exists (a literal moved to Tolerances leaves the list)."""
    stale = []
    for rel, allowed in ALLOWED_LITERALS.items():
        path = ROOT / rel
        have = tolerance_literals(path) if path.exists() else Counter()
        for literal, (count, reason) in allowed.items():
            assert reason, f"{rel}: {literal} has no reason"
            if have[literal] < count:
                stale.append(f"{rel}: {literal} listed × {count}, found × {have[literal]}")
    assert not stale, "; ".join(stale)


# ---------------------------------------------------------------------- kind strings
KIND_STRINGS = {"IM", "DKP-input", "DKP-output", "LIM", "constraint", "cusp", "meeting", "bifurcation"}
KIND_OWNERS = {"symkin/kinds.py"}


@pytest.mark.parametrize("path", FILES, ids=lambda p: _rel(p))
def test_kind_strings_are_spelled_once(path):
    rel = _rel(path)
    if rel in KIND_OWNERS:
        return
    spelled = []
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type == tokenize.STRING:
            try:
                value = ast.literal_eval(tok.string)
            except (ValueError, SyntaxError):
                continue
            if isinstance(value, str) and value in KIND_STRINGS:
                spelled.append(f"{tok.start[0]}: {value!r}")
    assert not spelled, f"{rel} spells kind strings (use symkin.kinds.Kind): {spelled}"
