"""A sweep through a Dask LocalCluster of separate worker processes equals the serial sweep, bit
for bit (the same function computes every point; only where it runs differs)."""

from __future__ import annotations

from pathlib import Path

import pytest
from dask.distributed import LocalCluster

from x3dpd.deck.parser import read_deck
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import COLUMNS, deck_hash, run_sweep

BEAM_1 = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"
#: Columns that measure the machine, not the physics.
TIMINGS = {"wall_s", "compile_s"}


def _same_rows(serial, other):
    for a, b in zip(serial, other):
        for col in COLUMNS:
            if col not in TIMINGS:
                assert a[col] == b[col] or (a[col] != a[col] and b[col] != b[col]), col


def _spec():
    """beam_1 (one sphere in the cavity), two chains (up and down) of two points, each capped
    short (9 cycles at about 37 Hz), and the closed-form undamped baseline."""
    return SweepSpec(
        deck=read_deck(BEAM_1),
        deck_text_hash=deck_hash(BEAM_1),
        frequencies=(37.0, 38.0),
        drives=(9.68080e-3,),
        node=9,
        dof=1,
        direction="both",
        baselines=("undamped",),
        criterion=Criterion(window=3, max_cycles=9),
    )


@pytest.mark.validate  # a second LocalCluster of worker processes: python -m pytest -m validate
def test_an_existing_cluster_given_by_its_address_equals_serial_bit_for_bit(tmp_path):
    spec = _spec()
    serial = run_sweep(spec, tmp_path / "serial", workers=1)
    # --scheduler: an existing cluster, here a LocalCluster of two worker processes
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster:
        remote = run_sweep(spec, tmp_path / "scheduler", scheduler=cluster.scheduler_address)
    assert len(remote) == 6
    _same_rows(serial, remote)


def test_dask_local_cluster_equals_serial_bit_for_bit(tmp_path):
    spec = _spec()
    serial = run_sweep(spec, tmp_path / "serial", workers=1)
    parallel = run_sweep(spec, tmp_path / "dask", workers=2)
    assert len(serial) == len(parallel) == 6  # 4 damper + 2 closed-form points
    _same_rows(serial, parallel)
    # the chain really ran in order: its second point starts where the first ended
    up = [r for r in parallel if r["direction"] == "up"]
    assert up[1]["t_start"] == up[0]["t_end"] > 0
    assert (tmp_path / "dask" / "sweep.csv").read_text().splitlines()[0] == ",".join(COLUMNS)
