"""Registry of the normal contact laws the step loop can run (one module per law).

A law module provides ``wall_force(a, a_old, a_rate, p, particles, states, s, col, n_terms)``,
``pair_force(a, a_old, a_rate, pi, pj, ki, kj, particles, states, s, col, n_terms)`` (the force
before clamping), ``stored_energy(fn, a, k)`` and the flags ``CLAMPED`` (apply max(0, F)),
``USES_RATE`` (reads da/dt) and ``DAMPED`` (dissipates without Maxwell terms). The step-loop
factory imports the selected module's functions into the loop (x3dpd.solver.variants), where
numba inlines them. Adding a law is a module plus a line here.
"""

from __future__ import annotations

from x3dpd.physics import hooke, maxwell

#: name -> module of the law
NORMAL_LAWS = {
    "lee_radok": maxwell,   # report 7.2.1-7.2.3: Hertz with any number of Maxwell terms
    "hooke": hooke,         # linear spring-dashpot with restitution e (LAMMPS/LIGGGHTS hooke)
}

#: What the loop imports from a law module.
NORMAL_LAW_API = ("wall_force", "pair_force", "stored_energy", "CLAMPED", "USES_RATE", "DAMPED")
