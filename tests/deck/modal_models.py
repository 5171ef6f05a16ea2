"""The analytic models behind tests/fixtures/modes/, computed again from their formulas, and
helpers for the mode-file tests."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "tests" / "fixtures" / "modes"


def make_mode_files():
    """tools/make_mode_files.py as a module (its CHAIN and CANTILEVER parameters, its writers)."""
    spec = importlib.util.spec_from_file_location(
        "make_mode_files", ROOT / "tools" / "make_mode_files.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def need_pynastran():
    """Skip the calling test unless pyNastran's OP2 reader imports."""
    from x3dpd.deck.modes.op2_format import INSTALL_HINT, pynastran_op2

    try:
        pynastran_op2()
        import cpylog  # noqa: F401
    except ImportError:
        pytest.skip(f"pyNastran is not installed (OP2 files); {INSTALL_HINT}")


def chain_closed_form(m: float, k: float, n: int):
    """Fixed-free chain of n masses m and n springs k: f_j [Hz] and mass-normalised shapes
    (n_modes, n): omega_j = 2 sqrt(k/m) sin(theta_j / 2), phi_ij = c_j sin(i theta_j),
    theta_j = (2j - 1) pi / (2n + 1), c_j from sum_i m phi_ij^2 = 1."""
    j = np.arange(1, n + 1)
    theta = (2 * j - 1) * np.pi / (2 * n + 1)
    freq = 2 * np.sqrt(k / m) * np.sin(theta / 2) / (2 * np.pi)
    phi = np.sin(np.outer(theta, np.arange(1, n + 1)))
    phi /= np.sqrt(m * (phi**2).sum(axis=1, keepdims=True))
    return freq, phi


def cantilever_fe(p: dict):
    """Frequencies [Hz] and mass-normalised shapes (modes, nodes, 6) of the clamped bar of
    tools/make_mode_files.py's CANTILEVER, assembled here from the Hermite beam element:
    k = EI/l^3 [[12, 6l, -12, 6l], [6l, 4l^2, -6l, 2l^2], ...],
    m = rho A l / 420 [[156, 22l, 54, -13l], [22l, 4l^2, 13l, -3l^2], ...]; bending in y with
    I_z = h b^3 / 12 (y, rz = dv/dx), in z with I_y = b h^3 / 12 (z, ry = -dw/dx)."""
    ne, L = p["elements"], p["L"]
    le, nn = L / ne, ne + 1
    A = p["b"] * p["h"]
    ke = (
        np.array(
            [
                [12, 6 * le, -12, 6 * le],
                [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                [-12, -6 * le, 12, -6 * le],
                [6 * le, 2 * le**2, -6 * le, 4 * le**2],
            ]
        )
        / le**3
    )
    me = np.array(
        [
            [156, 22 * le, 54, -13 * le],
            [22 * le, 4 * le**2, 13 * le, -3 * le**2],
            [54, 13 * le, 156, -22 * le],
            [-13 * le, -3 * le**2, -22 * le, 4 * le**2],
        ]
    )
    me = me * p["rho"] * A * le / 420
    # one plane at a time: unknowns (v_2, t_2, ..., v_nn, t_nn), node 1 clamped
    freqs, shapes = [], []
    for comp, rot, inertia, rot_sign in (
        (1, 5, p["h"] * p["b"] ** 3 / 12, 1.0),
        (2, 4, p["b"] * p["h"] ** 3 / 12, -1.0),
    ):
        K, M = np.zeros((2 * nn, 2 * nn)), np.zeros((2 * nn, 2 * nn))
        for e in range(ne):
            idx = np.arange(2 * e, 2 * e + 4)
            K[np.ix_(idx, idx)] += p["E"] * inertia * ke
            M[np.ix_(idx, idx)] += me
        lam, vec = scipy.linalg.eigh(K[2:, 2:], M[2:, 2:])
        for r in range(len(lam)):
            shape = np.zeros((nn, 6))
            shape[1:, comp] = vec[0::2, r]
            shape[1:, rot] = rot_sign * vec[1::2, r]
            freqs.append(np.sqrt(lam[r]) / (2 * np.pi))
            shapes.append(shape)
    order = np.argsort(freqs)[: p["modes"]]
    return np.array(freqs)[order], np.array(shapes)[order]


#: beta_n L of a clamped-free Euler-Bernoulli beam: roots of cos(x) cosh(x) = -1.
CANTILEVER_BETA_L = (1.8751040687119611, 4.6940911329741745)


def aligned(actual: np.ndarray, expected: np.ndarray) -> np.ndarray:
    """``expected`` (modes, ...) with each mode's sign chosen to match ``actual``'s: a mode
    shape is defined up to its sign, and the sign of the dot product of the two (over the
    values both have) decides. Only a whole mode is flipped, never one component."""
    both = ~np.isnan(actual) & ~np.isnan(expected)
    dots = np.array([np.sum(actual[r][both[r]] * expected[r][both[r]]) for r in range(len(actual))])
    return expected * np.where(dots < 0, -1.0, 1.0).reshape((-1,) + (1,) * (expected.ndim - 1))
