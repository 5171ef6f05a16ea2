"""Scene builders shared by the physics and solver tests, built directly as typed cards.

Every builder returns a :class:`~x3dpd.deck.cards.Deck`; ``build_model(deck)`` turns it into a
model and ``Simulation(model, ...)`` runs it. Units: inch, lbf, second (mass lbf s^2/in), like the
report. Node numbering is given in each docstring; particles always have the highest ids.

* :func:`floor_deck` -- one sphere above (or resting on) a flat, fixed, square floor of ONE face.
* :func:`pair_deck` -- particles and no walls at all (free flight, pair contacts only).
* :func:`closed_box_deck` -- particles in a fixed closed box (6 faces, 12 triangles).
* :func:`sdof_deck` -- the report's Table 4 beam: one mass on a spring-damper to ground, no
  particles.

**Shared step loops.** Every combination of effects compiles a step loop of its own
(x3dpd.solver.variants.Variant: 15-50 s each in a cold suite), so many scenes here are shaped to
share one: a sphere on a floor or in a box gets a resting spectator sphere (:func:`floor_deck`'s
node 6, :data:`SPECTATOR`) and so has pair contacts like the many-particle scenes; particles
without walls get a floor they never reach (:func:`pair_deck`'s ``far_floor``); a HOOKE floor
goes without the spectator, to share the loop of the shipped Chung & Ooi decks. A test that
relies on it says which loop it rides -- ``@pytest.mark.rides(BOX_LOOP)`` with the labels
below (x3dpd Variant.label) -- and fails when its Simulations run another
(tests/variant_report.py): a change to its scene that would compile a new loop shows in that
test. Every label below is in the suite's variant list (tests/meta/variants.txt).
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.deck.generate import cylinder_cavity_deck
from x3dpd.deck.cards import (
    Body,
    Boundary,
    Contact,
    Deck,
    Element,
    Initial,
    Mass,
    Material,
    Node,
    Parameters,
    Pdmp,
    SlaveSet,
    Trace,
    Triangle,
    Usrfrc,
)

#: Report Section 7 steel sphere (Figure 28): radius [in], E [psi], nu, density [lbf s^2/in^4].
STEEL_R = 0.0625
STEEL_E = 30.0e6
STEEL_NU = 0.33
STEEL_RHO = 0.283 / 386.1
#: Figure 28 impact speed [in/s] (= 2 pi * 10).
FIG28_V = 62.832
#: Figure 30/34 three-parameter material: E0, E1 [psi], tau1 [s].
FIG30_E0 = 24.0e6
FIG30_E1 = 12.0e6
FIG30_TAU1 = 2.0e-6
#: Table 4 (undamped beam, 200 mV RMS): drive [lbf], mass [lbf s^2/in], c [lbf s/in], k [lbf/in].
TABLE4_DRIVE = 4.84040e-3
TABLE4_MASS = 1.87646e-4
TABLE4_C = 3.08293e-4
TABLE4_K = 1.14823e1
G = 386.1

ALL_DOFS = (1, 2, 3, 4, 5, 6)

# ---- the shared step loops (Variant.label; see the module docstring) -------------------------

#: spheres of one kind, elastic, in a fixed box or on a fixed floor with the spectator
BOX_LOOP = "walls+pairs+walls_translate+one_particle_kind+one_wall_kind"
#: the same, viscoelastic (one Maxwell term: Figure 30's material, the beam decks')
BOX_VISCO_LOOP = (
    "walls+pairs+viscoelastic+n_maxwell=1+walls_translate+one_particle_kind+one_wall_kind"
)
#: the box scenes with friction, by tangential law
BOX_FRICTION_LOOP = {
    "regularized": "walls+pairs+friction+walls_translate+one_particle_kind+one_wall_kind",
    "coulomb": (
        "walls+pairs+friction+friction_law=coulomb+walls_translate+one_particle_kind+one_wall_kind"
    ),
    "mindlin": (
        "walls+pairs+friction+friction_law=mindlin+walls_translate+one_particle_kind+one_wall_kind"
    ),
    "linear_history": (
        "walls+pairs+friction+friction_law=linear_history+walls_translate+one_particle_kind"
        "+one_wall_kind"
    ),
}
#: the resting Mindlin stack of viscoelastic spheres (tests/hardcases/test_resting.py)
MINDLIN_STACK_LOOP = (
    "walls+pairs+friction+viscoelastic+n_maxwell=1+friction_law=mindlin+walls_translate"
    "+one_particle_kind+one_wall_kind"
)
#: ... and its threaded twin (a run with threads > 1, tests/solver/test_threads.py)
MINDLIN_STACK_THREADED_LOOP = MINDLIN_STACK_LOOP + "+threaded"
#: one sphere on a HOOKE plane, without the spectator, by tangential law: the loops of the
#: Chung & Ooi benchmark scenes (decks/benchmarks/chung_ooi, tests/physics/test_chung_ooi.py)
HOOKE_PLANE_LOOP = {
    "coulomb": "walls+friction+friction_law=coulomb+walls_translate+normal_law=hooke+one_wall_kind",
    "linear_history": (
        "walls+friction+friction_law=linear_history+walls_translate+normal_law=hooke+one_wall_kind"
    ),
    "mindlin": "walls+friction+friction_law=mindlin+walls_translate+normal_law=hooke+one_wall_kind",
}


def shared_loops() -> list[str]:
    """Every label above (tests/meta/test_variant_ratchet.py checks them against the list)."""
    return sorted(
        {BOX_LOOP, BOX_VISCO_LOOP, MINDLIN_STACK_LOOP, MINDLIN_STACK_THREADED_LOOP}
        | set(BOX_FRICTION_LOOP.values())
        | set(HOOKE_PLANE_LOOP.values())
    )


def sphere_mass(radius: float = STEEL_R, density: float = STEEL_RHO) -> float:
    """M = rho 4/3 pi R^3 (report Appendix B note 2) [lbf s^2/in]."""
    return density * 4.0 / 3.0 * math.pi * radius**3


def parameters(dt: float, itrac: int = 1, tmax: float = 1.0) -> Parameters:
    """PARAMETERS with DTMIN = DTMAX = dt."""
    return Parameters(0.0, float(tmax), 0.0, float(dt), float(dt), 0, 1.0e12, 0, 5, 0, int(itrac))


def pdmp(
    nodlim: int,
    *,
    radius=STEEL_R,
    density=STEEL_RHO,
    nu=STEEL_NU,
    e0=STEEL_E,
    e1=0.0,
    tau1=1.0,
    mu=0.0,
) -> Pdmp:
    return Pdmp(
        int(nodlim),
        float(radius),
        float(density),
        float(nu),
        float(e0),
        float(e1),
        float(tau1),
        float(mu),
    )


def floor_deck(
    *,
    dt: float,
    height: float | None = None,
    velocity=(0.0, -FIG28_V, 0.0),
    omega=(0.0, 0.0, 0.0),
    gravity: float = 0.0,
    side: float = 1.0,
    center=(0.0, 0.0),
    itrac: int = 1,
    spectator: bool = True,
    **material,
) -> Deck:
    """A sphere (node 5) above a fixed square floor y = 0 made of ONE face (nodes 1-4, triangles
    (1,2,3) and (1,3,4), wound -y).

    The floor spans ``[-side/2, side/2]`` in x and z around (0, 0); the sphere's centre starts at
    (center[0], height, center[1]) (default: just touching, ``height = R``) with the given
    translational ``velocity`` and angular velocity ``omega``. ``gravity`` > 0 adds a BODY card
    (0, -gravity, 0). ``spectator`` adds node 6 at rest on the floor at (-0.3, R, -0.3): the
    scene then rides the box scenes' loop (:data:`BOX_LOOP` and its kin; a test relying on it
    declares ``@pytest.mark.rides``). ``material`` goes to :func:`pdmp`.
    """
    h = side / 2.0
    r = float(material.get("radius", STEEL_R))
    y = r if height is None else float(height)
    nodes = (
        Node(1, -h, 0.0, -h),
        Node(2, h, 0.0, -h),
        Node(3, h, 0.0, h),
        Node(4, -h, 0.0, h),
        Node(5, float(center[0]), y, float(center[1])),
    )
    ids = (5, 6) if spectator else (5,)
    if spectator:
        nodes += (Node(6, -0.3 * side, r, -0.3 * side),)
    return Deck(
        path="<floor>",
        parameters=parameters(dt, itrac),
        pdmp=(pdmp(4, **material),),
        body=Body(0.0, -float(gravity), 0.0) if gravity else None,
        trace=Trace((5,)),
        nodes=nodes,
        boundaries=(Boundary(1, 4, 1, ALL_DOFS),),
        contacts=(Contact((Triangle(1, (1, 2, 3)), Triangle(1, (1, 3, 4))), (SlaveSet(1, ids),)),),
        initials=(Initial(5, tuple(float(v) for v in velocity) + tuple(float(w) for w in omega)),),
    )


def pair_deck(
    positions, velocities, *, dt: float, itrac: int = 1, far_floor: bool = False, **material
) -> Deck:
    """Particles (nodes 1, 2, ...; PDMP NODLIM 0) and no walls at all.

    ``positions`` (P, 3), ``velocities`` (P, 3) or (P, 6). ``far_floor``: a fixed floor y = -1
    (nodes 1-4, as :func:`floor_deck`'s, particles from node 5) that no particle reaches: the
    scene then rides a loop of the floor and box scenes (walls + pairs, :data:`BOX_LOOP` and
    its kin; the test declares it, ``@pytest.mark.rides``) instead of compiling a pairs-only
    one of its own.
    """
    positions = np.asarray(positions, float).reshape(-1, 3)
    first = 5 if far_floor else 1
    ids = list(range(first, first + len(positions)))
    nodes = tuple(Node(nid, *map(float, p)) for nid, p in zip(ids, positions))
    extra = {}
    if far_floor:
        corners = ((-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0))
        nodes = tuple(Node(k + 1, x, -1.0, z) for k, (x, z) in enumerate(corners)) + nodes
        extra = dict(
            boundaries=(Boundary(1, 4, 1, ALL_DOFS),),
            contacts=(
                Contact(
                    (Triangle(1, (1, 2, 3)), Triangle(1, (1, 3, 4))), (SlaveSet(1, tuple(ids)),)
                ),
            ),
        )
    return Deck(
        path="<pair>",
        parameters=parameters(dt, itrac),
        pdmp=(pdmp(first - 1, **material),),
        trace=Trace(tuple(ids)),
        nodes=nodes,
        initials=tuple(Initial(nid, tuple(map(float, v))) for nid, v in zip(ids, velocities)),
        **extra,
    )


_CUBE = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
#: Two triangles per face: z = 0, z = 1, y = 0 (the floor: nodes 1, 2, 5, 6), y = 1, x = 0, x = 1.
CUBE_TRIANGLES = (
    (1, 2, 3),
    (1, 3, 4),
    (5, 7, 6),
    (5, 8, 7),
    (1, 6, 2),
    (1, 5, 6),
    (4, 3, 7),
    (4, 7, 8),
    (1, 4, 8),
    (1, 8, 5),
    (2, 6, 7),
    (2, 7, 3),
)
#: A particle at rest far from everything: a one-sphere scene with it rides the many-particle
#: scenes' loop (walls + pairs, :data:`BOX_LOOP` and its kin) instead of compiling one of its
#: own; the test declares which, ``@pytest.mark.rides``.
SPECTATOR = (0.8, 0.8, 0.8)


def closed_box_deck(
    positions=(),
    velocities=(),
    *,
    dt: float,
    size=(1.0, 1.0, 1.0),
    itrac: int = 1,
    gravity: float = 0.0,
    rotation=None,
    origin=(0.0, 0.0, 0.0),
    groups=(),
    spectators=(),
    **material,
) -> Deck:
    """Particles in a fixed, closed box (corner nodes 1-8, all DOFs fixed, 12 triangles).

    The box is ``origin + rotation @ ([0, size])``; positions are world coordinates. Particles:
    ``positions``/``velocities`` with ``material`` (first PDMP card), then each ``groups`` entry
    ``(positions, velocities, material_dict)`` on its own PDMP card, then ``spectators`` (points,
    at rest, first group's material). Node ids from 9 up in that order; all particles are traced.
    ``gravity`` > 0 adds BODY (0, -gravity, 0).
    """
    rot = np.eye(3) if rotation is None else np.asarray(rotation, float)
    corners = np.asarray(origin, float) + (_CUBE * np.asarray(size, float)) @ rot.T
    all_groups = [(positions, velocities, material)] + list(groups)
    if len(spectators):
        sp = np.asarray(spectators, float).reshape(-1, 3)
        all_groups.append((sp, np.zeros_like(sp), material))
    nodes = [Node(k + 1, *map(float, c)) for k, c in enumerate(corners)]
    cards, initials, ids = [], [], []
    nid = 9
    for pos, vel, mat in all_groups:
        pos = np.asarray(pos, float).reshape(-1, 3)
        if not len(pos):
            continue
        cards.append(pdmp(nid - 1, **mat))
        for p, v in zip(pos, vel):
            nodes.append(Node(nid, *map(float, p)))
            if np.any(np.asarray(v) != 0.0):
                initials.append(Initial(nid, tuple(map(float, v))))
            ids.append(nid)
            nid += 1
    return Deck(
        path="<box>",
        parameters=parameters(dt, itrac),
        pdmp=tuple(cards),
        body=Body(0.0, -float(gravity), 0.0) if gravity else None,
        trace=Trace(tuple(ids)),
        nodes=tuple(nodes),
        boundaries=(Boundary(1, 8, 1, ALL_DOFS),),
        contacts=(
            Contact(tuple(Triangle(1, t) for t in CUBE_TRIANGLES), (SlaveSet(1, tuple(ids)),)),
        ),
        initials=tuple(initials),
    )


def sdof_deck(
    *,
    dt: float,
    hz: float,
    mass: float = TABLE4_MASS,
    k: float = TABLE4_K,
    c: float = TABLE4_C,
    drive: float = TABLE4_DRIVE,
    itrac: int = 1,
    x0: float = 0.0,
    v0: float = 0.0,
) -> Deck:
    """The report's Table 4 beam: node 1 with ``mass``, a spring ``k`` and damper ``c`` to ground
    along x, all other DOFs fixed, driven by ``drive * sin(2 pi hz t)`` along x (USRFRC card).
    No particles. ``v0`` is an initial x velocity (``x0`` is not supported: springs are
    measured from the deck's coordinates, so the start is always at rest length)."""
    if x0:
        raise ValueError("the spring's rest length is the deck geometry; x0 must be 0")
    return Deck(
        path="<sdof>",
        parameters=parameters(dt, itrac),
        materials=(Material(1, 1, 0.0, 1.0, float(k), 0.0, 0.0, float(c)),),
        trace=Trace((1,)),
        nodes=(Node(1, 0.0, 0.0, 0.0),),
        elements=(Element(1, 1, (1,)),),
        masses=(Mass(1, float(mass), 1.0, 1.0, 1.0),),
        boundaries=(Boundary(1, 1, 1, (2, 3, 4, 5, 6)),),
        initials=(Initial(1, (float(v0), 0.0, 0.0)),) if v0 else (),
        usrfrc=(Usrfrc((f"sine:node=1,dof=1,amp={drive!r},hz={hz!r}",)),) if drive else (),
    )


def base_sdof_deck(
    *,
    dt: float,
    mass: float = TABLE4_MASS,
    k: float = TABLE4_K,
    c: float = TABLE4_C,
    k_ground: float = 0.0,
    c_ground: float = 0.0,
    dof: int = 1,
    itrac: int = 1,
    gravity: float = 0.0,
) -> Deck:
    """A mass on a shaker: node 1 with ``mass``, free along ``dof`` only, joined to the base
    node 2 by a spring ``k`` and damper ``c`` along the global axes (MATID type 1, two-node
    element), and to ground by ``k_ground``, ``c_ground`` when non-zero; node 2 fixed in every
    DOF (a prescribed motion moves it). No particles, no USRFRC; gravity ``gravity`` along
    ``dof`` (a BODY card when non-zero)."""
    fixed = tuple(d for d in range(1, 7) if d != dof)
    materials = [Material(1, 1, 0.0, 1.0, float(k), float(k), float(k), float(c))]
    elements = [Element(1, 1, (1, 2))]
    if k_ground or c_ground:
        materials.append(
            Material(
                2, 1, 0.0, 1.0, float(k_ground), float(k_ground), float(k_ground), float(c_ground)
            )
        )
        elements.append(Element(2, 2, (1,)))
    return Deck(
        path="<base_sdof>",
        parameters=parameters(dt, itrac),
        materials=tuple(materials),
        trace=Trace((1, 2)),
        nodes=(Node(1, 0.0, 0.0, 0.0), Node(2, 0.0, -1.0, 0.0)),
        elements=tuple(elements),
        masses=(Mass(1, float(mass), 1.0, 1.0, 1.0),),
        boundaries=(Boundary(1, 1, 1, fixed), Boundary(2, 2, 1, ALL_DOFS)),
        body=Body(*(float(gravity) if d == dof else 0.0 for d in (1, 2, 3))) if gravity else None,
    )


#: The analytic-cavity CLI tests' cylinder (tests/cli/test_cylinder_cli.py, test_capsule_cli.py)
CAVITY_R, CAVITY_BIG_R, CAVITY_LENGTH = 0.03125, 0.2, 0.3


def small_cylinder_deck(pos, vel=None, *, material, dt=5e-7, shape="cylinder"):
    """A cylindrical (``shape="capsule"``: round-ended) cavity of radius 0.2 and length 0.3 on a
    light spring-mounted body (mass 1e-3, k 10), no gravity, spheres of R 0.03125 at ``pos``
    (velocities ``vel``) of ``material`` (x3dpd.deck.generate.Material3)."""
    return cylinder_cavity_deck(
        length=CAVITY_LENGTH,
        cavity_radius=CAVITY_BIG_R,
        particles=pos,
        radius=CAVITY_R,
        material=material,
        structure_mass=1e-3,
        stiffness=10.0,
        damping=0.0,
        free_dofs=(),
        gravity=(0.0, 0.0, 0.0),
        dt=dt,
        itrac=10,
        velocities=vel,
        shape=shape,
    )
