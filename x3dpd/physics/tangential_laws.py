"""Registry of the tangential (friction) laws the step loop can run (one module per law).

A law module provides

* ``N_HISTORY``: how many history values it keeps per contact. They are appended to the
  contact's state row (x3dpd.solver.contact_lists), created zero when the contact starts,
  cleared when it ends, carried across list rebuilds and saved in restart dumps with the row;
  in the vectorized pair pass they sit in the history scratch (one contiguous column per
  value, after the Maxwell terms), like the normal law's histories.
* ``STORES_ENERGY``: whether the law keeps elastic energy in the contact (a tangential spring).
* ``tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, dt, gamma,
  fox, foy, foz, h, row, col)`` -> ``(F_tx, F_ty, F_tz, dU)``: the tangential force on the
  body whose contact point slips with v_t (|v_t| = vt) relative to the other, given the unit
  normal n, the applied normal force F_N, the approach a, the tangential effective mass m_t,
  the static and kinetic friction coefficients, this step's tangential stiffness ``kt``
  (the normal law's ``tangential_stiffness`` constant times its ``stiffness_shape(a)``; only
  formed for a law that ``STORES_ENERGY``), the step dt and gamma = 1/(2 dt); the last step's force F_old (``fox``...; the state row's S_FT columns);
  its history ``h[row, col:col + N_HISTORY]`` (read and written). dU is the change of the
  stored energy over the step: the step loop books it as elastic, the rest of the slip work
  as dissipated (the ledger stays closed).
* ``stored_energy(fx, fy, fz, h, row, col)``: the energy the contact stores with force F_t and
  history ``h[row, col:]`` [energy].

The loop imports the selected law into the shared tangential response (``_tangential`` in
x3dpd.solver._template_contact), which wall and pair contacts both call. Adding a law is a
module plus a line here (docs/engine.md, "Adding a tangential law").
"""

from __future__ import annotations

from typing import NamedTuple

from x3dpd.physics import coulomb, mindlin


class TangentialLaw(NamedTuple):
    """A registered law: its module and the name of its force function there."""

    module: object
    force: str = "tangential_force"


#: name -> law (the names of ``--friction`` and of the FRICTION card)
TANGENTIAL_LAWS = {
    "regularized": TangentialLaw(coulomb, "regularized_tangential_force"),  # report Eq. 30
    "coulomb": TangentialLaw(coulomb, "coulomb_tangential_force"),          # report Eq. 29
    "mindlin": TangentialLaw(mindlin),   # Hertz-Mindlin spring with history (mindlin_rescale/force)
}

#: What the loop imports from a law module besides its force function.
TANGENTIAL_LAW_API = ("stored_energy", "N_HISTORY", "STORES_ENERGY")


def n_history(name: str) -> int:
    """History values per contact of the law ``name``."""
    return int(TANGENTIAL_LAWS[name].module.N_HISTORY)


def tangential_tables(name: str, normal_law, bodies, mu_kinetic, rep):
    """The step loop's tangential constants ``(tan_wall (P, 2), tan_pair (K, K, 2))``: the
    normal law's ``tangential_stiffness`` constant and the kinetic friction coefficient of
    every particle on a rigid wall and of every pair of particle kinds (representatives
    ``rep``; the pair's mu_k is the mean of the two, as its mu). ``bodies``: the particles'
    x3dpd.physics.normal_laws.ContactBody. Zeros for a law without a spring, which reads
    neither."""
    import numpy as np

    mu_k = np.asarray(mu_kinetic, dtype=np.float64)
    wall = np.zeros((len(bodies), 2))
    pair = np.zeros((len(rep), len(rep), 2))
    if not TANGENTIAL_LAWS[name].module.STORES_ENERGY:
        return wall, pair
    stiffness = normal_law.tangential_stiffness
    wall[:, 0] = [stiffness(b, None) for b in bodies]
    wall[:, 1] = mu_k
    for a, p in enumerate(rep):
        for b, q in enumerate(rep):
            pair[a, b] = stiffness(bodies[p], bodies[q]), 0.5 * (mu_k[p] + mu_k[q])
    return wall, pair
