"""The one place that decides how x3dpd compiles kernels.

Every kernel uses :func:`kernel` instead of ``numba.njit`` so that compile flags are never
hard-coded (``tests/meta/test_kernel_flags.py`` enforces this). ``fastmath`` stays off: contact
laws take square roots of small differences and the energy ledger sums many tiny terms, and
reassociation would make runs irreproducible across machines.

Every kernel compiles through a pipeline class of this module (:class:`X3dpdCompiler`, and
:class:`StepLoopCompiler` for the step loops), which puts x3dpd's compile-time changes to numba's
internals in place for the length of that compile only (:func:`x3dpd_compile`). Importing
x3dpd changes nothing in numba: a user's own ``numba.njit`` functions compile as numba compiles
them (``tests/meta/test_numba_untouched.py``).
"""

from __future__ import annotations

import contextlib
import os

import numba
from numba.core import compiler as _numba_compiler
from numba.core.compiler_lock import global_compiler_lock as _numba_compiler_lock

#: Flags shared by all kernels. ``cache=True`` stores compiled machine code beside the sources
#: (or in NUMBA_CACHE_DIR) so a second run starts in about a second.
JIT_FLAGS = {
    "cache": True,
    "fastmath": False,
    "error_model": "numpy",
    "nogil": True,
    # explicit, so that a kernel first compiled from inside a loop kernel keeps numba's
    # runtime: numba lets an unset flag inherit the caller's _nrt=False, and an
    # allocating kernel (a list rebuild) then fails to compile (a fresh checkout
    # resuming a state from a warm kernel cache stopped with a TypingError)
    "_nrt": True,
}

#: True when NUMBA_DISABLE_JIT=1 (coverage runs of the kernels in pure Python).
JIT_DISABLED = os.environ.get("NUMBA_DISABLE_JIT", "0") == "1"


def step_kernel(fn=None, **overrides):
    """Compile a function called once per time step from the step loop, inlined into its caller.

    A call between jitted functions passes every array with its reference count (atomic
    increments and decrements); a per-step function taking dozens of arrays would spend more on
    that than on its physics. ``inline="always"`` splices it into the loop at numba-IR level.
    """
    return kernel(fn, inline="always", **overrides)


def shared_kernel(fn=None, **overrides):
    """Compile a per-step function that is the same in every step-loop variant -- it reads no
    variant constant -- as a function of its own that every variant calls: compiled once and
    cached beside its source, instead of inlined into (and compiled again with) each variant's
    loop. Without NRT like the loop, so that the call passes its arrays without reference
    counting (it may not allocate). For functions called once or twice per step of scenes
    whose steps are long (with contacts), never per contact: a call passes every array's
    descriptor and loses the caller's constants, tens to hundreds of instructions
    (docs/engine.md, "Compile time")."""
    return kernel(fn, inline="never", _nrt=False, **overrides)


def loop_kernel(fn=None, **overrides):
    """Compile a time-step loop: a kernel that allocates nothing and runs numba without its
    reference-counting runtime (NRT).

    Every array the loop touches belongs to its Python caller, so the atomic increments and
    decrements numba emits around each inlined call's array arguments are pure overhead -- 21 %
    of the step time at 50 particles, measured with ``perf``. Without NRT they vanish; the price
    is that the loop may not create arrays (``np.empty``, array-valued slice assignment): it
    receives its scratch space as arguments instead. Calls from the loop to ordinary kernels
    (which may allocate) remain allowed.

    A step loop (not ``inline="never"``: a loop's own pass, see ``_template_pairs``) is
    optimized by LLVM once, after linking, instead of twice (:data:`OPTIMIZED_ONCE`). Every
    loop kernel compiles through numba's pipeline less the passes that do nothing for it
    (:class:`StepLoopCompiler`): a name in it keeps one type.
    """
    if fn is None:
        return lambda f: loop_kernel(f, **overrides)
    if overrides.get("inline") != "never":
        OPTIMIZED_ONCE.add(fn.__qualname__)
    return kernel(fn, _nrt=False, pipeline_class=StepLoopCompiler, **overrides)


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
    return kernel(fn, inline="never", _nrt=False, pipeline_class=VectorLoopCompiler, **overrides)


def threaded_kernel(fn=None, **overrides):
    """Compile a loop whose ``numba.prange`` iterations numba runs on several threads
    (``parallel=True``, its threading layer; as many as ``numba.set_num_threads`` allows the
    calling thread): its own function, never inlined, without NRT like the step loop. Only the
    threaded step-loop variants (``Variant.threaded``) call one, so the single-thread loops
    compile none of numba's parallel machinery. Its iterations must be independent: a thread
    count must never change a result (docs/engine.md, "Threads")."""
    return kernel(fn, inline="never", _nrt=False, parallel=True, **overrides)


def kernel(fn=None, **overrides):
    """Compile ``fn`` with the project's flags: ``@kernel`` or ``@kernel(cache=False)``; through
    numba's own pipeline with x3dpd's compile-time patches (:class:`X3dpdCompiler`) unless
    ``pipeline_class`` says otherwise."""
    flags = {**JIT_FLAGS, "pipeline_class": X3dpdCompiler, **overrides}
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
        return self.inline_ir(
            caller_ir, block, i, callee_ir, function.__code__.co_freevars, arg_typs=arg_typs
        )
    finally:
        _numba_inline.copy = saved


# ---- compile time: the step loop optimized once by LLVM, not twice -------------------------
# numba optimizes every function it lowers with LLVM's full -O3 function pipeline before
# linking (``CPUCodeLibrary._optimize_functions``: to shrink the IR and let its reference-count
# pruning see whole functions), and then the linked module once more with the full -O3 module
# pipeline, which runs the same function simplification again. The step loop has no reference
# counts to prune (loop_kernel: no NRT) and is optimized as a whole after linking anyway; its
# first pass cost as much as the second (beam_64: 4.2 of 7.7 CPU-s of LLVM, SROA on numba's
# allocas most of it). Libraries of OPTIMIZED_ONCE functions skip it. Private behaviour of
# numba 0.68 (pinned; tests/meta/test_kernel_flags.py checks the method is still called).
from numba.core import codegen as _numba_codegen  # noqa: E402

#: Qualified names of the step loops (x3dpd._jit.loop_kernel) LLVM optimizes once.
OPTIMIZED_ONCE: set[str] = set()
_optimize_functions = _numba_codegen.CPUCodeLibrary._optimize_functions


def _optimize_functions_once(self, ll_module):
    """``CPUCodeLibrary._optimize_functions``, skipped (but for the data layout it sets) for
    the libraries of :data:`OPTIMIZED_ONCE` functions."""
    if self.name in OPTIMIZED_ONCE:
        ll_module.data_layout = self._codegen._data_layout
        return
    _optimize_functions(self, ll_module)


# ---- compile time: numba's call typing, resolved once per (function, argument types) -------
# numba types every call -- ``a + b``, ``x[i, 0]``, ``math.sqrt(v)`` -- by trying the
# function's typing templates in turn (``BaseFunction.get_call_type``), each a Python call that
# may build a dispatcher or format an error message, for every call site anew. The step loop's
# ~7000 call sites have ~700 distinct (function, argument types): on beam_64 this took 3.3 of
# 26 CPU-s, 0.5 with a memo. The memo holds successful resolutions per compile flags (a
# template's answer depends on nothing else; a new template for the function changes the
# key); failures are not kept. Private behaviour of numba 0.68 (pinned; checked by
# tests/meta/test_kernel_flags.py).
from numba.core import targetconfig as _numba_targetconfig  # noqa: E402
from numba.core.types import functions as _numba_functions  # noqa: E402

_resolve_call_type = _numba_functions.BaseFunction.get_call_type
#: id(flags) -> (flags, {(function type, context, args, kws, templates): (signature, its
#: implementation key)}); the flags object is held so that its id is not reused while its memo
#: lives; the newest 8 kept
_CALL_TYPES: dict = {}


def _memo_call_type(self, context, args, kws):
    """``BaseFunction.get_call_type``, remembering each signature it resolved."""
    flags = _numba_targetconfig.ConfigStack.top_or_none()
    entry = _CALL_TYPES.get(id(flags))
    if entry is None or entry[0] is not flags:
        if len(_CALL_TYPES) >= 8:
            del _CALL_TYPES[next(iter(_CALL_TYPES))]
        entry = _CALL_TYPES[id(flags)] = (flags, {})
    try:
        key = (self, context, tuple(args), tuple(kws.items()), len(self.templates))
        known = entry[1].get(key)
    except TypeError:  # an unhashable argument type: resolve as numba does
        return _resolve_call_type(self, context, args, kws)
    if known is not None:
        sig, impl_key = known
        self._impl_keys[sig.args] = impl_key  # as the resolution did (lowering reads it)
        return sig
    sig = _resolve_call_type(self, context, args, kws)
    if sig is not None:
        entry[1][key] = (sig, self._impl_keys[sig.args])
    return sig


# ---- compile time: numba's error messages without terminal colours -------------------------
# numba formats an error message, in colour, for every typing template that does not fit a
# call and for every global it cannot type, though it throws nearly all of them away: ~17,000
# colour markups (colorama's stream wrappers, one per message part) per step loop. The plain
# scheme numba uses in its own test suite (NUMBA_DISABLE_ERROR_MESSAGE_HIGHLIGHTING) costs
# nothing; x3dpd reports its own errors, so the colours were never seen.


def _plain_markup(self, msg, color=None, style=None):
    """numba's coloured ``_markup``, the message as it is."""
    return msg


# ---- the patches above, in place for x3dpd's own compiles only ------------------------------
# The four replacements above change private methods of numba's classes. They are installed
# when an x3dpd kernel starts compiling (X3dpdCompiler, the pipeline class of every kernel of
# this module) and the originals put back when it ends, so that a user's own numba functions,
# compiled before, after or beside x3dpd's, compile with numba as it is. numba compiles one
# function at a time per process (its global compiler lock, held here too), so no other
# compile runs while they are in place; what an x3dpd compile compiles on its way (the kernels
# it calls, numba's own overloads of numpy functions) compiles with them, as it always did.
from numba.core import errors as _numba_errors  # noqa: E402

#: (class, method name, x3dpd's replacement) of each patch, for the length of an x3dpd compile
PATCHES = (
    (_numba_inline.InlineWorker, "inline_function", _inline_fresh_ir),
    (_numba_codegen.CPUCodeLibrary, "_optimize_functions", _optimize_functions_once),
    (_numba_functions.BaseFunction, "get_call_type", _memo_call_type),
) + (
    ((_numba_errors.HighlightColorScheme, "_markup", _plain_markup),)
    if hasattr(_numba_errors, "HighlightColorScheme")
    else ()
)
_MISSING = object()
#: nesting depth of :func:`x3dpd_compile` (an x3dpd kernel compiling the kernels it calls)
_DEPTH = [0]


@contextlib.contextmanager
def x3dpd_compile():
    """Hold numba's compiler lock with :data:`PATCHES` in place; the originals return when the
    outermost of nested uses ends (re-entrant: a kernel compiles the kernels it calls)."""
    with _numba_compiler_lock:
        saved = None
        if _DEPTH[0] == 0:
            saved = [(cls, name, cls.__dict__.get(name, _MISSING)) for cls, name, _ in PATCHES]
            for cls, name, new in PATCHES:
                setattr(cls, name, new)
        _DEPTH[0] += 1
        try:
            yield
        finally:
            _DEPTH[0] -= 1
            if saved is not None:
                for cls, name, old in saved:
                    if old is _MISSING:
                        delattr(cls, name)
                    else:
                        setattr(cls, name, old)


class X3dpdCompiler(_numba_compiler.Compiler):
    """numba's own pipeline (``numba.core.compiler.Compiler``), run with x3dpd's compile-time
    patches in place (:func:`x3dpd_compile`): the pipeline class of every x3dpd kernel."""

    def compile_extra(self, func):
        with x3dpd_compile():
            return super().compile_extra(func)

    def compile_ir(self, func_ir, lifted=(), lifted_from=None):
        with x3dpd_compile():
            return super().compile_ir(func_ir, lifted, lifted_from)


# ---- compile time: the step loop through a shorter numba pipeline ---------------------------
# Three of numba's passes over the one large inlined step loop do nothing for it but cost time
# in proportion to its size (beam_64, ``tools/bench/compile_profile.py``): SSA reconstruction
# (1.6 CPU-s; numba types a variable that is assigned several times from the union of its
# assignments instead, as it did before SSA, so the loop's sources keep each variable to one
# type), the typed rewrites (1.1 CPU-s: array expressions, constant arrays and string-literal
# indices, none of which a step loop has -- it allocates nothing -- but each rewrite pass
# re-derives every variable's lifetime), and the removal of SSA's phi nodes (0.4 CPU-s; the
# legalization pass after it rebuilds what that pass refreshes). Private behaviour of numba 0.68
# (pinned; tests/meta/test_kernel_flags.py checks the pass names). The step loops and the pair
# passes (``loop_kernel``, ``vector_kernel``) compile through it; their results are those of
# numba's full pipeline, bit for bit (every golden and API = CLI byte test).
from numba.core import compiler_machinery as _numba_machinery  # noqa: E402
from numba.core import typed_passes as _numba_typed_passes  # noqa: E402

#: The passes the step loops skip.
STEP_LOOP_SKIPPED_PASSES = (
    _numba_typed_passes.NopythonRewrites,
    _numba_typed_passes.PreLowerStripPhis,
)


class StepLoopCompiler(X3dpdCompiler):
    """numba's nopython pipeline for a step loop (:func:`loop_kernel`): without SSA
    reconstruction and without :data:`STEP_LOOP_SKIPPED_PASSES`.

    Typed without SSA, a name assigned values of two types (an int index and a float) does not
    type; then the loop is compiled again with numba's full pipeline, and its name is added to
    :data:`FULL_PIPELINE_FALLBACKS` -- or, with ``X3DPD_STRICT_STEP_LOOP=1`` (the test suite),
    the typing error is raised, so that such a name in the step kernels fails the tests instead
    of slowing a compile down."""

    def __init__(self, typingctx, targetctx, library, args, return_type, flags, locals):
        self._flags = flags  # as given: the full pipeline's, should this one fail
        super().__init__(typingctx, targetctx, library, args, return_type, flags, locals)

    def define_pipelines(self):
        self.state.flags = self.state.flags.copy()
        self.state.flags.enable_ssa = False
        full = _numba_compiler.DefaultPassBuilder.define_nopython_pipeline(self.state)
        pm = _numba_machinery.PassManager("x3dpd_step_loop")
        for pss, description in full.passes:
            if pss not in STEP_LOOP_SKIPPED_PASSES:
                pm.add_pass(pss, description)
        pm.finalize()
        return [pm]

    def compile_extra(self, func):
        try:
            return super().compile_extra(func)
        except _numba_errors.TypingError:
            if os.environ.get("X3DPD_STRICT_STEP_LOOP", "0") == "1":
                raise
            FULL_PIPELINE_FALLBACKS.append(func.__qualname__)
            s = self.state
            return X3dpdCompiler(
                s.typingctx, s.targetctx, None, s.args, s.return_type, self._flags, s.locals
            ).compile_extra(func)


#: Step loops that did not type without SSA and were compiled by numba's full pipeline.
FULL_PIPELINE_FALLBACKS: list[str] = []


class VectorLoopCompiler(StepLoopCompiler):
    """:class:`StepLoopCompiler` with numba's ``noalias`` flag: every array argument of the
    compiled function is declared not to overlap any other (:func:`vector_kernel`). numba has
    the flag (its parallel backend sets it for its own loop bodies) but no option for it; a
    pipeline class of its own sets it for x3dpd's vector kernels alone. Private behaviour:
    pinned numba range in pyproject.toml, checked by tests/meta/test_kernel_flags.py."""

    def __init__(self, typingctx, targetctx, library, args, return_type, flags, locals):
        flags = flags.copy()
        flags.noalias = True
        super().__init__(typingctx, targetctx, library, args, return_type, flags, locals)
