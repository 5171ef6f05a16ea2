"""How a replayed golden is compared with the committed one (tests/test_decks.py), on the
machine that made it and on another one.

A run is deterministic on one machine type: the step loop sums forces in a fixed order and is
compiled with ``fastmath`` off (x3dpd/_jit.py), so the same build on the same machine reproduces
a golden bit for bit; the 10-digit trace text then matches exactly (``rtol = 1e-9``,
``atol = 1e-12``: the text's last digit).

On another machine some numbers may come out one bit different: the modal algebra of the
MODAL decks goes through OpenBLAS, which picks its kernels by CPU (``OPENBLAS_CORETYPE=Haswell``
changes the modal step coefficients of decks/beam_64_modal.inp in their last bit on an
AVX-512 machine), and libm may differ. (numpy's ``exp`` did too -- its AVX-512 and AVX2
implementations differ in the last bit, which made the Maxwell step factors, and so the
modal goldens, differ between AVX-512 and AVX2 CPUs by 1e-6 of the structure's motion in
20 ms; they are computed by libm since.) Particle motion is chaotic and grows such a
difference about 10x per simulated millisecond, so no fixed tolerance fits every deck and
every time. Instead tools/regen_goldens.py measures, for each golden, how a one-ulp change of
an initial value and of a constant that every contact uses grows (the *rounding envelope*
E(t), PROVENANCE.json), and a replay on another machine must agree row by row within
``ROUNDING_MARGIN x E(t)`` (at least the text's last digit), over the rows where that bound is
still below ``CHAOS_CAP``: the window the chaos has not reached. The margin: on this
project's machine, the real rounding differences (OpenBLAS's Haswell kernels against its
SkylakeX ones; numpy's AVX2 exp against its AVX-512 one) stayed within 1.4x and 6x of the
envelope at every row; 100 leaves 16x to spare. A physical change is far larger: a change of
1e-4 in the particles' modulus moves beam_64 by 7e-6 of a column's scale within 3 ms, where
the bound is still the text's last digit (``test_a_physical_change_fails_its_golden``).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RTOL = 1e-9
ATOL = 1e-12
#: a replay on another machine: within this multiple of the rounding envelope (module docstring)
ROUNDING_MARGIN = 100.0
#: ... at least the text's last digit (10 significant digits) of the column's scale ...
TEXT_DIGIT = 1e-9
#: ... over the rows where the bound is below this: where the chaos has not yet taken over
CHAOS_CAP = 1e-4


def tool(name: str):
    """A script of tools/ as a module."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


regen = tool("regen_goldens")


def rounding_bound(prov: dict) -> np.ndarray:
    """Per output row, how far a replay on another machine may stray from the golden, as a
    fraction of each trace column's largest |value| (module docstring); NaN where the chaos has
    taken over (not compared)."""
    bound = np.maximum(TEXT_DIGIT, ROUNDING_MARGIN * np.asarray(prov["rounding_envelope"]))
    return np.where(bound <= CHAOS_CAP, bound, np.nan)


def agree_across_machines(a, b, prov: dict) -> tuple[bool, str]:
    """Whether trace ``a`` agrees with the golden ``b`` made on another machine: every row that
    ``rounding_bound`` compares within its bound. Returns (agree, what differs)."""
    bound = rounding_bound(prov)
    assert bound.shape[0] == a.times.size, "the golden's envelope has another number of rows"
    scale = np.maximum(np.abs(b.data).max(axis=(0, 1)), 1e-300)
    rel = (np.abs(a.data - b.data) / scale).max(axis=(1, 2))
    compared = ~np.isnan(bound)
    worst = np.argmax(np.where(compared, rel / np.where(compared, bound, 1.0), 0.0))
    ok = bool(np.all(rel[compared] <= bound[compared]))
    window = a.times[compared][-1] if compared.any() else a.times[0]
    text = (
        f"(golden from another machine) compared {int(compared.sum())} of {rel.size} rows, to "
        f"t = {window:.4g} s; worst row t = {a.times[worst]:.4g} s: {rel[worst]:.3g} of the "
        f"column scale against a bound of {bound[worst]:.3g} "
        f"({ROUNDING_MARGIN:g} x the rounding envelope, at least {TEXT_DIGIT:g})"
    )
    return ok, text


def same_machine(prov: dict) -> bool:
    """Whether this machine made the golden, as far as rounding goes: the CPU numba compiles for
    (which decides the instruction set numpy and OpenBLAS pick too) and the C library."""
    made = prov["machine"]
    return made.get("llvm_cpu") == regen.llvm_cpu() and made.get("libc") == regen.libc()
