"""``x3dpd`` as a real process, for the tests that kill a run and resume it."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

TIMEOUT = 600  # a cold kernel cache compiles the step loop first


def x3dpd(*args, cwd) -> subprocess.CompletedProcess:
    """Run ``python -m x3dpd ARGS`` in ``cwd`` to its end."""
    return subprocess.run(
        [sys.executable, "-m", "x3dpd", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )


def kill_after_first_dump(*args, cwd, dump: Path) -> None:
    """Start ``python -m x3dpd ARGS`` and SIGKILL it as soon as ``dump`` exists."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "x3dpd", *map(str, args)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    t_end = time.monotonic() + TIMEOUT
    while not dump.exists() and proc.poll() is None and time.monotonic() < t_end:
        time.sleep(0.005)
    if proc.poll() is not None:
        pytest.fail(f"the run ended ({proc.returncode}) before it could be killed")
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
