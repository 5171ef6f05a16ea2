"""What an effect unit declares about itself: the interface of x3dpd.physics.effect_units.

An *effect unit* is one effect of a scene -- a structure kind (the spring-dampers, the modes of
a MODAL card), a force source -- described in one place: its module of ``x3dpd.physics`` holds
the physical law and an :class:`EffectUnit` that says which deck cards its data comes from,
which arrays it owns (one bundle: constants, state, scratch), how those are built from the
model, what ``x3dpd check`` and the stop's diagnosis read of it (its stiffness), which energy
it stores, and which kernels of its module the step loop calls in which *slot*. Kept apart from
the registry so that a unit's module can import it while the registry imports the units.

The slots
---------
The step loop (x3dpd.solver._advance_template) calls the slots in a fixed order; each slot
calls the hooks of the scene's units in registry order -- first those that list the slot in
their ``first``, then the others -- and a slot no unit of the scene fills compiles to
nothing. One step of velocity Verlet (report Section 7.3, docs/engine.md):

1. ``first_half_kick`` (unless the last step's pass did it), the first half kick of every
   node, the drift of every node; then ``drift``; then ``follow``;
2. the forces at the new positions: the body forces, then ``force``, then the wall and pair
   contacts; then ``gather``; then ``kick``;
3. ``second_half_kick`` and the nodes' second half kick (fused with the next step's first half
   kicks when no full-step velocities are wanted); at a step whose full-step velocities are
   wanted (an output row, the end of a call, a stop) ``place``;
4. at an output row the energies: the nodes', the contacts', then ``energy``.

The rigid bodies (x3dpd.physics.rigid_link) run ``first`` in ``drift`` and ``follow``: a body
turns before the units that drive bodies set their turn (the modes), and its slaves follow
before the units' own coordinates do; its ``place`` runs after the modes' (a modal master's
slaves follow it). The prescribed motions (x3dpd.physics.motion) are registered after them:
their ``drift`` runs after the other units' (a modal node may be driven), their ``kick`` and
``place`` before them (``first``). The bodies' bundle is the one every hook gets as ``rigid``:
the units that drive a body (the modes, the motions) and the walls ride them.

A hook of any slot but ``energy`` is a
``step_kernel`` ``hook(u, nodes, rigid, stepping, t)``: ``u`` the unit's bundle; ``nodes``
the nodes (``x``, ``x0``, ``vel``, ``force``, ``inv_m`` ...), ``rigid`` the rigid bodies
(``rot``: each body's rotation), ``stepping`` the step (``dt``, ``ledger``), ``t`` the time
[s] the step ends at (x3dpd.solver.bundles); a unit with ``step_start`` gets, in its
``drift`` and ``kick`` hooks, the time the step starts at too, ``hook(u, nodes, rigid,
stepping, t, t_old)`` (exactly the loop's, not ``t - dt``: a function of time evaluated at
both ends of a step is then the same number in consecutive steps); a unit with
``variant_args`` gets, after these, the named constants of the variant's VARIANT block
(x3dpd.solver.variants: ``HAS_USER_FORCE``, ``USER_FORCE`` ...), which numba freezes into the
machine code as it does the loop's own. It books what it
dissipates or the work it does in ``stepping.ledger`` at the slots below (:data:`L_DDAMP`
...). An ``energy`` hook is
``hook(u, nodes, en)``: it adds its kinetic energy to ``en[0]``, its potential in a body-force
field to ``en[2]``, its stored (spring) energy to ``en[3]``, and returns its share of the Verlet
correction's sum f^2/m (the ledger's S: docs/energy.md).

Runtime units
-------------
A unit with ``runtime`` (gravity, x3dpd.physics.gravity) has no flag: every loop compiles it,
and its data say whether it acts (g = 0). That is for a cheap effect outside the contact loop,
where a flag would double the loop variants a suite compiles for no measurable speed. Its
``setup`` may add constant forces to the nodes' body forces ``fbody``, which every step's
forces start from (reset in the kick's own pass over memory: a body force costs no pass).

A unit's data comes from the model (x3dpd.model.model.Model): from the arrays a model builder
step makes of the deck's cards (the springs' MATID and ELEMENTS, the MODAL card), or, for a
unit with a card of its own (``card``: a :class:`UnitCard`), from ``model.unit_data[name]``,
which its ``build(rows, fail)`` makes of the card's records: ``rows`` one dict per record,
field -> value (a node field's value is the node's index, the others floats), ``fail(k,
message)`` the deck error at record k (``FILE:LINE:COL: CARD: message``) to raise; it returns
the unit's arrays by name. The deck reader and writer, the model builder (which also names the
unit's first effect when its card has records) and ``x3dpd check`` (its ``check(model)``:
findings ``(code, headline, lines)``) need no code of the unit's. A unit fed by a run option
instead of the deck (the prescribed motions of ``--motion``) finds its arrays in
``model.unit_data[name]`` too, put there by x3dpd.solver.simulation for ``setup``.

Setup
-----
The solver builds every unit's constants in three passes over the registry
(x3dpd.solver.state): ``lump(model, nodes)`` of the units that have one, before the inverse
masses are formed -- the rigid bodies put each body's mass and inertia on its master and none
on its slaves (``nodes``: ``fixed``, ``kin_mass``, ``kin_inertia`` and ``carried``, the nodes
another node carries, which velocity Verlet leaves alone), and may put arrays there that
other units' ``setup`` changes (``rig_free_rot``: a driven or modal master's rotation is not
free); then every unit's ``setup``; then ``finish(constants, nodes)`` of those that have one
(the bodies' inverse inertia, once the other units took their DOFs). A unit's constants are
what its ``lump`` and its ``setup`` return.

Python-side hooks (plain functions, optional): ``setup(model, dt, nodes)`` returns the unit's
constant arrays by bundle field from the model (x3dpd.model.model.Model) and the step ``dt``,
and may take the unit's nodes out of velocity Verlet by changing the node arrays in ``nodes``
(``inv_m``, ``mass``, ``kin_mass``, ``kin_inertia``, ``rig_free_rot``: the
modes carry their nodes), and add constant forces to their body forces ``fbody`` (gravity);
``start(u, force)`` runs after the forces at a state were evaluated (t0, a state set from
outside), before the first step; ``stiffness(c)`` gives, from the
constants ``c``, ``(nodes (S, 2), k (S, 3), first DOF)`` of each group of linear elements, for
the bound on the structure's highest frequency (x3dpd.solver.diagnosis); ``turns(c)`` the rigid
bodies whose rotation the unit sets.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

#: The slots of the step loop, in the order a step calls them, with what a hook there does.
SLOTS = {
    "first_half_kick": "kick the unit's own velocities by half a step, before the nodes' "
                       "first half kick (which resets the forces)",
    "drift": "place the unit's nodes after the free drift, before carried nodes follow",
    "follow": "move what follows the drifted nodes: the nodes the unit carries (their largest "
              "speed into stepping.nbr[5], for the contact lists' skin), its own coordinates "
              "(with the nodes' half-step velocities)",
    "force": "add the unit's forces and moments at the step's new positions",
    "gather": "move the forces on the nodes the unit carries onto those that carry them",
    "kick": "take the step's summed forces (after the carried nodes' are gathered)",
    "second_half_kick": "kick the unit's own velocities by the step's second half",
    "place": "set the unit's nodes' full-step velocities (output rows, a call's end)",
    "energy": "add the unit's kinetic and stored energy, return its share of S",
}

# The energy ledger's slots (cumulative since t0; x3dpd.solver._template_contact and the
# units' hooks book into them).
L_WEXT = 0      # work of external forces and prescribed motions on the system
L_WN = 1        # work absorbed by the normal contact forces (sum of 1/2 (F0+F1) da)
L_DFRIC = 2     # energy dissipated by friction
L_DDAMP = 3     # energy dissipated by structural dampers
L_DROLL = 4     # energy dissipated by rolling resistance (a rolling law's scenes only)


@dataclass(frozen=True)
class StateArray:
    """An array of a unit's bundle that evolves with the run: part of the solver state, saved
    in restart dumps under ``name``. It has one row per row of the constant ``rows`` and the
    trailing ``columns`` (a restart dump without it -- written before the unit existed -- gets
    an empty one)."""

    field: str                    # the bundle's field
    name: str                     # the state's and the restart dump's name
    rows: str                     # the constant whose rows it has one row per
    columns: tuple[int, ...] = ()
    #: its value at t0 from its row count (zeros without: a rigid body's rotation starts at I)
    initial: Callable | None = None

    def at_start(self, rows: int) -> np.ndarray:
        """The array at t0 for ``rows`` rows."""
        if self.initial is not None:
            return np.ascontiguousarray(self.initial(rows), dtype=np.float64)
        return np.zeros((rows,) + self.columns)


@dataclass(frozen=True)
class UnitCard:
    """A deck card of a unit's own (our extension): records of numbers, each with ``fields``
    in order; the ``node_fields`` among them are node ids."""

    name: str                       # the keyword, as the writer prints it
    fields: tuple[str, ...]
    node_fields: tuple[str, ...] = ()

    @property
    def key(self) -> str:
        """The four letters X3D reads of a keyword."""
        return self.name[:4]


@dataclass(frozen=True)
class EffectUnit:
    """One effect unit (a module of x3dpd.physics; see the module docstring)."""

    name: str                       # the unit's name ("modal"): its bundle's key
    flag: str                       # the x3dpd.solver.variants.Variant field that compiles it
    effects: tuple[str, ...]        # the Model.effects that call for it (any of them)
    cards: tuple[str, ...]          # the deck cards its data comes from (docs, messages)
    bundle: type                    # the NamedTuple of its arrays: constants, state, scratch
    setup: Callable                 # (model, dt, nodes) -> {constant field: array}
    hooks: Mapping[str, str]        # slot -> name of the hook in its module
    #: the slots whose hook runs before the other units' (module docstring, "The slots")
    first: tuple[str, ...] = ()
    #: compiled into every step loop, without a flag (``flag`` ""): an effect outside the
    #: contact loop whose data say whether it acts (module docstring, "Runtime units")
    runtime: bool = False
    #: its drift and kick hooks also take the step's start time (module docstring)
    step_start: bool = False
    #: constants of the variant its hooks take after the slot's arguments (module docstring)
    variant_args: tuple[str, ...] = ()
    #: slot -> the Variant flag without which its hook there is not compiled: a hook only an
    #: effect beside the unit's own calls for (the rigid bodies' kicks and turn: a turning body)
    only_with: Mapping[str, str] = field(default_factory=dict)
    state: tuple[StateArray, ...] = ()
    #: scratch arrays of the bundle: (field, the state field it is shaped like)
    scratch: tuple[tuple[str, str], ...] = ()
    #: (model, nodes) -> its constants by bundle field, before the inverse masses are formed
    #: (module docstring, "Setup"): a unit whose nodes carry others' masses (the rigid bodies)
    lump: Callable | None = None
    #: (constants, nodes) after every unit's ``setup`` (module docstring, "Setup")
    finish: Callable | None = None
    start: Callable | None = None
    stiffness: Callable | None = None
    turns: Callable | None = None
    #: kernels of its module that the Python side calls on a state, reached as attributes of
    #: the compiled loop module (x3dpd.solver.variants.make_advance)
    kernels: tuple[str, ...] = ()
    card: UnitCard | None = None    # a card of its own, and
    build: Callable | None = None   # (rows, fail) -> its arrays (model.unit_data[name])
    check: Callable | None = None   # (model) -> [(code, headline, lines)] for x3dpd check
    module: str = ""                # the defining module (set by the registry)
    doc: str = ""                   # one line for docs and messages

    def constants(self) -> tuple[str, ...]:
        """The bundle's constant fields: those neither state nor scratch."""
        moving = {s.field for s in self.state} | {f for f, _ in self.scratch}
        return tuple(f for f in self.bundle._fields if f not in moving)
