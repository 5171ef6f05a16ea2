"""SIGKILL in the middle of a hard run, then --restart: nothing lost.

The scene is the packed cavity shaken at 10 g (test_beds.py): every particle has lasting contacts
whose Maxwell histories and friction states must survive the dump. The resumed run's trace and
energy file must equal the uninterrupted run's byte for byte.
"""

from __future__ import annotations

from processes import kill_after_first_dump, x3dpd
from test_beds import packed_deck

from x3dpd.deck.writer import format_deck
from x3dpd.io.restart import load_restart

TMAX = 0.05


def write_deck(path):
    _, deck = packed_deck(4, 0.03125, clearance=0.01, dt=5e-7, tmax=TMAX, trest=0.01)
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
    kill_after_first_dump("bed.inp", "--trace", "bed.trace.txt", "--quiet", cwd=part, dump=dump)
    _, meta = load_restart(dump)
    assert 0 < meta["step"] < round(TMAX / 5e-7)
    res = x3dpd("bed.inp", "--trace", "bed.trace.txt", "--restart", "--quiet", cwd=part)
    assert res.returncode == 0, res.stderr
    for name in ("bed.trace.txt", "bed.energy.csv"):
        assert (part / name).read_bytes() == (ref / name).read_bytes()
