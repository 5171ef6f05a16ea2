"""The run option ``threads`` (docs/engine.md, "Threads"): the pair contacts' filter and response
run in chunks on numba's threads, the apply pass in list order, so the trace and the energy
ledger are the same bytes at any thread count. Through x3dpd.run and the CLI.

The scene: a free 8 x 8 x 8 simple-cubic block of steel spheres (a fixed floor far below that
none reaches), each touching its neighbours, squeezed by a uniform inward velocity field
(neighbours approach at 0.1 in/s: a Hertz contact of about 170 steps, longer in the block) and
spinning at random (contact points slip: Hertz-Mindlin's history sticks and slides),
viscoelastic (one Maxwell term). After 400 steps 1201 of its 1344 candidate pairs are in contact
-- two chunks of the threaded pass, whose apply chains its sums through both.
The threaded loop is a variant of its own and compiles once per session (x3dpd's kernel cache
keeps it).
"""

from __future__ import annotations

import numpy as np
import pytest

from cli_helpers import run_cli
from factories import (
    FIG30_E0,
    FIG30_E1,
    FIG30_TAU1,
    MINDLIN_STACK_LOOP,
    MINDLIN_STACK_THREADED_LOOP,
    STEEL_R,
    pair_deck,
)

import x3dpd
from x3dpd.deck import write_deck
from x3dpd.solver.threads import available

needs_two = pytest.mark.skipif(
    available() < 2, reason="numba may start one thread here (NUMBA_NUM_THREADS=1)"
)
SIDE = 8
DT = 2.0e-7
STEPS = 400


def _block_deck():
    """The squeezed, spinning block (module docstring)."""
    spacing = 2.0 * STEEL_R
    idx = np.indices((SIDE, SIDE, SIDE)).reshape(3, -1).T
    positions = idx * spacing
    rng = np.random.default_rng(21)
    spins = rng.uniform(-200.0, 200.0, (len(positions), 3))  # rad/s: slip ~ 10 in/s at R
    squeeze = -(0.1 / spacing) * (positions - positions.mean(axis=0))  # in/s
    velocities = np.hstack([squeeze, spins])
    # far_floor: the single-thread loop is the Mindlin stack's (tests/hardcases/test_resting.py;
    # the test rides it)
    return pair_deck(
        positions,
        velocities,
        dt=DT,
        itrac=20,
        e0=FIG30_E0,
        e1=FIG30_E1,
        tau1=FIG30_TAU1,
        mu=0.3,
        far_floor=True,
    )


def _run(tmp_path, name, threads):
    trace = tmp_path / f"{name}.trace.txt"
    result = x3dpd.run(
        _block_deck(), tmax=STEPS * DT, friction="mindlin", trace=trace, threads=threads
    )
    return result, trace.read_bytes(), trace.with_name(f"{name}.energy.csv").read_bytes()


@needs_two
@pytest.mark.rides(MINDLIN_STACK_LOOP, MINDLIN_STACK_THREADED_LOOP)
def test_two_threads_give_the_same_bytes_as_one_through_the_api_and_the_cli(tmp_path):
    one, trace_1, energy_1 = _run(tmp_path, "one", 1)
    two, trace_2, energy_2 = _run(tmp_path, "two", 2)
    # the scene does what the test is about: lasting contacts, friction that works, Maxwell
    # relaxation; and the threaded run really ran the threaded loop
    # (the threaded pass runs on a list of more than one chunk of PAIR_CHUNK = 1024 candidates
    # after a step with at least 1024 busy ones: at the end it still did)
    state = two.final_state.state
    open_pairs = int(state.pl_on[: int(state.npl[0])].sum())
    assert open_pairs >= 1024, open_pairs
    assert int(state.npl[0]) > 1024
    assert one.energy["dissipated_friction"][-1] > 0.0
    assert one.energy["dissipated_viscoelastic"][-1] > 0.0
    assert trace_1 == trace_2
    assert energy_1 == energy_2
    # the CLI's option runs the same threaded loop to the same bytes
    deck = tmp_path / "block.inp"
    write_deck(_block_deck(), deck)
    out = tmp_path / "cli.trace.txt"
    args = ["--tmax", repr(STEPS * DT), "--friction", "mindlin", "--trace", out]
    assert run_cli("run", deck, *args, "--threads", "2", "-q") == 0
    assert out.read_bytes() == trace_1
    assert out.with_name("cli.energy.csv").read_bytes() == energy_1


@pytest.mark.parametrize("value", ["0", "-1", "two", "1.5", "100000"])
def test_bad_thread_counts_are_refused_with_exit_2(tmp_path, capsys, value):
    deck = tmp_path / "block.inp"
    write_deck(_block_deck(), deck)
    out = tmp_path / "t.trace.txt"
    assert run_cli("run", deck, "--trace", out, "--threads", value) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("x3dpd: error: --threads: "), line
    assert not out.exists()


def test_the_api_refuses_a_bad_thread_count_before_anything_is_written(tmp_path):
    trace = tmp_path / "t.trace.txt"
    with pytest.raises(x3dpd.InputError, match="threads"):
        x3dpd.run(_block_deck(), tmax=DT, trace=trace, threads=0)
    assert not trace.exists()
