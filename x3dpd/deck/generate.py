"""Generate decks: a box cavity on a spring-mounted master node, filled with particles.

This is the report's Appendix D (``create_cavity.m``) done right: the cavity's 12 triangles lie on
the faces of the box (Appendix A's printed nodes do not), every particle is checked to lie inside
the box and to overlap no other particle, and the result is a typed :class:`~x3dpd.deck.cards.Deck`
that :func:`x3dpd.deck.writer.format_deck` writes out.

Node numbering: 1-8 box corners, 9 the master cavity node (lumped structure mass, spring to
ground, rigid link to the corners), particles from 10 on (PDMP NODLIM = 9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.deck.cards import (
    AnalyticWall,
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
    Rbel,
    SlaveSet,
    Title,
    Trace,
    Triangle,
    Usrfrc,
)
from x3dpd.geometry.shapes import BY_SHAPE_NAME
from x3dpd.materials import in_units

#: Corner order of the box (unit cube) and its 12 triangles, two per face.
_CORNERS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
_TRIANGLES = (
    (1, 2, 3),
    (1, 3, 4),  # z = 0
    (5, 7, 6),
    (5, 8, 7),  # z = 1
    (1, 6, 2),
    (1, 5, 6),  # y = 0
    (4, 3, 7),
    (4, 7, 8),  # y = 1
    (1, 4, 8),
    (1, 8, 5),  # x = 0
    (2, 6, 7),
    (2, 7, 3),
)  # x = 1
MASTER = 9
FIRST_PARTICLE = 10


@dataclass(frozen=True)
class Material3:
    """Particle material: E0, E1 [pressure], tau1 [s], Poisson's ratio, friction, density
    (the generated decks' inch-lbf-s units), further Maxwell pairs ``extra_terms``."""

    e0: float
    e1: float
    tau1: float
    nu: float
    mu: float
    density: float
    extra_terms: tuple[tuple[float, float], ...] = ()

    @classmethod
    def named(cls, name) -> Material3:
        """A library material (x3dpd.materials, by name or Material) in inch-lbf-s."""
        f = in_units(name).pdmp_fields()
        return cls(f["e0"], f["e1"], f["t1"], f["ppoi"], f["pcof"], f["prho"], f["extra_terms"])


def _material3(material) -> Material3:
    """``material`` as given (Material3), or a library name or Material converted."""
    return material if isinstance(material, Material3) else Material3.named(material)


def lattice_fill(
    size,
    radius: float,
    n: int,
    *,
    gap: float = 0.0,
    seed: int | None = None,
    jitter: float = 0.0,
    origin=(0.0, 0.0, 0.0),
    stack_axis: int = 1,
) -> np.ndarray:
    """Centres of ``n`` spheres stacked on a simple cubic lattice inside a box.

    Layers fill the box's cross-section first, lowest layer first along ``stack_axis`` (gravity's
    axis), like Appendix D (x fastest), but the lattice is centred in the free space and every
    sphere is kept at least ``gap`` from the walls and ``gap`` from its neighbours.
    ``jitter`` (a fraction of the free spacing) randomises positions reproducibly with ``seed``.

    Raises ValueError when the box cannot hold ``n`` spheres this way.
    """
    size = np.asarray(size, dtype=float)
    pitch = 2.0 * radius + gap
    counts = np.floor((size - 2.0 * gap - 2.0 * radius) / pitch + 1e-9).astype(int) + 1
    if np.any(size < 2.0 * (radius + gap)) or np.prod(counts) < n:
        raise ValueError(
            f"a {size[0]:g} x {size[1]:g} x {size[2]:g} box holds at most {int(np.prod(counts))} "
            f"spheres of radius {radius:g} on a cubic lattice with gap {gap:g}; asked for {n}"
        )
    axes = [a for a in (0, 2, 1) if a != stack_axis] + [stack_axis]
    per_layer = counts[axes[0]] * counts[axes[1]]
    layers = math.ceil(n / per_layer)
    pos = np.empty((n, 3))
    free = size - 2.0 * radius - 2.0 * gap - (counts - 1) * pitch
    start = np.asarray(origin, float) + radius + gap + 0.5 * free
    start[stack_axis] = origin[stack_axis] + radius + gap
    rng = np.random.default_rng(seed)
    k = 0
    for layer in range(layers):
        for b in range(counts[axes[1]]):
            for a in range(counts[axes[0]]):
                if k == n:
                    break
                idx = np.zeros(3)
                idx[axes[0]] = a
                idx[axes[1]] = b
                idx[stack_axis] = layer
                pos[k] = start + idx * pitch
                k += 1
    if jitter:
        pos += rng.uniform(-1, 1, size=pos.shape) * jitter * 0.5 * gap
    return pos


def box_cavity_deck(
    *,
    size,
    particles: np.ndarray,
    radius: float,
    material,
    structure_mass: float,
    stiffness: float,
    damping: float,
    gravity=(0.0, -386.1, 0.0),
    dt: float = 5e-7,
    tmax: float = 15.0,
    itrac: int = 2000,
    trest: float = 0.0,
    title: str = "",
    origin=(0.0, 0.0, 0.0),
    usrfrc=(),
    free_dofs=(1,),
    transverse_stiffness: float = 1.0e12,
) -> Deck:
    """A deck for a box cavity of interior ``size`` at ``origin`` holding ``particles`` of
    ``material`` (a :class:`Material3`, or a library name such as ``"tungsten carbide"``:
    x3dpd.materials, converted to the deck's inch-lbf-s).

    The master node (9) sits at the box's ``origin`` corner, carries ``structure_mass``, a spring
    ``stiffness`` and damper ``damping`` to ground along x (``transverse_stiffness`` along y, z,
    as Appendix A), and moves only in ``free_dofs`` (default: x only). ``usrfrc`` specs become a
    USRFRC card.
    """
    size = np.asarray(size, float)
    origin = np.asarray(origin, float)
    corners = origin + _CORNERS * size
    particles = np.asarray(particles, float).reshape(-1, 3)
    lo = origin + radius
    hi = origin + size - radius
    inside = np.all((particles >= lo - 1e-12) & (particles <= hi + 1e-12), axis=1)
    if not inside.all():
        bad = int(np.argmin(inside))
        raise ValueError(f"particle {bad + 1} at {particles[bad].tolist()} is not inside the box")
    nodes = [Node(i + 1, *map(float, corners[i])) for i in range(8)]
    nodes.append(Node(MASTER, *map(float, origin)))
    ids = list(range(FIRST_PARTICLE, FIRST_PARTICLE + len(particles)))
    nodes += [Node(nid, *map(float, p)) for nid, p in zip(ids, particles)]
    return _spring_mounted_deck(
        master=MASTER,
        nodlim=MASTER,
        nodes=nodes,
        ids=ids,
        slaves=tuple(range(1, 9)),
        triangles=tuple(Triangle(1, t) for t in _TRIANGLES),
        material=material,
        radius=radius,
        structure_mass=structure_mass,
        rotary_inertia=1.0e20,
        stiffness=stiffness,
        damping=damping,
        transverse_stiffness=transverse_stiffness,
        gravity=gravity,
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        trest=trest,
        title=title,
        usrfrc=usrfrc,
        free_dofs=free_dofs,
    )


def _spring_mounted_deck(
    *,
    master,
    nodlim,
    nodes,
    ids,
    slaves,
    triangles,
    material,
    radius,
    structure_mass,
    rotary_inertia,
    stiffness,
    damping,
    transverse_stiffness,
    gravity,
    dt,
    tmax,
    itrac,
    trest,
    title,
    usrfrc,
    free_dofs,
    initials=(),
    analytic_walls=None,
) -> Deck:
    """What the generated decks share: a master node with the structure's mass, rotary
    inertias, a spring and damper to ground (``transverse_stiffness`` along y, z), free only in
    ``free_dofs``, rigidly linked to the cavity's ``slaves``; one PDMP group after ``nodlim``,
    all of it CONTACT slave set 1 of the cavity's ``triangles`` (and ``analytic_walls``); TRACE the
    master, then the particles ``ids``."""
    fixed = tuple(d for d in range(1, 7) if d not in free_dofs)
    m = _material3(material)
    return Deck(
        path="<generated>",
        title=Title(title) if title else None,
        parameters=Parameters(
            0.0, float(tmax), float(trest), float(dt), float(dt), 0, 1.0e9, 0, 5, 0, int(itrac)
        ),
        materials=(
            Material(
                2,
                1,
                1.0e-12,
                1.0,
                float(stiffness),
                transverse_stiffness,
                transverse_stiffness,
                float(damping),
            ),
        ),
        pdmp=(
            Pdmp(
                nodlim,
                float(radius),
                float(m.density),
                float(m.nu),
                float(m.e0),
                float(m.e1),
                float(m.tau1),
                float(m.mu),
                extra_terms=tuple(m.extra_terms),
            ),
        ),
        body=Body(*map(float, gravity)),
        trace=Trace(tuple([master] + ids)),
        nodes=tuple(nodes),
        elements=(Element(1, 2, (master,)),),
        masses=(Mass(master, float(structure_mass), *(3 * (float(rotary_inertia),))),),
        rbels=(Rbel(master, (1, 2, 3, 4, 5, 6), tuple(slaves)),),
        boundaries=(Boundary(1, master, 1, fixed),) if fixed else (),
        contacts=(Contact(tuple(triangles), (SlaveSet(1, tuple(ids)),)),),
        initials=tuple(initials),
        usrfrc=(Usrfrc(tuple(usrfrc)),) if usrfrc else (),
        analytic_walls=analytic_walls or None,
    )


#: Node ids of a cylinder deck: the master, then the axis end nodes A and B (cap centres).
CYL_MASTER, CYL_A, CYL_B = 1, 2, 3


# Over 80 lines: one deck's cards written in order from one set of dimensions.
def cylinder_cavity_deck(
    *,
    length: float,
    cavity_radius: float,
    particles: np.ndarray,
    radius: float,
    material,
    structure_mass: float,
    stiffness: float,
    damping: float,
    facets: int | None = None,
    gravity=(0.0, -386.1, 0.0),
    dt: float = 5e-7,
    tmax: float = 15.0,
    itrac: int = 2000,
    trest: float = 0.0,
    title: str = "",
    usrfrc=(),
    free_dofs=(1,),
    transverse_stiffness: float = 1.0e12,
    rotary_inertia: float = 1.0e20,
    velocities: np.ndarray | None = None,
    shape: str = "cylinder",
) -> Deck:
    """A deck for a cylindrical cavity along x: axis from A = (0, 0, 0) to B = (``length``, 0,
    0), inner radius ``cavity_radius``, holding ``particles`` (their initial ``velocities``
    (P, 3), if given, as INITIAL records). ``shape`` is any registered analytic wall whose
    card is SET NODE_A NODE_B RADIUS (x3dpd.geometry.shapes).

    ``facets=None`` writes the analytic shape (CYLINDER or CAPSULE card, x3dpd.geometry.shapes);
    an integer n writes the same shape as CONTACT triangles instead (the shape's ``mesh``: n
    flat facets around with their corners on the wall), with its vertices after B (a vertex
    at A or B is that node). ``material`` as :func:`box_cavity_deck`'s. Node 1 is the master (mass,
    rotary inertias ``rotary_inertia``, spring and damper to ground along x, as
    :func:`box_cavity_deck`), 2 and 3 the axis nodes, all structure nodes rigidly linked to it;
    particles follow (PDMP NODLIM = the last structure node).
    """
    a = np.zeros(3)
    b = np.array([float(length), 0.0, 0.0])
    particles = np.asarray(particles, float).reshape(-1, 3)
    kind = BY_SHAPE_NAME[shape]
    gap, inside = kind.clearance(
        particles, np.full(len(particles), radius), np.stack([a, b]), (float(cavity_radius),)
    )
    if not (inside.all() and np.all(gap >= -1e-12)):
        bad = int(np.argmin(gap))
        raise ValueError(
            f"particle {bad + 1} at {particles[bad].tolist()} is not inside the {shape}"
        )
    nodes = [
        Node(CYL_MASTER, 0.0, 0.0, 0.0),
        Node(CYL_A, *map(float, a)),
        Node(CYL_B, *map(float, b)),
    ]
    contact_tris: tuple = ()
    walls: tuple = (AnalyticWall(shape, 1, (CYL_A, CYL_B), (float(cavity_radius),)),)
    if facets is not None:
        verts, tris = kind.mesh(np.stack([a, b]), (float(cavity_radius),), facets)
        vid = []
        for v in verts:
            if np.array_equal(v, a) or np.array_equal(v, b):
                vid.append(CYL_A if np.array_equal(v, a) else CYL_B)
            else:
                vid.append(CYL_B + 1 + len(nodes) - 3)
                nodes.append(Node(vid[-1], *map(float, v)))
        contact_tris = tuple(Triangle(1, tuple(vid[k] for k in tri)) for tri in tris)
        walls = ()
    last = nodes[-1].nid
    ids = list(range(last + 1, last + 1 + len(particles)))
    nodes += [Node(nid, *map(float, p)) for nid, p in zip(ids, particles)]
    initials = ()
    if velocities is not None:
        initials = tuple(
            Initial(nid, tuple(map(float, v)))
            for nid, v in zip(ids, np.asarray(velocities, float).reshape(-1, 3))
        )
    return _spring_mounted_deck(
        master=CYL_MASTER,
        nodlim=last,
        nodes=nodes,
        ids=ids,
        slaves=range(CYL_A, last + 1),
        triangles=contact_tris,
        material=material,
        radius=radius,
        structure_mass=structure_mass,
        rotary_inertia=rotary_inertia,
        stiffness=stiffness,
        damping=damping,
        transverse_stiffness=transverse_stiffness,
        gravity=gravity,
        dt=dt,
        tmax=tmax,
        itrac=itrac,
        trest=trest,
        title=title,
        usrfrc=usrfrc,
        free_dofs=free_dofs,
        initials=initials,
        analytic_walls=walls,
    )
