"""A predicted start for a sweep point: the structure put on its expected steady-state motion.

A lightly damped structure forgets its start slowly: the report's beam (zeta = 0.32 %,
tau = 1 / (zeta omega) = 1.3 s) needs about 170 drive cycles for a start-up transient to fall
below 1 %, whatever the particles do. A sweep point therefore starts, by default, with the
structure already moving on the motion it is expected to settle on, a *predictor* in the sense
of numerical continuation:

* the expected response is the steady state of the linear added-mass structure (the particles'
  mass rigidly on the driven node; :mod:`x3dpd.design.baselines`), a complex amplitude
  :math:`X_a(\\omega) = F / (k - M\\omega^2 + i c\\omega)`;
* in a chain it is scaled by what the particles did at the previous point,
  :math:`X = \\rho X_a(\\omega)` with :math:`\\rho = X_{prev} / X_a(\\omega_{prev})` (amplitude
  ratio and phase shift of the measured response to the added-mass one), so a point continues on
  the branch its predecessor was on;
* with the drive :math:`F \\sin(\\omega (t - t_0))` starting at the point's start ``t0``, the
  driven DOF gets :math:`u = |X| \\sin\\varphi` and :math:`\\dot u = |X| \\omega \\cos\\varphi`
  (:math:`\\varphi = \\arg X`): every node free along that DOF (the structure, its cavity and the
  particles in it) is translated and given the same velocity change, so the particles keep their
  places, contacts and histories relative to the cavity; only the springs to ground see the
  change.

The energy this adds or removes is booked in the ledger's reference energy (the residual stays
continuous; the point's dissipation per cycle is measured from ledger differences anyway). The
steady state reached does not depend on the start where it is unique; where several coexist the
chain's scaling keeps the branch. Only structures the added-mass baseline can solve in closed
form (a linear SDOF on the driven node) are predicted; any other deck starts as before.

A base drive (x3dpd.design.drive) is predicted the same way from the added-mass structure's
:class:`~x3dpd.design.baselines.BaseSdof`: its body gets X = T(w) U about its static position
under the body force (gravity along the drive sags it by M g / k), the base starts on its own
motion, and a chain's scale comes from the body's measured response at the previous point (a
``--response`` at the body; without one a chained point is not predicted). A chained point
that is not predicted still has its base moved from the previous point's motion onto its own
at the start (:func:`continued_base_start`), the energy booked the same way.
"""

from __future__ import annotations

import cmath
import math
from collections import OrderedDict


from x3dpd.api import FinalState, build
from x3dpd.api.stepper import (
    book_energy_change,
    place_modes,
    place_structure,
    put_on_motion,
    stepper,
    total_energy,
)
from x3dpd.design.baselines import (
    ModalLinear,
    base_sdof,
    linear_structure,
    particle_mass,
    rigid_body,
    with_added_mass,
    without_particles,
)
from x3dpd.design.drive import displacement_amplitude

#: Bounds of the chain's scale |rho|: outside them the previous point is no guide.
RHO_RANGE = (1e-3, 1e3)

#: Decks whose models (and added-mass structures) are kept: the points of a chain share one
#: deck object, so a chain builds them once, not at every point (the run builds its own).
CACHED_DECKS = 4
_CACHE: OrderedDict[int, tuple] = OrderedDict()


def _cached(deck, what: tuple, make):
    """``make()``, kept per deck *object* (by identity; the entry holds the deck, so its id is
    not reused while kept) and ``what``; the last CACHED_DECKS decks are kept."""
    entry = _CACHE.get(id(deck))
    if entry is None or entry[0] is not deck:
        entry = _CACHE[id(deck)] = (deck, {})
        while len(_CACHE) > CACHED_DECKS:
            _CACHE.popitem(last=False)
    _CACHE.move_to_end(id(deck))
    if what not in entry[1]:
        entry[1][what] = make()
    return entry[1][what]


def deck_model(deck):
    """The built model of ``deck`` (:func:`x3dpd.api.build`), built once per deck object."""
    return _cached(deck, ("model",), lambda: build(deck))


def added_mass_response(
    deck, node: int, dof: int, drive: float, omega: float, model=None
) -> complex | None:
    """Complex steady-state amplitude X of the added-mass structure under drive sin(omega t)
    [length], or None when it is not a linear SDOF. ``model``: the deck's built model, if at
    hand."""
    structure = added_mass_structure(deck, node, dof, model)
    if structure is None:
        return None
    return cmath.rect(*structure.response(drive, omega))


def added_mass_structure(deck, node: int, dof: int, model=None):
    """The linear added-mass structure (an Sdof or a ModalLinear) or None (built once per deck
    object, node and DOF)."""
    if deck.modal is not None and deck.modal.housing == "included":
        return None

    def make():
        mass = particle_mass(deck_model(deck) if model is None else model)
        return linear_structure(build(with_added_mass(deck, node, mass)), node, dof)

    return _cached(deck, ("added-mass", node, dof), make)


def predicted_start(point, previous, config, t_start: float):
    """The state to start ``point`` from (``previous`` = (row, FinalState) of the point before
    in a chain, or None), with the structure on its predicted steady-state motion; None when the
    structure cannot be predicted (the caller then starts as before). ``config`` is the point's
    run (a RunConfig at a fixed step: its step, force and, for a base drive, motion specs);
    ``t_start`` [s] where the point starts."""
    if config.step.auto:
        return None
    if point.base:
        return _base_start(point, previous, config, t_start)
    model = deck_model(point.deck)

    def response(drive: float, hz: float) -> complex | None:
        return added_mass_response(
            point.deck, point.node, point.dof, drive, 2.0 * math.pi * hz, model
        )

    omega = 2.0 * math.pi * point.frequency_hz
    target = response(point.drive, point.frequency_hz)
    if target is None:
        return None
    if previous is not None:
        row = previous[0]
        before = response(row["drive"], row["frequency_hz"])
        rho = cmath.rect(row["amplitude"], math.radians(row["phase"])) / before if before else 0
        if not (cmath.isfinite(rho) and RHO_RANGE[0] <= abs(rho) <= RHO_RANGE[1]):
            return None
        target *= rho
    sim = stepper(
        model,
        usrfrc=config.usrfrc,
        dt=config.step.dt,
        state=previous[1].state.copy() if previous is not None else None,
    )
    e_before = total_energy(sim)
    if model.modal is not None:
        structure = added_mass_structure(point.deck, point.node, point.dof, model)
        if not isinstance(structure, ModalLinear):
            return None
        scale = target / response(point.drive, point.frequency_hz)
        modes = scale * structure.modal_amplitudes(point.drive, omega)
        # q = Im Q, p = omega Re Q: the coupled modes' steady state Q
        place_modes(sim, modes.imag, omega * modes.real)
    else:
        u = abs(target) * math.sin(cmath.phase(target))
        v = abs(target) * omega * math.cos(cmath.phase(target))
        place_structure(sim, model.index_of(point.node), point.dof, u, v)
    return _booked(sim, e_before, config, t_start)


def added_mass_base(deck, node: int, dof: int, model=None):
    """The base-driven added-mass structure (a BaseSdof: the particles' mass on the body the
    base carries) of a deck whose ``node`` is moved along ``dof``, or None (built once per deck
    object, node and DOF)."""

    def make():
        bare = base_sdof(build(without_particles(deck)), node, dof)
        if bare is None:
            return None
        mass = particle_mass(deck_model(deck) if model is None else model)
        return base_sdof(build(with_added_mass(deck, bare.body, mass)), node, dof)

    return _cached(deck, ("added-mass base", node, dof), make)


def _base_start(point, previous, config, t_start: float):
    """The predicted start of a base-driven point (module doc), or None."""
    model = deck_model(point.deck)
    structure = added_mass_base(point.deck, point.node, point.dof, model)
    if structure is None:
        return None
    omega = 2.0 * math.pi * point.frequency_hz

    def response(drive: float, hz: float) -> complex:
        w = 2.0 * math.pi * hz
        return displacement_amplitude(drive, point.quantity, w) * structure.transmissibility(w)

    target = response(point.drive, point.frequency_hz)
    if previous is not None:
        row = previous[0]
        seen = [
            m
            for m in row.get("responses", ())
            if (m["response_node"], m["response_dof"]) == (structure.body, point.dof)
        ]
        if not seen:
            return None
        rho = cmath.rect(seen[0]["amplitude"], math.radians(seen[0]["phase"])) / response(
            row["drive"], row["frequency_hz"]
        )
        if not (cmath.isfinite(rho) and RHO_RANGE[0] <= abs(rho) <= RHO_RANGE[1]):
            return None
        target *= rho
    sim, e_before = _base_sim(model, config, t_start, previous)
    d = point.dof - 1
    sag = structure.m * float(model.body_accel[d]) / (structure.k_base + structure.k_ground)
    u = sag + abs(target) * math.sin(cmath.phase(target))
    v = abs(target) * omega * math.cos(cmath.phase(target))
    base_side, _, _ = rigid_body(model, model.index_of(point.node))
    place_structure(sim, model.index_of(structure.body), point.dof, u, v, keep=base_side)
    return _booked(sim, e_before, config, t_start)


def continued_base_start(point, previous, config, t_start: float):
    """The previous point's final state with the base moved onto this point's motion (the
    motion specs of ``config``, the point's run) at ``t_start`` (position, velocity; the
    structure as it was), the change of energy booked in the reference energy."""
    sim, e_before = _base_sim(deck_model(point.deck), config, t_start, previous)
    return _booked(sim, e_before, config, t_start)


def _base_sim(model, config, t_start: float, previous):
    """A simulation with the base's motion, at the deck's start (the base put on its motion
    there) or at the previous point's end with the base put on this motion at ``t_start``;
    and the energy before the base was moved (at the deck's start: after)."""
    dt, motion = config.step.dt, config.motion
    if previous is None:
        sim = stepper(model, motion=motion, dt=dt)
        return sim, total_energy(sim)
    sim = stepper(model, motion=motion, dt=dt, state=previous[1].state.copy())
    e_before = total_energy(sim)
    put_on_motion(sim, t_start)
    return sim, e_before


def _booked(sim, e_before: float, config, t_start: float) -> FinalState:
    """The placed state, its forces at ``t_start`` and the energy change booked
    (x3dpd.api.stepper.book_energy_change), as the state the point's run continues from."""
    book_energy_change(sim, e_before, t_start)
    return FinalState(state=sim.state, deck_key=config.key, dt=config.step.dt, time=t_start)
