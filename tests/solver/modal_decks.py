"""Small modal-structure decks for the MODAL tests, written as deck text (docs/deck-reference.md,
"MODAL"), and the closed forms they are checked against (numpy and scipy only)."""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg


def modal_deck(
    *,
    dt: float,
    tmax: float,
    modes,
    shapes,
    drive: str = "",
    masses=(),
    nodes=None,
    itrac: int = 1,
    trace=None,
    housing: str = "",
    extra: str = "",
) -> str:
    """A deck of modal nodes only (no particles): ``modes`` (number, Hz, zeta), ``shapes``
    (node, dof, values), ``masses`` (node, mass) added in the deck, ``drive`` a USRFRC spec."""
    nodes = nodes or sorted({s[0] for s in shapes})
    lines = [
        "TITLE",
        "modal test structure",
        "END",
        "PARAMETERS",
        f" 0.0 {float(tmax)!r} 0.0 {float(dt)!r} {float(dt)!r} 0 1e12 0 5 0 {itrac}",
        "END",
        "NODE COORDINATES",
    ]
    lines += [f" {n} {float(n)} 0 0" for n in nodes]
    lines += ["END", "MASS"]
    mass = dict(masses)
    lines += [f" {n} {float(mass.get(n, 0.0))!r} 0 0 0" for n in nodes]
    lines += ["END", "MODAL"]
    lines += [f" MODE {k} {float(f)!r} {float(z)!r}" for k, f, z in modes]
    lines += [f" SHAPE {n} {d} " + " ".join(repr(float(v)) for v in vals) for n, d, vals in shapes]
    if housing:
        lines.append(f" HOUSING {housing}")
    lines.append("END")
    if trace:
        lines += ["TRACE", " " + " ".join(map(str, trace)), "END"]
    if drive:
        lines += ["USRFRC", f" {drive}", "END"]
    return "\n".join(lines) + "\n" + extra


def chain_modes(m, k):
    """Mass-normalised modes of a fixed-free spring chain: masses ``m``, springs ``k``
    (k[0] to ground, k[i] between masses i-1 and i). Returns (omega, Phi (n, n), M, K)."""
    n = len(m)
    kk = np.zeros((n, n))
    for i, ki in enumerate(k):
        kk[i, i] += ki
        if i > 0:
            kk[i - 1, i - 1] += ki
            kk[i - 1, i] -= ki
            kk[i, i - 1] -= ki
    mm = np.diag(m)
    lam, phi = scipy.linalg.eigh(kk, mm)
    for j in range(n):
        if phi[np.argmax(np.abs(phi[:, j])), j] < 0:
            phi[:, j] *= -1
    return np.sqrt(lam), phi, mm, kk


def steady_state(t, x, hz: float, cycles: int) -> complex:
    """Complex amplitude X e^{i phi} of x = |X| sin(w t + phi), fitted over the last ``cycles``
    whole drive cycles (least squares on sin and cos)."""
    w = 2 * math.pi * hz
    keep = t >= t[-1] - cycles / hz + 1e-12
    a = np.column_stack([np.sin(w * t[keep]), np.cos(w * t[keep])])
    (s, c), *_ = np.linalg.lstsq(a, x[keep], rcond=None)
    return complex(s, c)


def receptance(hz: float, m, k, c) -> np.ndarray:
    """(n, n) complex receptance (K - w^2 M + i w C)^-1 of a linear system."""
    w = 2 * math.pi * hz
    return np.linalg.inv(k - w * w * m + 1j * w * c)
