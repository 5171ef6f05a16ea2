"""What a picture of a traced run needs: the particles' rows, radii and masses, and the cavity's
triangles placed at every output time.

A trace holds the traced nodes only. The cavity's triangle nodes are usually rigid slaves of a
master node (RBEL), and the trace holds the master (pmov.m's first row), so a vertex is placed at
each output time by the first rule that applies:

1. the vertex is traced itself: its traced position;
2. it is a rigid slave of a traced master: ``x0 + (x_master(t) - x_master0)`` (the master's
   translation; the report's cavities do not turn -- x3dpd keeps no rotation angles in the
   trace, so a turning cavity is drawn translated only);
3. otherwise (a fixed wall, e.g. decks/impact_wall.inp's floor): its deck coordinates.

An analytic wall (CYLINDER, CAPSULE ... card) is drawn as its shape's mesh with
:data:`CYLINDER_FACETS` flat facets around (x3dpd.geometry.shapes), whose vertices follow its
node A by the same rules.

:func:`scene_from_model` takes a :class:`x3dpd.model.model.Model` (any object with its
attributes), so this module does not depend on the model package.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from x3dpd.geometry.cavity import geometry_size, merge_vertices
from x3dpd.geometry.shapes import analytic_wall

#: Facets around a drawn analytic wall (a cylinder's sagitta is 0.2 % of its radius).
CYLINDER_FACETS = 48


@dataclass(frozen=True)
class Scene:
    """Geometry for pictures of a trace with ``R`` rows per output time.

    Attributes
    ----------
    node_ids : (R,) traced user node ids.
    particle_rows : (P,) trace rows that are particles; ``radius``, ``mass`` (P,) theirs
        [length], [mass].
    tri : (T, 3) vertex indices of the wall triangles.
    outline : (E, 2) vertex indices of the cavity's feature edges (between triangles that are
        not coplanar, or on the border of an open surface): its outline without the diagonals
        that split a flat face into triangles.
    unplaced : number of vertices that can move (free, or slaves of an untraced master) but
        have no traced position: they are drawn at their deck coordinates.
    vertex_x0 : (V, 3) deck coordinates of the vertices.
    vertex_row : (V,) trace row of each vertex, -1 if not traced.
    vertex_master_row : (V,) trace row of its traced rigid master, -1 if none.
    vertex_master_x0 : (V, 3) deck coordinates of that master.
    units : labels (``x3dpd.units``-style dict: length, velocity, energy, ...).
    title : the deck's title.
    """

    node_ids: np.ndarray
    particle_rows: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    tri: np.ndarray
    vertex_x0: np.ndarray
    vertex_row: np.ndarray
    vertex_master_row: np.ndarray
    vertex_master_x0: np.ndarray
    units: dict = field(default_factory=dict)
    title: str = ""
    outline: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    unplaced: int = 0

    def vertices(self, data: np.ndarray) -> np.ndarray:
        """(V, 3) vertex positions at one output time; ``data`` (R, 9) is the trace block."""
        out = self.vertex_x0.copy()
        moved = self.vertex_master_row >= 0
        if moved.any():
            out[moved] += data[self.vertex_master_row[moved], :3] - self.vertex_master_x0[moved]
        own = self.vertex_row >= 0
        out[own] = data[self.vertex_row[own], :3]
        return out

    def bounds(self, data: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corner of the cavity at the deck's coordinates and, given a trace
        block ``data`` (R, 9), of its particles' spheres (for fixed axes)."""
        lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        if self.vertex_x0.shape[0]:
            lo, hi = self.vertex_x0.min(axis=0), self.vertex_x0.max(axis=0)
        if data is not None and self.particle_rows.shape[0]:
            p = data[self.particle_rows, :3]
            r = self.radius[:, None]
            lo = np.minimum(lo, (p - r).min(axis=0))
            hi = np.maximum(hi, (p + r).max(axis=0))
        if not np.all(np.isfinite(lo) & np.isfinite(hi)):
            return np.zeros(3), np.ones(3)
        return lo, hi

    @property
    def particle_inertia(self) -> np.ndarray:
        """Solid-sphere moments of inertia 2/5 m R^2 [mass length^2]."""
        return 0.4 * self.mass * self.radius**2


def scene_from_model(model, node_ids, units: dict | None = None) -> Scene:
    """Build the :class:`Scene` of a trace following ``node_ids`` from the deck's ``model``."""
    node_ids = np.asarray(node_ids, dtype=np.int64)
    index = {int(nid): r for r, nid in enumerate(node_ids)}
    ids = np.asarray(model.node_ids)
    rows, radius, mass = [], [], []
    for r, nid in enumerate(node_ids):
        i = int(np.searchsorted(ids, nid))
        if i < ids.shape[0] and ids[i] == nid and i >= model.particle_start:
            rows.append(r)
            p = i - model.particle_start
            radius.append(float(model.radius[p]))
            mass.append(float(model.density[p]) * 4.0 / 3.0 * math.pi * float(model.radius[p]) ** 3)
    tri_nodes = np.asarray(model.tri_nodes, dtype=np.int64).reshape(-1, 3)
    verts, tri = np.unique(tri_nodes, return_inverse=True)
    master_of = np.full(ids.shape[0], -1, dtype=np.int64)
    for b, m in enumerate(np.asarray(model.rigid_master)):
        master_of[model.rigid_slaves[model.rigid_ptr[b] : model.rigid_ptr[b + 1]]] = m
    vrow = np.array([index.get(int(ids[v]), -1) for v in verts], dtype=np.int64)
    vmaster = master_of[verts] if verts.size else np.zeros(0, np.int64)
    vmrow = np.array(
        [index.get(int(ids[m]), -1) if m >= 0 else -1 for m in vmaster], dtype=np.int64
    )
    vmx0 = np.array([model.x0[m] if m >= 0 else np.zeros(3) for m in vmaster]).reshape(-1, 3)
    tri = tri.reshape(-1, 3).astype(np.int64)
    vx0 = np.asarray(model.x0)[verts].reshape(-1, 3)
    outline = feature_edges(tri, vx0)
    for w in range(np.asarray(getattr(model, "shape_kind", np.zeros(0))).shape[0]):
        # a drawn analytic wall's vertices translate with its node A (traced) or A's master
        a = int(model.shape_nodes[w, 0])
        shape, ends, lengths = analytic_wall(
            model.shape_kind[w], model.shape_nodes[w], model.shape_params[w], model.x0
        )
        cv, ct = shape.mesh(ends, lengths, CYLINDER_FACETS)
        k = cv.shape[0]
        ref = int(a) if int(ids[a]) in index else int(master_of[a])
        row = index.get(int(ids[ref]), -1) if ref >= 0 else -1
        tri = np.concatenate([tri, ct + vx0.shape[0]])
        # its outline: the shape's own, or its rims (the creases between facets are the
        # drawing's, not the shape's)
        rims = (
            shape.outline(ends, lengths, CYLINDER_FACETS)
            if shape.outline is not None
            else feature_edges(ct, cv, cos_tol=math.cos(3.0 * math.pi / CYLINDER_FACETS))
        )
        outline = np.concatenate([outline, rims + vx0.shape[0]])
        vx0 = np.concatenate([vx0, cv])
        verts = np.concatenate([verts, np.full(k, a)])
        vrow = np.concatenate([vrow, np.full(k, -1, np.int64)])
        vmaster = np.concatenate([vmaster, np.full(k, master_of[a])])
        vmrow = np.concatenate([vmrow, np.full(k, row, np.int64)])
        vmx0 = np.concatenate([vmx0, np.tile(model.x0[ref] if ref >= 0 else np.zeros(3), (k, 1))])
    fixed = getattr(model, "fixed", None)
    held = (
        np.all(np.asarray(fixed)[verts, :3], axis=1)
        if fixed is not None
        else np.zeros(verts.shape[0], bool)
    )
    unplaced = int(np.count_nonzero((vrow < 0) & (vmrow < 0) & ((vmaster >= 0) | ~held)))
    return Scene(
        node_ids,
        np.asarray(rows, np.int64),
        np.asarray(radius),
        np.asarray(mass),
        tri,
        vx0,
        vrow,
        vmrow,
        vmx0,
        dict(units or {}),
        str(getattr(model, "title", "")),
        outline,
        unplaced,
    )


def feature_edges(tri: np.ndarray, x: np.ndarray, cos_tol: float = 1.0 - 1e-9) -> np.ndarray:
    """Edges of the triangles ``tri`` (T, 3) on vertices ``x`` (V, 3) that are creases (their
    two triangles' normals differ) or borders (one triangle); (E, 2) vertex indices."""
    if tri.shape[0] == 0:
        return np.zeros((0, 2), np.int64)
    n = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    label = merge_vertices(x, geometry_size(x))  # coincident vertices are one
    owners: dict[tuple[int, int], list[int]] = {}
    ends: dict[tuple[int, int], tuple[int, int]] = {}
    for t, (a, b, c) in enumerate(tri):
        for e in ((a, b), (b, c), (c, a)):
            key = (min(label[e[0]], label[e[1]]), max(label[e[0]], label[e[1]]))
            owners.setdefault(key, []).append(t)
            ends.setdefault(key, e)
    out = [
        ends[k]
        for k, ts in owners.items()
        if len(ts) != 2 or abs(float(n[ts[0]] @ n[ts[1]])) < cos_tol
    ]
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)
