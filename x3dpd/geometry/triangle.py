"""Triangle geometry: normals, areas, plane distances, point-in-triangle, inward orientation.

Pure numpy, no physics. Arrays of triangles are given by their corner coordinates ``p0, p1, p2``
of shape ``(T, 3)``; arrays of points by ``(N, 3)``. Lengths are in the deck's unit.

The orientation of a wall triangle is taken from geometry, never from its winding: the report's
Appendix A deck winds some cavity triangles one way and some the other (decks/README.md).
"""

from __future__ import annotations

import numpy as np

#: Relative tolerance (times the size of the geometry) below which two planes count as one, or a
#: point counts as lying in a plane.
PLANE_TOL = 1e-9


def triangle_normals(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
    r"""Winding normals of triangles.

    :math:`\mathbf n = (\mathbf p_1-\mathbf p_0)\times(\mathbf p_2-\mathbf p_0)`.

    The length of :math:`\mathbf n` is twice the triangle's area; its direction follows the
    right-hand rule on the order ``p0, p1, p2``.

    Parameters
    ----------
    p0, p1, p2 : (T, 3) or (3,) array [length]
        Corners.

    Returns
    -------
    (T, 3) or (3,) array [length^2]
    """
    p0 = np.asarray(p0, dtype=np.float64)
    return np.cross(np.asarray(p1, dtype=np.float64) - p0, np.asarray(p2, dtype=np.float64) - p0)


def triangle_areas(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
    r"""Areas [length^2].

    :math:`A = \tfrac12\,|(\mathbf p_1-\mathbf p_0)\times(\mathbf p_2-\mathbf p_0)|`.
    """
    return 0.5 * np.linalg.norm(triangle_normals(p0, p1, p2), axis=-1)


def unit_normals(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> np.ndarray:
    r"""Unit winding normals :math:`\hat{\mathbf n} = \mathbf n / |\mathbf n|` (0 if degenerate)."""
    n = triangle_normals(p0, p1, p2)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.divide(n, length, out=np.zeros_like(n), where=length > 0.0)


def signed_distances(points: np.ndarray, p0: np.ndarray, n_hat: np.ndarray) -> np.ndarray:
    r"""Signed distances :math:`d_{ij} = (\mathbf x_i - \mathbf p_{0j})\cdot\hat{\mathbf n}_j`.

    Positive on the side ``n_hat`` points to.

    Parameters
    ----------
    points : (N, 3) array [length]
    p0 : (T, 3) array [length], one point of each plane.
    n_hat : (T, 3) array, unit normal of each plane.

    Returns
    -------
    (N, T) array [length]
    """
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    p0 = np.atleast_2d(np.asarray(p0, dtype=np.float64))
    n_hat = np.atleast_2d(np.asarray(n_hat, dtype=np.float64))
    return points @ n_hat.T - np.einsum("tk,tk->t", p0, n_hat)[None, :]


def edge_distances(points: np.ndarray, p0: np.ndarray, p1: np.ndarray,
                   p2: np.ndarray) -> np.ndarray:
    r"""In-plane distances from the projections of points to the three edge lines of triangles.

    With barycentric coordinates :math:`\lambda_k` of the projection of :math:`\mathbf x` onto the
    triangle's plane (:math:`\lambda_k` belongs to corner :math:`k`), the signed distance from the
    projection to the edge opposite corner :math:`k` is :math:`\lambda_k h_k`, where
    :math:`h_k = 2A/|\mathbf e_k|` is the altitude onto that edge. It is positive inside.

    Barycentric coordinates use :math:`\mathbf u = \mathbf p_1-\mathbf p_0`,
    :math:`\mathbf v = \mathbf p_2-\mathbf p_0`, :math:`\mathbf w = \mathbf x-\mathbf p_0`,
    :math:`\mathbf n = \mathbf u\times\mathbf v`:
    :math:`\lambda_1 = (\mathbf w\times\mathbf v)\cdot\mathbf n/|\mathbf n|^2`,
    :math:`\lambda_2 = (\mathbf u\times\mathbf w)\cdot\mathbf n/|\mathbf n|^2`,
    :math:`\lambda_0 = 1-\lambda_1-\lambda_2`.

    Parameters
    ----------
    points : (N, 3) array [length]
    p0, p1, p2 : (T, 3) array [length], non-degenerate triangles.

    Returns
    -------
    (N, T, 3) array [length], distance to the edge opposite corner 0, 1, 2.
    """
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    p0, p1, p2 = (np.atleast_2d(np.asarray(p, dtype=np.float64)) for p in (p0, p1, p2))
    u = p1 - p0
    v = p2 - p0
    n = np.cross(u, v)
    nn = np.einsum("tk,tk->t", n, n)
    w = points[:, None, :] - p0[None, :, :]
    lam1 = np.einsum("ntk,tk->nt", np.cross(w, v[None]), n) / nn
    lam2 = np.einsum("ntk,tk->nt", np.cross(u[None], w), n) / nn
    lam0 = 1.0 - lam1 - lam2
    two_area = np.sqrt(nn)
    h0 = two_area / np.linalg.norm(p2 - p1, axis=1)
    h1 = two_area / np.linalg.norm(p2 - p0, axis=1)
    h2 = two_area / np.linalg.norm(p1 - p0, axis=1)
    return np.stack([lam0 * h0[None], lam1 * h1[None], lam2 * h2[None]], axis=-1)


def points_in_triangles(points: np.ndarray, p0: np.ndarray, p1: np.ndarray, p2: np.ndarray,
                        tol: float | np.ndarray = 0.0) -> np.ndarray:
    r"""Whether the projection of each point onto each triangle's plane lies in the triangle.

    A projection counts as inside when it is no farther than ``tol`` outside every edge line,
    :math:`\min_k \lambda_k h_k \ge -\mathrm{tol}` (see :func:`edge_distances`): the triangle
    grown by ``tol`` normal to each edge (its corners grow a little more than ``tol``).

    Parameters
    ----------
    points : (N, 3) array [length]
    p0, p1, p2 : (T, 3) array [length]
    tol : float or (N,) array [length], edge tolerance (e.g. the particle radius).

    Returns
    -------
    (N, T) bool array
    """
    d = edge_distances(points, p0, p1, p2).min(axis=-1)
    tol = np.asarray(tol, dtype=np.float64)
    if tol.ndim == 1:
        tol = tol[:, None]
    return d >= -tol


def inward_signs(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray,
                 reference: np.ndarray) -> np.ndarray:
    r"""Orientation signs :math:`s = \operatorname{sign}(\mathbf n\cdot(\mathbf c-\mathbf p_0))`.

    ``s * n`` points from the triangle's plane toward the reference point :math:`\mathbf c`
    (the inside of a cavity). Zero where the reference point lies in the plane, i.e. where the
    inside cannot be told; callers decide what to do then.

    Parameters
    ----------
    p0, p1, p2 : (T, 3) array [length]
    reference : (3,) or (T, 3) array [length], interior reference point(s).

    Returns
    -------
    (T,) float array of +1.0, -1.0 or 0.0.
    """
    n_hat = unit_normals(p0, p1, p2)
    d = np.einsum("tk,tk->t", n_hat, np.asarray(reference, dtype=np.float64) - p0)
    scale = np.max(np.ptp(np.concatenate([p0, p1, p2]), axis=0), initial=0.0)
    return np.where(np.abs(d) <= PLANE_TOL * max(scale, 1e-300), 0.0, np.sign(d))
