"""The modal decks ``decks/beam_64_modal.inp`` and ``decks/chassis_128.inp`` (called by
tools/make_decks.py, which writes and checks every shipped deck).

beam_64_modal: the report's Section 8 cantilever (12 x 1.5 x 0.175 in aluminium) as its first
three Euler-Bernoulli bending modes, with beam_64's cavity and particles at the tip. The modes
are the closed-form ones of a uniform cantilever (:func:`cantilever_modes`); two numbers are
tuned so that the coupled first mode (the cavity's mass coupled in by x3dpd.model.build_modal)
is Table 4's SDOF: the beam's effective modulus (the report tuned its stiffness to the measured
frequency too) and the cavity's mass (what Section 8.2's equivalent mass leaves after the beam's
tip-equivalent mass mu L / 4).

chassis_128: Section 9's chassis damper (128 x 1/16 in steel spheres in the 0.444 x 0.444 x
0.350 in brass cavity) on the first three modes of the chassis panel, taken as a simply
supported plate's (m, n) = (1, 1), (2, 1), (3, 1) modes (Section 9.1: "roughly half of a
sinusoidal cycle in both the width and length directions"); the first coupled mode is tuned to
Table 5's SDOF (equivalent mass at the panel centre, frequency sqrt(k/m)).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace

import numpy as np
from scipy.optimize import brentq, fsolve

from x3dpd.deck.cards import Mass, Node, Pdmp
from x3dpd.deck.fill import fill_positions, filled_deck
from x3dpd.deck.generate import Material3, box_cavity_deck
from x3dpd.deck.modal_card import parse_modal
from x3dpd.errors import NOWHERE
from x3dpd.model.build import build_model

REPORT = "AFRL-VA-WP-TR-2003-3053"
G = 386.1

# ---- the cantilever (Sec. 8.1-8.2) ------------------------------------------------------------
BEAM_L, BEAM_B, BEAM_H = 12.0, 1.5, 0.175  # in: Sec. 8.1, aluminium beam 12 x 1.5 x 0.175 in
AL_E = 10.0e6  # psi, aluminium (6061) handbook modulus: the starting value
AL_RHO = 0.0975 / G  # lbf s^2/in^4 (0.0975 lbf/in^3, 6061 handbook)
BEAM_MODES = 3


def cantilever_roots(n: int) -> np.ndarray:
    """beta_k L of a clamped-free Euler-Bernoulli beam: cos x cosh x = -1 (k = 1..n)."""
    out = []
    for k in range(1, n + 1):
        guess = (k - 0.5) * math.pi
        out.append(brentq(lambda x: math.cos(x) * math.cosh(x) + 1.0, guess - 1.0, guess + 1.0))
    return np.array(out)


def cantilever_modes(n: int, e: float, rho: float, b: float, h: float, length: float):
    """(omega [rad/s], tip value, tip slope) of the first ``n`` mass-normalised bending modes
    (int_0^L mu phi^2 ds = 1, mu = rho b h; bending across the thickness h, I = b h^3 / 12);
    each sign chosen so that the tip value is positive. phi(s) = C [cosh bs - cos bs
    - sigma (sinh bs - sin bs)], sigma = (cosh bL + cos bL)/(sinh bL + sin bL); the tip value of
    a mass-normalised mode is 2/sqrt(mu L) (C follows from it)."""
    mu = rho * b * h
    inertia = b * h**3 / 12.0
    roots = cantilever_roots(n)
    omega = roots**2 * math.sqrt(e * inertia / (mu * length**4))
    tip, slope = [], []
    for x in roots:
        beta = x / length
        # the textbook forms with sigma cancel for high modes (cosh x ~ sinh x); expanded:
        # phi(L) = 2 (cosh x sin x - cos x sinh x) / (sinh x + sin x),
        # phi'(L) = 2 beta sinh x sin x / (sinh x + sin x)
        den = 1.0 + math.sin(x) / math.sinh(x)
        value = 2.0 * (math.sin(x) / math.tanh(x) - math.cos(x)) / den
        grad = 2.0 * beta * math.sin(x) / den
        scale = 2.0 / math.sqrt(mu * length) / abs(value)
        sign = 1.0 if value > 0 else -1.0
        tip.append(sign * scale * value)
        slope.append(sign * scale * grad)
    return omega, np.array(tip), np.array(slope)


# ---- the chassis (Sec. 9) ---------------------------------------------------------------------
PANEL_A, PANEL_B = 17.0, 8.0  # in: Sec. 9.1, the box's 17 in length and 8 in width
STINGER_Y = 3.425 - PANEL_A / 2  # Sec. 9.1: 3.425 in above the bottom; centred across the width
TABLE5_MASS = 3.54282e-4  # lbf s^2/in: Table 5 equivalent mass
TABLE5_K = 1.95442e2  # lbf/in: Table 5 spring stiffness
TABLE5_C = 3.55000e-3  # lbf s/in: Table 5 viscous damping coefficient
CHASSIS_CAVITY = (0.350, 0.444, 0.444)  # in: Sec. 9.1, interior length 0.350, edge 0.444
BRASS_RHO = 0.307 / G  # lbf s^2/in^4 (brass, 0.307 lbf/in^3 handbook)
#: the brass cavity: 0.5 in square tube, 0.028 in wall, 0.350 in long, two 0.028 in end caps
BRASS_VOLUME = (0.5**2 - 0.444**2) * 0.350 + 2 * 0.5**2 * 0.028
CHASSIS_MODES = ((1, 1), (2, 1), (3, 1))
CHASSIS_DRIVE_HZ = 118.2  # Table 5's sqrt(k/m) / 2 pi
CHASSIS_DRIVE_RMS = 0.1  # lbf: Sec. 9.2 / Table 5's 0.1 lbf RMS level


def plate_ratio(m: int, n: int) -> float:
    """f_mn / f_11 of a simply supported rectangular plate a x b."""
    return ((m / PANEL_A) ** 2 + (n / PANEL_B) ** 2) / ((1 / PANEL_A) ** 2 + (1 / PANEL_B) ** 2)


def plate_shape(m: int, n: int, y: float, z: float) -> tuple[float, float, float]:
    """sin(m pi y'/a) sin(n pi z'/b) (y' = y + a/2, z' = z + b/2: the panel centre at the
    origin), and the rotations it gives a normal (x) displacement: about y, d/dz; about z,
    -d/dy."""
    ya, zb = (y + PANEL_A / 2) * m * math.pi / PANEL_A, (z + PANEL_B / 2) * n * math.pi / PANEL_B
    value = _clean(math.sin(ya) * math.sin(zb))
    d_dy = _clean(m * math.pi / PANEL_A * math.cos(ya) * math.sin(zb))
    d_dz = _clean(n * math.pi / PANEL_B * math.sin(ya) * math.cos(zb))
    return value, d_dz, -d_dy


def _clean(x: float) -> float:
    """Zero what is zero but for the rounding of sin(k pi) and cos(pi/2)."""
    return 0.0 if abs(x) < 1e-12 else x


# ---- deck assembly ----------------------------------------------------------------------------
def _modal_card(modes: list[tuple[int, float, float]], shapes: list[tuple[int, int, list]]):
    lines = [f"MODE {k} {f:.9g} {z:.6g}" for k, f, z in modes]
    lines += [
        f"SHAPE {node} {dof} " + " ".join(f"{v:.9g}" for v in vals) for node, dof, vals in shapes
    ]
    return parse_modal(NOWHERE, [(line, 0, 1) for line in lines])


def _corner_masses(mass: float) -> tuple[Mass, ...]:
    """The cavity's mass spread over its 8 corner nodes (a hollow box's inertia, roughly)."""
    return tuple(Mass(i, mass / 8.0, 0.0, 0.0, 0.0) for i in range(1, 9))


def _coupled(deck, node: int) -> tuple[float, float, float]:
    """(first coupled frequency [Hz], effective mass at ``node`` along x, damping ratio) of a
    deck."""
    model = build_model(deck)
    ms = model.modal
    j = int(np.flatnonzero(ms.nodes == model.index_of(node))[0])
    return (
        float(ms.omega[0] / (2 * math.pi)),
        1.0 / float(ms.shape[j, 0, 0]) ** 2,
        float(ms.zeta[0]),
    )


def beam_modal_deck(base, beam_mass: float, beam_k: float, beam_c: float):
    """beam_64's deck (``base``: its particles, cavity, drive) on the three-mode cantilever;
    returns (deck, notes) with the tuned values for the header."""
    zeta = beam_c / (2.0 * math.sqrt(beam_k * beam_mass))
    target_hz = math.sqrt(beam_k / beam_mass) / (2 * math.pi)

    def deck_for(e: float, cavity_mass: float, zeta: float = zeta):
        omega, tip, slope = cantilever_modes(BEAM_MODES, e, AL_RHO, BEAM_B, BEAM_H, BEAM_L)
        card = _modal_card(
            [(k + 1, w / (2 * math.pi), zeta) for k, w in enumerate(omega)],
            [(9, 1, list(tip)), (9, 6, list(-slope))],
        )
        return replace(
            base,
            materials=(),
            elements=(),
            boundaries=(),
            modal=card,
            masses=_corner_masses(cavity_mass),
        )

    mu_l = AL_RHO * BEAM_B * BEAM_H * BEAM_L

    def residual(v):
        f, m, _ = _coupled(deck_for(v[0] * AL_E, v[1] * mu_l / 4), 9)
        return [f / target_hz - 1.0, m / beam_mass - 1.0]

    with warnings.catch_warnings():  # converged to the noise of eigh (~1e-9): checked below
        warnings.simplefilter("ignore", RuntimeWarning)
        e_scale, m_scale = fsolve(residual, [1.0, beam_mass / (mu_l / 4) - 1.0], xtol=1e-10)
    assert max(map(abs, residual([e_scale, m_scale]))) < 1e-8  # 9 digits are printed
    e_eff, cavity = e_scale * AL_E, m_scale * mu_l / 4
    # the coupled damping ratio is linear in the given one: scale it to Table 4's
    given = zeta * zeta / _coupled(deck_for(e_eff, cavity), 9)[2]
    deck = deck_for(e_eff, cavity, given)
    return deck, {
        "e_eff": e_eff,
        "cavity_mass": cavity,
        "zeta": zeta,
        "given_zeta": given,
        "target_hz": target_hz,
        "mu_l": mu_l,
        "coupled": _coupled(deck, 9),
    }


def chassis_deck(
    material: Material3,
    dt: float,
    itrac: int,
    trest: float,
    tmax: float,
    seed: int,
    gap_fraction: float,
    jitter: float,
):
    """Section 9's chassis damper on the panel's first three plate modes; (deck, notes)."""
    zeta = TABLE5_C / (2.0 * math.sqrt(TABLE5_K * TABLE5_MASS))
    target_hz = math.sqrt(TABLE5_K / TABLE5_MASS) / (2 * math.pi)
    cavity_mass = BRASS_RHO * BRASS_VOLUME
    lx, ly, lz = CHASSIS_CAVITY
    radius = 0.03125
    drive = f"sine:node=10,dof=1,amp={CHASSIS_DRIVE_RMS * math.sqrt(2):.6g},hz={CHASSIS_DRIVE_HZ:g}"
    base = box_cavity_deck(
        size=CHASSIS_CAVITY,
        particles=np.zeros((0, 3)),
        radius=radius,
        material=material,
        structure_mass=0.0,
        stiffness=0.0,
        damping=0.0,
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        trest=trest,
        origin=(0.0, -ly / 2, -lz / 2),
        usrfrc=(drive,),
        title="Sec. 9 chassis damper, (128) 0.0625 in steel spheres in a "
        "0.444 x 0.444 x 0.350 in brass cavity\n"
        "panel centre node 9 on the first three panel modes, drive at "
        "the stinger node 10",
    )
    nodes = [Node(9, 0.0, 0.0, 0.0) if nd.nid == 9 else nd for nd in base.nodes]
    nodes.append(Node(10, 0.0, STINGER_Y, 0.0))
    base = replace(base, nodes=tuple(nodes), pdmp=(replace(base.pdmp[0], nodlim=10),))
    fill = fill_positions(base, n=128, gap=gap_fraction * radius, seed=seed, jitter=jitter)
    assert fill.positions.shape[0] == 128, f"only {fill.positions.shape[0]} spheres fit"
    base = filled_deck(base, fill)
    base = replace(base, trace=replace(base.trace, nodes=(9, 10) + base.trace.nodes[1:]))

    def deck_for(f11: float, amplitude: float, zeta: float = zeta):
        modes, centre, stinger = [], [[], [], []], [[], [], []]
        for k, (m, n) in enumerate(CHASSIS_MODES):
            modes.append((k + 1, f11 * plate_ratio(m, n), zeta))
            for out, y in ((centre, 0.0), (stinger, STINGER_Y)):
                value, rot_y, rot_z = plate_shape(m, n, y, 0.0)
                out[0].append(amplitude * value)
                out[1].append(amplitude * rot_y)
                out[2].append(amplitude * rot_z)
        card = _modal_card(
            modes, [(9, 1, centre[0]), (9, 5, centre[1]), (9, 6, centre[2]), (10, 1, stinger[0])]
        )
        return replace(
            base,
            materials=(),
            elements=(),
            boundaries=(),
            modal=card,
            masses=_corner_masses(cavity_mass),
        )

    def residual(v):
        f, mass, _ = _coupled(deck_for(v[0] * target_hz, v[1] / math.sqrt(TABLE5_MASS)), 9)
        return [f / target_hz - 1.0, mass / TABLE5_MASS - 1.0]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        f_scale, a_scale = fsolve(residual, [1.0, 1.0], xtol=1e-10)
    assert max(map(abs, residual([f_scale, a_scale]))) < 1e-8
    f11, amplitude = f_scale * target_hz, a_scale / math.sqrt(TABLE5_MASS)
    given = zeta * zeta / _coupled(deck_for(f11, amplitude), 9)[2]
    deck = deck_for(f11, amplitude, given)
    plate_mass = 4.0 / amplitude**2  # a uniform plate's mode amplitude is 2/sqrt(M)
    return deck, {
        "zeta": zeta,
        "given_zeta": given,
        "target_hz": target_hz,
        "f11": f11,
        "amplitude": amplitude,
        "cavity_mass": cavity_mass,
        "plate_mass": plate_mass,
        "drive": drive,
        "coupled": _coupled(deck, 9),
    }


__all__ = [
    "beam_modal_deck",
    "chassis_deck",
    "cantilever_modes",
    "cantilever_roots",
    "plate_shape",
    "plate_ratio",
    "Pdmp",
]
