"""Step-loop template, part: particle contacts with walls (x3dpd.solver.variants).

The triangulated walls (``_wall_contacts``: the face locator of x3dpd.geometry.faces) and the
analytic walls (``_shape_contacts``: each shape's locator, x3dpd.geometry.shapes), both
answered by the shared contact response ``_wall_response``. Generated per variant beside the
loop, with the variant's constants (``_template_variant``).
"""

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.geometry.faces import _locate_on_face
from x3dpd.solver._template_contact import (HAS_TORQUE, L_DFRIC, L_DROLL, L_WN, OK,
                                            _close_contact, _penetration, _wall_closing_work,
                                            _wall_response)
from x3dpd.solver._template_variant import (HAS_ONE_WALL_KIND, HAS_ROLLING, SHAPE_CLEAR,
                                            SHAPE_LOCATE, TANGENTIAL_STORES)
from x3dpd.solver._template_wall_columns import (_wall_apply, _wall_columns_in,
                                                 _wall_columns_out, _wall_busy, _wall_gather,
                                                 _wall_response_columns)
from x3dpd.solver.contact_lists import COLUMN_ROW, PAIR_BLOCK, S_A, S_FN

@kernel
def _no_shape_locate(kind, x, na, nb, params, c, px, py, pz, r, out):
    """Stand-in for SHAPE_LOCATE in variants without analytic walls (never called)."""
    return


@kernel
def _no_shape_clear(kind, x, na, nb, params, c, px, py, pz, r):
    """Stand-in for SHAPE_CLEAR in variants without analytic walls (never called)."""
    return False


if SHAPE_LOCATE is None:
    SHAPE_LOCATE = _no_shape_locate
if SHAPE_CLEAR is None:
    SHAPE_CLEAR = _no_shape_clear


# Over 80 lines: a compiled kernel: face, edge and vertex tests share one triangle's projections.
@step_kernel
def _wall_contacts(nodes, particles, faces, walls, stepping, w, busy):
    """Particle-wall contact forces on the triangulated walls (report Figure 40): the face
    locator (x3dpd.geometry.faces) then the shared contact response ``_wall_response``, one
    contact at a time -- or, when every particle meets the walls alike, in columns with a
    vectorized response (``_wall_contacts_in_columns``). ``w`` is a 3-element scratch array,
    ``busy`` an int scratch of the list's capacity. Returns a status bit."""
    if HAS_ONE_WALL_KIND:
        return _wall_contacts_in_columns(nodes, particles, faces, walls, stepping, w, busy)
    x = nodes.x
    p0, radius = particles.p0, particles.radius
    wl_p, wl_f, ws, wl_on, nw = walls.first, walls.second, walls.state, walls.on, walls.count[0]
    face_n, face_d, face_ptr, face_tris, tri_nodes = (faces.normal, faces.offset, faces.tri_ptr,
                                                      faces.tris, faces.tri_nodes)
    ledger, pen_limit = stepping.ledger, stepping.pen_limit
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    # pass 1, tight: candidates within reach of their face's plane now or at the last step
    nbusy = _wall_busy(0, nw, x, p0, radius, wl_p, wl_f, wl_on, face_n, face_d, busy)
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
            if HAS_TORQUE and wl_on[s] != 0:
                # its friction's and rolling's work on this last step, at the wall point under
                # the particle (off the face: the face's first triangle's centroid)
                if a <= 0.0:
                    t = _locate_on_face(x[i, 0] - d * nx, x[i, 1] - d * ny, x[i, 2] - d * nz,
                                        nx, ny, nz, f, x, face_ptr, face_tris, tri_nodes, r, w)
                if t < 0:
                    t = face_tris[face_ptr[f]]
                    w[0] = 1.0 / 3.0
                    w[1] = 1.0 / 3.0
                    w[2] = 1.0 / 3.0
                lost, rolled = _wall_closing_work(nodes, particles, stepping, ws, s, p, nx, ny,
                                                  nz, tri_nodes, t, w, 3, False, 0.0, 0.0, 0.0)
                w_fric += lost
                w_roll += rolled
            dw, released = _close_contact(ws, wl_on, s, a, a_old, fn_old)
            w_normal += dw
            if TANGENTIAL_STORES:
                w_normal -= released
                w_fric += released
            continue
        if a > pen_limit * r:
            status |= _penetration(stepping.diag, p, f, a, r)
        dw, lost, rolled = _wall_response(nodes, particles, stepping, ws, wl_on, s, p, a, a_old,
                                          fn_old, nx, ny, nz, tri_nodes, t, w, 3, False, 0.0,
                                          0.0, 0.0)
        w_normal += dw
        w_fric += lost
        w_roll += rolled
    # the ledger is touched once per call, not per contact (no dependency through memory)
    ledger[L_WN] += w_normal
    ledger[L_DFRIC] += w_fric
    if HAS_ROLLING:
        ledger[L_DROLL] += w_roll
    return status


@step_kernel
def _wall_contacts_in_columns(nodes, particles, faces, walls, stepping, w, busy):
    """``_wall_contacts`` in three passes over the list block by block (PAIR_BLOCK candidates,
    ``_template_wall_columns``): gather and locate, the vectorized response, the apply pass in
    list order (which closes the contacts that ended). The ledger's sums chain through the
    blocks in that order."""
    nw = walls.count[0]
    if nw == 0:
        return OK
    c = walls.columns
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    for lo in range(0, nw, PAIR_BLOCK):
        hi = min(nw, lo + PAIR_BLOCK)
        nb = _wall_busy(lo, hi, nodes.x, particles.p0, particles.radius, walls.first,
                        walls.second, walls.on, faces.normal, faces.offset, busy)
        if nb == 0:
            continue
        _wall_gather(nb, nodes.x, nodes.vel, particles.p0, particles.radius, walls.first,
                     walls.second, walls.state, faces.normal, faces.offset, faces.tri_ptr,
                     faces.tris, faces.tri_nodes, faces.tri_frame, busy, c, walls.history, w)
        rows = c.reshape((c.shape[0] // COLUMN_ROW, COLUMN_ROW))  # a view; not when all idle
        _wall_response_columns(nb, particles, walls.history, stepping.dt, stepping.history_dt,
                               _wall_columns_in(rows), _wall_columns_out(rows))
        status, w_normal, w_fric, w_roll = _wall_apply(nb, busy, nodes, particles, faces, walls,
                                                       stepping, w, c, status, w_normal, w_fric,
                                                       w_roll)
    stepping.ledger[L_WN] += w_normal
    stepping.ledger[L_DFRIC] += w_fric
    if HAS_ROLLING:
        stepping.ledger[L_DROLL] += w_roll
    return status


@step_kernel
def _shape_contacts(nodes, particles, shapes, stepping, w, n_faces):
    """Particle contacts with the analytic walls (x3dpd.geometry.shapes): for every (particle,
    wall) pair of ``shapes``, the wall's locator (``SHAPE_LOCATE``: the shape's
    ``locate_parts``, chosen by its kind) gives each part's overlap, normal, node weights and
    lever; a touching part goes to the shared contact response ``_wall_response`` (reaction on
    the wall's two nodes, moment to the first). Each part is a state row (``shapes.row``); a
    penetration names the entity as ``n_faces + shapes.entity[wall] + part``. A pair its
    shape's ``clear_of`` (``SHAPE_CLEAR``) finds clear, whose parts' contacts are all closed,
    is skipped: the locator would find no part touching and the response do nothing (the same
    numbers, for a fraction of the work: a drilled plate's spheres in flight). Returns a
    status bit."""
    x = nodes.x
    p0, radius = particles.p0, particles.radius
    cs, con, loc = shapes.state, shapes.on, shapes.located
    status = OK
    w_normal = 0.0
    w_fric = 0.0
    w_roll = 0.0
    for k in range(shapes.particle.shape[0]):
        p = shapes.particle[k]
        c = shapes.wall[k]
        i = p0 + p
        r = radius[p]
        if SHAPE_CLEAR(shapes.kind[c], x, shapes.nodes[c, 0], shapes.nodes[c, 1], shapes.params,
                       c, x[i, 0], x[i, 1], x[i, 2], r):
            closed = True
            for part in range(shapes.parts[c]):
                s = shapes.row[k] + part
                if con[s] != 0 or cs[s, S_FN] != 0.0 or cs[s, S_A] > 0.0:
                    closed = False
            if closed:
                continue
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
                    if HAS_TORQUE and con[s] != 0:
                        # its friction's and rolling's work on this last step
                        xi = loc[part, 5]
                        w[0] = 1.0 - xi
                        w[1] = xi
                        lost, rolled = _wall_closing_work(
                            nodes, particles, stepping, cs, s, p, loc[part, 2], loc[part, 3],
                            loc[part, 4], shapes.nodes, c, w, 2, True, loc[part, 6],
                            loc[part, 7], loc[part, 8])
                        w_fric += lost
                        w_roll += rolled
                    dw, released = _close_contact(cs, con, s, a, a_old, fn_old)
                    w_normal += dw
                    if TANGENTIAL_STORES:
                        w_normal -= released
                        w_fric += released
                continue
            if a > stepping.pen_limit * r:
                status |= _penetration(stepping.diag, p, n_faces + shapes.entity[c] + part, a, r)
            xi = loc[part, 5]
            w[0] = 1.0 - xi
            w[1] = xi
            dw, lost, rolled = _wall_response(nodes, particles, stepping, cs, con, s, p, a, a_old,
                                              fn_old, loc[part, 2], loc[part, 3], loc[part, 4],
                                              shapes.nodes, c, w, 2, True, loc[part, 6],
                                              loc[part, 7], loc[part, 8])
            w_normal += dw
            w_fric += lost
            w_roll += rolled
    stepping.ledger[L_WN] += w_normal
    stepping.ledger[L_DFRIC] += w_fric
    if HAS_ROLLING:
        stepping.ledger[L_DROLL] += w_roll
    return status
