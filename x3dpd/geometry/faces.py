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

__all__ = ["_build_wall_list", "_face_offsets", "_face_planes", "_locate_on_face"]


@step_kernel
def _face_planes(x, tri_nodes, tri_sign, face_first_tri, face_n, face_d):
    """Unit inward normal n_f and offset d_f = n_f . p0 of every face from its first triangle."""
    for f in range(face_first_tri.shape[0]):
        t = face_first_tri[f]
        a = tri_nodes[t, 0]
        b = tri_nodes[t, 1]
        c = tri_nodes[t, 2]
        ux = x[b, 0] - x[a, 0]
        uy = x[b, 1] - x[a, 1]
        uz = x[b, 2] - x[a, 2]
        vx = x[c, 0] - x[a, 0]
        vy = x[c, 1] - x[a, 1]
        vz = x[c, 2] - x[a, 2]
        nx = uy * vz - uz * vy
        ny = uz * vx - ux * vz
        nz = ux * vy - uy * vx
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
        ax = x[p1, 0] - x[p0, 0]
        ay = x[p1, 1] - x[p0, 1]
        az = x[p1, 2] - x[p0, 2]
        bx = x[p2, 0] - x[p0, 0]
        by = x[p2, 1] - x[p0, 1]
        bz = x[p2, 2] - x[p0, 2]
        # twice the signed area along n
        area2 = nx * (ay * bz - az * by) + ny * (az * bx - ax * bz) + nz * (ax * by - ay * bx)
        outside = 0.0
        lam0 = 0.0
        lam1 = 0.0
        lam2 = 0.0
        for e in range(3):
            if e == 0:
                i = p1
                j = p2
            elif e == 1:
                i = p2
                j = p0
            else:
                i = p0
                j = p1
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
            lam0 = min(max(lam0, 0.0), 1.0)
            lam1 = min(max(lam1, 0.0), 1.0)
            lam2 = min(max(lam2, 0.0), 1.0)
            sw = lam0 + lam1 + lam2
            w[0] = lam0 / sw
            w[1] = lam1 / sw
            w[2] = lam2 / sw
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


