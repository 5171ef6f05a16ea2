"""Step-loop template, part: what every contact shares (x3dpd.solver.variants).

The normal force's bookkeeping (``_record_normal``), the tangential response that wall and
pair contacts share (``_tangential``: the scene's tangential law), the end of a contact
(``_close_contact``), the record of
a penetration (``_penetration``) and the contact response of a particle on any wall entity
(``_wall_response``), with the status bits and ledger slots of the loop. Generated per variant
beside the loop, with the variant's constants (``_template_variant``).
"""

import math

import numpy as np

from x3dpd._jit import step_kernel
# the ledger's slots (cumulative since t0), shared with the effect units' hooks
from x3dpd.physics.effect_unit import L_DDAMP, L_DFRIC, L_DROLL, L_WEXT, L_WN  # noqa: F401
from x3dpd.solver._template_variant import (HAS_FRICTION, HAS_ROLLING, N_MAXWELL, N_ROLLING,
                                            N_TANGENTIAL, ROLLING_TORQUE,
                                            NORMAL_CLAMPED, NORMAL_DAMPED, NORMAL_STIFFNESS_SHAPE,
                                            NORMAL_WALL_FORCE,
                                            TANGENTIAL_FORCE, TANGENTIAL_STORED_ENERGY,
                                            TANGENTIAL_STORES)
from x3dpd.solver.bundles import Status
from x3dpd.solver.contact_lists import S_A, S_FN, S_FT, S_H

# status bits returned by advance() and _forces() (x3dpd.solver.bundles.Status, as int64
# constants: numba types a Python int global as a literal, and the step loop, typed without SSA
# (x3dpd._jit.loop_kernel), cannot then widen ``status = OK`` to the int64 of ``status |= ...``)
OK = np.int64(Status.OK)
PENETRATION = np.int64(Status.PENETRATION)
NONFINITE = np.int64(Status.NONFINITE)
REALLOC_PAIRS = np.int64(Status.REALLOC_PAIRS)
REALLOC_WALLS = np.int64(Status.REALLOC_WALLS)

#: History columns at the end of a state row: the tangential law's, then the rolling law's.
CONTACT_TAIL = N_TANGENTIAL + N_ROLLING
#: The contact puts a moment on its bodies (friction or rolling resistance).
HAS_TORQUE = HAS_FRICTION or HAS_ROLLING


@step_kernel
def _booked_from(a, a_old, a_rate, dt):
    """The approach the step's normal work 1/2 (F_old + F) (a - a_from) is booked from.

    An open contact's last approach ``a_old``. A contact that opens on this step was a gap
    g < 0 away at the last one (a closed contact keeps no approach: ``a_old`` = 0), and its
    force jumps from 0 to F, so the step's work is 1/2 F (a - g): velocity Verlet conserves KE
    - S plus exactly that trapezoid (x3dpd.solver.ledger_checks). ``a_rate`` is the approach
    rate from the half-step velocities, so a - g = dt da/dt is this step's drift along n and
    g = a - dt da/dt. Booking 1/2 F a instead left up to 1/2 c_n v^2 dt per contact out of the
    ledger under the unclamped HOOKE dashpot, whose F is c_n v at the onset, and under Lee &
    Radok, whose Maxwell terms jump with the approach's increment, 2e-3 of the energy scale of
    decks/beam_64.inp in 50 ms (tests/solver/test_conservation.py)."""
    if a_old <= 0.0:
        return a - dt * a_rate
    return a_old


@step_kernel
def _record_normal(states, on, s, a, a_old, fn, fn_old):
    """Clamp the normal force at zero if the law says so (the report's modified Lee & Radok
    rule), keep it and the approach in the contact's state row, mark the contact open, and
    return the applied force with the work the contact absorbed this step,
    1/2 (F_old + F) (a - a_old)."""
    if NORMAL_CLAMPED and fn < 0.0:
        fn = 0.0
    states[s, S_A] = a
    states[s, S_FN] = fn
    on[s] = 1
    return fn, 0.5 * (fn_old + fn) * (a - a_old)


@step_kernel
def _tangential(vrx, vry, vrz, nx, ny, nz, fn, a, m_t, mu_s, kappa, mu_k, eta, dt, gamma, fox,
                foy, foz, h, row, col):
    """The tangential response of a contact, wall or pair alike: the tangential force on the
    body whose contact point moves with v_r relative to the other, by the scene's tangential
    law TANGENTIAL_FORCE (x3dpd.physics.tangential_laws; report Eq. 29/30, or a spring with
    history such as Hertz-Mindlin). Splits v_r into normal and tangential parts; the law's
    stiffness is k_t = ``kappa`` * the normal law's ``stiffness_shape(a)`` and its dashpot
    c_t = ``eta`` sqrt(k_t) (formed only for a law with a spring, the dashpot only under a
    damped normal law; ``kappa``, ``mu_k`` and ``eta`` from the tangential tables).
    F_old = (fox, foy, foz), the last step's force; the law's history is ``h[row, col:]``;
    ``dt`` the step the contact slips over (0 in a force evaluation at a state: the laws then
    give the force of their history as it stands).
    Returns (F_tx, F_ty, F_tz, slip work, dU): the trapezoidal slip work
    -1/2 (F_old + F_t) . v_t dt taken from the bodies, of which dU went into the law's stored
    energy (0 for Coulomb)."""
    vn = vrx * nx + vry * ny + vrz * nz
    vtx = vrx - vn * nx
    vty = vry - vn * ny
    vtz = vrz - vn * nz
    vt = math.sqrt(vtx * vtx + vty * vty + vtz * vtz)
    kt = 0.0
    ct = 0.0
    if TANGENTIAL_STORES and a > 0.0:
        kt = kappa * NORMAL_STIFFNESS_SHAPE(a)
        if NORMAL_DAMPED:
            ct = eta * math.sqrt(kt)
    ftx, fty, ftz, du = TANGENTIAL_FORCE(vtx, vty, vtz, vt, nx, ny, nz, fn, a, m_t, mu_s, mu_k,
                                         kt, ct, dt, gamma, fox, foy, foz, h, row, col)
    lost = -0.5 * ((fox + ftx) * vtx + (foy + fty) * vty + (foz + ftz) * vtz) * dt
    return ftx, fty, ftz, lost, du


@step_kernel
def _penetration(diag, p, other, a, r):
    """Record a contact deeper than the penetration limit in ``diag`` (particle, the wall
    entity ``other``, depth, radius) for the stop's diagnosis; return the status bit."""
    diag[0] = p
    diag[1] = other
    diag[2] = a
    diag[3] = r
    return PENETRATION


@step_kernel
def _close_contact(ws, on, s, a, a_old, fn_old):
    """End the contact of state row ``s`` (apart, or off its entity): its history is cleared;
    returns the work 1/2 F_old (a - a_old) of an open contact's last step and the energy the
    tangential law still stored (lost with the contact: the caller books it as dissipated,
    and takes it from the contacts' absorbed work)."""
    dw = 0.0
    released = 0.0
    if fn_old != 0.0 or a_old > 0.0:
        dw = 0.5 * fn_old * (a - a_old)
        if TANGENTIAL_STORES:
            released = TANGENTIAL_STORED_ENERGY(ws[s, S_FT], ws[s, S_FT + 1], ws[s, S_FT + 2],
                                                ws, s, ws.shape[1] - CONTACT_TAIL)
        for c in range(S_FT, ws.shape[1]):
            ws[s, c] = 0.0
    ws[s, S_A] = 0.0
    ws[s, S_FN] = 0.0
    on[s] = 0
    return dw, released


@step_kernel
def _wall_slip_velocity(vel, i, r, nx, ny, nz, wall_nodes, row, w, n_w, lever, lx, ly, lz):
    """Velocity of node ``i``'s contact point (at -r n, with its spin) relative to the wall
    point, which moves with sum_e w_e v_e of the nodes ``wall_nodes[row, :n_w]`` (plus
    omega x l of the first node when ``lever``): (v_rx, v_ry, v_rz) [length/s]."""
    rcx = -r * nx
    rcy = -r * ny
    rcz = -r * nz
    wx = vel[i, 3]
    wy = vel[i, 4]
    wz = vel[i, 5]
    vrx = vel[i, 0] + wy * rcz - wz * rcy
    vry = vel[i, 1] + wz * rcx - wx * rcz
    vrz = vel[i, 2] + wx * rcy - wy * rcx
    n0 = wall_nodes[row, 0]
    vwx = w[0] * vel[n0, 0]
    vwy = w[0] * vel[n0, 1]
    vwz = w[0] * vel[n0, 2]
    for e in range(1, n_w):
        nd = wall_nodes[row, e]
        vwx += w[e] * vel[nd, 0]
        vwy += w[e] * vel[nd, 1]
        vwz += w[e] * vel[nd, 2]
    vrx -= vwx
    vry -= vwy
    vrz -= vwz
    if lever:
        vrx -= vel[n0, 4] * lz - vel[n0, 5] * ly
        vry -= vel[n0, 5] * lx - vel[n0, 3] * lz
        vrz -= vel[n0, 3] * ly - vel[n0, 4] * lx
    return vrx, vry, vrz


@step_kernel
def _wall_closing_work(nodes, particles, stepping, ws, s, p, nx, ny, nz, wall_nodes, row, w,
                       n_w, lever, lx, ly, lz):
    """The friction and rolling work of the step on which an open wall contact ends: its
    forces fall from the last step's to zero, and velocity Verlet's trapezoid takes
    -1/2 (F_t,old + 0) . v_t dt from the bodies (and -1/2 (M_old + 0) . omega dt: the rolling
    law at F_N = 0, whose torque is zero). Not booking it left ~1.8e-4 of an impact's energy
    out of the ledger at the report's step, under every tangential law. The geometry (n, the
    wall point's weights and lever) is the one located at this step; call before
    ``_close_contact`` clears the row. Returns the energy dissipated by friction and by rolling
    resistance [energy]."""
    lost = 0.0
    rolled = 0.0
    vel = nodes.vel
    i = particles.p0 + p
    dt = stepping.dt
    if HAS_FRICTION:
        vrx, vry, vrz = _wall_slip_velocity(vel, i, particles.radius[p], nx, ny, nz, wall_nodes,
                                            row, w, n_w, lever, lx, ly, lz)
        vn = vrx * nx + vry * ny + vrz * nz
        lost -= 0.5 * (ws[s, S_FT] * (vrx - vn * nx) + ws[s, S_FT + 1] * (vry - vn * ny)
                       + ws[s, S_FT + 2] * (vrz - vn * nz)) * dt
    if HAS_ROLLING:
        _, _, _, rolled = ROLLING_TORQUE(vel[i, 3], vel[i, 4], vel[i, 5], 0.0,
                                         particles.tan_wall[p, 2], particles.tan_wall[p, 3],
                                         dt, ws, s, ws.shape[1] - N_ROLLING)
    return lost, rolled


# Over 80 lines: a compiled kernel: one contact's laws share their terms.
@step_kernel
def _wall_response(nodes, particles, stepping, ws, on, s, p, a, a_old, fn_old, nx, ny, nz,
                   wall_nodes, row, w, n_w, lever, lx, ly, lz):
    """The contact response of particle ``p`` on a wall entity, whatever its shape: the
    scene's normal law (x3dpd.physics.normal_laws) at approach ``a`` along the unit normal n
    (from the wall into the particle), the tangential law with spin (``_tangential``), and the
    reaction on the
    wall's nodes ``wall_nodes[row, :n_w]`` with weights ``w``. The wall point moves with
    sum_e w_e v_e, plus omega x l when ``lever`` (omega of the first node; l = (lx, ly, lz) from
    the weighted node point to the wall point, whose moment l x F then goes to the first node).
    A locator (``_locate_on_face``, an analytic wall's ``locate_parts``) supplies a, n,
    the weights and l. State row ``s`` of ``ws`` / ``on`` keeps the contact's history.
    Returns (normal work, friction loss, rolling loss)."""
    vel, force = nodes.vel, nodes.force
    radius, mu, inv_mt = particles.radius, particles.mu, particles.inv_mt
    dt = stepping.dt
    gamma = 0.5 / dt  # noqa: F841 (stick rate of the regularised friction law)
    i = particles.p0 + p
    r = radius[p]
    n0 = wall_nodes[row, 0]
    # normal force: the scene's law (x3dpd.physics.normal_laws)
    # approach rate: the wall point's velocity minus the particle's, along n (a law's rate,
    # and the gap an opening contact is booked from: _booked_from)
    a_rate = -(nx * vel[i, 0] + ny * vel[i, 1] + nz * vel[i, 2])
    for e in range(n_w):
        nd = wall_nodes[row, e]
        a_rate += w[e] * (nx * vel[nd, 0] + ny * vel[nd, 1] + nz * vel[nd, 2])
    if lever:
        a_rate += (nx * (vel[n0, 4] * lz - vel[n0, 5] * ly)
                   + ny * (vel[n0, 5] * lx - vel[n0, 3] * lz)
                   + nz * (vel[n0, 3] * ly - vel[n0, 4] * lx))
    fn = NORMAL_WALL_FORCE(a, a_old, a_rate, p, particles, ws, s, S_H, N_MAXWELL)
    fn, dw = _record_normal(ws, on, s, a, _booked_from(a, a_old, a_rate, dt), fn, fn_old)
    lost = 0.0
    rolled = 0.0
    fx = fn * nx
    fy = fn * ny
    fz = fn * nz
    if HAS_FRICTION:
        rcx = -r * nx
        rcy = -r * ny
        rcz = -r * nz
        vrx, vry, vrz = _wall_slip_velocity(vel, i, r, nx, ny, nz, wall_nodes, row, w, n_w,
                                            lever, lx, ly, lz)
        kappa = 0.0
        mu_k = 0.0
        eta = 0.0
        if TANGENTIAL_STORES:
            kappa = particles.tan_wall[p, 0]
            mu_k = particles.tan_wall[p, 1]
            eta = particles.tan_wall[p, 4]
        ftx, fty, ftz, lost, du = _tangential(vrx, vry, vrz, nx, ny, nz, fn, a, 1.0 / inv_mt[p],
                                              mu[p], kappa, mu_k, eta, stepping.history_dt,
                                              gamma, ws[s, S_FT],
                                              ws[s, S_FT + 1], ws[s, S_FT + 2], ws, s,
                                              ws.shape[1] - CONTACT_TAIL)
        ws[s, S_FT] = ftx
        ws[s, S_FT + 1] = fty
        ws[s, S_FT + 2] = ftz
        if TANGENTIAL_STORES:
            # the spring's share of the slip work is stored, not lost
            dw += du
            lost -= du
        fx += ftx
        fy += fty
        fz += ftz
        force[i, 3] += rcy * ftz - rcz * fty
        force[i, 4] += rcz * ftx - rcx * ftz
        force[i, 5] += rcx * fty - rcy * ftx
    if HAS_ROLLING:
        # rolling resistance against the particle's rolling (x3dpd.physics.rolling)
        mx, my, mz, rolled = ROLLING_TORQUE(vel[i, 3], vel[i, 4], vel[i, 5], fn,
                                            particles.tan_wall[p, 2], particles.tan_wall[p, 3],
                                            dt, ws, s, ws.shape[1] - N_ROLLING)
        force[i, 3] += mx
        force[i, 4] += my
        force[i, 5] += mz
    force[i, 0] += fx
    force[i, 1] += fy
    force[i, 2] += fz
    for e in range(n_w):
        nd = wall_nodes[row, e]
        force[nd, 0] -= w[e] * fx
        force[nd, 1] -= w[e] * fy
        force[nd, 2] -= w[e] * fz
    if lever:
        force[n0, 3] -= ly * fz - lz * fy
        force[n0, 4] -= lz * fx - lx * fz
        force[n0, 5] -= lx * fy - ly * fx
    return dw, lost, rolled
