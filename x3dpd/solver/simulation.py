# Over 400 lines: Simulation's operations share its prepared arrays.
"""Run a model: the Python side of the time-step loop.

:class:`Simulation` prepares the kernel arrays, compiles (or loads from cache) the step loop for
exactly the scene's effects, evaluates the forces at t0, then advances in chunks. The compiled
loop returns status bits; this module turns them into :class:`~x3dpd.errors.UnstableRunError`
with a diagnosis, grows contact lists when they overflow, and audits the energy ledger and the
cavity containment at fixed step counts (x3dpd.solver.run_checks).
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the solver reads a Model's arrays; it needs no runtime import of it
    from x3dpd.model.model import Model

from x3dpd.errors import InputError, UnstableRunError
from x3dpd.physics.effect_unit import L_WEXT
from x3dpd.physics.effect_units import UNITS, units_of
from x3dpd.physics.motion import MOTION_COLUMNS, motion_rows, motion_table, start_motion
from x3dpd.physics.rolling import n_history as rolling_history
from x3dpd.physics.tangential_laws import DEFAULT_LAW, n_history
from x3dpd.physics.user_force_file import build_external_forces
from x3dpd.geometry.faces import TRIANGLE_FRAME
from x3dpd.solver.bundles import (
    ContactList,
    Output,
    Status,
    build_bundles,
    contact_scratch,
    pack,
)
from x3dpd.solver.contact_lists import kept_histories, restore_histories
from x3dpd.solver.placement import follow_masters
from x3dpd.solver.run_checks import AUDIT_STEPS, RunChecks
from x3dpd.solver.state import STATE_HEAD, State, build_setup, initial_state
from x3dpd.solver.compile_lock import variant_compile_lock
from x3dpd.solver.threads import thread_count, use_threads
from x3dpd.solver.variants import Variant, cache_dir, make_advance

#: Columns of the energy ledger rows (see docs/energy.md).
ENERGY_COLUMNS = ("time", "kinetic_translation", "kinetic_rotation", "gravity_potential",
                  "spring_energy", "contact_energy", "dissipated_viscoelastic",
                  "dissipated_friction", "dissipated_dampers", "external_work", "total_energy",
                  "residual")
#: The column a scene with a rolling-resistance law adds to its ledger rows (after residual):
#: the energy its rolling law dissipated (x3dpd.physics.rolling).
ROLLING_COLUMN = "dissipated_rolling"


def energy_columns(rolling_law: str) -> tuple[str, ...]:
    """The energy ledger's columns of a scene: :data:`ENERGY_COLUMNS`, and
    :data:`ROLLING_COLUMN` when it runs a rolling law (so that every other scene's energy
    files stay as they were)."""
    return ENERGY_COLUMNS + ((ROLLING_COLUMN,) if rolling_law not in (None, "none") else ())

#: Status bits of a full contact list (an int: no enum arithmetic per call).
_LIST_FULL = int(Status.REALLOC_PAIRS | Status.REALLOC_WALLS)

#: Trace columns after time (report Appendix E order).
TRACE_COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")


@dataclass
class Block:
    """Output of one chunk: ``times`` (k,), ``data`` (k, R, 9), ``energy`` (k, 12)."""

    times: np.ndarray
    data: np.ndarray
    energy: np.ndarray


#: Seconds this process has spent loading and compiling step loops (and their first calls),
#: over every Simulation: what a sweep point or a design counts as its compile time, whoever
#: built the loop (its run, or the predicted start before it).
_COMPILE_SECONDS = [0.0]


def _count_compile(seconds: float) -> None:
    _COMPILE_SECONDS[0] += seconds


def process_compile_seconds() -> float:
    """Seconds this process has spent loading and compiling step loops so far [s]."""
    return _COMPILE_SECONDS[0]


class Simulation(RunChecks):
    """A model ready to run.

    Parameters
    ----------
    model : Model
    usrfrc : extra force specs (added to the deck's USRFRC card), see docs/usrfrc.md
    motion : prescribed-motion specs (``node=25,dof=1,amp=0.01,hz=37.21``)
    dt : time step [s]; default the deck's DTMAX
    friction : tangential law (x3dpd.physics.tangential_laws): "regularized" (Haff-Werner with
        gamma = 1/(2 dt)), "coulomb" or "mindlin" (Hertz-Mindlin); None (default): the deck's
        FRICTION card's, else DEFAULT_LAW (x3dpd.physics.tangential_laws)
    penetration_limit : stop when an approach exceeds this fraction of the radius
    energy_tolerance : stop when the ledger residual exceeds this fraction of the energy scale
    allow_python_usrfrc : accept user force files numba cannot compile (slow fallback)
    itrac : trace interval in steps; default the deck's ITRAC
    threads : threads of the pair contacts (x3dpd.solver.threads; default 1, "auto" all)
    """

    def __init__(self, model: Model, *, usrfrc=(), motion=(), dt: float | None = None,
                 friction: str | None = None, penetration_limit: float = 0.25,
                 energy_tolerance: float = 0.05, allow_python_usrfrc: bool = False,
                 itrac: int | None = None, skin: float | None = None, threads=1):
        self.model = model
        self.threads = thread_count(threads)
        friction = friction or model.friction_law or DEFAULT_LAW
        self.friction = friction
        if "friction" not in model.effects and model.rolling_law in (None, "none"):
            # no tangential law runs (every PCOF 0, no rolling law): build and compile the
            # default's setup and loop, so that a frictionless scene compiles one loop whatever
            # --friction says (none of the law's code or history would be used)
            friction = DEFAULT_LAW
        #: the tangential law the loop is built and compiled with (x3dpd.physics.tangential_laws)
        self.kernel_friction = friction
        self.dt = float(dt if dt is not None else model.dt)
        if not (self.dt > 0 and math.isfinite(self.dt)):
            raise InputError(f"time step must be a positive number, got {self.dt!r}")
        self.itrac = int(itrac if itrac is not None else model.itrac)
        if self.itrac < 1:
            raise InputError(f"trace interval ITRAC must be >= 1 step, got {self.itrac}")
        self.audit_steps = self.itrac * -(-AUDIT_STEPS // self.itrac)
        self.penetration_limit = float(penetration_limit)
        self.energy_tolerance = float(energy_tolerance)
        specs = list(model.usrfrc) + list(usrfrc)
        self._force_specs = specs
        self.ext = build_external_forces(specs, model, allow_python=allow_python_usrfrc)
        self.motion = motion_table(list(motion), model, model.x0) if motion else np.zeros(
            (0, len(MOTION_COLUMNS)))
        rows = motion_rows(self.motion)  # the motions (random ones' knots follow them)
        # the motions' and the external forces' units (x3dpd.physics.motion, external_force)
        # take their tables from the model's unit data
        driven = replace(model, unit_data={**model.unit_data, "motion": {"table": self.motion},
                                           "external_force": {"table": self.ext.table}})
        self.setup = build_setup(driven, self.dt, skin=skin, friction=friction)
        effects = set(model.effects)
        if specs:
            effects.add("external_force")
        if len(rows):
            effects.add("prescribed_motion")
        self.python_forces = list(self.ext.python_user)
        compiled = list(self.ext.compiled_user)
        if self.python_forces:
            effects.add("external_force")
        self.effects = frozenset(effects)
        self.variant = Variant.from_effects(self.effects, self.setup.n_maxwell, friction,
                                            user_force=bool(compiled),
                                            python_force=bool(self.python_forces),
                                            walls_translate=_walls_only_translate(
                                                self.setup, rows[:, 0].astype(np.int64)),
                                            normal_law=model.normal_law,
                                            rolling_law=model.rolling_law,
                                            one_particle_kind=_one_particle_kind(self.setup),
                                            one_wall_kind=_one_wall_kind(self.setup),
                                            threaded=self.threads > 1)
        t = _time.perf_counter()
        self.kernels = make_advance(self.variant, [(uf.path, uf.node_index) for uf in compiled])
        #: the columns of this scene's ledger rows (:func:`energy_columns`)
        self.energy_columns = energy_columns(model.rolling_law)
        self.compile_seconds = 0.0
        self._load_seconds = _time.perf_counter() - t
        _count_compile(self._load_seconds)
        self.state = initial_state(model, self.setup)
        #: the Python forces, which the external forces' unit adds in the step
        self.fpy = self.setup.units["external_force"]["python"]
        # a writable copy: a read-only array is another numba type, and another compile
        self.trace_nodes = np.array(model.trace_nodes, dtype=np.int64)
        self.diag = np.zeros(8)
        self._initialized = False

    # ------------------------------------------------------------------ setup
    @property
    def time(self) -> float:
        return self.model.t0 + self.state.step * self.dt

    @property
    def clock(self) -> int:
        """Steps of ``dt`` since t0: where a run stands (x3dpd.solver.variable_step's driver
        counts DTMAX steps)."""
        return self.state.step

    def initialize(self) -> None:
        """Forces at t0 (velocity Verlet needs them), initial contacts, the reference energy."""
        if self._initialized:
            return
        t = _time.perf_counter()
        with variant_compile_lock(cache_dir(), self.kernels.__name__):
            self._initialize()
        self.compile_seconds += _time.perf_counter() - t
        _count_compile(_time.perf_counter() - t)
        self._initialized = True

    def _initialize(self) -> None:
        """``initialize``'s work, under the variant's compile lock (its first kernel calls
        compile the loop or load it from the cache)."""
        s = self.state
        k = self.setup
        w_start = 0.0
        if len(motion_rows(self.motion)):
            w_start = start_motion(self.model.t0, self.motion, k.x0, s.x, s.vel, k.kin_mass,
                                   k.kin_inertia)
            follow_masters(self)
        self._direct_rebuild()
        self._python_force(self.model.t0)
        st = self.compute_forces(self.model.t0)
        self._check_status(st, self.model.t0, 0)
        self.project_modal_forces()
        s.ledger[L_WEXT] += w_start
        en = self._energy_now()
        s.e_ref = float(en[0] + en[1] + en[2] + en[3] + en[4] - en[5]) - w_start

    def restore(self, state: State) -> None:
        """Continue from a restart dump's state (forces at its step are part of it).

        Contact lists are kept as saved (not rebuilt), so that the resumed run sums forces in the
        same order as the uninterrupted one and reproduces it bit for bit.
        """
        if state.ledger.shape[0] < 5:   # a dump from before the rolling-resistance slot
            state.ledger = np.concatenate([state.ledger, np.zeros(5 - state.ledger.shape[0])])
        self.state = state
        self._sc = None
        k = self.setup
        if k.tri_nodes.shape[0]:
            face_n, face_d, _ = self._faces()
            self.kernels._face_planes(state.x, k.tri_nodes, k.tri_sign, k.face_first_tri, face_n,
                                      face_d)
        with variant_compile_lock(cache_dir(), self.kernels.__name__):
            self._compile_loop_callees()
        self._initialized = True

    def _compile_loop_callees(self) -> None:
        """Compile the kernels the step loop calls (the list rebuild's allocate) from Python,
        on copies of the lists.

        numba compiles a kernel first needed inside the step loop with the loop's flags, i.e.
        without reference counting, where an allocating kernel does not compile (a resumed run
        on a cold cache stopped with a TypingError). ``initialize`` compiles them through its
        own rebuild and energies; a restored state skips those, so this does it without
        touching the saved lists."""
        self._energy_now()
        b = self._bundles()
        # copies in the same memory order (numba compiles per layout)
        walls, pairs = (ContactList(*(a.copy(order="K") for a in b[name]))
                        for name in ("walls", "pairs"))
        self._rebuild_lists({**b, "walls": walls, "pairs": pairs})

    def snapshot(self) -> Block:
        """The trace rows and ledger at the current step (used for t = t0)."""
        self.initialize()
        output = self._no_output()
        self._snapshot(output)
        return Block(output.times.copy(), output.data.copy(), output.energy.copy())

    # ------------------------------------------------------------------ stepping
    def advance(self, nsteps: int, max_rows: int | None = None) -> Block:
        """Advance ``nsteps`` steps (fewer if the output buffer fills); return the rows written.
        Checks at fixed step counts only (x3dpd.solver.run_checks), whatever the calls."""
        self.initialize()
        nsteps = int(nsteps)
        if max_rows is None:
            max_rows = nsteps // self.itrac + 1
        max_rows = max(1, int(max_rows))
        r = self.trace_nodes.shape[0]
        out_t = np.empty(max_rows)
        out_data = np.empty((max_rows, r, 9))
        out_energy = np.empty((max_rows, len(self.energy_columns)))
        rows = 0
        audited = 0
        done = 0
        if self.variant.threaded:
            use_threads(self.threads)
        try:
            while done < nsteps and rows < max_rows:
                chunk = min(nsteps - done, self.audit_steps - self.state.step % self.audit_steps)
                if self.python_forces:
                    chunk = 1
                    self._python_force(self.time + self.dt)
                t0 = _time.perf_counter()
                output = Output(self.itrac, self.trace_nodes, out_t[rows:], out_data[rows:],
                                out_energy[rows:], self.state.e_ref)
                status, steps, got = self.kernels.advance_packed(
                    self.kernels.STEP, chunk, self.state.step, self.model.t0,
                    self._packed_bundles(output))
                if not self._timed_first_call:
                    self.compile_seconds += _time.perf_counter() - t0
                    _count_compile(_time.perf_counter() - t0)
                    self._timed_first_call = True
                self.state.step += steps
                done += steps
                rows += got
                self._audit_energy(out_energy[audited:rows])
                audited = rows
                if status & _LIST_FULL:
                    # list overflow: grow and go on from this step boundary
                    self._grow(status)
                    continue
                if status or self.state.step % self.audit_steps == 0:
                    # at a stop, a particle that tunnelled out is the cause of what stopped it
                    self._check_containment()
                if status:
                    self._check_status(status, self.diag[4], int(self.diag[5]))
                if got and rows >= max_rows:
                    break
            block = Block(out_t[:rows].copy(), out_data[:rows].copy(), out_energy[:rows].copy())
        except UnstableRunError as exc:
            # keep what was computed before the failure: the caller writes it, then stops
            exc.block = Block(out_t[:rows].copy(), out_data[:rows].copy(),
                              out_energy[:rows].copy())
            raise
        return block

    _timed_first_call = False
    _unstable_rows = 0

    # ------------------------------------------------------------------ diagnostics
    def _python_force(self, t: float) -> None:
        if not self.python_forces:
            return
        self.fpy[:] = 0.0
        s = self.state
        for uf in self.python_forces:
            uf.function(t, s.x[:, :3].copy(), s.vel.copy(), self.fpy)

    def energy_now(self) -> np.ndarray:
        """The energies of the current state: KE_trans, KE_rot, U_grav, U_spring, U_contact and
        the Verlet term S; the ledger's total is the sum of the first five minus S [energy]."""
        return self._energy_now()

    def _energy_now(self) -> np.ndarray:
        return self._snapshot(self._no_output())

    def _snapshot(self, output: Output) -> np.ndarray:
        """The step loop's output row of the current state (its SNAPSHOT mode) into ``output``'s
        first row; returns the energies (x3dpd.solver._template_energy._energies)."""
        b = self._bundles()
        self.kernels.advance_packed(self.kernels.SNAPSHOT, 1, -1, self.time, pack(b, output))
        return b["stepping"].small[:6].copy()

    def compute_forces(self, t: float | None = None) -> Status:
        """Evaluate every force at time ``t`` (default: now) from the current positions and
        velocities into ``state.force``, without counting work in the ledger; return the status
        flags (``Status.PENETRATION`` when an approach exceeds the limit).

        The state is the one the next step starts from, so nothing slips: the tangential laws
        run at a zero step (``Stepping.history_dt`` = 0: the force of their history as it
        stands, the dashpot on the state's velocities) and their histories are left as they
        were in every contact that stays open (the first step advances them by its own slip;
        advancing them here too added v_t dt twice). Contact lists are used as they are
        (``initialize`` builds them)."""
        t = self.time if t is None else float(t)
        kept = kept_histories(self.state, n_history(self.kernel_friction),
                              rolling_history(self.model.rolling_law))
        if self.variant.threaded:
            use_threads(self.threads)
        b = self._bundles(ledger=np.zeros_like(self.state.ledger), history_dt=0.0)
        status, _, _ = self.kernels.advance_packed(self.kernels.FORCES, 1, -1, t,
                                                   pack(b, self._no_output()))
        restore_histories(kept)
        return Status(status)

    def _no_output(self) -> Output:
        """Output buffers for a step-loop call that writes no rows (REBUILD, FORCES)."""
        return Output(self.itrac, self.trace_nodes, np.empty(1),
                      np.empty((1, self.trace_nodes.shape[0], 9)),
                      np.empty((1, len(self.energy_columns))), self.state.e_ref)

    def _rebuild_lists(self, bundles: dict) -> Status:
        """Rebuild the contact lists of ``bundles`` now (the step loop's REBUILD mode)."""
        status, _, _ = self.kernels.advance_packed(self.kernels.REBUILD, 1, 0, self.model.t0,
                                                   pack(bundles, self._no_output()))
        return Status(status)

    def project_modal_forces(self) -> None:
        """The effect units' ``start`` hooks on the forces now in ``state.force`` (the modal
        forces f = sum phi^T F, less the coupling damping, into ``state.mf``: what the first
        step of the modes uses; the forces on the driven DOFs into ``state.motion_prev``: the
        actuators' first step's; x3dpd.physics.effect_unit)."""
        bundles = self._bundles()
        for unit in UNITS:
            if unit.start is not None:
                unit.start(bundles[unit.name], self.state.force)

    def _faces(self):
        """The faces' planes (normal, offset) and the triangles' frames
        (x3dpd.geometry.faces._triangle_frames), which the step loop refreshes."""
        if not hasattr(self, "_face_n"):
            nf = self.setup.face_first_tri.shape[0]
            self._face_n, self._face_d = np.zeros((nf, 3)), np.zeros(nf)
            self._tri_frame = np.zeros((self.setup.tri_nodes.shape[0], TRIANGLE_FRAME))
        return self._face_n, self._face_d, self._tri_frame

    def _bundles(self, ledger: np.ndarray | None = None,
                 history_dt: float | None = None) -> dict:
        """The kernels' named bundles over the current state (built here and only here);
        ``ledger`` and ``history_dt`` as x3dpd.solver.bundles.build_bundles takes them."""
        s = self.state
        sc = getattr(self, "_sc", None)
        if sc is None or sc["ws2"].shape != s.ws.shape or sc["ps2"].shape != s.ps.shape:
            sc = self._sc = contact_scratch(s)
        return build_bundles(self.setup, s, faces_now=self._faces(), scratch=sc,
                             dt=self.dt, pen_limit=self.penetration_limit, diag=self.diag,
                             ledger=ledger, history_dt=history_dt,
                             units=units_of(self.variant))

    def _packed_bundles(self, output: Output) -> tuple:
        """``advance_packed``'s argument: the bundles packed once and kept while every array of
        the state is the same object (a grown list or another state packs them anew; the
        packed tuple holds the arrays, so their ids cannot be reused meanwhile)."""
        key = (id(getattr(self, "_sc", None)),
               *(id(v) for v in vars(self.state).values() if isinstance(v, np.ndarray)),
               *(id(v) for v in self.state.units.values()))
        cached = getattr(self, "_packed", None)
        if cached is None or cached[0] != key:
            b = self._bundles()
            cached = self._packed = (key, pack(b, output)[:-1])
        return cached[1] + (tuple(output),)

    def _direct_rebuild(self) -> None:
        """Build the contact lists from scratch (at t0), growing them until they fit."""
        s, k = self.state, self.setup
        face_n, face_d, _ = self._faces()
        if k.tri_nodes.shape[0]:
            self.kernels._face_planes(s.x, k.tri_nodes, k.tri_sign, k.face_first_tri, face_n,
                                      face_d)
        while True:
            b = self._bundles()
            full = self._rebuild_lists(b)
            if not full:
                break
            self._grow(full)
        s.nbr[:2] = 0.0
        s.nbr[3] = 1.0

    def _grow(self, status: int) -> None:
        s = self.state
        if status & Status.REALLOC_WALLS:
            cap = 2 * s.wl_p.shape[0]
            s.wl_p = _grown(s.wl_p, cap)
            s.wl_f = _grown(s.wl_f, cap)
            s.ws = _grown(s.ws, cap)
            s.wl_on = _grown(s.wl_on, cap)
        if status & Status.REALLOC_PAIRS:
            cap = 2 * s.pl_i.shape[0]
            s.pl_i = _grown(s.pl_i, cap)
            s.pl_j = _grown(s.pl_j, cap)
            s.ps = _grown(s.ps, cap)
            s.pl_on = _grown(s.pl_on, cap)
        s.nbr[3] = -1.0


def _one_particle_kind(setup) -> bool:
    """True when every particle is alike in all the pair contact response reads per particle:
    one kind (x3dpd.physics.mixing.particle_kinds) and bit-identical radius, moduli and
    Maxwell factors. The step loop then reads particle 0's values for every contact."""
    if setup.radius.shape[0] == 0 or setup.pair_c.shape[0] != 1:
        return False
    return all(bool(np.all(a == a[:1])) for a in (setup.radius, setup.ep, setup.decay,
                                                   setup.half))


def _one_wall_kind(setup) -> bool:
    """True when every particle meets the triangulated walls with bit-identical constants --
    radius, the wall laws' (Hertz and Maxwell, HOOKE), friction and tangential masses -- so
    that the wall response reads particle 0's (``_template_wall_columns``)."""
    if setup.radius.shape[0] == 0:
        return False
    return all(bool(np.all(a == a[:1])) for a in (setup.radius, setup.kw, setup.decay,
                                                   setup.half, setup.mu, setup.inv_mt,
                                                   setup.law_wall, setup.tan_wall))


def _walls_only_translate(setup, prescribed_nodes) -> bool:
    """True when no wall can turn: every triangle node is a fixed node or a slave of a rigid body
    whose master's rotations are all fixed (the report's cavities) and that the modes do not
    turn (a modal master without rotational shape values). Their normals are then constant and
    only the planes' offsets move. A wall node moved on its own by a prescribed motion could
    shear its triangle, so it disqualifies."""
    nodes = np.unique(setup.tri_nodes)
    if nodes.size == 0:
        return False
    if any(len(u.turns(setup.units[u.name])) for u in UNITS if u.turns is not None):
        return False
    fixed = np.all(setup.inv_m[nodes, :3] == 0.0, axis=1) & ~np.isin(nodes, prescribed_nodes)
    owner = np.full(setup.inv_m.shape[0], -1)
    rigid = setup.units["rigid_links"]
    for b in range(rigid["master"].shape[0]):
        owner[rigid["slaves"][rigid["ptr"][b]:rigid["ptr"][b + 1]]] = b
    for node, is_fixed in zip(nodes, fixed):
        b = owner[node]
        if b >= 0:
            if rigid["free_rot"][b].any():
                return False
        elif not is_fixed or setup.x0.shape[0] == 0:
            return False
    return True


def _grown(a: np.ndarray, cap: int) -> np.ndarray:
    out = np.zeros((cap,) + a.shape[1:], dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


__all__ = ["Simulation", "Block", "ENERGY_COLUMNS", "ROLLING_COLUMN", "energy_columns",
           "TRACE_COLUMNS", "STATE_HEAD"]
