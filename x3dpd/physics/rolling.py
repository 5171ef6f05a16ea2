"""Registry of the rolling-resistance laws the step loop can run (one module per law).

A rolling law acts between two bodies in contact (or a body and a wall) on their relative
angular velocity :math:`\\boldsymbol\\omega_r = \\boldsymbol\\omega_i - \\boldsymbol\\omega_j`
(a wall: the particle's own). A law module provides

* ``N_HISTORY``: history values per contact, appended to the state row after the tangential
  law's (created zero, cleared with the contact, carried across list rebuilds, saved in restart
  dumps; in the pair pass's history scratch after the tangential law's columns);
* ``rolling_torque(wrx, wry, wrz, fn, lever, inertia, dt, h, row, col)`` -> ``(M_x, M_y, M_z,
  dissipated)``: the torque on body i (minus on j) from the applied normal force F_N, the
  contact's rolling lever ``lever`` = mu_r R* [length] and rolling inertia ``inertia`` =
  I_i I_j / (I_i + I_j) (a wall: I_i) [mass length^2], with its history ``h[row, col:]``; and
  the energy it dissipated over the step (booked in the ledger's own column
  ``dissipated_rolling``, which a scene with a rolling law has).

``none`` compiles nothing (the variant's ``HAS_ROLLING`` is False). Adding a law is a module
plus a line here (docs/engine.md, "Adding a tangential or rolling law").
"""

from __future__ import annotations

from x3dpd.physics import epsd

#: name -> module of the law (None: no rolling resistance); the names of the FRICTION card's ROLL
ROLLING_LAWS = {
    "none": None,
    "epsd": epsd,      # constant torque against the relative rolling (Ai et al. 2011, model A)
}


def n_history(name: str) -> int:
    """History values per contact of the rolling law ``name``."""
    law = ROLLING_LAWS[name]
    return 0 if law is None else int(law.N_HISTORY)
