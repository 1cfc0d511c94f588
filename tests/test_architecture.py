"""Data flows one way: a module imports only from stages to its left (see conventions)."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "symkin"
# stage order: model → constraints (one definition per constraint kind) → curves (mechanism-free numerics) → (symbolic | numeric) → analysis → paths → workspace → plots/report → commands/cli
STAGE = {"startup": 0, "errors": 0, "tolerances": 0, "kinds": 0, "model": 1, "catalogue": 1, "constraints": 1.2, "curves": 1.5, "symbolic": 2, "numeric": 2,
         "analysis": 3, "paths": 4, "solutions": 4, "workspace": 5, "plots": 6, "report": 6, "reproduce": 6,
         "commands": 7, "cli": 7, "__main__": 8}
FORBIDDEN_IN_MODEL = {"sympy", "casadi", "matplotlib", "numpy", "scipy"}


def stage_of(path: Path) -> str:
    rel = path.relative_to(PACKAGE).parts
    return rel[0].removesuffix(".py")


def imported_modules(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module


FILES = [p for p in PACKAGE.rglob("*.py") if p.name != "__init__.py" or p.parent != PACKAGE]


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(PACKAGE)) for p in FILES])
def test_imports_flow_one_way(path):
    here = stage_of(path)
    if here not in STAGE:
        pytest.skip(f"{here} has no stage")
    for mod in imported_modules(path):
        parts = mod.split(".")
        if parts[0] in FORBIDDEN_IN_MODEL and here == "model":
            raise AssertionError(f"{path.name} (model) imports {mod}")
        if parts[0] != "symkin" or len(parts) < 2:
            continue
        target = parts[1]
        if target in STAGE and target != here:
            assert STAGE[target] <= STAGE[here], f"{path.relative_to(PACKAGE)} imports {mod}"


CURVES_MAY_IMPORT = {"tolerances", "errors", "kinds", "curves"}


@pytest.mark.parametrize("path", sorted((PACKAGE / "curves").rglob("*.py")), ids=lambda p: p.name)
def test_curve_toolkit_is_mechanism_free(path):
    """The curve toolkit is mechanism-free: it imports only the tolerances, the kinds and the errors
    (it sits below the numeric layer, whose projections use its corrector)."""
    for mod in imported_modules(path):
        parts = mod.split(".")
        if parts[0] == "symkin" and len(parts) >= 2:
            assert parts[1] in CURVES_MAY_IMPORT, f"curves/{path.name} imports {mod}"
