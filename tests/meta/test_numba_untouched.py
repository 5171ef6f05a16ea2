"""Importing x3dpd leaves numba as it is for the user's own code (issue 32 item 3).

x3dpd changes four private methods of numba to compile its step loops faster
(x3dpd._jit.PATCHES); they are in place only while an x3dpd kernel compiles (its pipeline
class, x3dpd._jit.X3dpdCompiler). These tests look from outside: a fresh process records
numba's methods, imports x3dpd and compiles x3dpd kernels (one of them failing), then compiles
the user's own functions -- and finds numba's own methods, numba's coloured error messages,
no memo of the user's call types and no option of x3dpd's in numba's option table.
tests/meta/test_kernel_flags.py checks the other side: x3dpd's kernels still compile with them.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = r"""
import json

import numpy as np
from numba.core import codegen, cpu, errors, inline_closurecall
from numba.core.types import functions

KINDS = [(inline_closurecall.InlineWorker, "inline_function"),
         (codegen.CPUCodeLibrary, "_optimize_functions"),
         (functions.BaseFunction, "get_call_type")]
if hasattr(errors, "HighlightColorScheme"):
    KINDS.append((errors.HighlightColorScheme, "_markup"))


def methods():
    return {f"{cls.__name__}.{name}": cls.__dict__[name] for cls, name in KINDS}


def options():
    return sorted(k for k in dir(cpu.CPUTargetOptions) if not k.startswith("__"))


def message(fn, *args):
    try:
        fn(*args)
    except errors.TypingError as exc:
        return str(exc)
    return ""


before, options_before = methods(), options()

import numba  # noqa: E402

import x3dpd.api  # noqa: E402,F401  (every kernel module: the solver, the laws, the shapes)
import x3dpd._jit as jit  # noqa: E402


@jit.step_kernel(cache=False)
def _twice(v):
    return 2.0 * v


@jit.loop_kernel(cache=False)
def x3dpd_loop(a):
    s = 0.0
    for v in a:
        s += _twice(v)
    return s


assert x3dpd_loop(np.ones(3)) == 6.0
x3dpd_message = message(jit.kernel(cache=False)(lambda a: a + "text"), 1.0)  # fails to compile
memo = sum(len(entry[1]) for entry in jit._CALL_TYPES.values())


@numba.njit(inline="always")
def _user_twice(v):
    return 2.0 * v


@numba.njit
def user_loop(a):
    s = 0.0
    for v in a:
        s += _user_twice(v)
    return s


@numba.njit
def user_bad(a):
    return a + "text"


assert user_loop(np.ones(3)) == 6.0
user_message = message(user_bad, 1.0)
after = methods()
print(json.dumps({
    "same": {k: after[k] is before[k] for k in before},
    "numba_modules": sorted({after[k].__module__ for k in after}),
    "options_same": options() == options_before,
    "memo_grew": sum(len(entry[1]) for entry in jit._CALL_TYPES.values()) != memo,
    "colour": errors.termcolor().__class__.__name__ == "HighlightColorScheme",
    "x3dpd_ansi": "\x1b[" in x3dpd_message,
    "user_ansi": "\x1b[" in user_message,
    "user_failed": bool(user_message),
}))
"""


def _probe() -> dict:
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("NUMBA_DISABLE_ERROR_MESSAGE_HIGHLIGHTING", "NUMBA_DISABLE_JIT")
    }
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_importing_and_compiling_x3dpd_leaves_numba_as_it_is_for_user_code():
    seen = _probe()
    # numba's own method objects, after x3dpd compiled (and failed to compile) its kernels
    assert all(seen["same"].values()), seen["same"]
    assert all(m.startswith("numba.") for m in seen["numba_modules"]), seen["numba_modules"]
    # no option of x3dpd's (the former ``_noalias``) in numba's CPU option table
    assert seen["options_same"]
    # the user's function typed its calls without x3dpd's memo
    assert seen["user_failed"] and not seen["memo_grew"]
    if seen["colour"]:
        # numba's coloured error message for the user; x3dpd's own compile built it plainly
        assert seen["user_ansi"]
        assert not seen["x3dpd_ansi"]


def test_the_patches_are_in_place_only_inside_an_x3dpd_compile():
    """The same in this process, from inside: outside :func:`x3dpd._jit.x3dpd_compile` every
    patched method is numba's; inside it x3dpd's; nested uses restore numba's only when the
    outermost ends, and an error inside restores them too."""
    import pytest

    import x3dpd._jit as jit

    def now():
        return [cls.__dict__.get(name) for cls, name, _ in jit.PATCHES]

    numba_own = now()
    ours = [new for _, _, new in jit.PATCHES]
    assert all(a is not b for a, b in zip(numba_own, ours))
    with jit.x3dpd_compile():
        assert now() == ours
        with jit.x3dpd_compile():
            assert now() == ours
        assert now() == ours
    assert now() == numba_own
    with pytest.raises(RuntimeError):
        with jit.x3dpd_compile():
            raise RuntimeError("a compile that fails")
    assert now() == numba_own
