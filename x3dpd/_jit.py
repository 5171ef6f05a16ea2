"""The one place that decides how x3dpd compiles kernels.

Every kernel uses :func:`kernel` instead of ``numba.njit`` so that compile flags are never
hard-coded (``tests/meta/test_kernel_flags.py`` enforces this). ``fastmath`` stays off: contact
laws take square roots of small differences and the energy ledger sums many tiny terms, and
reassociation would make runs irreproducible across machines.
"""

from __future__ import annotations

import os

import numba
from numba.core import cpu as _numba_cpu
from numba.core import options as _numba_options

#: Flags shared by all kernels. ``cache=True`` stores compiled machine code beside the sources
#: (or in NUMBA_CACHE_DIR) so a second run starts in about a second.
JIT_FLAGS = {"cache": True, "fastmath": False, "error_model": "numpy", "nogil": True,
             # explicit, so that a kernel first compiled from inside a loop kernel keeps numba's
             # runtime: numba lets an unset flag inherit the caller's _nrt=False, and an
             # allocating kernel (a list rebuild) then fails to compile (a fresh checkout
             # resuming a state from a warm kernel cache stopped with a TypingError)
             "_nrt": True}

#: True when NUMBA_DISABLE_JIT=1 (coverage runs of the kernels in pure Python).
JIT_DISABLED = os.environ.get("NUMBA_DISABLE_JIT", "0") == "1"


def step_kernel(fn=None, **overrides):
    """Compile a function called once per time step from the step loop, inlined into its caller.

    A call between jitted functions passes every array with its reference count (atomic
    increments and decrements); a per-step function taking dozens of arrays would spend more on
    that than on its physics. ``inline="always"`` splices it into the loop at numba-IR level.
    """
    return kernel(fn, inline="always", **overrides)


def loop_kernel(fn=None, **overrides):
    """Compile a time-step loop: a kernel that allocates nothing and runs numba without its
    reference-counting runtime (NRT).

    Every array the loop touches belongs to its Python caller, so the atomic increments and
    decrements numba emits around each inlined call's array arguments are pure overhead -- 21 %
    of the step time at 50 particles, measured with ``perf``. Without NRT they vanish; the price
    is that the loop may not create arrays (``np.empty``, array-valued slice assignment): it
    receives its scratch space as arguments instead. Calls from the loop to ordinary kernels
    (which may allocate) remain allowed.
    """
    return kernel(fn, _nrt=False, **overrides)


# numba has a compiler flag that marks every array argument ``noalias`` (its parallel backend
# sets it for its own loop bodies) but no public option for it; this maps the option ``_noalias``
# onto it, as numba maps ``_nrt`` onto its flag. Private behaviour: pinned numba range in
# pyproject.toml, checked by tests/meta/test_kernel_flags.py.
if not hasattr(_numba_cpu.CPUTargetOptions, "_noalias"):
    _numba_cpu.CPUTargetOptions._noalias = _numba_options._mapping("noalias")


def vector_kernel(fn=None, **overrides):
    """Compile a loop over contiguous columns that LLVM should vectorize: its own function
    (never inlined), without NRT like the step loop, and with every array argument declared
    not to overlap any other (LLVM ``noalias``).

    LLVM vectorizes a loop only when it can prove that its stores do not feed its loads. A loop
    that gathers rows of 2-D arrays through an index list and writes columns gives it no such
    proof (a column might overlap the rows it reads), and it stays scalar: the pair response
    ran 39.8 instead of 26 us per step on the settled bed of 512. The caller promises what
    ``noalias`` says: no two array arguments share memory that the function writes (distinct
    arrays, or distinct rows of one array). Results are bit for bit those of the scalar loop:
    ``fastmath`` stays off, so the packed instructions round exactly as the scalar ones do.
    """
    return kernel(fn, inline="never", _nrt=False, _noalias=True, **overrides)


def kernel(fn=None, **overrides):
    """Compile ``fn`` with the project's flags: ``@kernel`` or ``@kernel(cache=False)``."""
    flags = {**JIT_FLAGS, **overrides}
    if fn is None:
        return lambda f: numba.njit(**flags)(f)
    return numba.njit(**flags)(fn)


# ---- compile time: numba's IR inliner without its copies of the callee's IR ----------------
# Every ``step_kernel`` call is spliced into its caller by numba's ``InlineInlinables`` pass
# (``InlineWorker.inline_function``), which translates the callee afresh (``run_untyped_passes``)
# and then deep-copies that fresh IR twice (``inline_ir``: a working copy and an "unmutated
# original" that this pass throws away). Each copy deep-copies, per block, the callee's whole
# variable scope, so the copies grow as blocks x variables: on the beam_64 scene they were
# ~85 % of the inlining pass (1.55 million ``ir.Var`` copies, cProfile). The fresh IR belongs
# to nobody else, so inlining it as it is gives the same IR with no copy at all. Private
# behaviour of numba 0.68 (pinned in pyproject.toml; tests/meta/test_kernel_flags.py checks
# that the patched function is still the one numba calls).
from numba.core import inline_closurecall as _numba_inline  # noqa: E402


class _NoCopy:
    """Stands in for the ``copy`` module inside ``InlineWorker.inline_ir`` while
    :func:`_inline_fresh_ir` runs: "copies" are the IR itself."""

    @staticmethod
    def deepcopy(x, memo=None):
        return x


def _inline_fresh_ir(self, caller_ir, block, i, function, arg_typs=None):
    """``InlineWorker.inline_function``, inlining the callee's freshly translated IR in place
    instead of two deep copies of it (same IR, same machine code)."""
    callee_ir = self.run_untyped_passes(function)
    saved = _numba_inline.copy
    _numba_inline.copy = _NoCopy
    try:
        return self.inline_ir(caller_ir, block, i, callee_ir, function.__code__.co_freevars,
                              arg_typs=arg_typs)
    finally:
        _numba_inline.copy = saved


if not JIT_DISABLED:
    _numba_inline.InlineWorker.inline_function = _inline_fresh_ir
