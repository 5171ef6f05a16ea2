"""A design on a real Dask cluster -- ``dask scheduler`` and two ``dask worker`` processes
started as a lab would start them (docs/cluster.md) -- writes the same design.csv, byte for
byte, as the serial run (issue 30, item 4): every point is computed by the same function from
the same inputs, wherever it runs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

from factories import sdof_deck

from x3dpd.deck.writer import write_deck
from x3dpd.design.explore import run_design

ROOT = Path(__file__).resolve().parents[2]
#: the dask command-line tools of this interpreter's environment
DASK = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
WORKER = [sys.executable, "-m", "distributed.cli.dask_worker"]

DESIGN = """
structure = "sdof.inp"
[fill]
count = 0
[vary]
dt = [2e-5, 4e-5]
[evaluate]
kind = "sweep"
node = 1
dof = 1
drives = [4.84040e-3]
frequencies = "auto:35:40:0.01"
baselines = ["undamped"]
tol = 1e-3
"""


def _cluster(folder: Path):
    """Start ``dask scheduler`` and ``dask worker`` (two single-threaded worker processes) and
    return (processes, scheduler address)."""
    info = folder / "scheduler.json"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    scheduler = subprocess.Popen(
        [*DASK, "--scheduler-file", str(info), "--port", "0", "--no-dashboard"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env=env,
    )
    procs = [scheduler]
    deadline = time.monotonic() + 60
    while not info.exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    address = json.loads(info.read_text())["address"]
    procs.append(
        subprocess.Popen(
            [
                *WORKER,
                "--scheduler-file",
                str(info),
                "--nworkers",
                "2",
                "--nthreads",
                "1",
                "--no-dashboard",
                "--local-directory",
                str(folder / "workers"),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    )
    return procs, address


def _wait_for_workers(address: str, count: int) -> None:
    from dask.distributed import Client

    with Client(address, timeout=60) as client:
        client.wait_for_workers(count, timeout=120)


def test_a_design_on_a_dask_scheduler_and_workers_equals_the_serial_one(tmp_path):
    write_deck(sdof_deck(dt=1e-5, hz=37.0), tmp_path / "sdof.inp")
    spec = tmp_path / "design.toml"
    spec.write_text(DESIGN)
    run_design(spec, tmp_path / "serial", workers=1, echo=lambda s: None)
    procs, address = _cluster(tmp_path)
    try:
        _wait_for_workers(address, 2)
        lines = []
        run_design(spec, tmp_path / "cluster", scheduler=address, echo=lines.append)
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)
    serial = (tmp_path / "serial" / "design.csv").read_bytes()
    assert (tmp_path / "cluster" / "design.csv").read_bytes() == serial
    for name in ("dt2e-05", "dt4e-05"):
        peaks = Path("configs") / name / "sweep" / "peaks.csv"
        assert (tmp_path / "cluster" / peaks).read_bytes() == (
            tmp_path / "serial" / peaks
        ).read_bytes()
    assert any("points" in line for line in lines)
