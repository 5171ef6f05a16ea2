"""Solver state and the constant arrays the step kernels read, built from a :class:`Model`.

``State`` holds everything that evolves (coordinates, velocities, forces, rigid-body rotations,
contact candidate lists with their histories, the energy ledger); it is what a restart dump
saves. ``Kernel arrays`` (``Setup``) are derived once from the model and never change.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING

import numpy as np

from x3dpd.physics.effect_units import UNITS
from x3dpd.physics.maxwell import maxwell_step_factors
from x3dpd.physics.wall_material import (particle_walls, plane_strain_moduli, wall_friction,
                                          wall_hertz_constants)
from x3dpd.physics.mixing import pair_constant_table, particle_kinds
from x3dpd.physics.normal_laws import NORMAL_LAWS, contact_bodies
from x3dpd.physics.rolling import n_history as rolling_history
from x3dpd.physics.tangential_laws import n_history, tangential_tables
from x3dpd.solver.shape_table import ShapeTable, shape_table

if TYPE_CHECKING:  # the solver reads a Model's arrays; it needs no runtime import of it
    from x3dpd.model.model import Model


#: Columns of a contact state row before the Maxwell histories: approach, F_N, F_t (3).
STATE_HEAD = 5


@dataclass
class State:
    """Everything that evolves. Arrays are float64 / int64, indexed by node index.

    x (n,3) coordinates; vel (n,6) velocities (v, omega); force (n,6) force and moment sums;
    wl_p, wl_f, ws, wl_on (Lw) wall
    candidate list (particle, face, state row, open-contact flag); nwl (1,) its length; pl_i,
    pl_j, ps, pl_on (Lp) pair candidate list; npl (1,);
    nbr (7,) neighbour-list bookkeeping;
    ledger (5,) cumulative work/dissipation (the L_* slots of x3dpd.solver._template_contact);
    cs, cs_on (R) contact state rows and open flags of the analytic walls' static list, one
    row per part of each (particle, wall) pair (x3dpd.solver.bundles.Shapes; empty without
    any);
    step: steps done since t0; e_ref: energy at t0;
    scale: the largest energy-ledger term seen so far (what the residual is judged against);
    units: the effect units' state arrays by their names (x3dpd.physics.effect_unit.StateArray:
    every registered unit's, whatever the scene calls for), also read as attributes
    (``state.mq``; ``state.rot``, the rigid bodies' rotations (B, 3, 3))
    """

    x: np.ndarray
    vel: np.ndarray
    force: np.ndarray
    wl_p: np.ndarray
    wl_f: np.ndarray
    ws: np.ndarray
    wl_on: np.ndarray
    nwl: np.ndarray
    pl_i: np.ndarray
    pl_j: np.ndarray
    ps: np.ndarray
    pl_on: np.ndarray
    npl: np.ndarray
    nbr: np.ndarray
    ledger: np.ndarray
    cs: np.ndarray = None
    cs_on: np.ndarray = None
    step: int = 0
    e_ref: float = 0.0
    scale: float = 0.0
    units: dict = field(default_factory=dict)

    def __getattr__(self, name: str):
        units = self.__dict__.get("units")
        if units is not None and name in units:
            return units[name]
        raise AttributeError(f"State has no attribute {name!r}")

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Flat dict for a restart dump: the arrays in the order dumps have always had them
        (:data:`_DUMP_ORDER`), a later unit's after them, then ``step``, ``e_ref``, ``scale``."""
        core = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "units"}
        named = {**core, **self.units}
        order = [n for n in _DUMP_ORDER if n in named]
        order += [n for n in self.units if n not in order]
        order += [n for n in core if n not in order and n not in _SCALARS]
        return {n: np.asarray(named[n]) for n in order + list(_SCALARS)}

    def copy(self) -> "State":
        """An independent copy (every array copied): a final state to continue from, or to
        change without touching the running simulation's."""
        return State.from_arrays({k: np.array(v, copy=True) for k, v in self.to_arrays().items()})

    @classmethod
    def from_arrays(cls, arrays: dict) -> "State":
        kw = {}
        for f in fields(cls):
            if f.name == "units" or (f.name in _OPTIONAL_STATE and f.name not in arrays):
                continue   # a dump written before these existed: a scene without any
            v = arrays[f.name]
            if f.name == "step":
                kw[f.name] = int(v)
            elif f.name in ("e_ref", "scale"):
                kw[f.name] = float(v)
            else:
                kw[f.name] = np.array(v)
        state = cls(**kw)
        for unit in UNITS:
            for a in unit.state:   # a dump written before the unit existed: empty
                state.units[a.name] = (np.array(arrays[a.name]) if a.name in arrays
                                       else np.zeros((0,) + a.columns))
        if state.cs is None:
            state.cs = np.zeros((0, state.ws.shape[1]))
            state.cs_on = np.zeros(0, np.int8)
        return state


#: State fields absent from dumps of older versions: the analytic walls' contacts.
_OPTIONAL_STATE = ("cs", "cs_on")
#: The scalars at a dump's end.
_SCALARS = ("step", "e_ref", "scale")
#: The arrays of a restart dump in the order dumps have always had them, the effect units' at
#: the places they had before they were units (x3dpd.io.restart writes them in this order, so
#: that a dump's bytes stay those of before); a unit added later puts its arrays after these.
_DUMP_ORDER = ("x", "vel", "force", "rot", "fext_prev", "frow_prev", "motion_prev", "fd_prev",
               "wl_p", "wl_f", "ws", "wl_on", "nwl", "pl_i", "pl_j", "ps", "pl_on", "npl", "nbr",
               "ledger", "cs", "cs_on", "mq", "mp", "mf", "axial_fd_prev", "rotational_theta",
               "rotational_md_prev")


@dataclass(frozen=True)
class Setup:
    """Constant arrays of a scene, in the form the kernels take."""

    x0: np.ndarray
    inv_m: np.ndarray
    mass: np.ndarray
    fbody: np.ndarray
    kin_mass: np.ndarray
    kin_inertia: np.ndarray
    p0: int
    radius: np.ndarray
    kw: np.ndarray
    ep: np.ndarray
    pkind: np.ndarray   # (P,) particle kind (x3dpd.physics.mixing.particle_kinds)
    pair_c: np.ndarray  # (K, K, 3) per pair of kinds: Hertz factor, m_t, mu
    law_wall: np.ndarray  # (P, 2) normal-law constants on a wall (hooke: k_n, c_n)
    law_pair: np.ndarray  # (K, K, 2) normal-law constants per pair of kinds
    tan_wall: np.ndarray  # (P, 5) on a wall: k_t const, mu_k, rolling lever and inertia, eta
    tan_pair: np.ndarray  # (K, K, 5) the same per pair of kinds
    n_tangential: int     # tangential + rolling history values per contact (end of each row)
    decay: np.ndarray
    half: np.ndarray
    mu: np.ndarray
    inv_mt: np.ndarray
    pcav: np.ndarray
    cav_ptr: np.ndarray
    cav_faces: np.ndarray
    face_first_tri: np.ndarray
    face_ptr: np.ndarray
    face_tris: np.ndarray
    tri_nodes: np.ndarray
    tri_sign: np.ndarray
    shapes: "ShapeTable"      # the analytic walls and their static contact list
    n_maxwell: int
    skin: float
    dt: float
    #: the effect units' constant arrays, by unit name and bundle field
    #: (x3dpd.physics.effect_unit: every registered unit's, whatever the scene calls for)
    units: dict = field(default_factory=dict)


def _f64(a, shape=None):
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a.reshape(shape) if shape is not None else a


def _i64(a):
    return np.ascontiguousarray(a, dtype=np.int64)


def build_setup(model: Model, dt: float, skin: float | None = None,
                friction: str = "regularized") -> Setup:
    """Derive the kernel arrays of ``model`` for time step ``dt`` and the tangential law
    ``friction`` (x3dpd.physics.tangential_laws; the rolling law is the model's)."""
    nodes = _node_arrays(model, float(dt))
    particles = _particle_arrays(model, dt, nodes["mass"], friction)
    if skin is None:
        radius = particles["radius"]
        skin = 0.25 * float(radius.min()) if radius.shape[0] else 0.0
    return Setup(**nodes, **particles, **_wall_arrays(model), skin=float(skin), dt=float(dt))


def _node_arrays(model: Model, dt: float) -> dict:
    """The nodes' arrays of Setup and the effect units' constants, in the units' three passes
    (x3dpd.physics.effect_unit, "Setup"): ``lump`` (the rigid bodies' masses on their
    masters), the inverse masses, ``setup`` (a unit may take its nodes out of velocity
    Verlet), ``finish``."""
    n = model.n_nodes
    mass = _f64(model.mass).copy()
    fixed = np.array(model.fixed, dtype=bool).reshape(n, 6)
    kin_mass = mass.copy()
    kin_inertia = _f64(model.inertia, (n, 3)).copy()
    shared = {"fixed": fixed, "kin_mass": kin_mass, "kin_inertia": kin_inertia,
              "carried": np.zeros(n, dtype=bool)}
    lumped = {u.name: u.lump(model, shared) for u in UNITS if u.lump is not None}
    slave = shared.pop("carried")

    inv_m = np.zeros((n, 6))
    with np.errstate(divide="ignore"):
        for d in range(3):
            inv_m[:, d] = np.where(kin_mass > 0, 1.0 / np.where(kin_mass > 0, kin_mass, 1.0), 0.0)
            has = kin_inertia[:, d] > 0
            inv_m[:, 3 + d] = np.where(has, 1.0 / np.where(has, kin_inertia[:, d], 1.0), 0.0)
    inv_m[fixed] = 0.0
    inv_m[slave] = 0.0
    # the body forces every step's forces start from: the units add theirs (gravity's m g)
    out = {**shared, "inv_m": inv_m, "mass": mass, "fbody": np.zeros((n, 6))}
    units = {u.name: {**lumped.get(u.name, {}), **u.setup(model, dt, out)} for u in UNITS}
    for u in UNITS:
        if u.finish is not None:
            u.finish(units[u.name], out)   # after every unit took its DOFs
    own = ("inv_m", "mass", "fbody", "kin_mass", "kin_inertia")
    return {**{name: out[name] for name in own}, "x0": _f64(model.x0, (n, 3)), "units": units}


def _particle_arrays(model: Model, dt: float, mass: np.ndarray, friction: str) -> dict:
    """The particles' arrays of Setup: radii, moduli, Maxwell factors, kinds, the contact laws'
    constant tables (``mass``: the nodes' masses)."""
    p0 = model.particle_start
    npart = model.n_particles
    radius = _f64(model.radius)
    inertia = _f64(model.inertia, (model.n_nodes, 3))
    moduli = _f64(model.moduli, (npart, -1)) if npart else np.zeros((0, 1))
    taus = _f64(model.taus, (npart, -1)) if npart else np.zeros((0, 1))
    k_terms = moduli.shape[1]
    nu = _f64(model.poisson)
    ep = moduli / (1.0 - nu[:, None] ** 2) if npart else np.zeros((0, k_terms))
    cinst = ep.sum(axis=1) if npart else np.zeros(0)
    kw = 4.0 / 3.0 * ep * np.sqrt(radius)[:, None] if npart else np.zeros((0, k_terms))
    # compliant walls (WALLMAT): the mixed modulus and the wall's friction, per particle (a
    # particle meets only its own cavity's walls); rigid walls keep the values above
    e_wall, nu_wall, mu_wall = particle_walls(model.particle_cavity, model.wall_material)
    kw = wall_hertz_constants(kw, ep, radius, plane_strain_moduli(e_wall, nu_wall))
    decay = np.ones_like(moduli)
    half = np.ones_like(moduli)
    if k_terms > 1 and npart:
        # one value at a time through libm's exp (maxwell_step_factors), not numpy's exp: that
        # has an AVX-512 and an AVX2 implementation which differ in the last bit for some
        # arguments, and a golden from one CPU then drifted on the other (tests/test_decks.py)
        for p in range(npart):
            for k in range(1, k_terms):
                decay[p, k], half[p, k] = maxwell_step_factors(float(taus[p, k]), dt)
    pm = mass[p0:] if npart else np.zeros(0)
    pin = inertia[p0:, 0] if npart else np.zeros(0)
    inv_mt = 1.0 / pm + radius**2 / pin if npart else np.zeros(0)
    n_maxwell = 0
    if k_terms > 1 and npart and np.any(moduli[:, 1:] != 0.0):
        n_maxwell = k_terms - 1

    pcav = _i64(model.particle_cavity)
    # the normal law's own constants (its card's, x3dpd.physics.normal_laws) distinguish kinds too
    law = NORMAL_LAWS[model.normal_law]
    params = (np.zeros((npart, len(law.PARAMS))) if model.law_params is None
              else _f64(model.law_params).reshape(npart, len(law.PARAMS)))
    pm_all = mass[p0:] if npart else np.zeros(0)
    extra = law.kind_keys(params, pm_all)
    mu_k = getattr(model, "mu_kinetic", None)
    mu_k = _f64(model.mu) if mu_k is None else _f64(mu_k)
    if n_history(friction):
        # a tangential spring's constants (Poisson's ratio, kinetic mu) distinguish kinds too
        extra = extra + (nu, mu_k)
    mu_r = np.zeros(npart) if model.mu_roll is None else _f64(model.mu_roll)
    if model.rolling_law != "none":
        extra = extra + (mu_r,)
    pkind, rep = particle_kinds(radius, cinst, inv_mt, model.mu, *extra)
    pair_c = pair_constant_table(radius, cinst, inv_mt, model.mu, rep)
    law_wall, law_pair = law.law_tables(params, pm_all, rep)
    bodies = ([b._replace(wall_e=float(e), wall_nu=float(n)) for b, e, n in
               zip(contact_bodies(pm_all, radius, moduli, nu, params), e_wall, nu_wall)]
              if npart else [])   # a scene without particles has no contact bodies
    tan_wall, tan_pair = tangential_tables(friction, law, bodies, mu_k, rep, model.rolling_law,
                                           mu_r, pin)
    tan_wall[:, 1] = wall_friction(tan_wall[:, 1], mu_wall)   # a WALLMAT wall's mu

    return {"p0": int(p0), "radius": radius, "kw": _f64(kw), "ep": _f64(ep), "pkind": pkind,
            "pair_c": pair_c, "law_wall": _f64(law_wall), "law_pair": _f64(law_pair),
            "tan_wall": _f64(tan_wall), "tan_pair": _f64(tan_pair),
            "n_tangential": n_history(friction) + rolling_history(model.rolling_law),
            "decay": _f64(decay), "half": _f64(half), "mu": _f64(wall_friction(model.mu, mu_wall)),
            "inv_mt": _f64(inv_mt), "pcav": pcav, "n_maxwell": n_maxwell}


def _wall_arrays(model: Model) -> dict:
    """The walls' arrays of Setup: faces per cavity (CSR), triangles per face (CSR), the
    analytic walls and their static contact list."""
    ncav = int(model.cavity_set_ids.shape[0])
    tri_face = _i64(model.tri_face)
    nf = int(model.face_cavity.shape[0])
    order = np.argsort(tri_face, kind="stable")
    face_tris = _i64(order)
    face_ptr = np.zeros(nf + 1, dtype=np.int64)
    np.add.at(face_ptr, tri_face + 1, 1)
    face_ptr = np.cumsum(face_ptr)
    face_first_tri = _i64(face_tris[face_ptr[:-1]]) if nf else np.zeros(0, np.int64)
    fc = _i64(model.face_cavity)
    cav_faces = _i64(np.argsort(fc, kind="stable"))
    cav_ptr = np.zeros(ncav + 1, dtype=np.int64)
    np.add.at(cav_ptr, fc + 1, 1)
    cav_ptr = np.cumsum(cav_ptr)
    return {"cav_ptr": cav_ptr, "cav_faces": cav_faces, "face_first_tri": face_first_tri,
            "face_ptr": face_ptr, "face_tris": face_tris,
            "tri_nodes": _i64(model.tri_nodes).reshape(-1, 3), "tri_sign": _f64(model.tri_sign),
            "shapes": shape_table(model, _i64(model.particle_cavity))}


def initial_state(model: Model, setup: Setup) -> State:
    """State at t0: deck coordinates and velocities, empty contact lists."""
    n = model.n_nodes
    npart = model.n_particles
    vel = _f64(model.v0, (n, 6)).copy()
    # approach, F_N, F_t, the normal law's histories, the tangential law's
    # (x3dpd.solver.contact_lists)
    ncols = STATE_HEAD + max(setup.n_maxwell, 1) + setup.n_tangential
    ncols_pair = STATE_HEAD + 2 * max(setup.n_maxwell, 1) + setup.n_tangential
    nfaces_max = int(np.max(np.diff(setup.cav_ptr))) if setup.cav_ptr.shape[0] > 1 else 0
    lw = max(16, npart * max(3, min(nfaces_max, 6)))
    lp = max(16, 8 * npart)
    return State(
        x=setup.x0.copy(), vel=vel, force=np.zeros((n, 6)),
        wl_p=np.zeros(lw, np.int64), wl_f=np.zeros(lw, np.int64), ws=np.zeros((lw, ncols)),
        wl_on=np.zeros(lw, np.int8),
        nwl=np.zeros(1, np.int64),
        pl_i=np.zeros(lp, np.int64), pl_j=np.zeros(lp, np.int64), ps=np.zeros((lp, ncols_pair)),
        pl_on=np.zeros(lp, np.int8),
        npl=np.zeros(1, np.int64),
        nbr=np.array([0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0]), ledger=np.zeros(5),
        cs=np.zeros((setup.shapes.row_particle.shape[0], ncols)),
        cs_on=np.zeros(setup.shapes.row_particle.shape[0], np.int8),
        step=0, e_ref=0.0,
        units={a.name: a.at_start(setup.units[u.name][a.rows].shape[0])
               for u in UNITS for a in u.state},
    )
