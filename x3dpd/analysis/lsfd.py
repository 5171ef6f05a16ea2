"""Modal constants, residual terms and refined poles of a set of FRFs: least-squares
frequency-domain (LSFD) estimation, refined by nonlinear least squares, with standard errors,
and the mass-normalised mode shapes they give.

The model
---------
A set of FRFs H_o (response order q: 0 displacement, 1 velocity, 2 acceleration per unit force)
between a common point d (the reference, or with a roving hammer the response) and the points o
is, for real (normal) modes with modal damping,

.. math::

    H_o(\\omega) = (i\\omega)^q \\Big[ \\sum_{r=1}^{N}
        \\frac{C_{or}}{\\omega_r^2 - \\omega^2 + 2 i \\zeta_r \\omega_r \\omega}
        + \\frac{L_o}{(i\\omega)^2} + U_o \\Big],
    \\qquad C_{or} = \\phi_{or} \\phi_{dr},

with phi_r the mass-normalised shapes (phi_r^T M phi_r = 1): the receptance of N modes plus the
lower residual term L_o / (i w)^2 (the modes below the band, and rigid-body modes: a residual
inertance 1 / L_o) and the upper residual term U_o (the modes above: a residual flexibility),
L_o, U_o and C_or real. The driving-point FRF (o = d) gives phi_dr = sqrt(C_dr), and then
phi_or = C_or / phi_dr: without it the shapes cannot be scaled to unit modal mass.

The estimate
------------
For given poles the model is linear in (C_o, L_o, U_o): :func:`lsfd` solves it by least squares
over the band for every FRF at once (one basis, one right-hand side per FRF; Peeters et al.
2004). :func:`refine_modes` then fits the poles too, minimising the weighted residual
sum_o w_o^2 sum_f |H_o,model - H_o|^2 by variable projection (Golub and Pereyra 1973: the linear
parameters are eliminated by LSFD at every step; Kaufman's Jacobian; scipy's
``least_squares``), from the LSCF poles (x3dpd.analysis.lscf). The weights w_o = 1 / s_o, s_o
each FRF's residual RMS of a first pass, make it the maximum-likelihood estimate for additive
complex Gaussian noise of a level of its own on each FRF (El-kafafy, De Troyer, Peeters,
Guillaume, "Fast maximum-likelihood identification of modal parameters with uncertainty
intervals: a modal model-based formulation", Mech. Syst. Signal Process. 37 (2013) 422-439).

Standard errors are those of the linearised least squares, s^2 (J^T J)^-1, s^2 the weighted
residual variance (about 1): for f_r and zeta_r the inverse of the projected normal matrix
J_p^T J_p; for the linear parameters of FRF o the blocks of the full inverse (block
elimination), and for the shapes their first-order propagation through phi = C / sqrt(C_d).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError


def modal_basis(frequency, fn, zeta, order: int) -> np.ndarray:
    """The model's columns at ``frequency`` [Hz] (N_f, N + 2): (i w)^q / (w_r^2 - w^2 +
    2 i zeta_r w_r w) for each mode, then (i w)^(q - 2) and (i w)^q (the residual terms)."""
    w = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    wn = 2.0 * np.pi * np.asarray(fn, dtype=float)
    iw = 1j * w
    den = (
        wn[None, :] ** 2
        - w[:, None] ** 2
        + 2j * np.asarray(zeta)[None, :] * wn[None, :] * w[:, None]
    )
    q = iw[:, None] ** order
    return np.concatenate([q / den, q * iw[:, None] ** -2, q], axis=1)


def _stack(z: np.ndarray) -> np.ndarray:
    """Complex rows (N_f, ...) as real rows (2 N_f, ...): real parts, then imaginary parts (in
    Fortran order: LAPACK factors a tall C-ordered matrix 30 times slower)."""
    return np.asfortranarray(np.concatenate([z.real, z.imag], axis=0))


def lsfd(frequency, h, fn, zeta, order: int) -> tuple[np.ndarray, np.ndarray]:
    """The linear parameters (N_o, N + 2) -- C_o1..C_oN, L_o, U_o -- of the FRFs ``h`` (N_o,
    N_f) for the poles (``fn`` [Hz], ``zeta``), and the model FRFs (N_o, N_f)."""
    basis = modal_basis(frequency, fn, zeta, order)
    coef = np.linalg.lstsq(_stack(basis), _stack(np.asarray(h).T), rcond=None)[0].T
    return coef, coef @ basis.T


def _pole_jacobian(frequency, fn, zeta, coef, order) -> np.ndarray:
    """d H_o / d (f_r, zeta_r) of the model (N_o, N_f, 2 N) at the linear parameters ``coef``."""
    w = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    wn = 2.0 * np.pi * fn
    den = wn[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta[None, :] * wn[None, :] * w[:, None]
    q = ((1j * w) ** order)[:, None] / den**2
    d_wn = -q * (2.0 * wn[None, :] + 2j * zeta[None, :] * w[:, None]) * 2.0 * np.pi
    d_zeta = -q * 2j * wn[None, :] * w[:, None]
    n = fn.size
    c = coef[:, :n]
    return np.concatenate([c[:, None, :] * d_wn[None], c[:, None, :] * d_zeta[None]], axis=2)


@dataclass(frozen=True)
class ModalFit:
    """The fitted modes of a set of FRFs: ``fn`` [Hz], ``zeta`` and their standard errors;
    ``constants`` C (N_o, N), ``lower`` L_o and ``upper`` U_o residual terms (N_o,), the
    covariance ``coef_cov`` of each FRF's (C_o, L_o, U_o) with the driving point's
    (N_o, 2, N + 2, N + 2: [o, 0] own block, [o, 1] cross block with the driving point), the
    ``model`` FRFs (N_o, N_f at ``frequency``), the weights w_o, the weighted residual's
    variance ``s2`` and the RMS misfit relative to each FRF's RMS (``misfit``, N_o)."""

    fn: np.ndarray
    zeta: np.ndarray
    fn_se: np.ndarray
    zeta_se: np.ndarray
    constants: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    coef_cov: np.ndarray
    frequency: np.ndarray
    model: np.ndarray
    weights: np.ndarray
    s2: float
    misfit: np.ndarray
    order: int
    driving: int

    def shapes(self) -> tuple[np.ndarray, np.ndarray]:
        """Mass-normalised shapes phi (N_o, N) at the measured points and their standard
        errors: phi_d = sqrt(C_d) at the driving point, phi_o = C_o / phi_d elsewhere (module
        docstring). An :class:`InputError` when a mode's C_d is not positive."""
        c = self.constants
        d = self.driving
        cd = c[d]
        if np.all(cd < 0):
            raise InputError(
                "every mode's modal constant at the driving point is negative: the FRFs' sign "
                "is reversed (drive and response in opposite directions)"
            )
        bad = np.flatnonzero(cd <= 0)
        if bad.size:
            which = ", ".join(f"{k + 1} ({self.fn[k]:.6g} Hz)" for k in bad)
            raise InputError(
                f"mode(s) {which} have a modal constant <= 0 at the driving point, where every "
                "mode's is positive: is that FRF's response at its force's point and "
                "direction? (else: noise, or a mode it does not see; lower --modes)"
            )
        root = np.sqrt(cd)
        phi = c / root[None, :]
        phi[d] = root
        se = np.empty_like(phi)
        n = self.fn.size
        for o in range(c.shape[0]):
            for r in range(n):
                var_o = self.coef_cov[o, 0, r, r]
                var_d = self.coef_cov[d, 0, r, r]
                if o == d:
                    se[o, r] = np.sqrt(max(var_d, 0.0)) / (2.0 * root[r])
                    continue
                a = 1.0 / root[r]
                b = -c[o, r] / (2.0 * cd[r] * root[r])
                cov = self.coef_cov[o, 1, r, r]
                se[o, r] = np.sqrt(max(a * a * var_o + b * b * var_d + 2.0 * a * b * cov, 0.0))
        return phi, se


# Over 80 lines: one LSFD solve: assembly, solve, residuals and errors share its matrices.
def refine_modes(
    frequency, h, fn0, zeta0, *, order: int, driving: int, band: tuple[float, float]
) -> ModalFit:
    """Fit the model (module docstring) to ``h`` (N_o, N_f) over ``band`` from the poles
    (``fn0`` [Hz], ``zeta0``): weights from a first pass, then the poles refined by variable
    projection with each FRF weighted by its residual level."""
    from scipy.optimize import least_squares

    f = np.asarray(frequency, dtype=float)
    h = np.atleast_2d(np.asarray(h, dtype=complex))
    sel = (f >= band[0]) & (f <= band[1])
    f, h = f[sel], h[:, sel]
    n, n_o = len(fn0), h.shape[0]
    scale = np.sqrt(np.mean(np.abs(h) ** 2, axis=1))

    def level(p):
        _, model = lsfd(f, h, p[:n], p[n:], order)
        s = np.sqrt(0.5 * np.mean(np.abs(model - h) ** 2, axis=1))  # per real component
        return np.maximum(s, 1e-13 * scale)

    def solve(p0, weights):
        def residual(p):
            basis = _stack(modal_basis(f, p[:n], p[n:], order))
            y = _stack(h.T)
            coef = np.linalg.lstsq(basis, y, rcond=None)[0]
            return ((basis @ coef - y) * weights[None, :]).T.ravel()

        def jacobian(p):
            basis = _stack(modal_basis(f, p[:n], p[n:], order))
            coef = np.linalg.lstsq(basis, _stack(h.T), rcond=None)[0].T
            q, _ = np.linalg.qr(basis)
            jac = np.stack([_stack(j) for j in _pole_jacobian(f, p[:n], p[n:], coef, order)])
            jac = jac - np.einsum("ij,ojk->oik", q, np.einsum("ij,ojk->oik", q.T, jac))
            return np.asfortranarray((jac * weights[:, None, None]).reshape(-1, 2 * n))

        lo = np.concatenate([np.full(n, f[0]), np.full(n, 1e-7)])
        hi = np.concatenate([np.full(n, f[-1]), np.full(n, 0.99)])
        p0 = np.clip(p0, lo * (1 + 1e-12), hi * (1 - 1e-12))
        return least_squares(
            residual,
            p0,
            jac=jacobian,
            bounds=(lo, hi),
            x_scale=np.abs(p0),
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
            max_nfev=200,
        )

    p = np.concatenate([np.asarray(fn0, dtype=float), np.asarray(zeta0, dtype=float)])
    weights = 1.0 / level(p)
    sol = solve(p, weights)
    weights = 1.0 / level(sol.x)
    sol = solve(sol.x, weights)
    fn, zeta = sol.x[:n], sol.x[n:]
    coef, model = lsfd(f, h, fn, zeta, order)
    n_data = 2 * f.size * n_o
    n_par = 2 * n + n_o * (n + 2)
    if n_data <= n_par:
        raise InputError(
            f"{n_o} FRF(s) of {f.size} lines give {n_data} values for {n_par} parameters"
        )
    s2 = float(sol.fun @ sol.fun) / (n_data - n_par)
    try:
        cov_p, coef_cov = _covariance(f, coef, fn, zeta, order, weights, s2, driving)
    except np.linalg.LinAlgError:
        found = ", ".join(f"{x:.6g}" for x in fn)
        raise InputError(
            f"the fitted modes (Hz: {found}) are not independent (two poles on one "
            "frequency?): lower --modes"
        ) from None
    se = np.sqrt(np.maximum(np.diag(cov_p), 0.0))
    misfit = np.sqrt(np.mean(np.abs(model - h) ** 2, axis=1)) / scale
    return ModalFit(
        fn=fn,
        zeta=zeta,
        fn_se=se[:n],
        zeta_se=se[n:],
        constants=coef[:, :n],
        lower=coef[:, n],
        upper=coef[:, n + 1],
        coef_cov=coef_cov,
        frequency=f,
        model=model,
        weights=weights,
        s2=s2,
        misfit=misfit,
        order=order,
        driving=driving,
    )


def _covariance(f, coef, fn, zeta, order, weights, s2, driving):
    """s^2 (J^T J)^-1 of the weighted model by block elimination: the poles' block, and for
    each FRF its linear parameters' block and their cross block with the driving point's."""
    basis = _stack(modal_basis(f, fn, zeta, order))  # (2 N_f, p)
    jac = np.stack([_stack(j) for j in _pole_jacobian(f, fn, zeta, coef, order)])  # (N_o, 2N_f, 2N)
    jac = jac * weights[:, None, None]
    gram_inv = np.linalg.inv(basis.T @ basis)  # D_o^-1 = gram_inv / w_o^2
    cross = np.einsum("oij,ik->ojk", jac, basis) * weights[:, None, None]  # B_o (N_o, 2N, p)
    d_inv_bt = np.einsum("kl,ojl->okj", gram_inv, cross) / (weights**2)[:, None, None]
    schur = np.einsum("oij,oik->jk", jac, jac) - np.einsum("ojk,okl->jl", cross, d_inv_bt)
    cov_p = s2 * np.linalg.inv(schur)
    # cov(c_o, c_k) = s2 (delta_ok D_o^-1 + D_o^-1 B_o^T S^-1 B_k D_k^-1)
    left = np.einsum("okj,jl->okl", d_inv_bt, cov_p)  # D_o^-1 B_o^T cov_p
    coef_cov = np.empty((coef.shape[0], 2, coef.shape[1], coef.shape[1]))
    for o in range(coef.shape[0]):
        coef_cov[o, 0] = s2 * gram_inv / weights[o] ** 2 + left[o] @ d_inv_bt[o].T
        coef_cov[o, 1] = left[o] @ d_inv_bt[driving].T
    return cov_p, coef_cov
