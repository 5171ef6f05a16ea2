"""A run that goes unstable stops with a diagnosis (UnstableRunError), never prints garbage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.deck.cards import Boundary, Deck, Element, Initial, Mass, Material, Node, Parameters
from x3dpd.deck.generate import Material3, box_cavity_deck, lattice_fill
from x3dpd.errors import UnstableRunError
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation


def sdof_deck(k: float, m: float, dt: float) -> Deck:
    return Deck(
        parameters=Parameters(0.0, 1.0, 0.0, dt, dt, 0, 1e9, 0, 5, 0, 10),
        materials=(Material(2, 1, 0.0, 1.0, k, 0.0, 0.0, 0.0),),
        nodes=(Node(1, 0.0, 0.0, 0.0),),
        elements=(Element(1, 2, (1,)),),
        masses=(Mass(1, m, 0.0, 0.0, 0.0),),
        boundaries=(Boundary(1, 1, 1, (2, 3, 4, 5, 6)),),
        initials=(Initial(1, (1.0, 0.0, 0.0)),),
    )


def test_stable_spring_runs_and_conserves_the_modified_energy():
    k, m = 100.0, 1.0
    dt = 1.9 / math.sqrt(k / m)  # omega dt = 1.9 < 2: stable, if inaccurate
    sim = Simulation(build_model(sdof_deck(k, m, dt)))
    block = sim.advance(2000)
    # for a linear spring the residual is zero to round-off (the ledger's Verlet correction)
    assert np.max(np.abs(block.energy[:, 11])) < 1e-12 * 0.5


def test_step_beyond_the_spring_stability_limit_is_diagnosed():
    k, m = 100.0, 1.0
    dt = 2.1 / math.sqrt(k / m)  # omega dt = 2.1 > 2: exponential growth
    sim = Simulation(build_model(sdof_deck(k, m, dt)))
    with pytest.raises(UnstableRunError, match="stability limit") as err:
        sim.advance(2000)
    # caught while the amplitude is still finite (growth ~1.5x per period at omega dt = 2.1;
    # overflow would come after ~560 steps), with the stability diagnosis, not "non-finite"
    assert err.value.step <= 200


def test_particles_smashing_through_walls_with_a_huge_step_are_diagnosed():
    mat = Material3(30e6, 0.0, 1.0, 0.3, 0.0, 7.32971e-4)
    pos = lattice_fill((0.25, 0.25, 0.25), 0.03125, 8, gap=0.01)
    deck = box_cavity_deck(
        size=(0.25, 0.25, 0.25),
        particles=pos,
        radius=0.03125,
        material=mat,
        structure_mass=1.0,
        stiffness=1.0,
        damping=0.0,
        dt=2e-5,
        itrac=10,
        gravity=(0.0, -386.1 * 1000, 0.0),
    )
    sim = Simulation(build_model(deck))
    with pytest.raises(UnstableRunError) as err:
        sim.advance(200000)
    text = str(err.value)
    # the first sign of the broken step: a penetration, a particle out of its cavity, or the
    # energy the impacts created (each ledger row judged by the energy scale up to it)
    assert (
        "penetrated" in text
        or "left its cavity" in text
        or ("without a source" in text and "steps (at least 6 are needed" in text)
    )
    assert "time step" in text
    assert err.value.node == 0 or err.value.node >= 10  # 0: no node named
