r"""A step chosen by accuracy within DTMIN ... DTMAX (the X3D PARAMETERS pair), in the driver.

The step loop stays a fixed-step velocity Verlet; this driver picks, at every output time
(every ITRAC x DTMAX of simulated time), the step for the next output interval from the current
state and runs it with the compiled loop of a :class:`Simulation` built for that step:

* **Free flight.** When no particle is within reach of a wall plane of its cavity or of
  another particle -- reach = (closing speed bound) x interval + |g| interval^2 -- no contact
  can begin before the next decision, and only the structure limits the step (up to DTMAX).
* **Choice.** Otherwise :math:`\Delta t \le t_c(v)/n` with :math:`t_c` the contact time of
  the scene's normal law (its ``contact_time``, x3dpd.physics.normal_laws: Hertz's with the
  instantaneous modulus, HOOKE's half damped period; shortest particle-wall or
  particle-particle contact) at the speed :math:`v` a contact could have
  before the next decision -- twice the fastest particle's speed (a head-on pair) plus the
  speed gravity adds over the interval, at least 1 length/s -- and :math:`n` steps per contact
  (50, as ``x3dpd check``); and :math:`\Delta t \le` the structure's safe step (0.2 of its
  stability limit, given by the caller: ``x3dpd.model.timestep``). Because reach and :math:`v`
  come from the speeds particles have *now*, a contact is seen coming: a particle flying at a
  wall is resolved before it touches it.
* **Levels.** Steps are DTMAX / 2^k (k = 0, 1, ...; not below DTMIN). The run's clock counts
  DTMAX steps (:attr:`VariableStep.clock`); at level k the state's step count is clock x 2^k.
  Output and decision times are whole numbers of DTMAX steps, hence of steps at every level, and
  time is ``t0 + step * dt`` with ``dt = DTMAX / 2^k``, which is exactly ``t0 + clock * DTMAX``
  (scaling by a power of two is exact): output times are the ones a fixed DTMAX run writes.
* **Exact bookkeeping at a switch.** The state is handed on at a full step (velocities
  synchronised); its step count is rescaled; the Maxwell decay factors and the friction stick
  rate belong to each level's :class:`~x3dpd.solver.simulation.Simulation` (built for its
  step); the ledger's Verlet term :math:`S = \Delta t^2/8\,\sum f^2/m` changes with the step, so
  the reference energy is moved by :math:`S_\mathrm{old} - S_\mathrm{new}` and the residual
  stays continuous.
* **Determinism.** The choice depends only on the state, and is made only at output times, so
  a run continued from a saved ``(state, checkpoint())`` -- a restart dump holds both --
  repeats the uninterrupted one bit for bit, wherever it was stopped.

Where it pays: free flight and sparse impacts (DTMAX between contacts), scenes whose particles
are slow most of the time. Where it cannot: a bed in lasting contact is never in free flight,
and under a vigorous drive its fastest particle stays fast, so the step stays at the contact
limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from x3dpd.errors import InputError, UnstableRunError
from x3dpd.geometry.cells import find_pairs
from x3dpd.geometry.shapes import SHAPES, analytic_wall
from x3dpd.geometry.triangle import unit_normals
from x3dpd.physics.normal_laws import NORMAL_LAWS, scene_bodies
from x3dpd.solver.run_checks import AUDIT_STEPS
from x3dpd.solver.simulation import Block, Simulation

#: Floor of the closing speed a decision assumes [length/s].
MIN_SPEED = 1.0
#: Steps per Hertz contact (as ``x3dpd check`` recommends: peak force within 0.054 %).
STEPS_PER_CONTACT = 50
#: Without a usable DTMIN (0, or equal to DTMAX with an explicit ``auto``), the finest step is
#: DTMAX / 2^AUTO_LEVELS.
AUTO_LEVELS = 10


def auto_floor(dtmin: float, dtmax: float) -> float:
    """The finest step of an ``auto`` run: DTMIN when 0 < DTMIN < DTMAX, else DTMAX/1024."""
    return float(dtmin) if 0.0 < dtmin < dtmax else float(dtmax) / 2**AUTO_LEVELS


@dataclass
class VariableStepRun:
    """Rows at the output times (``times`` (T,), ``data`` (T, R, 9), ``energy`` (T, 12)), the
    steps chosen (``steps``: (time, dt) at each change), ``state`` and ``level`` to continue."""

    times: np.ndarray
    data: np.ndarray
    energy: np.ndarray
    steps: list = field(default_factory=list)
    state: object = None
    level: int = 0
    n_steps: int = 0


class VariableStep:
    """Run ``model`` with a step chosen by accuracy in DTMAX / 2^k >= DTMIN.

    It offers what the run loop (:func:`x3dpd.run`) uses of a :class:`Simulation`: ``clock``
    (DTMAX steps since t0), ``dt`` (= DTMAX, the clock's unit), ``itrac`` (output interval in
    DTMAX steps), ``time``, ``state``, ``snapshot()``, ``advance(n)`` (n DTMAX steps),
    ``restore(state, checkpoint)``, ``effects``, ``kernels``, ``compile_seconds``.

    ``itrac`` (or ``interval`` [s], a multiple of DTMAX) is the output and decision interval;
    ``dt_structure`` the structure's safe step [s]; ``sim_options`` go to every
    :class:`Simulation` (usrfrc, motion, friction, penetration_limit, ...).
    """

    def __init__(self, model, *, dtmin: float, dtmax: float, interval: float | None = None,
                 itrac: int | None = None, dt_structure: float = math.inf,
                 steps_per_contact: int = STEPS_PER_CONTACT, **sim_options):
        if not (0.0 < dtmin <= dtmax and math.isfinite(dtmax)):
            raise InputError(f"a step chosen by accuracy needs 0 < DTMIN <= DTMAX, got "
                             f"{dtmin!r}, {dtmax!r}")
        self.model = model
        self.dt = self.dtmax = float(dtmax)
        self.levels = [self.dtmax]
        while self.levels[-1] / 2.0 >= dtmin * (1.0 - 1e-12):
            self.levels.append(self.levels[-1] / 2.0)
        if itrac is None:
            itrac = int(round((interval or model.itrac * dtmax) / dtmax))
            if interval and abs(itrac * dtmax - interval) > 1e-9 * interval:
                raise InputError("the output interval must be a whole number of DTMAX steps")
        self.itrac = int(itrac)
        if self.itrac < 1:
            raise InputError(f"trace interval ITRAC must be >= 1 step, got {self.itrac}")
        self.interval = self.itrac * self.dtmax
        #: containment is checked at multiples of this many DTMAX steps (every level's
        #: Simulation at the same times: x3dpd.solver.run_checks.AUDIT_STEPS)
        self.audit_steps = self.itrac * -(-AUDIT_STEPS // self.itrac)
        self.n = int(steps_per_contact)
        self.dt_structure = float(dt_structure)
        self.options = sim_options
        self._sims: dict[int, Simulation] = {}
        self._trace_nodes = None
        self.level = 0
        self.state = None
        self.changes: list = []       # (time, dt) at the start and at every change
        self.steps_taken = 0          # steps of any size since t0
        self.finest = self.coarsest = None   # levels used so far

    # ------------------------------------------------------------------ what a run loop reads
    def _sim(self, k: int) -> Simulation:
        if k not in self._sims:
            sim = Simulation(self.model, dt=self.levels[k], itrac=self.itrac * 2**k,
                             **self.options)
            sim.audit_steps = self.audit_steps << k
            if self._trace_nodes is not None:
                sim.trace_nodes = self._trace_nodes
            self._sims[k] = sim
        return self._sims[k]

    def _ensure(self) -> Simulation:
        if self.state is None:
            sim = self._sim(0)
            self.state, self.level = sim.state, 0
        return self._sim(self.level)

    @property
    def clock(self) -> int:
        """DTMAX steps since t0 (exact: the state's step count is clock x 2^level)."""
        self._ensure()
        return int(self.state.step) >> self.level

    @property
    def time(self) -> float:
        return self.model.t0 + self.clock * self.dtmax

    @property
    def trace_nodes(self):
        return self._ensure().trace_nodes

    @trace_nodes.setter
    def trace_nodes(self, nodes) -> None:
        self._trace_nodes = nodes
        for sim in self._sims.values():
            sim.trace_nodes = nodes

    @property
    def effects(self):
        return self._sim(0).effects

    @property
    def energy_columns(self):
        """The ledger rows' columns (Simulation.energy_columns: the same at every level)."""
        return self._sim(0).energy_columns

    @property
    def motion(self):
        return self._sim(0).motion

    @property
    def energy_tolerance(self) -> float:
        return self._sim(0).energy_tolerance

    @property
    def kernels(self):
        return self._sim(0).kernels

    @property
    def compile_seconds(self) -> float:
        return sum(s.compile_seconds for s in self._sims.values())

    @property
    def _load_seconds(self) -> float:
        return sum(s._load_seconds for s in self._sims.values())

    def snapshot(self) -> Block:
        """The rows at t0 (the ledger's Verlet term at DTMAX; a first switch moves it)."""
        return self._ensure().snapshot()

    def checkpoint(self) -> dict:
        """What a restart dump must keep besides the state: the level and the step record."""
        self._ensure()
        return {"level": self.level, "steps_taken": self.steps_taken, "finest": self.finest,
                "coarsest": self.coarsest, "levels": len(self.levels), "dtmax": self.dtmax}

    def restore(self, state, checkpoint: dict | None = None) -> None:
        """Continue from ``state`` at the level ``checkpoint`` (of :meth:`checkpoint`) names."""
        cp = checkpoint or {}
        level = int(cp.get("level", 0))
        if not 0 <= level < len(self.levels) or int(cp.get("levels", len(self.levels))) != \
                len(self.levels):
            raise InputError(f"the saved step level {level} does not belong to this run's "
                             f"{len(self.levels)} levels (DTMIN or DTMAX changed)")
        self.state, self.level = state, level
        self.steps_taken = int(cp.get("steps_taken", 0))
        self.finest, self.coarsest = cp.get("finest"), cp.get("coarsest")
        self._sim(level).restore(state)

    def step_record(self) -> dict:
        """The steps used since t0: ``min``, ``max``, ``mean`` [s] and ``steps``."""
        span = self.time - self.model.t0
        used = (self.finest, self.coarsest) if self.finest is not None else (None, None)
        return {"mode": "auto", "dtmin": self.levels[-1], "dtmax": self.dtmax,
                "min": self.levels[used[0]] if used[0] is not None else None,
                "max": self.levels[used[1]] if used[1] is not None else None,
                "mean": span / self.steps_taken if self.steps_taken else None,
                "steps": self.steps_taken}

    # ------------------------------------------------------------------ stepping
    def advance(self, n: int) -> Block:
        """Advance ``n`` DTMAX steps' worth of time; choose the level at every output time."""
        self._ensure()
        blocks: list[Block] = []
        left = int(n)
        try:
            while left > 0:
                clock = self.clock
                if clock % self.itrac == 0:
                    self._decide()
                now = min(left, self.itrac - clock % self.itrac)
                k = self.level
                blocks.append(self._sim(k).advance(now << k))
                self.steps_taken += now << k
                self.finest = k if self.finest is None else max(self.finest, k)
                self.coarsest = k if self.coarsest is None else min(self.coarsest, k)
                left -= now
        except UnstableRunError as exc:
            part = getattr(exc, "block", None)
            exc.block = _joined(blocks + ([part] if part is not None else []),
                                self.trace_nodes.shape[0])
            raise
        return _joined(blocks, self.trace_nodes.shape[0])

    def _decide(self) -> None:
        want = self.wanted_level(self.state)
        if not self.changes:
            self.changes.append((self.time, self.levels[self.level]))
        if want != self.level:
            self._switch(want)
            self.changes.append((self.time, self.levels[self.level]))

    def wanted_level(self, state) -> int:
        """The coarsest level whose step resolves a contact at the speed one could have, or,
        when no contact can begin within the next interval, the structure's limit alone."""
        m = self.model
        p0 = m.particle_start
        speed = np.sqrt(np.sum(state.vel[p0:, :3] ** 2, axis=1))
        walls = np.sqrt(np.sum(state.vel[:p0, :3] ** 2, axis=1))
        g = math.hypot(*m.body_accel)
        v = max(2.0 * float(np.max(speed, initial=0.0)) + g * self.interval, MIN_SPEED)
        reach = (v + float(np.max(walls, initial=0.0))) * self.interval + g * self.interval**2
        dt = self.dt_structure
        if self._contact_possible(state, reach):
            dt = min(self._contact_time(v) / self.n, dt)
        for k, step in enumerate(self.levels):
            if step <= dt:
                return k
        return len(self.levels) - 1

    def _contact_possible(self, state, reach: float) -> bool:
        """Could a contact be open within ``reach`` [length] of closing: a particle within it
        of a wall *plane* of its cavity (a lower bound of the distance to the wall), or of
        another particle of its cavity?"""
        m = self.model
        if not m.n_particles:
            return False
        k = self._sim(self.level).setup
        xp = state.x[k.p0:]
        if "pair_contact" in m.effects and m.n_particles > 1:
            if find_pairs(xp, k.radius, k.pcav, skin=reach).shape[0]:
                return True
        if "wall_contact" in m.effects and k.tri_nodes.shape[0]:
            first = k.face_first_tri
            corners = [state.x[k.tri_nodes[first, j]] for j in range(3)]
            n_in = k.tri_sign[first][:, None] * unit_normals(*corners)
            d0 = np.sum(n_in * corners[0], axis=1)
            for c in range(k.cav_ptr.shape[0] - 1):
                faces = k.cav_faces[k.cav_ptr[c]:k.cav_ptr[c + 1]]
                mine = np.flatnonzero(k.pcav == c)
                if faces.size and mine.size:
                    gap = xp[mine] @ n_in[faces].T - d0[faces] - k.radius[mine][:, None]
                    if np.min(gap) < reach:
                        return True
        table = k.shapes
        for w in range(table.kind.shape[0]):   # analytic walls: the exact gap
            mine = table.particle[table.wall == w]
            shape, ends, lengths = analytic_wall(table.kind[w], table.nodes[w], table.params[w],
                                                 state.x)
            if mine.size and np.min(shape.clearance(xp[mine], k.radius[mine], ends,
                                                    lengths)[0]) < reach:
                return True
        return False

    def _contact_time(self, v: float) -> float:
        """The shortest contact at impact speed ``v`` by the scene's normal law's
        ``contact_time`` (x3dpd.physics.normal_laws: Hertz's with the instantaneous modulus,
        or HOOKE's half damped period), of each particle group on a wall and on itself."""
        m = self.model
        law = NORMAL_LAWS[m.normal_law]
        walls = "wall_contact" in m.effects or any(s.effect in m.effects for s in SHAPES)
        best = math.inf
        for body in scene_bodies(m).values():
            if walls:
                best = min(best, law.contact_time(body, None, v))
            if "pair_contact" in m.effects:
                best = min(best, law.contact_time(body, body, v))
        return best

    def _switch(self, k: int) -> None:
        old, new = self._sim(self.level), self._sim(k)
        st = self.state
        s_old = _verlet_term(st, old)
        st.step = (int(st.step) << (k - self.level)) if k > self.level else \
            (int(st.step) >> (self.level - k))
        new.restore(st)
        st.e_ref += s_old - _verlet_term(st, new)
        self.level = k

    def run(self, t_end: float, *, state=None, checkpoint: dict | None = None
            ) -> VariableStepRun:
        """Advance to ``t_end`` [s] (rounded to whole output intervals), from ``state`` and
        ``checkpoint`` of an earlier run if given; return its rows and what it chose."""
        rows = []
        if state is None:
            rows.append(self.snapshot())
        else:
            self.restore(state, checkpoint)
        before = self.steps_taken
        left = int(round((t_end - self.time) / self.interval)) * self.itrac
        if left > 0:
            rows.append(self.advance(left))
        block = _joined(rows, self.trace_nodes.shape[0])
        return VariableStepRun(block.times, block.data, block.energy, list(self.changes),
                               self.state, self.level, self.steps_taken - before)


def _joined(blocks, n_traced: int) -> Block:
    blocks = [b for b in blocks if b.times.shape[0]]
    if not blocks:
        return Block(np.zeros(0), np.zeros((0, n_traced, 9)), np.zeros((0, 12)))
    if len(blocks) == 1:
        return blocks[0]
    return Block(np.concatenate([b.times for b in blocks]),
                 np.concatenate([b.data for b in blocks]),
                 np.concatenate([b.energy for b in blocks]))


def _verlet_term(state, sim: Simulation) -> float:
    """S = dt^2/8 sum f^2 / m at the current forces, for ``sim``'s step (the ledger's term)."""
    inv_m = sim.setup.inv_m
    return float(sim.dt**2 / 8.0 * np.sum(state.force**2 * inv_m))
