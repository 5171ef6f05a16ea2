r"""Hertz-Mindlin tangential contact with history: a tangential spring limited by Coulomb.

Mindlin (1949): two elastic spheres pressed together over a contact circle of radius
:math:`a_c = \sqrt{R^* \delta}` resist a tangential displacement :math:`\xi` with the stiffness

.. math::  k_t = 8 G^* a_c, \qquad \frac{1}{G^*} = \frac{2-\nu_i}{G_i} + \frac{2-\nu_j}{G_j},
           \qquad G = \frac{E}{2(1+\nu)}

(a rigid wall: :math:`G^* = G/(2-\nu)`), as long as :math:`|F_t| \le \mu_s F_N`. The normal law
supplies :math:`k_t` (its ``tangential_stiffness`` constant :math:`\kappa` times its
``stiffness_shape(δ)``): Hertz and Lee & Radok :math:`\kappa = 8G^*\sqrt{R^*}`, shape
:math:`\sqrt\delta`, with the instantaneous modulus :math:`E_0 + E_1 + \dots`; HOOKE a constant
:math:`k_t = 2(1-\nu)/(2-\nu)\,k_n`, Mindlin's ratio :math:`k_t/k_n` of Hertz contacts.

**Incremental form and the unloading rule** (LAMMPS ``tangential mindlin_rescale/force``). The
history is the spring's force :math:`F_s` itself (equivalently :math:`\xi = -F_s/k_t`) plus
:math:`k_t` of the last step and a sliding flag. Each step

1. :math:`F_s` is rotated onto the current tangent plane, keeping its magnitude;
2. if the contact unloads (:math:`k_t < k_{t,old}`) it is rescaled,
   :math:`F_s \leftarrow F_s\,k_t/k_{t,old}`;
3. the trial spring force :math:`F_s^* = F_s - k_t v_t \Delta t` (:math:`v_t` the contact
   point's slip velocity) and the trial force :math:`F^* = F_s^* - c_t v_t` with the
   tangential dashpot :math:`c_t` (below);
4. Coulomb's limit: a sticking contact slides when :math:`|F^*| > \mu_s F_N`, a sliding one
   sticks again when :math:`|F^*| \le \mu_k F_N`; sliding,
   :math:`F = \mu_k F_N\,F^*/|F^*|` and the spring takes that force, :math:`F_s = F` (the
   dashpot rests while the contact slides, as in Kratos DEM's Hertz-Mindlin); sticking,
   :math:`F = F^*` and :math:`F_s = F_s^*`.

The stored energy is :math:`U = |F_s|^2/(2k_t)`. Why this rule: a spring whose stiffness changes
under it changes its energy without work. Stored as a displacement (``mindlin`` of LAMMPS),
:math:`U = \tfrac12 k_t \xi^2` grows when the contact loads (:math:`k_t` grows at fixed
:math:`\xi`): an elastic impact can create energy. Stored as a force, :math:`U = F_s^2/(2k_t)`
falls when :math:`k_t` grows (loading, no rescale needed), and would grow when it falls; the
rescale of step 2 makes :math:`U' = U\,k_t/k_{t,old} < U` instead. So no step of the rule adds
energy: rotation keeps it, loading and unloading lower it, sliding and the dashpot dissipate
(Thornton's Mindlin-Deresiewicz rules give the same bound at much more bookkeeping; this is
what LAMMPS recommends for the same reason).

**Damping** tied to the normal law's: :math:`c_t = \eta\sqrt{k_t}` with the normal law's
``tangential_damping`` constant :math:`\eta`. Under HOOKE (:math:`F_N = k_n a + c_n\dot a`,
:math:`c_n = 2\zeta\sqrt{m^* k_n}`) :math:`\eta = 2\zeta\sqrt{m^*}`, so
:math:`c_t = 2\zeta\sqrt{m^* k_t} = c_n\sqrt{k_t/k_n}`: the same damping ratio and effective
mass as the normal dashpot (Tsuji, Tanaka & Ishida 1992; EDEM's and Kratos DEM's Hertz-Mindlin;
LAMMPS's ``damp_tangential`` x the normal damping with the factor fixed by the same ratio).
Under the report's Lee & Radok law :math:`\eta = 0`: its loss is the material's relaxation
(Maxwell terms, Section 7.2.3), not a dashpot with a damping ratio; the consistent tangential
counterpart would relax the spring's shear modulus with the same terms, which x3dpd does not
do (docs/physics.md says why it matters little for a damper). The dashpot's work is booked with
the slip work as friction dissipation; the spring's energy as stored.

Units: force, length, s (k_t in force/length).
"""

from __future__ import annotations

import math

from x3dpd._jit import step_kernel

__all__ = ["N_HISTORY", "STORES_ENERGY", "H_STIFFNESS", "H_SLIDING", "tangential_force",
           "stored_energy", "onto_tangent_plane", "shear_modulus", "effective_shear_modulus_wall",
           "effective_shear_modulus_pair"]

#: History per contact: k_t of the last step [force/length], 1.0 while sliding else 0.0, the
#: spring's force F_s (3 values; the applied force F = F_s + the dashpot's is the state row's).
N_HISTORY = 5
H_STIFFNESS = 0
H_SLIDING = 1
H_SPRING = 2
#: The spring stores elastic energy (the ledger's stored-energy term).
STORES_ENERGY = True


def shear_modulus(e: float, nu: float) -> float:
    """G = E / (2 (1 + nu)) [pressure]."""
    return e / (2.0 * (1.0 + nu))


def effective_shear_modulus_wall(e: float, nu: float) -> float:
    """G* = G / (2 - nu) of a sphere on a rigid wall [pressure]."""
    return shear_modulus(e, nu) / (2.0 - nu)


def effective_shear_modulus_pair(e_i: float, nu_i: float, e_j: float, nu_j: float) -> float:
    """1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j [pressure]."""
    return 1.0 / ((2.0 - nu_i) / shear_modulus(e_i, nu_i) + (2.0 - nu_j) / shear_modulus(e_j, nu_j))


def contact_time(normal_law, i, j, v: float) -> float:
    """The tangential spring's half period pi sqrt(m_t / k_t) [s] at its stiffest (the
    impact's largest approach, ``normal_law.peak_approach``), for particle ``i`` on a rigid
    wall (``j`` None) or on ``j`` (ContactBody, solid spheres: 1/m_t = sum 3.5/m). Like a normal
    law's contact time it must be resolved by the step (x3dpd.model.timestep): the spring
    oscillates ~1.7 times faster than a Hertz contact lasts."""
    k = normal_law.tangential_stiffness(i, j) * normal_law.stiffness_shape(
        normal_law.peak_approach(i, j, v))
    inv_mt = 3.5 / i.mass + (0.0 if j is None else 3.5 / j.mass)
    return math.pi * math.sqrt(1.0 / (inv_mt * k))


@step_kernel
def onto_tangent_plane(vx, vy, vz, nx, ny, nz):
    """A history vector v rotated onto the tangent plane of the unit normal n, its magnitude
    kept: (v - (v.n) n) and the factor |v| / |v - (v.n) n| that restores the magnitude (0 for
    a vector along n or zero), as a tangential law with history rotates what it keeps."""
    old2 = vx * vx + vy * vy + vz * vz
    vn = vx * nx + vy * ny + vz * nz
    vx -= vn * nx
    vy -= vn * ny
    vz -= vn * nz
    v2 = vx * vx + vy * vy + vz * vz
    return vx, vy, vz, math.sqrt(old2 / v2) if v2 > 0.0 else 0.0


@step_kernel
def tangential_force(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k, kt, ct, dt, gamma,
                     fox, foy, foz, h, row, col):
    """One step of the Mindlin spring and its dashpot (module docstring, steps 1-4). ``kt`` is
    this step's stiffness k_t [force/length], ``ct`` the dashpot [force*s/length];
    h[row, col] = k_t of the last step, h[row, col + 1] the sliding flag, h[row, col + 2:5] the
    spring's force (all updated; the applied force of the last step, ``fox``..., is not used).
    Returns (F_tx, F_ty, F_tz, U - U_old)."""
    k_old = h[row, col + H_STIFFNESS]
    sx = h[row, col + H_SPRING]
    sy = h[row, col + H_SPRING + 1]
    sz = h[row, col + H_SPRING + 2]
    old2 = sx * sx + sy * sy + sz * sz
    u_old = 0.5 * old2 / k_old if k_old > 0.0 else 0.0
    # 1. onto the current tangent plane, magnitude kept
    sx, sy, sz, scale = onto_tangent_plane(sx, sy, sz, nx, ny, nz)
    # 2. unloading: F_s scales with k_t (mindlin_rescale/force)
    if kt < k_old:
        scale *= kt / k_old
    # 3. trial spring force, and with the dashpot the trial force
    sx = sx * scale - kt * vtx * dt
    sy = sy * scale - kt * vty * dt
    sz = sz * scale - kt * vtz * dt
    fx = sx - ct * vtx
    fy = sy - ct * vty
    fz = sz - ct * vtz
    # 4. Coulomb limit, static to start sliding, kinetic to go on; sliding, the spring
    # takes the whole force (the dashpot rests)
    ftrial = math.sqrt(fx * fx + fy * fy + fz * fz)
    fna = abs(fn)
    sliding = h[row, col + H_SLIDING] != 0.0
    limit = (mu_k if sliding else mu_s) * fna
    if ftrial > limit and ftrial > 0.0:
        r = mu_k * fna / ftrial
        fx *= r
        fy *= r
        fz *= r
        sx = fx
        sy = fy
        sz = fz
        h[row, col + H_SLIDING] = 1.0
    else:
        h[row, col + H_SLIDING] = 0.0
    h[row, col + H_STIFFNESS] = kt
    h[row, col + H_SPRING] = sx
    h[row, col + H_SPRING + 1] = sy
    h[row, col + H_SPRING + 2] = sz
    u = 0.5 * (sx * sx + sy * sy + sz * sz) / kt if kt > 0.0 else 0.0
    return fx, fy, fz, u - u_old


@step_kernel
def stored_energy(fx, fy, fz, h, row, col):
    """U = |F_s|^2 / (2 k_t) of the spring after its last step [energy] (F_s from the history;
    the applied force ``fx``... includes the dashpot's)."""
    k = h[row, col + H_STIFFNESS]
    sx = h[row, col + H_SPRING]
    sy = h[row, col + H_SPRING + 1]
    sz = h[row, col + H_SPRING + 2]
    return 0.5 * (sx * sx + sy * sy + sz * sz) / k if k > 0.0 else 0.0
