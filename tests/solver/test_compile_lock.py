"""One compile of a variant at a time across processes (x3dpd.solver.compile_lock)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from x3dpd.solver.compile_lock import variant_compile_lock

_HOLDER = textwrap.dedent("""
    import sys, time
    from x3dpd.solver.compile_lock import variant_compile_lock
    with variant_compile_lock(sys.argv[1], "loop"):
        print("held", flush=True)
        time.sleep(float(sys.argv[2]))
        print(time.monotonic(), flush=True)
""")


def test_a_second_process_waits_for_the_first_to_release_the_lock(tmp_path):
    holder = subprocess.Popen(
        [sys.executable, "-c", _HOLDER, str(tmp_path), "1.0"], stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout.readline().strip() == "held"
    with variant_compile_lock(tmp_path, "loop"):
        acquired = time.monotonic()
    released = float(holder.stdout.readline())
    holder.wait(timeout=30)
    # CLOCK_MONOTONIC is one clock for every process of the machine
    assert acquired >= released


def test_another_variant_and_a_nested_use_do_not_wait(tmp_path):
    holder = subprocess.Popen(
        [sys.executable, "-c", _HOLDER, str(tmp_path), "30"], stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout.readline().strip() == "held"
        t = time.monotonic()
        with variant_compile_lock(tmp_path, "another_loop"):
            with variant_compile_lock(tmp_path, "another_loop"):  # re-entry: no deadlock
                pass
        assert time.monotonic() - t < 5.0
    finally:
        holder.kill()
        holder.wait()


_RUN = textwrap.dedent("""
    import json, sys
    from x3dpd.api import build
    from x3dpd.api.stepper import stepper
    sim = stepper(build(sys.argv[1]))
    sim.advance(10)
    stats = sim.kernels.advance_packed.stats
    print(json.dumps({"hits": sum(stats.cache_hits.values()),
                      "misses": sum(stats.cache_misses.values())}))
""")


@pytest.mark.validate
def test_two_processes_starting_one_new_scene_compile_it_once(tmp_path):
    # a cold compile of impact_wall's loop (~20 CPU-s) while a second process waits for it
    deck = Path(__file__).parents[2] / "decks" / "impact_wall.inp"
    env = {**os.environ, "X3DPD_CACHE_DIR": str(tmp_path / "cache")}
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", _RUN, str(deck)],
            env=env,
            cwd=tmp_path,
            stdout=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    counts = [json.loads(p.communicate(timeout=900)[0].strip().splitlines()[-1]) for p in procs]
    assert sorted(c["misses"] for c in counts) == [0, 1], counts
    # the kernel cache's manifest: one compile and one load of the loop, both booked
    (manifest,) = (tmp_path / "cache" / "kernels").glob("*/manifest.json")
    (entry,) = json.loads(manifest.read_text())["variants"].values()
    assert (entry["compiles"], entry["loads"]) == (1, 1), entry
    assert entry["compile_seconds"] > 0.0
