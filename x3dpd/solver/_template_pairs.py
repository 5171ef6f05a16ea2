"""Step-loop template, part: particle-particle contacts in three passes (x3dpd.solver.variants).

Filter (``_pair_filter``), vectorized response (``_pair_response``) and apply
(``_pair_apply``), run by ``_pair_contacts``; docs/engine.md, "The pair contact passes".
Generated per variant beside the loop, with the variant's constants (``_template_variant``).
"""

import math

import numpy as np

from x3dpd._jit import loop_kernel, step_kernel, vector_kernel
from x3dpd.solver._template_contact import (CONTACT_TAIL, HAS_TORQUE, L_DFRIC, L_DROLL, L_WN,
                                            OK,
                                            _booked_from, _close_contact, _penetration,
                                            _tangential)
from x3dpd.solver._template_variant import (HAS_FRICTION, HAS_ONE_PARTICLE_KIND, N_MAXWELL,
                                            N_TANGENTIAL, NORMAL_CLAMPED, NORMAL_PAIR_FORCE,
                                            NORMAL_USES_RATE, HAS_ROLLING, ROLLING_TORQUE,
                                            TANGENTIAL_STORES)
from x3dpd.solver.contact_lists import PAIR_COLUMNS, S_A, S_FN, S_FT, S_H

# rows of the pair pass's column scratch (x3dpd.solver.contact_lists.PAIR_COLUMNS)
C_FX, C_FY, C_FZ = (PAIR_COLUMNS.index(c) for c in ("fx", "fy", "fz"))
C_TIX, C_TIY, C_TIZ = (PAIR_COLUMNS.index(c) for c in ("tix", "tiy", "tiz"))
C_TJX, C_TJY, C_TJZ = (PAIR_COLUMNS.index(c) for c in ("tjx", "tjy", "tjz"))
C_A, C_FN, C_DW, C_LOST, C_RMIN = (PAIR_COLUMNS.index(c) for c in ("a", "fn", "dw", "lost", "rmin"))
C_ROLLED = PAIR_COLUMNS.index("rolled")
C_FTX, C_FTY, C_FTZ = (PAIR_COLUMNS.index(c) for c in ("ftx", "fty", "ftz"))
C_DX, C_DY, C_DZ = (PAIR_COLUMNS.index(c) for c in ("dx", "dy", "dz"))


@loop_kernel(inline="never")
def _pair_filter(x, p0, radius, pl_i, pl_j, pl_on, npairs, busy, dx_, dy_, dz_):
    """Pass 1 of the pair contacts: write into ``busy`` the candidates that touch now or had an
    open contact and their x_j - x_i into ``dx_``, ``dy_``, ``dz_``; return how many.

    A function of its own, not inlined: inside the step loop's single large function the
    filter's array pointers spill to the stack and are reloaded for every candidate; here they
    stay in registers (measured: 0.85 -> 0.80 us/step at 50 particles, 8.1 -> 7.2 at 512). It is
    compiled without NRT like the loop, so the call passes its arrays without reference counting.
    The wall filter gained nothing from the same treatment and stays inline.

    Indices are cast to unsigned: numba then omits the code that wraps negative indices around
    (four instructions per array access, most of this loop's instructions); list entries are
    never negative. Measured 0.80 -> 0.75 us/step at 50 particles.
    """
    nbusy = 0
    for s in range(npairs):
        pi = np.uint64(pl_i[s])
        pj = np.uint64(pl_j[s])
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        cut = radius[pi] + radius[pj]
        if dx * dx + dy * dy + dz * dz < cut * cut or pl_on[s] != 0:
            busy[nbusy] = s
            dx_[nbusy] = dx
            dy_[nbusy] = dy
            dz_[nbusy] = dz
            nbusy += 1
    return nbusy


@vector_kernel
def _pair_response(nbusy, busy, dx_, dy_, dz_, vel, particles, pl_i, pl_j, ps, hist, dt,
                   fx_, fy_, fz_, tix_, tiy_, tiz_, tjx_, tjy_, tjz_, a_, fn_, ftx_, fty_, ftz_,
                   dw_, lost_, rmin_, rolled_):
    """Pass 2 of the pair contacts: the contact response of every busy candidate ``busy[:nbusy]``
    (report Figure 41), written into columns (one entry per busy candidate; names in
    x3dpd.solver.contact_lists.PAIR_COLUMNS) for pass 3 to apply.

    The normal law is the scene's (x3dpd.physics.normal_laws), with n = (x_j - x_i)/|x_j - x_i|
    and approach a = R_i + R_j - |x_j - x_i|; the tangential law with spin (``_tangential``, the
    same as on walls) acts at the contact points
    x_i + R_i n and x_j - R_j n. A candidate that no longer touches (a <= 0) gets F = 0; pass 3
    closes it as a wall contact is closed (``_close_contact``). Nothing here writes the contact
    state or the
    forces -- pass 3 does, in list order -- so the loop has no stores through indices and LLVM
    vectorizes it (x3dpd._jit.vector_kernel): the gathers of x and v become packed gathers, and
    the square roots and divisions packed ones. Maxwell histories are read and written in
    ``hist`` (row q: busy candidate q, Fortran order), filled from the state rows before this
    pass and copied back by pass 3, so that they too are contiguous stores.
    """
    p0, radius, pkind, pair_c = particles.p0, particles.radius, particles.kind, particles.pair_c
    gamma = 0.5 / dt  # noqa: F841 (stick rate of the regularised friction law)
    for q in range(nbusy):
        # unsigned indices, as in the filter: no wrap-around code for negative indices
        s = np.uint64(busy[q])
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        if HAS_ONE_PARTICLE_KIND:
            # all particles alike (x3dpd.solver.variants): their constants are read once,
            # not gathered per contact
            pi = np.uint64(0)
            pj = np.uint64(0)
        else:
            pi = np.uint64(pl_i[s])
            pj = np.uint64(pl_j[s])
        dx = dx_[q]
        dy = dy_[q]
        dz = dz_[q]
        ri = radius[pi]
        rj = radius[pj]
        dist = math.sqrt(dx * dx + dy * dy + dz * dz)
        a = (ri + rj) - dist
        a_old = ps[s, S_A]
        fn_old = ps[s, S_FN]
        inv_dist = 1.0 / dist
        nx = dx * inv_dist
        ny = dy * inv_dist
        nz = dz * inv_dist
        # the pair's mixed constants (x3dpd.physics.mixing), looked up by particle kind
        ki = np.uint64(pkind[pi])
        kj = np.uint64(pkind[pj])
        touching = a > 0.0
        fn = 0.0
        a_from = a_old
        if touching:
            a_rate = 0.0
            if NORMAL_USES_RATE:
                a_rate = -(nx * (vel[j, 0] - vel[i, 0]) + ny * (vel[j, 1] - vel[i, 1])
                           + nz * (vel[j, 2] - vel[i, 2]))
            # Maxwell histories in the busy candidates' rows of ``hist`` (copied there from
            # the state rows; pass 3 copies them back): row q, columns 0 ..
            fn = NORMAL_PAIR_FORCE(a, a_old, a_rate, pi, pj, ki, kj, particles, hist, q, 0,
                                   N_MAXWELL)
            if NORMAL_CLAMPED and fn < 0.0:
                fn = 0.0
            a_from = _booked_from(a, a_old, a_rate, dt)
        # work of the normal force over the step, 1/2 (F_old + F) (a - a_from), a_from = a_old
        # or, on the step a contact opens, its gap (_booked_from; pass 3 books it for touching
        # candidates only)
        dw = 0.5 * (fn_old + fn) * (a - a_from)
        # force on j along +n, on i along -n
        fx = fn * nx
        fy = fn * ny
        fz = fn * nz
        tx = 0.0
        ty = 0.0
        tz = 0.0
        ftx = 0.0
        fty = 0.0
        ftz = 0.0
        lost = 0.0
        if HAS_FRICTION:
            wix = vel[i, 3]
            wiy = vel[i, 4]
            wiz = vel[i, 5]
            wjx = vel[j, 3]
            wjy = vel[j, 4]
            wjz = vel[j, 5]
            # contact point velocities: i at +ri n, j at -rj n
            vix = vel[i, 0] + ri * (wiy * nz - wiz * ny)
            viy = vel[i, 1] + ri * (wiz * nx - wix * nz)
            viz = vel[i, 2] + ri * (wix * ny - wiy * nx)
            vjx = vel[j, 0] - rj * (wjy * nz - wjz * ny)
            vjy = vel[j, 1] - rj * (wjz * nx - wjx * nz)
            vjz = vel[j, 2] - rj * (wjx * ny - wjy * nx)
            kappa = 0.0
            mu_k = 0.0
            eta = 0.0
            if TANGENTIAL_STORES:
                kappa = particles.tan_pair[ki, kj, 0]
                mu_k = particles.tan_pair[ki, kj, 1]
                eta = particles.tan_pair[ki, kj, 4]
            # the tangential law's history in the busy candidates' rows of ``hist``, after the
            # Maxwell terms (copied there from the state rows; pass 3 copies it back)
            ftx, fty, ftz, lost, du = _tangential(vjx - vix, vjy - viy, vjz - viz, nx, ny, nz,
                                                  fn, a, pair_c[ki, kj, 1], pair_c[ki, kj, 2],
                                                  kappa, mu_k, eta, dt, gamma, ps[s, S_FT],
                                                  ps[s, S_FT + 1], ps[s, S_FT + 2], hist, q,
                                                  2 * N_MAXWELL)
            if TANGENTIAL_STORES and touching:
                # the spring's share of the slip work is stored, not lost (a candidate that
                # no longer touches: lost is its last step's slip work, -1/2 F_old . v_t dt,
                # and pass 3 books the spring's energy as it closes the contact)
                dw += du
                lost -= du
            fx += ftx
            fy += fty
            fz += ftz
            # torques: r_i x (-F_t) with r_i = ri n ; r_j x F_t with r_j = -rj n
            tx = ny * ftz - nz * fty
            ty = nz * ftx - nx * ftz
            tz = nx * fty - ny * ftx
        fx_[q] = fx
        fy_[q] = fy
        fz_[q] = fz
        tix_[q] = ri * tx
        tiy_[q] = ri * ty
        tiz_[q] = ri * tz
        tjx_[q] = rj * tx
        tjy_[q] = rj * ty
        tjz_[q] = rj * tz
        if HAS_ROLLING:
            # rolling resistance against the relative rolling w_i - w_j (x3dpd.physics.rolling):
            # M on i, -M on j (the columns are subtracted from the moments)
            mx, my, mz, rolled = ROLLING_TORQUE(vel[i, 3] - vel[j, 3], vel[i, 4] - vel[j, 4],
                                                vel[i, 5] - vel[j, 5], fn,
                                                particles.tan_pair[ki, kj, 2],
                                                particles.tan_pair[ki, kj, 3], dt, hist, q,
                                                2 * N_MAXWELL + N_TANGENTIAL)
            tix_[q] -= mx
            tiy_[q] -= my
            tiz_[q] -= mz
            tjx_[q] += mx
            tjy_[q] += my
            tjz_[q] += mz
            rolled_[q] = rolled
        a_[q] = a
        fn_[q] = fn
        ftx_[q] = ftx
        fty_[q] = fty
        ftz_[q] = ftz
        dw_[q] = dw
        lost_[q] = lost
        rmin_[q] = ri if ri < rj else rj


@loop_kernel(inline="never")
def _pair_apply(nbusy, busy, p0, pl_i, pl_j, ps, pl_on, force, pen_limit, diag, c, hist):
    """Pass 3 of the pair contacts, in list order: the contact states, the forces on both
    particles and the ledger's sums from the columns ``c`` of ``_pair_response`` -- the same
    sums in the same order as a single scalar loop. Returns (status, normal work, friction
    loss, rolling loss). Its own function, like the filter: inlined into the step loop, the
    column pointers were reloaded from the stack at every contact (measured with
    tools/bench/profile_jit.py)."""
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    rolled_ = c[C_ROLLED]
    fx_, fy_, fz_ = c[C_FX], c[C_FY], c[C_FZ]
    tix_, tiy_, tiz_, tjx_, tjy_, tjz_ = c[C_TIX], c[C_TIY], c[C_TIZ], c[C_TJX], c[C_TJY], c[C_TJZ]
    a_, fn_, dw_, lost_, rmin_ = c[C_A], c[C_FN], c[C_DW], c[C_LOST], c[C_RMIN]
    ftx_, fty_, ftz_ = c[C_FTX], c[C_FTY], c[C_FTZ]
    for q in range(nbusy):
        s = np.uint64(busy[q])
        a = a_[q]
        if a <= 0.0:
            if HAS_TORQUE and pl_on[s] != 0:
                # the friction's and rolling's work of the step the contact ends on
                w_fric += lost_[q]
                if HAS_ROLLING:
                    w_roll += rolled_[q]
            dw, released = _close_contact(ps, pl_on, s, a, ps[s, S_A], ps[s, S_FN])
            w_normal += dw
            if TANGENTIAL_STORES:
                w_normal -= released
                w_fric += released
            continue
        rmin = rmin_[q]
        if a > pen_limit * rmin:
            status |= _penetration(diag, pl_i[s], -1 - pl_j[s], a, rmin)
        ps[s, S_A] = a
        ps[s, S_FN] = fn_[q]
        if N_MAXWELL > 0:
            for k in range(2 * N_MAXWELL):
                ps[s, S_H + k] = hist[q, k]
        if CONTACT_TAIL > 0:
            for k in range(CONTACT_TAIL):
                ps[s, ps.shape[1] - CONTACT_TAIL + k] = hist[q, 2 * N_MAXWELL + k]
        pl_on[s] = 1
        w_normal += dw_[q]
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        fx = fx_[q]
        fy = fy_[q]
        fz = fz_[q]
        if HAS_TORQUE:
            w_fric += lost_[q]
            if HAS_ROLLING:
                w_roll += rolled_[q]
            ps[s, S_FT] = ftx_[q]
            ps[s, S_FT + 1] = fty_[q]
            ps[s, S_FT + 2] = ftz_[q]
            force[i, 3] -= tix_[q]
            force[i, 4] -= tiy_[q]
            force[i, 5] -= tiz_[q]
            force[j, 3] -= tjx_[q]
            force[j, 4] -= tjy_[q]
            force[j, 5] -= tjz_[q]
        force[j, 0] += fx
        force[j, 1] += fy
        force[j, 2] += fz
        force[i, 0] -= fx
        force[i, 1] -= fy
        force[i, 2] -= fz
    return status, w_normal, w_fric, w_roll


@step_kernel
def _pair_contacts(nodes, particles, pairs, stepping, busy):
    """Particle-particle contact forces (report Figure 41) in three passes: the candidates that
    touch (``_pair_filter``), their contact response in columns (``_pair_response``,
    vectorized), and the contact states, the forces on both particles and the ledger in list
    order (``_pair_apply``). State column S_FT holds the friction force on particle j;
    histories: N_MAXWELL terms of i, then N_MAXWELL terms of j, then the tangential law's
    N_TANGENTIAL (the row's last columns). ``busy`` is an int scratch of
    the list's capacity."""
    x, vel = nodes.x, nodes.vel
    p0, radius = particles.p0, particles.radius
    pl_i, pl_j, ps, pl_on, npairs = (pairs.first, pairs.second, pairs.state, pairs.on,
                                     pairs.count[0])
    ledger = stepping.ledger
    # pass 1, tight: the candidates that touch now or touched at the last step; most
    # candidates are apart and cost about 2 ns each
    c = pairs.columns
    nbusy = _pair_filter(x, p0, radius, pl_i, pl_j, pl_on, npairs, busy, c[C_DX], c[C_DY],
                         c[C_DZ])
    hist = pairs.history
    if N_MAXWELL > 0:
        # the busy candidates' Maxwell histories, row q for candidate q (pass 3 copies them back)
        for q in range(nbusy):
            s = np.uint64(busy[q])
            for k in range(2 * N_MAXWELL):
                hist[q, k] = ps[s, S_H + k]
    if CONTACT_TAIL > 0:
        # the tangential and rolling laws' histories, after the Maxwell terms (the state row's
        # last columns)
        for q in range(nbusy):
            s = np.uint64(busy[q])
            for k in range(CONTACT_TAIL):
                hist[q, 2 * N_MAXWELL + k] = ps[s, ps.shape[1] - CONTACT_TAIL + k]
    if nbusy == 0:
        # nothing touches (a falling or sparse scene): skip the calls and their arguments
        return OK
    # pass 2: the contact response, into columns
    _pair_response(nbusy, busy, c[C_DX], c[C_DY], c[C_DZ], vel, particles, pl_i, pl_j, ps,
                   hist, stepping.dt,
                   c[C_FX], c[C_FY], c[C_FZ], c[C_TIX], c[C_TIY], c[C_TIZ], c[C_TJX], c[C_TJY],
                   c[C_TJZ], c[C_A], c[C_FN], c[C_FTX], c[C_FTY], c[C_FTZ], c[C_DW], c[C_LOST],
                   c[C_RMIN], c[C_ROLLED])
    # pass 3: states, forces and the ledger
    status, w_normal, w_fric, w_roll = _pair_apply(nbusy, busy, p0, pl_i, pl_j, ps, pl_on,
                                                   nodes.force, stepping.pen_limit,
                                                   stepping.diag, c, hist)
    ledger[L_WN] += w_normal
    ledger[L_DFRIC] += w_fric
    if HAS_ROLLING:
        ledger[L_DROLL] += w_roll
    return status
