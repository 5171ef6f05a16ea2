"""A structure given by its modes (MODAL card; x3dpd.physics.modal) against closed forms.

* One mode equal to the report's Table 4 SDOF gives that SDOF deck's trajectory.
* A 2-DOF chain given as its modes, with a lumped mass added in the deck, has the closed-form
  FRF of the chain with that mass (the deck's mass coupled into the modes).
* A two-mode structure's steady state matches its closed-form FRF at, between and beside both
  resonances, within 0.5 % and 0.5 degrees.
* A mode 100x above the step's Nyquist frequency stays bounded for 10^6 steps and the ledger
  stays exact (the per-mode step is exact under a constant force).

All decks here share one compiled loop (a modal structure and a built-in force).
"""

from __future__ import annotations

import math

import numpy as np
import pytest


import reference as ref
from factories import TABLE4_C, TABLE4_DRIVE, TABLE4_K, TABLE4_MASS, sdof_deck
from modal_decks import chain_modes, modal_deck, receptance, steady_state

import x3dpd


def _run(tmp_path, text: str, name: str = "modal.inp", **kw):
    path = tmp_path / name
    path.write_text(text)
    return x3dpd.run(str(path), **kw)


def _x(result, row: int = 0, dof: int = 0):
    """Times and the displacement of trace row ``row`` along ``dof`` (from its start)."""
    x = result.trace.position[:, row, dof]
    return result.trace.times, x - x[0]


# ---- one mode = the SDOF deck ------------------------------------------------------------------
def _sdof_as_mode(dt, tmax, hz):
    wn = math.sqrt(TABLE4_K / TABLE4_MASS)
    zeta = TABLE4_C / (2 * math.sqrt(TABLE4_K * TABLE4_MASS))
    return modal_deck(
        dt=dt,
        tmax=tmax,
        itrac=10,
        modes=[(1, wn / (2 * math.pi), zeta)],
        shapes=[(1, 1, [1.0 / math.sqrt(TABLE4_MASS)])],
        drive=f"sine:node=1,dof=1,amp={TABLE4_DRIVE!r},hz={hz!r}",
    )


def test_one_mode_gives_the_sdof_decks_trajectory(tmp_path):
    """Same physics, two integrators of m x'' + c x' + k x = F sin(w t) from rest, 1 s:

    * the mode (the exact free oscillator plus a linearly varying force) is second order: its
      error against the exact solution is below 2.5e-6 of the amplitude at dt = 1e-5 s and grows
      4x (3.5 ... 4.5) when the step doubles;
    * the SDOF deck (velocity Verlet) is first order in its damper: c v at the half step lags by
      dt/2, an extra stiffness c w^2 dt/2, which shifts w_n by c dt/(4 m) = 4.1e-6 and so the
      transient's phase by 1e-3 rad after 1 s: an error of ~5e-4 of the amplitude.

    So the two trajectories must agree within 6e-4 of the amplitude (the SDOF deck's own error),
    and the mode must be the one converging at second order."""
    hz, tmax = 37.21, 1.0
    s = ref.Sdof(TABLE4_MASS, TABLE4_K, TABLE4_C, TABLE4_DRIVE, 2 * math.pi * hz)
    err = {}
    for dt in (1e-5, 2e-5):
        res = _run(tmp_path, _sdof_as_mode(dt, tmax, hz))
        t, xm = _x(res)
        sd = x3dpd.run(sdof_deck(dt=dt, hz=hz, itrac=10, v0=0.0), tmax=tmax)
        ts, xs = _x(sd)
        assert np.array_equal(t, ts)
        exact = s.response(t)
        err[dt] = np.abs(xm - exact).max() / s.amplitude
        if dt == 1e-5:
            assert np.abs(xm - xs).max() < 6e-4 * s.amplitude
    assert err[1e-5] < 2.5e-6
    assert 3.5 < err[2e-5] / err[1e-5] < 4.5


# ---- a 2-DOF chain as modes, a lumped mass added in the deck -----------------------------------
CHAIN_M = (2.0e-3, 1.0e-3)  # lbf s^2/in
CHAIN_K = (40.0, 25.0)  # lbf/in (ground-1, 1-2)
CHAIN_ZETA = (0.03, 0.04)
ADDED = 0.5e-3  # lbf s^2/in lumped on node 2 by the deck's MASS card


@pytest.mark.parametrize("factor", [0.85, 1.0, 1.6, 2.9])
def test_two_dof_chain_with_added_mass_has_its_closed_form_frf(tmp_path, factor):
    """The chain's modes (without ADDED) go in the MODAL card, ADDED goes on node 2's MASS
    record; the response must be the closed-form FRF of the chain *with* ADDED,
    (K - w^2 (M + M_a) + i w C)^-1 F, C = M Phi diag(2 zeta w) Phi^T M the damping the given
    modes have. Driven at node 1 at multiples of the coupled first mode; both nodes within
    0.5 % and 0.5 degrees once the transient has died (e^{-zeta w t} < 1e-7)."""
    omega, phi, mm, kk = chain_modes(CHAIN_M, CHAIN_K)
    cc = mm @ phi @ np.diag(2 * np.array(CHAIN_ZETA) * omega) @ phi.T @ mm
    ma = np.diag([0.0, ADDED])
    lam = np.sort(np.real(np.linalg.eigvals(np.linalg.solve(mm + ma, kk))))
    hz = factor * math.sqrt(lam[0]) / (2 * math.pi)
    drive = 0.01
    settle = math.log(1e7) / (min(CHAIN_ZETA) * math.sqrt(lam[0]))
    dt = 2e-5
    tmax = round((settle + 5 / hz) / dt) * dt
    res = _run(
        tmp_path,
        modal_deck(
            dt=dt,
            tmax=tmax,
            itrac=5,
            modes=[
                (k + 1, w / (2 * math.pi), z) for k, (w, z) in enumerate(zip(omega, CHAIN_ZETA))
            ],
            shapes=[(1, 1, phi[0]), (2, 1, phi[1])],
            masses=[(2, ADDED)],
            drive=f"sine:node=1,dof=1,amp={drive!r},hz={float(hz)!r}",
        ),
    )
    h = receptance(hz, mm + ma, kk, cc)[:, 0] * drive
    for node in (0, 1):
        t, x = _x(res, node)
        got = steady_state(t, x, hz, 5)
        assert abs(got) == pytest.approx(abs(h[node]), rel=5e-3)
        assert math.degrees(abs(np.angle(got / h[node]))) < 0.5


# ---- a two-mode structure against its FRF -------------------------------------------------------
TWO = [(1, 6.0, 0.04), (2, 17.0, 0.05)]
PHI = {1: (20.0, 14.0), 2: (9.0, -25.0)}  # node -> shape values of modes 1, 2


@pytest.mark.parametrize("hz", [4.5, 6.0, 11.0, 17.0, 21.0])
def test_two_mode_structure_matches_its_frf(tmp_path, hz):
    """Beside, at, between, at and beside the two resonances: the steady-state response at both
    nodes to F sin(w t) at node 1 against H = sum_k phi_o phi_i / (w_k^2 - w^2 + 2 i zeta_k
    w_k w), within 0.5 % in amplitude and 0.5 degrees in phase."""
    drive = 0.002
    wk = np.array([2 * math.pi * f for _, f, _ in TWO])
    zk = np.array([z for _, _, z in TWO])
    settle = math.log(1e7) / (zk.min() * wk.min())
    dt = 1e-4
    tmax = round((settle + 5 / hz) / dt) * dt
    res = _run(
        tmp_path,
        modal_deck(
            dt=dt,
            tmax=tmax,
            itrac=2,
            modes=TWO,
            shapes=[(n, 1, v) for n, v in PHI.items()],
            drive=f"sine:node=1,dof=1,amp={drive!r},hz={float(hz)!r}",
        ),
    )
    w = 2 * math.pi * hz
    for row, node in enumerate((1, 2)):
        h = (
            sum(
                PHI[node][k] * PHI[1][k] / (wk[k] ** 2 - w * w + 2j * zk[k] * wk[k] * w)
                for k in range(2)
            )
            * drive
        )
        t, x = _x(res, row)
        got = steady_state(t, x, hz, 5)
        assert abs(got) == pytest.approx(abs(h), rel=5e-3)
        assert math.degrees(abs(np.angle(got / h))) < 0.5


# ---- a mode far above the step's Nyquist frequency ----------------------------------------------
def test_mode_far_above_nyquist_stays_bounded_and_the_ledger_exact(tmp_path):
    """Mode 2 at 100.3 x the Nyquist frequency 1/(2 dt), undamped, with mode 1 under a
    constant force for 10^6 steps: the displacement never leaves the exact envelope
    |u| <= sum_k 2 |phi_k|^2 F / w_k^2 (each mode oscillates about its static deflection
    phi F / w^2 with that amplitude), and the ledger (energies minus the force's work) stays
    exact: the per-mode step is the exact solution under a constant force, so only rounding is
    left (< 1e-9 of the energy scale)."""
    dt = 1e-4
    f2 = 100.3 / (2 * dt)
    force = 0.5
    phi = (10.0, 3.0)
    res = _run(
        tmp_path,
        modal_deck(
            dt=dt,
            tmax=1e6 * dt,
            itrac=1000,
            modes=[(1, 21.7, 0.0), (2, f2, 0.0)],
            shapes=[(1, 1, phi)],
            drive=f"constant:node=1,dof=1,amp={force!r}",
        ),
    )
    assert res.summary["steps"] == 1_000_000
    w = (2 * math.pi * 21.7, 2 * math.pi * f2)
    bound = sum(2 * p * p * force / wk**2 for p, wk in zip(phi, w))
    t, x = _x(res)
    assert np.abs(x).max() <= bound * (1 + 1e-9)
    assert np.abs(x).max() > 0.5 * bound  # it did move
    e = res.energy
    scale = np.abs(e["external_work"]).max()
    assert np.abs(e["residual"]).max() < 1e-9 * scale
