"""Step-loop template, part: the triangulated walls' contacts in columns, when every particle
meets the walls with the same constants (``HAS_ONE_WALL_KIND``; x3dpd.solver.variants).

The pair contacts' treatment (``_template_pairs``) for wall contacts: a pass that finds the
candidates within reach of their face, locates the touching ones on the face's triangles and
gathers what the contact response reads into contiguous columns (``_wall_gather``: the
approach, the face's normal, the particle's velocity and spin, the wall point's velocity, the
state row's approach, normal and friction force, the laws' histories), the response over
those columns, vectorized (``_wall_response_columns``), and a pass that applies it in list
order (``_wall_apply``): the contact states, the force and moment on the particle, the
reaction on the triangle's three nodes by their barycentric weights, and the ledger's sums.
The physics is ``_wall_response``'s (``_template_contact``) to the last operation but the
order of the moment's sums; a contact that ends is closed as ``_template_walls`` closes it, in
the same place of the ledger's sums.
Generated per variant beside the loop, with the variant's constants (``_template_variant``).
"""


import numpy as np

from x3dpd._jit import loop_kernel, step_kernel, vector_kernel
from x3dpd.geometry.faces import (FRAME_FRESH, _face_frames, _locate_on_face,
                                  _locate_on_frames)
from x3dpd.solver._template_contact import (CONTACT_TAIL, HAS_TORQUE, _booked_from,
                                            _close_contact, _penetration, _tangential,
                                            _wall_closing_work)
from x3dpd.solver._template_variant import (HAS_FRICTION, HAS_ROLLING, N_MAXWELL, N_ROLLING,
                                            NORMAL_CLAMPED, NORMAL_WALL_FORCE, ROLLING_TORQUE,
                                            TANGENTIAL_STORES)
from x3dpd.solver.contact_lists import (COLUMN_ROW, S_A, S_FN, S_FT, S_H, WALL_COLUMNS,
                                         WALL_INPUT_COLUMNS, WALL_OUTPUT_COLUMNS)

# rows of the wall pass's column scratch (x3dpd.solver.contact_lists.WALL_COLUMNS)
(W_FX, W_FY, W_FZ, W_TX, W_TY, W_TZ, W_FN, W_FTX, W_FTY, W_FTZ, W_DW, W_LOST,
 W_ROLLED) = (WALL_COLUMNS.index(c) for c in WALL_OUTPUT_COLUMNS)
(W_A, W_AOLD, W_FNOLD, W_FTOX, W_FTOY, W_FTOZ, W_NX, W_NY, W_NZ, W_VX, W_VY, W_VZ, W_WX, W_WY,
 W_WZ, W_VWX, W_VWY, W_VWZ) = (WALL_COLUMNS.index(c) for c in WALL_INPUT_COLUMNS)
W_TRI, W_W0, W_W1, W_W2 = (WALL_COLUMNS.index(c) for c in ("tri", "w0", "w1", "w2"))
# positions in the response's tuples of input and output columns
(I_A, I_AOLD, I_FNOLD, I_FTOX, I_FTOY, I_FTOZ, I_NX, I_NY, I_NZ, I_VX, I_VY, I_VZ, I_WX, I_WY,
 I_WZ, I_VWX, I_VWY, I_VWZ) = range(len(WALL_INPUT_COLUMNS))
(O_FX, O_FY, O_FZ, O_TX, O_TY, O_TZ, O_FN, O_FTX, O_FTY, O_FTZ, O_DW, O_LOST,
 O_ROLLED) = range(len(WALL_OUTPUT_COLUMNS))
#: the wall response's histories: the particle's Maxwell terms, then the tangential and rolling
#: laws' (a wall contact's state row: S_H .., then its last CONTACT_TAIL columns)
N_WALL_HISTORY = N_MAXWELL + CONTACT_TAIL


@step_kernel
def _at(column, e):
    """Where column ``column`` keeps entry ``e`` in the flat scratch (contact_lists:
    COLUMN_ROW entries a column, a constant of the compiled code)."""
    return np.uint64(column * COLUMN_ROW) + e


@step_kernel
def _wall_busy(lo, hi, x, p0, radius, wl_p, wl_f, wl_on, face_n, face_d, busy):
    """Pass 1 of the wall contacts, over the candidates ``lo`` .. ``hi`` - 1 of the list: the
    ones within reach of their face's plane now or open at the last step go into ``busy``.
    Returns how many are busy. Inlined into the step, so that a block with none (a falling or
    fluidized bed) costs no call."""
    nbusy = 0
    for s_list in range(lo, hi):
        s = np.uint64(s_list)
        p = np.uint64(wl_p[s])
        f = np.uint64(wl_f[s])
        i = np.uint64(p0 + wl_p[s])
        d = face_n[f, 0] * x[i, 0] + face_n[f, 1] * x[i, 1] + face_n[f, 2] * x[i, 2] - face_d[f]
        if d < radius[p] or wl_on[s] != 0:
            busy[np.uint64(nbusy)] = s_list
            nbusy += 1
    return nbusy


@loop_kernel(inline="never")
def _wall_gather(nbusy, x, vel, p0, radius, wl_p, wl_f, ws, face_n, face_d, face_ptr,
                 face_tris, tri_nodes, tri_frame, busy, c, hist, w):
    """Pass 1, continued, over the ``nbusy`` busy candidates of ``busy`` (:func:`_wall_busy`):
    a touching one is located on the face's triangles (``_locate_on_frames``: the triangle,
    its barycentric weights; the face's frames computed first if this step has not yet), and
    every busy one's inputs are gathered into the columns of ``c`` (entry k for the k-th busy
    one) and its histories into row k of ``hist``. One that does not touch, or touches
    outside the face, gets triangle -1: pass 3 closes it. ``w`` is a 3-element scratch."""
    tail = ws.shape[1] - CONTACT_TAIL
    for k in range(nbusy):
        e = np.uint64(k)
        s = np.uint64(busy[e])
        p = np.uint64(wl_p[s])
        f = np.uint64(wl_f[s])
        i = np.uint64(p0 + wl_p[s])
        nx = face_n[f, 0]
        ny = face_n[f, 1]
        nz = face_n[f, 2]
        r = radius[p]
        d = nx * x[i, 0] + ny * x[i, 1] + nz * x[i, 2] - face_d[f]
        a = r - d
        t = -1
        if a > 0.0:
            if tri_frame[face_tris[face_ptr[f]], FRAME_FRESH] == 0.0:
                _face_frames(x, face_n, f, face_ptr, face_tris, tri_nodes, tri_frame)
            t = _locate_on_frames(x[i, 0] - d * nx, x[i, 1] - d * ny, x[i, 2] - d * nz, f,
                                  face_ptr, face_tris, tri_frame, r, w)
        c[_at(W_TRI, e)] = t
        c[_at(W_A, e)] = a if t >= 0 else 0.0
        c[_at(W_AOLD, e)] = ws[s, S_A]
        c[_at(W_FNOLD, e)] = ws[s, S_FN]
        c[_at(W_NX, e)] = nx
        c[_at(W_NY, e)] = ny
        c[_at(W_NZ, e)] = nz
        for k3 in range(6):
            c[_at(W_VX + k3, e)] = vel[i, k3]
        vwx = 0.0
        vwy = 0.0
        vwz = 0.0
        if t >= 0:
            tt = np.uint64(t)
            for k3 in range(3):
                nd = np.uint64(tri_nodes[tt, k3])
                vwx += w[k3] * vel[nd, 0]
                vwy += w[k3] * vel[nd, 1]
                vwz += w[k3] * vel[nd, 2]
            c[_at(W_W0, e)] = w[0]
            c[_at(W_W1, e)] = w[1]
            c[_at(W_W2, e)] = w[2]
        c[_at(W_VWX, e)] = vwx
        c[_at(W_VWY, e)] = vwy
        c[_at(W_VWZ, e)] = vwz
        if HAS_FRICTION:
            c[_at(W_FTOX, e)] = ws[s, S_FT]
            c[_at(W_FTOY, e)] = ws[s, S_FT + 1]
            c[_at(W_FTOZ, e)] = ws[s, S_FT + 2]
        for k2 in range(N_MAXWELL):
            hist[e, k2] = ws[s, S_H + k2]
        for k2 in range(CONTACT_TAIL):
            hist[e, N_MAXWELL + k2] = ws[s, tail + k2]


@step_kernel
def _wall_columns_in(rows):
    """The columns the wall response reads (I_* positions), rows of the flat scratch."""
    return (rows[W_A], rows[W_AOLD], rows[W_FNOLD], rows[W_FTOX], rows[W_FTOY], rows[W_FTOZ],
            rows[W_NX], rows[W_NY], rows[W_NZ], rows[W_VX], rows[W_VY], rows[W_VZ], rows[W_WX],
            rows[W_WY], rows[W_WZ], rows[W_VWX], rows[W_VWY], rows[W_VWZ])


@step_kernel
def _wall_columns_out(rows):
    """The columns the wall response writes (O_* positions)."""
    return (rows[W_FX], rows[W_FY], rows[W_FZ], rows[W_TX], rows[W_TY], rows[W_TZ], rows[W_FN],
            rows[W_FTX], rows[W_FTY], rows[W_FTZ], rows[W_DW], rows[W_LOST], rows[W_ROLLED])


# Over 80 lines: a compiled kernel: one fused pass over the wall columns.
@vector_kernel
def _wall_response_columns(n, particles, hist, dt, history_dt, cin, cout):
    """Pass 2 of the wall contacts: ``_wall_response``'s physics (the normal law at approach a
    along n, the tangential law with spin at the contact point -r n against the wall point's
    velocity, the rolling law) for ``n`` busy candidates, from the columns ``cin`` into the
    columns ``cout``: the force and moment on the particle, the applied normal force, the
    friction force, the normal work (the step's trapezoid, from the gap an opening contact
    had: ``_booked_from``), the friction and rolling losses. Every particle alike: particle
    0's constants. A candidate that does not touch (a = 0 in its column) gets F = 0 and is
    closed by pass 3, which ignores its row here."""
    radius, mu, inv_mt = particles.radius, particles.mu, particles.inv_mt
    gamma = 0.5 / dt  # noqa: F841 (stick rate of the regularised friction law)
    a_, a_old_, fn_old_ = cin[I_A], cin[I_AOLD], cin[I_FNOLD]
    ftox_, ftoy_, ftoz_ = cin[I_FTOX], cin[I_FTOY], cin[I_FTOZ]
    nx_, ny_, nz_ = cin[I_NX], cin[I_NY], cin[I_NZ]
    vx_, vy_, vz_, wx_, wy_, wz_ = (cin[I_VX], cin[I_VY], cin[I_VZ], cin[I_WX], cin[I_WY],
                                    cin[I_WZ])
    vwx_, vwy_, vwz_ = cin[I_VWX], cin[I_VWY], cin[I_VWZ]
    fx_, fy_, fz_, tx_, ty_, tz_ = (cout[O_FX], cout[O_FY], cout[O_FZ], cout[O_TX], cout[O_TY],
                                    cout[O_TZ])
    fn_, ftx_, fty_, ftz_ = cout[O_FN], cout[O_FTX], cout[O_FTY], cout[O_FTZ]
    dw_, lost_, rolled_ = cout[O_DW], cout[O_LOST], cout[O_ROLLED]
    p = np.uint64(0)
    r = radius[p]
    m_t = 1.0 / inv_mt[p]
    mu_s = mu[p]
    kappa = 0.0
    mu_k = 0.0
    eta = 0.0
    if TANGENTIAL_STORES:
        kappa = particles.tan_wall[p, 0]
        mu_k = particles.tan_wall[p, 1]
        eta = particles.tan_wall[p, 4]
    lever, inertia = particles.tan_wall[p, 2], particles.tan_wall[p, 3]
    for k in range(n):
        e = np.uint64(k)
        a = a_[e]
        a_old = a_old_[e]
        fn_old = fn_old_[e]
        nx = nx_[e]
        ny = ny_[e]
        nz = nz_[e]
        touching = a > 0.0
        # approach rate: the wall point's velocity minus the particle's, along n
        a_rate = (nx * (vwx_[e] - vx_[e]) + ny * (vwy_[e] - vy_[e])
                  + nz * (vwz_[e] - vz_[e]))
        fn_law = NORMAL_WALL_FORCE(a, a_old, a_rate, p, particles, hist, e, 0, N_MAXWELL)
        if NORMAL_CLAMPED and fn_law < 0.0:
            fn_law = 0.0
        fn = fn_law if touching else 0.0
        dw = 0.5 * (fn_old + fn) * (a - _booked_from(a, a_old, a_rate, dt))
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
            rcx = -r * nx
            rcy = -r * ny
            rcz = -r * nz
            wx = wx_[e]
            wy = wy_[e]
            wz = wz_[e]
            # the contact point's velocity (at -r n, with the spin) less the wall point's
            vrx = vx_[e] + wy * rcz - wz * rcy - vwx_[e]
            vry = vy_[e] + wz * rcx - wx * rcz - vwy_[e]
            vrz = vz_[e] + wx * rcy - wy * rcx - vwz_[e]
            ftx, fty, ftz, lost, du = _tangential(vrx, vry, vrz, nx, ny, nz, fn, a, m_t, mu_s,
                                                  kappa, mu_k, eta, history_dt, gamma,
                                                  ftox_[e], ftoy_[e], ftoz_[e], hist, e,
                                                  N_MAXWELL)
            if TANGENTIAL_STORES:
                # the spring's share of the slip work is stored, not lost
                dw += du
                lost -= du
            fx += ftx
            fy += fty
            fz += ftz
            tx = rcy * ftz - rcz * fty
            ty = rcz * ftx - rcx * ftz
            tz = rcx * fty - rcy * ftx
        rolled = 0.0
        if HAS_ROLLING:
            # rolling resistance against the particle's rolling (x3dpd.physics.rolling)
            mx, my, mz, rolled = ROLLING_TORQUE(wx_[e], wy_[e], wz_[e], fn, lever, inertia, dt,
                                                hist, e, N_MAXWELL + CONTACT_TAIL - N_ROLLING)
            tx += mx
            ty += my
            tz += mz
        fx_[e] = fx
        fy_[e] = fy
        fz_[e] = fz
        tx_[e] = tx
        ty_[e] = ty
        tz_[e] = tz
        fn_[e] = fn
        ftx_[e] = ftx
        fty_[e] = fty
        ftz_[e] = ftz
        dw_[e] = dw
        lost_[e] = lost
        rolled_[e] = rolled


@loop_kernel(inline="never")
def _wall_apply(n, busy, nodes, particles, faces, walls, stepping, w, c, status, w_normal,
                w_fric, w_roll):
    """Pass 3 of the wall contacts, in list order over the ``n`` busy candidates: a touching
    one's state row (approach, force, friction force, histories), the force and moment on its
    particle, the reaction on its triangle's nodes by their weights, and the ledger's sums;
    one that no longer touches its face (triangle -1) is closed one at a time as the scalar
    pass closes it (``_close_wall_contact``), in the same place of the sums. Returns (status,
    normal work, friction and rolling losses), continued from the ones given."""
    ws, wl_on, wl_p = walls.state, walls.on, walls.first
    hist, force, tri_nodes = walls.history, nodes.force, faces.tri_nodes
    p0, radius = particles.p0, particles.radius
    tail = ws.shape[1] - CONTACT_TAIL
    for k in range(n):
        e = np.uint64(k)
        s = np.uint64(busy[e])
        if c[_at(W_TRI, e)] < 0.0:
            dw, lost, rolled = _close_wall_contact(s, nodes, particles, faces, walls, stepping,
                                                   w)
            w_normal += dw
            w_fric += lost
            w_roll += rolled
            continue
        p = np.uint64(wl_p[s])
        i = np.uint64(p0 + wl_p[s])
        a = c[_at(W_A, e)]
        r = radius[p]
        if a > stepping.pen_limit * r:
            status |= _penetration(stepping.diag, wl_p[s], walls.second[s], a, r)
        fn = c[_at(W_FN, e)]
        ws[s, S_A] = a
        ws[s, S_FN] = fn
        wl_on[s] = 1
        for k2 in range(N_MAXWELL):
            ws[s, S_H + k2] = hist[e, k2]
        for k2 in range(CONTACT_TAIL):
            ws[s, tail + k2] = hist[e, N_MAXWELL + k2]
        w_normal += c[_at(W_DW, e)]
        fx = c[_at(W_FX, e)]
        fy = c[_at(W_FY, e)]
        fz = c[_at(W_FZ, e)]
        if HAS_TORQUE:
            w_fric += c[_at(W_LOST, e)]
            if HAS_ROLLING:
                w_roll += c[_at(W_ROLLED, e)]
            if HAS_FRICTION:
                ws[s, S_FT] = c[_at(W_FTX, e)]
                ws[s, S_FT + 1] = c[_at(W_FTY, e)]
                ws[s, S_FT + 2] = c[_at(W_FTZ, e)]
            force[i, 3] += c[_at(W_TX, e)]
            force[i, 4] += c[_at(W_TY, e)]
            force[i, 5] += c[_at(W_TZ, e)]
        force[i, 0] += fx
        force[i, 1] += fy
        force[i, 2] += fz
        t = np.uint64(int(c[_at(W_TRI, e)]))
        for k3 in range(3):
            nd = np.uint64(tri_nodes[t, k3])
            wk = c[_at(W_W0 + k3, e)]
            force[nd, 0] -= wk * fx
            force[nd, 1] -= wk * fy
            force[nd, 2] -= wk * fz
    return status, w_normal, w_fric, w_roll


@step_kernel
def _close_wall_contact(s, nodes, particles, faces, walls, stepping, w):
    """Close wall candidate ``s``, which no longer touches its face, as the scalar pass does
    (``_template_walls``): the last step's friction and rolling work at the wall point under
    the particle, the contact's last normal work, the energy a tangential spring still stored.
    Returns (normal work, friction loss, rolling loss)."""
    x = nodes.x
    ws, wl_on = walls.state, walls.on
    face_n, face_d, face_ptr, face_tris, tri_nodes = (faces.normal, faces.offset, faces.tri_ptr,
                                                      faces.tris, faces.tri_nodes)
    p = np.uint64(walls.first[s])
    f = np.uint64(walls.second[s])
    i = np.uint64(particles.p0 + walls.first[s])
    nx = face_n[f, 0]
    ny = face_n[f, 1]
    nz = face_n[f, 2]
    r = particles.radius[p]
    d = nx * x[i, 0] + ny * x[i, 1] + nz * x[i, 2] - face_d[f]
    a = r - d
    lost = 0.0
    rolled = 0.0
    if HAS_TORQUE and wl_on[s] != 0:
        # its friction's and rolling's work on this last step, at the wall point under the
        # particle (off the face: the face's first triangle's centroid)
        t = _locate_on_face(x[i, 0] - d * nx, x[i, 1] - d * ny, x[i, 2] - d * nz, nx, ny, nz,
                            f, x, face_ptr, face_tris, tri_nodes, r, w)
        if t < 0:
            t = face_tris[face_ptr[f]]
            w[0] = 1.0 / 3.0
            w[1] = 1.0 / 3.0
            w[2] = 1.0 / 3.0
        lost, rolled = _wall_closing_work(nodes, particles, stepping, ws, s, p, nx, ny, nz,
                                          tri_nodes, t, w, 3, False, 0.0, 0.0, 0.0)
    dw, released = _close_contact(ws, wl_on, s, a, ws[s, S_A], ws[s, S_FN])
    if TANGENTIAL_STORES:
        dw -= released
        lost += released
    return dw, lost, rolled
