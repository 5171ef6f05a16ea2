"""A step loop held in the hand, for the tools above the API that place a state before a run
(``x3dpd fill --settle``; a sweep point's predicted start, x3dpd.design.predict).

:func:`stepper` builds the compiled step loop of a built model (:class:`Simulation`,
docs/engine.md) at a fixed step and starts it at the deck's t0 or from an earlier run's state.
A tool changes its state only through the solver's placement operations
(x3dpd.solver.placement): :func:`total_energy` (what the energy ledger counts as the system's
energy now), :func:`place_structure`, :func:`place_modes` (with :func:`carry_particles`),
:func:`put_on_motion`, and :func:`book_energy_change`, which books the energy they added in the
ledger's reference energy. It hands the state to :func:`x3dpd.api.run` as a
:class:`~x3dpd.api.FinalState` (``initial_state=``).
"""

from __future__ import annotations

from collections.abc import Sequence

from x3dpd.solver.placement import (
    book_energy_change,
    body_poses,
    carry_particles,
    place_modes,
    place_structure,
    put_on_motion,
    total_energy,
)
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


__all__ = [
    "Simulation",
    "body_poses",
    "book_energy_change",
    "carry_particles",
    "place_modes",
    "place_structure",
    "process_compile_seconds",
    "put_on_motion",
    "stepper",
    "total_energy",
]
