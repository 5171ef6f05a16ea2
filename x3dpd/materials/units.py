"""A material in a deck's unit system (the UNITS card, x3dpd.units; default inch-lbf-s).

Library values are SI. In a system whose length, force and time units are L, F, T metres,
newtons and seconds: pressure [F/L^2] = Pa * L^2 / F (psi for inch-lbf), mass density
[F T^2 / L^4] = kg/m^3 * L^4 / (F T^2) (lbf s^2/in^4 for inch-lbf-s), time = s / T.
Converted values are rounded to 12 significant digits, so that a value the source gave in the
deck's own units comes back as written (30e6 psi -> Pa -> 30000000.0 psi), not one ulp off.
"""

from __future__ import annotations

from dataclasses import dataclass

from x3dpd.materials.library import Material, MaterialError, material
from x3dpd.units import DEFAULT, parse_units, si_size


def round12(x: float) -> float:
    """``x`` to 12 significant digits (a value given in the deck's units comes back as written)."""
    return float(f"{x:.12g}")


def unit_system(units) -> tuple[str, str, str]:
    """(length, force, time) from None, a tuple, ``"in lbf s"`` or a UNITS card."""
    if units is None:
        return DEFAULT
    if hasattr(units, "system"):
        units = units.system
    if isinstance(units, str):
        units = units.split()
    try:
        return parse_units(units)
    except ValueError as exc:
        raise MaterialError(f"units: {exc}") from None


@dataclass(frozen=True)
class DeckMaterial:
    """A :class:`Material` in the unit system ``units`` = (length, force, time): ``E`` and
    the Maxwell arms' moduli [force/length^2], ``rho`` [force time^2/length^4], taus [time]."""

    name: str
    E: float
    nu: float
    rho: float
    mu: float
    maxwell: tuple[tuple[float, float], ...]
    units: tuple[str, str, str]

    def pdmp_fields(self) -> dict:
        """The PDMP card's material fields (report Appendix B): PRHO, PPOI, E0, E1, T1, PCOF and
        our further Maxwell pairs. An elastic material has E1 = 0 and T1 = 1 (Appendix B: "T1
        is set to any nonzero number")."""
        e1, t1 = self.maxwell[0] if self.maxwell else (0.0, 1.0)
        return {
            "prho": self.rho,
            "ppoi": self.nu,
            "e0": self.E,
            "e1": e1,
            "t1": t1,
            "pcof": self.mu,
            "extra_terms": tuple(self.maxwell[1:]),
        }


def in_units(mat, units=None) -> DeckMaterial:
    """``mat`` (a :class:`Material` or a name) in ``units``: None (inch-lbf-s, the report's
    decks), ``(length, force, time)``, a string such as ``"m N s"``, or a deck's UNITS card.
    Raises :class:`MaterialError` for units x3dpd does not know (x3dpd.units)."""
    mat: Material = material(mat)
    system = unit_system(units)
    metres, newtons, seconds = si_size(system)
    pressure = metres**2 / newtons  # per Pa
    density = metres**4 / (newtons * seconds**2)  # per kg/m^3
    return DeckMaterial(
        name=mat.name,
        E=round12(mat.E * pressure),
        nu=mat.nu,
        rho=round12(mat.rho * density),
        mu=mat.mu,
        maxwell=tuple((round12(e * pressure), round12(tau / seconds)) for e, tau in mat.maxwell),
        units=system,
    )
