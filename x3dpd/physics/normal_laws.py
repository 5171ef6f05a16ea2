"""Registry of the normal contact laws the step loop can run (one module per law).

A law module provides ``wall_force(a, a_old, a_rate, p, particles, states, s, col, n_terms)``,
``pair_force(a, a_old, a_rate, pi, pj, ki, kj, particles, states, s, col, n_terms)`` (the force
before clamping), ``stored_energy(fn, a, k)`` and the flags ``CLAMPED`` (apply max(0, F)),
``USES_RATE`` (reads da/dt) and ``DAMPED`` (dissipates without Maxwell terms). The step-loop
factory imports the selected module's functions into the loop (x3dpd.solver.variants), where
numba inlines them.

For the checks before and during a run (``x3dpd check``'s recommended step, the stop's diagnosis,
the step chosen by accuracy) a law module also provides ``contact_time(i, j, v)``: the duration
[s] of a head-on impact at normal speed ``v`` [length/s] of particle ``i`` on a rigid flat wall
(``j`` None) or on particle ``j``, both :class:`ContactBody`; and ``CONTACT_NAME``, how the
messages name that impact. For a tangential law with a spring (x3dpd.physics.mindlin) it provides
``tangential_stiffness(i, j)``, the constant kappa of k_t = kappa * ``stiffness_shape(a)``
(compiled into the loop), ``tangential_damping(i, j)``, the constant eta of the tangential
dashpot c_t = eta * sqrt(k_t) that damps the spring as the law damps its normal spring (0 for
an undamped law), and ``peak_approach(i, j, v)``, the largest approach of an impact
(where the spring is stiffest, for the step estimate).

A law owns its constants (:data:`NORMAL_LAW_SETUP`): ``CARD``, the deck card that selects it
(None: the default law, lee_radok) with one record per PDMP group, and ``PARAMS``, the names of
that record's constants after NODLIM (the model's ``law_params``, x3dpd.model.build_particles);
``WALL_STIFFNESS``, the card field that gives the wall stiffness directly (then a wall material,
WALLMAT, is refused; None: the law's wall stiffness comes from the moduli WALLMAT mixes);
``law_tables(params, mass, rep)``, the step loop's tables ``(law_wall (P, 2), law_pair (K, K,
2))`` from the particles' constants, masses and the kinds' representatives; and
``kind_keys(params, mass)``, the per-particle arrays that make two particles different kinds
under the law (x3dpd.physics.mixing.particle_kinds). The solver builds them through these
names only (x3dpd.solver.state). Adding a law is a module plus a line here.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from x3dpd.physics import hooke, maxwell
from x3dpd.physics.wall_material import particle_walls, plane_strain_moduli

#: name -> module of the law
NORMAL_LAWS = {
    "lee_radok": maxwell,   # report 7.2.1-7.2.3: Hertz with any number of Maxwell terms
    "hooke": hooke,         # linear spring-dashpot with restitution e (LAMMPS/LIGGGHTS hooke)
}

#: What the loop imports from a law module.
NORMAL_LAW_API = ("wall_force", "pair_force", "stored_energy", "CLAMPED", "USES_RATE", "DAMPED",
                  "stiffness_shape")

#: What the solver's setup and the model builder read of a law module (x3dpd.solver.state,
#: x3dpd.model.build_particles).
NORMAL_LAW_SETUP = ("CARD", "PARAMS", "WALL_STIFFNESS", "law_tables", "kind_keys")

#: What the checks read of a law module (never compiled into the loop).
NORMAL_LAW_CHECKS = ("contact_time", "CONTACT_NAME", "tangential_stiffness",
                     "tangential_damping", "peak_approach")


class ContactBody(NamedTuple):
    """One particle as the laws' ``contact_time`` sees it: what the deck gives every law
    (a law reads the fields it needs)."""

    mass: float          # [mass]
    radius: float        # [length]
    modulus: float       # instantaneous Young's modulus E0 + E1 + ... [force/length^2]
    poisson: float
    #: the law's own constants of the particle, in its PARAMS order (HOOKE: k_n [force/length]
    #: and e); () under a law without a card
    law: tuple = ()
    #: Young's modulus [force/length^2] and Poisson's ratio of the walls the body meets
    #: (WALLMAT, x3dpd.physics.wall_material); inf: rigid
    wall_e: float = math.inf
    wall_nu: float = 0.0


def contact_bodies(mass, radius, moduli, poisson, law_params=None) -> list[ContactBody]:
    """The :class:`ContactBody` of every particle from per-particle arrays: ``mass``,
    ``radius``, ``poisson`` (P,), ``moduli`` (P, K) (column 0 E0, then E1 ...), ``law_params``
    (P, n) the normal law's own constants (HOOKE: k_n and e), or None."""
    modulus = np.asarray(moduli, dtype=np.float64).reshape(len(radius), -1).sum(axis=1)
    law = (np.zeros((len(radius), 0)) if law_params is None
           else np.asarray(law_params, dtype=np.float64))
    return [ContactBody(float(m), float(r), float(e), float(nu), tuple(float(v) for v in c))
            for m, r, e, nu, c in zip(mass, radius, modulus, poisson, law)]


def group_bodies(group, mass, radius, moduli, poisson, law_params=None,
                 walls=None) -> dict:
    """Particle group -> the :class:`ContactBody` of its first particle (a group's particles
    are alike), from the per-particle arrays of :func:`contact_bodies` and ``group`` (P,).
    ``walls``: (E_w, nu_w) arrays (P,) of each particle's walls (inf: rigid; None: all rigid);
    a group gets its stiffest (largest E_w/(1-nu_w^2)), which gives its shortest wall
    contact."""
    group = np.asarray(group)
    if group.shape[0] == 0:
        return {}
    ids, first = np.unique(group, return_index=True)
    bodies = contact_bodies(np.asarray(mass)[first], np.asarray(radius)[first],
                            np.asarray(moduli)[first], np.asarray(poisson)[first],
                            None if law_params is None else np.asarray(law_params)[first])
    if walls is not None:
        e_w, nu_w = (np.asarray(w, dtype=np.float64) for w in walls)
        stiff = plane_strain_moduli(e_w, nu_w)
        for k, g in enumerate(ids):
            mine = np.flatnonzero(group == g)
            w = mine[np.argmax(stiff[mine])]
            bodies[k] = bodies[k]._replace(wall_e=float(e_w[w]), wall_nu=float(nu_w[w]))
    return dict(zip((int(g) for g in ids), bodies))


def scene_bodies(model) -> dict:
    """:func:`group_bodies` of a model (x3dpd.model.model.Model: its particle arrays, its normal
    law's constants and wall materials)."""
    e_w, nu_w, _ = particle_walls(model.particle_cavity, model.wall_material)
    return group_bodies(model.particle_group, model.mass[model.particle_start:], model.radius,
                        model.moduli, model.poisson, model.law_params, (e_w, nu_w))
