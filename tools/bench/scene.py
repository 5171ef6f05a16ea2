"""The benchmark scene shared by x3dpd's benchmark and the LAMMPS peer (``lammps_peer.py``).

Units: inch, lbf, second (the report's units). Mass is lbf*s^2/in, density lbf*s^2/in^4,
modulus psi, acceleration in/s^2.

Scene
-----
``n`` equal steel spheres in a box-shaped cavity, gravity along -y, the cavity shaken along x.

* Particles: radius R = 0.03125 in (the report's 1/16" diameter; the same R for every n -- the
  fill fraction does not depend on R, only on the lattice), density 0.283/386.1 lbf*s^2/in^4,
  elastic Hertz with E = E0 = 27.5e6 psi, E1 = 0 (no Maxwell term), nu = 0.30, friction mu = 0.30.
* Arrangement (like report Appendix A): a simple cubic lattice of ``m x m`` particles per layer
  with m = ceil(n ** (1/3)); the lattice index runs x fastest, then y (up, away from the floor),
  then z (layers), so for n = 50 there are three full 4x4 layers and a last layer of 2 particles
  lying on the floor -- Appendix A's order. Lattice spacing s = 2.05 R in x, y and z; every
  coordinate is jittered by a uniform random amount in [-0.02 R, +0.02 R] (seeded), which
  keeps every pair at least 2.01 R apart and every particle at least 1.005 R from every wall,
  so the start is contact-free.
* Cavity interior: ``box_lo = (0, 0, 0)``, ``box_hi = (m s + 4 R, m s, nz s)`` (nz = number of
  layers): the lattice plus a free length of 4 R along x (2 R on each side, lattice centred) so
  particles hit the x walls when shaken. The bottom row of particles sits on (1.025 R above) the
  floor y = 0. The resulting particle volume fraction is about 0.26 (n = 50), 0.33 (64), 0.39 (512),
  0.43 (4096); without the free length it would be 4/3 pi / 2.05^3 = 0.486.
* Supported counts: any n >= 1; the benchmark set is 50 (Appendix A), 64, 512, 4096.
* Time step dt = 5e-7 s; gravity (0, -386.1, 0) in/s^2.

Two ways to drive the cavity along x at f = 37.21 Hz (omega = 2 pi f), both aiming at a 3 g peak
cavity acceleration (g = 386.1 in/s^2):

1. Prescribed motion (LAMMPS peer): displacement amplitude ``A = 3 g / omega^2``.
2. Force-driven (x3dpd): the cavity + structure is a single-DOF oscillator of mass
   ``m_s = 2.04213e-4`` lbf*s^2/in, spring ``k = 11.4823`` lbf/in and dashpot
   ``c = 3.08293e-4`` lbf*s/in (report Table 4 / App. A), driven by ``F sin(omega t)``. In
   steady state the structure alone (particles ignored) moves with displacement amplitude
   ``X = F / sqrt((k - m_s omega^2)^2 + (c omega)^2)`` and acceleration amplitude
   ``omega^2 X``. Requiring ``omega^2 X = 3 g`` gives the drive amplitude::

       F = 3 g * sqrt((k - m_s * omega**2)**2 + (c * omega)**2) / omega**2

   (about 6.93e-3 lbf). The structure's natural frequency sqrt(k/m_s)/(2 pi) = 37.74 Hz lies just
   above the drive, so F is small and sensitive to k and m_s; the particles (n * m_p, e.g.
   4.8e-5 lbf*s^2/in for n = 512) add mass and shift the real response -- only the structure
   alone is used here, on purpose, so F does not depend on n.
"""

from __future__ import annotations

import math

import numpy as np

G = 386.1  # in/s^2
RADIUS = 0.03125  # in
DENSITY = 0.283 / G  # lbf*s^2/in^4
E0 = 27.5e6  # psi (long-term modulus; E1 = 0 -> elastic Hertz)
NU = 0.30
MU = 0.30
DT = 5e-7  # s
SPACING = 2.05  # lattice spacing in units of R
JITTER = 0.02  # max jitter per coordinate, units of R
FREE_X = 4.0  # free length along x, units of R
SHAKE_HZ = 37.21
SHAKE_G = 3.0  # peak cavity acceleration in g
M_S = 2.04213e-4  # lbf*s^2/in
K_S = 11.4823  # lbf/in
C_S = 3.08293e-4  # lbf*s/in

BENCH_COUNTS = (50, 64, 512, 4096)


def _lattice_side(n: int) -> int:
    m = max(1, round(n ** (1.0 / 3.0)))
    while m**3 < n:
        m += 1
    while m > 1 and (m - 1) ** 3 >= n:
        m -= 1
    return m


def drive_force_amplitude(omega: float, accel: float, m: float, k: float, c: float) -> float:
    """Force amplitude F of ``F sin(omega t)`` giving steady-state acceleration amplitude
    ``accel`` of the SDOF oscillator (m, k, c): ``F = accel*sqrt((k-m w^2)^2+(c w)^2)/w^2``."""
    return accel * math.hypot(k - m * omega**2, c * omega) / omega**2


def _min_pair_distance(pos: np.ndarray, chunk: int = 512) -> float:
    n = len(pos)
    best = math.inf
    for i0 in range(0, n, chunk):
        a = pos[i0 : i0 + chunk]
        d2 = ((a[:, None, :] - pos[None, :, :]) ** 2).sum(axis=2)
        rows = np.arange(len(a))
        d2[rows, i0 + rows] = math.inf
        best = min(best, float(d2.min()) if d2.size else math.inf)
    return math.sqrt(best)


def bench_scene(n_particles: int, seed: int = 0) -> dict:
    """The benchmark scene for ``n_particles`` particles (inch-lbf-s). Deterministic in ``seed``.

    Keys: n, seed, radius, density, particle_mass, E (= E0), E0, E1, nu, mu, positions (n,3),
    box_lo (3,), box_hi (3,) (cavity interior at t = 0), lattice (m, m, nz), spacing,
    fill_fraction, dt, gravity (3,), shake_axis (0 = x), shake_freq_hz, shake_omega,
    shake_accel (3 g), shake_amplitude (A = 3 g / omega^2, prescribed motion),
    structure_mass, structure_k, structure_c, structure_freq_hz (sqrt(k/m_s)/2pi),
    drive_force (F of F sin(omega t), force-driven version, see module docstring).
    """
    n = int(n_particles)
    if n < 1:
        raise ValueError(f"n_particles must be >= 1, got {n_particles!r}")
    R = RADIUS
    s = SPACING * R
    m = _lattice_side(n)
    per_layer = m * m
    nz = -(-n // per_layer)

    idx = np.arange(n)
    ix, iy, iz = idx % m, (idx // m) % m, idx // per_layer
    x_off = 0.5 * FREE_X * R
    lattice = np.column_stack([x_off + (ix + 0.5) * s, (iy + 0.5) * s, (iz + 0.5) * s]).astype(
        np.float64
    )
    rng = np.random.default_rng(seed)
    positions = lattice + rng.uniform(-JITTER * R, JITTER * R, size=(n, 3))
    positions = np.ascontiguousarray(positions, dtype=np.float64)

    box_lo = np.zeros(3)
    box_hi = np.array([m * s + FREE_X * R, m * s, nz * s])

    # The start must be contact-free (guaranteed by construction; checked anyway).
    if n > 1 and _min_pair_distance(positions) < 2.0 * R:
        raise AssertionError("bench_scene: overlapping particles")
    if np.any(positions - R < box_lo) or np.any(positions + R > box_hi):
        raise AssertionError("bench_scene: particle overlaps a wall")

    vol_p = 4.0 / 3.0 * math.pi * R**3
    omega = 2.0 * math.pi * SHAKE_HZ
    accel = SHAKE_G * G
    return {
        "n": n,
        "seed": int(seed),
        "radius": R,
        "density": DENSITY,
        "particle_mass": DENSITY * vol_p,
        "E": E0,
        "E0": E0,
        "E1": 0.0,
        "nu": NU,
        "mu": MU,
        "positions": positions,
        "box_lo": box_lo,
        "box_hi": box_hi,
        "lattice": (m, m, nz),
        "spacing": s,
        "fill_fraction": n * vol_p / float(np.prod(box_hi - box_lo)),
        "dt": DT,
        "gravity": np.array([0.0, -G, 0.0]),
        "shake_axis": 0,
        "shake_freq_hz": SHAKE_HZ,
        "shake_omega": omega,
        "shake_accel": accel,
        "shake_amplitude": accel / omega**2,
        "structure_mass": M_S,
        "structure_k": K_S,
        "structure_c": C_S,
        "structure_freq_hz": math.sqrt(K_S / M_S) / (2.0 * math.pi),
        "drive_force": drive_force_amplitude(omega, accel, M_S, K_S, C_S),
    }


if __name__ == "__main__":  # quick look: python tools/bench/scene.py
    for count in BENCH_COUNTS:
        sc = bench_scene(count)
        print(
            f"n={count:5d} lattice={sc['lattice']} box_hi={np.round(sc['box_hi'], 5)} "
            f"fill={sc['fill_fraction']:.3f} A={sc['shake_amplitude']:.5g} in "
            f"F={sc['drive_force']:.5g} lbf f_s={sc['structure_freq_hz']:.4g} Hz"
        )
