"""Body (gravity) acceleration from the BODY card: a force source that is an effect unit.

Every node with mass feels :math:`\\mathbf f = m\\,\\mathbf g`; the potential energy, measured from
the initial configuration, is :math:`U = -\\sum m\\,\\mathbf g\\cdot(\\mathbf x - \\mathbf x_0)`.
Units: g in length/s^2 (the report's decks: -386.1 in/s^2 along y; report Section 7.3).

An effect unit (x3dpd.physics.effect_unit) compiled into every step loop (``runtime``: a
scene without gravity has g = 0 and the same machine code, so gravity adds no loop variant).
Its ``setup`` writes m g into the nodes' body forces (``fbody``: what every step's forces start
from, reset in the kick's own pass over memory, so that gravity costs no pass of its own); its
bundle :class:`Gravity` holds g; its ``energy`` hook adds U to U_grav (the ledger's
``gravity_potential``). Its data is the model's ``body_accel`` (the BODY card,
x3dpd.model.build). The masses it weighs are the nodes' after the units before it in the
registry took theirs out (a modal structure's nodes weigh nothing here: their weight is in
the modes' static solution).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from x3dpd._jit import kernel, step_kernel
from x3dpd.physics.effect_unit import EffectUnit


class Gravity(NamedTuple):
    """The body acceleration."""

    g: np.ndarray            # (3,) body acceleration [length/s^2]


@kernel
def _gravity_energy(mass, x, x0, g):
    """U = -sum m g . (x - x0) [energy]."""
    u = 0.0
    for i in range(mass.shape[0]):
        m = mass[i]
        if m != 0.0:
            for d in range(3):
                u -= m * g[d] * (x[i, d] - x0[i, d])
    return u


@step_kernel
def energy_hook(u, nodes, en):
    """Slot ``energy``: U into U_grav (a runtime test, not a variant flag: with and without
    gravity the loop is the same code); gravity's forces are constant, in no share of S of
    their own (they are in the nodes' forces)."""
    g = u.g
    if g[0] != 0.0 or g[1] != 0.0 or g[2] != 0.0:
        en[2] += _gravity_energy(nodes.mass, nodes.x, nodes.x0, g)
    return 0.0


def body_forces(mass: np.ndarray, g: np.ndarray) -> np.ndarray:
    """(n, 6) forces m g on every node with mass [force]; zero moments."""
    out = np.zeros((mass.shape[0], 6))
    out[:, :3] = mass[:, None] * g[None, :]
    out[mass == 0.0, :3] = 0.0
    return out


def _setup(model, dt, nodes) -> dict:
    """g from the BODY card; m g added to the nodes' body forces ``fbody``."""
    g = np.ascontiguousarray(model.body_accel, np.float64).reshape(3)
    nodes["fbody"] += body_forces(nodes["mass"], g)
    return {"g": g}


UNIT = EffectUnit(
    name="gravity", flag="", runtime=True, effects=("gravity",), cards=("BODY",),
    bundle=Gravity, setup=_setup, hooks={"energy": "energy_hook"},
    doc="BODY: the body acceleration g, forces m g, potential -m g . (x - x0)")
