"""Every kernel is compiled through x3dpd._jit, so compile flags live in one place.

A module that called ``numba.njit`` itself could silently turn on fastmath, drop the disk cache,
or (for the step loop) bring back numba's reference counting. Only ``x3dpd/_jit.py`` may name
numba's compile decorators (reading ``py_func`` off a user's own njit function is fine).
"""

from __future__ import annotations

import ast
import re
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
        bad += [
            f"{path.relative_to(PACKAGE)}:{line}: {what}"
            for line, what in _numba_compile_uses(tree)
        ]
    assert not bad, "compile through x3dpd._jit instead:\n" + "\n".join(bad)


def _seen_during_a_compile() -> dict:
    """The four patched numba methods (x3dpd._jit.PATCHES) as a real x3dpd compile sees them:
    read from inside the pipeline of a kernel compiling."""
    import numpy as np

    import x3dpd._jit as jit

    seen = {}

    class Probe(jit.X3dpdCompiler):
        def define_pipelines(self):
            seen.update({name: getattr(cls, name) for cls, name, _ in jit.PATCHES})
            return super().define_pipelines()

    assert jit.kernel(cache=False, pipeline_class=Probe)(lambda a: a.sum())(np.ones(2)) == 2.0
    return seen


def test_the_check_can_fail():
    tree = ast.parse("import numba\nf = numba.njit(lambda: 0)\nfrom numba import jit\n")
    assert sorted(_numba_compile_uses(tree)) == [(2, "numba.njit"), (3, "from numba import jit")]


def test_the_step_loop_runs_without_reference_counting():
    source = (PACKAGE / "solver" / "_advance_template.py").read_text()
    assert "@loop_kernel\ndef advance_packed(" in source


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


def test_vector_kernels_vectorize_loops_over_many_columns():
    """``x3dpd._jit.vector_kernel`` declares its array arguments ``noalias`` (a numba flag its
    pipeline class sets, ``VectorLoopCompiler``; pyproject.toml pins numba to versions where
    it works), and
    LLVM then vectorizes a loop shaped like the pair response: it gathers rows of 2-D arrays
    through an index list and writes a dozen columns. The same loop compiled without the flag
    stays scalar -- LLVM cannot rule out that a column overlaps the rows it reads (the check can
    fail)."""
    import math

    import numpy as np

    from x3dpd._jit import loop_kernel, vector_kernel

    def body(n, first, second, x, vel, o0, o1, o2, o3, o4, o5, o6, o7, o8, o9, o10, o11):
        for q in range(n):
            i = np.uint64(first[q])
            j = np.uint64(second[q])
            dx = x[j, 0] - x[i, 0]
            dy = x[j, 1] - x[i, 1]
            dz = x[j, 2] - x[i, 2]
            r = math.sqrt(dx * dx + dy * dy + dz * dz)
            inv = 1.0 / r
            o0[q] = dx * inv
            o1[q] = dy * inv
            o2[q] = dz * inv
            o3[q] = 0.1 - r
            o4[q] = o3[q] * math.sqrt(abs(o3[q]))
            o5[q] = vel[j, 0] - vel[i, 0]
            o6[q] = vel[j, 1] - vel[i, 1]
            o7[q] = vel[j, 2] - vel[i, 2]
            o8[q] = vel[i, 3] + vel[j, 3]
            o9[q] = vel[i, 4] + vel[j, 4]
            o10[q] = vel[i, 5] + vel[j, 5]
            o11[q] = r * inv

    vec = vector_kernel(cache=False)(body)
    plain = loop_kernel(inline="never", cache=False)(body)
    rng = np.random.default_rng(0)
    n = 37
    first, second = rng.integers(0, 20, n), rng.integers(20, 40, n)
    x, vel = rng.uniform(0.0, 1.0, (40, 3)), rng.normal(size=(40, 6))
    out_v = [np.zeros(n) for _ in range(12)]
    out_p = [np.zeros(n) for _ in range(12)]
    vec(n, first, second, x, vel, *out_v)
    plain(n, first, second, x, vel, *out_p)
    # bit for bit the same results (fastmath off: packed operations round as scalar ones)
    for a, b in zip(out_v, out_p):
        assert a.tobytes() == b.tobytes()
    packed_sqrt = re.compile(r"@llvm\.sqrt\.v\d+f64")
    assert packed_sqrt.search("".join(vec.inspect_llvm().values())), (
        "vector_kernel no longer vectorizes"
    )
    assert not packed_sqrt.search("".join(plain.inspect_llvm().values()))


def test_numba_inlines_through_the_copy_free_inliner():
    """x3dpd._jit replaces numba's ``InlineWorker.inline_function`` (private, numba 0.68) while
    an x3dpd kernel compiles, so that inlining a step kernel does not deep-copy its fresh IR
    twice. The patch works only while numba's inlining pass calls that method and ``inline_ir``
    copies through its module's ``copy``: if a numba upgrade changes either, this fails instead
    of compile time silently doubling."""
    import inspect

    from numba.core import inline_closurecall, untyped_passes

    import x3dpd._jit as jit

    assert _seen_during_a_compile()["inline_function"] is jit._inline_fresh_ir
    assert "inline_worker.inline_function(" in inspect.getsource(
        untyped_passes.InlineInlinables._do_work
    )
    assert "copy.deepcopy(" in inspect.getsource(inline_closurecall.InlineWorker.inline_ir)


def test_the_copy_free_inliner_computes_what_numba_inlines():
    """A step kernel inlined twice into one caller, with a branch and a loop, gives the
    values of the plain Python functions (the inlined IR is the same IR, uncopied)."""
    import numpy as np

    from x3dpd._jit import kernel, step_kernel

    @step_kernel
    def clipped_sum(a, lo):
        s = 0.0
        for v in a:
            s += v if v > lo else lo
        return s

    @kernel(cache=False)
    def twice(a):
        return clipped_sum(a, 0.5) - 2.0 * clipped_sum(a[::-1], 0.25)

    a = np.linspace(0.0, 1.0, 11)
    expect = sum(v if v > 0.5 else 0.5 for v in a) - 2.0 * sum(
        v if v > 0.25 else 0.25 for v in a[::-1]
    )
    assert twice(a) == expect


def test_numba_optimizes_through_the_once_only_step_loop_pass():
    """x3dpd._jit skips numba's per-function LLVM pass for step loops (``loop_kernel``; they
    are optimized whole after linking), patched in while an x3dpd kernel compiles. The patch
    works only while numba's code library runs that pass through ``_optimize_functions`` from
    ``add_llvm_module``: if a numba upgrade changes that, this fails instead of compile time
    silently growing."""
    import inspect

    from numba.core import codegen

    import x3dpd._jit as jit

    assert _seen_during_a_compile()["_optimize_functions"] is jit._optimize_functions_once
    assert "self._optimize_functions(" in inspect.getsource(codegen.CPUCodeLibrary.add_llvm_module)


def test_a_loop_optimized_once_computes_what_python_computes():
    """A step loop (registered in OPTIMIZED_ONCE, its function pass skipped) with an inlined
    step kernel, a branch and a loop-carried sum gives the plain Python values bit for bit; a
    loop kernel of its own (``inline="never"``) keeps both passes."""
    import numpy as np

    from x3dpd._jit import OPTIMIZED_ONCE, loop_kernel, step_kernel

    @step_kernel
    def _kick(v, f, h, k):
        v[k] += h * f[k] if f[k] > 0.0 else 0.5 * h * f[k]

    def once_loop(v, f, h, n):
        total = 0.0
        for _ in range(n):
            for k in range(v.shape[0]):
                _kick(v, f, h, k)
                total += v[k] * v[k]
        return total

    def own_pass(v):
        return v.sum()

    compiled = loop_kernel(cache=False)(once_loop)
    loop_kernel(inline="never", cache=False)(own_pass)
    assert once_loop.__qualname__ in OPTIMIZED_ONCE
    assert own_pass.__qualname__ not in OPTIMIZED_ONCE
    f = np.linspace(-1.0, 1.0, 7) ** 3
    v_jit = np.zeros(7)
    total = compiled(v_jit, f, 1e-3, 5)
    # the same arithmetic in Python
    v_ref = np.zeros(7)
    ref = 0.0
    for _ in range(5):
        for k in range(7):
            v_ref[k] += 1e-3 * f[k] if f[k] > 0.0 else 0.5 * 1e-3 * f[k]
            ref += v_ref[k] * v_ref[k]
    assert total == ref
    assert v_jit.tobytes() == v_ref.tobytes()


def test_numba_types_calls_through_the_memo():
    """x3dpd._jit remembers numba's resolved call types (``BaseFunction.get_call_type``,
    private, numba 0.68) while an x3dpd kernel compiles: a function with the same call many
    times resolves it once, gives the Python values, and a call numba cannot type still fails
    with numba's TypingError (failures are not remembered)."""
    import numpy as np
    import pytest
    from numba.core import errors
    from numba.core.types import functions

    import x3dpd._jit as jit
    from x3dpd._jit import kernel

    assert _seen_during_a_compile()["get_call_type"] is jit._memo_call_type
    assert functions.BaseFunction.get_call_type is jit._resolve_call_type  # numba's, outside
    resolved = []
    real = jit._resolve_call_type

    def counting(self, context, args, kws):
        resolved.append((self, tuple(args)))
        return real(self, context, args, kws)

    jit._resolve_call_type = counting
    try:

        @kernel(cache=False)
        def many(a):
            s = 0.0
            s += a[0] * 1.5
            s += a[1] * 1.5
            s += a[2] * 1.5
            s += a[3] * 1.5
            s += a[4] * 1.5
            s += a[5] * 1.5
            return s

        a = np.arange(6.0)
        assert many(a) == sum(x * 1.5 for x in a)
        # six getitems, six multiplications, six additions of the same types: each resolved once
        assert len(resolved) == len(set(resolved))

        @kernel(cache=False)
        def untypable(a):
            return a + "text"

        with pytest.raises(errors.TypingError):
            untypable(a)
        with pytest.raises(errors.TypingError):  # again: the failure was not remembered
            kernel(cache=False)(untypable.py_func)(a)
    finally:
        jit._resolve_call_type = real


def test_step_loops_compile_through_the_shorter_pipeline():
    """x3dpd._jit compiles step loops (``loop_kernel``) with numba's nopython pipeline less SSA
    reconstruction, the typed rewrites and the phi stripping (``StepLoopCompiler``, private
    numba 0.68 classes): the passes it leaves out must still exist under these names, and the
    pipeline it builds must hold numba's others and not those."""
    import numpy as np
    from numba.core import typed_passes, untyped_passes

    import x3dpd._jit as jit

    assert jit.STEP_LOOP_SKIPPED_PASSES == (
        typed_passes.NopythonRewrites,
        typed_passes.PreLowerStripPhis,
    )
    built = []

    class Probe(jit.StepLoopCompiler):
        def define_pipelines(self):
            pms = super().define_pipelines()
            built.append(([p for p, _ in pms[0].passes], self.state.flags.enable_ssa))
            return pms

    def loop(a):
        s = 0.0
        for v in a:
            s += v
        return s

    assert jit.kernel(cache=False, _nrt=False, pipeline_class=Probe)(loop)(np.ones(3)) == 3.0
    passes, ssa = built[0]
    assert ssa is False
    assert untyped_passes.ReconstructSSA not in passes
    assert not set(jit.STEP_LOOP_SKIPPED_PASSES) & set(passes)
    assert typed_passes.NopythonTypeInference in passes
    assert typed_passes.IRLegalization in passes
    assert typed_passes.NativeLowering in passes


def test_a_step_loop_with_one_name_of_two_types_falls_back_or_fails_strictly(monkeypatch):
    """Typed without SSA, a name given an int and, on one branch, a float does not type. A step loop
    with one compiles through numba's full pipeline instead (the same values as Python, its
    name in FULL_PIPELINE_FALLBACKS); under ``X3DPD_STRICT_STEP_LOOP=1``, as in this suite, the
    typing error is raised."""
    import numpy as np
    import pytest
    from numba.core import errors

    import x3dpd._jit as jit

    def two_types(a):
        total = 0.0
        for c in range(a.shape[0]):
            total += a[c]
        if total > 1.0:
            c = 0.5 * total  # the int index's name, now a float, where the branches join
        return c

    monkeypatch.setenv("X3DPD_STRICT_STEP_LOOP", "1")
    with pytest.raises(errors.TypingError):
        jit.loop_kernel(cache=False)(two_types)(np.arange(4.0))
    monkeypatch.setenv("X3DPD_STRICT_STEP_LOOP", "0")
    before = len(jit.FULL_PIPELINE_FALLBACKS)
    assert jit.loop_kernel(cache=False)(two_types)(np.arange(4.0)) == 3.0
    assert jit.FULL_PIPELINE_FALLBACKS[before:] == [two_types.__qualname__]


def test_numba_error_messages_are_built_without_colour():
    """x3dpd._jit makes numba's coloured markup (``HighlightColorScheme._markup``, private)
    return the message as it is while an x3dpd kernel compiles: building a colour sequence per
    message part cost ~1 CPU-s per step loop. The message text is unchanged."""
    from numba.core import errors

    import x3dpd._jit as jit

    scheme = errors.termcolor()
    with jit.x3dpd_compile():
        assert scheme.errmsg("no match") == "no match"
    if hasattr(errors, "HighlightColorScheme"):
        assert _seen_during_a_compile()["_markup"] is jit._plain_markup
