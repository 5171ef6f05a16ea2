"""The energy audit stops a run at the same step through the API, the CLI and however the run
is split into calls of the step loop (docs/physics.md, "Stopping a run that goes unstable").

decks/beam_64.inp made elastic (E1 = 0): 64 Hertz spheres in a box shaken on a spring. The
ledger books each contact's work by the trapezoid, which velocity Verlet conserves, but an
elastic contact stores the exact Hertz energy 2/5 F a, and nothing books their difference (a
viscoelastic one's goes to its dissipation): at the 5e-7 s step the residual grows to about
6e-4 of the energy scale within 0.02 s, while the scale -- the largest of the ledger's terms --
keeps growing with the drive's work: a tolerance of 5e-4 is exceeded at a row near 0.019 s, and
no longer against the scale at 0.03 s. (The Lee & Radok deck itself closes to round-off:
tests/solver/test_conservation.py.) The audit judged every row of a chunk
against the largest scale of the whole chunk, so a run whose chunks the API sized to the machine's
speed stopped later, or not at all (the same shaken HOOKE bed stopped at 0.3215 s through the API
and at 0.2807 s through the CLI); now each row is judged against the rows up to it only.
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.cli import main
from x3dpd.errors import UnstableRunError
from x3dpd.io.energy import read_energy
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

BEAM_64 = Path(__file__).resolve().parents[2] / "decks" / "beam_64.inp"
TMAX = 0.03
TOL = 5e-4


@pytest.fixture(scope="module")
def DECK(tmp_path_factory):
    """decks/beam_64.inp with elastic spheres: PDMP's E1 (field 6) 0."""
    lines = BEAM_64.read_text().split("\n")
    k = next(i for i, line in enumerate(lines) if line.strip().upper() == "PDMP") + 1
    while lines[k].lstrip().startswith("$"):
        k += 1
    fields = lines[k].split()
    fields[5] = "0.0"
    lines[k] = "   " + " ".join(fields)
    path = tmp_path_factory.mktemp("elastic") / "beam_64.inp"
    path.write_text("\n".join(lines))
    return path


RESIDUAL, U_CONTACT = 11, 5


@pytest.fixture(scope="module")
def expected(DECK):
    """(step, time) of the first ledger row the rule flags, from a run the audit does not stop:
    |residual| > TOL * scale + U_c, scale = max(|e_ref|, every |term| of the rows after t0 up
    to this one) (x3dpd.solver.ledger_checks)."""
    free = x3dpd.run(DECK, tmax=TMAX, energy_tolerance=math.inf)
    e = free.energy.data[1:]  # row 0 is t0's, before any step
    e_ref = free.final_state.state.e_ref
    scale = np.maximum.accumulate(np.maximum(np.max(np.abs(e[:, 1:11]), axis=1), abs(e_ref)))
    bad = np.abs(e[:, RESIDUAL]) > TOL * scale + np.maximum(e[:, U_CONTACT], 0.0)
    assert bad.any(), "the residual must exceed the tolerance within TMAX"
    k = int(np.argmax(bad))
    # the row passes against the scale the run reaches later: judged by later rows (a long
    # chunk), it would not stop the run here
    assert abs(e[k, RESIDUAL]) <= TOL * scale[-1] + max(e[k, U_CONTACT], 0.0)
    dt = free.summary["dt"]
    return int(round(e[k, 0] / dt)), float(e[k, 0])


def _stops_at(run) -> tuple[int, float]:
    with pytest.raises(UnstableRunError, match="without a source") as err:
        run()
    return err.value.step, err.value.time


def test_the_api_stops_where_the_rule_says_whatever_its_chunks(DECK, expected):
    """Chunks sized to the machine's speed, and one trace row per chunk (a stop callback asked
    after every row)."""
    assert _stops_at(lambda: x3dpd.run(DECK, tmax=TMAX, energy_tolerance=TOL)) == expected
    assert (
        _stops_at(
            lambda: x3dpd.run(
                DECK, tmax=TMAX, energy_tolerance=TOL, stop=lambda chunk: False, stop_every=1
            )
        )
        == expected
    )


@pytest.mark.parametrize("calls", [1, 37], ids=["one-call", "37-calls"])
def test_a_simulation_stops_at_the_same_step_in_one_call_or_many(DECK, expected, calls):
    sim = Simulation(build_model(x3dpd.load_deck(DECK)), energy_tolerance=TOL)
    total = int(round(TMAX / sim.dt))
    per_call = -(-total // calls)

    def advance():
        while sim.clock < total:
            sim.advance(min(per_call, total - sim.clock))

    assert _stops_at(advance) == expected


def test_the_cli_stops_at_the_same_step(DECK, expected, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    shutil.copy(DECK, "beam_64.inp")
    with pytest.raises(SystemExit) as exc:
        main(["beam_64.inp", "--tmax", repr(TMAX), "--energy-tolerance", repr(TOL)])
    _, err = capsys.readouterr()
    assert exc.value.code == 3, err
    step, t = expected
    assert re.search(rf"unstable run at t = {t:.6g} s: total energy (was lost|grew)", err), err
    # the energy file ends with the row the audit flagged
    assert read_energy("beam_64.energy.csv").data[-1, 0] == pytest.approx(t, rel=1e-12)


HOOKE = Path(__file__).resolve().parents[2] / "decks" / "hooke_wall.inp"


def test_the_summary_names_the_residual_in_both_units():
    """``energy["residual"]`` is an energy; ``summary["relative_residual"]`` (and the older
    ``summary["residual"]``) that energy over ``summary["energy_scale"]``;
    ``summary["residual_energy"]`` the last row's energy. decks/hooke_wall.inp to 6e-5 s: in
    the middle of its impact, where the contact stores energy and the residual is round-off."""
    res = x3dpd.run(HOOKE, tmax=6e-5, energy_tolerance=0.02)
    s = res.summary
    last = res.energy["residual"][-1]
    assert s["residual_energy"] == last
    assert s["relative_residual"] == last / s["energy_scale"]
    assert s["residual"] == s["relative_residual"]
    assert s["energy_tolerance"] == 0.02
    # the scale is the largest ledger term so far: here the kinetic energy at t0, 1/2 m v^2
    m = res.model.mass[-1]
    assert s["energy_scale"] == pytest.approx(0.5 * m * 10.0**2, rel=1e-12)
    assert x3dpd.run(HOOKE, tmax=1e-6).summary["energy_tolerance"] == 0.05


@pytest.mark.parametrize("bad", [0.0, -0.1, math.nan])
def test_a_tolerance_that_is_not_a_positive_fraction_is_refused(bad):
    with pytest.raises(x3dpd.InputError, match="energy_tolerance must be a positive"):
        x3dpd.run(HOOKE, tmax=1e-6, energy_tolerance=bad)
