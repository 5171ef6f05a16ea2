"""The poles of a set of FRFs: the least-squares complex-frequency-domain (LSCF) estimator and a
stabilisation step that keeps the physical poles.

The estimator
-------------
All FRFs o = 1..N_o of a set (one reference, several responses; or one response, several
references) share the structure's poles, so over the band they are approximated by rational
functions with one common denominator in the z-domain:

.. math::

    H_o(\\omega) \\approx \\frac{B_o(\\Omega)}{A(\\Omega)}, \\quad
    A(\\Omega) = \\sum_{k=0}^{n} a_k \\Omega^k, \\quad
    B_o(\\Omega) = \\sum_{k=0}^{n} b_{ok} \\Omega^k, \\quad
    \\Omega = e^{i \\omega \\Delta t}, \\; \\Delta t = \\frac{1}{2 f_{hi}},

with real coefficients (poles in complex-conjugate pairs) and f_hi the top of the band: the band
lies on the upper half of the unit circle, where the powers Omega^k are nearly orthogonal. The
equation error eps_o(w_f) = w_o (B_o(Omega_f) - H_o(w_f) A(Omega_f)) is linear in the
coefficients. With Gamma the N_f x (n + 1) matrix of Omega_f^k, its normal equations have the
blocks

.. math::

    R = \\Re(\\Gamma^H \\Gamma), \\quad S_o = -\\Re(\\Gamma^H \\mathrm{diag}(H_o) \\Gamma), \\quad
    T_o = \\Re(\\Gamma^H \\mathrm{diag}(|H_o|^2) \\Gamma),

Toeplitz matrices (Omega_f^-k Omega_f^l = Omega_f^(l-k)) built from 2n + 1 sums each. Eliminating
each B_o leaves the reduced normal equations of the denominator,

.. math::

    M a = 0, \\qquad M = \\sum_o w_o^2 (T_o - S_o^T R^{-1} S_o),

solved with a_n = 1. The roots z_r of A are the discrete poles; the continuous poles are
lambda_r = ln(z_r) / Delta t, with f_r = |lambda_r| / 2 pi and zeta_r = -Re(lambda_r) / |lambda_r|.
The weight w_o = 1 / rms|H_o| makes every FRF count alike.

Stabilisation
-------------
The estimator runs at the orders n = 2, 4, ..., n_max. A pole is *stable* at order n when the
order n - 2 has a pole within 1 % in frequency and 5 % in damping (Peeters et al. 2004), and
*physical* when it lies in the band with 0 < zeta < 0.5. Stable poles are grouped by frequency
(neighbours within 0.5 %); a structural mode is a group found at many orders, a computational
pole comes and goes. :func:`select_poles` takes the N groups found at the most orders (at least
three) and, from each, the pole of the highest order.

References: P. Guillaume, P. Verboven, S. Vanlanduit, H. Van der Auweraer, B. Peeters, "A
poly-reference implementation of the least-squares complex frequency-domain estimator", Proc.
IMAC XXI (2003); P. Verboven, "Frequency-domain system identification for modal analysis", PhD
thesis, Vrije Universiteit Brussel (2002), Section 5.3; B. Peeters, H. Van der Auweraer,
P. Guillaume, J. Leuridan, "The PolyMAX frequency-domain method: a new standard for modal
parameter estimation?", Shock and Vibration 11 (2004) 395-409. The same single-reference
estimator (unweighted) is ``Model.get_poles("lscf")`` of sdypy-EMA, which the PyPI package pyEMA
re-exports.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from x3dpd.errors import InputError

#: Stabilisation criteria between consecutive orders: relative frequency and damping changes.
STABLE_FREQUENCY = 0.01
STABLE_DAMPING = 0.05
#: Stable poles closer than this (relative frequency) belong to one group.
GROUP_FREQUENCY = 0.005
#: The largest damping ratio taken as physical.
ZETA_MAX = 0.5
#: A group must be found at this many orders to count as a mode.
MIN_ORDERS = 3


@dataclass(frozen=True)
class PoleOrders:
    """The LSCF poles at each order: ``orders`` (K,), and per order the physical poles'
    ``freq`` [Hz], ``zeta``, ``poles`` (complex, rad/s) and ``stable`` flags."""

    orders: list[int]
    freq: list[np.ndarray]
    zeta: list[np.ndarray]
    poles: list[np.ndarray]
    stable: list[np.ndarray]


@dataclass(frozen=True)
class PoleGroup:
    """Stable poles of one frequency: the orders they were found at, the chosen pole
    (complex, rad/s) and its frequency [Hz] and damping."""

    n_orders: int
    pole: complex
    fn: float
    zeta: float


def lscf_poles(frequency, h, *, band: tuple[float, float], max_order: int) -> PoleOrders:
    """LSCF poles of the FRFs ``h`` (N_o, N_f) at ``frequency`` [Hz] over ``band``, at the
    orders 2, 4, ..., ``max_order`` (module docstring), with their stability flags."""
    f = np.asarray(frequency, dtype=float)
    h = np.atleast_2d(np.asarray(h, dtype=complex))
    lo, hi = band
    sel = (f >= lo) & (f <= hi)
    f, h = f[sel], h[:, sel]
    n = int(max_order)
    dt = 0.5 / hi
    lags = np.arange(-n, n + 1)
    power = np.exp(1j * 2.0 * np.pi * dt * np.outer(f, lags))  # Omega_f^j, j = -n..n
    weight = 1.0 / np.sqrt(np.mean(np.abs(h) ** 2, axis=1))
    r_mom = np.sum(power, axis=0).real
    s_mom = -(h @ power).real * weight[:, None]
    t_mom = ((np.abs(h) ** 2) @ power).real * (weight**2)[:, None]
    idx = np.arange(n + 1)
    toe = idx[None, :] - idx[:, None] + n  # element (k, l) of a Toeplitz matrix: lag l - k
    r_full = r_mom[toe]
    s_full = s_mom[:, toe]  # (N_o, n+1, n+1)
    t_full = t_mom[:, toe].sum(axis=0)
    orders, freqs, zetas, poles_list = [], [], [], []
    for order in range(2, n + 1, 2):
        m = order + 1
        r = r_full[:m, :m]
        s = s_full[:, :m, :m]
        try:
            rs = np.linalg.solve(r, np.concatenate(list(s), axis=1))  # R^-1 [S_1 ... S_No]
            mm = t_full[:m, :m].copy()
            for o in range(h.shape[0]):
                mm -= s[o].T @ rs[:, o * m : (o + 1) * m]
            a = np.linalg.solve(mm[:order, :order], -mm[:order, order])
        except np.linalg.LinAlgError:  # an order the lines cannot determine: none of its poles
            continue
        z = np.roots(np.append(a, 1.0)[::-1])
        z = z[(np.abs(z) > 0) & np.isfinite(z)]
        lam = np.log(z.astype(complex)) / dt
        keep = lam.imag > 0
        lam = lam[keep]
        fn = np.abs(lam) / (2.0 * np.pi)
        zeta = -lam.real / np.abs(lam)
        ok = (fn >= lo) & (fn <= hi) & (zeta > 0) & (zeta < ZETA_MAX)
        order_of = np.argsort(fn[ok])
        orders.append(order)
        freqs.append(fn[ok][order_of])
        zetas.append(zeta[ok][order_of])
        poles_list.append(lam[ok][order_of])
    stable = [np.zeros(0, dtype=bool) if not orders else np.zeros(freqs[0].size, dtype=bool)]
    for k in range(1, len(orders)):
        stable.append(_stable(freqs[k], zetas[k], freqs[k - 1], zetas[k - 1]))
    return PoleOrders(orders, freqs, zetas, poles_list, stable)


def _stable(fn, zeta, fn_prev, zeta_prev) -> np.ndarray:
    """Which poles (fn, zeta) have a pole of the previous order within the criteria."""
    if fn_prev.size == 0 or fn.size == 0:
        return np.zeros(fn.size, dtype=bool)
    df = np.abs(fn[:, None] - fn_prev[None, :]) <= STABLE_FREQUENCY * fn[:, None]
    dz = np.abs(zeta[:, None] - zeta_prev[None, :]) <= STABLE_DAMPING * zeta[:, None]
    return np.any(df & dz, axis=1)


def pole_groups(orders: PoleOrders) -> list[PoleGroup]:
    """The stable poles grouped by frequency, most orders first (module docstring)."""
    rows = [
        (orders.freq[k][j], orders.orders[k], orders.poles[k][j], orders.zeta[k][j])
        for k in range(len(orders.orders))
        for j in np.flatnonzero(orders.stable[k])
    ]
    rows.sort(key=lambda row: row[0])
    groups: list[list[tuple]] = []
    for row in rows:
        if groups and row[0] - groups[-1][-1][0] <= GROUP_FREQUENCY * row[0]:
            groups[-1].append(row)
        else:
            groups.append([row])
    out = []
    for members in groups:
        top = max(m[1] for m in members)
        at_top = [m for m in members if m[1] == top]
        middle = float(np.median([m[0] for m in members]))
        best = min(at_top, key=lambda m: abs(m[0] - middle))
        out.append(
            PoleGroup(
                len({m[1] for m in members}), complex(best[2]), float(best[0]), float(best[3])
            )
        )
    out.sort(key=lambda g: (-g.n_orders, g.fn))
    return out


def select_poles(groups: list[PoleGroup], n_modes: int, *, band: tuple[float, float]) -> np.ndarray:
    """The poles (complex, rad/s; increasing frequency) of the ``n_modes`` groups found at the
    most orders; an :class:`InputError` when fewer than ``n_modes`` groups are found at
    :data:`MIN_ORDERS` orders or more."""
    modes = [g for g in groups if g.n_orders >= MIN_ORDERS]
    if len(modes) < n_modes:
        found = ", ".join(f"{g.fn:.4g}" for g in sorted(modes, key=lambda g: g.fn)) or "none"
        raise InputError(
            f"the band {band[0]:g}:{band[1]:g} Hz shows {len(modes)} stable mode(s) "
            f"(Hz: {found}); --modes {n_modes} asks for more: lower --modes or widen --band"
        )
    chosen = sorted(modes[:n_modes], key=lambda g: g.fn)
    return np.array([g.pole for g in chosen])


def max_order(n_modes: int, n_lines: int) -> int:
    """The highest LSCF order tried: room for computational poles beside 2 N modal ones
    (4 N + 24), within what N_f lines determine (N_f - 2), even."""
    top = min(4 * n_modes + 24, n_lines - 2)
    return top - top % 2
