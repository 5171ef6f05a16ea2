"""Pre-run check of a model: summary, recommended time step and geometry warnings.

:func:`check_model` never changes the model; it returns a :class:`CheckReport` whose
:meth:`~CheckReport.format` is what ``x3dpd check DECK`` prints. The geometry finders
(:func:`particle_wall_penetrations`, :func:`particles_outside`, :func:`particle_overlaps`,
:func:`faces_in_particle_cloud`) are reusable on their own; the solver uses
:func:`particle_wall_penetrations` to refuse a start with deep penetrations. The time-step
advice comes from :mod:`x3dpd.model.timestep`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from x3dpd.geometry.cavity import (
    cavity_extents,
    enclosed_volume,
    geometry_size,
    merge_vertices,
    surface_edges,
)
from x3dpd.geometry.pairs import overlapping_pairs
from x3dpd.geometry.triangle import unit_normals
from x3dpd.geometry.walls import sphere_triangle_pairs
from x3dpd.model.check_cylinders import (cylinder_extent, cylinder_volume, cylinder_warnings,
                                         describe_cylinder, smallest_clearance)
from x3dpd.model.magnitudes import magnitude_errors
from x3dpd.model.model import Model
from x3dpd.model.timestep import (
    STEPS_PER_CONTACT,
    TimeStepAdvice,
    recommended_time_step,
    time_step_is_a_problem,
    time_step_warning,
)

#: Relative tolerance for "touching" (distance equal to a radius sum or a radius).
REL_TOL = 1e-9
#: Longest listing of one warning's details.
MAX_LISTED = 20
_AXES = "xyz"


# -- geometry -----------------------------------------------------------------------------------

class WallPenetration(NamedTuple):
    """A particle whose sphere crosses a wall it lies over (centre on the inner side)."""

    particle: int  # 0-based particle number (node index - particle_start)
    node_id: int
    triangle: int  # 0-based, in CONTACT order
    depth: float  # R - d [length]


class OutsideParticle(NamedTuple):
    """A particle whose centre starts outside the cavity it belongs to."""

    particle: int
    node_id: int
    triangle: int  # 0-based triangle it lies behind, -1 when only outside the bounding box
    distance: float  # how far behind the wall (or outside the box) [length]


def _walls(model: Model):
    p = [model.x0[model.tri_nodes[:, k]] for k in range(3)]
    n_in = model.tri_sign[:, None] * unit_normals(*p)
    return p, n_in, model.face_cavity[model.tri_face]


def _over_walls(model: Model, edge_tol: np.ndarray):
    (p0, p1, p2), n_in, tri_cav = _walls(model)
    return sphere_triangle_pairs(model.x0[model.particle_start:], model.particle_cavity, p0, p1,
                                 p2, n_in, tri_cav, edge_tol)


def _deepest_per_face(model: Model, s, t, value, keep) -> list[tuple[int, int, float]]:
    """Largest ``value`` per (particle, face) among the kept pairs, sorted by particle.

    Returns (particle, triangle, value) with the first triangle in CONTACT order on ties.
    """
    s, t, value = s[keep], t[keep], value[keep]
    face = model.tri_face[t]
    order = np.lexsort((t, -value, face, s))
    s, t, value, face = s[order], t[order], value[order], face[order]
    first = np.ones(s.shape[0], dtype=bool)
    first[1:] = (s[1:] != s[:-1]) | (face[1:] != face[:-1])
    return list(zip(s[first].tolist(), t[first].tolist(), value[first].tolist()))


def particle_wall_penetrations(model: Model, min_depth_fraction: float = 0.0
                               ) -> list[WallPenetration]:
    r"""Particles that start penetrating a wall of their cavity.

    Penetration of particle :math:`i` into triangle :math:`t`: its centre is on the inner side
    and closer than :math:`R` to the plane, :math:`0 \le d < R`, and its projection lies in the
    triangle grown by :math:`R` (an edge contact counts). Depth :math:`R - d`. One entry per
    particle and face (the deepest triangle of the face); only depths above
    ``min_depth_fraction * R`` (and above touching, :data:`REL_TOL`) are returned.
    """
    r = model.radius
    s, t, d = _over_walls(model, r)
    depth = r[s] - d
    keep = (d >= -REL_TOL * r[s]) & (depth > np.maximum(REL_TOL, min_depth_fraction) * r[s])
    return [WallPenetration(i, int(model.node_ids[model.particle_start + i]), k, v)
            for i, k, v in _deepest_per_face(model, s, t, depth, keep)]


def particles_outside(model: Model) -> list[OutsideParticle]:
    r"""Particles whose centre starts outside the cavity they bound.

    Outside: behind some wall, :math:`d < 0` with the projection inside the wall's triangle, or
    -- for a closed cavity -- outside the bounding box of its triangle nodes. An open cavity (a
    floor, an open-top box) has no inside beyond its walls' inner half-spaces, so only the first
    test applies to it. One entry per particle (the farthest behind). Exact for convex cavities.
    """
    p0 = model.particle_start
    s, t, d = _over_walls(model, REL_TOL * model.radius)
    keep = d < -REL_TOL * model.radius[s]
    worst: dict[int, tuple[float, int]] = {}
    for i, k, v in _deepest_per_face(model, s, t, -d, keep):
        if i not in worst or v > worst[i][0]:
            worst[i] = (v, k)
    for c in range(model.cavity_set_ids.shape[0]):
        if not np.any(model.face_cavity[model.tri_face] == c) or not _closed(model, c)[0]:
            continue   # (a cylinder's own test: x3dpd.model.check_cylinders)
        lo, hi = cavity_extents(model.x0[model.tri_nodes[model.face_cavity[model.tri_face] == c]
                                         .reshape(-1)])
        tol = REL_TOL * geometry_size(np.stack([lo, hi]))
        mine = np.flatnonzero(model.particle_cavity == c)
        x = model.x0[p0 + mine]
        gap = np.max(np.maximum(lo - x, x - hi), axis=1)
        for i, g in zip(mine[gap > tol].tolist(), gap[gap > tol].tolist()):
            worst.setdefault(i, (g, -1))
    return [OutsideParticle(i, int(model.node_ids[p0 + i]), k, v)
            for i, (v, k) in sorted(worst.items())]


def particle_overlaps(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping particle pairs as ``(node id pairs (M, 2), overlap depths (M,))``."""
    pairs, depth = overlapping_pairs(model.x0[model.particle_start:], model.radius, REL_TOL)
    return model.node_ids[model.particle_start:][pairs].reshape(-1, 2), depth


def faces_in_particle_cloud(model: Model) -> list[int]:
    r"""Faces whose plane cuts through their cavity's particles.

    A face is inside the particle cloud when, among the particles of its cavity whose centres
    lie over it (projection within :math:`R` of its triangles), some centres are on or behind
    its plane (:math:`d \le 0`) and some in front (:math:`d > 0`). A cavity wall should have
    every particle on its inner side.
    """
    s, t, d = _over_walls(model, model.radius)
    tol = REL_TOL * model.radius[s]
    face = model.tri_face[t]
    return [int(f) for f in np.unique(face)
            if np.any(d[face == f] <= tol[face == f]) and np.any(d[face == f] > tol[face == f])]


# -- report -------------------------------------------------------------------------------------

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
    cylinders: tuple[str, ...] = ()  # each analytic cylinder, with its smallest clearance

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

    @property
    def n_particles(self) -> int:
        return int(sum(g.count for g in self.groups))

    @property
    def exit_status(self) -> int:
        return 2 if self.errors else (1 if self.warnings else 0)


def check_model(model: Model, steps_per_contact: int = STEPS_PER_CONTACT) -> CheckReport:
    """Summarise a model and list what is likely wrong with it before a run.

    Warnings, in this order: walls that cut through the particle cloud (one headline per
    cavity), particles outside their cavity, particles penetrating walls, overlapping particles,
    cavities whose inside could not be told consistently, particles in no slave set, cavities
    without particles, and a time step above the recommendation (:func:`recommended_time_step`).
    The model itself is consistent (:func:`~x3dpd.model.build.build_model` raised otherwise);
    ``errors`` lists numbers a run cannot work with (:func:`~x3dpd.model.magnitudes.
    magnitude_errors`: masses that underflow, kinetic energies or weights that overflow).
    """
    ps = model.particle_start
    cavities = _cavity_summaries(model)
    outside = particles_outside(model)
    warnings = _cloud_findings(model, faces_in_particle_cloud(model), outside)
    if outside:
        warnings.append(Finding(
            "particles-outside",
            f"{len(outside)} of the {model.n_particles} particles start outside the cavity they "
            f"bound: their centres lie behind a wall or outside the box of the cavity's nodes, "
            f"so those walls would push them from the wrong side",
            _listed([f"particle node {o.node_id}: " + (
                f"{o.distance:.6g} behind {_tri(model, o.triangle)}" if o.triangle >= 0 else
                f"{o.distance:.6g} outside the bounding box of cavity set "
                f"{model.cavity_set_ids[model.particle_cavity[o.particle]]}") for o in outside])))
    behind = {o.particle for o in outside}
    pen = sorted((p for p in particle_wall_penetrations(model) if p.particle not in behind),
                 key=lambda p: -p.depth)
    if pen:
        r = model.radius
        warnings.append(Finding(
            "wall-penetration",
            f"{len({p.particle for p in pen})} particles "
            + ("inside their cavity " if behind else "")
            + f"start penetrating a wall (deepest: "
            f"particle node {pen[0].node_id}, {pen[0].depth:.6g} = "
            f"{pen[0].depth / r[pen[0].particle]:.3g} R into {_tri(model, pen[0].triangle)})",
            _listed([f"particle node {p.node_id}: {p.depth:.6g} ({p.depth / r[p.particle]:.3g} R) "
                     f"into {_tri(model, p.triangle)}" for p in pen])))
    warnings += [Finding(code, head, _listed(lines))
                 for code, head, lines in cylinder_warnings(model, REL_TOL)]
    pairs, depth = particle_overlaps(model)
    if pairs.shape[0]:
        rad = dict(zip(model.node_ids[ps:].tolist(), model.radius.tolist()))
        order = np.argsort(-depth, kind="stable")
        warnings.append(Finding(
            "particle-overlap",
            f"{pairs.shape[0]} particle pairs start overlapping (deepest: nodes "
            f"{pairs[order[0], 0]} and {pairs[order[0], 1]}, {depth[order[0]]:.6g})",
            _listed([f"particle nodes {a} and {b}: overlap {d:.6g} "
                     f"({d / min(rad[a], rad[b]):.3g} R)"
                     for (a, b), d in zip(pairs[order].tolist(), depth[order])])))
    for cav in cavities:
        if cav.closed and (not cav.consistent or not cav.volume or cav.volume < 0):
            warnings.append(Finding(
                "cavity-orientation",
                f"cavity set {cav.set_id} is closed, but the inward sides taken from the centroid "
                f"of its nodes do not agree along shared edges: the cavity is probably not "
                f"convex, and some walls may push particles outward"))
        if cav.n_particles == 0:
            warnings.append(Finding("empty-cavity",
                                    f"cavity set {cav.set_id} has no slave particles"))
    loose = model.node_ids[ps:][model.particle_cavity < 0]
    if loose.size and (model.tri_nodes.shape[0] or model.cylinder_radius.shape[0]):
        warnings.append(Finding(
            "no-cavity",
            f"{loose.size} particles are in no CONTACT slave set and will pass through every "
            f"wall: nodes {_ranges(loose)}"))
    ts = recommended_time_step(model, steps_per_contact)
    if time_step_is_a_problem(ts):
        warnings.append(Finding("time-step", time_step_warning(ts, model)))
    groups = []
    for g in np.unique(model.particle_group).tolist():
        mine = np.flatnonzero(model.particle_group == g)
        groups.append(GroupSummary(int(g), int(mine.size), _ranges(model.node_ids[ps + mine]),
                                   float(model.radius[mine[0]]), float(model.mass[ps + mine[0]])))
    return CheckReport(
        path=model.path, n_nodes=model.n_nodes, groups=tuple(groups),
        particle_mass=float(model.mass[ps:].sum()), structure_mass=float(model.mass[:ps].sum()),
        cavities=tuple(cavities), effects=model.effects, time_step=ts,
        warnings=tuple(warnings),
        errors=tuple(Finding("extreme-value", text) for text in magnitude_errors(model)))


def _closed(model: Model, c: int) -> tuple[bool, bool]:
    """(closed, consistently oriented) for the surface of cavity ``c``'s triangles."""
    mine = np.flatnonzero(model.face_cavity[model.tri_face] == c)
    pts = model.x0[model.tri_nodes[mine]].reshape(-1, 3)
    labels = merge_vertices(pts, geometry_size(pts)).reshape(-1, 3)
    return surface_edges(labels, model.tri_sign[mine])


def _cavity_summaries(model: Model) -> list[CavitySummary]:
    out = []
    tri_cav = model.face_cavity[model.tri_face]
    pvol = 4.0 / 3.0 * math.pi * model.radius**3
    for c, sid in enumerate(model.cavity_set_ids.tolist()):
        mine = np.flatnonzero(tri_cav == c)
        cyl = np.flatnonzero(model.cylinder_cavity == c)
        inside = model.particle_cavity == c
        if mine.size == 0:   # a cavity of analytic cylinders (CYLINDER card)
            ends = np.concatenate([np.stack(cylinder_extent(model, k)) for k in cyl])
            lo, hi = cavity_extents(ends)
            closed = consistent = True
            volume = sum(cylinder_volume(model, k) for k in cyl)
        else:
            corners = model.x0[model.tri_nodes[mine]]  # (T, 3 corners, 3)
            lo, hi = cavity_extents(corners.reshape(-1, 3))
            closed, consistent = _closed(model, c)
            volume = enclosed_volume(corners[:, 0], corners[:, 1], corners[:, 2],
                                     model.tri_sign[mine]) if closed else None
        cylinders = []
        for k in cyl:
            gap = smallest_clearance(model, k)
            cylinders.append(describe_cylinder(model, k) + (
                "" if gap is None else f"; smallest particle clearance {gap:.6g}"))
        out.append(CavitySummary(
            int(sid), tuple(lo.tolist()), tuple(hi.tolist()), int(mine.size),
            int(np.unique(model.tri_face[mine]).size), closed, consistent, volume,
            int(inside.sum()), float(pvol[inside].sum()), tuple(cylinders)))
    return out


def _cloud_findings(model: Model, faces: list[int], outside: list[OutsideParticle]
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
        who = (f"the {_count(total)} contact triangles" if tris.size == total else
               f"{_count(int(tris.size))} of the {_count(total)} contact triangles")
        first = [int(np.flatnonzero(model.tri_face == f)[0]) for f in mine]
        planes = _planes_text(n_in[first], p0[first])
        centres = model.x0[model.particle_start:][model.particle_cavity == c]
        n_out = sum(1 for o in outside if model.particle_cavity[o.particle] == c)
        text = (f"cavity set {sid}: {who} lie in the plane{'s' if len(mine) > 1 else ''} "
                f"{planes}, inside the particle cloud (particle centres span "
                f"{_span_text(centres)}), so "
                + ("no closed cavity holds the particles" if tris.size == total else
                   "these walls cut through the particles"))
        if n_out:
            text += (f"; {n_out} of the {centres.shape[0]} particles start outside the cavity "
                     f"they bound")
        text += (". The report's Appendix A deck prints its cavity this way; "
                 "decks/appendix_a_cube.inp moves the cavity nodes onto the faces of the box the "
                 "particles fill.")
        out.append(Finding("faces-in-particle-cloud", text))
    return out


def _planes_text(n_in: np.ndarray, p0: np.ndarray) -> str:
    """'x = 0.0625, 0.1875, z = ±0.09375' for axis-aligned planes, 'n·x = d' otherwise."""
    by_axis: dict[int, list[float]] = {}
    other = []
    for n, p in zip(n_in, p0):
        k = int(np.argmax(np.abs(n)))
        if abs(abs(n[k]) - 1.0) <= 1e-9:
            by_axis.setdefault(k, []).append(float(p[k]))
        else:
            other.append(f"({n[0]:.4g}, {n[1]:.4g}, {n[2]:.4g})·x = {float(n @ p):.6g}")
    parts = []
    for k in sorted(by_axis):
        vals = sorted(set(round(v, 12) for v in by_axis[k]), key=lambda v: (abs(v), v))
        text, used = [], set()
        for v in vals:
            if v in used:
                continue
            if v != 0.0 and -v in vals:
                text.append(f"±{abs(v):g}")
                used.update({v, -v})
            else:
                text.append(f"{v:g}")
                used.add(v)
        parts.append(f"{_AXES[k]} = {', '.join(text)}")
    return ", ".join(parts + other)


def _span_text(centres: np.ndarray) -> str:
    """'x, y from 0.03125 to 0.21875 and z from -0.09375 to 0.09375'."""
    if centres.shape[0] == 0:
        return "nothing"
    lo, hi = centres.min(axis=0), centres.max(axis=0)
    groups: list[tuple[list[str], float, float]] = []
    for k in range(3):
        for g in groups:
            if math.isclose(g[1], lo[k], abs_tol=1e-12) and math.isclose(g[2], hi[k],
                                                                         abs_tol=1e-12):
                g[0].append(_AXES[k])
                break
        else:
            groups.append(([_AXES[k]], float(lo[k]), float(hi[k])))
    return " and ".join(f"{', '.join(a)} from {a_lo:g} to {a_hi:g}" for a, a_lo, a_hi in groups)


def _tri(model: Model, k: int) -> str:
    nodes = " ".join(str(int(model.node_ids[i])) for i in model.tri_nodes[k])
    return f"triangle {k + 1} (nodes {nodes})"


def _listed(lines: list[str]) -> tuple[str, ...]:
    if len(lines) <= MAX_LISTED:
        return tuple(lines)
    return (*lines[:MAX_LISTED], f"... and {len(lines) - MAX_LISTED} more")


def _ranges(ids: np.ndarray) -> str:
    """'26-40, 42, 44-50' from sorted ids."""
    ids = np.sort(np.asarray(ids))
    out, start = [], 0
    for k in range(1, ids.size + 1):
        if k == ids.size or ids[k] != ids[k - 1] + 1:
            a, b = int(ids[start]), int(ids[k - 1])
            out.append(f"{a}" if a == b else f"{a}-{b}")
            start = k
    return ", ".join(out)


_WORDS = ("zero one two three four five six seven eight nine ten eleven twelve thirteen "
          "fourteen fifteen sixteen seventeen eighteen nineteen twenty").split()


def _count(n: int) -> str:
    return _WORDS[n] if 0 <= n < len(_WORDS) else str(n)
