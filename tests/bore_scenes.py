"""Scenes shared by the analytic wall tests (tests/solver/test_cylinder_cavity.py,
test_capsule_cavity.py): a steel sphere in a bore along x from A = origin to B = (length, 0, 0)
(x3dpd.deck.generate.cylinder_cavity_deck), a head-on impact on its wall at V, and Hertz's
closed form for that impact."""

from __future__ import annotations

import numpy as np

import reference as ref
from factories import STEEL_E, STEEL_NU, STEEL_R, STEEL_RHO, sphere_mass

from x3dpd.deck.generate import Material3, cylinder_cavity_deck
from x3dpd.model.build import build_model
from x3dpd.solver.simulation import Simulation

M = sphere_mass()
K_WALL = ref.hertz_k(STEEL_E / (1.0 - STEEL_NU**2), STEEL_R)
V = 62.832
LENGTH = 0.8
BIG_R = 0.3
STRUCTURE = {"structure_mass": 1e-3, "stiffness": 10.0, "damping": 0.0}


def bore_deck(
    shape,
    pos,
    vel,
    *,
    dt,
    tmax,
    mu=0.3,
    facets=None,
    free_dofs=(),
    itrac=1,
    radius=STEEL_R,
    e=STEEL_E,
    length=LENGTH,
    big_r=BIG_R,
    structure=None,
):
    """Spheres at ``pos`` moving at ``vel`` in a ``shape`` ("cylinder", "capsule") on a
    spring-mounted master, no gravity; ``facets`` n: the same shape as CONTACT triangles."""
    mat = Material3(e, 0.0, 1.0, STEEL_NU, mu, STEEL_RHO)
    return cylinder_cavity_deck(
        length=length,
        cavity_radius=big_r,
        particles=pos,
        radius=radius,
        material=mat,
        facets=facets,
        gravity=(0.0, 0.0, 0.0),
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        free_dofs=free_dofs,
        velocities=vel,
        shape=shape,
        **(structure or STRUCTURE),
    )


def head_on_impact(shape, pos, vel, approach):
    """Run one sphere touching a fixed ``shape``'s wall at t = 0, moving into it at V, at
    dt = t_c / 2000 for 1.15 t_c; the closed form, and per output the time, the approach
    ``approach(x)`` and the velocity component along ``vel``. Head-on, friction (on, as in
    the other scenes: one compiled loop) has no slip to act on."""
    h = ref.hertz_impact(M, K_WALL, V)
    dt = h.contact_time / 2000
    sim = Simulation(build_model(bore_deck(shape, [pos], [vel], dt=dt, tmax=1.0)))
    first = sim.snapshot()
    block = sim.advance(2300)
    t = np.concatenate([first.times, block.times])
    data = np.concatenate([first.data, block.data])[:, 1]  # trace: master, then the sphere
    unit = np.asarray(vel) / np.linalg.norm(vel)
    return h, t, approach(data[:, :3]), data[:, 3:6] @ unit


def check_against_hertz(h, t, a, v_in):
    """Contact time, maximum approach and rebound speed within 2e-5 (velocity Verlet at 2000
    steps per contact errs by O((pi/2000)^2) ~ 2.5e-6; the interpolated zero crossing and the
    parabola-refined peak are O(dt^2) and O(dt^3): the bound of tests/physics/test_hertz.py's
    flat-wall impact, which this must equal -- the wall law uses the flat-wall Hertz stiffness
    and does not see the curvature)."""
    contact = ref.zero_crossing(t, a, falling=True)
    errors = {
        "contact time": contact / h.contact_time - 1,
        "max approach": ref.refined_peak(a) / h.a_max - 1,
        "rebound speed": -v_in[-1] / V - 1,
    }
    for name, err in errors.items():
        assert abs(err) < 2e-5, (name, err)
    assert a[-1] < 0.0


def angular_momentum(model, state):
    """Total angular momentum about the origin: spheres m x v + I omega, and the rigid cavity
    (its mass and inertia tensor at the master node) M x_m v_m + R J R^T omega."""
    x, v = state.x, state.vel
    total = np.zeros(3)
    for i in range(model.particle_start, model.n_nodes):
        total += model.mass[i] * np.cross(x[i], v[i, :3]) + model.inertia[i] * v[i, 3:]
    m = int(model.rigid_master[0])
    rot = state.rot[0]
    inertia = rot @ model.rigid_inertia[0] @ rot.T
    return total + model.rigid_mass[0] * np.cross(x[m], v[m, :3]) + inertia @ v[m, 3:]
