"""Registry of the tangential (friction) laws the step loop can run (one module per law).

A law module provides

* ``N_HISTORY``: how many history values it keeps per contact. They are appended to the
  contact's state row (x3dpd.solver.contact_lists), created zero when the contact starts,
  cleared when it ends, carried across list rebuilds and saved in restart dumps with the row;
  in the vectorized pair pass they sit in the history scratch (one contiguous column per
  value, after the Maxwell terms), like the normal law's histories.
* ``STORES_ENERGY``: whether the law keeps elastic energy in the contact (a tangential spring).
* ``tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, ct, dt, gamma,
  fox, foy, foz, h, row, col)`` -> ``(F_tx, F_ty, F_tz, dU)``: the tangential force on the
  body whose contact point slips with v_t (|v_t| = vt) relative to the other, given the unit
  normal n, the applied normal force F_N, the approach a, the tangential effective mass m_t,
  the static and kinetic friction coefficients, this step's tangential stiffness ``kt``
  (the normal law's ``tangential_stiffness`` constant times its ``stiffness_shape(a)``; only
  formed for a law that ``STORES_ENERGY``), the tangential dashpot ``ct`` = eta sqrt(k_t)
  [force*s/length] that matches the normal law's damping (its ``tangential_damping`` constant
  eta; 0 under an undamped normal law: only formed for a law that ``STORES_ENERGY`` under a
  ``DAMPED`` normal law), the step dt the contact slips over (0 when the loop evaluates the
  forces at a state, x3dpd.solver.simulation.Simulation.compute_forces: the law then gives the
  force of its history as it stands, and what it writes is discarded) and gamma = 1/(2 dt) of
  the run's step; the last step's
  force F_old (``fox``...; the state row's S_FT columns);
  its history ``h[row, col:col + N_HISTORY]`` (read and written). dU is the change of the
  stored energy over the step: the step loop books it as elastic, the rest of the slip work
  as dissipated (the ledger stays closed).
* ``stored_energy(fx, fy, fz, h, row, col)``: the energy the contact stores with force F_t and
  history ``h[row, col:]`` [energy].
* a law with a spring also ``contact_time(normal_law, i, j, v)``: the spring's half period at
  its stiffest, which the step estimate and ``x3dpd check`` resolve as they resolve a normal
  law's contact time (x3dpd.model.timestep).

The loop imports the selected law into the shared tangential response (``_tangential`` in
x3dpd.solver._template_contact), which wall and pair contacts both call. Adding a law is a
module plus a line here (docs/engine.md, "Adding a tangential law").
"""

from __future__ import annotations

from typing import NamedTuple

from x3dpd.physics import coulomb, linear_history, mindlin


class TangentialLaw(NamedTuple):
    """A registered law: its module and the name of its force function there."""

    module: object
    force: str = "tangential_force"


#: name -> law (the names of ``--friction`` and of the FRICTION card)
TANGENTIAL_LAWS = {
    "regularized": TangentialLaw(coulomb, "regularized_tangential_force"),  # report Eq. 30
    "coulomb": TangentialLaw(coulomb, "coulomb_tangential_force"),          # report Eq. 29
    "mindlin": TangentialLaw(mindlin),   # Hertz-Mindlin spring with history (mindlin_rescale/force)
    "linear_history": TangentialLaw(linear_history),   # LAMMPS's tangential linear_history
}
#: The law of a run that asks for none on a deck without a FRICTION card (report Eq. 30): the
#: one place the default is named (x3dpd.api.DEFAULT_FRICTION, Simulation, the time step).
DEFAULT_LAW = "regularized"

#: Columns of the tangential tables (``Particles.tan_wall``, ``tan_pair``): kappa, mu_k, the
#: rolling lever mu_r R*, the rolling inertia I_r, the dashpot constant eta.
TANGENTIAL_COLUMNS = 5

#: What the loop imports from a law module besides its force function.
TANGENTIAL_LAW_API = ("stored_energy", "N_HISTORY", "STORES_ENERGY")


def n_history(name: str) -> int:
    """History values per contact of the law ``name``."""
    return int(TANGENTIAL_LAWS[name].module.N_HISTORY)


def tangential_tables(name: str, normal_law, bodies, mu_kinetic, rep, rolling: str = "none",
                      mu_roll=None, inertia=None):
    """The step loop's tangential and rolling constants ``(tan_wall (P, 5), tan_pair (K, K, 5))``
    of every particle on a rigid wall and of every pair of particle kinds (representatives
    ``rep``): the normal law's ``tangential_stiffness`` constant kappa, the kinetic friction
    coefficient, the rolling lever mu_r R* [length], the rolling inertia I_r [mass length^2]
    (x3dpd.physics.rolling) and the normal law's ``tangential_damping`` constant eta
    [sqrt(mass)] of the dashpot c_t = eta sqrt(k_t). A pair's mu_k and mu_r are the means of
    the two; its R* and I_r the series values. ``bodies``: the particles'
    x3dpd.physics.normal_laws.ContactBody; ``inertia`` their moments of inertia. Columns a
    scene's laws do not read stay zero."""
    import numpy as np

    mu_k = np.asarray(mu_kinetic, dtype=np.float64)
    wall = np.zeros((len(bodies), TANGENTIAL_COLUMNS))
    pair = np.zeros((len(rep), len(rep), TANGENTIAL_COLUMNS))
    if TANGENTIAL_LAWS[name].module.STORES_ENERGY:
        stiffness, damping = normal_law.tangential_stiffness, normal_law.tangential_damping
        wall[:, 0] = [stiffness(b, None) for b in bodies]
        wall[:, 1] = mu_k
        wall[:, 4] = [damping(b, None) for b in bodies]
        for a, p in enumerate(rep):
            for b, q in enumerate(rep):
                pair[a, b, :2] = stiffness(bodies[p], bodies[q]), 0.5 * (mu_k[p] + mu_k[q])
                pair[a, b, 4] = damping(bodies[p], bodies[q])
    if rolling != "none":
        mu_r = np.asarray(mu_roll, dtype=np.float64)
        radius = np.array([b.radius for b in bodies])
        inertia = np.asarray(inertia, dtype=np.float64)
        wall[:, 2] = mu_r * radius
        wall[:, 3] = inertia
        for a, p in enumerate(rep):
            for b, q in enumerate(rep):
                r_star = radius[p] * radius[q] / (radius[p] + radius[q])
                pair[a, b, 2] = 0.5 * (mu_r[p] + mu_r[q]) * r_star
                pair[a, b, 3] = inertia[p] * inertia[q] / (inertia[p] + inertia[q])
    return wall, pair
