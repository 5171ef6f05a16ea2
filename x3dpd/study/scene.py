"""What a study measures on a scene, and how.

:func:`classify` tells an impact scene (particles with initial velocities, no drive, no gravity),
a driven damper (a USRFRC force) and a free scene (anything else, e.g. particles settling) apart,
and whether trajectories are chaotic (more than one particle and a drive or gravity: two runs
that differ in the last bit of one coordinate part ways within a few impacts, so only statistics
compare). :func:`measure` reduces one run to the scene's quantities:

* impact: ``peak_force`` = max over particles and steps of m |v(n+1) - v(n)| / dt (velocity
  Verlet's kick is the mean of two force samples) [force]; ``restitution`` = the particles'
  speed after / before, sqrt(KE_end / KE_0); ``contact_time`` = the time the ledger's contact
  energy is non-zero [s];
* driven: ``amplitude`` = half the peak-to-peak displacement of the measured node along the
  drive's direction (the USRFRC force's or prescribed motion's DOF; x when none says) over the
  last third of the window [length]; ``power_per_cycle`` = energy dissipated per drive cycle
  over that third (viscoelastic + friction + dampers, from the ledger) [energy]; the node's
  displacement history for the trace norm;
* free: ``dissipated`` = total energy dissipated by the end of the window [energy], and the first
  traced node's history.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from x3dpd.api import DEFAULT_FRICTION

MAIN = {"impact": "peak_force", "driven": "amplitude", "free": "dissipated"}
QUANTITIES = {
    "impact": ("peak_force", "restitution", "contact_time"),
    "driven": ("amplitude", "power_per_cycle"),
    "free": ("dissipated",),
}
_DISSIPATED = ("dissipated_viscoelastic", "dissipated_friction", "dissipated_dampers")


@dataclass(frozen=True)
class Scene:
    """``kind`` ("impact" | "driven" | "free"), ``chaotic``, the node measured (user id), the
    drive frequency [Hz] (0 when unknown), whether the particles are viscoelastic and have
    friction."""

    kind: str
    chaotic: bool
    node: int
    drive_hz: float
    viscoelastic: bool
    friction: bool
    n_particles: int
    #: the deck's tangential law (its FRICTION card's, else x3dpd.api.DEFAULT_FRICTION)
    friction_law: str = DEFAULT_FRICTION
    #: the direction measured (0, 1, 2: x, y, z): the drive's DOF
    axis: int = 0

    @property
    def main(self) -> str:
        return MAIN[self.kind]


def classify(model, usrfrc=(), motion=()) -> Scene:
    """The scene of a built model (``usrfrc``: the force specs the study applies; ``motion``:
    its prescribed motions, which drive the scene at their frequency but are not what is
    measured: a base-driven deck's response is its traced node, not the shaker's)."""
    effects = set(model.effects)
    specs = list(usrfrc) or list(model.usrfrc)
    driven = bool(specs) or bool(motion) or "external_force" in effects
    gravity = bool(np.any(model.body_accel != 0.0))
    n = int(model.n_particles)
    moving = n and bool(np.any(model.v0[model.particle_start :, :3] != 0.0))
    kind = "driven" if driven else ("impact" if moving and not gravity else "free")
    node = int(model.node_ids[model.trace_nodes[0]]) if len(model.trace_nodes) else 0
    hz = 0.0
    axis = None
    for spec in specs:
        m = re.search(r"node=(\d+)", spec)
        f = re.search(r"hz=([0-9.eE+-]+)", spec)
        if m and node == 0:
            node = int(m.group(1))
        if f and not hz:
            hz = float(f.group(1))
        if m and f:
            node = int(m.group(1))
            axis = _axis(spec)
            break
    for spec in motion:
        f = re.search(r"hz=([0-9.eE+-]+)", spec)
        if f and not hz:
            hz = float(f.group(1))
        if axis is None:
            axis = _axis(spec)
    return Scene(
        kind,
        n > 1 and (driven or gravity),
        node,
        hz,
        "viscoelastic" in effects,
        "friction" in effects,
        n,
        getattr(model, "friction_law", None) or DEFAULT_FRICTION,
        axis or 0,
    )


def _axis(spec: str) -> int | None:
    """The translation a drive spec's ``dof=`` names (0, 1, 2), None for a rotation or none."""
    d = re.search(r"dof=(\d+)", spec)
    return int(d.group(1)) - 1 if d and 1 <= int(d.group(1)) <= 3 else None


def measure(result, scene: Scene) -> dict:
    """The scene's quantities from one run's result (see the module docstring), plus
    ``signal`` = (times, the measured node's displacement along ``scene.axis``) for the trace
    norm."""
    tr, en = result.trace, result.energy
    t = tr.time
    out: dict = {}
    ids = tr.node_ids.tolist()
    k = ids.index(scene.node) if scene.node in ids else 0
    x = tr.position[:, k, scene.axis] - tr.position[0, k, scene.axis]
    out["signal"] = (t.copy(), x.copy())
    if scene.kind == "impact":
        model = result.model
        p0 = model.particle_start
        mass = np.array([model.mass[p0 + i] for i in range(model.n_particles)])
        pid = [
            ids.index(int(model.node_ids[p0 + i]))
            for i in range(model.n_particles)
            if int(model.node_ids[p0 + i]) in ids
        ]
        v = tr.velocity[:, pid, :]
        dt = np.diff(t)[:, None]
        dv = np.linalg.norm(np.diff(v, axis=0), axis=2) / dt if len(t) > 1 else np.zeros((1, 1))
        out["peak_force"] = float(np.max(dv * mass[None, : len(pid)])) if dv.size else 0.0
        ke = en["kinetic_translation"] + en["kinetic_rotation"]
        out["restitution"] = math.sqrt(ke[-1] / ke[0]) if ke[0] > 0 else math.nan
        touching = en["contact_energy"] > 0.0
        out["contact_time"] = float(np.sum(touching) * np.median(np.diff(t))) if len(t) > 1 else 0.0
    elif scene.kind == "driven":
        third = t >= t[0] + (t[-1] - t[0]) * 2.0 / 3.0
        out["amplitude"] = float(np.ptp(x[third]) / 2.0) if third.any() else math.nan
        lost = sum(en[c] for c in _dissipated(en))
        span = t[third][-1] - t[third][0] if third.sum() > 1 else 0.0
        rate = (lost[third][-1] - lost[third][0]) / span if span > 0 else math.nan
        out["power_per_cycle"] = rate / scene.drive_hz if scene.drive_hz else rate
    else:
        out["dissipated"] = float(sum(en[c][-1] for c in _dissipated(en)))
    return out


def _dissipated(energy) -> tuple:
    """The ledger's dissipation columns of a run: viscoelastic, friction, dampers, and rolling
    resistance when its scene has a rolling law."""
    return _DISSIPATED + tuple(c for c in ("dissipated_rolling",) if c in energy.columns)


def trace_norm(signal, reference) -> float:
    """Relative RMS difference of two displacement histories at their common times:
    ||x - x_ref|| / ||x_ref|| (tracediff's comparison reduced to one number)."""
    t, x = signal
    tr, xr = reference
    if len(t) == 0 or len(tr) == 0:
        return math.nan
    step = np.median(np.diff(tr)) if len(tr) > 1 else 1.0
    key = np.round(t / step * 1e6).astype(np.int64)
    key_r = np.round(tr / step * 1e6).astype(np.int64)
    common, ia, ib = np.intersect1d(key, key_r, return_indices=True)
    if common.size < 2:
        return math.nan
    norm = float(np.linalg.norm(xr[ib]))
    return float(np.linalg.norm(x[ia] - xr[ib]) / norm) if norm > 0 else math.nan
