"""One run configured once (x3dpd/api/config.py): ``x3dpd.run_config`` resolves every default of
a run from the deck and checks every option before anything runs; ``x3dpd.run`` takes a
RunConfig or the keywords it always took."""

from __future__ import annotations

import inspect
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import x3dpd
from x3dpd.physics.tangential_laws import TANGENTIAL_LAWS

DECKS = Path(__file__).resolve().parents[2] / "decks"
BEAM = DECKS / "beam_1.inp"
IMPACT = DECKS / "impact_wall.inp"

#: The keywords x3dpd.run took before RunConfig (its public contract).
RUN_KEYWORDS = (
    "tmax dt usrfrc usrfrc_mode motion friction trace energy overwrite restart itrac "
    "trace_nodes keep_trace initial_state stop stop_every progress on_compile usrfrc_python "
    "penetration_limit energy_tolerance threads handle_signals command"
).split()


def test_every_default_comes_from_the_deck():
    deck = x3dpd.load_deck(BEAM)
    par = deck.parameters
    config = x3dpd.run_config(deck)
    assert config.tmax == par.tmax
    assert not config.step.auto and config.step.dt == par.dtmax
    assert config.itrac == par.itrac
    assert config.steps == round((par.tmax - par.time) / par.dtmax)
    traced = [int(n) for n in config.model.node_ids[list(config.trace_nodes)]]
    assert traced == list(deck.trace.nodes)
    assert config.friction == x3dpd.api.DEFAULT_FRICTION in TANGENTIAL_LAWS
    assert config.files is None and config.threads == 1 and config.initial_state is None
    assert config.usrfrc == () and config.replaced == ()


def test_a_deck_whose_dtmin_is_below_dtmax_chooses_its_step():
    deck = x3dpd.load_deck(BEAM)
    par = deck.parameters
    finer = replace(deck, parameters=replace(par, dtmin=par.dtmax / 8))
    step = x3dpd.run_config(finer).step
    assert step.auto and step.dt == par.dtmax and step.dtmin == par.dtmax / 8
    # auto without a usable DTMIN goes down to DTMAX / 1024; a number is a fixed step
    assert x3dpd.run_config(deck, dt="auto").step.dtmin == par.dtmax / 1024
    assert not x3dpd.run_config(finer, dt=1e-7).step.auto


def test_the_options_win_over_the_deck(tmp_path):
    config = x3dpd.run_config(
        BEAM,
        tmax=0.01,
        itrac=7,
        friction="mindlin",
        trace_nodes=[9],
        usrfrc=["sine:node=9,dof=1,amp=1e-3,hz=30"],
        trace=tmp_path / "b.trace.txt",
    )
    assert (config.tmax, config.itrac, config.friction) == (0.01, 7, "mindlin")
    assert [int(config.model.node_ids[i]) for i in config.trace_nodes] == [9]
    deck_drive = x3dpd.load_deck(BEAM).usrfrc[0].specs
    assert list(config.replaced) == [s.strip() for s in deck_drive]
    assert config.files.energy == str(tmp_path / "b.energy.csv")
    assert not list(tmp_path.iterdir())  # configuring writes nothing


@pytest.mark.parametrize(
    "options, phrase",
    [
        (dict(friction="stick"), "friction 'stick'"),
        (dict(dt="fast"), "dt must be a number of seconds or 'auto'"),
        (dict(dt=-1e-7), "time step must be a positive number"),
        (dict(itrac=0), "ITRAC must be >= 1"),
        (dict(tmax=math.nan), "--tmax must be a finite number"),
        (dict(tmax=-1.0), "is before the start time"),
        (dict(trace_nodes=[9, 99999]), "node(s) 99999 are not in the deck"),
        (dict(usrfrc_mode="both"), "usrfrc_mode must be 'replace' or 'add'"),
        (dict(energy_tolerance=0.0), "energy_tolerance must be a positive fraction"),
        (dict(restart=True, trace=None), "restart=True needs the trace path"),
        (dict(threads=0), "expected a whole number >= 1"),
        (dict(initial_state="start"), "initial_state must be the final_state"),
    ],
)
def test_a_bad_option_is_an_input_error_before_anything_runs(tmp_path, options, phrase):
    options = {"trace": tmp_path / "t.trace.txt", **options}
    with pytest.raises(x3dpd.InputError) as err:
        x3dpd.run_config(BEAM, **options)
    assert phrase in str(err.value)
    with pytest.raises(x3dpd.InputError):  # run raises the same, before it writes
        x3dpd.run(BEAM, **options)
    assert not list(tmp_path.iterdir())


def test_replace_checks_again_and_rebuilds_the_model_only_for_the_forces():
    config = x3dpd.run_config(BEAM)
    later = config.replace(tmax=0.5, itrac=3)
    assert (later.tmax, later.itrac) == (0.5, 3) and later.model is config.model
    assert later.deck is config.deck and later.key == config.key
    driven = config.replace(usrfrc=["sine:node=9,dof=1,amp=1e-3,hz=30"])
    assert driven.model is not config.model and driven.replaced
    with pytest.raises(x3dpd.InputError):
        config.replace(itrac=-1)
    with pytest.raises(TypeError):
        config.replace(tmax_s=1.0)


def test_run_keeps_every_keyword_it_took():
    names = list(inspect.signature(x3dpd.run).parameters)
    assert names[0] == "deck" and set(RUN_KEYWORDS) <= set(names[1:])
    assert set(names[1:]) == set(inspect.signature(x3dpd.run_config).parameters) - {"deck"}


def test_a_config_runs_as_its_options_do(tmp_path):
    """The same bytes whether the options go to run or to run_config; a config continued with
    changed options goes on from the state it is given."""
    options = dict(tmax=2e-6, itrac=5)
    by_keywords = x3dpd.run(IMPACT, trace=tmp_path / "a.trace.txt", **options)
    config = x3dpd.run_config(IMPACT, trace=tmp_path / "b.trace.txt", **options)
    by_config = x3dpd.run(config)
    for name in ("position", "velocity", "spin"):
        assert np.array_equal(getattr(by_keywords.trace, name), getattr(by_config.trace, name))
    assert np.array_equal(by_keywords.energy.data, by_config.energy.data)
    later = x3dpd.run(config, tmax=4e-6, trace=None, initial_state=by_config.final_state)
    whole = x3dpd.run(IMPACT, tmax=4e-6, itrac=5)
    n = later.trace.time.shape[0]
    assert np.array_equal(later.trace.time, whole.trace.time[-n:])
    assert np.array_equal(later.trace.position, whole.trace.position[-n:])
