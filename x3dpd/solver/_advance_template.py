"""Template of the explicit time-step loop (report Section 7.3), specialised per scene.

:func:`x3dpd.solver.variants.make_advance` copies this file and its parts -- what every contact
shares (``_template_contact.py``), the wall contacts (``_template_walls.py``), the pair
contacts (``_template_pairs.py``), the energies (``_template_energy.py``) -- into x3dpd's kernel
cache with the constants of one scene in their copy of ``_template_variant.py`` (which effects
exist, how many Maxwell terms, which laws and wall shapes), so numba compiles exactly the
effects the scene calls for -- absent effects are constant-false branches that never reach the
machine code -- and caches the result on disk.

Integration: velocity Verlet (central difference) with a constant step,

    v(n+1/2) = v(n) + dt/2 a(n);  x(n+1) = x(n) + dt v(n+1/2);  forces f(n+1) from x(n+1), v(n+1/2);
    v(n+1) = v(n+1/2) + dt/2 a(n+1).

Velocity-dependent forces (dampers, friction, wall velocities) use the half-step velocity, as
X3D's central-difference scheme does. The kernels take the named bundles of
:mod:`x3dpd.solver.bundles` (``nodes``, ``particles``, ``walls`` ...), never positional arrays;
the per-step ones are inlined into ``advance`` (x3dpd._jit.step_kernel).
"""

import math

from x3dpd._jit import loop_kernel, step_kernel
from x3dpd.geometry.cells import _find_pairs
from x3dpd.geometry.faces import (_build_wall_list, _face_offsets, _face_planes,
                                  _forget_frames)
from x3dpd.solver._template_contact import NONFINITE, OK, REALLOC_PAIRS, REALLOC_WALLS
from x3dpd.solver._template_energy import _energies, _ledger_row
from x3dpd.solver._template_pair_passes import _pair_contacts
from x3dpd.solver._template_variant import (FILLED_DRIFT, FILLED_FIRST_HALF_KICK,
                                            FILLED_FOLLOW, FILLED_FORCE, FILLED_GATHER,
                                            FILLED_KICK, FILLED_PLACE, FILLED_SECOND_HALF_KICK,
                                            HAS_ONE_WALL_KIND, HAS_PAIRS, HAS_SHAPES,
                                            HAS_WALLS, HAS_WALLS_TRANSLATE, SLOT_DRIFT,
                                            SLOT_FIRST_HALF_KICK, SLOT_FOLLOW, SLOT_FORCE,
                                            SLOT_GATHER, SLOT_KICK, SLOT_PLACE,
                                            SLOT_SECOND_HALF_KICK, UNIT_BUNDLES)
from x3dpd.solver._template_walls import _shape_contacts, _wall_contacts
from x3dpd.solver.bundles import (ContactList, Faces, Nodes, Output, Particles, RigidBodies,
                                  Shapes, Stepping)
from x3dpd.solver.contact_lists import _active_flags, _merge_states, _pair_approach


@step_kernel
def _force_terms(t, nodes, rigid, particles, faces, walls, pairs, shapes, units, stepping):
    """Add every force but the body forces (which ``nodes.force`` holds on entry) at time t:
    the effect units' (slot ``force``: the external forces among them, last), the wall and
    pair contacts; then the units' slot ``gather`` (the rigid slaves' forces onto their
    masters). Returns the contacts' status bits."""
    x = nodes.x
    status = OK
    if FILLED_FORCE:
        SLOT_FORCE(units, nodes, rigid, stepping, t)
    if HAS_WALLS:
        if HAS_WALLS_TRANSLATE:
            _face_offsets(x, faces.tri_nodes, faces.first_tri, faces.normal, faces.offset)
        else:
            _face_planes(x, faces.tri_nodes, faces.tri_sign, faces.first_tri, faces.normal,
                         faces.offset)
        if HAS_ONE_WALL_KIND:
            # the triangles' barycentric frames for the locator of the wall columns, computed
            # face by face when a step first locates a contact on the face (_wall_gather)
            _forget_frames(faces.tri_frame)
        # the rebuild's scratch is free while forces run
        status |= _wall_contacts(nodes, particles, faces, walls, stepping,
                                 stepping.small[6:9], walls.first_new)
    if HAS_SHAPES:
        status |= _shape_contacts(nodes, particles, shapes, stepping, stepping.small[6:9],
                                  faces.offset.shape[0])
    if HAS_PAIRS:
        status |= _pair_contacts(nodes, particles, pairs, stepping, pairs.first_new)
    if FILLED_GATHER:
        SLOT_GATHER(units, nodes, rigid, stepping, t)
    return status


@step_kernel
def _lists_upkeep(now, nodes, particles, faces, walls, pairs, stepping):
    """Rebuild the contact lists at this step boundary when ``now`` or when the skin may be
    used up: the bound of the displacements at this step's force evaluation, what has
    accumulated since the last build plus this step's drift (2 x the last step's, to allow for
    acceleration). ``stepping.nbr`` = [displacement bound of particles, of wall nodes, rebuild
    count, list state (-1: rebuild now), last largest particle speed, last largest wall-node
    speed, unused]. Returns REALLOC_WALLS / REALLOC_PAIRS when a list is full, else OK."""
    if not (HAS_WALLS or HAS_PAIRS):
        return OK
    nbr, dt, skin = stepping.nbr, stepping.dt, stepping.skin
    dp = nbr[0] + 2.0 * dt * nbr[4]
    dw = nbr[1] + 2.0 * dt * nbr[5]
    if now or nbr[3] < 0.0 or 2.0 * dp > skin or dp + dw > skin:
        full = _rebuild_lists(nodes, particles, faces, walls, pairs, skin)
        if full != OK or now:
            return full
        nbr[0] = 0.0
        nbr[1] = 0.0
        nbr[2] += 1.0
        nbr[3] = 1.0
    return OK


@step_kernel
def _rebuild_lists(nodes, particles, faces, walls, pairs, skin):
    """Rebuild the candidate lists of walls and pairs within ``skin``, carrying the histories of
    lasting contacts over. Returns REALLOC_WALLS / REALLOC_PAIRS when a list is full (the
    caller grows it and calls again), else OK."""
    x, p0, radius = nodes.x, particles.p0, particles.radius
    if HAS_WALLS:
        m = _build_wall_list(x, p0, radius, particles.cavity, faces.cav_ptr, faces.cav_faces,
                             faces.normal, faces.offset, faces.tri_ptr, faces.tris,
                             faces.tri_nodes, skin, walls.first_new, walls.second_new,
                             walls.approach_new)
        if m < 0:
            return REALLOC_WALLS
        _adopt_new_list(walls, m)
    if HAS_PAIRS:
        npart = radius.shape[0]
        xp = x[p0:p0 + npart]
        m = _find_pairs(xp, radius, particles.cavity, skin, pairs.first_new, pairs.second_new)
        if m < 0:
            return REALLOC_PAIRS
        _pair_approach(x, p0, radius, pairs.first_new, pairs.second_new, m, pairs.approach_new)
        _adopt_new_list(pairs, m)
    return OK


@step_kernel
def _adopt_new_list(lst, m):
    """Make the rebuilt list (``*_new``, ``m`` entries) the live one, with carried histories."""
    _merge_states(lst.first, lst.second, lst.state, lst.count[0], lst.first_new,
                  lst.second_new, lst.state_new, m, lst.approach_new)
    for k in range(m):
        lst.first[k] = lst.first_new[k]
        lst.second[k] = lst.second_new[k]
        for c in range(lst.state.shape[1]):
            lst.state[k, c] = lst.state_new[k, c]
    _active_flags(lst.state, m, lst.on)
    lst.count[0] = m


@step_kernel
def _drift(synced, flat, t_old, t, nodes, rigid, particles, units, stepping):
    """The first half kick (unless the last step's second one already did it: ``synced``
    False): the units' slot ``first_half_kick`` (the rigid bodies' rotation), then the nodes',
    which also resets the forces to the body forces; the drift of every node from ``t_old`` to
    ``t``, the units' slot ``drift`` (the rigid bodies' turn first, the prescribed motions'
    last), their slot ``follow`` (the rigid slaves first, which report their largest speed in
    ``nbr[5]``); and the bound of the displacements the contact lists' skin must cover
    (``stepping.nbr``)."""
    x, vel = nodes.x, nodes.vel
    dt, nbr = stepping.dt, stepping.nbr
    if synced:
        if FILLED_FIRST_HALF_KICK:
            SLOT_FIRST_HALF_KICK(units, nodes, rigid, stepping, t)
        vf, ff, imf, fbf = flat
        for k in range(vf.shape[0]):
            vf[k] += 0.5 * dt * ff[k] * imf[k]
            ff[k] = fbf[k]
    for i in range(particles.p0):
        x[i, 0] += dt * vel[i, 0]
        x[i, 1] += dt * vel[i, 1]
        x[i, 2] += dt * vel[i, 2]
    vmax2 = 0.0
    for i in range(particles.p0, x.shape[0]):
        x[i, 0] += dt * vel[i, 0]
        x[i, 1] += dt * vel[i, 1]
        x[i, 2] += dt * vel[i, 2]
        if HAS_WALLS or HAS_PAIRS:
            v2 = vel[i, 0] * vel[i, 0] + vel[i, 1] * vel[i, 1] + vel[i, 2] * vel[i, 2]
            vmax2 = max(vmax2, v2)
    if FILLED_DRIFT:
        SLOT_DRIFT(units, nodes, rigid, stepping, t, t_old)
    nbr[5] = 0.0   # the largest speed of a carried node: the follow hooks report it
    if FILLED_FOLLOW:
        SLOT_FOLLOW(units, nodes, rigid, stepping, t)
    nbr[4] = math.sqrt(vmax2)
    nbr[0] += dt * nbr[4]
    nbr[1] += dt * nbr[5]


@step_kernel
def _flat(nodes):
    """Velocities, forces, inverse masses and body forces as flat arrays (n * 6): views, taken
    once a call (a reshape in the step costs a call into numba's runtime)."""
    return (nodes.vel.reshape(-1), nodes.force.reshape(-1), nodes.inv_m.reshape(-1),
            nodes.fbody.reshape(-1))


@step_kernel
def _body_forces(flat):
    """Every force starts from the body forces (gravity's m g: x3dpd.physics.gravity)."""
    _, ff, _, fbf = flat
    for k in range(ff.shape[0]):
        ff[k] = fbf[k]


@step_kernel
def _after_forces(t_old, t, nodes, rigid, units, stepping):
    """What takes the step's summed forces: the units' slot ``kick`` (the prescribed motions'
    actuator work among them)."""
    if FILLED_KICK:
        SLOT_KICK(units, nodes, rigid, stepping, t, t_old)


@step_kernel
def _kick_on(t, flat, nodes, rigid, units, stepping):
    """This step's second half kick and the next step's first in one pass over memory (no
    full-step velocities wanted): the units' slots ``second_half_kick`` and
    ``first_half_kick`` (the rigid bodies' rotation), then the nodes', computed as
    (v + h a) + h a so that the rounding -- and so every trajectory -- is bit for bit the same
    whichever steps end a call; the forces reset to the body forces."""
    h = 0.5 * stepping.dt
    if FILLED_SECOND_HALF_KICK:
        SLOT_SECOND_HALF_KICK(units, nodes, rigid, stepping, t)
    if FILLED_FIRST_HALF_KICK:
        SLOT_FIRST_HALF_KICK(units, nodes, rigid, stepping, t)
    vf, ff, imf, fbf = flat
    for k in range(vf.shape[0]):
        vf[k] = (vf[k] + h * ff[k] * imf[k]) + h * ff[k] * imf[k]
        ff[k] = fbf[k]


@step_kernel
def _kick_to_end(t, flat, nodes, rigid, units, stepping):
    """The second half kick to full-step velocities -- the nodes', then the units' slot
    ``second_half_kick`` (the rigid bodies' rotation) -- and what follows them: the units' slot
    ``place`` (the prescribed motions' first, the rigid slaves after the modes)."""
    h = 0.5 * stepping.dt
    vf, ff, imf, _ = flat
    for k in range(vf.shape[0]):
        vf[k] += h * ff[k] * imf[k]
    if FILLED_SECOND_HALF_KICK:
        SLOT_SECOND_HALF_KICK(units, nodes, rigid, stepping, t)
    if FILLED_PLACE:
        SLOT_PLACE(units, nodes, rigid, stepping, t)


@step_kernel
def _output_row(t, row, nodes, particles, walls, pairs, shapes, units, stepping, output):
    """Row ``row`` of the output buffers at time t: the trace nodes' x, v, omega and the
    energy ledger row (the energies also in ``stepping.small[0:6]``). Returns NONFINITE when a
    traced value or the residual is inf or NaN (caught here, cheaply, before it reaches the
    trace), else OK."""
    x, vel, data = nodes.x, nodes.vel, output.data
    trace_nodes = output.trace_nodes
    for k in range(trace_nodes.shape[0]):
        i = trace_nodes[k]
        for d in range(3):
            data[row, k, d] = x[i, d]
        for d in range(6):
            data[row, k, 3 + d] = vel[i, d]
    output.times[row] = t
    en = stepping.small[0:6]   # energies at an output step
    _energies(nodes, particles, walls, pairs, shapes, units, stepping.dt, en)
    _ledger_row(t, en, stepping.ledger, output.e_ref, output.energy[row])
    bad = False
    for k in range(trace_nodes.shape[0]):
        for d in range(9):
            if not math.isfinite(data[row, k, d]):
                bad = True
    if bad or not math.isfinite(output.energy[row, 11]):
        return NONFINITE
    return OK


#: What one call of the step loop does (its ``mode``): everything goes through the one entry
#: :func:`advance_packed`, so that numba compiles the force terms, the list rebuild and the
#: energies once per variant (inlined there, each at its one call site) instead of once more
#: for separate Python-facing kernels.
STEP = 0      # advance up to ``nsteps`` steps
REBUILD = 1   # rebuild the contact lists now (t0, a grown list); no step, ``nbr`` untouched
FORCES = 2    # every force at ``t_start`` from the current state into nodes.force; no step
SNAPSHOT = 3  # the output row of the current state at ``t_start`` (its energies also in
#               stepping.small[0:6]); no step, no list rebuild


@loop_kernel
def advance_packed(mode, nsteps, step0, t_start, packed):
    """Advance up to ``nsteps`` steps from step index ``step0`` (time t_start + step0 dt)
    (``mode`` STEP), or only rebuild the contact lists (REBUILD) or only evaluate the forces at
    ``t_start`` (FORCES: ``step0`` = -1, ``nsteps`` = 1; the ledger given is the caller's), or
    only write the output row of the current state at ``t_start`` (SNAPSHOT: ``step0`` = -1,
    ``nsteps`` = 1; the energies also in ``stepping.small[0:6]``).

    ``packed``: the bundles as plain tuples in ADVANCE_BUNDLES order, the effect units' as a
    tuple of them (x3dpd.solver.bundles.pack): numba checks the types of plain tuples of arrays
    in C, but of named tuples in Python, which cost ~0.1 ms a call -- as much as a hundred steps
    of a small scene. The named tuples are rebuilt here, in compiled code, at no cost.

    A step is a fixed sequence (x3dpd.physics.effect_unit, "The slots"): the lists' upkeep
    (``stepping.nbr``, see ``_lists_upkeep``), the kick and drift (``_drift``), the forces
    (``_force_terms``), what takes them (``_after_forces``), the second half kick (``_kick_on``,
    or ``_kick_to_end`` when full-step velocities are wanted), the output row (``_output_row``,
    every ``output.itrac``-th step). This loop allocates nothing (x3dpd._jit.loop_kernel).
    Returns (status, steps done, rows written); the run stops at the first non-zero status or a
    full output buffer.
    """
    (nodes_, rigid_, particles_, faces_, walls_, pairs_, shapes_, units_, stepping_,
     output_) = packed
    nodes, rigid = Nodes(*nodes_), RigidBodies(*rigid_)
    particles, faces, walls, pairs = (Particles(*particles_), Faces(*faces_),
                                      ContactList(*walls_), ContactList(*pairs_))
    shapes, units = Shapes(*shapes_), UNIT_BUNDLES(units_)
    stepping, output = Stepping(*stepping_), Output(*output_)
    dt, diag = stepping.dt, stepping.diag
    flat = _flat(nodes)
    rows = 0
    synced = True   # vel holds full-step velocities and force the forces of this step
    out_in = output.itrac - step0 % output.itrac   # steps to the next trace output
    for it in range(nsteps):
        step = step0 + it
        if mode == STEP or mode == REBUILD:   # FORCES and SNAPSHOT use the lists as they are
            full = _lists_upkeep(mode == REBUILD, nodes, particles, faces, walls, pairs,
                                 stepping)
            if full != OK:
                return full, it, rows
        if mode == REBUILD:
            return OK, 0, 0
        t = t_start + (step + 1) * dt
        st = OK
        if mode == SNAPSHOT:
            out_in = 0   # no step: straight to the output row of the current state
        else:
            if mode == FORCES:
                _body_forces(flat)
            else:
                _drift(synced, flat, t_start + step * dt, t, nodes, rigid, particles, units,
                       stepping)
            st = _force_terms(t, nodes, rigid, particles, faces, walls, pairs, shapes, units,
                              stepping)
            if mode == FORCES:
                return st, 0, 0
            _after_forces(t_start + step * dt, t, nodes, rigid, units, stepping)
            out_in -= 1
            synced = st != OK or it == nsteps - 1 or out_in == 0
            if not synced:
                _kick_on(t, flat, nodes, rigid, units, stepping)
                continue
            _kick_to_end(t, flat, nodes, rigid, units, stepping)
            if st != OK:
                diag[4] = t
                diag[5] = step + 1
                return st, it + 1, rows
        if out_in == 0:
            out_in = output.itrac
            st = _output_row(t, rows, nodes, particles, walls, pairs, shapes, units, stepping,
                             output)
            rows += 1
            if mode == SNAPSHOT:
                return OK, 0, rows
            if st != OK:
                diag[4] = t
                diag[5] = step + 1
                return st, it + 1, rows - 1
            if rows >= output.times.shape[0]:
                return OK, it + 1, rows
    return OK, nsteps, rows
