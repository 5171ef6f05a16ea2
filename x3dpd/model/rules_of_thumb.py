"""The report's rules of thumb for a particle damper, as numbers: notes, never refusals.

Four first-order checks the report asks a designer to make before simulating (Section 7.5) --
each a :class:`RuleNote` with its number and the report's section; ``x3dpd check`` prints them
(x3dpd.cli.check) and the design tools call :func:`rules_of_thumb`.

* **turn-on** (Section 7.2.4; Section 5.2: aligned dampers "turn off" below 1 g): a particle
  resting on a wall moves when the cavity's acceleration a overcomes gravity g or friction.
  With the drive along the unit axis e at angle theta to gravity it lifts when
  a |cos theta| > g and slides when a |sin theta| > mu g (Coulomb, the PDMP card's PCOF), so

      a_on = min(g / |cos theta|, mu g / |sin theta|)

  is the turn-on level, compared with the drive's peak acceleration A (:func:`drive_estimate`).
* **clearance** (Section 10: peak displacement 3.25e-4 in, clearance "slightly less than
  6.5e-4"; Section 11.2: 0.0046 in, free length 0.009 in): the particles' free length along the
  drive -- the cavity's extent less the bed's (centres' span + 2R, as they start) -- against
  twice the structure's predicted peak displacement X.
* **mass ratio** (Section 7.5, first rule: damping grows with the particles' mass, and so does
  the frequency shift): mu_m = m_p / m_s, m_s the spring-mounted body's mass (SDOF) or the
  damped mode's effective mass 1/phi^2 at the drive (mass-normalised modes); stuck particles
  would lower the mode to f / sqrt(1 + mu_m).
* **mode separation** (Section 7.5, step 2: "well-separated, resonant modes"): the damped mode's
  nearest neighbour, as a frequency ratio and in half-power bandwidths |f_j - f_k| / (2 zeta_k
  f_k).

Modes whose frequencies agree within :data:`REPEATED` are one repeated mode (a rod's y and z
bending pair, a symmetric plate's: the eigensolver returns any two orthogonal shapes of it, so
each alone means nothing): its effective mass at the drive is 1 / sum phi_k^2 over the group,
and its nearest neighbour is the nearest mode outside it.

The structure's response is the linear one without the particles (:mod:`x3dpd.model.
linear_structure`; the undamped system of Section 7.5 step 1), to the deck's one sine or sweep
USRFRC law at a translational DOF of an SDOF or modal structure; anything else is not estimated
and the note says why (a caller may pass its own :class:`DriveEstimate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.errors import X3dpdError
from x3dpd.model.check_beds import bed_extent
from x3dpd.model.linear_structure import ModalLinear, Sdof, linear_modal, linear_sdof, rigid_body
from x3dpd.model.model import Model
from x3dpd.physics.usrfrc import (
    KIND_RANDOM,
    KIND_SINE,
    KIND_SWEEP_LINEAR,
    KIND_SWEEP_LOG,
    force_table,
    law_count,
    split_specs,
)
from x3dpd.units import labels_for, standard_gravity

SECTIONS = {
    "turn-on": "report Sections 7.2.4, 5.2",
    "clearance": "report Sections 10, 11.2",
    "mass-ratio": "report Section 7.5",
    "mode-separation": "report Section 7.5 step 2",
}
_AXES = "xyz"
#: Modes whose frequencies differ by less than this fraction are one repeated mode: far below a
#: lightly damped mode's half-power bandwidth 2 zeta (1e-3 at zeta = 0.05 %), far above the
#: rounding of an OP2 file's 32-bit frequencies (6e-8).
REPEATED = 1e-4


@dataclass(frozen=True)
class RuleNote:
    """One rule of thumb: ``code`` (a key of :data:`SECTIONS`), its headline number ``value``
    (a ratio: drive / turn-on level, free length / twice the peak displacement, particle mass /
    structure mass, neighbour frequency / damped mode's), the sentence ``text`` and the
    report's ``section``."""

    code: str
    value: float
    text: str
    section: str


@dataclass(frozen=True)
class DriveEstimate:
    """The structure's steady response to its drive: along ``dof`` (1-3) of node ``node`` (id),
    the largest displacement ``peak_displacement`` [length] and acceleration
    ``peak_acceleration`` [length/s^2] over the drive's frequencies, the mode ``mode`` (0-based)
    nearest the drive for a modal structure, ``hz`` the frequency of the displacement peak,
    and a ``description`` of the drive."""

    node: int
    dof: int
    peak_displacement: float
    peak_acceleration: float
    hz: float
    description: str
    mode: int | None = None


def _band_max(func, lo: float, hi: float, extra=()) -> tuple[float, float]:
    """(max, argmax) of ``func`` over [lo, hi] [rad/s]: a log grid, the ``extra`` points inside
    the band (resonances), then a bounded refinement around the best."""
    if hi <= lo:
        return func(lo), lo
    grid = np.concatenate([np.geomspace(lo, hi, 801), [w for w in extra if lo <= w <= hi]])
    grid.sort()
    vals = np.array([func(w) for w in grid])
    k = int(np.argmax(vals))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    if b > a:
        from scipy.optimize import minimize_scalar  # here: a second of import for every run

        res = minimize_scalar(
            lambda w: -func(w), bounds=(a, b), method="bounded", options={"xatol": 1e-10 * b}
        )
        if -res.fun > vals[k]:
            return float(-res.fun), float(res.x)
    return float(vals[k]), float(grid[k])


def _receptance(structure, omega: float) -> float:
    if isinstance(structure, Sdof):
        return 1.0 / math.hypot(structure.k - structure.m * omega**2, structure.c * omega)
    return abs(structure.receptance(omega))


def _resonances(structure) -> list[float]:
    if isinstance(structure, Sdof):
        return [math.sqrt(structure.k / structure.m)]
    return [float(w) for w in structure.omega]


def drive_estimate(model: Model, usrfrc=()) -> DriveEstimate | str:
    """The :class:`DriveEstimate` of the deck's USRFRC laws -- or of ``usrfrc`` specs, which
    replace them as ``x3dpd run --usrfrc`` does -- or a phrase saying why there is none."""
    laws, files = split_specs(tuple(usrfrc) or tuple(model.usrfrc))
    if files:
        return "the drive is a user force file"
    if not laws:
        return "no USRFRC drive"
    try:
        table = force_table(laws, model.node_ids)
    except X3dpdError as exc:
        return f"the drive cannot be read ({exc})"
    rows = table[: law_count(table)]
    if np.any(rows[:, 0] == KIND_RANDOM):
        return "a random drive"
    waves = rows[np.isin(rows[:, 0], (KIND_SINE, KIND_SWEEP_LINEAR, KIND_SWEEP_LOG))]
    if waves.shape[0] == 0:
        return "no sine or sweep drive law"
    if waves.shape[0] > 1:
        return f"{waves.shape[0]} sine or sweep drive laws (only a single one is estimated)"
    kind, index, dof_index, amp = waves[0, :4]
    node, dof = int(model.node_ids[int(index)]), int(dof_index) + 1
    structure = linear_sdof(model, node, dof, ignore_particles=True) or linear_modal(
        model, node, dof, ignore_particles=True
    )
    if structure is None:
        return (
            f"the structure driven at node {node} dof {dof} is neither a spring-mounted "
            "body nor a modal structure"
        )
    amp = abs(float(amp))
    force = labels_for(model.units)["force"]
    if kind == KIND_SINE:
        lo = hi = float(waves[0, 4])
        size = f"{amp:.3g}"
        if waves[0, 8] > 0.0:  # an envelope: its larger amplitude
            size = f"{amp:.3g} -> {abs(float(waves[0, 7])):.3g}"
            amp = max(amp, abs(float(waves[0, 7])))
        what = f"sine {size} {force} at {lo / (2 * math.pi):.4g} Hz"
    else:
        f0, f1 = sorted((float(waves[0, 4]), float(waves[0, 5])))
        lo, hi = 2 * math.pi * f0, 2 * math.pi * f1
        what = f"sweep {amp:.3g} {force} over {f0:.4g}-{f1:.4g} Hz"
    extra = _resonances(structure)
    x, w_x = _band_max(lambda w: amp * _receptance(structure, w), lo, hi, extra)
    a, _ = _band_max(lambda w: amp * w * w * _receptance(structure, w), lo, hi, extra)
    mode = None
    if isinstance(structure, ModalLinear):
        mode = int(np.argmin(np.abs(structure.omega - w_x)))
    return DriveEstimate(
        node, dof, x, a, w_x / (2 * math.pi), f"{what} at node {node} {_AXES[dof - 1]}", mode
    )


def _turn_on(model: Model, drive, g0: float, acc: str) -> RuleNote:
    g_vec = np.asarray(model.body_accel, float)
    g = math.hypot(*g_vec)
    mus = sorted(set(np.round(model.mu, 12).tolist()))
    mu_text = "mu " + (f"{mus[0]:.3g}" if len(mus) == 1 else f"{mus[0]:.3g}-{mus[-1]:.3g}")
    if g == 0.0:
        return RuleNote(
            "turn-on",
            0.0,
            "no BODY gravity holds the particles: any vibration moves them",
            SECTIONS["turn-on"],
        )
    if isinstance(drive, str):
        return RuleNote(
            "turn-on",
            math.nan,
            (
                f"the particles lift when the cavity's acceleration along gravity exceeds g = "
                f"{g:.4g} {acc} ({g / g0:.3g} g) and slide when it exceeds {mu_text} x g across "
                f"it; the drive's acceleration is not estimated ({drive})"
            ),
            SECTIONS["turn-on"],
        )
    cos = abs(g_vec[drive.dof - 1]) / g
    sin = math.sqrt(max(0.0, 1.0 - cos * cos))
    lift = g / cos if cos > 1e-12 else math.inf
    slide = max(mus) * g / sin if sin > 1e-12 else math.inf
    how = (
        f"lift them (gravity {math.degrees(math.acos(min(cos, 1.0))):.3g} deg from the drive)"
        if lift <= slide
        else f"slide them ({mu_text} x g, the drive "
        f"{math.degrees(math.asin(min(sin, 1.0))):.3g} deg across gravity)"
    )
    level = min(lift, slide)
    ratio = drive.peak_acceleration / level if level > 0 else math.inf
    return RuleNote(
        "turn-on",
        ratio,
        (
            f"the cavity needs {level:.3g} {acc} ({level / g0:.3g} g) to {how}; the drive "
            f"({drive.description}, on the structure without particles) gives up to "
            f"{drive.peak_acceleration:.3g} {acc} ({drive.peak_acceleration / g0:.3g} g): "
            f"{ratio:.3g} x the turn-on level"
            + ("" if ratio >= 1 else ": the particles will not move (they act as added mass)")
        ),
        SECTIONS["turn-on"],
    )


def _clearances(model: Model, drive: DriveEstimate, length: str) -> list[RuleNote]:
    d = drive.dof - 1
    out = []
    for c, sid in enumerate(model.cavity_set_ids.tolist()):
        extent = bed_extent(model, c, d)
        if extent is None:
            continue
        cavity, bed, free = extent
        twice = 2.0 * drive.peak_displacement
        ratio = free / twice if twice > 0 else math.inf
        out.append(
            RuleNote(
                "clearance",
                ratio,
                (
                    f"cavity set {sid}: the particles' free length along {_AXES[d]} is {free:.3g} "
                    f"{length} (cavity {cavity:.4g} less the bed {bed:.4g} as they start); "
                    f"twice the structure's predicted peak displacement ({drive.description}) is "
                    f"{twice:.3g} {length}: free length = {ratio:.3g} x that (the report's dampers "
                    "work best near 1)"
                ),
                SECTIONS["clearance"],
            )
        )
    return out


def repeated_group(omega: np.ndarray, mode: int) -> list[int]:
    """The modes (0-based) that are one repeated mode with ``mode`` (:data:`REPEATED`)."""
    w = np.asarray(omega, float)
    return [j for j in range(w.size) if abs(w[j] - w[mode]) <= REPEATED * w[mode]]


def _group_text(group: list[int], hz: float) -> str:
    if len(group) == 1:
        return f"mode {group[0] + 1}"
    names = ", ".join(str(j + 1) for j in group[:-1]) + f" and {group[-1] + 1}"
    return f"modes {names} (one repeated mode at {hz:.4g} Hz)"


def _cavity_dof(model: Model, group: list[int]) -> tuple[int, int] | None:
    """(node id, dof 1-3) where the first cavity's body moves most in the modes ``group``: the
    master of the rigid body holding its first wall node, its translation of largest sum of
    phi^2."""
    walls = model.tri_nodes.reshape(-1)[:1].tolist() + model.shape_nodes.reshape(-1)[:1].tolist()
    if not walls:
        return None
    _, _, master = rigid_body(model, int(walls[0]))
    phi = [float(np.sum(model.modal.shape_at(master, d)[group] ** 2)) for d in range(3)]
    return int(model.node_ids[master]), int(np.argmax(phi)) + 1


def _mass_ratio(model: Model, drive, modal_mode: int | None, mass: str) -> RuleNote | None:
    mp = float(np.sum(model.mass[model.particle_start :]))
    ms, what, hz = float(np.sum(model.mass[: model.particle_start])), "total structure mass", None
    where = None if isinstance(drive, str) else (drive.node, drive.dof)
    if where is not None:
        sdof = linear_sdof(model, drive.node, drive.dof, ignore_particles=True)
        if sdof is not None:
            ms, what = sdof.m, "spring-mounted body's mass"
            hz = math.sqrt(sdof.k / sdof.m) / (2 * math.pi)
            where = None
    if model.modal is not None and modal_mode is not None:
        group = repeated_group(model.modal.omega, modal_mode)
        where = where or _cavity_dof(model, group)
        if where is not None and where[0] in model.node_ids:
            phi = model.modal.shape_at(model.index_of(where[0]), where[1] - 1)[group]
            if np.any(phi != 0.0):
                hz = float(model.modal.omega[modal_mode]) / (2 * math.pi)
                ms = 1.0 / float(np.sum(phi**2))
                what = (
                    f"{_group_text(group, hz)}'s effective mass at node {where[0]} "
                    f"{_AXES[where[1] - 1]}"
                )
    if not ms > 0:
        return None
    ratio = mp / ms
    text = f"particles {mp:.4g} {mass} / {what} {ms:.4g} {mass} = {ratio:.3g} ({100 * ratio:.3g} %)"
    if hz is not None:
        text += (
            f"; were they stuck to the cavity, the mode would move from {hz:.4g} Hz to "
            f"{hz / math.sqrt(1 + ratio):.4g} Hz"
        )
    return RuleNote("mass-ratio", ratio, text, SECTIONS["mass-ratio"])


def _separation(model: Model, mode: int) -> RuleNote:
    ms = model.modal
    f = ms.omega / (2 * math.pi)
    group = repeated_group(ms.omega, mode)
    damped = _group_text(group, float(f[mode]))
    others = [j for j in range(f.size) if j not in group]
    if not others:
        return RuleNote(
            "mode-separation",
            math.inf,
            f"{damped} at {f[mode]:.4g} Hz is the structure's only mode",
            SECTIONS["mode-separation"],
        )
    j = min(others, key=lambda k: abs(f[k] - f[mode]))
    band = 2.0 * ms.zeta[mode] * f[mode]
    bandwidths = abs(f[j] - f[mode]) / band if band > 0 else math.inf
    return RuleNote(
        "mode-separation",
        float(f[j] / f[mode]),
        (
            f"the damped {damped} ({f[mode]:.4g} Hz) has its nearest neighbour, mode "
            f"{j + 1}, at {f[j]:.4g} Hz: {f[j] / f[mode]:.3g} x its frequency, {bandwidths:.3g} "
            "half-power bandwidths away (particle dampers suit well-separated modes)"
        ),
        SECTIONS["mode-separation"],
    )


def rules_of_thumb(
    model: Model, *, usrfrc=(), drive: DriveEstimate | None = None
) -> list[RuleNote]:
    """The rules of thumb of a model (module docstring): turn-on, clearance per cavity, mass
    ratio, and for a modal structure the damped mode's separation. ``drive`` replaces the
    estimate of the deck's USRFRC drive (or of ``usrfrc`` specs, which replace the deck's).
    Never raises on a model that builds: a rule it cannot evaluate (numbers at the edge of double
    precision included) is left out or says why."""
    units = labels_for(model.units)
    with np.errstate(all="ignore"):
        estimate = drive if drive is not None else _guarded(drive_estimate, model, usrfrc)
        if estimate is None:
            estimate = "the drive's response overflows"
        mode = None
        if model.modal is not None:
            mode = (
                estimate.mode if not isinstance(estimate, str) and estimate.mode is not None else 0
            )
        out = []
        if model.n_particles:
            out.append(
                _guarded(
                    _turn_on, model, estimate, standard_gravity(model.units), units["acceleration"]
                )
            )
            if not isinstance(estimate, str):
                out += _guarded(_clearances, model, estimate, units["length"]) or []
            out.append(_guarded(_mass_ratio, model, estimate, mode, units["mass"]))
        if model.modal is not None and model.modal.omega.size:
            out.append(_guarded(_separation, model, mode))
    return [note for note in out if note is not None]


def _guarded(rule, *args):
    """``rule(*args)``, or None when its arithmetic overflows or fails (an extreme deck)."""
    try:
        return rule(*args)
    except (ArithmeticError, ValueError):
        return None
