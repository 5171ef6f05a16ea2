"""Unit systems a deck may declare (the ``UNITS`` card, our extension; default inch-lbf-s).

X3D has no units: every number is in one consistent system chosen by whoever wrote the deck. The
report's decks use inch, lbf and second, so mass is in lbf s^2/in and energy in lbf in. A deck
may name its system with a ``UNITS`` card of one record, ``LENGTH FORCE TIME``::

    UNITS
      m N s
    END

The solver does not convert anything -- the numbers are used as written -- but labels (plots,
movies, the trace sidecar's ``units``, ``x3dpd check``) follow the declared system. Derived units
are spelled out: mass = force time^2 / length, energy = force length, pressure = force /
length^2, with the usual names where the system has one (kg, J, Pa for m N s; psi for in lbf).
"""

from __future__ import annotations

LENGTHS = ("in", "ft", "m", "cm", "mm")
FORCES = ("lbf", "N", "kN", "dyn")
TIMES = ("s", "ms")
DEFAULT = ("in", "lbf", "s")

#: Names of derived units where a system has one: (length, force, time) -> {quantity: name}.
_NAMED = {
    ("m", "N", "s"): {"mass": "kg", "energy": "J", "pressure": "Pa"},
    ("mm", "N", "s"): {"mass": "t", "energy": "mJ", "pressure": "MPa"},
    ("cm", "dyn", "s"): {"mass": "g", "energy": "erg", "pressure": "Ba"},
    ("in", "lbf", "s"): {"pressure": "psi"},
    ("ft", "lbf", "s"): {"mass": "slug"},
}


def parse_units(words) -> tuple[str, str, str]:
    """``(length, force, time)`` from three unit names (case as listed in LENGTHS, FORCES, TIMES;
    matched case-insensitively). Raises ValueError saying what was expected."""
    words = [str(w) for w in words]
    if len(words) != 3:
        raise ValueError(
            f"expected 3 unit names LENGTH FORCE TIME (e.g. 'in lbf s' or 'm N s'); "
            f"got {len(words)}: {' '.join(words) or '(none)'}"
        )
    out = []
    for word, allowed, what in zip(words, (LENGTHS, FORCES, TIMES), ("LENGTH", "FORCE", "TIME")):
        hit = [a for a in allowed if a.lower() == word.lower()]
        if not hit:
            raise ValueError(f"{what} unit {word!r}: expected one of {', '.join(allowed)}")
        out.append(hit[0])
    return tuple(out)  # type: ignore[return-value]


def labels_for(system=None) -> dict[str, str]:
    """Labels of every quantity x3dpd prints, for ``system`` = (length, force, time) or None
    (the default inch-lbf-s)."""
    length, force, time = tuple(system) if system else DEFAULT
    named = _NAMED.get((length, force, time), {})
    return {
        "system": f"{length} {force} {time}",
        "time": time,
        "length": length,
        "velocity": f"{length}/{time}",
        "angular_velocity": f"rad/{time}",
        "acceleration": f"{length}/{time}^2",
        "force": force,
        "mass": named.get("mass", f"{force} {time}^2/{length}"),
        "energy": named.get("energy", f"{force} {length}"),
        "pressure": named.get("pressure", f"{force}/{length}^2"),
        "density": f"{named['mass']}/{length}^3"
        if "mass" in named
        else f"{force} {time}^2/{length}^4",
    }


def trace_units(system=None) -> dict[str, str]:
    """The units a trace's sidecar records: those of its columns (``x3dpd.io.trace.
    DEFAULT_UNITS``) and, for tools that read the energy file beside it, force, mass, energy."""
    lab = labels_for(system)
    return {
        k: lab[k]
        for k in ("time", "length", "velocity", "angular_velocity", "force", "mass", "energy")
    }


#: Standard gravity g_n = 9.80665 m/s^2 in each length unit per s^2; inch decks use the
#: report's 386.1 in/s^2 (its BODY card, Appendix A; 9.80665 / 0.0254 = 386.0886), so that
#: "1 g" means what the shipped decks' gravity and the ring-down's dB re 1 g mean.
_STANDARD_GRAVITY = {
    "in": 386.1,
    "ft": 9.80665 / 0.3048,
    "m": 9.80665,
    "cm": 980.665,
    "mm": 9806.65,
}
#: SI size of each unit: metres per length unit, newtons per force unit, seconds per time unit
#: (lbf: the international pound-force, 0.45359237 kg x 9.80665 m/s^2, exact).
LENGTH_SI = {"in": 0.0254, "ft": 0.3048, "m": 1.0, "cm": 0.01, "mm": 0.001}
FORCE_SI = {"lbf": 4.4482216152605, "N": 1.0, "kN": 1000.0, "dyn": 1e-5}
TIME_SI = {"s": 1.0, "ms": 1.0e-3}
_SECONDS = TIME_SI


def si_size(system=None) -> tuple[float, float, float]:
    """``(metres, newtons, seconds)`` in one length, force and time unit of ``system`` =
    (length, force, time) or None (inch-lbf-s). A quantity of dimension L^a F^b T^c is
    ``value * m**a * n**b * s**c`` in SI."""
    length, force, time = tuple(system) if system else DEFAULT
    return LENGTH_SI[length], FORCE_SI[force], TIME_SI[time]


def standard_gravity(system=None) -> float:
    """One standard gravity in the acceleration unit of ``system`` = (length, force, time) or
    None (inch-lbf-s): 386.1 in/s^2, 9.80665 m/s^2, 32.174 ft/s^2, ... [length/time^2]."""
    length, _, time = tuple(system) if system else DEFAULT
    return _STANDARD_GRAVITY[length] * _SECONDS[time] ** 2
