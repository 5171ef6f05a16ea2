"""``decks/capsule_wc7.inp``: the report's Section 6.4 temperature-chamber capsule -- a titanium
capsule with seven through holes, one 1/8 in tungsten-carbide sphere in each, on the Section 8
beam -- as a deck at temperature (called by tools/make_decks.py, which writes and checks every
shipped deck).

Report AFRL-VA-WP-TR-2003-3053, Sec. 6.4: "a titanium capsule with seven through holes
containing seven tungsten carbide spheres 1/8-inch in diameter", ring-downs from -94 to 365 F
(Figure 20); Sec. 6.3 names what is probably the same standard treatment: "7 by 9/64 inch
diameter bores in a titanium test capsule with two caps. Free internal length was 5/32-inch."
The rest (the hole pattern, the loss and friction of the spheres, the capsule's mass) is
assumed, and the header says so line by line.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.deck import cards as c
from x3dpd.deck.temperature_card import MaterialRecord, Reading, Temperature
from x3dpd.materials import material_at, parse_temperature

REPORT = "AFRL-VA-WP-TR-2003-3053"
G = 386.1  # in/s^2 (the report's gravity)
# ---- the host: Sec. 8.2's beam model (as tools/make_decks.py's beam decks) ------------------
BEAM_MASS = 2.04213e-4  # lbf s^2/in, Sec. 8.2 equivalent mass (beam + cavity)
BEAM_K = 1.14823e1  # lbf/in, Table 4
BEAM_C = 3.08293e-4  # lbf s/in, Table 4
RIGID = 1.0e12  # lbf/in, the beam decks' y and z springs
# ---- the capsule (Sec. 6.3, 6.4) ------------------------------------------------------------
N_HOLES = 7  # "seven through holes containing seven tungsten carbide spheres"
RADIUS = 0.0625  # in, "1/8-inch in diameter"
BORE_RADIUS = 9.0 / 128.0  # in, "9/64 inch diameter bores" (Sec. 6.3)
FREE_LENGTH = 5.0 / 32.0  # in, "Free internal length was 5/32-inch" (Sec. 6.3), read as the
#                           report's free length (Sec. 11: the room a sphere has to travel)
BORE_LENGTH = 2.0 * RADIUS + FREE_LENGTH  # in, 9/32 between the caps
PITCH = 3.0 / 16.0  # in, hole centre to centre: assumed (the report gives no pattern)
# ---- materials: the library's, at the assembly temperature ----------------------------------
ASSEMBLY = "70F"
SPHERES, WALLS = "tungsten-carbide", "titanium"
STEEL_LOSS = 5.0 / 32.5  # Sec. 8.3 steel: E1 / (E0 + E1) = 5e6 / (27.5e6 + 5e6)
TAU1 = 2.0e-6  # s, Sec. 8.3 steel's relaxation time
# ---- drive and run ---------------------------------------------------------------------------
DRIVE_AMP, DRIVE_HZ = 0.04, 37.0  # lbf, Hz: rings the beam past the spheres' peak damping
DT, TMAX, ITRAC, TREST = 5e-7, 2.0, 2000, 0.1
SEED = 2003
MASTER = 1


def hole_centres() -> np.ndarray:
    """(7, 3): the holes' axes cross the plane x = 0 at the centre and the corners of a hexagon
    of side PITCH in the y-z plane (the drive is along x)."""
    angle = np.arange(6) * np.pi / 3.0
    ring = np.column_stack([np.zeros(6), PITCH * np.sin(angle), PITCH * np.cos(angle)])
    return np.vstack([np.zeros((1, 3)), ring])


def sphere_positions(centres: np.ndarray) -> np.ndarray:
    """One sphere per hole, resting a tenth of the radial gap above the bore's bottom (gravity
    along -y), at an axial place drawn (seed SEED) within the middle 80 % of its free length, so
    that the seven do not move in lockstep."""
    rng = np.random.default_rng(SEED)
    gap = BORE_RADIUS - RADIUS
    x = rng.uniform(-0.4, 0.4, N_HOLES) * FREE_LENGTH / 2.0
    pos = centres + np.column_stack([x, np.full(N_HOLES, -0.9 * gap), np.zeros(N_HOLES)])
    assert np.all(np.abs(pos[:, 0]) + RADIUS < BORE_LENGTH / 2.0)
    return pos


def _temperature() -> Temperature:
    kelvin, unit = parse_temperature("70", "degF")
    at = Reading("70", kelvin, unit)
    return Temperature(at, at, (MaterialRecord(None, SPHERES),), (MaterialRecord(None, WALLS),))


def capsule_deck() -> tuple[c.Deck, list[str]]:
    """The deck and its header lines."""
    wc, ti = material_at(SPHERES, ASSEMBLY), material_at(WALLS, ASSEMBLY)
    e1, e0 = STEEL_LOSS * wc.E, (1.0 - STEEL_LOSS) * wc.E
    centres = hole_centres()
    axis = [MASTER + 1 + k for k in range(2 * N_HOLES)]
    nodlim = axis[-1]
    ids = [nodlim + 1 + k for k in range(N_HOLES)]
    half = np.array([BORE_LENGTH / 2.0, 0.0, 0.0])
    ends = [centre + s * half for centre in centres for s in (-1.0, 1.0)]
    pos = sphere_positions(centres)
    mass = wc.rho * 4.0 / 3.0 * math.pi * RADIUS**3
    f_bare = math.sqrt(BEAM_K / BEAM_MASS) / (2 * math.pi)
    zeta = BEAM_C / (2 * math.sqrt(BEAM_K * BEAM_MASS))
    deck = c.Deck(
        path="<generated>",
        title=c.Title(
            "Sec. 6.4 temperature capsule: titanium, 7 bores 9/64 in x 9/32 in, (7) 1/8 in "
            "tungsten carbide spheres\n"
            "on the Sec. 8.2 beam, one sphere per bore, free length 5/32 in along the drive (x)"
        ),
        parameters=c.Parameters(0.0, TMAX, TREST, DT, DT, 0, 1.0e9, 0, 5, 0, ITRAC),
        materials=(c.Material(2, 1, 1.0e-12, 1.0, BEAM_K, RIGID, RIGID, BEAM_C),),
        pdmp=(c.Pdmp(nodlim, RADIUS, wc.rho, wc.nu, e0, e1, TAU1, wc.mu),),
        body=c.Body(0.0, -G, 0.0),
        trace=c.Trace(tuple([MASTER] + ids)),
        nodes=(
            c.Node(MASTER, 0.0, 0.0, 0.0),
            *(c.Node(i, *map(float, p)) for i, p in zip(axis, ends)),
            *(c.Node(i, *map(float, p)) for i, p in zip(ids, pos)),
        ),
        elements=(c.Element(1, 2, (MASTER,)),),
        masses=(c.Mass(MASTER, BEAM_MASS, 1.0e20, 1.0e20, 1.0e20),),
        rbels=(c.Rbel(MASTER, (1, 2, 3, 4, 5, 6), tuple(axis)),),
        boundaries=(c.Boundary(MASTER, MASTER, 1, (2, 3, 4, 5, 6)),),
        contacts=(c.Contact((), tuple(c.SlaveSet(k + 1, (i,)) for k, i in enumerate(ids))),),
        usrfrc=(c.Usrfrc((f"sine:node={MASTER},dof=1,amp={DRIVE_AMP!r},hz={DRIVE_HZ!r}",)),),
        wallmat=tuple(c.WallMat(k + 1, ti.E, ti.nu, wc.mu) for k in range(N_HOLES)),
        analytic_walls=tuple(
            c.AnalyticWall("cylinder", k + 1, (axis[2 * k], axis[2 * k + 1]), (BORE_RADIUS,))
            for k in range(N_HOLES)
        ),
        units=c.Units("in", "lbf", "s"),
        temperature=_temperature(),
    )
    header = _header(wc, ti, e0, e1, mass, f_bare, zeta)
    return deck, header


def _header(wc, ti, e0, e1, mass, f_bare, zeta) -> list[str]:
    return [
        "capsule_wc7.inp: the report's Sec. 6.4 temperature-chamber damper, a titanium capsule",
        "  with seven through holes, one 1/8 in tungsten-carbide sphere in each, on the Sec. 8",
        "  beam, as a deck at temperature (TEMPERATURE card; docs/deck-reference.md).",
        "Generated by tools/make_decks.py (tools/make_capsule_deck.py; do not edit by hand).",
        f"Source: {REPORT}, Sec. 6.4 and Figure 20 (the capsule, -94 to 365 F), Sec. 6.3",
        "  (the treatment's bores), Sec. 8.2-8.3 and Table 4 (the beam model, the loss law).",
        "",
        "The report: 'a titanium capsule with seven through holes containing seven tungsten",
        "  carbide spheres 1/8-inch in diameter' (Sec. 6.4); '7 by 9/64 inch diameter bores in a",
        "  titanium test capsule with two caps. Free internal length was 5/32-inch' (Sec. 6.3,",
        "  the standard treatment of its tests, taken to be the same capsule).",
        "Bores: seven CYLINDER cavities (flat caps), radius 9/128 = "
        f"{BORE_RADIUS:g} in, length {BORE_LENGTH:g} in:",
        "  'free internal length' read as the report's free length (Sec. 11: the room a sphere",
        "  travels), so the bore is 1/8 + 5/32 = 9/32 in long (our reading; the other one, a",
        "  5/32 in bore, would leave 1/32 in). Axes along the drive (x), as the report's",
        "  capsules' lengths set the rattle space (Sec. 4.1). Radial gap "
        f"{BORE_RADIUS - RADIUS:.6g} in.",
        f"  Hole pattern (assumed, not given): the centre and the corners of a hexagon of side "
        f"{PITCH:g} in",
        "  in the y-z plane. Each bore is its own CONTACT set: the spheres never meet.",
        "  Axis nodes 2-15 are RBEL slaves of master node 1. The capsule's mass is not given:",
        "  the beam's equivalent mass below (with the Sec. 8 acrylic cavity) is kept.",
        f"Beam: Sec. 8.2's first-mode model, master node 1, MASS {BEAM_MASS:g} lbf s^2/in, "
        f"spring {BEAM_K:g} lbf/in",
        f"  and damper {BEAM_C:g} lbf s/in to ground along x (Table 4): {f_bare:.4g} Hz, zeta "
        f"{zeta:.4g}",
        "  without particles; x only (BOUNDARY), gravity -386.1 in/s^2 along y as the beam decks.",
        f"Materials: the library's (x3dpd materials) at {ASSEMBLY}, the TEMPERATURE card's "
        "assembly",
        f"  temperature. Spheres {SPHERES}: E {wc.E:.6g} psi, nu {wc.nu:g}, density "
        f"{wc.rho:.6g} lbf s^2/in^4,",
        f"  mass {mass:.6g} lbf s^2/in each ({7 * mass / BEAM_MASS:.3%} of the beam's for "
        "seven). The report gives no loss:",
        "  the relative loss of Sec. 8.3's steel model (as decks/shaker_fig9.inp), E1/(E0+E1) "
        "= 5/32.5,",
        f"  tau1 {TAU1:g} s, E0 + E1 = E: E0 {e0:.6g}, E1 {e1:.6g} psi; friction PCOF "
        f"{wc.mu:g} (library: WC on steel).",
        f"  Walls {WALLS} (Ti-6Al-4V), WALLMAT per bore: E {ti.E:.6g} psi, nu {ti.nu:g}, MU "
        f"{wc.mu:g} (as PCOF;",
        "  no WC-on-titanium value in hand).",
        "Temperature: UNITS in lbf s, so a bare temperature is in F; OPERATING 70 = ASSEMBLY 70:",
        "  the deck runs at room temperature as written; --temperature T (or a design's",
        "  temperature) runs it at T with the library's tables (docs/physics.md).",
        f"Drive: USRFRC sine {DRIVE_AMP:g} lbf at {DRIVE_HZ:g} Hz on node 1 (x3dpd ringdown's "
        "default drive: it rings the",
        "  beam past the spheres' peak damping); a design sets its own.",
        f"Run: DT {DT:g} s, TMAX {TMAX:g} s, ITRAC {ITRAC} (1 ms), TREST {TREST:g} s. TRACE: "
        "node 1, the spheres.",
    ]
