"""Compiled geometry of rigid wall faces (report Section 7.3, Figure 40), used by the step loop.

A *face* is a planar group of master triangles (one side of a cavity); its plane is kept as a
unit inward normal n_f and an offset d_f = n_f . p (length), so the signed distance of a point x
from it is n_f . x - d_f. Particles are tested against faces first (one dot product) and only
near a face against its triangles, with barycentric weights that carry the contact reaction to
the triangle's three nodes. All functions take arrays and scalars only.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import kernel, step_kernel

__all__ = ["TRIANGLE_FRAME", "_build_wall_list", "_face_frames", "_face_offsets",
           "_face_planes", "_forget_frames", "_locate_on_face", "_locate_on_frames",
           "_triangle_frames"]

#: Values per triangle of :func:`_triangle_frames`: the gradients g_e (3 each) and offsets h_e
#: of the barycentric coordinates lambda_e = g_e . q - h_e, e = 0, 1, 2, and the heights H_e
#: over each edge: 3 x 3 + 3 + 3; then FRAME_FRESH, 1.0 when the frame is this step's
#: (:func:`_face_frames`).
TRIANGLE_FRAME = 16
FRAME_FRESH = 15


@step_kernel
def _edge_cross(x, p0, p1, p2):
    """(x1 - x0) x (x2 - x0) of triangle (p0, p1, p2), as three scalars: its normal times
    twice its area."""
    ax = x[p1, 0] - x[p0, 0]
    ay = x[p1, 1] - x[p0, 1]
    az = x[p1, 2] - x[p0, 2]
    bx = x[p2, 0] - x[p0, 0]
    by = x[p2, 1] - x[p0, 1]
    bz = x[p2, 2] - x[p0, 2]
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@step_kernel
def _twice_area(x, nx, ny, nz, p0, p1, p2):
    """Twice the signed area of triangle (p0, p1, p2) along the unit normal n:
    A = n . ((x1 - x0) x (x2 - x0))."""
    cx, cy, cz = _edge_cross(x, p0, p1, p2)
    return nx * cx + ny * cy + nz * cz


@step_kernel
def _clamped_weights(lam0, lam1, lam2, w):
    """Barycentric coordinates clamped to [0, 1] and scaled to sum 1, into ``w``: the weights
    of a triangle's nodes at the point nearest q within the edge tolerance."""
    lam0 = min(max(lam0, 0.0), 1.0)
    lam1 = min(max(lam1, 0.0), 1.0)
    lam2 = min(max(lam2, 0.0), 1.0)
    sw = lam0 + lam1 + lam2
    w[0] = lam0 / sw
    w[1] = lam1 / sw
    w[2] = lam2 / sw


@step_kernel
def _edge(e, p0, p1, p2):
    """The nodes (i, j) of edge e, the edge opposite node e: (1, 2), (2, 0), (0, 1)."""
    if e == 0:
        return p1, p2
    if e == 1:
        return p2, p0
    return p0, p1


@step_kernel
def _face_planes(x, tri_nodes, tri_sign, face_first_tri, face_n, face_d):
    """Unit inward normal n_f and offset d_f = n_f . p0 of every face from its first triangle."""
    for f in range(face_first_tri.shape[0]):
        t = face_first_tri[f]
        a = tri_nodes[t, 0]
        nx, ny, nz = _edge_cross(x, a, tri_nodes[t, 1], tri_nodes[t, 2])
        s = tri_sign[t] / math.sqrt(nx * nx + ny * ny + nz * nz)
        face_n[f, 0] = nx * s
        face_n[f, 1] = ny * s
        face_n[f, 2] = nz * s
        face_d[f] = face_n[f, 0] * x[a, 0] + face_n[f, 1] * x[a, 1] + face_n[f, 2] * x[a, 2]


@step_kernel
def _face_offsets(x, tri_nodes, face_first_tri, face_n, face_d):
    """Offsets d_f = n_f . p0 of faces whose normals cannot change (translating walls)."""
    for f in range(face_first_tri.shape[0]):
        a = tri_nodes[face_first_tri[f], 0]
        face_d[f] = face_n[f, 0] * x[a, 0] + face_n[f, 1] * x[a, 1] + face_n[f, 2] * x[a, 2]


@step_kernel
def _locate_on_face(qx, qy, qz, nx, ny, nz, f, x, face_ptr, face_tris, tri_nodes, tol, w):
    """Find the triangle of face ``f`` that holds point q (within ``tol`` of its edges).

    Writes clamped barycentric weights into ``w`` and returns the triangle index, or -1.
    The edge tolerance keeps particles from slipping through seams, edges and corners.
    """
    best = -1
    best_out = 1e300
    for k in range(face_ptr[f], face_ptr[f + 1]):
        t = face_tris[k]
        p0 = tri_nodes[t, 0]
        p1 = tri_nodes[t, 1]
        p2 = tri_nodes[t, 2]
        area2 = _twice_area(x, nx, ny, nz, p0, p1, p2)
        outside = 0.0
        lam0 = 0.0
        lam1 = 0.0
        lam2 = 0.0
        for e in range(3):
            i, j = _edge(e, p0, p1, p2)
            ex = x[j, 0] - x[i, 0]
            ey = x[j, 1] - x[i, 1]
            ez = x[j, 2] - x[i, 2]
            rx = qx - x[i, 0]
            ry = qy - x[i, 1]
            rz = qz - x[i, 2]
            lam = (nx * (ey * rz - ez * ry) + ny * (ez * rx - ex * rz)
                   + nz * (ex * ry - ey * rx)) / area2
            if lam < 0.0:
                # distance outside this edge = -lam * height = -lam * |area2| / |e|
                dist = -lam * abs(area2) / math.sqrt(ex * ex + ey * ey + ez * ez)
                if dist > outside:
                    outside = dist
            if e == 0:
                lam0 = lam
            elif e == 1:
                lam1 = lam
            else:
                lam2 = lam
        if outside <= tol and outside < best_out:
            best_out = outside
            best = t
            _clamped_weights(lam0, lam1, lam2, w)
            if outside == 0.0:
                break
    return best


@step_kernel
def _triangle_frames(x, face_n, face_ptr, face_tris, tri_nodes, frames):
    """Each triangle's barycentric frame at the current node positions, for
    :func:`_locate_on_frames`: with its face's unit normal n, the edge e_e opposite node e (e_0
    from node 1 to node 2, e_1 from 2 to 0, e_2 from 0 to 1) and twice the signed area along n,
    A = n . (e_2 x (x_2 - x_0)), the coordinate of a point q of the plane is

        lambda_e = n . (e_e x (q - x_i)) / A = g_e . q - h_e,  g_e = (n x e_e) / A,
        h_e = g_e . x_i   (x_i the edge's first node),

    and a point with lambda_e < 0 lies -lambda_e H_e outside edge e, H_e = |A| / |e_e| (the
    triangle's height over it). A few dozen operations per triangle per step; the locator then
    needs three dot products per triangle, no division and no square root."""
    for f in range(face_ptr.shape[0] - 1):
        _face_frames(x, face_n, f, face_ptr, face_tris, tri_nodes, frames)


@step_kernel
def _forget_frames(frames):
    """Mark every triangle's frame as not yet computed this step (:func:`_face_frames`): a
    plain sweep of the flags, cheaper than one store a face through the face's index."""
    for t in range(frames.shape[0]):
        frames[t, FRAME_FRESH] = 0.0


@step_kernel
def _face_frames(x, face_n, f, face_ptr, face_tris, tri_nodes, frames):
    """The frames (:func:`_triangle_frames`) of face ``f``'s triangles, marked fresh: the wall
    pass computes a face's frames the first time a step locates a contact on it, so a step
    with no touching contact (a falling or fluidized bed) computes none -- the same numbers
    from the same positions as computing all of them at the start of the step."""
    nx = face_n[f, 0]
    ny = face_n[f, 1]
    nz = face_n[f, 2]
    for k in range(face_ptr[f], face_ptr[f + 1]):
        t = face_tris[k]
        p0 = tri_nodes[t, 0]
        p1 = tri_nodes[t, 1]
        p2 = tri_nodes[t, 2]
        area2 = _twice_area(x, nx, ny, nz, p0, p1, p2)
        inv = 1.0 / area2
        for e in range(3):
            i, j = _edge(e, p0, p1, p2)
            ex = x[j, 0] - x[i, 0]
            ey = x[j, 1] - x[i, 1]
            ez = x[j, 2] - x[i, 2]
            gx = (ny * ez - nz * ey) * inv
            gy = (nz * ex - nx * ez) * inv
            gz = (nx * ey - ny * ex) * inv
            frames[t, 3 * e] = gx
            frames[t, 3 * e + 1] = gy
            frames[t, 3 * e + 2] = gz
            frames[t, 9 + e] = gx * x[i, 0] + gy * x[i, 1] + gz * x[i, 2]
            frames[t, 12 + e] = abs(area2) / math.sqrt(ex * ex + ey * ey + ez * ez)
        frames[t, FRAME_FRESH] = 1.0


@step_kernel
def _locate_on_frames(qx, qy, qz, f, face_ptr, face_tris, frames, tol, w):
    """:func:`_locate_on_face` on the triangles' frames (:func:`_triangle_frames`): the
    triangle of face ``f`` that holds point q of the face's plane within ``tol`` of its edges,
    its clamped barycentric weights into ``w``; returns the triangle, or -1."""
    best = -1
    best_out = 1e300
    for k in range(face_ptr[f], face_ptr[f + 1]):
        t = face_tris[k]
        lam0 = frames[t, 0] * qx + frames[t, 1] * qy + frames[t, 2] * qz - frames[t, 9]
        lam1 = frames[t, 3] * qx + frames[t, 4] * qy + frames[t, 5] * qz - frames[t, 10]
        lam2 = frames[t, 6] * qx + frames[t, 7] * qy + frames[t, 8] * qz - frames[t, 11]
        outside = max(0.0, -lam0 * frames[t, 12], -lam1 * frames[t, 13], -lam2 * frames[t, 14])
        if outside <= tol and outside < best_out:
            best_out = outside
            best = t
            _clamped_weights(lam0, lam1, lam2, w)
            if outside == 0.0:
                break
    return best


@kernel
def _build_wall_list(x, p0, radius, pcav, cav_ptr, cav_faces, face_n, face_d, face_ptr,
                     face_tris, tri_nodes, skin, out_p, out_f, out_a):
    """Candidate (particle, face) pairs: centre within R + skin of the plane, on its inner side or
    less than R behind it, and projecting onto the face (edge tolerance R + skin).

    Sorted by particle, then face. Returns the count, or -1 when the output is full.
    """
    count = 0
    cap = out_p.shape[0]
    w = np.empty(3)
    for p in range(radius.shape[0]):
        c = pcav[p]
        if c < 0:
            continue
        i = p0 + p
        r = radius[p]
        for k in range(cav_ptr[c], cav_ptr[c + 1]):
            f = cav_faces[k]
            nx = face_n[f, 0]
            ny = face_n[f, 1]
            nz = face_n[f, 2]
            d = nx * x[i, 0] + ny * x[i, 1] + nz * x[i, 2] - face_d[f]
            if d >= r + skin or d <= -r:
                continue
            if _locate_on_face(x[i, 0] - d * nx, x[i, 1] - d * ny, x[i, 2] - d * nz, nx, ny, nz,
                               f, x, face_ptr, face_tris, tri_nodes, r + skin, w) < 0:
                continue
            if count >= cap:
                return -1
            out_p[count] = p
            out_f[count] = f
            out_a[count] = r - d
            count += 1
    return count


