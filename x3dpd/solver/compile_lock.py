"""One compile of a step-loop variant at a time, across processes.

Two processes that start the same new scene at once (a sweep's or a design's Dask workers, the
test suite's workers) would each compile the variant for half a minute and each write the same
numba cache entry. :func:`variant_compile_lock` makes the second wait for the first, then load
the machine code the first wrote to the kernel cache: one compile instead of two, and a core
free meanwhile.

The lock is an exclusive ``flock`` on a file beside the variant's generated sources (POSIX; where
``fcntl`` is missing it does nothing). It is taken around a Simulation's first calls of its
kernels, where numba compiles or loads them; with a warm cache it is held for milliseconds.
Re-entry from the same thread is a no-op, so nested use cannot deadlock.

Held, the lock is also where the kernel cache learns what happened: the block is timed and the
variant booked in the cache's manifest as compiled (with its compile seconds) or loaded
(x3dpd.solver.kernel_cache.watch_first_calls).
"""

from __future__ import annotations

import contextlib
import os
import threading
from pathlib import Path

from x3dpd.solver.kernel_cache import watch_first_calls

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows: no cross-process lock
    fcntl = None

_HELD = threading.local()


@contextlib.contextmanager
def variant_compile_lock(folder: Path, module_name: str):
    """Hold the compile lock of the generated loop module ``module_name`` (in ``folder``)."""
    held = getattr(_HELD, "names", None)
    if held is None:
        held = _HELD.names = set()
    if module_name in held:
        yield
        return
    if fcntl is None:
        with watch_first_calls(folder, module_name):
            yield
        return
    try:
        fd = os.open(Path(folder) / f"{module_name}.lock", os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:  # an unwritable cache folder: compile without the lock
        with watch_first_calls(folder, module_name):
            yield
        return
    held.add(module_name)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        with watch_first_calls(folder, module_name):
            yield
    finally:
        held.discard(module_name)
        os.close(fd)  # closing the descriptor releases the lock
