"""How many threads one run's step loop uses (the run option ``threads``; docs/engine.md,
"Threads").

One thread is the default: the single-thread loop is the one every golden was recorded with,
and sweeps, studies and designs already keep every core busy with one run per worker process.
More threads select a threaded loop variant (``Variant.threaded``), in which the pair contacts'
filter and response run in chunks on numba's threads; the results are the same bits whatever
the count.
"""

from __future__ import annotations

import numba
from numba.np.ufunc import parallel as _numba_parallel

from x3dpd.errors import InputError

#: the ``threads`` value that asks for every core numba sees
AUTO = "auto"


def available() -> int:
    """The threads numba may start: ``NUMBA_NUM_THREADS`` as it was when numba was imported
    (by default the cores it sees; numba's limit for ``set_num_threads`` is fixed then, whatever
    the environment says later)."""
    return int(_numba_parallel.NUM_THREADS)


def thread_count(value, option: str = "threads") -> int:
    """The thread count the option ``threads`` asks for: a whole number from 1 to
    :func:`available`, or ``"auto"`` (all of them). Anything else is an InputError that names
    ``option`` (the CLI's ``--threads``) and the limit."""
    if isinstance(value, str):
        text = value.strip().lower()
        if text == AUTO:
            return available()
        try:
            value = int(text)
        except ValueError:
            raise InputError(f"{option}: expected a whole number of threads or 'auto', got "
                             f"{value!r}") from None
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise InputError(f"{option}: expected a whole number >= 1 or 'auto', got {value!r}")
    if value > available():
        raise InputError(f"{option}: {value} is more than the {available()} threads numba may "
                         "start on this machine (NUMBA_NUM_THREADS; 'auto' takes them all)")
    return value


def use_threads(count: int) -> None:
    """Let the compiled loop called next from this thread run on ``count`` threads (numba's
    setting is per calling thread)."""
    numba.set_num_threads(count)
