"""Mixing rules: the constants of a contact between two particles from the two bodies' own.

Report Section 7.2 (one material) generalised to several PDMP groups (docs/physics.md):

* Hertz factor of the pair, multiplying Σ_k (E_ik + E_jk)/(1-ν²) a^{3/2} in the step loop:
  ``k = 4/3 · s · sqrt(R_i R_j / (R_i + R_j))`` with the series weight
  ``s = c_i c_j / (c_i + c_j)²`` and ``c`` a body's plane-strain instantaneous modulus
  Σ_k E_k/(1-ν²) (psi). For identical spheres k·2E/(1-ν²) = 4/3 E* sqrt(R*) with E* = E/(2(1-ν²)),
  R* = R/2: the report's Eq. 5 constant.
* Tangential effective mass ``m_t = 1 / (1/m_ti + 1/m_tj)`` with 1/m_t = 1/m + R²/I per body
  (lbf·s²/in).
* Friction coefficient: the mean of the two PCOFs.

A scene has few particle *kinds* (bodies with equal radius, modulus, mass and PCOF -- usually one
per PDMP card), so the step loop looks these constants up in a kinds × kinds table built once,
instead of spending a square root and three divisions on every contact every step.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd._jit import kernel, step_kernel

__all__ = ["pair_constants", "pair_constant_table", "particle_kinds"]


@step_kernel
def pair_constants(ri, rj, ci, cj, inv_mti, inv_mtj, mui, muj):
    """(Hertz factor k, tangential effective mass m_t, friction coefficient μ) of a pair."""
    sq = math.sqrt(ri * rj / (ri + rj))
    wgt = ci * cj / (ci + cj) ** 2
    return 4.0 / 3.0 * wgt * sq, 1.0 / (inv_mti + inv_mtj), 0.5 * (mui + muj)


@kernel
def _fill_table(radius, cinst, inv_mt, mu, rep, out):
    for a in range(rep.shape[0]):
        p = rep[a]
        for b in range(rep.shape[0]):
            q = rep[b]
            k, m_t, mu_ab = pair_constants(radius[p], radius[q], cinst[p], cinst[q], inv_mt[p],
                                           inv_mt[q], mu[p], mu[q])
            out[a, b, 0] = k
            out[a, b, 1] = m_t
            out[a, b, 2] = mu_ab


def particle_kinds(radius, cinst, inv_mt, mu, *more) -> tuple[np.ndarray, np.ndarray]:
    """Group particles with bit-identical contact properties (``more``: further per-particle
    properties that must agree, e.g. a normal law's constants).

    Returns ``(kind, rep)``: the kind index of every particle (int64, in order of first
    appearance) and one representative particle per kind.
    """
    props = np.column_stack([np.asarray(v, dtype=np.float64) for v in
                             (radius, cinst, inv_mt, mu, *more)])
    if props.shape[0] == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    _, first, inverse = np.unique(props, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")          # kinds numbered by first appearance
    renumber = np.empty_like(order)
    renumber[order] = np.arange(order.shape[0])
    return renumber[inverse.reshape(-1)].astype(np.int64), first[order].astype(np.int64)


def pair_constant_table(radius, cinst, inv_mt, mu, rep) -> np.ndarray:
    """(kinds, kinds, 3) table of :func:`pair_constants` for the representatives ``rep``.

    Computed by the same compiled expression the contact loop used to evaluate per contact, so
    the looked-up values are bit for bit what that evaluation gave.
    """
    out = np.zeros((rep.shape[0], rep.shape[0], 3))
    if rep.shape[0]:
        f64 = [np.ascontiguousarray(v, np.float64) for v in (radius, cinst, inv_mt, mu)]
        _fill_table(*f64, np.ascontiguousarray(rep, np.int64), out)
    return out
