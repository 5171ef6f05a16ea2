"""A sweep point of a scene with a rolling law books the rolling loss in its dissipation (the
ledger's split per cycle, design.csv's ``dissipated_*_per_cycle`` columns, and the two sums of
sweep.csv): it was left out. And the baselines of a deck whose FRICTION, HOOKE or WALLMAT cards
name its particle groups or walls are built without those cards (they were kept, and the
particle-free deck was refused: "NODLIM 9 names no PDMP group")."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from x3dpd.deck.cards import Friction, Hooke, WallMat
from x3dpd.deck.parser import read_deck
from x3dpd.design.spec import SweepSpec
from x3dpd.design.steady_state import Criterion, run_point
from x3dpd.design.sweep import deck_hash, plan

BEAM_1 = Path(__file__).resolve().parents[2] / "decks" / "beam_1.inp"


def _rolling_beam():
    deck = read_deck(BEAM_1)
    friction = (Friction(deck.pdmp[0].nodlim, "regularized", 0.3, 0.3, "epsd", 0.05),)
    return dataclasses.replace(deck, friction=friction)


@pytest.mark.parametrize("cards", ["friction+wallmat", "friction+hooke"])
def test_the_baselines_of_a_deck_with_friction_hooke_and_wall_cards_are_planned(cards):
    deck = _rolling_beam()
    if cards == "friction+wallmat":
        set_id = deck.contacts[0].triangles[0].set_id
        deck = dataclasses.replace(deck, wallmat=(WallMat(set_id, 4.5e5, 0.35, 0.4),))
    else:  # HOOKE replaces the viscoelastic law: the group's E1 set to 0
        elastic = tuple(dataclasses.replace(p, e1=0.0) for p in deck.pdmp)
        hooke = (Hooke(deck.pdmp[0].nodlim, 1.0e4, 0.8),)
        deck = dataclasses.replace(deck, pdmp=elastic, hooke=hooke)
    spec = SweepSpec(
        deck=deck,
        deck_text_hash=deck_hash(BEAM_1) + "-cards",
        frequencies=(36.5, 37.0),
        drives=(9.68080e-3,),
        node=9,
        dof=1,
        baselines=("undamped", "added-mass"),
    )
    chains, closed = plan(spec)
    assert len(chains) == 2
    assert {r["config"] for r in closed} == {"undamped", "added-mass"}
    assert all(r["method"] == "closed-form" and r["amplitude"] > 0.0 for r in closed)


# a loop variant of its own (a rolling law on the beam): python -m pytest -m validate
@pytest.mark.validate
def test_a_rolling_scene_books_the_rolling_loss_per_cycle():
    spec = SweepSpec(
        deck=_rolling_beam(),
        deck_text_hash=deck_hash(BEAM_1) + "-rolling",
        frequencies=(36.5,),
        drives=(9.68080e-3,),
        node=9,
        dof=1,
        criterion=Criterion(window=3, max_cycles=12),
    )
    chains, _ = plan(spec)
    (point,) = chains[0]
    row, _ = run_point(point)
    rolling = row["dissipated_rolling_per_cycle"]
    assert rolling > 0.0
    split = sum(
        row[f"dissipated_{name}_per_cycle"]
        for name in ("viscoelastic", "friction", "dampers", "rolling")
    )
    assert row["dissipated_per_cycle"] == pytest.approx(split, rel=1e-12)
    assert row["dissipated_particles_per_cycle"] == pytest.approx(
        split - row["dissipated_dampers_per_cycle"], rel=1e-12
    )
    assert math.isfinite(row["amplitude"])
