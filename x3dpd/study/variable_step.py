r"""A step chosen by accuracy within DTMIN ... DTMAX (the X3D PARAMETERS pair), in the driver.

The step loop stays a fixed-step velocity Verlet; this driver picks, before every output
interval, the step for the next one from the current state and runs it with the compiled loop:

* **Free flight.** When no particle is within reach of a wall plane of its cavity or of
  another particle -- reach = (closing speed bound) x interval + |g| interval^2 -- no contact
  can begin before the next decision, and only the structure limits the step (up to DTMAX).
* **Choice.** Otherwise :math:`\Delta t \le t_c(v)/n` with :math:`t_c` the Hertz contact time
  (:func:`x3dpd.model.timestep.hertz_contact_time`, instantaneous modulus, shortest
  particle-wall or particle-particle contact) at the speed :math:`v` a contact could have
  before the next decision -- twice the fastest particle's speed (a head-on pair) plus the
  speed gravity adds over the interval, at least 1 length/s -- and :math:`n` steps per contact
  (50, as ``x3dpd check``); and :math:`\Delta t \le` the structure's safe step (0.2 of its
  stability limit). Because reach and :math:`v` come from the speeds particles have *now*, a
  contact is seen coming: a particle flying at a wall is resolved before it touches it.
* **Levels.** Steps are DTMAX / 2^k (k = 0, 1, ...; not below DTMIN), so every output time and
  every switch time is a whole number of steps at every level: time stays ``t0 + step * dt``
  exactly, and refining is always possible; coarsening waits until the step count divides.
* **Exact bookkeeping at a switch.** The state is handed on at a full step (velocities
  synchronised); its step count is rescaled; the Maxwell decay factors and the friction stick
  rate belong to each level's :class:`~x3dpd.solver.simulation.Simulation` (built for its
  step); the ledger's Verlet term :math:`S = \Delta t^2/8\,\sum f^2/m` changes with the step, so
  the reference energy is moved by :math:`S_\mathrm{old} - S_\mathrm{new}` and the residual
  stays continuous.
* **Determinism.** The choice depends only on the state and the current level, so a run
  continued from a saved ``(state, level)`` repeats the uninterrupted one bit for bit.

Where it pays: free flight and sparse impacts (DTMAX between contacts), scenes whose particles
are slow most of the time. Where it cannot: a bed in lasting contact is never in free flight,
and under a vigorous drive its fastest particle stays fast, so the step stays at the contact
limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from x3dpd.geometry.cells import find_pairs
from x3dpd.geometry.triangle import unit_normals
from x3dpd.model.timestep import STEPS_PER_CONTACT, hertz_contact_time, recommended_time_step
from x3dpd.physics.hertz import effective_modulus_pair, effective_modulus_wall, effective_radius
from x3dpd.solver.simulation import Simulation

MIN_SPEED = 1.0


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

    ``interval`` is the output (and decision) interval [s], a multiple of DTMAX;
    ``sim_options`` go to every :class:`Simulation` (usrfrc, friction, ...).
    """

    def __init__(self, model, *, dtmin: float, dtmax: float, interval: float | None = None,
                 steps_per_contact: int = STEPS_PER_CONTACT, **sim_options):
        if not (0.0 < dtmin <= dtmax):
            raise ValueError(f"need 0 < DTMIN <= DTMAX, got {dtmin!r}, {dtmax!r}")
        self.model = model
        self.dtmax = float(dtmax)
        self.levels = [self.dtmax]
        while self.levels[-1] / 2.0 >= dtmin * (1.0 - 1e-12):
            self.levels.append(self.levels[-1] / 2.0)
        self.interval = float(interval or model.itrac * dtmax)
        self.per_interval = int(round(self.interval / self.dtmax))
        if self.per_interval < 1 or abs(self.per_interval * self.dtmax - self.interval) > \
                1e-9 * self.interval:
            raise ValueError("the output interval must be a whole number of DTMAX steps")
        self.n = int(steps_per_contact)
        self.options = sim_options
        self._sims: dict[int, Simulation] = {}
        self.dt_structure = recommended_time_step(model).dt_structure
        self.level = 0
        self.state = None

    def _sim(self, k: int) -> Simulation:
        if k not in self._sims:
            self._sims[k] = Simulation(self.model, dt=self.levels[k],
                                       itrac=self.per_interval * 2**k, **self.options)
        return self._sims[k]

    def wanted_level(self, state) -> int:
        """The coarsest level whose step resolves a contact at the speed one could have, or,
        when no contact can begin within the next interval, the structure's limit alone."""
        m = self.model
        p0 = m.particle_start
        speed = np.sqrt(np.sum(state.vel[p0:, :3] ** 2, axis=1)) if m.n_particles else \
            np.zeros(1)
        walls = np.sqrt(np.sum(state.vel[:p0, :3] ** 2, axis=1))
        g = math.hypot(*m.body_accel)
        v = max(2.0 * float(np.max(speed, initial=0.0)) + g * self.interval, MIN_SPEED)
        reach = (v + float(np.max(walls, initial=0.0))) * self.interval + g * self.interval**2
        if self._contact_possible(state, reach):
            dt = min(self._contact_time(v) / self.n, self.dt_structure)
        else:
            dt = self.dt_structure
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
        return False

    def _contact_time(self, v: float) -> float:
        m = self.model
        if not m.n_particles:
            return math.inf
        e_inst = m.moduli.sum(axis=1)
        best = math.inf
        mass = m.mass[m.particle_start:]
        for i in np.unique(m.particle_group, return_index=True)[1]:
            if "wall_contact" in m.effects:
                best = min(best, hertz_contact_time(
                    mass[i], m.radius[i], effective_modulus_wall(e_inst[i], m.poisson[i]), v))
            if "pair_contact" in m.effects:
                best = min(best, hertz_contact_time(
                    mass[i] / 2.0, effective_radius(m.radius[i], m.radius[i]),
                    effective_modulus_pair(e_inst[i], m.poisson[i], e_inst[i], m.poisson[i]), v))
        return best

    def _switch(self, k: int) -> None:
        old, new = self._sim(self.level), self._sim(k)
        st = self.state
        factor = 2 ** (k - self.level)  # > 1 refining, < 1 coarsening
        step = st.step * factor
        s_old = _verlet_term(st, old)
        st.step = int(round(step))
        new.restore(st)
        st.e_ref += s_old - _verlet_term(st, new)
        self.level = k

    def run(self, t_end: float, *, state=None, level: int = 0) -> VariableStepRun:
        """Advance to ``t_end`` [s] (from ``state``/``level`` of an earlier run if given)."""
        if state is None:
            sim = self._sim(0)
            first = sim.snapshot()
            self.state, self.level = sim.state, 0
            rows = [first]
        else:
            self.state, self.level = state, level
            self._sim(level).restore(state)
            rows = []
        chosen = [(self._sim(self.level).time, self.levels[self.level])]
        n_steps = 0
        while True:
            sim = self._sim(self.level)
            left = int(round((t_end - sim.time) / self.interval))
            if left <= 0:
                break
            want = self.wanted_level(self.state)
            if want < self.level:  # coarsen only to a level whose step count divides
                while want < self.level and self.state.step % 2 ** (self.level - want):
                    want += 1
            if want != self.level:
                self._switch(want)
                sim = self._sim(self.level)
                chosen.append((sim.time, self.levels[self.level]))
            n = self.per_interval * 2**self.level
            rows.append(sim.advance(n))
            n_steps += n
        times = np.concatenate([b.times for b in rows]) if rows else np.zeros(0)
        data = np.concatenate([b.data for b in rows]) if rows else np.zeros((0, 0, 9))
        energy = np.concatenate([b.energy for b in rows]) if rows else np.zeros((0, 12))
        return VariableStepRun(times, data, energy, chosen, self.state, self.level, n_steps)


def _verlet_term(state, sim: Simulation) -> float:
    """S = dt^2/8 sum f^2 / m at the current forces, for ``sim``'s step (the ledger's term)."""
    inv_m = sim.setup.inv_m
    return float(sim.dt**2 / 8.0 * np.sum(state.force**2 * inv_m))
