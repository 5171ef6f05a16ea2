"""Sidecars, restart dumps and written decks get the permissions of ordinary new files (those of
the trace beside them), not the 0600 of a temporary file."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from x3dpd._files import write_atomically
from x3dpd.io.trace import TraceWriter, sidecar_path

pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX permission bits")


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield 0o644
    os.umask(old)


def test_sidecar_has_the_traces_mode(tmp_path, umask_022):
    trace = tmp_path / "t.trace.txt"
    with TraceWriter(trace, [1], {"dt": 1e-3, "itrac": 1}) as w:
        w.write_block([0.0], np.zeros((1, 1, 9)))
    assert _mode(trace) == umask_022
    assert _mode(sidecar_path(trace)) == _mode(trace)


def test_new_file_follows_the_umask_and_a_replaced_file_keeps_its_mode(tmp_path):
    old = os.umask(0o027)
    try:
        p = tmp_path / "a.bin"
        write_atomically(p, lambda f: f.write(b"1"))
        assert _mode(p) == 0o640
        os.chmod(p, 0o604)
        write_atomically(p, lambda f: f.write(b"2"))
        assert _mode(p) == 0o604 and p.read_bytes() == b"2"
    finally:
        os.umask(old)


def test_restart_dump_mode(tmp_path, umask_022):
    from x3dpd.io.restart import save_restart

    path = tmp_path / "t.restart.npz"
    save_restart(path, {"x": np.zeros(3)}, {"step": 0})
    assert _mode(path) == umask_022
