"""Model builder steps for the cavities: CONTACT triangles and slave sets, analytic walls.

Wall orientation comes from geometry, never from the winding of the triangles: each triangle's
inward side is the side facing the centroid of its cavity's triangle nodes (the "master nodes").
The report's Appendix A winds some cavity triangles one way and some the other.
"""

from __future__ import annotations

import numpy as np

from x3dpd.errors import Pos
from x3dpd.geometry.cavity import geometry_size, group_faces
from x3dpd.geometry.shapes import MAX_SHAPE_NODES, MAX_SHAPE_PARAMS, SHAPES, kind_of
from x3dpd.geometry.triangle import PLANE_TOL, inward_signs, triangle_areas, unit_normals
from x3dpd.model.build_base import BuilderBase, _pos_at


class WallSteps(BuilderBase):
    """The cavities' walls: triangles, their inward sides and faces, analytic walls, slave sets."""

    # Over 80 lines: every wall kind's arrays built in one pass over the wall cards.
    def _walls(self) -> None:
        tris = [t for c in self.deck.contacts for t in c.triangles]
        sets = [s for c in self.deck.contacts for s in c.slaves]
        idx = np.array(
            [
                [self.structural(nid, t.pos, "CONTACT", "triangle node") for nid in t.nodes]
                for t in tris
            ],
            dtype=np.int64,
        ).reshape(-1, 3)
        p0, p1, p2 = (self.x0[idx[:, k]] for k in range(3))
        area = triangle_areas(p0, p1, p2)
        longest = np.max(
            np.stack(
                [
                    np.linalg.norm(p1 - p0, axis=1),
                    np.linalg.norm(p2 - p1, axis=1),
                    np.linalg.norm(p0 - p2, axis=1),
                ]
            ),
            axis=0,
            initial=0.0,
        )
        for k, t in enumerate(tris):
            if not area[k] > PLANE_TOL * longest[k] ** 2:
                raise self.error(
                    f"triangle {k + 1} (nodes {' '.join(map(str, t.nodes))}) is "
                    f"degenerate: area {area[k]:.6g}",
                    t.pos,
                    "CONTACT",
                )
        set_ids = sorted(
            {t.set_id for t in tris} | {w.set_id for w in self.deck.analytic_walls or ()}
        )
        cav_of_set = {s: c for c, s in enumerate(set_ids)}
        pcav = np.full(self.ids.shape[0] - self.pstart, -1, dtype=np.int64)
        where: dict[int, Pos] = {}
        for ss in sets:
            if ss.set_id not in cav_of_set:
                raise self.error(
                    f"slave set {ss.set_id} has no master triangles and no "
                    f"{' or '.join(s.card for s in SHAPES)} (the CONTACT triangles "
                    f"and analytic walls use set ids "
                    f"{', '.join(map(str, set_ids)) or 'none'})",
                    ss.pos,
                    "CONTACT",
                )
            for k, nid in enumerate(ss.nodes):
                pos = _pos_at(ss.positions, k, ss.pos)
                i = self.node(nid, pos, "CONTACT", "slave node")
                if i < self.pstart:
                    raise self.error(
                        f"slave node {nid} is not a particle (particles are the "
                        f"nodes above PDMP NODLIM {self.nodlim})",
                        pos,
                        "CONTACT",
                    )
                if i in where:
                    raise self.error(
                        f"particle {nid} is already a slave of another set (line "
                        f"{where[i].line}); a particle belongs to one cavity",
                        pos,
                        "CONTACT",
                    )
                where[i] = pos
                pcav[i - self.pstart] = cav_of_set[ss.set_id]
        sign = np.zeros(len(tris))
        face = np.zeros(len(tris), dtype=np.int64)
        face_cavity: list[int] = []
        n_hat = unit_normals(p0, p1, p2)
        for c, sid in enumerate(set_ids):
            mine = np.array([k for k, t in enumerate(tris) if t.set_id == sid], dtype=np.int64)
            if mine.size == 0:  # a cavity of analytic walls only
                continue
            corners = np.unique(idx[mine].reshape(-1))
            s = inward_signs(p0[mine], p1[mine], p2[mine], self.x0[corners].mean(axis=0))
            if np.any(s == 0.0):  # e.g. a flat floor: the master nodes' centroid is in its plane
                own = self.pstart + np.flatnonzero(pcav == c)
                if own.size:
                    ref = self.x0[own].mean(axis=0)
                    s = np.where(s == 0.0, inward_signs(p0[mine], p1[mine], p2[mine], ref), s)
            if np.any(s == 0.0):
                k = int(mine[np.flatnonzero(s == 0.0)[0]])
                raise self.error(
                    f"cannot tell the inside of triangle {k + 1} (nodes "
                    f"{' '.join(map(str, tris[k].nodes))}): the centroid of cavity {sid}'s "
                    f"triangle nodes and of its particles lie in the triangle's plane",
                    tris[k].pos,
                    "CONTACT",
                )
            sign[mine] = s
            local = group_faces(s[:, None] * n_hat[mine], p0[mine], geometry_size(self.x0[corners]))
            face[mine] = len(face_cavity) + local
            face_cavity.extend([c] * (int(local.max()) + 1))
        self.triangles = tris
        self.tri_nodes = idx
        self.tri_sign = sign
        self.tri_face = face
        self.face_cavity = np.array(face_cavity, dtype=np.int64)
        self.cavity_set_ids = np.array(set_ids, dtype=np.int64)
        self.particle_cavity = pcav
        self._analytic_walls(cav_of_set)
        self._cell_walls()
        self.cav_of_set = cav_of_set

    def _wall_materials(self) -> np.ndarray | None:
        """The WALLMAT card (our extension; x3dpd.physics.wall_material): (C, 3) E, NU, MU per
        cavity (E = inf, MU = nan: rigid, the particles' PCOF), or None without the card."""
        records = self.deck.wallmat
        if not records:
            return None
        selected = self._card_law()
        if selected is not None and selected[1].WALL_STIFFNESS:
            card = selected[1].CARD
            raise self.error(
                f"the {card} law gives its wall stiffness {selected[1].WALL_STIFFNESS} "
                f"directly, so a wall material has nothing to act on; remove WALLMAT or the "
                f"{card} card (WALLMAT applies to the Hertz law of PDMP)",
                records[0].pos,
                "WALLMAT",
            )
        table = np.tile([np.inf, 0.0, np.nan], (len(self.cav_of_set), 1))
        given: dict[int, Pos] = {}
        for r in records:
            if r.set_id not in self.cav_of_set:
                raise self.error(
                    f"set {r.set_id} has no walls (the CONTACT triangles and "
                    f"analytic walls use set ids "
                    f"{', '.join(map(str, sorted(self.cav_of_set))) or 'none'})",
                    r.pos,
                    "WALLMAT",
                )
            if r.set_id in given:
                raise self.error(
                    f"set {r.set_id} is given twice (first at line {given[r.set_id].line})",
                    r.pos,
                    "WALLMAT",
                )
            given[r.set_id] = r.pos
            table[self.cav_of_set[r.set_id]] = r.e, r.nu, r.mu
        table.flags.writeable = False
        return table

    def _analytic_walls(self, cav_of_set: dict[int, int]) -> None:
        """The analytic wall cards (our extension: CYLINDER, CAPSULE ...; x3dpd.geometry.shapes).
        A shape's nodes must move rigidly together (one rigid body, or all fixed), so that the
        reaction and the wall's velocity formed from them are exact."""
        kinds, nodes, params, cavity = [], [], [], []
        for w in self.deck.analytic_walls or ():
            kind = kind_of(w.shape)
            shape = SHAPES[kind]
            ends = [
                self.structural(nid, _pos_at(w.positions, k, w.pos), shape.card, what)
                for k, (nid, what) in enumerate(zip(w.nodes, shape.node_words))
            ]
            ids = " and ".join(map(str, w.nodes))
            bodies = [self.slave_of.get(i, self.body_of_master.get(i)) for i in ends]
            fixed = all(self.fixed[i].all() for i in ends)
            if len(ends) > 1 and not fixed and (bodies[0] is None or len(set(bodies)) > 1):
                raise self.error(
                    f"{shape.nodes_word} {ids} must move as one rigid cavity: "
                    f"make them RBEL slaves (or the master) of one rigid body, or "
                    f"fix all their DOFs",
                    w.pos,
                    shape.card,
                )
            problem = shape.problem(self.x0[ends], np.asarray(w.params, float))
            if problem is not None:
                raise self.error(f"{shape.nodes_word} {ids} {problem}", w.pos, shape.card)
            kinds.append(kind)
            nodes.append((ends + ends)[:MAX_SHAPE_NODES])
            row = list(w.params)
            if shape.constants is not None:  # fixed for a wall that never turns (_cell_walls)
                row += list(shape.constants(self.x0[ends], np.asarray(w.params, float)))
            params.append(row + [0.0] * (MAX_SHAPE_PARAMS - len(row)))
            cavity.append(cav_of_set[w.set_id])
        self.shape_kind = np.array(kinds, dtype=np.int64)
        self.shape_nodes = np.array(nodes, dtype=np.int64).reshape(-1, MAX_SHAPE_NODES)
        self.shape_params = np.array(params, dtype=np.float64).reshape(-1, MAX_SHAPE_PARAMS)
        self.shape_cavity = np.array(cavity, dtype=np.int64)

    def _cell_walls(self) -> None:
        """Walls whose particles sit alone in cells (a drilled plate's holes, ``Shape.cells``):
        the wall alone in its set (a particle would be located in every such wall of its set),
        one particle per cell, on a body that cannot turn (the cells' pattern follows the axis
        A -> B, not a turn about it)."""
        walls = self.deck.analytic_walls or ()
        tri_sets = {t.set_id for c in self.deck.contacts for t in c.triangles}
        for k, w in enumerate(walls):
            shape = SHAPES[int(self.shape_kind[k])]
            if shape.cells is None and shape.constants is None:
                continue
            c = int(self.shape_cavity[k])
            others = int(np.count_nonzero(self.shape_cavity == c)) - 1
            if others or w.set_id in tri_sets:
                raise self.error(
                    f"set {w.set_id} holds other walls besides this {shape.card} record: "
                    f"give each {shape.card} record a CONTACT set of its own",
                    w.pos,
                    shape.card,
                )
            ends = self.shape_nodes[k, : len(shape.node_fields)]
            for i in ends:
                body = self.slave_of.get(int(i), self.body_of_master.get(int(i)))
                master = int(i) if body is None else int(self.rigid_master[body])
                if master in self.modal_nodes or not self.fixed[master, 3:].all():
                    raise self.error(
                        f"node {int(self.ids[i])} can turn (its rigid body's master "
                        f"{int(self.ids[master])} has a free or modal rotation): the "
                        f"{shape.name}' pattern does not follow a turn; fix the master's "
                        "rotations (BOUNDARY DOFs 4 5 6)",
                        w.pos,
                        shape.card,
                    )
            mine = np.flatnonzero(self.particle_cavity == c)
            if shape.cells is None or mine.size < 2:
                continue
            cells = shape.cells(self.x0[self.pstart + mine], self.x0[ends], self.shape_params[k])
            _, first, count = np.unique(cells, axis=0, return_index=True, return_counts=True)
            if np.any(count > 1):
                twice = cells[first[np.argmax(count > 1)]]
                same = mine[np.all(cells == twice, axis=1)]
                ids = " and ".join(str(int(self.ids[self.pstart + p])) for p in same[:2])
                raise self.error(
                    f"particles {ids} are in the same hole of set {w.set_id} (one particle "
                    "per cell: they would pass through each other)",
                    w.pos,
                    shape.card,
                )
