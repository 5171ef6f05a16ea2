"""The time step a generated deck needs: DTMAX from the estimate ``x3dpd check`` uses.

A deck written by ``x3dpd fill`` (or built with :mod:`x3dpd.deck.generate`) inherits a time step
chosen for other particles. :func:`fit_time_step` replaces it with
:func:`x3dpd.model.timestep.recommended_time_step` of the new deck's own model (the shortest
contact over :data:`~x3dpd.model.timestep.STEPS_PER_CONTACT` steps, or 0.2 of the structure's
critical step; report Section 7.3), so that ``x3dpd check`` finds it clean, unless the caller
gives the step. The trace keeps its interval: ITRAC is scaled by old DTMAX / new DTMAX, and the
recommended step is chosen to divide the template's trace interval exactly (a periodic random
drive's period, a whole number of the template's intervals, then stays a whole number of
samples: ``x3dpd frf``'s leakage-free lines, docs/testing-like-a-test-engineer.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from x3dpd.deck.cards import Deck
from x3dpd.errors import InputError
from x3dpd.model.build import build_model
from x3dpd.model.timestep import TimeStepAdvice, recommended_time_step


@dataclass(frozen=True)
class FittedStep:
    """What :func:`fit_time_step` did: the new ``deck``, its step ``dt`` [s], the ``advice``
    it came from (None when the caller gave the step), the template's ``old_dt`` and the
    trace interval ``itrac`` (steps) that keeps the template's trace interval."""

    deck: Deck
    dt: float
    old_dt: float
    itrac: int
    advice: TimeStepAdvice | None

    def describe(self) -> str:
        """One phrase for a command's summary line."""
        how = "as given" if self.advice is None else f"recommended ({_why(self.advice)})"
        return (
            f"DTMAX {self.dt:.3g} s {how}, was {self.old_dt:.3g} s; ITRAC {self.itrac} "
            f"keeps the trace every {self.itrac * self.dt:.6g} s"
        )


def _why(ts: TimeStepAdvice) -> str:
    if ts.binding == "contact":
        return (
            f"{ts.contact_law} {ts.contact_kind} contact {ts.t_contact:.3g} s / "
            f"{ts.steps_per_contact} steps"
        )
    return f"0.2 x the structure's critical step, node {ts.omega_node} {ts.omega_dof}"


def floor_digits(x: float, digits: int = 3) -> float:
    """``x`` rounded down to ``digits`` significant digits (9.4987e-8 -> 9.49e-8): a readable
    step that never exceeds the recommendation."""
    if not (x > 0.0 and math.isfinite(x)):
        return x
    scale = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return float(f"{math.floor(x / scale * (1.0 + 1e-12))}e{round(math.log10(scale))}")


#: Largest share of the recommended step :func:`fit_time_step` gives up to keep the template's
#: trace interval exact (the step is interval / ITRAC): with fewer than 1 / this steps per
#: interval the step is floored to 3 digits and the interval rounded instead.
INTERVAL_STEP_LOSS = 0.01


def interval_step(dt: float, interval: float) -> tuple[float, int]:
    """``(step, ITRAC)``: the largest step <= ``dt`` [s] that divides the trace ``interval``
    [s] exactly, ITRAC = ceil(interval / dt) steps, when it costs at most
    :data:`INTERVAL_STEP_LOSS` of ``dt``; else ``dt`` floored to 3 significant digits and the
    ITRAC nearest the interval (a step within 1e-12 of a divisor counts as one)."""
    n = math.ceil(interval / dt * (1.0 - 1e-12))
    if n >= 1 and interval / n >= (1.0 - INTERVAL_STEP_LOSS) * dt:
        return interval / n, n
    step = floor_digits(dt)
    return step, max(1, round(interval / step))


def fit_time_step(deck: Deck, *, dt: float | None = None, usrfrc=(), motion=()) -> FittedStep:
    """``deck`` with PARAMETERS DTMAX = ``dt`` or, when None, the recommended step of its own
    model, shortened to divide the template's trace interval DTMAX x ITRAC exactly
    (:func:`interval_step`); DTMIN becomes DTMAX on a constant-step deck (DTMIN = DTMAX) and is
    capped at DTMAX on a variable-step one; ITRAC keeps the trace interval. Raises
    :class:`InputError` when the deck has no PARAMETERS card or no step limit applies."""
    par = deck.parameters
    if par is None:
        raise InputError(f"{deck.path}: no PARAMETERS card: no time step to set")
    advice = None
    if dt is None:
        advice = recommended_time_step(
            build_model(deck, usrfrc=tuple(usrfrc), motion=tuple(motion))
        )
        if not math.isfinite(advice.dt_recommended):
            raise InputError(
                f"{deck.path}: no contact and no spring or damper on a free structural DOF "
                "limits the time step (modes are integrated exactly at any step): give one (--dt)"
            )
        dt, itrac = interval_step(advice.dt_recommended, par.itrac * par.dtmax)
    dt = float(dt)
    if not (dt > 0.0 and math.isfinite(dt)):
        raise InputError(f"time step must be a positive number; got {dt!r}")
    constant = par.dtmin >= par.dtmax
    if advice is None:
        itrac = max(1, round(par.itrac * par.dtmax / dt))
    new = replace(par, dtmax=dt, dtmin=dt if constant else min(par.dtmin, dt), itrac=itrac)
    return FittedStep(replace(deck, parameters=new), dt, float(par.dtmax), itrac, advice)


def soft_step(dt: float, stiffness: float) -> float:
    """The step that resolves a contact softened by ``stiffness`` as ``dt`` resolves the
    deck's: a Hertz impact lasts t_c = 2.87 (m*^2 / (R* E*^2 v))^(1/5) (x3dpd.model.timestep,
    hertz_contact_time; report Sec. 7.3), so t_c, and the step at the same steps per contact,
    scale as E^(-2/5) [s]."""
    return float(dt) * float(stiffness) ** -0.4


def softened(deck: Deck, stiffness: float) -> Deck:
    """``deck`` with every modulus of its particles (PDMP E0, E1, E2 ...) scaled by
    ``stiffness``, the relaxation times kept: softer contacts, the DEM field's speed lever,
    run at :func:`soft_step` (``x3dpd study --stiffness-scale``, ``x3dpd design``'s
    ``stiffness_scale``). The walls' WALLMAT moduli and a HOOKE card's stiffness are not the
    particles' and are kept."""
    f = float(stiffness)
    return replace(
        deck,
        pdmp=tuple(
            replace(
                p,
                e0=p.e0 * f,
                e1=p.e1 * f,
                extra_terms=tuple((e * f, tau) for e, tau in p.extra_terms),
            )
            for p in deck.pdmp
        ),
    )
