"""Restart dumps: kill a run, resume it, get the uninterrupted run's files byte for byte.

The runs are real ``x3dpd`` processes on a small deck (10 spheres in the report's beam cavity,
driven at 37.21 Hz: the same compiled step loop as decks/beam_64.inp), 0.2 s of simulated time
(4e5 steps, about a second of CPU time), a restart dump every TREST = 0.02 s.
"""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from x3dpd.deck.generate import Material3, box_cavity_deck, lattice_fill
from x3dpd.deck.writer import format_deck
from x3dpd.io.restart import load_restart

TMAX = 0.2
TREST = 0.02
DRIVE = "sine:node=9,dof=1,amp=4.84040e-3,hz=37.21"
STEEL = Material3(e0=27.5e6, e1=5.0e6, tau1=2.0e-6, nu=0.33, mu=0.30, density=7.32971e-4)
CAVITY = (0.263, 0.372, 0.372)
TIMEOUT = 600  # a cold numba cache compiles the step loop first (about 30 s)


def ten_sphere_deck(path: Path, irest: int = 0, damping: float = 3.08293e-4) -> Path:
    radius = 0.03125
    pos = lattice_fill(CAVITY, radius, 10, gap=0.05 * radius, seed=1, jitter=0.5)
    deck = box_cavity_deck(
        size=CAVITY,
        particles=pos,
        radius=radius,
        material=STEEL,
        structure_mass=2.04213e-4,
        stiffness=1.14823e1,
        damping=damping,
        dt=5e-7,
        tmax=TMAX,
        itrac=2000,
        trest=TREST,
        usrfrc=(DRIVE,),
    )
    text = "$ ten spheres in the Sec. 8.2 beam cavity (tests/cli/test_restart.py)\n"
    text += format_deck(deck)
    if irest:
        old = " 0 1000000000.0 0 5 0"
        assert old in text
        text = text.replace(old, " 0 1000000000.0 1 5 0")
    path.write_text(text)
    return path


def x3dpd(*args, cwd, **kw):
    return subprocess.run(
        [sys.executable, "-m", "x3dpd", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        **kw,
    )


def start(*args, cwd):
    return subprocess.Popen(
        [sys.executable, "-m", "x3dpd", *map(str, args)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def wait_for(path: Path, proc: subprocess.Popen) -> None:
    t_end = time.monotonic() + TIMEOUT
    while not path.exists():
        if proc.poll() is not None:
            out, err = proc.communicate()
            pytest.fail(f"x3dpd ended ({proc.returncode}) before {path.name} appeared:\n{err}")
        if time.monotonic() > t_end:
            proc.kill()
            pytest.fail(f"{path.name} did not appear within {TIMEOUT} s")
        time.sleep(0.005)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run: deck, trace, energy file, sidecar and last restart dump."""
    d = tmp_path_factory.mktemp("reference")
    deck = ten_sphere_deck(d / "ten.inp")
    res = x3dpd(deck, "--trace", "ref.trace.txt", cwd=d)
    assert res.returncode == 0, res.stderr
    return d


def same_files(a: Path, b: Path, stem_a: str, stem_b: str) -> None:
    assert (a / f"{stem_a}.trace.txt").read_bytes() == (b / f"{stem_b}.trace.txt").read_bytes()
    assert (a / f"{stem_a}.energy.csv").read_bytes() == (b / f"{stem_b}.energy.csv").read_bytes()


def test_sigkill_then_restart_is_bytewise_identical(reference, tmp_path):
    deck = ten_sphere_deck(tmp_path / "ten.inp")
    dump = tmp_path / "part.trace.txt.restart.npz"
    proc = start(deck, "--trace", "part.trace.txt", cwd=tmp_path)
    wait_for(dump, proc)
    assert proc.poll() is None, "the run ended before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    assert proc.returncode == -signal.SIGKILL
    _, meta = load_restart(dump)
    assert 0 < meta["step"] < round(TMAX / 5e-7)
    side = json.loads((tmp_path / "part.trace.txt.json").read_text())
    assert side["status"] == "running"  # killed: nobody closed it
    res = x3dpd(deck, "--trace", "part.trace.txt", "--restart", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    same_files(tmp_path, reference, "part", "ref")
    side = json.loads((tmp_path / "part.trace.txt.json").read_text())
    assert side["status"] == "complete" and side["resumed_at"] == meta["time"]


def test_sigint_exits_130_with_a_valid_dump(reference, tmp_path):
    deck = ten_sphere_deck(tmp_path / "ten.inp")
    dump = tmp_path / "part.trace.txt.restart.npz"
    proc = start(deck, "--trace", "part.trace.txt", cwd=tmp_path)
    wait_for(dump, proc)  # stepping is under way
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=TIMEOUT)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert "interrupted at t =" in err
    assert f"Resume with: x3dpd {deck} --restart --trace part.trace.txt" in err
    arrays, meta = load_restart(dump)
    assert meta["reason"] == "interrupted"
    assert 0 < meta["step"] < round(TMAX / 5e-7)
    trace = tmp_path / "part.trace.txt"
    side = json.loads((tmp_path / "part.trace.txt.json").read_text())
    assert side["status"] == "interrupted"
    # the dump points at the end of the flushed trace
    assert meta["trace"]["bytes"] == trace.stat().st_size == side["bytes"]
    assert meta["trace"]["blocks"] == side["blocks"]
    assert meta["energy"]["bytes"] == (tmp_path / "part.energy.csv").stat().st_size
    assert arrays["x"].shape == (9 + 10, 3)
    res = x3dpd(deck, "--trace", "part.trace.txt", "--restart", "--quiet", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stdout == "" and res.stderr == ""
    same_files(tmp_path, reference, "part", "ref")


@pytest.fixture
def finished(reference, tmp_path):
    """A copy of the reference run's files (its dump is the end-of-run one, at TMAX)."""
    for f in reference.iterdir():
        shutil.copy2(f, tmp_path / f.name)
    return tmp_path


@pytest.mark.parametrize(
    "extra, words",
    [
        (("--dt", "2.5e-7"), "dt 2.5e-07"),
        (("--usrfrc", "constant:node=9,dof=1,amp=1e-3"), "--usrfrc"),
        (("--friction", "coulomb"), "--friction"),
    ],
)
def test_restart_refuses_another_setup(finished, extra, words):
    before = (finished / "ref.trace.txt").read_bytes()
    res = x3dpd(
        "ten.inp",
        "--trace",
        "ref.trace.txt",
        "--restart",
        "--overwrite",
        "--tmax",
        "0.22",
        *extra,
        cwd=finished,
    )
    assert res.returncode == 2, res.stderr
    assert "cannot resume from ref.trace.txt.restart.npz" in res.stderr and words in res.stderr
    assert (finished / "ref.trace.txt").read_bytes() == before


def test_restart_refuses_a_changed_deck(finished):
    ten_sphere_deck(finished / "ten.inp", damping=4e-4)
    res = x3dpd(
        "ten.inp",
        "--trace",
        "ref.trace.txt",
        "--restart",
        "--overwrite",
        "--tmax",
        "0.22",
        cwd=finished,
    )
    assert res.returncode == 2 and "the deck's cards differ" in res.stderr


def test_finished_run_has_an_end_dump_at_tmax(finished):
    _, meta = load_restart(finished / "ref.trace.txt.restart.npz")
    assert meta["reason"] == "end" and meta["step"] == round(TMAX / 5e-7)
    assert meta["trace"]["bytes"] == (finished / "ref.trace.txt").stat().st_size
    res = x3dpd("ten.inp", "--trace", "ref.trace.txt", "--restart", cwd=finished)
    assert res.returncode == 2 and "nothing to run (give a larger --tmax)" in res.stderr


def test_complete_trace_needs_overwrite_and_irest_resumes(reference, tmp_path):
    """IREST = 1 in the deck resumes (the deck's key masks IREST); a complete trace is only cut
    back with --overwrite, which keeps a .bak of the trace and the energy file.

    The dump at 0.18 s is the end dump of a run to TMAX 0.18 (the same steps as the reference's
    first 0.18 s); the complete reference trace is put in its place, so resuming from 0.18 s
    would cut it."""
    deck = ten_sphere_deck(tmp_path / "ten.inp")
    res = x3dpd(deck, "--trace", "ref.trace.txt", "--tmax", "0.18", "-q", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    for name in ("ref.trace.txt", "ref.trace.txt.json", "ref.energy.csv"):
        shutil.copy2(reference / name, tmp_path / name)
    ten_sphere_deck(tmp_path / "ten.inp", irest=1)
    res = x3dpd("ten.inp", "--trace", "ref.trace.txt", cwd=tmp_path)
    assert res.returncode == 2 and "--overwrite" in res.stderr
    res = x3dpd("ten.inp", "--trace", "ref.trace.txt", "--overwrite", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    same_files(tmp_path, reference, "ref", "ref")
    assert (tmp_path / "ref.trace.txt.bak").read_bytes() == (
        reference / "ref.trace.txt"
    ).read_bytes()
    assert (tmp_path / "ref.energy.csv.bak").is_file()
    assert "t = 0.18 .. 0.2 s" in res.stdout


def test_resume_with_a_later_tmax_extends_the_run(finished, reference):
    """A finished run goes on from its end dump: nothing is cut, so no --overwrite is needed."""
    res = x3dpd(
        "ten.inp", "--trace", "ref.trace.txt", "--restart", "--tmax", "0.22", "-q", cwd=finished
    )
    assert res.returncode == 0, res.stderr
    new = (finished / "ref.trace.txt").read_bytes()
    old = (reference / "ref.trace.txt").read_bytes()
    assert new.startswith(old) and new.count(b"\n") == old.count(b"\n") + 20 * 11
    energy = (finished / "ref.energy.csv").read_bytes()
    assert energy.startswith((reference / "ref.energy.csv").read_bytes())
    assert not (finished / "ref.trace.txt.bak").exists()


def test_restart_without_a_dump_exits_2(tmp_path):
    deck = ten_sphere_deck(tmp_path / "ten.inp")
    res = x3dpd(deck, "--restart", cwd=tmp_path)
    assert res.returncode == 2
    assert "ten.trace.txt.restart.npz, which does not exist" in res.stderr
