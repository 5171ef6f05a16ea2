r"""LAMMPS's ``tangential linear_history``: a tangential spring on the accumulated tangential
displacement, with a dashpot and Coulomb's limit (Cundall & Strack 1979).

The history is the contact points' accumulated tangential displacement :math:`\boldsymbol\xi`
(and the spring's stiffness of the last step). Each step

1. :math:`\boldsymbol\xi` is rotated onto the current tangent plane, keeping its magnitude;
2. :math:`\boldsymbol\xi \leftarrow \boldsymbol\xi + \mathbf v_t\Delta t` (:math:`\mathbf v_t`
   the contact point's slip velocity);
3. :math:`\mathbf F = -k_t\boldsymbol\xi - c_t\mathbf v_t`;
4. Coulomb's limit with one coefficient (the PCOF, or the FRICTION card's MUS): if
   :math:`|\mathbf F| > \mu F_N`, :math:`\mathbf F \leftarrow \mu F_N\,\mathbf F/|\mathbf F|`
   and the spring is reset to carry it with the dashpot still acting,
   :math:`\boldsymbol\xi = -(\mathbf F + c_t\mathbf v_t)/k_t` (LAMMPS's rule).

:math:`k_t` and :math:`c_t` come from the normal law (x3dpd.physics.tangential_laws): under
HOOKE a constant :math:`k_t = 2(1-\nu)/(2-\nu)\,k_n` and :math:`c_t = c_n\sqrt{k_t/k_n}`, which
is LAMMPS's ``hooke ... tangential linear_history`` with those ``xkt`` and ``xgammat``: the law
to compare with LAMMPS on a HOOKE bed. Under Hertz :math:`k_t = 8G^*\sqrt{R^*\delta}` grows with
the approach while :math:`\boldsymbol\xi` is kept -- LAMMPS's ``mindlin`` (no rescale), whose
stored energy :math:`\tfrac12 k_t\xi^2` grows without work while a contact loads: an elastic
impact can come out with more energy than it went in with. For Hertz contacts use ``mindlin``
(x3dpd.physics.mindlin), which is built to prevent that.

How it differs from ``mindlin`` under HOOKE: sticking, not at all (the same linear spring and
dashpot); sliding, ``mindlin`` rests the dashpot and the spring carries the whole limited force,
while here the spring carries the limited force minus the dashpot's.

Stored energy :math:`U = \tfrac12 k_t|\boldsymbol\xi|^2`. **Caveat (LAMMPS's rule itself):** with a
dashpot (HOOKE e < 1) the reset at the onset of sliding stores
:math:`\tfrac12|\mathbf F + c_t\mathbf v_t|^2/k_t` in the spring, energy no work put there; the
ledger books it as negative friction dissipation, and in gross sliding at a large slip speed the
energy audit stops the run (Chung & Ooi's test-6 deck at chi = 0.187,
``x3dpd decks/benchmarks/chung_ooi/test6_aluminium_alloy.inp --friction linear_history``: exit 3
at 3.6 us, friction -1.79 of the energy scale 6.45). Use it to compare with LAMMPS without
tangential damping (e = 1) or at partial slip; use ``mindlin`` for damped contacts.
Units: force, length, s.
"""

from __future__ import annotations

import math

from x3dpd._jit import step_kernel
from x3dpd.physics import mindlin

__all__ = ["N_HISTORY", "STORES_ENERGY", "tangential_force", "stored_energy", "contact_time"]

#: History per contact: the tangential displacement xi (3 values) [length] and k_t of the last
#: step [force/length].
N_HISTORY = 4
H_XI = 0
H_STIFFNESS = 3
#: The spring stores elastic energy (the ledger's stored-energy term).
STORES_ENERGY = True


def contact_time(normal_law, i, j, v: float) -> float:
    """The spring's half period at its stiffest [s], for the step estimate and ``x3dpd check``:
    the same spring as Hertz-Mindlin's (x3dpd.physics.mindlin.contact_time)."""
    return mindlin.contact_time(normal_law, i, j, v)


@step_kernel
def tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, ct, dt, gamma,
                     fox, foy, foz, h, row, col):
    """One step of the law (module docstring, steps 1-4): ``kt`` [force/length] and ``ct``
    [force*s/length] this step's spring and dashpot, one Coulomb coefficient ``mu_s``;
    h[row, col:col + 3] = xi, h[row, col + 3] = k_t (both updated). Returns
    (F_tx, F_ty, F_tz, U - U_old)."""
    xx = h[row, col + H_XI]
    xy = h[row, col + H_XI + 1]
    xz = h[row, col + H_XI + 2]
    old2 = xx * xx + xy * xy + xz * xz
    u_old = 0.5 * h[row, col + H_STIFFNESS] * old2
    # 1. onto the current tangent plane, magnitude kept
    xx, xy, xz, scale = mindlin.onto_tangent_plane(xx, xy, xz, nx, ny, nz)
    # 2. the step's slip
    xx = xx * scale + vtx * dt
    xy = xy * scale + vty * dt
    xz = xz * scale + vtz * dt
    # 3. spring and dashpot
    fx = -kt * xx - ct * vtx
    fy = -kt * xy - ct * vty
    fz = -kt * xz - ct * vtz
    # 4. Coulomb's limit; the spring is reset to carry the limited force with the dashpot
    f = math.sqrt(fx * fx + fy * fy + fz * fz)
    limit = mu_s * abs(fn)
    if f > limit and f > 0.0:
        r = limit / f
        fx *= r
        fy *= r
        fz *= r
        if kt > 0.0:
            xx = -(fx + ct * vtx) / kt
            xy = -(fy + ct * vty) / kt
            xz = -(fz + ct * vtz) / kt
        else:
            xx = 0.0
            xy = 0.0
            xz = 0.0
    h[row, col + H_XI] = xx
    h[row, col + H_XI + 1] = xy
    h[row, col + H_XI + 2] = xz
    h[row, col + H_STIFFNESS] = kt
    return fx, fy, fz, 0.5 * kt * (xx * xx + xy * xy + xz * xz) - u_old


@step_kernel
def stored_energy(fx, fy, fz, h, row, col):
    """U = k_t |xi|^2 / 2 of the spring after its last step [energy]."""
    xx = h[row, col + H_XI]
    xy = h[row, col + H_XI + 1]
    xz = h[row, col + H_XI + 2]
    return 0.5 * h[row, col + H_STIFFNESS] * (xx * xx + xy * xy + xz * xz)
