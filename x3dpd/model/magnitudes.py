"""Numbers a deck cannot run with: masses, speeds and loads that leave double precision.

A deck may be syntactically perfect and still describe a run that overflows at its first step: a
density so small that a particle's mass underflows to zero (its acceleration is infinite), an
initial velocity whose kinetic energy :math:`\\tfrac12 m v^2` overflows, a BODY acceleration
whose weights :math:`m|\\mathbf g|` do. :func:`magnitude_errors` lists them, one sentence each,
for ``x3dpd check`` (an error: exit 2) -- the run would otherwise stop at once on non-finite
numbers, or worse, divide by zero while advising a step.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.model.model import Model

#: Largest magnitude we accept for a kinetic energy or a weight (far below DBL_MAX ~ 1.8e308, so
#: that sums over nodes and products with a step's dt^2 stay finite).
LARGEST = 1e250


def safe_norms(v: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of ``v`` (n, 3) without overflow (``math.hypot``)."""
    return np.array([math.hypot(*row) for row in np.asarray(v, float).reshape(-1, 3)])


def magnitude_errors(model: Model) -> list[str]:
    """One message per kind of number that leaves double precision (empty: none)."""
    out = []
    ps = model.particle_start
    ids = model.node_ids
    pm = model.mass[ps:]
    bad = np.flatnonzero(~(np.isfinite(pm) & (pm > 0.0)))
    if bad.size:
        i = int(bad[0])
        out.append(
            f"{bad.size} particles have a mass of {pm[i]:.4g} (first: node "
            f"{ids[ps + i]}): PDMP PRHO * 4/3 pi RZERO^3 is not a positive finite "
            f"number, so their accelerations would be infinite"
        )
    speed = safe_norms(model.v0[:, :3])
    mass = np.where(np.isfinite(model.mass), model.mass, np.inf)
    with np.errstate(over="ignore", invalid="ignore"):
        ke = 0.5 * mass * speed * speed
    bad = np.flatnonzero(~(ke <= LARGEST) & (speed > 0.0))
    if bad.size:
        i = int(bad[np.argmax(speed[bad])])
        out.append(
            f"node {ids[i]} starts at a speed of {speed[i]:.4g} length/s: its kinetic "
            f"energy (1/2 m v^2 = {ke[i]:.4g}) overflows double precision (PDMP "
            f"VX0..VZ0 or INITIAL)"
        )
    g = math.hypot(*model.body_accel)
    with np.errstate(over="ignore", invalid="ignore"):
        weight = mass * g
    if g > 0.0 and not np.all(weight <= LARGEST):
        out.append(
            f"BODY acceleration {g:.4g} length/s^2 gives weights m|g| up to "
            f"{float(np.max(weight)):.4g}, beyond double precision"
        )
    return out


__all__ = ["LARGEST", "magnitude_errors", "safe_norms"]
