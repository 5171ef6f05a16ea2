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
   :math:`\boldsymbol\xi_L = -(\mathbf F + c_t\mathbf v_t)/k_t` (LAMMPS's rule);
5. x3dpd's addition, so that no step creates energy: the reset spring is scaled along its
   direction, :math:`\boldsymbol\xi = s\,\boldsymbol\xi_L` with the largest :math:`s \le 1`
   such that (a) it holds no more than Coulomb's limit, :math:`k_t|\boldsymbol\xi| \le \mu F_N`,
   and (b) it stores no more than it stored plus the slip work the step put in,
   :math:`\tfrac12 k_t|\boldsymbol\xi|^2 \le U_{old} + W`,
   :math:`W = -\tfrac12(\mathbf F_{old} + \mathbf F)\cdot\mathbf v_t\Delta t` (the step loop's
   trapezoid; :math:`s = 0` if :math:`U_{old} + W \le 0`).

Why step 5. With a dashpot and a fast slip (:math:`c_t|\mathbf v_t| > \mu F_N`) LAMMPS's
reset points the spring *along* the slip, :math:`k_t|\boldsymbol\xi_L| = c_t|\mathbf v_t| -
\mu F_N`, and stores :math:`\tfrac12|\mathbf F + c_t\mathbf v_t|^2/k_t`, energy no work put
there: Chung & Ooi's test 6 (``x3dpd decks/benchmarks/chung_ooi/test6_aluminium_alloy.inp
--friction linear_history``, chi = 0.187) gained 1.79 J on its first step, 0.38 of its 4.66 J,
and the energy audit stopped it (exit 3). (a) alone bounds the stored energy by
:math:`(\mu F_N)^2/(2k_t)`, as ``mindlin``'s, but not its growth: at a contact's first step,
where :math:`\mathbf F_{old} = 0` and the unclamped HOOKE dashpot makes :math:`F_N = c_n v_n`,
the spring would take :math:`(\mu F_N)^2/(2k_t)` while the step's slip work is
:math:`\tfrac12\mu F_N|v_t|\Delta t`, less whenever :math:`\mu c_n v_n/k_t > |v_t|\Delta t`
(test 6 at its step; every contact as the step shrinks); (b) makes every sliding step's
booked dissipation :math:`W - \Delta U \ge 0`. The applied force is LAMMPS's in every step;
only the spring's state can differ, and only where LAMMPS's is not energy-consistent or holds
more than the limit: (a) binds only where :math:`|\mathbf F + c_t\mathbf v_t| > \mu F_N` (never
without a dashpot; in straight sliding where :math:`c_t|\mathbf v_t| > 2\mu F_N`), (b) only
where the step would book negative friction dissipation. LAMMPS's step does that only with a
fast slip or where the slip reverses within a step: with the step's own work
:math:`-\mathbf F\cdot\mathbf v_t\Delta t` it dissipates
:math:`(|\mathbf F^*| - \mu F_N)(\mu F_N + c_t\mathbf v_t\cdot\hat{\mathbf F}^*)/k_t +
\tfrac12k_t|\boldsymbol\xi_L - \boldsymbol\xi_{old}|^2 + c_t v_t^2\Delta t`, not negative when
:math:`c_t|\mathbf v_t| \le \mu F_N` (:math:`\mathbf F^*` the trial force), and the trapezoid
differs from that work by :math:`\tfrac12(\mathbf F - \mathbf F_{old})\cdot\mathbf v_t\Delta t`.
So undamped (e = 1) contacts run LAMMPS's rule (to round-off: (a) compares
:math:`|\mathbf F| = \mu F_N` with itself), and damped ones as long as the slip stays slow.
In gross sliding the applied force is :math:`\mu F_N` against the slip under every law, so the
rebound is the Coulomb law's. Where the rule does differ (docs/physics.md, "LAMMPS's
linear_history"), LAMMPS's spring holds energy the slip never put in and gives it back when the
contact sticks again.

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

Stored energy :math:`U = \tfrac12 k_t|\boldsymbol\xi|^2`.
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
def energy_consistent_scale(kt, x2, limit, budget):
    """The largest factor s in [0, 1] of LAMMPS's reset spring xi (|xi|^2 = ``x2``, stiffness
    ``kt``) that keeps it within Coulomb's limit, k_t s |xi| <= ``limit`` = mu F_N, and its
    energy within ``budget`` = U_old + the step's slip work, 1/2 k_t s^2 |xi|^2 <= budget (0
    when the budget is not positive): 1 where LAMMPS's reset is within the limit and
    energy-consistent (module docstring, step 5)."""
    u = 0.5 * kt * x2
    s = 1.0
    if kt * kt * x2 > limit * limit:
        s = limit / math.sqrt(kt * kt * x2)
    if u * s * s > budget:
        s = math.sqrt(budget / u) if budget > 0.0 else 0.0
    return s


@step_kernel
def tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, ct, dt, gamma,
                     fox, foy, foz, h, row, col):
    """One step of the law (module docstring, steps 1-5): ``kt`` [force/length] and ``ct``
    [force*s/length] this step's spring and dashpot, one Coulomb coefficient ``mu_s``;
    h[row, col:col + 3] = xi, h[row, col + 3] = k_t (both updated); the last step's applied
    force ``fox``... for the step's slip work. Returns (F_tx, F_ty, F_tz, U - U_old)."""
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
    # (LAMMPS), 5. no more than mu F_N and no more energy than the step's slip work put in
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
            work = -0.5 * ((fox + fx) * vtx + (foy + fy) * vty + (foz + fz) * vtz) * dt
            s = energy_consistent_scale(kt, xx * xx + xy * xy + xz * xz, limit, u_old + work)
            xx *= s
            xy *= s
            xz *= s
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
