"""``decks/shaker_fig9.inp``: the report's Figure 9 shaker test as a base-driven deck (called by
tools/make_decks.py, which writes and checks every shipped deck).

Report AFRL-VA-WP-TR-2003-3053, Sec. 4.2 and Figure 9: "a representative forced dwell sine
sweep response, for a MPID attached on a cantilever beam that is excited at the base by a[n]
electromagnetic shaker", with "eight 0.125 inch tungsten carbide particles, 0.19 len x 0.5 dia
cavity". The report gives no numbers for that beam nor for the particles' material; the deck
takes the beam of Sec. 8.2 (Table 4, the other decks' structure) on a base node instead of
ground, and handbook values for tungsten carbide (the header says which is which).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.deck.cards import (
    AnalyticWall,
    Body,
    Boundary,
    Contact,
    Deck,
    Element,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    Rbel,
    SlaveSet,
    Title,
    Trace,
)

REPORT = "AFRL-VA-WP-TR-2003-3053"
G = 386.1  # in/s^2 (the report's gravity)
# ---- the host: Sec. 8.2's beam model (as tools/make_decks.py), mounted on the base node -----
BEAM_MASS = 2.04213e-4  # lbf s^2/in, Sec. 8.2 equivalent mass (beam + cavity)
BEAM_K = 1.14823e1  # lbf/in, Table 4
BEAM_C = 3.08293e-4  # lbf s/in, Table 4
# ---- Figure 9's damper ------------------------------------------------------------------
N_SPHERES = 8  # "Eight 0.125 inch tungsten carbide particles"
RADIUS = 0.0625  # in (0.125 in diameter)
CAVITY_LENGTH = 0.19  # in ("0.19 len")
CAVITY_RADIUS = 0.25  # in ("0.5 dia")
# ---- tungsten carbide: handbook values, not the report's (it gives none) ---------------------
WC_E = 90.0e6  # psi (620 GPa)
WC_NU = 0.24
WC_DENSITY = 0.5636 / G  # lbf s^2/in^4 (15.6 g/cm^3 = 0.5636 lbf/in^3)
STEEL_LOSS = 5.0 / 32.5  # Sec. 8.3 steel: E1 / (E0 + E1) = 5e6 / (27.5e6 + 5e6)
WC_TAU1 = 2.0e-6  # s, Sec. 8.3 steel's relaxation time
WC_E1 = STEEL_LOSS * WC_E
WC_E0 = WC_E - WC_E1
WC_MU = 0.30  # Sec. 8.3 steel's friction coefficient
# ---- run -------------------------------------------------------------------------------------
DT, TMAX, ITRAC, TREST = 5e-7, 2.0, 2000, 0.1
RING = 0.175  # in, radius of the ring the spheres start on
GAP = 0.05 * RADIUS  # in, start gap above the bottom cap
SEED = 2003
V_IMPACT = 5.0  # in/s: the cavity's speed at 3 g and 37 Hz, 3 g / w
MASTER, AXIS_A, AXIS_B, BASE = 1, 2, 3, 4


def sphere_positions() -> np.ndarray:
    """The 8 centres: a ring of radius RING about the axis (y), one layer resting GAP to 3 GAP
    above the bottom cap, angles and radii jittered (seed SEED) so the spheres do not move in
    lockstep. Asserts the clearances."""
    rng = np.random.default_rng(SEED)
    angle = 2 * np.pi * np.arange(N_SPHERES) / N_SPHERES + rng.uniform(-0.02, 0.02, N_SPHERES)
    rho = RING + rng.uniform(-0.003, 0.003, N_SPHERES)
    y = RADIUS + GAP * (1.0 + 2.0 * rng.uniform(0.0, 1.0, N_SPHERES))
    pos = np.column_stack([rho * np.cos(angle), y, rho * np.sin(angle)])
    d = np.linalg.norm(pos[:, None] - pos[None], axis=2) + np.eye(N_SPHERES)
    assert d.min() > 2 * RADIUS + 1e-3, d.min()
    assert (CAVITY_RADIUS - rho - RADIUS).min() > 1e-3
    assert (CAVITY_LENGTH - y - RADIUS).min() > 0.0
    return pos


def shaker_deck() -> tuple[Deck, list[str]]:
    """The deck and its header lines."""
    pos = sphere_positions()
    ids = list(range(BASE + 1, BASE + 1 + N_SPHERES))
    mass = WC_DENSITY * 4.0 / 3.0 * math.pi * RADIUS**3
    f_bare = math.sqrt(BEAM_K / BEAM_MASS) / (2 * math.pi)
    f_added = math.sqrt(BEAM_K / (BEAM_MASS + N_SPHERES * mass)) / (2 * math.pi)
    zeta = BEAM_C / (2 * math.sqrt(BEAM_K * BEAM_MASS))
    # Hertz on a cap at V_IMPACT (report Sec. 5): k = 4/3 E* sqrt(R), contact time
    k = 4.0 / 3.0 * WC_E / (1.0 - WC_NU**2) * math.sqrt(RADIUS)
    tc = 2.0 * 1.4716 * (5.0 * mass * V_IMPACT**2 / (4.0 * k)) ** 0.4 / V_IMPACT
    deck = Deck(
        path="<generated>",
        title=Title(
            "Fig. 9 shaker: (8) 0.125 in tungsten carbide spheres, base-driven\n"
            f"cylinder {CAVITY_LENGTH} long (y) x {2 * CAVITY_RADIUS} in diameter on "
            "the Sec. 8.2 beam, spring to base node 4"
        ),
        parameters=Parameters(0.0, TMAX, TREST, DT, DT, 0, 1.0e9, 0, 5, 0, ITRAC),
        materials=(Material(1, 1, 0.0, 1.0, 0.0, BEAM_K, 0.0, BEAM_C),),
        pdmp=(Pdmp(BASE, RADIUS, WC_DENSITY, WC_NU, WC_E0, WC_E1, WC_TAU1, WC_MU),),
        body=Body(0.0, -G, 0.0),
        trace=Trace(tuple([MASTER, BASE] + ids)),
        nodes=(
            Node(MASTER, 0.0, 0.0, 0.0),
            Node(AXIS_A, 0.0, 0.0, 0.0),
            Node(AXIS_B, 0.0, CAVITY_LENGTH, 0.0),
            Node(BASE, 0.0, -1.0, 0.0),
            *(Node(i, *map(float, p)) for i, p in zip(ids, pos)),
        ),
        elements=(Element(1, 1, (MASTER, BASE)),),
        masses=(Mass(MASTER, BEAM_MASS, 1.0e20, 1.0e20, 1.0e20),),
        rbels=(Rbel(MASTER, (1, 2, 3, 4, 5, 6), (AXIS_A, AXIS_B)),),
        boundaries=(
            Boundary(MASTER, MASTER, 1, (1, 3, 4, 5, 6)),
            Boundary(BASE, BASE, 1, (1, 2, 3, 4, 5, 6)),
        ),
        contacts=(Contact((), (SlaveSet(1, tuple(ids)),)),),
        analytic_walls=(AnalyticWall("cylinder", 1, (AXIS_A, AXIS_B), (CAVITY_RADIUS,)),),
    )
    header = [
        "shaker_fig9.inp: the report's Figure 9 shaker test, a particle damper on a cantilever",
        "  beam excited at its base, as a base-driven deck (x3dpd sweep --drive base).",
        "Generated by tools/make_decks.py (tools/make_shaker_deck.py; do not edit by hand).",
        f"Source: {REPORT}, Sec. 4.2 and Figure 9 (the damper, the base excitation), Sec. 6.1",
        "  and Figure 15 (the basic beam tester: excitation aligned with gravity), Sec. 8.2-8.3",
        "  and Table 4 (the beam model, the particles' viscoelastic law).",
        "",
        "Figure 9 says only: 'Eight 0.125 inch tungsten carbide particles, 0.19 len x 0.5 dia",
        "  cavity', a cantilever beam 'excited at the base by a electromagnetic shaker'. The",
        "  rest is our assumption, as follows.",
        "Beam: Sec. 8.2's first-mode model (the other decks' structure) on a moving base instead",
        f"  of ground: master node 1, MASS {BEAM_MASS:g} lbf s^2/in (Sec. 8.2: beam + cavity), "
        f"joined to",
        f"  the base node 4 by a spring KY {BEAM_K:g} lbf/in and damper C {BEAM_C:g} lbf s/in "
        "(Table 4;",
        "  MATID type 1, acting along y: the master is fixed in x, z and the rotations by",
        "  BOUNDARY). A base-excited cantilever's first mode as a mass on a spring to the base",
        "  (participation factor 1). Without particles it resonates at "
        f"{f_bare:.4g} Hz, zeta {zeta:.4g};",
        f"  with their mass added rigidly at {f_added:.4g} Hz.",
        "Base: node 4, every DOF fixed (BOUNDARY); the sweep's prescribed motion moves it along y:",
        "  x3dpd sweep decks/shaker_fig9.inp --drive base --node 4 --dof 2 --amp 0.02g ...",
        "  (a run without --motion keeps the table still). Gravity BODY 0 -386.1 0 in/s^2 along",
        "  the motion (Sec. 6.1, Fig. 15: the standard aligned configuration).",
        f"Cavity: CYLINDER on axis nodes 2 (0,0,0) and 3 (0,{CAVITY_LENGTH:g},0), radius "
        f"{CAVITY_RADIUS:g} in (Fig. 9),",
        "  the axis along the motion (Sec. 4.1: the capsule's length sets the rattle space);",
        "  nodes 2 and 3 are RBEL slaves of node 1. Free travel along the axis "
        f"{CAVITY_LENGTH - 2 * RADIUS:.3g} in.",
        f"Particles: {N_SPHERES} spheres of radius {RADIUS:g} in (Fig. 9), mass {mass:.6g} "
        f"lbf s^2/in each",
        f"  ({N_SPHERES * mass / BEAM_MASS:.3%} of the beam's), one layer on a ring of radius "
        f"{RING:g} in about the axis,",
        f"  {GAP:g} to {3 * GAP:g} in above the bottom cap, angles and radii jittered (seed "
        f"{SEED}); none touches.",
        "  Tungsten carbide (the report gives no properties: handbook values, our assumption):",
        f"  E {WC_E:g} psi (620 GPa), nu {WC_NU:g}, density 15.6 g/cm^3 = 0.5636 lbf/in^3 / "
        f"{G:g} = {WC_DENSITY:.6g}",
        "  lbf s^2/in^4 (typical of cemented carbide, WC-Co; pure WC is 15.6-15.7 g/cm^3).",
        "  No loss data either: the particles get the relative loss of Sec. 8.3's steel model,",
        f"  E1/(E0+E1) = 5/32.5, tau1 {WC_TAU1:g} s, with E0 + E1 = E: E0 {WC_E0:.6g}, E1 "
        f"{WC_E1:.6g} psi;",
        f"  friction mu {WC_MU:g} (Sec. 8.3's steel value).",
        f"Run: DT {DT:g} s (the report's; a {V_IMPACT:g} in/s impact on a cap lasts {tc:.3g} s, "
        f"{tc / DT:.0f} steps), TMAX {TMAX:g} s,",
        f"  ITRAC {ITRAC} (1 ms), TREST {TREST:g} s. TRACE: node 1, the base node 4, the "
        "particles.",
    ]
    return deck, header
