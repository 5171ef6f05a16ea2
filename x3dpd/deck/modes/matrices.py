"""Modes of a structure given by its stiffness and mass matrices: :func:`modes_from_matrices`."""

from __future__ import annotations

import numpy as np

from x3dpd.deck.modes.modeset import ModeSet, parse_dof, sorted_mode_set


# Over 80 lines: one eigen-solution: checks, solve, normalisation and order on the same matrices.
def modes_from_matrices(
    K,
    M,
    node_ids,
    dofs,
    *,
    n_modes: int | None = None,
    damping=None,
    units=None,
    name: str = "<matrices>",
) -> ModeSet:
    """The lowest modes of K phi = omega^2 M phi, mass-normalised, as a :class:`ModeSet`.

    Solves the symmetric-definite problem with :func:`scipy.linalg.eigh`, whose eigenvectors
    satisfy phi_r^T M phi_s = delta_rs (mass-normalised; generalized mass 1). f_r =
    sqrt(lambda_r) / (2 pi) [Hz]. A shape's sign is fixed so that its component of largest
    magnitude is positive (the first such row on a tie).

    Parameters
    ----------
    K, M : (n, n) array_like
        Symmetric stiffness [F/L] and mass [F T^2/L] matrices; M positive definite, K positive
        semi-definite (rigid-body modes get f = 0).
    node_ids, dofs : (n,) array_like
        The node id and component (1-6 or ``x y z rx ry rz``) of each matrix row; components a
        node has no row for are NaN in the shapes.
    n_modes : int, optional
        How many of the lowest modes to keep (all n by default).
    damping : float or (n_modes,) array_like, optional
        Modal damping ratio(s) to attach.
    units : (length, force, time), optional
        The matrices' unit system.
    name : str
        What the ModeSet's ``path`` says (error messages name it).

    Raises ValueError when the matrices do not fit that description.
    """
    import scipy.linalg  # here: reading mode files needs no scipy (0.4 s to import)

    K = np.array(K, dtype=np.float64)
    M = np.array(M, dtype=np.float64)
    n = K.shape[0] if K.ndim == 2 else -1
    if K.shape != (n, n) or M.shape != (n, n) or n == 0:
        raise ValueError(f"K {K.shape} and M {M.shape} must be square matrices of one size")
    node_ids = np.asarray(node_ids).reshape(-1)
    dofs = [parse_dof(d) for d in np.asarray(dofs).reshape(-1)]
    if len(node_ids) != n or len(dofs) != n:
        raise ValueError(
            f"{len(node_ids)} node ids and {len(dofs)} DOFs for matrices of size "
            f"{n}; expected one (node id, DOF) per row"
        )
    rows = list(zip(node_ids.tolist(), dofs))
    if len(set(rows)) != n:
        dup = next(r for r in rows if rows.count(r) > 1)
        raise ValueError(f"node {dup[0]} DOF {dup[1]} names more than one matrix row")
    for what, A in (("K", K), ("M", M)):
        if not np.all(np.isfinite(A)):
            raise ValueError(f"{what} has a NaN or infinite entry")
        if not np.allclose(A, A.T, rtol=1e-10, atol=1e-12 * np.abs(A).max()):
            raise ValueError(f"{what} is not symmetric")
    n_modes = n if n_modes is None else int(n_modes)
    if not 1 <= n_modes <= n:
        raise ValueError(f"n_modes = {n_modes}: expected 1 to {n}")
    try:
        lam, phi = scipy.linalg.eigh(K, M, subset_by_index=[0, n_modes - 1])
    except np.linalg.LinAlgError:
        raise ValueError("M is not positive definite") from None
    # eigh's eigenvalues of a positive semi-definite K are >= 0 up to round-off of the order of
    # eps * the largest eigenvalue (about eps * ||K|| / min(M's eigenvalues)).
    scale = np.abs(scipy.linalg.eigvalsh(K, M, subset_by_index=[n - 1, n - 1]))[0]
    if (lam < -1e-9 * scale).any():
        raise ValueError(
            f"K is not positive semi-definite (eigenvalue {lam.min():g}); "
            "expected K phi = omega^2 M phi to have omega^2 >= 0"
        )
    freq = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)
    big = np.argmax(np.abs(phi), axis=0)
    phi = phi * np.sign(phi[big, np.arange(n_modes)])
    nodes = np.unique(node_ids)
    shapes = np.full((n_modes, len(nodes), 6), np.nan)
    col = np.searchsorted(nodes, node_ids)
    shapes[:, col, np.array(dofs) - 1] = phi.T
    if damping is not None:
        damping = np.broadcast_to(np.asarray(damping, dtype=np.float64), (n_modes,))
    return sorted_mode_set(
        name, np.arange(1, n_modes + 1), freq, nodes, shapes, damping=damping, units=units
    )
