"""The Python API: ``x3dpd.run`` writes what ``x3dpd run`` writes, byte for byte, and returns the
trace, ledger, summary and final state in memory; errors are typed; runs continue from states.

Short windows of the shipped decks (their step loops are compiled by the golden tests anyway).
"""

from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.cli import main

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks"
BEAM_DRIVE = "sine:node=9,dof=1,amp=4.84040e-3,hz=37.21"
CUBE_DRIVE = "sine:node=25,dof=1,amp=4.84040e-3,hz=37.21"
SHAKER_BASE = "node=4,dof=2,amp=0.02,hz=36.75"

#: (deck, extra CLI arguments, API keywords, tmax): every shipped deck that runs, a short window
SHIPPED = [
    ("appendix_a_cube.inp", ["--usrfrc", CUBE_DRIVE], {"usrfrc": [CUBE_DRIVE]}, 2e-3),
    ("beam_1.inp", [], {}, 2e-3),
    ("beam_64.inp", [], {}, 2e-3),
    ("beam_64_modal.inp", [], {}, 2e-3),
    ("chassis_128.inp", [], {}, 2e-3),
    ("beam_512.inp", [], {}, 1e-3),
    ("cylinder_64.inp", [], {}, 2e-3),
    ("capsule_64.inp", [], {}, 2e-3),
    ("shaker_fig9.inp", ["--motion", SHAKER_BASE], {"motion": [SHAKER_BASE]}, 2e-3),
    ("capsule_wc7.inp", ["--temperature", "850F"], {"temperature": "850F"}, 2e-3),
    ("impact_wall.inp", [], {}, None),
    ("hooke_wall.inp", [], {}, None),
    ("mip_apparatus_05.inp", [], {}, 2e-3),
    ("mip_apparatus_025.inp", [], {}, 1e-3),
    ("mip_engine.inp", [], {}, 2e-3),
]


def test_every_runnable_shipped_deck_is_compared():
    """Every deck in decks/ but the printed Appendix A (refused) is in SHIPPED."""
    runnable = sorted(p.name for p in DECKS.glob("*.inp") if p.name != "appendix_a.inp")
    assert sorted(s[0] for s in SHIPPED) == runnable


def cli(*args) -> int:
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in args])
    return exc.value.code or 0


@pytest.mark.parametrize("deck, cli_args, kw, tmax", SHIPPED, ids=[s[0] for s in SHIPPED])
def test_api_writes_the_same_bytes_as_the_cli(
    deck, cli_args, kw, tmax, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    shutil.copy(DECKS / deck, deck)
    extra = ["--tmax", repr(tmax)] if tmax else []
    assert cli(deck, "--trace", "cli.trace.txt", "-q", *cli_args, *extra) == 0
    result = x3dpd.run(deck, trace="api.trace.txt", tmax=tmax, **kw)
    assert Path("api.trace.txt").read_bytes() == Path("cli.trace.txt").read_bytes()
    assert Path("api.energy.csv").read_bytes() == Path("cli.energy.csv").read_bytes()
    a = json.loads(Path("api.trace.txt.json").read_text())
    b = json.loads(Path("cli.trace.txt.json").read_text())
    for key in ("energy_file", "restart_file", "command"):
        a.pop(key), b.pop(key)
    assert a == b
    # the in-memory trace is the file's, and the same type read_trace returns
    back = x3dpd.read_trace("api.trace.txt")
    assert type(result.trace) is type(back)
    np.testing.assert_array_equal(result.trace.node_ids, back.node_ids)
    np.testing.assert_allclose(result.trace.time, back.time, rtol=1e-9, atol=0)
    np.testing.assert_allclose(result.trace.position, back.position, rtol=1e-9, atol=1e-300)
    energy = x3dpd.read_energy("api.energy.csv")
    # the file writes the time as the trace does (10 digits), the energies exactly
    np.testing.assert_allclose(result.energy.data[:, 0], energy.data[:, 0], rtol=1e-9, atol=0)
    np.testing.assert_array_equal(result.energy.data[:, 1:], energy.data[:, 1:])
    assert result.summary["status"] == "complete"


def test_trace_arrays_and_ledger(tmp_path, monkeypatch):
    """Shapes, names and the ledger: impact_wall's sphere approaches the wall at 62.832 in/s
    along -x (Fig. 28) and leaves elastically (e = 1: energy conserved to the ledger's
    residual)."""
    monkeypatch.chdir(tmp_path)
    r = x3dpd.run(DECKS / "impact_wall.inp")
    tr = r.trace
    T, N = tr.time.shape[0], tr.node_ids.shape[0]
    assert T == 1201 and tr.position.shape == tr.velocity.shape == tr.spin.shape == (T, N, 3)
    assert os.listdir(tmp_path) == []  # trace=None: nothing written
    v0, v1 = tr.velocity[0, -1], tr.velocity[-1, -1]
    assert np.linalg.norm(v0) == pytest.approx(62.832, rel=1e-9)
    assert np.dot(v0, v1) < 0  # it bounced
    assert np.linalg.norm(v1) == pytest.approx(62.832, rel=1e-3)  # elastic Hertz
    assert r.energy.columns[0] == "time" and r.energy.data.shape == (T, 12)
    ke = r.energy["kinetic_translation"]
    m = r.model.mass[-1]
    assert ke[0] == pytest.approx(0.5 * m * 62.832**2, rel=1e-12)
    s = r.summary
    assert s["steps"] == 12000 and s["t_end"] == pytest.approx(1.2e-5)
    assert abs(s["residual"]) < 1e-3
    assert s["trace_file"] is None and s["dumps"] == 0


def test_continue_from_final_state_equals_one_run():
    """Two runs, the second continuing the first's final state, give the one run's rows bit for
    bit (same sums in the same order)."""
    deck = DECKS / "beam_1.inp"
    whole = x3dpd.run(deck, tmax=4e-3)
    first = x3dpd.run(deck, tmax=2e-3)
    second = x3dpd.run(deck, tmax=4e-3, initial_state=first.final_state)
    assert second.trace.time[0] == pytest.approx(2e-3 + 1e-3, rel=1e-12)
    joined = np.concatenate([first.trace.data, second.trace.data])
    np.testing.assert_array_equal(joined, whole.trace.data)
    np.testing.assert_array_equal(
        np.concatenate([first.energy.data, second.energy.data]), whole.energy.data
    )
    with pytest.raises(x3dpd.InputError, match="same step"):
        x3dpd.run(deck, tmax=4e-3, dt=2.5e-7, initial_state=first.final_state)
    with pytest.raises(x3dpd.InputError, match="another deck"):
        x3dpd.run(DECKS / "beam_64.inp", tmax=4e-3, initial_state=first.final_state)


def test_stop_trace_nodes_and_itrac():
    seen = []

    def stop(chunk):
        seen.append(chunk.time[-1])
        assert chunk.position.shape[1:] == (1, 3) and chunk.energy.shape[1] == 12
        return chunk.time[-1] >= 1e-3

    r = x3dpd.run(DECKS / "beam_1.inp", tmax=0.1, trace_nodes=[9], itrac=50, stop=stop)
    assert r.summary["status"] == "stopped"
    assert 1e-3 <= r.summary["t_end"] < 0.1
    assert r.trace.node_ids.tolist() == [9]
    np.testing.assert_allclose(np.diff(r.trace.time), 50 * 5e-7, rtol=1e-9)
    with pytest.raises(x3dpd.InputError, match="not in the deck"):
        x3dpd.run(DECKS / "beam_1.inp", tmax=1e-3, trace_nodes=[12345])


def test_where_a_stopped_run_ends_does_not_depend_on_the_machines_speed(monkeypatch):
    """With ``stop``, the run is asked after every ``stop_every`` rows, a fixed step count:
    the chunks a run without ``stop`` adapts to its measured speed (CHUNK_SECONDS) would make
    the stopping step -- and the state a chained sweep point starts from -- depend on the load
    of the machine. Two runs, one told its chunks should last a microsecond and one a minute,
    stop at the same step with the same state (the check can fail: the adaptive chunks differ
    by orders of magnitude)."""
    import x3dpd.api.loop as loop

    def stop(chunk):
        return chunk.time[-1] >= 1.9e-3

    ends = []
    for seconds in (1e-6, 60.0):
        monkeypatch.setattr(loop, "CHUNK_SECONDS", seconds)
        r = x3dpd.run(
            DECKS / "beam_1.inp", tmax=0.1, trace_nodes=[9], itrac=5, stop=stop, stop_every=200
        )
        assert r.summary["status"] == "stopped"
        ends.append((r.summary["t_end"], r.summary["steps"], r.final_state))
    (t_a, n_a, s_a), (t_b, n_b, s_b) = ends
    assert (t_a, n_a) == (t_b, n_b)
    # the stop is checked every 200 rows of 5 steps: the first check at or after 1.9 ms
    dt = 5e-7
    assert n_a == 200 * 5 * math.ceil(1.9e-3 / (200 * 5 * dt))
    np.testing.assert_array_equal(s_a.state.x, s_b.state.x)


def test_usrfrc_replaces_the_decks_drive_unless_added():
    """beam_1's deck drives node 9 with BEAM_DRIVE. Giving the same spec replaces it (same run
    as none); adding it drives twice, which is the single drive at twice the amplitude (to
    rounding: the forces are summed in another order)."""
    deck = DECKS / "beam_1.inp"
    base = x3dpd.run(deck, tmax=2e-3)
    same = x3dpd.run(deck, tmax=2e-3, usrfrc=[BEAM_DRIVE])
    assert same.summary["usrfrc_replaced"] == [BEAM_DRIVE]
    np.testing.assert_array_equal(base.trace.data, same.trace.data)
    twice = x3dpd.run(deck, tmax=2e-3, usrfrc=[BEAM_DRIVE], usrfrc_mode="add")
    double = x3dpd.run(deck, tmax=2e-3, usrfrc=[BEAM_DRIVE.replace("4.84040e-3", "9.68080e-3")])
    assert twice.summary["usrfrc"] == [BEAM_DRIVE, BEAM_DRIVE]
    np.testing.assert_allclose(twice.trace.data, double.trace.data, rtol=1e-12, atol=1e-17)
    assert not np.array_equal(twice.trace.data, base.trace.data)


def test_errors_are_typed(tmp_path):
    bad = tmp_path / "bad.inp"
    bad.write_text("PARAMETERS\n 0.0 abc\nEND\n")
    with pytest.raises(x3dpd.DeckError) as exc:
        x3dpd.run(bad)
    assert str(exc.value).startswith(f"{bad}:2:")
    with pytest.raises(x3dpd.InputError, match="does not exist"):
        x3dpd.run(tmp_path / "missing.inp")
    with pytest.raises(x3dpd.InputError, match="usrfrc_mode"):
        x3dpd.run(DECKS / "beam_1.inp", usrfrc_mode="twice")
    assert list(tmp_path.iterdir()) == [bad]


def test_unstable_run_raises_and_keeps_rows_up_to_the_diagnosis(tmp_path):
    """A step 2000 times too large on impact_wall: UnstableRunError, the rows computed before
    it written, none later than the time the diagnosis names."""
    with pytest.raises(x3dpd.UnstableRunError) as exc:
        x3dpd.run(DECKS / "impact_wall.inp", dt=2e-6, tmax=1e-3, trace=tmp_path / "u.trace.txt")
    err = exc.value
    tr = x3dpd.read_trace(tmp_path / "u.trace.txt")
    assert tr.status == "unstable" and tr.times[0] == 0.0
    assert tr.times[-1] <= err.time + 1e-12
    assert err.result.summary["status"] == "unstable"
    assert err.result.trace.time[-1] == pytest.approx(tr.times[-1], rel=1e-9)


def test_load_deck_check_and_build():
    deck = x3dpd.load_deck(DECKS / "beam_64.inp")
    model = x3dpd.build(deck)
    assert model.n_particles == 64
    report = x3dpd.check(DECKS / "beam_64.inp")
    assert report.errors == [] or report.errors == ()
    assert report.n_particles == 64
    assert set(x3dpd.__all__) <= set(dir(x3dpd))
    with pytest.raises(AttributeError):
        x3dpd.no_such_thing  # noqa: B018
