"""How long compiling a step loop takes on this machine: a log beside the kernel cache, read
for the estimate the compile-progress line shows (``x3dpd run``'s "compiling ... about N s").

Each first run of a scene (a numba cache miss, x3dpd.solver.variants) appends its measured
compile time; the estimate is the median of the last :data:`KEEP` entries, or
:data:`DEFAULT_SECONDS` on a machine that has compiled nothing yet.
"""

from __future__ import annotations

import json
import os
import statistics
from pathlib import Path

from x3dpd.solver.variants import cache_dir

#: Compile times kept in the log.
KEEP = 20
#: Estimate before this machine has compiled anything [s] (this machine, 2 cores, idle).
DEFAULT_SECONDS = 30.0


def _log_path() -> Path:
    # beside the source-hash folders: compile times carry over from one x3dpd revision to the next
    return cache_dir().parent / "compile_times.json"


def recorded_compile_seconds() -> list[float]:
    """The compile times logged on this machine, oldest first [s] (none if unreadable)."""
    try:
        data = json.loads(_log_path().read_text())
        return [float(x) for x in data if float(x) > 0.0]
    except (OSError, ValueError, TypeError):
        return []


def expected_compile_seconds() -> float:
    """The median of the logged compile times, or :data:`DEFAULT_SECONDS` [s]."""
    times = recorded_compile_seconds()
    return statistics.median(times[-KEEP:]) if times else DEFAULT_SECONDS


def record_compile_seconds(seconds: float) -> None:
    """Append one measured compile time to the log (atomically; a failure is ignored: the log
    only feeds an estimate)."""
    times = (recorded_compile_seconds() + [round(float(seconds), 2)])[-KEEP:]
    path = _log_path()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".tmp{os.getpid()}")
        tmp.write_text(json.dumps(times))
        os.replace(tmp, path)
    except OSError:
        pass
