"""Placing a step loop's state before a run: the structure put on a motion a tool predicted, the
particles carried along with their body, and the energy this adds booked in the ledger.

These are the public operations the tools above the API use on a :class:`~x3dpd.solver.
simulation.Simulation` they hold (x3dpd.api.stepper; a sweep point's predicted start,
x3dpd.design.predict), so that none of them touches the loop's kernels or writes its state
arrays itself. A placement is a sequence of them:

1. ``e_before = total_energy(sim)``, the energy the ledger counts now;
2. :func:`place_structure` (every node free along a DOF translated together),
   :func:`place_modes` (a modal structure on its modal coordinates, the particles carried with
   the body that holds their cavity) or :func:`put_on_motion` (prescribed nodes on their
   motion at a time), in any combination;
3. :func:`book_energy_change`: wall planes and forces at the placed state, the modal forces and
   the actuators' forces from them, and the change of energy, ``total_energy(sim) - e_before``,
   added to the ledger's reference energy ``state.e_ref`` -- so that the residual stays
   continuous (docs/physics.md, "Energy ledger").

The state is then the one a run continues from (``FinalState(state=sim.state, ...)``).
"""

from __future__ import annotations

import numpy as np

from x3dpd.physics.motion import apply_motion


def total_energy(sim) -> float:
    """Kinetic + potential + stored contact energy minus the Verlet term, as the ledger counts
    it (docs/physics.md, "Energy ledger") [energy]."""
    en = sim.energy_now()
    return float(en[:5].sum() - en[5])


def place_structure(
    sim, node: int, dof: int, displacement: float, velocity: float, keep=()
) -> None:
    """Translate every node free along ``dof`` (1, 2, 3) -- the structure, its cavity and the
    particles in it -- by one change, so that the node of index ``node`` (``model.index_of``
    of its id) stands at its initial position + ``displacement`` [length] with ``velocity``
    [length/s] along ``dof``; the nodes of index in ``keep`` stay where they are. The particles
    keep their places, contacts and histories relative to the cavity; only springs to ground
    and to the kept nodes see the change."""
    state, model = sim.state, sim.model
    d = dof - 1
    dx = model.x0[node, d] + displacement - state.x[node, d]
    dv = velocity - state.vel[node, d]
    moving = ~np.asarray(model.fixed[:, d])
    moving[list(keep)] = False
    state.x[moving, d] += dx
    state.vel[moving, d] += dv


def place_modes(sim, q: np.ndarray, p: np.ndarray) -> None:
    """Put a modal structure (MODAL card) on the modal coordinates ``q`` and momenta ``p``
    (x3dpd.physics.modal): its modal nodes and their rigid bodies placed from them, the
    particles carried along with the body that holds their cavity's walls
    (:func:`carry_particles`), every rigid body's slaves on their master."""
    state, k = sim.state, sim.setup
    poses = body_poses(sim)
    state.mq[:] = q
    state.mp[:] = p
    modal = sim._bundles()["modal"]
    sim.kernels._modal_place(modal, state.x, k.x0, state.vel, state.rot, state.mp, True)
    carry_particles(sim, poses)
    follow_masters(sim)


def body_poses(sim) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Rigid body -> (its master's position, its velocity (6,), the body's rotation matrix),
    copies: where the bodies stand before a placement moves them."""
    state = sim.state
    return {
        b: (state.x[m].copy(), state.vel[m].copy(), state.rot[b].copy())
        for b, m in enumerate(sim.setup.units["rigid_links"]["master"])
    }


def carry_particles(sim, poses: dict) -> None:
    """Move the particles of every cavity whose walls a modal body holds rigidly with that body
    from its pose in ``poses`` (:func:`body_poses`) to where it stands now: positions,
    velocities and the body's turn, so that they keep their places, contacts and histories
    relative to the cavity."""
    state, model, k = sim.state, sim.model, sim.setup
    p0 = model.particle_start
    modal_bodies = set(model.modal.body.tolist())
    for cavity, body in cavity_bodies(model).items():
        if body < 0 or body not in modal_bodies:
            continue
        m = int(k.units["rigid_links"]["master"][body])
        x_m, v_m, r_old = poses[body]
        turn = state.rot[body] @ r_old.T
        mine = p0 + np.flatnonzero(model.particle_cavity == cavity)
        rel = state.x[mine] - x_m
        rel_v = state.vel[mine, :3] - v_m[:3] - np.cross(v_m[3:], rel)
        new_rel = rel @ turn.T
        state.x[mine] = state.x[m] + new_rel
        state.vel[mine, :3] = (
            state.vel[m, :3] + np.cross(state.vel[m, 3:], new_rel) + rel_v @ turn.T
        )


def cavity_bodies(model) -> dict[int, int]:
    """Cavity index -> the rigid body whose slaves carry its walls (-1: none)."""
    owner = np.full(model.n_nodes, -1)
    for b in range(model.rigid_master.shape[0]):
        owner[model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]] = b
        owner[model.rigid_master[b]] = b
    out = {}
    tri_cavity = model.face_cavity[model.tri_face] if model.tri_face.shape[0] else []
    for nodes, c in zip(model.tri_nodes, tri_cavity):
        out.setdefault(int(c), int(owner[nodes[0]]))
    for nodes, c in zip(model.shape_nodes, model.shape_cavity):
        out.setdefault(int(c), int(owner[nodes[0]]))
    return out


def follow_masters(sim) -> None:
    """Every rigid body's slaves placed on their master (position, velocity)."""
    state, rigid = sim.state, sim.setup.units["rigid_links"]
    if rigid["master"].shape[0]:
        sim.kernels._update_slaves(state.x, state.vel, rigid["master"], rigid["ptr"],
                                   rigid["slaves"], rigid["r0"], state.rot, True, True)


def put_on_motion(sim, t: float) -> None:
    """The prescribed nodes (``motion`` specs, docs/usrfrc.md) put on their motion at time
    ``t`` [s], position and velocity; rigid bodies' slaves follow their masters."""
    state = sim.state
    apply_motion(t, sim.motion, sim.setup.x0, state.x, state.vel)
    follow_masters(sim)


def book_energy_change(sim, e_before: float, t: float) -> None:
    """Finish a placement at time ``t`` [s]: wall planes follow the moved nodes, the forces at
    the placed state (the modal forces and the actuators' forces of the prescribed motions
    from them: what the first step starts from), and the energy the placement added,
    ``total_energy(sim) - e_before``, booked in the ledger's reference energy."""
    state = sim.state
    sim.restore(state)  # wall planes follow the moved nodes
    sim.compute_forces(t)
    sim.project_modal_forces()
    state.e_ref += total_energy(sim) - e_before
