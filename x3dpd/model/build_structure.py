"""Model builder steps for the structure: lumped masses, spring-damper elements, boundary
conditions and rigid bodies (RBEL)."""

from __future__ import annotations

import numpy as np

from x3dpd.errors import Pos
from x3dpd.model.build_base import _ALL_DOFS, BuilderBase, _pos_at

#: MATID types: 1 as X3D's (axis-aligned), 2 and 3 our extensions (docs/deck-reference.md).
AXIS_ALIGNED, AXIAL, ROTATIONAL = 1, 2, 3
MATERIAL_TYPES = {
    AXIS_ALIGNED: "spring-damper along the global x, y, z axes",
    AXIAL: "spring-damper along the line between two nodes",
    ROTATIONAL: "rotational spring-damper about the global axes",
}


class StructureSteps(BuilderBase):
    """Masses, springs, fixed DOFs and rigid bodies of the structural nodes."""

    def _masses(self) -> None:
        for rec in self.deck.masses:
            i = self.structural(rec.nid, rec.pos, "MASS", "node")
            for name, value in (
                ("mass", rec.mass),
                ("Ixx", rec.ixx),
                ("Iyy", rec.iyy),
                ("Izz", rec.izz),
            ):
                if value < 0.0:
                    raise self.error(
                        f"negative {name} {value:g} for node {rec.nid}", rec.pos, "MASS"
                    )
            self.mass[i] += rec.mass
            self.inertia[i] += (rec.ixx, rec.iyy, rec.izz)

    # Over 80 lines: the three spring types read in one pass over MATID and ELEMENTS.
    def _springs(self) -> None:
        """MATID + ELEMENTS: the axis-aligned spring-dampers of type 1 (X3D's), the axial ones
        of type 2 and the rotational ones of type 3 (our extensions), each in arrays of its own."""
        materials: dict[int, object] = {}
        for mat in self.deck.materials:
            if mat.mid in materials:
                raise self.error(
                    f"material {mat.mid} is defined twice (first at line "
                    f"{materials[mat.mid].pos.line})",
                    mat.pos,
                    "MATID",
                )
            if mat.mtype not in MATERIAL_TYPES:
                kinds = "; ".join(f"{t} = {what}" for t, what in MATERIAL_TYPES.items())
                raise self.error(
                    f"material {mat.mid} has type {mat.mtype}; the types are {kinds}",
                    mat.pos,
                    "MATID",
                )
            if mat.mass < 0.0:
                raise self.error(
                    f"negative element mass {mat.mass:g} in material {mat.mid}", mat.pos, "MATID"
                )
            if mat.mtype == AXIAL and (mat.ky != 0.0 or mat.kz != 0.0):
                raise self.error(
                    f"material {mat.mid} is of type 2 (a spring along the line "
                    f"between two nodes), whose stiffness is KX alone; KY and KZ "
                    f"must be 0, got {mat.ky:g} and {mat.kz:g}",
                    mat.pos,
                    "MATID",
                )
            materials[mat.mid] = mat
        seen: dict[int, Pos] = {}
        axis = ([], [], [], [])  # type 1: elements, nodes, k (3), c (3)
        axial = ([], [], [], [], [])  # type 2: elements, nodes, k, c, rest length
        rotational = ([], [], [], [])  # type 3: elements, nodes, k (3), c (3)
        for el in self.deck.elements:
            if el.eid in seen:
                raise self.error(
                    f"element {el.eid} is defined twice (first at line {seen[el.eid].line})",
                    el.pos,
                    "ELEMENTS",
                )
            seen[el.eid] = el.pos
            mat = materials.get(el.mid)
            if mat is None:
                raise self.error(
                    f"element {el.eid} uses material {el.mid}, which no MATID record defines",
                    el.pos,
                    "ELEMENTS",
                )
            if len(el.nodes) not in (1, 2) or len(set(el.nodes)) != len(el.nodes):
                raise self.error(
                    f"element {el.eid} must join one node to ground or two "
                    f"distinct nodes, got {list(el.nodes)}",
                    el.pos,
                    "ELEMENTS",
                )
            idx = [
                self.structural(nid, el.pos, "ELEMENTS", f"element {el.eid} node")
                for nid in el.nodes
            ]
            for i in idx:  # lumped equally on both ends; a ground end's share is dropped
                self.mass[i] += 0.5 * mat.mass
            pair = idx + [-1] * (2 - len(idx))
            if mat.mtype == AXIAL:
                axial[0].append(el)
                axial[1].append(pair)
                axial[2].append(mat.scale * mat.kx)
                axial[3].append(mat.scale * mat.c)
                axial[4].append(self._rest_length(el, mat, idx))
                continue
            out = rotational if mat.mtype == ROTATIONAL else axis
            out[0].append(el)
            out[1].append(pair)
            out[2].append([mat.scale * mat.kx, mat.scale * mat.ky, mat.scale * mat.kz])
            out[3].append([mat.scale * mat.c] * 3)
        self.spring_elements = tuple(axis[0])
        self.spring_nodes = np.array(axis[1], dtype=np.int64).reshape(-1, 2)
        self.spring_k = np.array(axis[2], dtype=np.float64).reshape(-1, 3)
        self.spring_c = np.array(axis[3], dtype=np.float64).reshape(-1, 3)
        self.axial_elements = tuple(axial[0])
        self.axial_nodes = np.array(axial[1], dtype=np.int64).reshape(-1, 2)
        self.axial_k = np.array(axial[2], dtype=np.float64)
        self.axial_c = np.array(axial[3], dtype=np.float64)
        self.axial_length = np.array(axial[4], dtype=np.float64)
        self.rotational_elements = tuple(rotational[0])
        self.rotational_nodes = np.array(rotational[1], dtype=np.int64).reshape(-1, 2)
        self.rotational_k = np.array(rotational[2], dtype=np.float64).reshape(-1, 3)
        self.rotational_c = np.array(rotational[3], dtype=np.float64).reshape(-1, 3)

    def _rest_length(self, el, mat, idx: list[int]) -> float:
        """L0 of a type 2 element: the distance of its two nodes in the deck (> 0)."""
        if len(idx) != 2:
            raise self.error(
                f"element {el.eid} uses material {mat.mid} of type 2, a spring "
                f"along the line between two nodes, but has one node (a spring "
                f"to ground has no line); give NODE2, or use a type 1 material "
                f"for a spring to ground along the global axes",
                el.pos,
                "ELEMENTS",
            )
        length = float(np.linalg.norm(self.x0[idx[1]] - self.x0[idx[0]]))
        if not length > 0.0:
            a, b = el.nodes
            raise self.error(
                f"element {el.eid} uses material {mat.mid} of type 2, a spring "
                f"along the line between its nodes, but nodes {a} and {b} have "
                f"the same coordinates (lines {self.node_pos[a].line} and "
                f"{self.node_pos[b].line}): the line is undefined; move one "
                f"node, or use a type 1 material (axis-aligned)",
                el.pos,
                "ELEMENTS",
            )
        return length

    def _boundaries(self) -> np.ndarray:
        fixed = np.zeros((self.ids.shape[0], 6), dtype=bool)
        for rec in self.deck.boundaries:
            card = "BOUNDARY CONDITIONS"
            self.node(rec.first, rec.pos, card, "first node")
            self.node(rec.last, rec.pos, card, "last node")
            if rec.inc <= 0 or rec.last < rec.first:
                raise self.error(
                    f"node range {rec.first}..{rec.last} step {rec.inc} is empty; "
                    f"the increment must be > 0 and the last node >= the first",
                    rec.pos,
                    card,
                )
            bad = [d for d in rec.dofs if d not in _ALL_DOFS]
            if bad:
                raise self.error(
                    f"DOF {bad[0]} is not one of 1..6 (x, y, z, rx, ry, rz)", rec.pos, card
                )
            cols = [d - 1 for d in rec.dofs]
            for nid in range(rec.first, rec.last + 1, rec.inc):
                i = self.index.get(nid)
                if i is not None:
                    fixed[i, cols] = True
        return fixed

    def _rigid_bodies(self) -> None:
        owner: dict[int, tuple[int, Pos]] = {}  # node index -> (master id, line of its RBEL)
        masters, ptr, slaves = [], [0], []
        for rb in self.deck.rbels:
            if sorted(rb.dofs) != list(_ALL_DOFS):
                code = "".join(str(d) for d in rb.dofs)
                raise self.error(
                    f"DOF code {code}: only 123456 (all six DOFs rigidly linked) is supported",
                    rb.pos,
                    "RBEL",
                )
            m = self.structural(rb.master, rb.pos, "RBEL", "master node")
            if m in owner:
                raise self.error(
                    f"master node {rb.master} already belongs to the rigid body of "
                    f"master {owner[m][0]} (line {owner[m][1].line}); a node may "
                    f"be in one rigid body only",
                    rb.pos,
                    "RBEL",
                )
            owner[m] = (rb.master, rb.pos)
            body = []
            for k, nid in enumerate(rb.slaves):
                pos = _pos_at(rb.slave_positions, k, rb.pos)
                s = self.structural(nid, pos, "RBEL", "slave node")
                if s in owner:
                    raise self.error(
                        f"slave node {nid} already belongs to the rigid body of "
                        f"master {owner[s][0]} (line {owner[s][1].line}); a node "
                        f"may be in one rigid body only",
                        pos,
                        "RBEL",
                    )
                owner[s] = (rb.master, rb.pos)
                body.append(s)
            masters.append(m)
            slaves.extend(body)
            ptr.append(len(slaves))
        self.rigid_master = np.array(masters, dtype=np.int64)
        self.rigid_ptr = np.array(ptr, dtype=np.int64)
        self.rigid_slaves = np.array(slaves, dtype=np.int64)
        b = len(masters)
        self.rigid_mass = np.zeros(b)
        self.rigid_inertia = np.zeros((b, 3, 3))
        for k, m in enumerate(masters):
            sl = self.rigid_slaves[ptr[k] : ptr[k + 1]]
            r = self.x0[sl] - self.x0[m]
            ms = self.mass[sl]
            self.rigid_mass[k] = self.mass[m] + ms.sum()
            # Parallel-axis theorem about the master's initial position:
            # J = diag(I_m) + sum_s [diag(I_s) + m_s (|r_s|^2 1 - r_s r_s^T)].
            j = np.diag(self.inertia[m] + self.inertia[sl].sum(axis=0))
            j += np.einsum("s,s->", ms, np.einsum("sk,sk->s", r, r)) * np.eye(3)
            j -= np.einsum("s,si,sj->ij", ms, r, r)
            self.rigid_inertia[k] = j
        self.slave_of = {int(s): k for k in range(b) for s in slaves[ptr[k] : ptr[k + 1]]}
        self.body_of_master = {int(m): k for k, m in enumerate(masters)}
