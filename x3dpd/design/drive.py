"""How a sweep drives its deck: a force (the deck's USRFRC sine replaced) or a prescribed base
motion (a shaker table, report Section 4.2, Figure 9), and the ``--amp`` values of each.

A force drive's amplitude is a force [force]. A base drive moves its node and DOF on
``u(t) = A sin(w (t - t0))`` (x3dpd.physics.motion), its amplitude given as one of

========================  ==================  ====================================
``--amp``                 quantity            displacement amplitude A at w
========================  ==================  ====================================
``0.001``, ``0.001disp``  displacement [L]    A = d
``0.5vel``                velocity [L/T]      A = v / w
``200acc``                acceleration [L/T^2] A = a / w^2
``2g``                    acceleration        A = 2 g_n / w^2 (g_n: x3dpd.units)
========================  ==================  ====================================

(L, T the deck's length and time units; ``g`` is converted to an acceleration when read, so a
sweep's ``drive`` column holds 772.2 in/s^2 for ``2g`` in an inch deck). A sweep at a fixed
velocity or acceleration amplitude moves the base less at higher frequencies, as a shaker
controller holding an acceleration level does.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

from x3dpd.errors import InputError

#: Drive kinds of ``--drive``.
DRIVES = ("force", "base")
#: What an amplitude is, by its ``--amp`` suffix (a plain number: displacement for a base
#: drive, force for a force drive).
SUFFIXES = {"disp": "displacement", "vel": "velocity", "acc": "acceleration", "g": "acceleration"}
#: Quantities of a base drive, and the letter of each in a point's file name.
BASE_QUANTITIES = {"displacement": "D", "velocity": "V", "acceleration": "A"}
#: Largest drive level a run can hold: a force, or a base's displacement, velocity or
#: acceleration amplitude [force; length, length/s, length/s^2]. The energies a run books go
#: as a level's square (m v^2, F x, m a x), which must stay below 1e250, the largest energy
#: x3dpd accepts (x3dpd.model.magnitudes.LARGEST: far from DBL_MAX ~ 1.8e308).
LARGEST_LEVEL = 1e125

_AMP = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?)\s*([A-Za-z]*)\s*$")


def parse_amplitudes(texts: Sequence[str], drive: str, g: float) -> tuple[str, tuple[float, ...]]:
    """``--amp`` values (repeatable, each a number or a comma list) -> (quantity, values).

    ``drive`` "force": plain numbers, quantity "force". ``drive`` "base": a number with an
    optional suffix (module doc), all of one quantity; ``g`` the deck's standard gravity
    [length/time^2] for the ``g`` suffix. Raises InputError naming the bad value.
    """
    if drive not in DRIVES:
        raise InputError(f"--drive {drive!r}: expected one of {', '.join(DRIVES)}")
    quantities, values = [], []
    for text in texts:
        for part in str(text).split(","):
            match = _AMP.match(part)
            if match is None:
                raise InputError(
                    f"--amp {text!r}: expected a drive amplitude (force), or a "
                    "comma list of them; a base drive's may end in disp, vel, acc "
                    "or g (e.g. 2g)"
                )
            number, suffix = match.group(1), match.group(2).lower()
            if suffix and suffix not in SUFFIXES:
                raise InputError(
                    f"--amp {text!r}: unknown unit suffix {match.group(2)!r}; "
                    f"expected {', '.join(SUFFIXES)} (e.g. 2g, 0.5acc, 0.1vel, "
                    "0.001disp) or none"
                )
            if suffix and drive == "force":
                raise InputError(
                    f"--amp {text!r}: a force drive's amplitude is a force "
                    "(a plain number); unit suffixes are for --drive base"
                )
            v = float(number.replace("d", "e").replace("D", "e"))
            if not (math.isfinite(v) and v != 0):
                raise InputError(f"--amp {text!r}: a drive amplitude must be finite and not 0")
            if drive == "base" and v < 0:
                raise InputError(f"--amp {text!r}: a base motion's amplitude must be > 0")
            if suffix == "g":
                v *= g
            quantities.append("force" if drive == "force" else SUFFIXES.get(suffix, "displacement"))
            values.append(v)
    if not values:
        raise InputError("--amp: give at least one drive amplitude")
    if len(set(quantities)) > 1:
        raise InputError(
            f"--amp: give every amplitude of a base drive as one quantity (got "
            f"{', '.join(sorted(set(quantities)))})"
        )
    return quantities[0], tuple(dict.fromkeys(values))


def check_levels(
    quantity: str, drives, frequencies, what: str = "--amp", units: dict | None = None
) -> None:
    """InputError unless every drive level, at every frequency [Hz], stays within
    :data:`LARGEST_LEVEL`: a force drive's force; a base drive's displacement, velocity and
    acceleration amplitudes (a run with 1e300 g blew up, and its diagnosis blamed the step).
    ``units``: labels of the deck's units (x3dpd.units.labels_for) for the message."""
    units = units or {}
    for drive in drives:
        for hz in frequencies:
            w = 2.0 * math.pi * hz
            if quantity == "force":
                levels = {"force": abs(drive)}
            else:
                a = abs(displacement_amplitude(drive, quantity, w))
                levels = {quantity: abs(drive)}  # the level given first, then what it implies
                levels |= {"displacement": a, "velocity": a * w, "acceleration": a * w * w}
            for name, level in levels.items():
                if not level <= LARGEST_LEVEL:
                    unit = units.get("length" if name == "displacement" else name, "")
                    raise InputError(
                        f"{what}: a drive whose {name} amplitude is {level:.4g} {unit} at "
                        f"{hz:g} Hz is beyond what a run can hold (its energies, as the "
                        f"level squared, would overflow double precision; at most "
                        f"{LARGEST_LEVEL:g}); give a physical level"
                    )


def displacement_amplitude(value: float, quantity: str, omega: float) -> float:
    """The base's displacement amplitude A [length] at ``omega`` [rad/s] for an amplitude
    ``value`` of ``quantity`` (displacement d: A = d; velocity v: v / w; acceleration a:
    a / w^2)."""
    if quantity == "displacement":
        return value
    if quantity == "velocity":
        return value / omega
    if quantity == "acceleration":
        return value / (omega * omega)
    raise ValueError(f"not a base-drive quantity: {quantity!r}")


def base_motion_spec(node: int, dof: int, amplitude: float, hz: float, t0: float) -> str:
    """The prescribed motion (x3dpd.physics.motion) of a base-driven point: ``u = A sin(2 pi hz
    (t - t0))`` from its start ``t0`` on, no ramp. The base starts at u = 0 with its full
    velocity A w (a velocity jump; the motion's work books the kinetic energy it gives the
    base), so a point started on its predicted steady state (x3dpd.design.predict) is on it
    from the first step; a smooth ``ramp=`` would disturb that steady state."""
    return f"node={node},dof={dof},amp={float(amplitude)!r},hz={float(hz)!r},t0={float(t0)!r}"
