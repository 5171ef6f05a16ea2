"""Every kernel is compiled through x3dpd._jit, so compile flags live in one place.

A module that called ``numba.njit`` itself could silently turn on fastmath, drop the disk cache,
or (for the step loop) bring back numba's reference counting. Only ``x3dpd/_jit.py`` may name
numba's compile decorators (reading ``py_func`` off a user's own njit function is fine).
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "x3dpd"
DECORATORS = {"njit", "jit", "generated_jit", "vectorize", "guvectorize", "cfunc"}


def _numba_compile_uses(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr in DECORATORS:
            if isinstance(node.value, ast.Name) and node.value.id == "numba":
                yield node.lineno, f"numba.{node.attr}"
        elif isinstance(node, ast.ImportFrom) and node.module == "numba":
            for alias in node.names:
                if alias.name in DECORATORS:
                    yield node.lineno, f"from numba import {alias.name}"


def test_only_the_jit_module_names_numba_compile_decorators():
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name == "_jit.py":
            continue
        tree = ast.parse(path.read_text(), filename=str(path))
        bad += [f"{path.relative_to(PACKAGE)}:{line}: {what}"
                for line, what in _numba_compile_uses(tree)]
    assert not bad, "compile through x3dpd._jit instead:\n" + "\n".join(bad)


def test_the_check_can_fail():
    tree = ast.parse("import numba\nf = numba.njit(lambda: 0)\nfrom numba import jit\n")
    assert sorted(_numba_compile_uses(tree)) == [(2, "numba.njit"), (3, "from numba import jit")]


def test_the_step_loop_runs_without_reference_counting():
    source = (PACKAGE / "solver" / "_advance_template.py").read_text()
    assert "@loop_kernel\ndef advance(" in source


def test_loop_kernels_really_compile_without_reference_counting():
    """The private ``_nrt=False`` option of numba (x3dpd._jit.loop_kernel) must still remove the
    reference counting around array arguments; pyproject.toml pins numba to versions where it
    does. A plain kernel of the same code keeps it (the check can fail)."""
    import numpy as np

    from x3dpd._jit import kernel, loop_kernel, step_kernel

    def body(a, b):
        for i in range(a.shape[0]):
            a[i] += _inner(b, i)

    @step_kernel
    def _inner(b, i):
        return b[i] * 2.0

    free = loop_kernel(cache=False)(body)
    counted = kernel(cache=False)(body)
    a, b = np.zeros(4), np.arange(4.0)
    free(a, b)
    counted(a, b)
    assert a.tolist() == [0.0, 4.0, 8.0, 12.0]
    ir_free = "".join(free.inspect_llvm().values())
    ir_counted = "".join(counted.inspect_llvm().values())
    assert "NRT_incref" not in ir_free and "NRT_decref" not in ir_free
    assert "NRT_incref" in ir_counted or "NRT_decref" in ir_counted
