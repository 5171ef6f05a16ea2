"""Template of the explicit time-step loop (report Section 7.3), specialised per scene.

:func:`x3dpd.solver.variants.make_advance` copies this file, replaces the block between the
VARIANT markers with the constants of one scene (which effects exist, how many Maxwell terms,
which friction law) and imports the copy from x3dpd's kernel cache, so numba compiles exactly the
effects the scene calls for -- absent effects are constant-false branches that never reach the
machine code -- and caches the result on disk.

Integration: velocity Verlet (central difference) with a constant step,

    v(n+1/2) = v(n) + dt/2 a(n);  x(n+1) = x(n) + dt v(n+1/2);  forces f(n+1) from x(n+1), v(n+1/2);
    v(n+1) = v(n+1/2) + dt/2 a(n+1).

Velocity-dependent forces (dampers, friction, wall velocities) use the half-step velocity, as
X3D's central-difference scheme does. The kernels take the named bundles of
:mod:`x3dpd.solver.bundles` (``nodes``, ``particles``, ``walls`` ...), never positional arrays;
the per-step ones are inlined into ``advance`` (x3dpd._jit.step_kernel).
"""

# --- VARIANT BEGIN ---
HAS_GRAVITY = True
HAS_SPRINGS = True
HAS_RIGID = True
HAS_RIGID_ROTATION = True
HAS_WALLS = True
HAS_PAIRS = True
HAS_FRICTION = True
HAS_VISCOELASTIC = True
HAS_EXTERNAL = True
HAS_USER_FORCE = False
HAS_PYTHON_FORCE = False
HAS_MOTION = True
N_MAXWELL = 1
HAS_WALLS_TRANSLATE = False
HAS_SHAPES = True
HAS_ONE_PARTICLE_KIND = False
from x3dpd.physics.coulomb import regularized_coulomb_slip_coefficient as FRICTION_LAW  # noqa: E402,E501
from x3dpd.physics.maxwell import wall_force as NORMAL_WALL_FORCE, pair_force as NORMAL_PAIR_FORCE, stored_energy as NORMAL_STORED_ENERGY, CLAMPED as NORMAL_CLAMPED, USES_RATE as NORMAL_USES_RATE, DAMPED as NORMAL_DAMPED  # noqa: E402,E501
SHAPE_LOCATE = None
USER_FORCE = None
# --- VARIANT END ---

import math  # noqa: E402

import numpy as np  # noqa: E402

from x3dpd._jit import kernel, loop_kernel, step_kernel, vector_kernel  # noqa: E402
from x3dpd.geometry.cells import _find_pairs  # noqa: E402
from x3dpd.geometry.faces import (  # noqa: E402
    _build_wall_list, _face_offsets, _face_planes, _locate_on_face)
from x3dpd.physics.gravity import _gravity_energy, _gravity_forces  # noqa: E402
from x3dpd.physics.motion import _apply_motion, _apply_motion_step, _motion_work  # noqa: E402,E501
from x3dpd.physics.rigid_link import (  # noqa: E402
    _gather_slaves, _rigid_angular_kick, _rotate, _update_slaves)
from x3dpd.physics.spring_damper import _spring_energy, _spring_forces  # noqa: E402
from x3dpd.physics.usrfrc import _force_value  # noqa: E402
from x3dpd.solver.bundles import (  # noqa: E402
    ContactList, Faces, Loads, Nodes, Output, Particles, RigidBodies, Shapes, Springs, Status,
    Stepping)
from x3dpd.solver.contact_lists import (  # noqa: E402
    PAIR_COLUMNS, S_A, S_FN, S_FT, S_H, _active_flags, _merge_states, _pair_approach)

@kernel
def _no_user_force(t, x, vel, force):
    """Stand-in for USER_FORCE in variants without a user file (never called)."""
    return


if USER_FORCE is None:
    USER_FORCE = _no_user_force


@kernel
def _no_shape_locate(kind, x, na, nb, params, c, px, py, pz, r, out):
    """Stand-in for SHAPE_LOCATE in variants without analytic walls (never called)."""
    return


if SHAPE_LOCATE is None:
    SHAPE_LOCATE = _no_shape_locate

# status bits returned by advance() and _forces() (x3dpd.solver.bundles.Status, as int constants)
OK = int(Status.OK)
PENETRATION = int(Status.PENETRATION)
NONFINITE = int(Status.NONFINITE)
REALLOC_PAIRS = int(Status.REALLOC_PAIRS)
REALLOC_WALLS = int(Status.REALLOC_WALLS)

#: Slip speeds at or below this [length/s] count as rolling (no friction force). The stick
#: regularisation halves the slip every step; without a floor a settled bed's slips -- and the
#: velocity components only friction acts on -- sink into subnormal numbers within ~1000 steps,
#: where every operation on them costs ~100 times more. 1e-100 is far below any physical slip
#: in any unit system and far above the subnormal range (its square, 1e-200, is still normal).
SLIP_FLOOR = 1e-100

# rows of the pair pass's column scratch (x3dpd.solver.contact_lists.PAIR_COLUMNS)
C_FX, C_FY, C_FZ = (PAIR_COLUMNS.index(c) for c in ("fx", "fy", "fz"))
C_TIX, C_TIY, C_TIZ = (PAIR_COLUMNS.index(c) for c in ("tix", "tiy", "tiz"))
C_TJX, C_TJY, C_TJZ = (PAIR_COLUMNS.index(c) for c in ("tjx", "tjy", "tjz"))
C_A, C_FN, C_DW, C_LOST, C_RMIN = (PAIR_COLUMNS.index(c) for c in ("a", "fn", "dw", "lost", "rmin"))
C_FTX, C_FTY, C_FTZ = (PAIR_COLUMNS.index(c) for c in ("ftx", "fty", "ftz"))
C_DX, C_DY, C_DZ = (PAIR_COLUMNS.index(c) for c in ("dx", "dy", "dz"))

# ledger slots (cumulative since t0)
L_WEXT = 0      # work of external forces and prescribed motions on the system
L_WN = 1        # work absorbed by the normal contact forces (sum of 1/2 (F0+F1) da)
L_DFRIC = 2     # energy dissipated by friction
L_DDAMP = 3     # energy dissipated by structural dampers


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
def _friction_force(vrx, vry, vrz, nx, ny, nz, fn, mu, m_t, dt, gamma, ftx_old, fty_old, ftz_old):
    """Friction force on the body whose contact point moves with v_r relative to the other.

    Splits v_r into normal and tangential parts, applies FRICTION_LAW to the slip speed
    (report Eq. 29/30; ``gamma`` = 1/(2 dt), the stick rate): F_t = -c(|v_t|) v_t, zero at slip
    speeds up to SLIP_FLOOR. Returns (F_tx, F_ty, F_tz, dissipated) with the trapezoidal slip
    work -1/2 (F_t,old + F_t) . v_t dt (F_t,old: the last step's force). Reads and writes no
    state, so the vectorized pair response can call it.
    """
    vn = vrx * nx + vry * ny + vrz * nz
    vtx = vrx - vn * nx
    vty = vry - vn * ny
    vtz = vrz - vn * nz
    vt = math.sqrt(vtx * vtx + vty * vty + vtz * vtz)
    ftx = 0.0
    fty = 0.0
    ftz = 0.0
    if vt > SLIP_FLOOR:
        mag = FRICTION_LAW(vt, fn, mu, m_t, gamma)
        ftx = -mag * vtx
        fty = -mag * vty
        ftz = -mag * vtz
    lost = -0.5 * ((ftx_old + ftx) * vtx + (fty_old + fty) * vty + (ftz_old + ftz) * vtz) * dt
    return ftx, fty, ftz, lost


@step_kernel
def _friction(vrx, vry, vrz, nx, ny, nz, fn, mu, m_t, dt, gamma, states, s):
    """:func:`_friction_force` with the last step's force read from, and the new one kept in,
    the contact's state row ``states[s]`` (columns S_FT ...). Returns (F_tx, F_ty, F_tz,
    dissipated)."""
    ftx, fty, ftz, lost = _friction_force(vrx, vry, vrz, nx, ny, nz, fn, mu, m_t, dt, gamma,
                                          states[s, S_FT], states[s, S_FT + 1],
                                          states[s, S_FT + 2])
    states[s, S_FT] = ftx
    states[s, S_FT + 1] = fty
    states[s, S_FT + 2] = ftz
    return ftx, fty, ftz, lost


@step_kernel
def _wall_response(nodes, particles, stepping, ws, on, s, p, a, a_old, fn_old, nx, ny, nz,
                   wall_nodes, row, w, n_w, lever, lx, ly, lz):
    """The contact response of particle ``p`` on a wall entity, whatever its shape: the
    scene's normal law (x3dpd.physics.normal_laws) at approach ``a`` along the unit normal n
    (from the wall into the particle), Coulomb friction with spin, and the reaction on the
    wall's nodes ``wall_nodes[row, :n_w]`` with weights ``w``. The wall point moves with
    sum_e w_e v_e, plus omega x l when ``lever`` (omega of the first node; l = (lx, ly, lz) from
    the weighted node point to the wall point, whose moment l x F then goes to the first node).
    A locator (``_locate_on_face``, an analytic wall's ``locate_parts``) supplies a, n,
    the weights and l. State row ``s`` of ``ws`` / ``on`` keeps the contact's history.
    Returns (normal work, friction loss)."""
    vel, force = nodes.vel, nodes.force
    radius, mu, inv_mt = particles.radius, particles.mu, particles.inv_mt
    dt = stepping.dt
    gamma = 0.5 / dt  # noqa: F841 (stick rate of the regularised friction law)
    i = particles.p0 + p
    r = radius[p]
    n0 = wall_nodes[row, 0]
    # normal force: the scene's law (x3dpd.physics.normal_laws)
    a_rate = 0.0
    if NORMAL_USES_RATE:
        # approach rate: the wall point's velocity minus the particle's, along n
        a_rate = -(nx * vel[i, 0] + ny * vel[i, 1] + nz * vel[i, 2])
        for e in range(n_w):
            nd = wall_nodes[row, e]
            a_rate += w[e] * (nx * vel[nd, 0] + ny * vel[nd, 1] + nz * vel[nd, 2])
        if lever:
            a_rate += (nx * (vel[n0, 4] * lz - vel[n0, 5] * ly)
                       + ny * (vel[n0, 5] * lx - vel[n0, 3] * lz)
                       + nz * (vel[n0, 3] * ly - vel[n0, 4] * lx))
    fn = NORMAL_WALL_FORCE(a, a_old, a_rate, p, particles, ws, s, S_H, N_MAXWELL)
    fn, dw = _record_normal(ws, on, s, a, a_old, fn, fn_old)
    lost = 0.0
    fx = fn * nx
    fy = fn * ny
    fz = fn * nz
    if HAS_FRICTION:
        # relative velocity of the particle's contact point (at -R n) and the wall point
        rcx = -r * nx
        rcy = -r * ny
        rcz = -r * nz
        wx = vel[i, 3]
        wy = vel[i, 4]
        wz = vel[i, 5]
        vrx = vel[i, 0] + wy * rcz - wz * rcy
        vry = vel[i, 1] + wz * rcx - wx * rcz
        vrz = vel[i, 2] + wx * rcy - wy * rcx
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
        ftx, fty, ftz, lost = _friction(vrx, vry, vrz, nx, ny, nz, fn, mu[p],
                                        1.0 / inv_mt[p], dt, gamma, ws, s)
        fx += ftx
        fy += fty
        fz += ftz
        force[i, 3] += rcy * ftz - rcz * fty
        force[i, 4] += rcz * ftx - rcx * ftz
        force[i, 5] += rcx * fty - rcy * ftx
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
    return dw, lost


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
    returns the work 1/2 F_old (a - a_old) of an open contact's last step."""
    dw = 0.0
    if fn_old != 0.0 or a_old > 0.0:
        dw = 0.5 * fn_old * (a - a_old)
        for c in range(S_FT, ws.shape[1]):
            ws[s, c] = 0.0
    ws[s, S_A] = 0.0
    ws[s, S_FN] = 0.0
    on[s] = 0
    return dw


@step_kernel
def _wall_contacts(nodes, particles, faces, walls, stepping, w, busy):
    """Particle-wall contact forces on the triangulated walls (report Figure 40): the face
    locator (x3dpd.geometry.faces) then the shared contact response ``_wall_response``. ``w``
    is a 3-element scratch array, ``busy`` an int scratch of the list's capacity. Returns a
    status bit."""
    x = nodes.x
    p0, radius = particles.p0, particles.radius
    wl_p, wl_f, ws, wl_on, nw = walls.first, walls.second, walls.state, walls.on, walls.count[0]
    face_n, face_d, face_ptr, face_tris, tri_nodes = (faces.normal, faces.offset, faces.tri_ptr,
                                                      faces.tris, faces.tri_nodes)
    ledger, pen_limit = stepping.ledger, stepping.pen_limit
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    # pass 1, tight: candidates within reach of their face's plane now or at the last step
    nbusy = 0
    for s in range(nw):
        p = np.uint64(wl_p[s])   # unsigned indices: no negative-index wrap-around code
        f = np.uint64(wl_f[s])
        i = np.uint64(p0 + wl_p[s])
        d = face_n[f, 0] * x[i, 0] + face_n[f, 1] * x[i, 1] + face_n[f, 2] * x[i, 2] - face_d[f]
        if d < radius[p] or wl_on[s] != 0:
            busy[nbusy] = s
            nbusy += 1
    # pass 2: the contact law on those
    for q in range(nbusy):
        s = np.uint64(busy[q])
        p = np.uint64(wl_p[s])
        f = np.uint64(wl_f[s])
        i = np.uint64(p0 + wl_p[s])
        nx = face_n[f, 0]
        ny = face_n[f, 1]
        nz = face_n[f, 2]
        r = radius[p]
        d = nx * x[i, 0] + ny * x[i, 1] + nz * x[i, 2] - face_d[f]
        a = r - d
        a_old = ws[s, S_A]
        fn_old = ws[s, S_FN]
        t = -1
        if a > 0.0:
            t = _locate_on_face(x[i, 0] - d * nx, x[i, 1] - d * ny, x[i, 2] - d * nz, nx, ny, nz,
                                f, x, face_ptr, face_tris, tri_nodes, r, w)
        if t < 0:
            # no contact (or the particle left the face): close any open contact
            w_normal += _close_contact(ws, wl_on, s, a, a_old, fn_old)
            continue
        if a > pen_limit * r:
            status |= _penetration(stepping.diag, p, f, a, r)
        dw, lost = _wall_response(nodes, particles, stepping, ws, wl_on, s, p, a, a_old, fn_old,
                                  nx, ny, nz, tri_nodes, t, w, 3, False, 0.0, 0.0, 0.0)
        w_normal += dw
        w_fric += lost
    # the ledger is touched once per call, not per contact (no dependency through memory)
    ledger[L_WN] += w_normal
    ledger[L_DFRIC] += w_fric
    return status


@step_kernel
def _shape_contacts(nodes, particles, shapes, stepping, w, n_faces):
    """Particle contacts with the analytic walls (x3dpd.geometry.shapes): for every (particle,
    wall) pair of ``shapes``, the wall's locator (``SHAPE_LOCATE``: the shape's
    ``locate_parts``, chosen by its kind) gives each part's overlap, normal, node weights and
    lever; a touching part goes to the shared contact response ``_wall_response`` (reaction on
    the wall's two nodes, moment to the first). Each part is a state row (``shapes.row``); a
    penetration names the entity as ``n_faces + shapes.entity[wall] + part``. Returns a
    status bit."""
    x = nodes.x
    p0, radius = particles.p0, particles.radius
    cs, con, loc = shapes.state, shapes.on, shapes.located
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    for k in range(shapes.particle.shape[0]):
        p = shapes.particle[k]
        c = shapes.wall[k]
        i = p0 + p
        r = radius[p]
        SHAPE_LOCATE(shapes.kind[c], x, shapes.nodes[c, 0], shapes.nodes[c, 1], shapes.params,
                     c, x[i, 0], x[i, 1], x[i, 2], r, loc)
        for part in range(shapes.parts[c]):
            s = shapes.row[k] + part
            valid = loc[part, 0] != 0.0
            a = loc[part, 1] if valid else 0.0
            a_old = cs[s, S_A]
            fn_old = cs[s, S_FN]
            if not valid or a <= 0.0:
                if con[s] != 0 or fn_old != 0.0 or a_old > 0.0:
                    w_normal += _close_contact(cs, con, s, a, a_old, fn_old)
                continue
            if a > stepping.pen_limit * r:
                status |= _penetration(stepping.diag, p, n_faces + shapes.entity[c] + part, a, r)
            xi = loc[part, 5]
            w[0] = 1.0 - xi
            w[1] = xi
            dw, lost = _wall_response(nodes, particles, stepping, cs, con, s, p, a, a_old, fn_old,
                                      loc[part, 2], loc[part, 3], loc[part, 4], shapes.nodes, c,
                                      w, 2, True, loc[part, 6], loc[part, 7], loc[part, 8])
            w_normal += dw
            w_fric += lost
    stepping.ledger[L_WN] += w_normal
    stepping.ledger[L_DFRIC] += w_fric
    return status


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
                   dw_, lost_, rmin_):
    """Pass 2 of the pair contacts: the contact response of every busy candidate ``busy[:nbusy]``
    (report Figure 41), written into columns (one entry per busy candidate; names in
    x3dpd.solver.contact_lists.PAIR_COLUMNS) for pass 3 to apply.

    The normal law is the scene's (x3dpd.physics.normal_laws), with n = (x_j - x_i)/|x_j - x_i|
    and approach a = R_i + R_j - |x_j - x_i|; friction with spin acts at the contact points
    x_i + R_i n and x_j - R_j n. A candidate that no longer touches (a <= 0) gets F = 0; pass 3
    closes it as a wall contact is closed (``_close_contact``). Nothing here writes the contact state or the
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
        # work of the normal force over the step, 1/2 (F_old + F) (a - a_old) (pass 3 books it
        # for touching candidates only)
        dw = 0.5 * (fn_old + fn) * (a - a_old)
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
            ftx, fty, ftz, lost = _friction_force(vjx - vix, vjy - viy, vjz - viz, nx, ny, nz,
                                                  fn, pair_c[ki, kj, 2], pair_c[ki, kj, 1], dt,
                                                  gamma, ps[s, S_FT], ps[s, S_FT + 1],
                                                  ps[s, S_FT + 2])
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
    loss). Its own function, like the filter: inlined into the step loop, the column pointers
    were reloaded from the stack at every contact (measured with tools/bench/profile_jit.py)."""
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    fx_, fy_, fz_ = c[C_FX], c[C_FY], c[C_FZ]
    tix_, tiy_, tiz_, tjx_, tjy_, tjz_ = c[C_TIX], c[C_TIY], c[C_TIZ], c[C_TJX], c[C_TJY], c[C_TJZ]
    a_, fn_, dw_, lost_, rmin_ = c[C_A], c[C_FN], c[C_DW], c[C_LOST], c[C_RMIN]
    ftx_, fty_, ftz_ = c[C_FTX], c[C_FTY], c[C_FTZ]
    for q in range(nbusy):
        s = np.uint64(busy[q])
        a = a_[q]
        if a <= 0.0:
            w_normal += _close_contact(ps, pl_on, s, a, ps[s, S_A], ps[s, S_FN])
            continue
        rmin = rmin_[q]
        if a > pen_limit * rmin:
            status |= _penetration(diag, pl_i[s], -1 - pl_j[s], a, rmin)
        ps[s, S_A] = a
        ps[s, S_FN] = fn_[q]
        if N_MAXWELL > 0:
            for k in range(2 * N_MAXWELL):
                ps[s, S_H + k] = hist[q, k]
        pl_on[s] = 1
        w_normal += dw_[q]
        i = np.uint64(p0 + pl_i[s])
        j = np.uint64(p0 + pl_j[s])
        fx = fx_[q]
        fy = fy_[q]
        fz = fz_[q]
        if HAS_FRICTION:
            w_fric += lost_[q]
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
    return status, w_normal, w_fric


@step_kernel
def _pair_contacts(nodes, particles, pairs, stepping, busy):
    """Particle-particle contact forces (report Figure 41) in three passes: the candidates that
    touch (``_pair_filter``), their contact response in columns (``_pair_response``,
    vectorized), and the contact states, the forces on both particles and the ledger in list
    order (``_pair_apply``). State column S_FT holds the friction force on particle j;
    histories: N_MAXWELL terms of i, then N_MAXWELL terms of j. ``busy`` is an int scratch of
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
    if nbusy == 0:
        # nothing touches (a falling or sparse scene): skip the calls and their arguments
        return OK
    # pass 2: the contact response, into columns
    _pair_response(nbusy, busy, c[C_DX], c[C_DY], c[C_DZ], vel, particles, pl_i, pl_j, ps,
                   hist, stepping.dt,
                   c[C_FX], c[C_FY], c[C_FZ], c[C_TIX], c[C_TIY], c[C_TIZ], c[C_TJX], c[C_TJY],
                   c[C_TJZ], c[C_A], c[C_FN], c[C_FTX], c[C_FTY], c[C_FTZ], c[C_DW], c[C_LOST],
                   c[C_RMIN])
    # pass 3: states, forces and the ledger
    status, w_normal, w_fric = _pair_apply(nbusy, busy, p0, pl_i, pl_j, ps, pl_on, nodes.force,
                                           stepping.pen_limit, stepping.diag, c, hist)
    ledger[L_WN] += w_normal
    ledger[L_DFRIC] += w_fric
    return status


@kernel
def _energies(nodes, springs, particles, walls, pairs, shapes, dt, out):
    """out[0:6] = KE_trans, KE_rot, U_grav, U_spring, U_contact, S (Verlet correction)."""
    x, x0, vel, force = nodes.x, nodes.x0, nodes.vel, nodes.force
    kin_mass, kin_inertia, inv_m = nodes.kin_mass, nodes.kin_inertia, nodes.inv_m
    ke_t = 0.0
    ke_r = 0.0
    shadow = 0.0
    for i in range(x.shape[0]):
        m = kin_mass[i]
        if m != 0.0:
            ke_t += 0.5 * m * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        for d in range(3):
            ke_r += 0.5 * kin_inertia[i, d] * vel[i, 3 + d] ** 2
        for d in range(6):
            shadow += force[i, d] ** 2 * inv_m[i, d]
    out[0] = ke_t
    out[1] = ke_r
    out[2] = _gravity_energy(nodes.mass, x, x0, nodes.g) if HAS_GRAVITY else 0.0
    out[3] = _spring_energy(x, x0, springs.nodes, springs.k) if HAS_SPRINGS else 0.0
    out[4] = (_contact_energy(particles, walls, pairs, shapes)
              if (HAS_WALLS or HAS_PAIRS or HAS_SHAPES) else 0.0)
    out[5] = dt * dt / 8.0 * shadow


@kernel
def _contact_energy(particles, walls, pairs, shapes):
    """Elastic energy stored in the open contacts, by the normal law's ``stored_energy``."""
    u = 0.0
    ws = walls.state
    for s in range(walls.count[0]):
        if ws[s, S_A] > 0.0:
            k = particles.law_wall[walls.first[s], 0]
            u += NORMAL_STORED_ENERGY(ws[s, S_FN], ws[s, S_A], k)
    ps = pairs.state
    kind = particles.kind
    for s in range(pairs.count[0]):
        if ps[s, S_A] > 0.0:
            k = particles.law_pair[kind[pairs.first[s]], kind[pairs.second[s]], 0]
            u += NORMAL_STORED_ENERGY(ps[s, S_FN], ps[s, S_A], k)
    if HAS_SHAPES:
        cs = shapes.state
        for s in range(cs.shape[0]):
            if cs[s, S_A] > 0.0:
                k = particles.law_wall[shapes.row_particle[s], 0]
                u += NORMAL_STORED_ENERGY(cs[s, S_FN], cs[s, S_A], k)
    return u


@kernel
def _forces(t, nodes, loads, springs, rigid, particles, faces, walls, pairs, shapes, stepping):
    """All forces at time t from x and the (half-step) velocities into ``nodes.force``; updates
    the ledger. Returns the status bits (x3dpd.solver.bundles.Status)."""
    ff = nodes.force.reshape(-1)
    for k in range(ff.shape[0]):
        ff[k] = 0.0
    if HAS_GRAVITY:
        _gravity_forces(nodes.mass, nodes.g, nodes.force)
    return _force_terms(t, nodes, loads, springs, rigid, particles, faces, walls, pairs,
                        shapes, stepping)


@step_kernel
def _force_terms(t, nodes, loads, springs, rigid, particles, faces, walls, pairs, shapes,
                 stepping):
    """Add every force but the body forces (which ``nodes.force`` holds on entry) at time t."""
    x, vel, force = nodes.x, nodes.vel, nodes.force
    dt, ledger = stepping.dt, stepping.ledger
    status = OK
    if HAS_SPRINGS:
        ledger[L_DDAMP] += _spring_forces(x, nodes.x0, vel, springs.nodes, springs.k, springs.c,
                                          force, springs.fd_prev, dt)
    if HAS_EXTERNAL:
        ext_table, frow_prev = loads.table, loads.row_prev
        wext = 0.0
        # built-in forces act on a few DOFs: work row by row (exact even if rows share a DOF)
        for r in range(ext_table.shape[0]):
            i = int(ext_table[r, 1])
            d = int(ext_table[r, 2])
            fe = _force_value(t, ext_table, r)
            force[i, d] += fe
            wext += 0.5 * (frow_prev[r] + fe) * vel[i, d] * dt
            frow_prev[r] = fe
        if HAS_USER_FORCE or HAS_PYTHON_FORCE:
            # user forces may touch any DOF
            fext, fext_prev = loads.user, loads.user_prev
            fe_flat = fext.reshape(-1)
            for k in range(fe_flat.shape[0]):
                fe_flat[k] = 0.0
            if HAS_USER_FORCE:
                USER_FORCE(t, x, vel, fext)
            if HAS_PYTHON_FORCE:
                for k in range(fe_flat.shape[0]):
                    fe_flat[k] += loads.python.reshape(-1)[k]
            for i in range(fext.shape[0]):
                for d in range(6):
                    fe = fext[i, d]
                    if fe != 0.0 or fext_prev[i, d] != 0.0:
                        wext += 0.5 * (fext_prev[i, d] + fe) * vel[i, d] * dt
                        force[i, d] += fe
                        fext_prev[i, d] = fe
        ledger[L_WEXT] += wext
    if HAS_WALLS:
        if HAS_WALLS_TRANSLATE:
            _face_offsets(x, faces.tri_nodes, faces.first_tri, faces.normal, faces.offset)
        else:
            _face_planes(x, faces.tri_nodes, faces.tri_sign, faces.first_tri, faces.normal,
                         faces.offset)
        # the rebuild's scratch is free while forces run
        status |= _wall_contacts(nodes, particles, faces, walls, stepping,
                                 stepping.small[6:9], walls.first_new)
    if HAS_SHAPES:
        status |= _shape_contacts(nodes, particles, shapes, stepping, stepping.small[6:9],
                                  faces.offset.shape[0])
    if HAS_PAIRS:
        status |= _pair_contacts(nodes, particles, pairs, stepping, pairs.first_new)
    if HAS_RIGID:
        _gather_slaves(x, force, rigid.master, rigid.ptr, rigid.slaves, HAS_RIGID_ROTATION)
    return status


@step_kernel
def _rebuild_lists(nodes, particles, faces, walls, pairs, skin):
    """Rebuild the candidate lists of walls and pairs within ``skin``, carrying the histories of
    lasting contacts over. Returns REALLOC_WALLS / REALLOC_PAIRS when a list is full (the
    caller grows it and calls again), else OK."""
    x, p0, radius = nodes.x, particles.p0, particles.radius
    if HAS_WALLS:
        m = _build_wall_list(x, p0, radius, particles.cavity, faces.cav_ptr, faces.cav_faces,
                             faces.normal, faces.offset, faces.tri_ptr, faces.tris,
                             faces.tri_nodes, skin, walls.first_new, walls.second_new,
                             walls.approach_new)
        if m < 0:
            return REALLOC_WALLS
        _adopt_new_list(walls, m)
    if HAS_PAIRS:
        npart = radius.shape[0]
        xp = x[p0:p0 + npart]
        m = _find_pairs(xp, radius, particles.cavity, skin, pairs.first_new, pairs.second_new)
        if m < 0:
            return REALLOC_PAIRS
        _pair_approach(x, p0, radius, pairs.first_new, pairs.second_new, m, pairs.approach_new)
        _adopt_new_list(pairs, m)
    return OK


@step_kernel
def _adopt_new_list(lst, m):
    """Make the rebuilt list (``*_new``, ``m`` entries) the live one, with carried histories."""
    _merge_states(lst.first, lst.second, lst.state, lst.count[0], lst.first_new,
                  lst.second_new, lst.state_new, m, lst.approach_new)
    for k in range(m):
        lst.first[k] = lst.first_new[k]
        lst.second[k] = lst.second_new[k]
        for c in range(lst.state.shape[1]):
            lst.state[k, c] = lst.state_new[k, c]
    _active_flags(lst.state, m, lst.on)
    lst.count[0] = m


@loop_kernel
def advance(nsteps, step0, t_start, nodes, loads, springs, rigid, particles, faces, walls, pairs,
            shapes, stepping, output):
    """Advance up to ``nsteps`` steps from step index ``step0`` (time t_start + step0 dt).

    ``stepping.nbr`` = [displacement bound of particles, of wall nodes, rebuild count, list
    state (-1: rebuild now), last largest particle speed, last largest wall-node speed, unused];
    ``stepping.small`` is 9 floats of scratch (this loop allocates nothing: see
    x3dpd._jit.loop_kernel). Every ``output.itrac``-th step appends one row to the output
    buffers. Returns (status, steps done, rows written); the run stops at the first non-zero
    status or a full output buffer.
    """
    x, x0, vel, force = nodes.x, nodes.x0, nodes.vel, nodes.force
    kin_mass, kin_inertia, inv_m, fgrav = (nodes.kin_mass, nodes.kin_inertia, nodes.inv_m,
                                           nodes.fgrav)
    motion_table, motion_prev = loads.motion, loads.motion_prev
    rig_master, rig_ptr, rig_slaves, rig_r0, rot = (rigid.master, rigid.ptr, rigid.slaves,
                                                    rigid.r0, rigid.rot)
    rig_inv_ib, rig_ib, rig_free_rot = rigid.inv_ib, rigid.ib, rigid.free_rot
    p0 = particles.p0
    dt, skin, ledger, nbr, diag = (stepping.dt, stepping.skin, stepping.ledger, stepping.nbr,
                                   stepping.diag)
    itrac, trace_nodes, out_t, out_data, out_energy = (output.itrac, output.trace_nodes,
                                                       output.times, output.data, output.energy)
    n = x.shape[0]
    rows = 0
    h = 0.5 * dt
    en = stepping.small[0:6]   # energies at an output step
    vf = vel.reshape(-1)
    ff = force.reshape(-1)
    imf = inv_m.reshape(-1)
    fgf = fgrav.reshape(-1)   # body forces m g (zero without gravity): what force starts from
    synced = True   # vel holds full-step velocities and force the forces of this step
    out_in = itrac - step0 % itrac   # steps to the next trace output
    for it in range(nsteps):
        step = step0 + it
        # ---- neighbour lists: rebuild at a step boundary when the skin may be used up
        if HAS_WALLS or HAS_PAIRS:
            # bound of the displacements at the force evaluation of this step: what has
            # accumulated since the last build plus this step's drift (2 x the last step's, to
            # allow for acceleration)
            dp = nbr[0] + 2.0 * dt * nbr[4]
            dw = nbr[1] + 2.0 * dt * nbr[5]
            if nbr[3] < 0.0 or 2.0 * dp > skin or dp + dw > skin:
                full = _rebuild_lists(nodes, particles, faces, walls, pairs, skin)
                if full != OK:
                    return full, it, rows
                nbr[0] = 0.0
                nbr[1] = 0.0
                nbr[2] += 1.0
                nbr[3] = 1.0
        # ---- first half kick (unless the last step's pass already did it) and drift
        if synced:
            if HAS_RIGID_ROTATION:
                _rigid_angular_kick(vel, force, rig_master, rot, rig_inv_ib, rig_ib,
                                    rig_free_rot, h, False)
            for k in range(vf.shape[0]):
                vf[k] += h * ff[k] * imf[k]
                ff[k] = fgf[k]
        for i in range(p0):
            x[i, 0] += dt * vel[i, 0]
            x[i, 1] += dt * vel[i, 1]
            x[i, 2] += dt * vel[i, 2]
        vmax2 = 0.0
        for i in range(p0, n):
            x[i, 0] += dt * vel[i, 0]
            x[i, 1] += dt * vel[i, 1]
            x[i, 2] += dt * vel[i, 2]
            if HAS_WALLS or HAS_PAIRS:
                v2 = vel[i, 0] * vel[i, 0] + vel[i, 1] * vel[i, 1] + vel[i, 2] * vel[i, 2]
                vmax2 = max(vmax2, v2)
        if HAS_RIGID_ROTATION:
            _rotate(rot, rig_master, vel, dt)
        t = t_start + (step + 1) * dt
        if HAS_MOTION:
            _apply_motion_step(t_start + step * dt, t, motion_table, x0, x, vel)
        vwall = 0.0
        if HAS_RIGID:
            vwall = _update_slaves(x, vel, rig_master, rig_ptr, rig_slaves, rig_r0, rot, True,
                                   HAS_RIGID_ROTATION)
        nbr[4] = math.sqrt(vmax2)
        nbr[5] = vwall
        nbr[0] += dt * nbr[4]
        nbr[1] += dt * vwall
        # ---- forces at the new positions (``force`` holds the body forces m g: the kick pass
        # reset it to them)
        st = _force_terms(t, nodes, loads, springs, rigid, particles, faces, walls,
                                   pairs, shapes, stepping)
        if HAS_MOTION:
            # work of the motion's actuators (x3dpd.physics.motion._motion_work)
            ledger[L_WEXT] += _motion_work(t_start + step * dt, t, motion_table, kin_mass,
                                           kin_inertia, force, motion_prev)
        # ---- second half kick. Full-step velocities are needed only at outputs and at the end
        # of the call; elsewhere this half kick and the next step's first one go in one pass
        # over memory, computed as (v + h a) + h a so that the rounding -- and so every
        # trajectory -- is bit for bit the same whichever steps end a call.
        out_in -= 1
        synced = st != OK or it == nsteps - 1 or out_in == 0
        if not synced:
            if HAS_RIGID_ROTATION:
                # the second half kick of this step (implicit), the first of the next
                _rigid_angular_kick(vel, force, rig_master, rot, rig_inv_ib, rig_ib,
                                    rig_free_rot, h, True)
                _rigid_angular_kick(vel, force, rig_master, rot, rig_inv_ib, rig_ib,
                                    rig_free_rot, h, False)
            for k in range(vf.shape[0]):
                vf[k] = (vf[k] + h * ff[k] * imf[k]) + h * ff[k] * imf[k]
                ff[k] = fgf[k]
            continue
        for k in range(vf.shape[0]):
            vf[k] += h * ff[k] * imf[k]
        if HAS_RIGID_ROTATION:
            _rigid_angular_kick(vel, force, rig_master, rot, rig_inv_ib, rig_ib, rig_free_rot, h,
                                True)
        if HAS_MOTION:
            _apply_motion(t, motion_table, x0, x, vel)
        if HAS_RIGID:
            _update_slaves(x, vel, rig_master, rig_ptr, rig_slaves, rig_r0, rot, False,
                           HAS_RIGID_ROTATION)
        if st != OK:
            diag[4] = t
            diag[5] = step + 1
            return st, it + 1, rows
        # ---- output
        if out_in == 0:
            out_in = itrac
            for k in range(trace_nodes.shape[0]):
                i = trace_nodes[k]
                for d in range(3):
                    out_data[rows, k, d] = x[i, d]
                for d in range(6):
                    out_data[rows, k, 3 + d] = vel[i, d]
            out_t[rows] = t
            _energies(nodes, springs, particles, walls, pairs, shapes, dt, en)
            _ledger_row(t, en, ledger, output.e_ref, out_energy[rows])
            rows += 1
            # non-finite state is caught at output steps (cheap), before it reaches the trace
            bad = False
            for k in range(trace_nodes.shape[0]):
                for d in range(9):
                    if not math.isfinite(out_data[rows - 1, k, d]):
                        bad = True
            if bad or not math.isfinite(out_energy[rows - 1, 11]):
                diag[4] = t
                diag[5] = step + 1
                return NONFINITE, it + 1, rows - 1
            if rows >= out_t.shape[0]:
                return OK, it + 1, rows
    return OK, nsteps, rows


@loop_kernel
def advance_packed(nsteps, step0, t_start, packed):
    """``advance`` with its bundles as plain tuples in its argument order
    (x3dpd.solver.bundles.pack): numba checks the types of plain tuples of arrays in C, but of
    named tuples in Python, which cost ~0.1 ms a call -- as much as a hundred steps of a small
    scene. The named tuples are rebuilt here, in compiled code, at no cost."""
    (nodes, loads, springs, rigid, particles, faces, walls, pairs, shapes, stepping,
     output) = packed
    return advance(nsteps, step0, t_start, Nodes(*nodes), Loads(*loads), Springs(*springs),
                   RigidBodies(*rigid), Particles(*particles), Faces(*faces),
                   ContactList(*walls), ContactList(*pairs), Shapes(*shapes),
                   Stepping(*stepping), Output(*output))


@kernel
def _ledger_row(t, en, ledger, e_ref, row):
    """row = t, KE_t, KE_r, U_g, U_s, U_c, D_visc, D_fric, D_damp, W_ext, E_total, residual.

    D_visc = W_N - U_c when contacts are viscoelastic or damped (absorbed minus still stored); elastic
    contacts dissipate nothing by definition, so their integration error shows in the residual.
    """
    row[0] = t
    for k in range(5):
        row[1 + k] = en[k]
    if HAS_VISCOELASTIC or NORMAL_DAMPED:
        row[6] = ledger[L_WN] - en[4]
    else:
        row[6] = 0.0
    row[7] = ledger[L_DFRIC]
    row[8] = ledger[L_DDAMP]
    row[9] = ledger[L_WEXT]
    e_total = en[0] + en[1] + en[2] + en[3] + en[4]
    row[10] = e_total
    row[11] = (e_total - en[5]) - e_ref + row[6] + row[7] + row[8] - row[9]
