"""SIGKILL in the middle of a hard run, then --restart: nothing lost.

The scene is the packed cavity shaken at 10 g (test_beds.py): every particle has lasting contacts
whose Maxwell histories and friction states must survive the dump. The resumed run's trace and
energy file must equal the uninterrupted run's byte for byte.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest
from test_beds import packed_deck

from x3dpd.deck.writer import format_deck
from x3dpd.io.restart import load_restart

TIMEOUT = 600  # a cold kernel cache compiles first
TMAX = 0.12


def x3dpd(*args, cwd, wait=True):
    cmd = [sys.executable, "-m", "x3dpd", *map(str, args)]
    if wait:
        return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT)
    return subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def write_deck(path):
    _, deck = packed_deck(4, 0.03125, clearance=0.01, dt=5e-7, tmax=TMAX, trest=0.02)
    path.write_text(format_deck(deck))


def test_sigkill_during_a_packed_shaken_bed_then_restart_loses_nothing(tmp_path):
    ref, part = tmp_path / "ref", tmp_path / "part"
    ref.mkdir()
    part.mkdir()
    for d in (ref, part):
        write_deck(d / "bed.inp")
    res = x3dpd("bed.inp", "--trace", "bed.trace.txt", "--quiet", cwd=ref)
    assert res.returncode == 0, res.stderr
    dump = part / "bed.trace.txt.restart.npz"
    proc = x3dpd("bed.inp", "--trace", "bed.trace.txt", "--quiet", cwd=part, wait=False)
    t_end = time.monotonic() + TIMEOUT
    while not dump.exists() and proc.poll() is None and time.monotonic() < t_end:
        time.sleep(0.005)
    if proc.poll() is not None:
        pytest.fail(f"the run ended ({proc.returncode}) before it could be killed")
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    _, meta = load_restart(dump)
    assert 0 < meta["step"] < round(TMAX / 5e-7)
    res = x3dpd("bed.inp", "--trace", "bed.trace.txt", "--restart", "--quiet", cwd=part)
    assert res.returncode == 0, res.stderr
    for name in ("bed.trace.txt", "bed.energy.csv"):
        assert (part / name).read_bytes() == (ref / name).read_bytes()
