r"""Rolling resistance of constant torque: the "elastic-plastic spring-dashpot" family's type A
(Ai, Chen, Rotter & Ooi, Powder Technology 206 (2011) 269-282, model A; LIGGGHTS ``cdt``).

The contact resists the relative rolling :math:`\boldsymbol\omega_r = \boldsymbol\omega_i -
\boldsymbol\omega_j` (a wall: the particle's own :math:`\boldsymbol\omega`) with a torque of
constant magnitude

.. math::  \mathbf M_r = -\mu_r R^* |F_N|\,\hat{\boldsymbol\omega}_r

on body i (and :math:`-\mathbf M_r` on j): :math:`\mu_r` the rolling-resistance coefficient
(FRICTION card, the mean of the two groups' for a pair), :math:`R^*` the effective radius (a
wall: R). Model A chatters when the rolling stops (the torque flips every step); we regularise
it as the report's Coulomb law is (Eq. 30, x3dpd.physics.coulomb):
:math:`|\mathbf M_r| = \min(\mu_r R^* |F_N|,\; I_r |\boldsymbol\omega_r|/(2\Delta t))` with the
rolling inertia :math:`I_r = I_i I_j/(I_i + I_j)` (a wall: :math:`I_i`), so the stick branch halves
the relative rolling per step instead of reversing it, and whenever the contact truly rolls the
torque is exactly model A's.

Closed form (tests/physics/test_rolling.py): a solid sphere rolling without slip on a flat wall
under its weight decelerates at :math:`\dot v = -\mu_r R m g/(R(m + I/R^2)) = -\tfrac57 \mu_r g`.

Energy: the torque's work over a step is booked by the trapezoid
:math:`-\tfrac12(\mathbf M_{old} + \mathbf M)\cdot\boldsymbol\omega_r\Delta t` (velocity Verlet's
own accounting, x3dpd.solver.ledger_checks), so the history is the last step's torque.
Units: torque force*length, angular velocity rad/s.
"""

from __future__ import annotations

import math

from x3dpd._jit import step_kernel

__all__ = ["N_HISTORY", "ROLL_FLOOR", "rolling_torque"]

#: History per contact: the last step's torque on body i (3 values).
N_HISTORY = 3
#: Relative rolling speeds at or below this [rad/s] get no torque (as Coulomb's SLIP_FLOOR).
ROLL_FLOOR = 1e-100


@step_kernel
def rolling_torque(wrx, wry, wrz, fn, lever, inertia, dt, h, row, col):
    """(M_x, M_y, M_z, dissipated) of model A regularised (module docstring); the last step's
    torque in ``h[row, col:col + 3]`` (read, then replaced by this step's)."""
    mox = h[row, col]
    moy = h[row, col + 1]
    moz = h[row, col + 2]
    w = math.sqrt(wrx * wrx + wry * wry + wrz * wrz)
    mx = 0.0
    my = 0.0
    mz = 0.0
    if w > ROLL_FLOOR:
        stick = 0.5 * inertia / dt
        limit = lever * abs(fn)
        c = stick if stick * w < limit else limit / w
        mx = -c * wrx
        my = -c * wry
        mz = -c * wrz
    h[row, col] = mx
    h[row, col + 1] = my
    h[row, col + 2] = mz
    lost = -0.5 * ((mox + mx) * wrx + (moy + my) * wry + (moz + mz) * wrz) * dt
    return mx, my, mz, lost
