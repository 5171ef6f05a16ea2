# Over 400 lines: check_model gathers every finding of x3dpd check (their parts: check_*.py).
"""Pre-run check of a model: summary, recommended time step and geometry warnings.

:func:`check_model` never changes the model; it returns a :class:`CheckReport` whose
:meth:`~CheckReport.format` is what ``x3dpd check DECK`` prints. The geometry finders
(:func:`particle_wall_penetrations`, :func:`particles_outside`, :func:`particle_overlaps`,
:func:`faces_in_particle_cloud`) live in :mod:`x3dpd.model.check_geometry` (importable from here
too) and are reusable on their own; the solver uses :func:`particle_wall_penetrations` to refuse
a start with deep penetrations. The time-step advice comes from :mod:`x3dpd.model.timestep`,
the wording of the findings' details from :mod:`x3dpd.model.check_text`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from x3dpd.geometry.cavity import cavity_extents, enclosed_volume
from x3dpd.model.check_shapes import (
    describe_shape,
    shape_clearances,
    shape_volume,
    shape_warnings,
    smallest_clearance,
    summary_extent,
)
from x3dpd.model.check_geometry import (  # noqa: F401  (WallPenetration re-exported)
    REL_TOL,
    OutsideParticle,
    WallPenetration,
    _closed,
    _walls,
    faces_in_particle_cloud,
    particle_overlaps,
    particle_wall_penetrations,
    particles_outside,
)
from x3dpd.model.check_text import (  # noqa: F401  (MAX_LISTED re-exported)
    MAX_LISTED,
    _count,
    _listed,
    _planes_text,
    _ranges,
    _span_text,
    _tri,
)
from x3dpd.model.check_beds import jammed_beds
from x3dpd.model.check_modal import modal_table, modal_warnings
from x3dpd.model.magnitudes import magnitude_errors
from x3dpd.model.model import Model
from x3dpd.model.rules_of_thumb import RuleNote, rules_of_thumb
from x3dpd.physics.effect_units import UNITS
from x3dpd.model.temperature import check_findings, check_lines
from x3dpd.physics.usrfrc import is_user_file
from x3dpd.physics.wall_material import mixed_modulus, plane_strain_modulus
from x3dpd.model.timestep import (
    STEPS_PER_CONTACT,
    TimeStepAdvice,
    recommended_time_step,
    time_step_is_a_problem,
    time_step_warning,
)


@dataclass(frozen=True)
class WallSummary:
    """A cavity's WALLMAT material: E [pressure] (inf: rigid), NU, MU, and the mixed modulus
    E* of each particle group in it, ((0-based group, E*), ...)."""

    e: float
    nu: float
    mu: float
    e_star: tuple[tuple[int, float], ...]


@dataclass(frozen=True)
class CavitySummary:
    """One cavity: bounding box of its triangle nodes, closure, volume and fill."""

    set_id: int
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    n_triangles: int
    n_faces: int
    closed: bool
    consistent: bool
    volume: float | None  # None when the faces do not close
    n_particles: int
    particle_volume: float
    analytic_walls: tuple[str, ...] = ()  # each analytic wall, with its smallest clearance
    wall_material: WallSummary | None = None  # WALLMAT (None: a deck without the card)

    @property
    def fill_ratio(self) -> float | None:
        return None if not self.volume else self.particle_volume / self.volume


@dataclass(frozen=True)
class GroupSummary:
    """One PDMP particle group: how many particles, which nodes, radius and mass of each."""

    group: int  # 0-based PDMP card number
    count: int
    nodes: str  # node id ranges, e.g. "26-75"
    radius: float
    mass: float


@dataclass(frozen=True)
class Finding:
    """One warning or error: a headline and optional detail lines."""

    code: str
    headline: str
    details: tuple[str, ...] = ()


@dataclass(frozen=True)
class CheckReport:
    """Result of :func:`check_model`; ``exit_status`` is 0 clean, 1 warnings, 2 errors."""

    path: str
    n_nodes: int
    groups: tuple[GroupSummary, ...]
    particle_mass: float
    structure_mass: float
    cavities: tuple[CavitySummary, ...]
    effects: frozenset
    time_step: TimeStepAdvice
    warnings: tuple[Finding, ...]
    errors: tuple[Finding, ...] = ()
    modes: tuple[str, ...] = ()  # the modal structure's table (x3dpd.model.check_modal)
    #: the report's rules of thumb (x3dpd.model.rules_of_thumb): notes, never warnings
    rules: tuple[RuleNote, ...] = ()
    #: the Python files a run of this deck executes (USRFRC user force files, deck and option)
    code_files: tuple[str, ...] = ()
    temperature: tuple[str, ...] = ()  # the TEMPERATURE card's lines (x3dpd.model.temperature)

    @property
    def n_particles(self) -> int:
        return int(sum(g.count for g in self.groups))

    @property
    def exit_status(self) -> int:
        return 2 if self.errors else (1 if self.warnings else 0)


# Over 80 lines: every finding of x3dpd check gathered in print order (their parts: check_*.py).
def check_model(
    model: Model, steps_per_contact: int = STEPS_PER_CONTACT, *, usrfrc=()
) -> CheckReport:
    """Summarise a model and list what is likely wrong with it before a run.

    Warnings, in this order: walls that cut through the particle cloud (one headline per
    cavity), particles outside their cavity or penetrating walls, the analytic walls' and modal
    structure's, beds wall to wall along the drive (x3dpd.model.check_beds), overlapping
    particles, cavities whose inside could not be told consistently, particles in no slave set,
    cavities without particles, and a time step above the recommendation.
    The model itself is consistent (:func:`~x3dpd.model.build.build_model` raised otherwise);
    ``errors`` lists numbers a run cannot work with (:func:`~x3dpd.model.magnitudes.
    magnitude_errors`: masses that underflow, kinetic energies or weights that overflow).
    ``rules`` holds the report's rules of thumb (:func:`~x3dpd.model.rules_of_thumb.
    rules_of_thumb`, with the drive of the deck's USRFRC card and ``usrfrc``): notes that
    change neither the warnings nor the exit status.
    """
    ps = model.particle_start
    cavities = _cavity_summaries(model)
    outside = particles_outside(model)
    warnings = _cloud_findings(model, faces_in_particle_cloud(model), outside)
    if outside:
        warnings.append(
            Finding(
                "particles-outside",
                f"{len(outside)} of the {model.n_particles} particles start outside the cavity "
                f"they bound: their centres lie behind a wall or outside the box of the cavity's "
                f"nodes, so those walls would push them from the wrong side",
                _listed(
                    [
                        f"particle node {o.node_id}: "
                        + (
                            f"{o.distance:.6g} behind {_tri(model, o.triangle)}"
                            if o.triangle >= 0
                            else f"{o.distance:.6g} outside the bounding box of cavity set "
                            f"{model.cavity_set_ids[model.particle_cavity[o.particle]]}"
                        )
                        for o in outside
                    ]
                ),
            )
        )
    behind = {o.particle for o in outside}
    pen = sorted(
        (p for p in particle_wall_penetrations(model) if p.particle not in behind),
        key=lambda p: -p.depth,
    )
    if pen:
        r = model.radius
        warnings.append(
            Finding(
                "wall-penetration",
                f"{len({p.particle for p in pen})} particles "
                + ("inside their cavity " if behind else "")
                + f"start penetrating a wall (deepest: "
                f"particle node {pen[0].node_id}, {pen[0].depth:.6g} = "
                f"{pen[0].depth / r[pen[0].particle]:.3g} R into {_tri(model, pen[0].triangle)})",
                _listed(
                    [
                        f"particle node {p.node_id}: {p.depth:.6g} "
                        f"({p.depth / r[p.particle]:.3g} R) into {_tri(model, p.triangle)}"
                        for p in pen
                    ]
                ),
            )
        )
    warnings += [
        Finding(code, head, _listed(lines)) for code, head, lines in shape_warnings(model, REL_TOL)
    ]
    unit_findings = [f for u in UNITS if u.check is not None for f in u.check(model)]
    for code, head, lines in modal_warnings(model) + unit_findings:
        warnings.append(Finding(code, head, _listed(lines)))
    warnings += [Finding(code, head, lines) for code, head, lines in jammed_beds(model, usrfrc)]
    warnings += [Finding(code, head, tuple(lines)) for code, head, lines in check_findings(model)]
    pairs, depth = particle_overlaps(model)
    if pairs.shape[0]:
        rad = dict(zip(model.node_ids[ps:].tolist(), model.radius.tolist()))
        order = np.argsort(-depth, kind="stable")
        warnings.append(
            Finding(
                "particle-overlap",
                f"{pairs.shape[0]} particle pairs start overlapping (deepest: nodes "
                f"{pairs[order[0], 0]} and {pairs[order[0], 1]}, {depth[order[0]]:.6g})",
                _listed(
                    [
                        f"particle nodes {a} and {b}: overlap {d:.6g} "
                        f"({d / min(rad[a], rad[b]):.3g} R)"
                        for (a, b), d in zip(pairs[order].tolist(), depth[order])
                    ]
                ),
            )
        )
    for cav in cavities:
        if cav.closed and (not cav.consistent or not cav.volume or cav.volume < 0):
            warnings.append(
                Finding(
                    "cavity-orientation",
                    f"cavity set {cav.set_id} is closed, but the inward sides taken from the "
                    f"centroid of its nodes do not agree along shared edges: the cavity is "
                    f"probably not convex, and some walls may push particles outward",
                )
            )
        if cav.n_particles == 0:
            warnings.append(
                Finding("empty-cavity", f"cavity set {cav.set_id} has no slave particles")
            )
    loose = model.node_ids[ps:][model.particle_cavity < 0]
    if loose.size and (model.tri_nodes.shape[0] or model.shape_kind.shape[0]):
        warnings.append(
            Finding(
                "no-cavity",
                f"{loose.size} particles are in no CONTACT slave set and will pass through every "
                f"wall: nodes {_ranges(loose)}",
            )
        )
    ts = recommended_time_step(model, steps_per_contact)
    if time_step_is_a_problem(ts):
        warnings.append(Finding("time-step", time_step_warning(ts, model)))
    groups = []
    for g in np.unique(model.particle_group).tolist():
        mine = np.flatnonzero(model.particle_group == g)
        groups.append(
            GroupSummary(
                int(g),
                int(mine.size),
                _ranges(model.node_ids[ps + mine]),
                float(model.radius[mine[0]]),
                float(model.mass[ps + mine[0]]),
            )
        )
    return CheckReport(
        path=model.path,
        n_nodes=model.n_nodes,
        groups=tuple(groups),
        particle_mass=float(model.mass[ps:].sum()),
        structure_mass=float(model.mass[:ps].sum()),
        cavities=tuple(cavities),
        effects=model.effects,
        time_step=ts,
        warnings=tuple(warnings),
        errors=tuple(Finding("extreme-value", text) for text in magnitude_errors(model)),
        modes=tuple(modal_table(model)),
        temperature=tuple(check_lines(model)),
        rules=tuple(rules_of_thumb(model, usrfrc=usrfrc)),
        code_files=tuple(
            dict.fromkeys(spec for spec in (*model.usrfrc, *usrfrc) if is_user_file(spec))
        ),
    )


def _cavity_summaries(model: Model) -> list[CavitySummary]:
    out = []
    tri_cav = model.face_cavity[model.tri_face]
    pvol = 4.0 / 3.0 * math.pi * model.radius**3
    found = shape_clearances(model) if model.shape_kind.shape[0] else []
    for c, sid in enumerate(model.cavity_set_ids.tolist()):
        mine = np.flatnonzero(tri_cav == c)
        walls = np.flatnonzero(model.shape_cavity == c)
        inside = model.particle_cavity == c
        if mine.size == 0:  # a cavity of analytic walls (CYLINDER, CAPSULE ... cards)
            ends = np.concatenate([np.stack(summary_extent(model, k)) for k in walls])
            lo, hi = cavity_extents(ends)
            closed = consistent = True
            volume = sum(shape_volume(model, k) for k in walls)
        else:
            corners = model.x0[model.tri_nodes[mine]]  # (T, 3 corners, 3)
            lo, hi = cavity_extents(corners.reshape(-1, 3))
            closed, consistent = _closed(model, c)
            volume = (
                enclosed_volume(corners[:, 0], corners[:, 1], corners[:, 2], model.tri_sign[mine])
                if closed
                else None
            )
        analytic = []
        for k in walls:
            gap = smallest_clearance(model, k, found)
            analytic.append(
                describe_shape(model, k)
                + ("" if gap is None else f"; smallest particle clearance {gap:.6g}")
            )
        out.append(
            CavitySummary(
                int(sid),
                tuple(lo.tolist()),
                tuple(hi.tolist()),
                int(mine.size),
                int(np.unique(model.tri_face[mine]).size),
                closed,
                consistent,
                volume,
                int(inside.sum()),
                float(pvol[inside].sum()),
                tuple(analytic),
                _wall_material(model, c),
            )
        )
    return out


def _wall_material(model: Model, c: int) -> WallSummary | None:
    """The WALLMAT material of cavity ``c`` and the mixed modulus E* of each particle group
    in it (x3dpd.physics.wall_material); None for a deck without WALLMAT."""
    if model.wall_material is None:
        return None
    e, nu, mu = (float(v) for v in model.wall_material[c])
    if math.isinf(e):
        return WallSummary(e, nu, mu, ())
    c_wall = plane_strain_modulus(e, nu)
    mixed = []
    for g in np.unique(model.particle_group[model.particle_cavity == c]).tolist():
        p = int(np.flatnonzero(model.particle_group == g)[0])
        c_p = float(model.moduli[p].sum()) / (1.0 - float(model.poisson[p]) ** 2)
        mixed.append((int(g), mixed_modulus(c_p, c_wall)))
    return WallSummary(e, nu, mu, tuple(mixed))


def _cloud_findings(
    model: Model, faces: list[int], outside: list[OutsideParticle]
) -> list[Finding]:
    """One headline per cavity whose wall planes cut through its particles."""
    out = []
    tri_cav = model.face_cavity[model.tri_face]
    (p0, _, _), n_in, _ = _walls(model)
    for c, sid in enumerate(model.cavity_set_ids.tolist()):
        mine = [f for f in faces if model.face_cavity[f] == c]
        if not mine:
            continue
        tris = np.flatnonzero(np.isin(model.tri_face, mine))
        total = int(np.sum(tri_cav == c))
        who = (
            f"the {_count(total)} contact triangles"
            if tris.size == total
            else f"{_count(int(tris.size))} of the {_count(total)} contact triangles"
        )
        first = [int(np.flatnonzero(model.tri_face == f)[0]) for f in mine]
        planes = _planes_text(n_in[first], p0[first])
        centres = model.x0[model.particle_start :][model.particle_cavity == c]
        n_out = sum(1 for o in outside if model.particle_cavity[o.particle] == c)
        text = (
            f"cavity set {sid}: {who} lie in the plane{'s' if len(mine) > 1 else ''} "
            f"{planes}, inside the particle cloud (particle centres span "
            f"{_span_text(centres)}), so "
            + (
                "no closed cavity holds the particles"
                if tris.size == total
                else "these walls cut through the particles"
            )
        )
        if n_out:
            text += (
                f"; {n_out} of the {centres.shape[0]} particles start outside the cavity they bound"
            )
        text += (
            ". The report's Appendix A deck prints its cavity this way; "
            "decks/appendix_a_cube.inp moves the cavity nodes onto the faces of the box the "
            "particles fill."
        )
        out.append(Finding("faces-in-particle-cloud", text))
    return out
