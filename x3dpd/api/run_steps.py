"""The steps of :func:`x3dpd.api.run`, in the order it takes them (docs/running.md), over a
:class:`~x3dpd.api.config.RunConfig` that resolved and checked everything before them:

1. :func:`make_step_loop` -- compile or load the step loop (:class:`Simulation` or the variable
   step driver) of the configured scene, continue from an ``initial_state``;
2. :func:`record_options` -- what the restart dumps record of the run;
3. :func:`open_files` -- with a trace path: the trace, its sidecar and the energy file (or, on a
   restart, the dump they resume from);
4-6. recording, stepping and the result: :mod:`x3dpd.api.run_record`.

What the steps share is a :class:`RunPlan`.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from x3dpd.api.config import RunConfig
from x3dpd.api.loop import Stats
from x3dpd.api.outputs import load_dump, open_outputs, user_file_hashes
from x3dpd.api.stepping import make_stepper
from x3dpd.errors import InputError
from x3dpd.physics.motion import motion_count
from x3dpd.solver.compile_log import expected_compile_seconds


@dataclasses.dataclass
class RunPlan:
    """What the steps of one run share: its :class:`RunConfig` and -- as the steps fill them
    in -- the step loop, the open output files and what the restart dumps record."""

    config: RunConfig
    stats: Stats
    sim: object = None  # the step loop (make_step_loop)
    options: dict = dataclasses.field(default_factory=dict)  # recorded in restart dumps
    deck_sha: str | None = None
    meta: dict | None = None  # the restart dump resumed from
    writer: object = None  # trace and energy writers (open_files)
    ewriter: object = None
    steps_before: int = 0  # variable step: steps taken before this run

    @property
    def auto(self) -> bool:
        """Whether the step is chosen by accuracy."""
        return self.config.step.auto

    @property
    def writes(self) -> bool:
        """Whether the run writes files (a trace path was given)."""
        return self.config.files is not None


def make_step_loop(plan: RunPlan) -> None:
    """Step 1: the step loop of the configured scene (fixed step or chosen by accuracy,
    x3dpd.api.stepping), recording the configured nodes, ``on_compile`` told when it must be
    compiled; continued from the configured ``initial_state`` when there is one."""
    config = plan.config
    sim = make_stepper(config)
    plan.sim = sim
    sim.trace_nodes = np.array(config.trace_nodes, dtype=np.int64)  # writable, as compiled
    sim.compiled_here = not _kernels_cached(sim)
    if config.on_compile is not None and sim.compiled_here:
        config.on_compile(CompileNotice.now())
    if config.initial_state is not None:
        _continue_from(sim, config.initial_state)


def record_options(plan: RunPlan) -> None:
    """The options a restart dump records, so that a resumed run can be refused if they
    differ."""
    config = plan.config
    plan.options = {
        "usrfrc": list(config.usrfrc),
        "motion": list(config.motion),
        "friction": config.friction,
        "tmax": config.tmax,
        "usrfrc_python": config.usrfrc_python,
        "usrfrc_files": user_file_hashes(config.applied),
        "usrfrc_mode": "replace" if config.replaced else "add",
        "step": "auto" if plan.auto else "fixed",
    }


def open_files(plan: RunPlan) -> None:
    """Step 3 (with a trace path): the sidecar's record of the run, the restart dump resumed
    from (``restart`` or the deck's IREST = 1; refused when it is at TMAX already), the trace
    and energy files opened (``overwrite`` keeps ``.bak`` copies), a stale dump removed."""
    config, files = plan.config, plan.config.files
    if files is None:
        return
    sim = plan.sim
    sidecar = _sidecar(plan)
    if files.resume:
        plan.meta = meta = load_dump(
            files.dump,
            asked_by=files.asked_by,
            sim=sim,
            key=config.key,
            options=plan.options,
            model=config.model,
        )
        sidecar["resumed_at"] = meta["time"]
        if plan.auto:
            sidecar["step"] = sim.step_record()
        if meta["step"] >= config.steps:
            raise InputError(
                f"{files.dump}: the restart dump is at t = "
                f"{meta['time']:.9g} s, not before TMAX {config.tmax:.9g} s: nothing to "
                "run (give a larger --tmax)"
            )
    plan.writer, plan.ewriter = open_outputs(
        files.trace,
        files.energy,
        sim,
        sidecar,
        plan.meta,
        sim.energy_columns,
        overwrite=files.overwrite,
    )
    if not files.resume:
        try:  # a stale dump of an earlier run must not be resumed against this trace
            os.unlink(files.dump)
        except FileNotFoundError:
            pass


def _sidecar(plan: RunPlan) -> dict:
    """The trace sidecar's record of the run (the deck and its hash, the step, the forces)."""
    from x3dpd.io.trace import sha256_file

    config, files, sim, model = plan.config, plan.config.files, plan.sim, plan.config.model
    path = config.deck_path
    plan.deck_sha = sha256_file(path) if os.path.isfile(path) else None
    sidecar = {
        "deck_path": path,
        "deck_sha256": plan.deck_sha,
        "dt": config.step.dt,
        "itrac": config.itrac,
        "effects": sorted(sim.effects),
        "title": model.title,
        "t0": model.t0,
        "tmax": config.tmax,
        "usrfrc": list(config.applied),
        "motion": list(config.motion),
        "friction": config.friction,
        "energy_file": files.energy,
        "restart_file": files.dump,
        "command": files.command,
    }
    if plan.auto:
        sidecar["dt"] = "auto"
        sidecar["step"] = sim.step_record()
    if config.replaced:
        sidecar["usrfrc_replaced"] = list(config.replaced)
    units = getattr(model, "units", None)
    if units is not None:
        sidecar["units"] = dict(units) if isinstance(units, dict) else units
    return sidecar


def _continue_from(sim, initial) -> None:
    """Restore ``initial`` (a FinalState the RunConfig checked) into the step loop; a state
    whose motions' count differs gets the actuators' forces of none yet."""
    state = initial.state.copy()
    n_motion = motion_count(sim.motion)
    if state.motion_prev.shape[0] != n_motion:
        state.units["motion_prev"] = np.zeros(n_motion)
    if initial.checkpoint is not None:
        sim.restore(state, initial.checkpoint)
    else:
        sim.restore(state)


class CompileNotice(str):
    """What ``on_compile`` receives: the message to show (a ``str``), with the compile time
    expected on this machine as ``expected_s`` [s] (x3dpd.solver.compile_log), for a progress
    line that counts up to it."""

    expected_s: float

    @classmethod
    def now(cls) -> CompileNotice:
        expected = expected_compile_seconds()
        notice = cls(
            "compiling the step loop for this scene's effects: the first run of a "
            f"scene after installing or changing x3dpd, about {expected:.0f} s here; "
            "later runs load it from the cache in about a second"
        )
        notice.expected_s = expected
        return notice


def _kernels_cached(sim) -> bool:
    """Whether numba's disk cache already holds this scene's step loop."""
    path = getattr(sim.kernels, "__file__", None)
    if not path:
        return True
    folder = os.path.join(os.path.dirname(path), "__pycache__")
    stem = os.path.splitext(os.path.basename(path))[0]
    try:
        return any(f.startswith(stem + ".") and f.endswith(".nbi") for f in os.listdir(folder))
    except OSError:
        return False
