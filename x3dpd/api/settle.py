"""A filled cavity's particles let fall under the deck's gravity until they rest
(``x3dpd fill --settle``).

:func:`settle` runs the deck without its USRFRC drive (the structure free, under its BODY
gravity only) for a given time or, with ``seconds=None``, until the bed is at rest, and returns
the deck with its particles where they are, shifted back by the cavity's mean displacement (the
structure sags under their weight and swings about its sag). It says whether they rest:

* **At rest** is: no particle moves, relative to its cavity's mean velocity, faster than the
  speed a fall of 1 % of its radius gives, :math:`v_{rest} = \\sqrt{2 g \\cdot 0.01 R_{min}}`
  (0.39 in/s for R = 0.02 in under 386.1 in/s^2), at two looks :math:`3 v_{rest}/g` apart (the
  end and that much before it). A bed that rests on its floor jiggles far below it; a sphere
  still falling or bouncing is far above it at one look at least: at the top of a bounce (or
  released at rest) it is slow for a moment, but a free fall about that moment gives it at
  least :math:`1.5 v_{rest}` at one of the looks. A run shorter than the gap cannot tell, and
  says so.
* **The time scale** is the free fall across the cavity along g,
  :math:`t_{fall} = \\sqrt{2 h / g}`, h the cavity's height along g (its wall nodes' extent;
  the particles' own extent plus a diameter for analytic walls). Without a time, the run goes
  one t_fall, then quarters of it (at least the gap between the looks) until the bed rests,
  for at most ``max_falls`` t_fall.

A deck without gravity has nothing to settle under: an :class:`~x3dpd.errors.InputError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from x3dpd.api.stepper import stepper
from x3dpd.deck import Deck, Node
from x3dpd.errors import InputError
from x3dpd.model.build import build_model

#: at rest: no particle faster than a fall of this fraction of its radius gives
REST_DROP = 0.01
#: without a time: at most this many free falls across the cavity
MAX_FALLS = 20.0


@dataclass(frozen=True)
class Settled:
    """The deck after :func:`settle`: ``deck`` (its particles where the run left them),
    ``seconds`` simulated [s], ``fastest`` the fastest particle's speed relative to its cavity
    at either look [length/s], ``rest_speed`` the speed below which a bed counts as at rest
    [length/s], ``fall_time`` the free fall across the cavity [s] and ``speed_unit`` the
    deck's (``in/s``)."""

    deck: Deck
    seconds: float
    fastest: float
    rest_speed: float
    fall_time: float
    speed_unit: str = "length/s"
    #: the time between the two looks [s] (module docstring); a shorter run cannot tell
    look_gap: float = 0.0

    @property
    def told(self) -> bool:
        """Whether the run was long enough for both looks."""
        return self.seconds >= self.look_gap

    @property
    def at_rest(self) -> bool:
        return self.told and self.fastest <= self.rest_speed

    def describe(self) -> str:
        """One line: how long it ran and whether the bed rests."""
        if not self.told:
            return (
                f"after {self.seconds:.4g} s it is too early to tell whether the particles "
                f"rest (two looks {self.look_gap:.3g} s apart; the fastest at "
                f"{self.fastest:.3g} {self.speed_unit}): give a longer --settle, or --settle auto"
            )
        if self.at_rest:
            return (
                f"settled for {self.seconds:.4g} s: at rest (the fastest particle at "
                f"{self.fastest:.3g} {self.speed_unit} relative to the cavity, below "
                f"{self.rest_speed:.3g})"
            )
        return (
            f"after {self.seconds:.4g} s the particles still move: the fastest at "
            f"{self.fastest:.3g} {self.speed_unit} relative to the cavity (at rest below "
            f"{self.rest_speed:.3g}); a free fall across the cavity takes "
            f"{self.fall_time:.3g} s: give a longer --settle, or --settle auto"
        )


def settle(deck: Deck, seconds: float | None = None, *, max_falls: float = MAX_FALLS) -> Settled:
    """``deck``'s particles after ``seconds`` [s] of falling (None: until at rest, at most
    ``max_falls`` free falls across the cavity). Module docstring."""
    model = build_model(replace(deck, usrfrc=()))
    g = float(np.linalg.norm(model.body_accel))
    if g == 0.0:
        raise InputError(
            f"{deck.path}: --settle: the deck has no BODY gravity, so nothing "
            "pulls the particles down; add a BODY card"
        )
    if seconds is not None and not seconds > 0.0:
        raise InputError(f"--settle {seconds!r}: expected a time > 0 [s] or auto")
    if model.n_particles == 0:
        raise InputError(f"{deck.path}: --settle: the deck has no particles to settle")
    p0, walls = model.particle_start, np.unique(model.tri_nodes)
    # the cavity's frame: its wall nodes, or (analytic walls) the rigid bodies that carry them
    frame = walls if walls.size else np.asarray(model.rigid_master, np.int64)
    radius = np.asarray(model.radius, float)
    rest_speed = math.sqrt(2.0 * g * REST_DROP * float(radius.min()))
    fall_time = math.sqrt(2.0 * _height(model, walls, radius, g) / g)
    sim = stepper(model)

    def run_to(t: float) -> None:
        end = int(round(t / sim.dt))
        while sim.state.step < end:  # one output row at a time: memory stays small
            sim.advance(end - sim.state.step, max_rows=1)

    gap = 3.0 * rest_speed / g

    def fastest_by(t: float) -> float:
        """Run to ``t``; the fastest particle at t - gap (when the run reaches it) and at t."""
        looks = []
        if t - gap >= sim.state.step * sim.dt:
            run_to(t - gap)
            looks.append(_fastest(sim.state.vel, p0, frame))
        run_to(t)
        return max(looks + [_fastest(sim.state.vel, p0, frame)])

    if seconds is not None:
        fastest = fastest_by(seconds)
    else:
        t = max(fall_time, gap)
        fastest = fastest_by(t)
        while fastest > rest_speed and t < max_falls * fall_time:
            t += max(0.25 * fall_time, gap)
            fastest = fastest_by(t)
    x = sim.state.x
    shift = (x[frame] - model.x0[frame]).mean(axis=0) if frame.size else np.zeros(3)
    where = {int(model.node_ids[i]): x[i] - shift for i in range(p0, model.n_nodes)}
    nodes = tuple(
        Node(nd.nid, *map(float, where[nd.nid])) if nd.nid in where else nd for nd in deck.nodes
    )
    return Settled(
        replace(deck, nodes=nodes),
        sim.state.step * sim.dt,
        fastest,
        rest_speed,
        fall_time,
        f"{model.units[0]}/{model.units[2]}",
        gap,
    )


def _fastest(vel: np.ndarray, p0: int, frame: np.ndarray) -> float:
    """The largest particle speed relative to the cavity's mean velocity [length/s]."""
    moving = vel[frame, :3].mean(axis=0) if frame.size else np.zeros(3)
    rel = vel[p0:, :3] - moving
    return float(np.sqrt((rel * rel).sum(axis=1)).max()) if rel.shape[0] else 0.0


def _height(model, walls: np.ndarray, radius: np.ndarray, g: float) -> float:
    """The cavity's height along g [length]: its wall nodes' extent, or (analytic walls) the
    particles' extent plus a diameter."""
    down = np.asarray(model.body_accel, float) / g
    if walls.size:
        h = model.x0[walls] @ down
        return float(h.max() - h.min())
    h = model.x0[model.particle_start :] @ down
    return float(h.max() - h.min() + 2.0 * radius.max())
