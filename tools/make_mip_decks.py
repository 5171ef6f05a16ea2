"""``decks/mip_apparatus_05.inp``, ``decks/mip_apparatus_025.inp`` and ``decks/mip_engine.inp``:
the report's Section 11 multiple individual particle (MIP) damper on its test apparatus and on
the jet-engine mode (called by tools/make_decks.py, which writes and checks every shipped deck).

Every number's source is in the decks' headers (report AFRL-VA-WP-TR-2003-3053, Section 11;
the material library's handbook values, x3dpd/materials/library.toml); what the report does
not give is stated there as an assumption. The plates are PLATES cards (docs/deck-reference.md),
which the deck reader builds into HOLES walls and one sphere per hole.
"""

from __future__ import annotations

import math
import textwrap

from x3dpd.deck.cards import (
    Body,
    Boundary,
    Deck,
    Element,
    Hooke,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Title,
    Trace,
    Usrfrc,
)
from x3dpd.deck.plates import sphere_ids
from x3dpd.deck.plates_card import Plate
from x3dpd.materials import in_units
from x3dpd.physics.hertz import hertz_contact_time

G = 386.1  # in/s^2, the report's
#: Section 11.3: "The cavity plates were measured to be 0.250, 0.251, 0.251, 0.252, 0.501,
#: 0.5015, 0.502, and 0.503 inch."
THICKNESS = {0.5: (0.501, 0.5015, 0.502, 0.503), 0.25: (0.250, 0.251, 0.251, 0.252)}
#: Section 11.2: "There are 988 particles in each 0.25-inch plate and 221 particles in each
#: 0.5-inch plate."
HOLES = {0.5: 221, 0.25: 988}
#: Assumed (the report gives no drawing): holes 0.005 in wider than the spheres, on a square
#: grid of this pitch centred on the 10 in plate (15 x 15 at 0.6 in spans 8.905 in; 32 x 31
#: at 0.3 in, 9.555 in).
PITCH = {0.5: 0.6, 0.25: 0.3}
HOLE_PLAY = 0.005
PLATE_SIZE = 10.0  # in, Section 11.2: "four 10 by 10-inch ... plates"
END_PLATE = 0.050  # in, Section 11.2: "0.050-inch-thick end plates"
SHIM = 0.009  # in, Section 11.4: the best calculated free length; Figure 72's shims
RESTITUTION = 0.6  # assumed: the report gives none (docs/report-studies.md)
V_REF = 8.0  # in/s: a sphere meeting the plate at twice its 3 ips rms velocity amplitude
APPARATUS = dict(mass_lb=350.0, k=6.25e5, zeta=0.047, hz=132.0, drive=150.0)
ENGINE = dict(mass_lb=600.0, hz=146.0, zeta=0.067)


def _wrapped(lines: list[str]) -> list[str]:
    """Header lines wrapped at 96 characters, continued two spaces further in."""
    out = []
    for line in lines:
        indent = " " * (len(line) - len(line.lstrip()) + 2)
        out += textwrap.wrap(line, 96, subsequent_indent=indent) or [""]
    return out


def hooke_stiffness(diameter: float, plate: str) -> tuple[float, float, float]:
    """(k_n, t_c, E*) of a HOOKE contact with Hertz's duration: an SS-302 sphere of
    ``diameter`` meeting a ``plate`` ("steel-302" or "aluminium-6061") flat at V_REF;
    k_n = m (pi / t_c)^2 makes the undamped spring's half period pi sqrt(m / k_n) = t_c."""
    ball, wall = in_units("steel-302"), in_units(plate)
    radius = 0.5 * diameter
    m = ball.rho * 4.0 / 3.0 * math.pi * radius**3
    e_star = 1.0 / ((1 - ball.nu**2) / ball.E + (1 - wall.nu**2) / wall.E)
    t_c = hertz_contact_time(m, radius, e_star, V_REF)
    return m * (math.pi / t_c) ** 2, t_c, e_star


def _plates(diameter: float, thickness, shim: float) -> tuple[Plate, ...]:
    return tuple(
        Plate(
            set_id=k + 1,
            master=1,
            holes=HOLES[diameter],
            pitch=PITCH[diameter],
            hole=diameter + HOLE_PLAY,
            thickness=t,
            size=(PLATE_SIZE, PLATE_SIZE),
            shim=shim,
            end=END_PLATE,
            axis=2,
        )
        for k, t in enumerate(thickness)
    )


def _deck(title, mass, k, c, drive, diameter, thickness, shim, dt, tmax, itrac, plate) -> Deck:
    """A spring-mounted SDOF along y (node 1, rotations and x, z fixed), gravity along -y (the
    holes' axis), the plates on it, SS-302 spheres with a HOOKE contact on ``plate``."""
    kn, _, _ = hooke_stiffness(diameter, plate)
    pd = Pdmp(1, 0.5 * diameter, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)
    fields = in_units("steel-302").pdmp_fields()
    deck = Deck(
        path="<generated>",
        title=Title(title),
        parameters=Parameters(0.0, tmax, 0.0, dt, dt, 0, 1.0e9, 0, 5, 0, itrac),
        materials=(Material(2, 1, 1.0e-12, 1.0, 1.0e12, k, 1.0e12, c),),
        pdmp=(Pdmp(**{**pd.__dict__, **fields}),),
        hooke=(Hooke(1, kn, RESTITUTION),),
        body=Body(0.0, -G, 0.0),
        nodes=(Node(1, 0.0, 0.0, 0.0),),
        elements=(Element(1, 2, (1,)),),
        masses=(Mass(1, mass, 1.0e20, 1.0e20, 1.0e20),),
        boundaries=(Boundary(1, 1, 1, (1, 3, 4, 5, 6)),),
        usrfrc=(Usrfrc((drive,)),),
        plates=_plates(diameter, thickness, shim),
    )
    return Deck(**{**deck.__dict__, "trace": Trace((1,) + tuple(a for a, _ in sphere_ids(deck)))})


def apparatus(diameter: float) -> tuple[Deck, list[str]]:
    """The Section 11.3 test apparatus with the four plates of ``diameter`` spheres."""
    a = APPARATUS
    mass = a["mass_lb"] / G
    c = 2.0 * a["zeta"] * math.sqrt(a["k"] * mass)
    fn = math.sqrt(a["k"] / mass) / (2 * math.pi)
    kn, t_c, e_star = hooke_stiffness(diameter, "steel-302")
    kn_al, t_al, e_al = hooke_stiffness(diameter, "aluminium-6061")
    dt = {0.5: 1.25e-6, 0.25: 6.25e-7}[diameter]
    drive = f"sine:node=1,dof=2,amp={a['drive']!r},hz={a['hz']!r}"
    title = (
        f"Sec. 11.3 MIP test apparatus: 350 lb SDOF, four plates of {diameter} in SS-302 "
        f"spheres\n{HOLES[diameter]} holes per plate, {SHIM} in shims, drive {a['drive']} lbf "
        f"at {a['hz']} Hz"
    )
    itrac = round(1e-4 / dt)
    deck = _deck(
        title,
        mass,
        a["k"],
        c,
        drive,
        diameter,
        THICKNESS[diameter],
        SHIM,
        dt,
        0.5,
        itrac,
        "steel-302",
    )
    free = [t + SHIM - diameter for t in THICKNESS[diameter]]
    n = HOLES[diameter]
    ball = in_units("steel-302")
    m = ball.rho * 4 / 3 * math.pi * (0.5 * diameter) ** 3
    first = [a for a, _ in sphere_ids(deck)]
    head = [
        f"mip_apparatus_{str(diameter).replace('0.', '0')}.inp: the report's Section 11 "
        f"multiple individual particle (MIP) damper,",
        f"  four plates of {n} holes with one {diameter} in SS-302 sphere each, on the 350 lb "
        "test apparatus",
        "Generated by tools/make_mip_decks.py via tools/make_decks.py (do not edit by hand).",
        "Source: AFRL-VA-WP-TR-2003-3053, Section 11 (11.2 design, 11.3 tests, Table 6).",
        "",
        "Structure (node 1, along y: the apparatus's vertical plunge mode, Sec. 11.3):",
        f"  MASS {mass:.6g} lbf s^2/in = 350 lb / {G} (Sec. 11.3: 'a modal mass of 350 "
        "pounds'); assumed to hold the plates and end plates, the spheres added to it;",
        f"  KY {a['k']:g} lbf/in (Sec. 11.3: 'The stiffness of the system was 6.25e5 lbf/in'):",
        f"  sqrt(k/m)/2 pi = {fn:.2f} Hz (Sec. 11.3: 'The first mode of the test apparatus at "
        "low levels of excitation was 132 Hz');",
        f"  C {c:.6g} lbf s/in = 2 zeta sqrt(k m), zeta {a['zeta']} (Sec. 11.3 and Table 6's "
        "150 lbf row: 132 Hz, 0.047).",
        "  The apparatus's own frequency and damping change with the level (Table 6, 150-1200 "
        "lbf):",
        "  designs/mip_apparatus.toml sets each level's ([levels]); this deck is the low level.",
        f"Drive: USRFRC {drive} (Table 6's lowest level at the low-level mode).",
        f"Gravity: BODY -{G} in/s^2 along y, the holes' axis (the apparatus is vertical).",
        "",
        "Damper (PLATES card: the reader builds each plate's HOLES wall and spheres):",
        f"  four plates of {n} holes (Sec. 11.2: '988 particles in each 0.25-inch plate and 221 "
        "particles in each 0.5-inch plate'),",
        f"  measured thicknesses {', '.join(map(str, THICKNESS[diameter]))} in (Sec. 11.3), "
        f"{PLATE_SIZE:g} x {PLATE_SIZE:g} in (Sec. 11.2),",
        f"  {SHIM} in shims (Sec. 11.4: 'the 0.009-inch shims'; Figure 72), free lengths "
        f"thickness + shim - diameter = {', '.join(f'{f:.4f}' for f in free)} in,",
        f"  {END_PLATE} in end plates between the plates (Sec. 11.2), rigid in the model.",
        f"  Spheres: {4 * n} x {m * G:.5f} lb = {4 * n * m * G:.2f} lb (Sec. 11.4: "
        f"'{'16.5' if diameter == 0.5 else '9.2'} lb'), SS-302 from the material library "
        "(x3dpd materials steel-302:",
        "  ASM Metals Handbook Desk Edition, type 302: E 193 GPa, nu 0.29, 8.0 g/cm^3; "
        "mu 0.42, Marks' Standard Handbook).",
        f"  ASSUMED (the report gives no drawing): holes {diameter + HOLE_PLAY} in across "
        f"({HOLE_PLAY} in over the spheres) on a square grid of pitch {PITCH[diameter]} in, "
        "centred on the plate;",
        "  the plates stacked along y on node 1, each on an end plate. Where the holes lie "
        "changes nothing in this deck (node 1 only translates).",
        "Contact: HOOKE (docs/deck-reference.md): one sphere per hole meets only its hole's "
        "ends, the impact damper's setting,",
        f"  where a coefficient of restitution describes each impact. ASSUMED e = {RESTITUTION} "
        "(the report gives none; docs/report-studies.md shows what it changes).",
        f"  KN = m (pi/t_c)^2 = {kn:.6g} lbf/in: the Hertz duration t_c = {t_c:.4g} s of an "
        f"SS-302 sphere on an SS-302 plate (E* {e_star:.4g} psi) at {V_REF:g} in/s",
        "  (x3dpd.physics.hertz.hertz_contact_time; report Sec. 7.2.1). The plates as tested "
        f"were aluminium (Sec. 11.2): HOOKE 1 {kn_al:.6g} {RESTITUTION}",
        f"  (E* {e_al:.4g} psi with aluminium 6061, t_c {t_al:.4g} s; x3dpd materials "
        "aluminium-6061) -- edit the HOOKE record for them.",
        f"Run: DT {dt:g} s (the HOOKE impact in {t_c / dt:.0f} steps; `x3dpd check`), TMAX 0.5 s, "
        f"trace every {itrac} steps (0.1 ms).",
        f"TRACE: node 1, then the first sphere of each plate (nodes {', '.join(map(str, first))}).",
    ]
    return deck, _wrapped(head)


def engine() -> tuple[Deck, list[str]]:
    """Section 11.2's jet-engine mode with the 0.5 in damper, driven through the stall ramp."""
    e = ENGINE
    mass = e["mass_lb"] / G
    w = 2 * math.pi * e["hz"]
    k = mass * w * w
    c = 2.0 * e["zeta"] * math.sqrt(k * mass)
    lo, hi = (v * math.sqrt(2.0) * c for v in (0.4, 3.0))
    lo, hi = round(lo, 1), round(hi, 1)
    drive = f"sine:node=1,dof=2,amp={lo!r},hz={e['hz']!r},amp1={hi!r},ramp=5.0"
    title = (
        "Sec. 11.2 jet-engine mode: 600 lb at 146 Hz, zeta 0.067, with the 0.5 in MIP damper\n"
        "stall: 0.4 -> 3.0 ips rms in 5 s"
    )
    nominal = (0.5,) * 4
    deck = _deck(title, mass, k, c, drive, 0.5, nominal, SHIM, 1.25e-6, 5.5, 400, "steel-302")
    kn, t_c, _ = hooke_stiffness(0.5, "steel-302")
    head = [
        "mip_engine.inp: the report's Section 11.2 jet-engine mode with the 0.5 in MIP damper, "
        "driven through the stall",
        "Generated by tools/make_mip_decks.py via tools/make_decks.py (do not edit by hand).",
        "Source: AFRL-VA-WP-TR-2003-3053, Section 11.2 (the customer's data) and 11.4.",
        "",
        f"Mode (node 1, along y): MASS {mass:.6g} lbf s^2/in = 600 lb / {G} (Sec. 11.2: 'The "
        "modal mass participation in the 146 Hz mode of concern is 600 lb');",
        f"  KY {k:.6g} lbf/in = m (2 pi 146)^2; C {c:.6g} lbf s/in = 2 zeta sqrt(k m), zeta 0.067 "
        "(Sec. 11.2: 'The measured damping ratio for the mode is 0.067').",
        f"Drive: USRFRC {drive}:",
        "  the stall (Sec. 11.2: 'the vibration increased from 0.4 ips rms to 3.0 ips rms in "
        "slightly less than 5 seconds'; Figure 65),",
        f"  a sine at the mode whose amplitude grows linearly (ASSUMED: Figure 65 is not "
        f"legible) from {lo} to {hi} lbf, the forces that",
        "  give the mode alone 0.4 and 3.0 ips rms at resonance, F = v_rms sqrt(2) c "
        "(docs/usrfrc.md, 'An amplitude envelope').",
        f"Gravity: BODY -{G} in/s^2 along y, the holes' axis (ASSUMED: a damper on top of the "
        "casing, its holes radial, Sec. 11.4).",
        "",
        "Damper: the 0.5 in damper as tested (four plates of 221 holes, 884 SS-302 spheres, "
        "16.5 lb; Sec. 11.2, 11.4),",
        f"  plates at the nominal 0.5 in (as drawn) with {SHIM} in shims: the 0.009 in free "
        "length of Sec. 11.2 ('the cavity free length had to be",
        "  approximately 0.009 inch') and 11.4; SS-302 plates, as the report wants for the "
        "engine (Sec. 11.4). ASSUMED: one damper",
        "  (the report envisions two on opposite sides of the engine: four more PLATES records), "
        "room-temperature properties",
        "  (the casing runs at 600-800 F, Sec. 11.1), and the apparatus deck's holes, pitch and "
        f"HOOKE contact (KN {kn:.6g} lbf/in, t_c {t_c:.4g} s,",
        f"  e = {RESTITUTION}; decks/mip_apparatus_05.inp's header says where they come from).",
        "Run: DT 1.25e-06 s, TMAX 5.5 s (the ramp and 0.5 s at 3.0 ips rms), trace every 400 "
        "steps (0.5 ms).",
        "TRACE: node 1, then the first sphere of each plate.",
    ]
    return deck, _wrapped(head)
