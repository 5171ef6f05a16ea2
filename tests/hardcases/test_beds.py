"""Many particles pressed together: a cavity packed full (simple cubic lattice, ~1 % clearance)
shaken at 10 g, and 512 small spheres. Each run must end with a bounded ledger, every particle
inside its cavity and every value finite -- or stop with a diagnosis (which would fail here).

The cavity is a spring-mounted box (x3dpd.deck.generate.box_cavity_deck, the beam decks'
structure) driven by a sine force F on its master node. Far above the structure's resonance the
box's acceleration amplitude is F/M * w^2/(w^2 - w_n^2) (undamped SDOF); F is chosen for 10 g.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from x3dpd.deck.generate import Material3, box_cavity_deck, lattice_fill
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

G = 386.1
#: Section 8.3 particles (decks/beam_64.inp): E0, E1, tau1, nu, mu, density.
BEAM_MATERIAL = Material3(2.75e7, 5.0e6, 2.0e-6, 0.33, 0.3, 0.283 / 386.1)
STRUCTURE_MASS, STIFFNESS, HZ = 1e-3, 11.4823, 60.0


def packed_deck(n_side, radius, *, clearance, dt, peak_g=10.0, tmax=1.0, trest=0.0):
    """(cavity size, deck): n_side^3 spheres on a lattice with ``clearance`` (a fraction of the
    diameter) to each other and the walls, the box driven at ``peak_g``."""
    gap = clearance * 2 * radius
    size = n_side * (2 * radius + gap) + gap
    pos = lattice_fill((size, size, size), radius, n_side**3, gap=gap)
    w, wn = 2 * math.pi * HZ, math.sqrt(STIFFNESS / STRUCTURE_MASS)
    force = peak_g * G * STRUCTURE_MASS * (w * w - wn * wn) / (w * w)
    deck = box_cavity_deck(
        size=(size,) * 3,
        particles=pos,
        radius=radius,
        material=BEAM_MATERIAL,
        structure_mass=STRUCTURE_MASS,
        stiffness=STIFFNESS,
        damping=3e-4,
        dt=dt,
        itrac=int(round(1e-4 / dt)),
        tmax=tmax,
        trest=trest,
        usrfrc=(f"sine:node=9,dof=1,amp={force!r},hz={HZ!r}",),
    )
    return size, deck


def shaken_box(n_side, radius, *, clearance, dt):
    size, deck = packed_deck(n_side, radius, clearance=clearance, dt=dt)
    return size, Simulation(build_model(deck))


def check_bed(sim, block, size, radius):
    assert np.all(np.isfinite(block.data)) and np.all(np.isfinite(block.energy))
    e = block.energy
    assert np.all(np.abs(e[:, 11]) <= sim.energy_tolerance * sim.state.scale)
    master_x = block.data[:, 0, 0]
    p = block.data[:, 1:, :3]
    lo = np.stack([master_x, np.zeros_like(master_x), np.zeros_like(master_x)], axis=1)
    rel = p - lo[:, None, :]
    # centres stay within the cavity, allowing the 25 % penetration limit the solver enforces
    assert np.all(rel > radius * 0.75) and np.all(rel < size - radius * 0.75)
    return master_x


@pytest.mark.parametrize(
    "n_side, radius, dt, seconds",
    [
        (4, 0.03125, 5e-7, 0.03),  # 64 report-size spheres, packed full
        (8, 0.015625, 2.5e-7, 0.01),  # 512 small spheres (half the radius: half the contact time)
    ],
    ids=["packed-64", "packed-512"],
)
def test_a_packed_cavity_shaken_at_10g(n_side, radius, dt, seconds):
    size, sim = shaken_box(n_side, radius, clearance=0.01, dt=dt)
    block = sim.advance(int(round(seconds / dt)))
    x = check_bed(sim, block, size, radius)
    # the box really was shaken at ~10 g: its acceleration (second difference of the 1e-4 s
    # samples, error (w h)^2/12 ~ 1e-3) peaks near 10 g over the last drive period; the free
    # response at w_n adds (w_n/w)^2 ~ 8 % of it and the particles' impacts jolt it: 25 %
    acc = np.diff(x, 2) / 1e-4**2
    tail = acc[-int(round(1 / HZ / 1e-4)) :]
    assert np.max(np.abs(tail)) == pytest.approx(10 * G, rel=0.25)
