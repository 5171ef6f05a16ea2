"""The model: a deck turned into the plain arrays the solver needs.

Built by :func:`x3dpd.model.build.build_model`. Nodes are addressed by *index* (0..n-1, in
ascending user node id); ``node_ids[i]`` is the user id of index ``i``. Particles (PDMP nodes)
always form the contiguous tail ``particle_start .. n-1`` because they are the highest node ids.

Every array is owned by the model (C-contiguous, float64 or int64/bool) and must not be modified.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from x3dpd.model.modal_structure import ModalStructure
from x3dpd.physics.effect_units import UNITS

# Names of the effects a scene can call for. The solver compiles exactly these.
EFFECTS = (
    "gravity",  # BODY card with a non-zero vector
    "springs",  # ELEMENTS with non-zero stiffness
    "dampers",  # ELEMENTS with non-zero damping
    "axial_springs",  # MATID type 2 elements (spring-damper along the line of two nodes)
    "rotational_springs",  # MATID type 3 elements (rotational spring-damper)
    "rigid_links",  # RBEL cards
    "rigid_rotation",  # a rigid body whose master has a free rotational DOF
    "wall_contact",  # CONTACT triangles with slave particles
    "cylinder_contact",  # CYLINDER cavities with slave particles
    "pair_contact",  # two or more particles sharing a cavity
    "viscoelastic",  # some particle with E1 != 0 (Maxwell terms)
    "friction",  # some particle with PCOF > 0
    "external_force",  # USRFRC forces (deck card or --usrfrc)
    "prescribed_motion",  # --motion
    "modal_structure",  # MODAL card (x3dpd.physics.modal)
)
# and the effects of the effect units (x3dpd.physics.effect_units) a unit card of its own names
EFFECTS += tuple(e for u in UNITS for e in u.effects if e not in EFFECTS)


@dataclass(frozen=True)
class Model:
    """Arrays of one scene. Shapes: n nodes, P particles, S springs (MATID type 1), A axial
    and Q rotational elements (types 2, 3), B rigid bodies, T triangles, F wall faces,
    C cavities, K viscoelastic terms (K = 1 for elastic particles).

    Attributes
    ----------
    node_ids : (n,) int64, ascending user node ids.
    x0 : (n, 3) float64, initial coordinates [length].
    mass : (n,) float64, translational lumped mass [mass] (MASS, element masses, particles).
    inertia : (n, 3) float64, rotary inertias about the global axes [mass length^2].
    fixed : (n, 6) bool, DOFs fixed by BOUNDARY CONDITIONS (x, y, z, rx, ry, rz).
    v0 : (n, 6) float64, initial velocities (PDMP VX0..VZ0 then INITIAL) [length/s, rad/s].
    body_accel : (3,) float64, BODY acceleration [length/s^2].

    particle_start : int, index of the first particle node; particles are ``particle_start..n-1``.
    radius, density, poisson, mu : (P,) float64 per particle (RZERO, PRHO, PPOI, PCOF).
    moduli : (P, K) float64, relaxation-function moduli; column 0 is E0, columns 1.. are E1, E2...
    taus : (P, K) float64, relaxation times; column 0 is ``inf`` (the long-term spring).
    particle_group : (P,) int64, index of the PDMP card the particle belongs to.
    particle_cavity : (P,) int64, cavity index whose walls the particle meets (-1: none).
    normal_law : str, the normal contact law of every particle (x3dpd.physics.normal_laws):
        "lee_radok" (the report's), or the law a card selects ("hooke": HOOKE card).
    law_params : (P, n) float64, the normal law's own constants per particle from its card, in
        the law's PARAMS order (HOOKE: k_n [force/length] and restitution e), or None under
        the report's law.

    spring_nodes : (S, 2) int64, node indices; second is -1 for a spring to ground.
    spring_k, spring_c : (S, 3) float64, stiffness [force/length] and damping [force s/length]
        along x, y, z (material SCALE already applied). MATID type 1 elements only.
    axial_nodes : (A, 2) int64, node indices of each MATID type 2 (axial) element.
    axial_k, axial_c : (A,) float64, its stiffness [force/length] and damping [force s/length]
        along the line between its nodes (SCALE applied).
    axial_length : (A,) float64, rest length L0 > 0: the nodes' distance in the deck [length].
    rotational_nodes : (Q, 2) int64, node indices of each MATID type 3 (rotational) element;
        second is -1 for a rotational spring to ground.
    rotational_k, rotational_c : (Q, 3) float64, stiffness [force length/rad] and damping
        [force length s/rad] about x, y, z (SCALE applied).

    rigid_master : (B,) int64, master node index of each rigid body.
    rigid_ptr : (B+1,) int64, CSR pointer into ``rigid_slaves``.
    rigid_slaves : (sum,) int64, slave node indices.
    rigid_mass : (B,) float64, master + slave masses.
    rigid_inertia : (B, 3, 3) float64, inertia tensor about the master node at t = 0 (masters'
        rotary inertias plus slaves' masses and inertias, parallel-axis theorem).

    tri_nodes : (T, 3) int64, node indices of each wall triangle as written in the deck.
    tri_sign : (T,) float64, +1 or -1 so that ``sign * (p1-p0) x (p2-p0)`` points into the
        cavity (from the geometry, never from the winding).
    tri_face : (T,) int64, the face (coplanar triangles with one inward normal) of each triangle.
    face_cavity : (F,) int64, cavity index of each face.
    cavity_set_ids : (C,) int64, CONTACT set id of each cavity (of its triangles, its
        analytic walls or both).
    wall_material : (C, 3) float64, the walls' E [force/length^2], NU, MU per cavity (WALLMAT
        card; E = inf and MU = nan: a rigid wall, the particles' PCOF), or None: every wall
        rigid (x3dpd.physics.wall_material).
    shape_kind : (W,) int64, kind of each analytic wall (CYLINDER, CAPSULE ... card): its
        index in x3dpd.geometry.shapes.SHAPES.
    shape_nodes : (W, 2) int64, node indices of each analytic wall, in card order (a one-node
        shape repeats its node).
    shape_params : (W, P) float64, its lengths in card order (RADIUS ...) [length], zero-padded.
    shape_cavity : (W,) int64, cavity index of each analytic wall.

    trace_nodes : (R,) int64, node indices to trace, in TRACE order.

    t0, tmax, dt, trest : float; start and end time, step (DTMAX), restart interval [s].
    itrac : int, trace every ``itrac`` steps; irest : int; incmax : float.
    effects : frozenset[str], subset of :data:`EFFECTS`.
    usrfrc : tuple[str, ...], force specs from the deck's USRFRC card.
    title : str, path : str.
    units : (length, force, time) unit names the deck declares (UNITS card; x3dpd.units).
    modal : the modal structure (MODAL card; x3dpd.model.modal_structure), None without one.
    unit_data : the arrays of the effect units with a card of their own, by unit name (their
        ``build`` of the card's records: x3dpd.physics.effect_units); empty without such cards.
    temperature : what the TEMPERATURE card did (x3dpd.model.temperature.AtTemperature: the
        temperatures, each material's strain and ratios, each cavity's clearance at both), None
        without one: the arrays above are then the deck's at its operating temperature.
    """

    node_ids: np.ndarray
    x0: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    fixed: np.ndarray
    v0: np.ndarray
    body_accel: np.ndarray

    particle_start: int
    radius: np.ndarray
    density: np.ndarray
    poisson: np.ndarray
    mu: np.ndarray
    moduli: np.ndarray
    taus: np.ndarray
    particle_group: np.ndarray
    particle_cavity: np.ndarray

    spring_nodes: np.ndarray
    spring_k: np.ndarray
    spring_c: np.ndarray

    rigid_master: np.ndarray
    rigid_ptr: np.ndarray
    rigid_slaves: np.ndarray
    rigid_mass: np.ndarray
    rigid_inertia: np.ndarray

    tri_nodes: np.ndarray
    tri_sign: np.ndarray
    tri_face: np.ndarray
    face_cavity: np.ndarray
    cavity_set_ids: np.ndarray

    trace_nodes: np.ndarray

    t0: float
    tmax: float
    dt: float
    trest: float
    itrac: int
    irest: int
    incmax: float
    effects: frozenset = field(default_factory=frozenset)
    usrfrc: tuple = ()
    title: str = ""
    path: str = "<deck>"
    normal_law: str = "lee_radok"
    law_params: np.ndarray | None = None
    wall_material: np.ndarray | None = None
    #: FRICTION card: the tangential law of the whole scene (None: no card, the run's
    #: option decides), per particle the kinetic mu (mu = the static one) and the rolling
    #: coefficient of ``rolling_law``
    friction_law: str | None = None
    mu_kinetic: np.ndarray | None = None
    rolling_law: str = "none"
    mu_roll: np.ndarray | None = None
    units: tuple = ("in", "lbf", "s")
    shape_kind: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    shape_nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    shape_params: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    shape_cavity: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    modal: ModalStructure | None = None
    axial_nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    axial_k: np.ndarray = field(default_factory=lambda: np.zeros(0))
    axial_c: np.ndarray = field(default_factory=lambda: np.zeros(0))
    axial_length: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rotational_nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    rotational_k: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    rotational_c: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    unit_data: dict = field(default_factory=dict)
    temperature: object | None = None

    @property
    def n_nodes(self) -> int:
        return int(self.node_ids.shape[0])

    @property
    def n_particles(self) -> int:
        return int(self.radius.shape[0])

    def index_of(self, node_id: int) -> int:
        """Index of user node ``node_id``; raises KeyError when the node does not exist."""
        i = int(np.searchsorted(self.node_ids, node_id))
        if i >= self.node_ids.shape[0] or self.node_ids[i] != node_id:
            raise KeyError(node_id)
        return i
