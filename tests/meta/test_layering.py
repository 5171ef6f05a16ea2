"""The package imports only downward: cli -> (design | study) -> api -> deck | model | solver | io |
analysis -> physics | geometry -> materials -> (errors, units, _jit). ``materials`` (the material
library) sits just above the bottom: anything may import it, it imports only the bottom layer.
Imports under ``if TYPE_CHECKING:`` do not count (no runtime edge). ``x3dpd/__init__.py`` is the
public facade: it may load the API (lazily, in its ``__getattr__``) and nothing else above the
bottom layer."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "x3dpd"
LAYER = {"cli": 5, "design": 4, "study": 4, "api": 3, "deck": 2, "model": 2, "solver": 2, "io": 2, "analysis": 2,
         "physics": 1, "geometry": 1, "materials": 0.5, "errors": 0, "units": 0, "_jit": 0, "_files": 0, "__init__": 0,
         "__main__": 6}
#: What the facade ``x3dpd/__init__.py`` may import (lazily) besides the bottom layer.
FACADE = {"api"}


def _group(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "x3dpd":
        return None
    return parts[1] if len(parts) > 1 else "__init__"


def _runtime_imports(tree: ast.AST):
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in ast.walk(node):
                skip.add(id(sub))
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.lineno, node.module
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name


def test_imports_go_downward_only():
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        here = rel.parts[0].removesuffix(".py")
        for line, module in _runtime_imports(ast.parse(path.read_text())):
            there = _group(module)
            if there is None or there == here:
                continue
            if here == "__init__" and there in FACADE:
                continue
            if LAYER[there] >= LAYER[here]:
                bad.append(f"x3dpd/{rel}:{line}: {here} imports {module}")
    assert not bad, "imports that do not go downward:\n" + "\n".join(bad)
