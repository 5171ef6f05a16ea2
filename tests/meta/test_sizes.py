"""Smaller pieces (docs/architecture.md, "Size"): no function of the package over 80 lines and
no module over 400 without a one-line reason written where a reader meets it.

A long function carries ``# Over 80 lines: REASON`` on the line above its ``def`` (above its
decorators, if any); a long module carries ``# Over 400 lines: REASON`` in its first three
lines. The reason is what makes the piece better whole (a compiled kernel whose parts would
cost a call per contact, a command's one flow of options to output), not an apology.
"""

from __future__ import annotations

import ast
import pathlib

import pytest

PACKAGE = pathlib.Path(__file__).resolve().parents[2] / "x3dpd"
MAX_FUNCTION = 80
MAX_FILE = 400
FUNCTION_MARK = "# Over 80 lines:"
FILE_MARK = "# Over 400 lines:"


def _first_line(node: ast.AST) -> int:
    decorators = getattr(node, "decorator_list", [])
    return min([node.lineno] + [d.lineno for d in decorators])


def long_pieces(root: pathlib.Path = PACKAGE) -> tuple[list[str], list[str]]:
    """(functions, files) past their limit without a reason, as ``path:line name (n lines)``."""
    functions, files = [], []
    for path in sorted(root.rglob("*.py")):
        lines = path.read_text(encoding="utf-8").splitlines()
        rel = path.relative_to(root.parent)
        if len(lines) > MAX_FILE and not any(
            line.startswith(FILE_MARK) and line[len(FILE_MARK) :].strip() for line in lines[:3]
        ):
            files.append(f"{rel} ({len(lines)} lines)")
        for node in ast.walk(ast.parse("\n".join(lines))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            length = node.end_lineno - node.lineno + 1
            if length <= MAX_FUNCTION:
                continue
            above = lines[_first_line(node) - 2].strip() if _first_line(node) > 1 else ""
            if not (above.startswith(FUNCTION_MARK) and above[len(FUNCTION_MARK) :].strip()):
                functions.append(f"{rel}:{node.lineno} {node.name} ({length} lines)")
    return functions, files


def test_no_long_function_without_its_reason():
    functions, _ = long_pieces()
    assert not functions, (
        f"functions over {MAX_FUNCTION} lines: split them or write '{FUNCTION_MARK} REASON' "
        "above the def:\n" + "\n".join(functions)
    )


def test_no_long_module_without_its_reason():
    _, files = long_pieces()
    assert not files, (
        f"modules over {MAX_FILE} lines: split them or write '{FILE_MARK} REASON' in their "
        "first three lines:\n" + "\n".join(files)
    )


@pytest.mark.parametrize("marked", [False, True])
def test_the_size_check_can_fail(tmp_path, marked):
    package = tmp_path / "pkg"
    package.mkdir()
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION))
    mark = f"{FUNCTION_MARK} one flow\n" if marked else ""
    (package / "mod.py").write_text(f"{mark}def f():\n{body}\n", encoding="utf-8")
    padding = "\n".join(f"y{i} = {i}" for i in range(MAX_FILE + 1))
    head = f"{FILE_MARK} a table\n" if marked else ""
    (package / "big.py").write_text(f"{head}{padding}\n", encoding="utf-8")
    functions, files = long_pieces(package)
    assert (functions, files) == (
        ([], []) if marked else (["pkg/mod.py:1 f (81 lines)"], ["pkg/big.py (401 lines)"])
    )
