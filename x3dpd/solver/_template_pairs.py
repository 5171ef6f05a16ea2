# Over 400 lines: the pair passes (filter, response, apply) share one block's column layout.
"""Step-loop template, part: particle-particle contacts in three passes (x3dpd.solver.variants).

Filter (``_pair_filter``), vectorized response (``_pair_response``) and apply
(``_pair_apply``), run by ``_pair_contacts`` (``_template_pair_passes``: in one thread, or the
first two in chunks on several); docs/engine.md, "The pair contact passes" and "Threads".
Generated per variant beside the loop, with the variant's constants (``_template_variant``).
"""

import math

import numpy as np

from x3dpd._jit import loop_kernel, step_kernel, vector_kernel
from x3dpd.solver._template_contact import (CONTACT_TAIL, HAS_TORQUE,
                                            _close_contact, _penetration, _tangential)
from x3dpd.solver._template_variant import (HAS_FRICTION, HAS_ONE_PARTICLE_KIND, N_MAXWELL,
                                            N_TANGENTIAL, NORMAL_CLAMPED, NORMAL_PAIR_FORCE,
                                            HAS_ROLLING, ROLLING_TORQUE,
                                            TANGENTIAL_STORES)
from x3dpd.solver.contact_lists import (COLUMN_ROW, PAIR_COLUMNS, PAIR_INPUT_COLUMNS,
                                         PAIR_OUTPUT_COLUMNS, S_A, S_FN, S_FT, S_H)

# rows of the pair pass's column scratch (x3dpd.solver.contact_lists.PAIR_COLUMNS)
C_FX, C_FY, C_FZ = (PAIR_COLUMNS.index(c) for c in ("fx", "fy", "fz"))
C_TIX, C_TIY, C_TIZ = (PAIR_COLUMNS.index(c) for c in ("tix", "tiy", "tiz"))
C_TJX, C_TJY, C_TJZ = (PAIR_COLUMNS.index(c) for c in ("tjx", "tjy", "tjz"))
C_A, C_FN, C_DW, C_LOST, C_RMIN = (PAIR_COLUMNS.index(c) for c in ("a", "fn", "dw", "lost", "rmin"))
C_ROLLED = PAIR_COLUMNS.index("rolled")
C_FTX, C_FTY, C_FTZ = (PAIR_COLUMNS.index(c) for c in ("ftx", "fty", "ftz"))
C_DX, C_DY, C_DZ = (PAIR_COLUMNS.index(c) for c in ("dx", "dy", "dz"))
C_VIX, C_VIY, C_VIZ = (PAIR_COLUMNS.index(c) for c in ("vix", "viy", "viz"))
C_WIX, C_WIY, C_WIZ = (PAIR_COLUMNS.index(c) for c in ("wix", "wiy", "wiz"))
C_VJX, C_VJY, C_VJZ = (PAIR_COLUMNS.index(c) for c in ("vjx", "vjy", "vjz"))
C_WJX, C_WJY, C_WJZ = (PAIR_COLUMNS.index(c) for c in ("wjx", "wjy", "wjz"))
# the filter writes v_i, w_i (and v_j, w_j) into six consecutive rows each
assert (C_WIZ - C_VIX, C_WJZ - C_VJX) == (5, 5)
C_AOLD, C_FNOLD = (PAIR_COLUMNS.index(c) for c in ("a_old", "fn_old"))
C_FTOX, C_FTOY, C_FTOZ = (PAIR_COLUMNS.index(c) for c in ("ftox", "ftoy", "ftoz"))
# positions in the response's tuples of input and output columns (``_columns_in``, ``_out``)
I_DX, I_DY, I_DZ, I_VIX, I_VIY, I_VIZ, I_WIX, I_WIY, I_WIZ, I_VJX, I_VJY, I_VJZ, I_WJX, I_WJY, \
    I_WJZ, I_AOLD, I_FNOLD, I_FTOX, I_FTOY, I_FTOZ = range(len(PAIR_INPUT_COLUMNS))
O_FX, O_FY, O_FZ, O_TIX, O_TIY, O_TIZ, O_TJX, O_TJY, O_TJZ, O_A, O_FN, O_FTX, O_FTY, O_FTZ, \
    O_DW, O_LOST, O_ROLLED, O_RMIN = range(len(PAIR_OUTPUT_COLUMNS))
#: the response reads the bodies' velocities (the approach rate: its normal law's, and the gap
#: an opening contact's work is booked from, _booked_from; friction) and spins
GATHER_VELOCITY = True
GATHER_SPIN = HAS_FRICTION or HAS_ROLLING
#: entries of one column area of the scratch (contact_lists.pair_columns): the columns of one
#: block of the list
AREA = len(PAIR_COLUMNS) * COLUMN_ROW


@step_kernel
def _entry(column, e):
    """Where column ``column`` keeps entry ``e`` (its area's base plus the busy candidate's
    place in the block) in the flat scratch: a constant offset, COLUMN_ROW being a constant of
    the compiled code (contact_lists.COLUMN_ROW)."""
    return np.uint64(column * COLUMN_ROW) + e


@loop_kernel(inline="never")
def _pair_filter(lo, hi, q0, area, x, vel, p0, radius, pl_i, pl_j, pl_on, ps, busy, c, hist):
    """Pass 1 of the pair contacts, over the candidates ``lo`` .. ``hi`` - 1 of the list (at
    most PAIR_BLOCK): write into ``busy`` (from position ``q0`` on) the candidates that touch
    now or had an open contact, and gather, in list order, what the contact response reads
    into the columns of ``c`` (contact_lists.PAIR_INPUT_COLUMNS; the area from entry ``area``
    on, entry k for the k-th busy candidate, ``_entry``): x_j - x_i, the velocities and spins of
    both particles (when the scene's laws read them), the state row's approach, normal and
    friction force, and the laws' histories into ``hist`` (Maxwell terms, then the tangential
    and rolling laws'; row q0 + k). Returns how many are busy. The step loop filters the list
    block by block, each from q0 = 0 into the first area; a threaded loop filters its blocks at
    once, each from q0 = lo into an area of its own (``_template_pair_passes``).

    Gathered here, the response reads contiguous 1-D columns only, no index: LLVM vectorizes
    it without gathers. Each column entry is addressed from the area's base by a constant
    offset (``_entry``): one register for all columns, where a pointer per column spilled to
    the stack and was reloaded at every store. A function of its own, not inlined: inside the
    step loop's single large function the filter's array pointers spill to the stack and are
    reloaded for every candidate; here they stay in registers (measured: 0.85 -> 0.80 us/step
    at 50 particles, 8.1 -> 7.2 at 512). It is compiled without NRT like the loop, so the call
    passes its arrays without reference counting.

    Indices are cast to unsigned: numba then omits the code that wraps negative indices around
    (four instructions per array access, most of this loop's instructions); list entries are
    never negative. Measured 0.80 -> 0.75 us/step at 50 particles.
    """
    # the candidates that touch, with x_j - x_i: a tight loop, which keeps its arrays in
    # registers (with the gather below in it, five of them were reloaded from the stack at
    # every candidate, most of which are apart)
    nbusy = 0
    for s_list in range(lo, hi):
        # unsigned: no wrap-around code; ``s`` one type throughout (no SSA: _jit.loop_kernel)
        s = np.uint64(s_list)
        pi = np.uint64(pl_i[s])
        pj = np.uint64(pl_j[s])
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        cut = radius[pi] + radius[pj]
        if dx * dx + dy * dy + dz * dz < cut * cut or pl_on[s] != 0:
            e = np.uint64(area + nbusy)
            busy[np.uint64(q0 + nbusy)] = s_list
            c[_entry(C_DX, e)] = dx
            c[_entry(C_DY, e)] = dy
            c[_entry(C_DZ, e)] = dz
            nbusy += 1
    # what the response reads of the busy ones' bodies and states
    tail = ps.shape[1] - CONTACT_TAIL
    for nth in range(nbusy):
        q = np.uint64(q0 + nth)
        e = np.uint64(area + nth)
        s = np.uint64(busy[q])
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        c[_entry(C_AOLD, e)] = ps[s, S_A]
        c[_entry(C_FNOLD, e)] = ps[s, S_FN]
        # velocities (0-2) and spins (3-5) of both: columns vix .. wiz and vjx .. wjz
        for k in range(0 if GATHER_VELOCITY else 3, 6 if GATHER_SPIN else 3):
            c[_entry(C_VIX + k, e)] = vel[i, k]
            c[_entry(C_VJX + k, e)] = vel[j, k]
        if HAS_FRICTION:
            c[_entry(C_FTOX, e)] = ps[s, S_FT]
            c[_entry(C_FTOY, e)] = ps[s, S_FT + 1]
            c[_entry(C_FTOZ, e)] = ps[s, S_FT + 2]
        if N_MAXWELL > 0:
            for k in range(2 * N_MAXWELL):
                hist[q, k] = ps[s, S_H + k]
        if CONTACT_TAIL > 0:
            # the tangential and rolling laws' histories (the state row's last columns)
            for k in range(CONTACT_TAIL):
                hist[q, 2 * N_MAXWELL + k] = ps[s, tail + k]
    return nbusy


@step_kernel
def _column_rows(c):
    """The flat scratch as rows of COLUMN_ROW entries: row ``area // COLUMN_ROW + C`` is column
    C of the area from entry ``area`` on (a view; one reshape, then a row is a plain index)."""
    return c.reshape((c.shape[0] // COLUMN_ROW, COLUMN_ROW))


@step_kernel
def _columns_in(rows, area):
    """The columns of the area from entry ``area`` on that the contact response reads, rows of
    ``_column_rows``, as a tuple (I_* positions): separate arguments to it, so that its
    ``noalias`` covers each (x3dpd._jit.vector_kernel)."""
    r0 = area // COLUMN_ROW
    return (rows[r0 + C_DX], rows[r0 + C_DY], rows[r0 + C_DZ], rows[r0 + C_VIX],
            rows[r0 + C_VIY], rows[r0 + C_VIZ], rows[r0 + C_WIX], rows[r0 + C_WIY],
            rows[r0 + C_WIZ], rows[r0 + C_VJX], rows[r0 + C_VJY], rows[r0 + C_VJZ],
            rows[r0 + C_WJX], rows[r0 + C_WJY], rows[r0 + C_WJZ], rows[r0 + C_AOLD],
            rows[r0 + C_FNOLD], rows[r0 + C_FTOX], rows[r0 + C_FTOY], rows[r0 + C_FTOZ])


@step_kernel
def _columns_out(rows, area):
    """The columns of the area from entry ``area`` on that the contact response writes, as a
    tuple (O_* positions)."""
    r0 = area // COLUMN_ROW
    return (rows[r0 + C_FX], rows[r0 + C_FY], rows[r0 + C_FZ], rows[r0 + C_TIX],
            rows[r0 + C_TIY], rows[r0 + C_TIZ], rows[r0 + C_TJX], rows[r0 + C_TJY],
            rows[r0 + C_TJZ], rows[r0 + C_A], rows[r0 + C_FN], rows[r0 + C_FTX],
            rows[r0 + C_FTY], rows[r0 + C_FTZ], rows[r0 + C_DW], rows[r0 + C_LOST],
            rows[r0 + C_ROLLED], rows[r0 + C_RMIN])


# Over 80 lines: a compiled kernel: one fused pass over a block's columns.
@vector_kernel
def _pair_response(q0, n, busy, pl_i, pl_j, particles, hist, dt, cin, cout, history_dt):
    """Pass 2 of the pair contacts: the contact response of a block's ``n`` busy candidates
    (report Figure 41), from the columns the filter gathered (``cin``, I_* positions; entry k
    for the k-th, busy candidate q0 + k) into the columns ``cout`` (O_* positions;
    contact_lists.PAIR_OUTPUT_COLUMNS) for pass 3 to apply. Each entry's answer depends on
    that entry alone, so any split of the list (threads) gives the same bits.

    The normal law is the scene's (x3dpd.physics.normal_laws), with n = (x_j - x_i)/|x_j - x_i|
    and approach a = R_i + R_j - |x_j - x_i|; the tangential law with spin (``_tangential``, the
    same as on walls) acts at the contact points x_i + R_i n and x_j - R_j n. A candidate that
    no longer touches (a <= 0) gets F = 0; pass 3 closes it as a wall contact is closed
    (``_close_contact``). Nothing here reads through an index or writes the contact state or
    the forces -- pass 1 gathered, pass 3 applies, in list order -- so the loop reads and
    writes contiguous 1-D columns only and LLVM vectorizes it (x3dpd._jit.vector_kernel):
    packed square roots, divisions and multiply-adds, no gathers (tests/solver/
    test_pair_columns.py checks the machine code). Histories (Maxwell terms, then the
    tangential and rolling laws') are read and written in ``hist`` (row q0 + k, Fortran order: one
    contiguous column per history value). Particles of several kinds gather their constants
    by ``busy``, ``pl_i``, ``pl_j``; one kind reads them once. ``history_dt``: the step the
    contacts slip over (``Stepping.history_dt``: dt, or 0 in a force evaluation at a state).
    """
    radius, pkind = particles.radius, particles.kind
    gamma = 0.5 / dt  # noqa: F841 (stick rate of the regularised friction law)
    dx_, dy_, dz_ = cin[I_DX], cin[I_DY], cin[I_DZ]
    vix_, viy_, viz_, wix_, wiy_, wiz_ = (cin[I_VIX], cin[I_VIY], cin[I_VIZ], cin[I_WIX],
                                          cin[I_WIY], cin[I_WIZ])
    vjx_, vjy_, vjz_, wjx_, wjy_, wjz_ = (cin[I_VJX], cin[I_VJY], cin[I_VJZ], cin[I_WJX],
                                          cin[I_WJY], cin[I_WJZ])
    a_old_, fn_old_ = cin[I_AOLD], cin[I_FNOLD]
    ftox_, ftoy_, ftoz_ = cin[I_FTOX], cin[I_FTOY], cin[I_FTOZ]
    fx_, fy_, fz_ = cout[O_FX], cout[O_FY], cout[O_FZ]
    tix_, tiy_, tiz_ = cout[O_TIX], cout[O_TIY], cout[O_TIZ]
    tjx_, tjy_, tjz_ = cout[O_TJX], cout[O_TJY], cout[O_TJZ]
    a_, fn_, ftx_, fty_, ftz_ = cout[O_A], cout[O_FN], cout[O_FTX], cout[O_FTY], cout[O_FTZ]
    dw_, lost_, rolled_, rmin_ = cout[O_DW], cout[O_LOST], cout[O_ROLLED], cout[O_RMIN]
    # one kind: the friction and rolling constants of the pair, read once before the loop (in
    # the loop LLVM sinks them into the law's branches and gathers them there, masked)
    k0 = np.uint64(pkind[0])
    m_t0, mu_s0, kappa0, mu_k0, eta0 = _friction_constants(particles, k0, k0)
    lever0, inertia0 = particles.tan_pair[k0, k0, 2], particles.tan_pair[k0, k0, 3]
    for nth in range(n):
        # unsigned indices: numba then drops the wrap-around of negative indices from every
        # access (from an unknown ``q0`` LLVM cannot tell q >= 0, and the selects keep the
        # loop scalar); ``e`` the entry in the columns, ``q`` the busy candidate
        e = np.uint64(nth)
        q = np.uint64(q0 + nth)
        if HAS_ONE_PARTICLE_KIND:
            # all particles alike (x3dpd.solver.variants): their constants are read once,
            # not gathered per contact
            pi = np.uint64(0)
            pj = np.uint64(0)
        else:
            # unsigned indices: no wrap-around code for negative indices
            s = np.uint64(busy[q])
            pi = np.uint64(pl_i[s])
            pj = np.uint64(pl_j[s])
        dx = dx_[e]
        dy = dy_[e]
        dz = dz_[e]
        ri = radius[pi]
        rj = radius[pj]
        dist = math.sqrt(dx * dx + dy * dy + dz * dz)
        a = (ri + rj) - dist
        a_old = a_old_[e]
        fn_old = fn_old_[e]
        inv_dist = 1.0 / dist
        nx = dx * inv_dist
        ny = dy * inv_dist
        nz = dz * inv_dist
        # the pair's mixed constants (x3dpd.physics.mixing), looked up by particle kind
        ki = np.uint64(pkind[pi])
        kj = np.uint64(pkind[pj])
        touching = a > 0.0
        # the normal law for every busy candidate, its force kept for those that touch: a
        # branch-free body, whose table reads are then loop-invariant loads (one kind) instead
        # of masked gathers. A candidate apart gets F = 0; its law value (NaN under Hertz's
        # a^1.5) and the histories of its row in ``hist`` are never applied (pass 3 closes it)
        a_rate = -(nx * (vjx_[e] - vix_[e]) + ny * (vjy_[e] - viy_[e])
                   + nz * (vjz_[e] - viz_[e]))
        # Maxwell histories in row q of ``hist``, columns 0 ..
        fn_law = NORMAL_PAIR_FORCE(a, a_old, a_rate, pi, pj, ki, kj, particles, hist, q, 0,
                                   N_MAXWELL)
        if NORMAL_CLAMPED and fn_law < 0.0:
            fn_law = 0.0
        fn = fn_law if touching else 0.0
        # work the normal force does over the step as velocity Verlet moves the bodies, the
        # trapezoid 1/2 (F_old n_old + F n) . (-dt dv) (dv = v_j - v_i at the half step, the
        # drift of x_j - x_i over the step), n_old the direction at the last step's positions
        # d - dt dv: along the approach alone, 1/2 (F_old + F) (a - a_old), it missed the turn
        # of n, 1e-7 of beam_64's energy scale in 50 ms. A contact opening (F_old = 0) books
        # 1/2 F dt da/dt (_booked_from's gap), a closing one (F = 0) 1/2 F_old's term (pass 3)
        dvx = vjx_[e] - vix_[e]
        dvy = vjy_[e] - viy_[e]
        dvz = vjz_[e] - viz_[e]
        ox = dx - dt * dvx
        oy = dy - dt * dvy
        oz = dz - dt * dvz
        inv_old = 1.0 / math.sqrt(ox * ox + oy * oy + oz * oz)
        old_rate = -(ox * dvx + oy * dvy + oz * dvz) * inv_old
        dw = 0.5 * dt * (fn_old * old_rate + fn * a_rate)
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
            wix = wix_[e]
            wiy = wiy_[e]
            wiz = wiz_[e]
            wjx = wjx_[e]
            wjy = wjy_[e]
            wjz = wjz_[e]
            # contact point velocities: i at +ri n, j at -rj n
            vix = vix_[e] + ri * (wiy * nz - wiz * ny)
            viy = viy_[e] + ri * (wiz * nx - wix * nz)
            viz = viz_[e] + ri * (wix * ny - wiy * nx)
            vjx = vjx_[e] - rj * (wjy * nz - wjz * ny)
            vjy = vjy_[e] - rj * (wjz * nx - wjx * nz)
            vjz = vjz_[e] - rj * (wjx * ny - wjy * nx)
            m_t, mu_s, kappa, mu_k, eta = m_t0, mu_s0, kappa0, mu_k0, eta0
            if not HAS_ONE_PARTICLE_KIND:
                m_t, mu_s, kappa, mu_k, eta = _friction_constants(particles, ki, kj)
            # the tangential law's history in row q of ``hist``, after the Maxwell terms
            ftx, fty, ftz, lost, du = _tangential(vjx - vix, vjy - viy, vjz - viz, nx, ny, nz,
                                                  fn, a, m_t, mu_s, kappa, mu_k, eta,
                                                  history_dt, gamma,
                                                  ftox_[e], ftoy_[e], ftoz_[e], hist, q,
                                                  2 * N_MAXWELL)
            # the last step's friction force acted at the last step's contact points, the arms
            # +ri n_old and -rj n_old, and may lean out of this step's tangent plane: its half
            # of the trapezoid is -1/2 F_old . v_r,old dt with v_r,old the contact points'
            # relative velocity on those arms, not on this step's tangent plane (the law's
            # v_t). Their difference, second order in the turn of n, was 2e-8 of beam_64's
            # energy scale in 50 ms.
            mx = ox * inv_old
            my = oy * inv_old
            mz = oz * inv_old
            vrox = (dvx - rj * (wjy * mz - wjz * my)) - ri * (wiy * mz - wiz * my)
            vroy = (dvy - rj * (wjz * mx - wjx * mz)) - ri * (wiz * mx - wix * mz)
            vroz = (dvz - rj * (wjx * my - wjy * mx)) - ri * (wix * my - wiy * mx)
            vrx = vjx - vix
            vry = vjy - viy
            vrz = vjz - viz
            vrn = vrx * nx + vry * ny + vrz * nz
            lost -= 0.5 * dt * (ftox_[e] * (vrox - (vrx - vrn * nx))
                                + ftoy_[e] * (vroy - (vry - vrn * ny))
                                + ftoz_[e] * (vroz - (vrz - vrn * nz)))
            if TANGENTIAL_STORES and touching:
                # the spring's share of the slip work is stored, not lost (a candidate that
                # no longer touches: lost is its last step's slip work, -1/2 F_old . v_r,old
                # dt, and pass 3 books the spring's energy as it closes the contact)
                dw += du
                lost -= du
            fx += ftx
            fy += fty
            fz += ftz
            # torques: r_i x (-F_t) with r_i = ri n ; r_j x F_t with r_j = -rj n
            tx = ny * ftz - nz * fty
            ty = nz * ftx - nx * ftz
            tz = nx * fty - ny * ftx
        fx_[e] = fx
        fy_[e] = fy
        fz_[e] = fz
        tix_[e] = ri * tx
        tiy_[e] = ri * ty
        tiz_[e] = ri * tz
        tjx_[e] = rj * tx
        tjy_[e] = rj * ty
        tjz_[e] = rj * tz
        if HAS_ROLLING:
            # rolling resistance against the relative rolling w_i - w_j (x3dpd.physics.rolling):
            # M on i, -M on j (the columns are subtracted from the moments)
            lever, inertia = lever0, inertia0
            if not HAS_ONE_PARTICLE_KIND:
                lever, inertia = particles.tan_pair[ki, kj, 2], particles.tan_pair[ki, kj, 3]
            mx, my, mz, rolled = ROLLING_TORQUE(wix_[e] - wjx_[e], wiy_[e] - wjy_[e],
                                                wiz_[e] - wjz_[e], fn, lever, inertia, dt, hist,
                                                q, 2 * N_MAXWELL + N_TANGENTIAL)
            tix_[e] -= mx
            tiy_[e] -= my
            tiz_[e] -= mz
            tjx_[e] += mx
            tjy_[e] += my
            tjz_[e] += mz
            rolled_[e] = rolled
        a_[e] = a
        fn_[e] = fn
        ftx_[e] = ftx
        fty_[e] = fty
        ftz_[e] = ftz
        dw_[e] = dw
        lost_[e] = lost
        rmin_[e] = ri if ri < rj else rj


@step_kernel
def _friction_constants(particles, ki, kj):
    """(m_t, mu_s, kappa, mu_k, eta) of a pair of particle kinds: the tangential effective mass
    and static mu (x3dpd.physics.mixing), the tangential law's stiffness constant, kinetic mu and
    damping constant (x3dpd.physics.tangential_laws.tangential_tables; 0 for a law without a
    spring)."""
    kappa = 0.0
    mu_k = 0.0
    eta = 0.0
    if TANGENTIAL_STORES:
        kappa = particles.tan_pair[ki, kj, 0]
        mu_k = particles.tan_pair[ki, kj, 1]
        eta = particles.tan_pair[ki, kj, 4]
    return particles.pair_c[ki, kj, 1], particles.pair_c[ki, kj, 2], kappa, mu_k, eta


@loop_kernel(inline="never")
def _pair_apply(q0, n, area, busy, p0, pl_i, pl_j, ps, pl_on, force, pen_limit, diag, c, hist,
                status, w_normal, w_fric, w_roll):
    """Pass 3 of the pair contacts, in list order over a block's ``n`` busy candidates q0 ..
    q0 + n - 1: the contact states, the forces on both particles and the ledger's sums from the
    columns ``c`` of ``_pair_response`` (the area from entry ``area`` on, ``_entry``) -- the
    same sums in the same order as a single scalar loop.
    Returns (status, normal work, friction loss, rolling loss), continued from the ones given
    (OK and zeros for the whole list; a threaded loop chains them through its chunks in list
    order). Its own function, like the filter: inlined into the step loop, the column
    pointers were reloaded from the stack at every contact (measured with
    tools/bench/profile_jit.py); and like the filter's, its column entries are constant offsets
    from the area's base, not a pointer per column."""
    for nth in range(n):
        # unsigned: no wrap-around code (``_pair_response``); ``e`` the entry in the columns
        q = np.uint64(q0 + nth)
        e = np.uint64(area + nth)
        s = np.uint64(busy[q])
        a = c[_entry(C_A, e)]
        if a <= 0.0:
            if HAS_TORQUE and pl_on[s] != 0:
                # the friction's and rolling's work of the step the contact ends on
                w_fric += c[_entry(C_LOST, e)]
                if HAS_ROLLING:
                    w_roll += c[_entry(C_ROLLED, e)]
            # its last step's work: the response's trapezoid (1/2 F_old n_old . -dt dv)
            _, released = _close_contact(ps, pl_on, s, a, ps[s, S_A], ps[s, S_FN])
            w_normal += c[_entry(C_DW, e)]
            if TANGENTIAL_STORES:
                w_normal -= released
                w_fric += released
            continue
        rmin = c[_entry(C_RMIN, e)]
        if a > pen_limit * rmin:
            status |= _penetration(diag, pl_i[s], -1 - pl_j[s], a, rmin)
        ps[s, S_A] = a
        ps[s, S_FN] = c[_entry(C_FN, e)]
        if N_MAXWELL > 0:
            for k in range(2 * N_MAXWELL):
                ps[s, S_H + k] = hist[q, k]
        if CONTACT_TAIL > 0:
            for k in range(CONTACT_TAIL):
                ps[s, ps.shape[1] - CONTACT_TAIL + k] = hist[q, 2 * N_MAXWELL + k]
        pl_on[s] = 1
        w_normal += c[_entry(C_DW, e)]
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        fx = c[_entry(C_FX, e)]
        fy = c[_entry(C_FY, e)]
        fz = c[_entry(C_FZ, e)]
        if HAS_TORQUE:
            w_fric += c[_entry(C_LOST, e)]
            if HAS_ROLLING:
                w_roll += c[_entry(C_ROLLED, e)]
            ps[s, S_FT] = c[_entry(C_FTX, e)]
            ps[s, S_FT + 1] = c[_entry(C_FTY, e)]
            ps[s, S_FT + 2] = c[_entry(C_FTZ, e)]
            force[i, 3] -= c[_entry(C_TIX, e)]
            force[i, 4] -= c[_entry(C_TIY, e)]
            force[i, 5] -= c[_entry(C_TIZ, e)]
            force[j, 3] -= c[_entry(C_TJX, e)]
            force[j, 4] -= c[_entry(C_TJY, e)]
            force[j, 5] -= c[_entry(C_TJZ, e)]
        force[j, 0] += fx
        force[j, 1] += fy
        force[j, 2] += fz
        force[i, 0] -= fx
        force[i, 1] -= fy
        force[i, 2] -= fz
    return status, w_normal, w_fric, w_roll
