"""A step loop held in the hand, for the tools above the API that place a state before a run
(``x3dpd fill --settle``; a sweep point's predicted start, x3dpd.design.predict).

:func:`stepper` builds the compiled step loop of a built model (:class:`Simulation`,
docs/engine.md) at a fixed step and starts it at the deck's t0 or from an earlier run's state;
:func:`total_energy` is what the energy ledger counts as the system's energy at that moment;
:func:`apply_motion` puts prescribed nodes on their motion at a time (docs/usrfrc.md). A tool
that changes ``stepper(...).state`` books the energy it adds in ``state.e_ref`` and hands the
state to :func:`x3dpd.api.run` as a :class:`~x3dpd.api.FinalState` (``initial_state=``).
"""

from __future__ import annotations

from collections.abc import Sequence

from x3dpd.physics.motion import apply_motion
from x3dpd.solver.simulation import Simulation, process_compile_seconds


def stepper(
    model,
    *,
    dt: float | None = None,
    usrfrc: Sequence[str] = (),
    motion: Sequence[str] = (),
    state=None,
) -> Simulation:
    """The step loop of ``model`` (a built model, :func:`x3dpd.api.build`) at the fixed step
    ``dt`` [s] (default the deck's DTMAX) with extra forces ``usrfrc`` and prescribed
    ``motion`` (specs as :func:`x3dpd.api.run`'s). Started: at t0 (forces, contacts and the
    reference energy computed), or -- given ``state`` (a ``FinalState.state`` of an earlier run
    of the same deck at the same step) -- continuing from that state, which it then owns."""
    sim = Simulation(model, usrfrc=tuple(usrfrc), motion=tuple(motion), dt=dt)
    if state is None:
        sim.initialize()
    else:
        sim.restore(state)
    return sim


def total_energy(sim: Simulation) -> float:
    """Kinetic + potential + stored contact energy minus the Verlet term, as the ledger counts
    it (docs/physics.md, "Energy ledger") [energy]."""
    en = sim.energy_now()
    return float(en[:5].sum() - en[5])


__all__ = [
    "Simulation",
    "apply_motion",
    "process_compile_seconds",
    "stepper",
    "total_energy",
]
