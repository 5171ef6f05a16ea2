"""The named bundles of arrays the step kernels take, the status flags they return, and the one
place that builds the bundles from a scene's :class:`~x3dpd.solver.state.Setup` and
:class:`~x3dpd.solver.state.State`.

Every kernel of the step loop (``advance``, ``_forces``, ``_energies``, the list rebuild) takes a
handful of these named tuples instead of dozens of positional arrays, so an array is always
reached by name (``nodes.vel``, ``pairs.state``) and two arrays of the same dtype can no longer
be swapped by position. numba compiles a named tuple of arrays as a struct of array descriptors:
a field access costs nothing at run time, and the compiled loop is the same machine code as with
separate arguments (``tools/bench`` instruction counts).

The tuples hold references to the state's arrays (the kernels update them in place); build them
again after anything replaces an array (a grown contact list, a restored state).
"""

from __future__ import annotations

import enum
from typing import NamedTuple

import numpy as np

from x3dpd.geometry.shapes import MAX_SHAPE_PARTS
from x3dpd.physics.effect_units import UNITS
from x3dpd.physics.rigid_link import RigidBodies
from x3dpd.solver.contact_lists import (PAIR_BLOCK, S_H, history_columns, pair_columns,
                                         wall_columns)

__all__ = ["Status", "Nodes", "RigidBodies", "Particles", "Faces",
           "ContactList", "Shapes", "Stepping", "Output"]


class Status(enum.IntFlag):
    """Status bits returned by the step kernels (``advance``, ``_forces``): 0 is success."""

    OK = 0
    PENETRATION = 1     # an approach exceeded the penetration limit (diag holds the contact)
    NONFINITE = 2       # a traced value or the ledger became inf or NaN
    REALLOC_PAIRS = 4   # the pair candidate list is full: grow it, go on from this step
    REALLOC_WALLS = 8   # the wall candidate list is full


class Nodes(NamedTuple):
    """Every node, structure and particles, indexed by node index (n nodes)."""

    x: np.ndarray            # (n, 3) coordinates [length]
    x0: np.ndarray           # (n, 3) coordinates at t0
    vel: np.ndarray          # (n, 6) velocities v [length/s], omega [rad/s]
    force: np.ndarray        # (n, 6) force [force] and moment [force*length] sums
    inv_m: np.ndarray        # (n, 6) inverse mass / inertia per DOF (0: fixed or slave)
    mass: np.ndarray         # (n,) node mass
    fbody: np.ndarray        # (n, 6) body forces (gravity's m g: what ``force`` starts each
    #                          step from; the effect units' setup fills it)
    kin_mass: np.ndarray     # (n,) mass for kinetic energy (a rigid master carries its body)
    kin_inertia: np.ndarray  # (n, 3) principal inertia for kinetic energy


class Particles(NamedTuple):
    """The spheres (P particles, node indices p0 .. p0+P-1) and their contact constants."""

    p0: int                  # node index of the first particle
    radius: np.ndarray       # (P,) [length]
    kw: np.ndarray           # (P, K) wall Hertz constants 4/3 E*_k sqrt(R) per Maxwell term
    ep: np.ndarray           # (P, K) plane-strain moduli E_k / (1 - nu^2)
    kind: np.ndarray         # (P,) particle kind (x3dpd.physics.mixing.particle_kinds)
    pair_c: np.ndarray       # (kinds, kinds, 3): Hertz factor, tangential mass m_t, mu
    decay: np.ndarray        # (P, K) e^{-dt/tau_k}
    half: np.ndarray         # (P, K) e^{-dt/(2 tau_k)}
    mu: np.ndarray           # (P,) friction coefficient against walls
    inv_mt: np.ndarray       # (P,) 1/m + R^2/I (inverse tangential mass on a wall)
    cavity: np.ndarray       # (P,) cavity index of each particle
    law_wall: np.ndarray     # (P, 2) constants of the normal law on a wall (hooke: k_n, c_n)
    law_pair: np.ndarray     # (kinds, kinds, 2) constants of the normal law between kinds
    tan_wall: np.ndarray     # (P, 5) on a wall: k_t constant, kinetic mu, mu_r R*, I_r, eta
    tan_pair: np.ndarray     # (kinds, kinds, 5) the same between kinds


class Faces(NamedTuple):
    """Cavity walls: planar faces made of triangles, grouped by cavity (CSR)."""

    cav_ptr: np.ndarray      # (C+1,) offsets into ``cav_faces``
    cav_faces: np.ndarray    # face indices of each cavity
    normal: np.ndarray       # (F, 3) unit normal of each face's plane, into the cavity
    offset: np.ndarray       # (F,) plane offset: n . x = offset on the face
    first_tri: np.ndarray    # (F,) one triangle of each face (its plane's source)
    tri_ptr: np.ndarray      # (F+1,) offsets into ``tris``
    tris: np.ndarray         # triangle indices of each face
    tri_nodes: np.ndarray    # (T, 3) node indices of each triangle
    tri_sign: np.ndarray     # (T,) +-1: orientation of the triangle's normal
    tri_frame: np.ndarray    # (T, 15) barycentric frames (x3dpd.geometry.faces), each step


class ContactList(NamedTuple):
    """A candidate contact list (walls: particle, face; pairs: particle i, particle j), one
    state row per candidate (x3dpd.solver.contact_lists), and the rebuild's scratch space."""

    first: np.ndarray        # (L,) particle (walls) or particle i (pairs)
    second: np.ndarray       # (L,) face (walls) or particle j (pairs)
    state: np.ndarray        # (L, columns) contact state rows
    on: np.ndarray           # (L,) int8: 1 while the contact is open
    count: np.ndarray        # (1,) live length of the list
    first_new: np.ndarray    # (L,) scratch of the rebuild (also the contact loops' busy list)
    second_new: np.ndarray   # (L,) scratch of the rebuild
    state_new: np.ndarray    # (L, columns) scratch of the rebuild
    approach_new: np.ndarray  # (L,) scratch of the rebuild: approach of new candidates
    # scratch of the pair pass (walls, answered one contact at a time, hold placeholders):
    columns: np.ndarray      # flat: an area of C columns per list block (pair_columns)
    history: np.ndarray      # (L + pad, H) Fortran-order histories of busy candidates


class Shapes(NamedTuple):
    """Analytic walls (x3dpd.geometry.shapes; W walls) and their static contact list: every
    particle of a wall's cavity against each of the wall's parts (K (particle, wall) pairs;
    pair k owns the state rows row[k] .. row[k] + parts[wall[k]] - 1)."""

    kind: np.ndarray         # (W,) shape kind (index in x3dpd.geometry.shapes.SHAPES)
    nodes: np.ndarray        # (W, 2) node indices A, B
    params: np.ndarray       # (W, P) lengths [length] (RADIUS ...)
    parts: np.ndarray        # (W,) parts of each wall
    entity: np.ndarray       # (W,) number of its first part (a stop names n_faces + it + part)
    particle: np.ndarray     # (K,) particle of each pair
    wall: np.ndarray         # (K,) wall of each pair
    row: np.ndarray          # (K,) first state row of each pair
    row_particle: np.ndarray  # (R,) particle of each state row
    state: np.ndarray        # (R, columns) contact state rows (x3dpd.solver.contact_lists)
    on: np.ndarray           # (R,) int8: 1 while the contact is open
    located: np.ndarray      # (MAX_PARTS, 9) scratch: the locator's rows


class Stepping(NamedTuple):
    """Step size, list bookkeeping, the energy ledger and the diagnosis of a stop."""

    dt: float                # time step [s]
    skin: float              # neighbour-list skin [length]
    pen_limit: float         # penetration limit, fraction of the radius
    ledger: np.ndarray       # (4,) cumulative work and dissipation (slots L_* of the loop)
    nbr: np.ndarray          # (7,) neighbour-list bookkeeping (see advance)
    diag: np.ndarray         # (8,) what stopped a run: particle, other, depth, radius, t, step
    small: np.ndarray        # (9,) scratch: energies of an output step, barycentric weights
    history_dt: float        # the step contacts slip over, which the tangential laws'
    #                          histories advance by [s]: dt; 0 in a force evaluation at a state
    #                          (x3dpd.solver.simulation.Simulation.compute_forces)


class Output(NamedTuple):
    """Trace and ledger buffers of one ``advance`` call."""

    itrac: int               # steps between trace rows
    trace_nodes: np.ndarray  # (R,) node indices of the TRACE nodes
    times: np.ndarray        # (rows,) output times
    data: np.ndarray         # (rows, R, 9) x, v, omega of the trace nodes
    energy: np.ndarray       # (rows, 12) energy ledger rows
    e_ref: float             # total energy at t0


def build_bundles(setup, state, *, faces_now: tuple, scratch: dict, dt: float,
                  pen_limit: float, diag: np.ndarray, ledger: np.ndarray | None = None,
                  history_dt: float | None = None, units=()) -> dict:
    """The kernels' bundles of one scene (everything but :class:`Output`), by name; the effect
    units' (x3dpd.physics.effect_units) by their names too, and those of ``units`` (the units
    the scene's loop compiles) as a tuple under ``"units"``.

    ``faces_now``: (normal, offset, triangle frames) arrays the kernels refresh from the wall
    nodes;
    ``scratch``: the rebuild scratch arrays of both lists and ``small`` (see
    :func:`contact_scratch`); ``ledger`` replaces the state's ledger (a scratch one for force
    evaluations that must not count work); ``history_dt`` the step the tangential laws'
    histories advance by (default ``dt``; 0 for a force evaluation at a state).
    """
    k, s = setup, state
    own = {u.name: unit_bundle(u, k.units[u.name], s, scratch) for u in UNITS}
    walls = ContactList(s.wl_p, s.wl_f, s.ws, s.wl_on, s.nwl, scratch["wl_p2"], scratch["wl_f2"],
                        scratch["ws2"], scratch["wl_a"], scratch["wl_c"], scratch["wl_h"])
    pairs = ContactList(s.pl_i, s.pl_j, s.ps, s.pl_on, s.npl, scratch["pl_i2"],
                        scratch["pl_j2"], scratch["ps2"], scratch["pl_a"], scratch["pl_c"],
                        scratch["pl_h"])
    return {
        "nodes": Nodes(s.x, k.x0, s.vel, s.force, k.inv_m, k.mass, k.fbody, k.kin_mass,
                       k.kin_inertia),
        # the rigid bodies' unit bundle is every hook's ``rigid`` (x3dpd.physics.effect_unit)
        "rigid": own["rigid_links"],
        "particles": Particles(int(k.p0), k.radius, k.kw, k.ep, k.pkind, k.pair_c, k.decay,
                               k.half, k.mu, k.inv_mt, k.pcav, k.law_wall, k.law_pair,
                               k.tan_wall, k.tan_pair),
        "faces": Faces(k.cav_ptr, k.cav_faces, faces_now[0], faces_now[1], k.face_first_tri,
                       k.face_ptr, k.face_tris, k.tri_nodes, k.tri_sign, faces_now[2]),
        "walls": walls,
        "pairs": pairs,
        "shapes": Shapes(*k.shapes, s.cs, s.cs_on, scratch["located"]),
        "stepping": Stepping(float(dt), float(k.skin), float(pen_limit),
                             s.ledger if ledger is None else ledger, s.nbr, diag,
                             scratch["small"], float(dt if history_dt is None else history_dt)),
        **own,
        "units": tuple(own[u.name] for u in units),
    }


def unit_bundle(unit, constants: dict, state, scratch: dict):
    """The bundle of effect unit ``unit``: its ``constants`` (x3dpd.solver.state.Setup.units),
    its state arrays in ``state`` and its scratch arrays in ``scratch``."""
    arrays = dict(constants)
    for a in unit.state:
        arrays[a.field] = state.units[a.name]
    for field, _ in unit.scratch:
        arrays[field] = scratch[f"{unit.name}.{field}"]
    return unit.bundle(**arrays)


def contact_scratch(state) -> dict:
    """Scratch arrays of the list rebuilds, sized like the state's lists."""
    s = state
    return {"wl_p2": np.zeros_like(s.wl_p), "wl_f2": np.zeros_like(s.wl_f),
            "ws2": np.zeros_like(s.ws), "wl_a": np.zeros(s.wl_p.shape[0]),
            "pl_i2": np.zeros_like(s.pl_i), "pl_j2": np.zeros_like(s.pl_j),
            "ps2": np.zeros_like(s.ps), "pl_a": np.zeros(s.pl_i.shape[0]),
            # the wall pass's columns (variants with one wall kind; a scene without walls
            # holds a list of one candidate: placeholders)
            "wl_c": wall_columns() if s.wl_p.shape[0] > 1 else np.zeros(1),
            "wl_h": history_columns(min(s.wl_p.shape[0], PAIR_BLOCK), s.ws.shape[1] - S_H),
            "pl_c": pair_columns(s.pl_i.shape[0]),
            "pl_h": history_columns(s.pl_i.shape[0], s.ps.shape[1] - S_H),
            "small": np.zeros(9), "located": np.zeros((MAX_SHAPE_PARTS, 9)),
            # the effect units' scratch arrays, shaped like their state arrays
            **{f"{u.name}.{field}": np.zeros_like(s.units[_state_name(u, like)])
               for u in UNITS for field, like in u.scratch}}


def _state_name(unit, field: str) -> str:
    return next(a.name for a in unit.state if a.field == field)


#: The order of ``advance``'s bundle arguments (after nsteps, step0, t_start); ``units`` is the
#: tuple of the bundles of the effect units the loop compiles, in registry order.
ADVANCE_BUNDLES = ("nodes", "rigid", "particles", "faces", "walls", "pairs", "shapes", "units",
                   "stepping", "output")


def pack(bundles: dict, output: Output) -> tuple:
    """The argument of ``advance_packed``: every bundle as a plain tuple, in
    :data:`ADVANCE_BUNDLES` order, the units' a tuple of plain tuples (numba types plain tuples
    of arrays in C, fast)."""
    named = {**bundles, "output": output}
    return tuple(tuple(tuple(u) for u in named[name]) if name == "units"
                 else tuple(named[name]) for name in ADVANCE_BUNDLES)
