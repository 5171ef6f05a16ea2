"""Frequency sweeps: a linear structure against its closed form, Dask against serial, resuming,
chains and baselines."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from factories import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_deck

from x3dpd.deck.parser import read_deck
from x3dpd.deck.writer import write_deck
from x3dpd.design.baselines import linear_sdof, particle_mass, with_added_mass, without_particles
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import Criterion
from x3dpd.design.sweep import deck_hash, read_csv, run_sweep
from x3dpd.errors import InputError
from x3dpd.model.build import build_model

DECKS = Path(__file__).resolve().parents[2] / "decks"


def sdof_file(tmp_path: Path) -> Path:
    """The report's Table 4 beam alone (no particles), dt = 10 us (w dt = 2.5e-3)."""
    path = tmp_path / "sdof.inp"
    write_deck(sdof_deck(dt=1e-5, hz=37.0), path)
    return path


def spec_for(path: Path, freqs, **kw) -> SweepSpec:
    deck = read_deck(path)
    kw.setdefault("criterion", Criterion(tol=1e-3))
    return SweepSpec(
        deck=deck,
        deck_text_hash=deck_hash(path),
        frequencies=tuple(freqs),
        drives=kw.pop("drives", (TABLE4_DRIVE,)),
        node=kw.pop("node", 1),
        dof=1,
        **kw,
    )


def exact(hz: float):
    """m x'' + c x' + k x = F sin(w t): X = F / |k - m w^2 + i c w|, phi = -arg(...)."""
    w = 2 * math.pi * hz
    return (
        TABLE4_DRIVE / math.hypot(TABLE4_K - TABLE4_MASS * w * w, TABLE4_C * w),
        -math.atan2(TABLE4_C * w, TABLE4_K - TABLE4_MASS * w * w),
    )


def test_the_linear_structures_sweep_equals_its_closed_form(tmp_path):
    freqs = (35.0, 37.5, 39.0, 39.37, 40.0)
    rows = run_sweep(spec_for(sdof_file(tmp_path), freqs), tmp_path / "out", workers=1)
    assert [r["frequency_hz"] for r in rows] == list(freqs)
    for r in rows:
        amp, phi = exact(r["frequency_hz"])
        assert r["converged"]
        # tolerance: the criterion's 1e-3, plus the integrator's phase error (w dt)^2 / 24 =
        # 2.6e-7 in frequency, amplified near resonance by 1 / (2 zeta) = 160: 2e-3 in all
        assert r["amplitude"] == pytest.approx(amp, rel=2e-3)
        assert math.radians(r["phase"]) == pytest.approx(phi, abs=2e-3)
        w = 2 * math.pi * r["frequency_hz"]
        # steady state: the drive's work per cycle is the dashpot's pi c w X^2
        assert r["input_work_per_cycle"] == pytest.approx(math.pi * TABLE4_C * w * amp**2, rel=4e-3)
        assert r["acceleration"] == pytest.approx(w * w * r["amplitude"], rel=1e-12)
    csv = read_csv(tmp_path / "out" / "sweep.csv")
    assert {
        "config",
        "frequency_hz",
        "drive",
        "amplitude",
        "phase",
        "dissipated_per_cycle",
        "cycles",
        "converged",
        "wall_s",
    } <= set(csv[0])
    assert [c["amplitude"] for c in csv] == [r["amplitude"] for r in rows]


def test_a_rerun_computes_only_the_missing_points(tmp_path):
    path = sdof_file(tmp_path)
    out = tmp_path / "out"
    spec = spec_for(path, (36.0, 38.0, 39.0))
    first = run_sweep(spec, out, workers=1)
    (out / "points" / "deck_F4.840400e-03_rest_38.000000Hz.json").unlink()
    computed = []
    again = run_sweep(spec, out, workers=1, on_point=computed.append)
    assert [r["frequency_hz"] for r in computed] == [38.0]
    assert [r["amplitude"] for r in again] == [r["amplitude"] for r in first]
    # more frequencies in the same folder: only the new ones run
    computed.clear()
    run_sweep(spec_for(path, (36.0, 37.0, 38.0, 39.0)), out, workers=1, on_point=computed.append)
    assert [r["frequency_hz"] for r in computed] == [37.0]
    # another criterion would mix incomparable points: refused without --overwrite
    other = spec_for(path, (36.0,), criterion=Criterion(tol=1e-2))
    with pytest.raises(InputError, match="other settings"):
        run_sweep(other, out, workers=1)
    assert json.loads((out / "sweep.json").read_text())["criterion"]["tol"] == 1e-3
    rows = run_sweep(other, out, workers=1, overwrite=True)
    assert len(rows) == 1


def test_a_chain_continues_from_the_previous_points_state(tmp_path):
    rows = run_sweep(
        spec_for(sdof_file(tmp_path), (37.0, 38.0, 39.0), direction="both"),
        tmp_path / "out",
        workers=1,
    )
    for direction, order in (("up", [37.0, 38.0, 39.0]), ("down", [39.0, 38.0, 37.0])):
        chain = sorted(
            (r for r in rows if r["direction"] == direction),
            key=lambda r: order.index(r["frequency_hz"]),
        )
        assert chain[0]["t_start"] == 0.0
        for before, after in zip(chain, chain[1:]):
            assert after["t_start"] == before["t_end"]
        for r in chain:
            assert r["amplitude"] == pytest.approx(exact(r["frequency_hz"])[0], rel=2e-3)
            assert r["branch"] == "single"  # a linear structure has one steady state


def test_a_point_inserted_into_a_finished_chain_is_refused(tmp_path):
    path = sdof_file(tmp_path)
    run_sweep(spec_for(path, (37.0, 39.0), direction="up"), tmp_path / "out", workers=1)
    # appending at the chain's end continues from its last state: allowed
    computed = []
    run_sweep(
        spec_for(path, (37.0, 39.0, 40.0), direction="up"),
        tmp_path / "out",
        workers=1,
        on_point=computed.append,
    )
    assert [r["frequency_hz"] for r in computed] == [40.0]
    # inserting 38 Hz would rewrite the history of 39 and 40 Hz: refused
    with pytest.raises(InputError, match="inserted before 39 Hz"):
        run_sweep(
            spec_for(path, (37.0, 38.0, 39.0, 40.0), direction="up"), tmp_path / "out", workers=1
        )


def test_added_mass_baseline_is_the_closed_form_with_the_particles_mass():
    deck = read_deck(DECKS / "beam_64.inp")
    bare = build_model(without_particles(deck))
    assert bare.n_particles == 0
    sdof = linear_sdof(bare, 9, 1)
    # Table 4 / the deck's header: MASS 2.04213e-4 on node 9 (+ half the spring element's
    # 1e-12), k = 11.4823, c = 3.08293e-4
    assert sdof.m == pytest.approx(2.04213e-4 + 0.5e-12, rel=1e-12)
    assert (sdof.k, sdof.c) == (11.4823, 0.000308293)
    n, radius, rho = 64, 0.03125, 0.000732971
    mp = n * rho * 4.0 / 3.0 * math.pi * radius**3
    assert particle_mass(build_model(deck)) == pytest.approx(mp, rel=1e-12)
    added = linear_sdof(build_model(with_added_mass(deck, 9, mp)), 9, 1)
    assert added.m == pytest.approx(sdof.m + mp, rel=1e-12)
    # a deck with particles is not a linear SDOF
    assert linear_sdof(build_model(deck), 9, 1) is None


def row(config, f, amp, direction="", drive=1.0, **kw):
    return {
        "config": config,
        "frequency_hz": f,
        "amplitude": amp,
        "direction": direction,
        "drive": drive,
        "change": 0.001,
        "irregular": False,
        **kw,
    }


def test_hysteresis_puts_points_on_high_and_low_branches():
    from x3dpd.design.sweep import label_branches

    rows = [
        row("deck", 37.0, 1.0, "up"),
        row("deck", 37.0, 0.5, "down"),
        row("deck", 38.0, 0.30, "up"),
        row("deck", 38.0, 0.301, "down"),
        row("deck", 39.0, 0.2, "up", irregular=True),
        row("deck", 39.0, 0.2, "down"),
    ]
    label_branches(rows)
    assert [r["branch"] for r in rows] == ["high", "low", "single", "single", "irregular", "single"]


def test_peak_attenuation_is_20_log10_of_the_peaks_ratio():
    import numpy as np

    from x3dpd.analysis.design_plots import attenuations

    rows = [
        row("deck", 37.0, 0.01),
        row("deck", 38.0, 0.02),
        row("undamped", 37.0, 0.05),
        row("undamped", 38.0, 0.1),
    ]
    curve = {("added-mass", 1.0): (np.array([37.0, 37.5, 38.0]), np.array([0.1, 0.2, 0.1]))}
    att = {a["baseline"]: a["attenuation_db"] for a in attenuations(rows, curve)}
    # swept undamped peak 0.1 / damper peak 0.02 = 5 -> 13.98 dB; closed-form curve peak 0.2
    assert att["undamped"] == pytest.approx(20 * math.log10(5.0), rel=1e-12)
    assert att["added-mass"] == pytest.approx(20 * math.log10(10.0), rel=1e-12)


def test_every_point_carries_its_intervals(tmp_path):
    """sweep.csv's amplitude_ci, phase_ci and dissipated_per_cycle_ci (95 % half-widths, the
    columns' units): a particle-free structure's are its extrapolation's remaining
    uncertainty, within the tolerance. They measure the steady state of the run, not the time
    step's error: the exact answer lies within them plus the integrator's error, which
    resonance amplifies (test_the_linear_structures_sweep_equals_its_closed_form: 2e-3; 4.4e-5
    at 36 Hz)."""
    out = tmp_path / "out"
    rows = run_sweep(spec_for(sdof_file(tmp_path), (36.0, 38.0)), out, workers=1)
    header = (out / "sweep.csv").read_text().splitlines()[0].split(",")
    for column in ("amplitude_ci", "phase_ci", "dissipated_per_cycle_ci"):
        assert column in header
    for r in rows:
        amp, phase = exact(r["frequency_hz"])
        assert r["converged"] and not r["irregular"]
        assert 0.0 <= r["amplitude_ci"] <= 1e-3 * r["amplitude"]
        assert abs(r["amplitude"] - amp) <= r["amplitude_ci"] + 2e-3 * amp
        assert math.isfinite(r["phase_ci"]) and math.isfinite(r["dissipated_per_cycle_ci"])


def test_a_points_compile_time_counts_its_predicted_starts_loop_too(tmp_path, monkeypatch):
    """Issue 33, item 20: the predicted start builds the scene's step loop before the run does,
    and that first build was the compile a user waits for; compile_s must count it. Every loop
    build is made 0.4 s slower here, so a point's two builds (its predicted start's and its
    run's) take at least 0.8 s."""
    import time

    import x3dpd.solver.simulation as simulation

    real = simulation.make_advance

    def slow(*args, **kw):
        time.sleep(0.4)
        return real(*args, **kw)

    monkeypatch.setattr(simulation, "make_advance", slow)
    (row,) = run_sweep(spec_for(sdof_file(tmp_path), (38.0,)), tmp_path / "out", workers=1)
    assert row["start"] == "predicted"
    assert row["compile_s"] >= 0.8


def test_the_sweep_says_how_each_point_starts(tmp_path):
    from click.testing import CliRunner

    from x3dpd.cli import _register, cli

    _register()
    path = sdof_file(tmp_path)
    for options, words in (
        ((), "each point from its predicted steady state"),
        (("--no-predict",), "each point from the deck's initial state"),
    ):
        res = CliRunner().invoke(
            cli,
            [
                "sweep",
                str(path),
                "--freq",
                "38",
                "--amp",
                repr(TABLE4_DRIVE),
                "--node",
                "1",
                "--dof",
                "1",
                "--workers",
                "1",
                "--out",
                str(tmp_path / f"o{len(options)}"),
                *options,
            ],
        )
        assert res.exit_code == 0, res.output
        assert words in res.output and "from rest" not in res.output


def test_sweep_and_design_csv_write_numpy_numbers_as_plain_numbers(tmp_path):
    """np.float64 is a float, and numpy 2 writes its repr as np.float64(37.5): a row value out
    of numpy (a peak search's frequency, a pooled amplitude) would have reached sweep.csv and
    design.csv so, unreadable. Both tables write the same text as for Python floats."""
    import numpy as np

    from x3dpd.design.design_table import write_design_csv
    from x3dpd.design.sweep_table import write_csv

    values = {"config": "deck", "frequency_hz": 37.5, "drive": 1e-3, "amplitude": 2.5e-3}
    as_numpy = {k: (np.float64(v) if isinstance(v, float) else v) for k, v in values.items()}
    for write, name in ((write_csv, "sweep.csv"), (write_design_csv, "design.csv")):
        plain, numpy_ = tmp_path / f"plain_{name}", tmp_path / f"numpy_{name}"
        write(plain, [values])
        write(numpy_, [as_numpy])
        assert numpy_.read_text() == plain.read_text()
        assert "np." not in numpy_.read_text() and ",37.5," in plain.read_text()
