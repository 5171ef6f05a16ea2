"""Model builder steps for the loads: USRFRC force specs and the check that every loaded,
free DOF has mass."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from x3dpd.errors import UsrfrcError
from x3dpd.model.build_base import _AXES, BuilderBase
from x3dpd.physics.motion import motion_table, prescribed_mask
from x3dpd.physics.usrfrc import force_table, is_user_file, split_specs


class LoadSteps(BuilderBase):
    """External forces (USRFRC, ``--usrfrc``) and the zero-mass check of loaded DOFs."""

    def _zero_mass_check(self) -> None:
        """A free, loaded translational DOF needs mass (explicit time integration divides by it)."""
        loads: dict[tuple[int, int], str] = {}
        for el, nodes, k, c in zip(
            self.spring_elements, self.spring_nodes, self.spring_k, self.spring_c
        ):
            for i in nodes[nodes >= 0]:
                for a in range(3):
                    if k[a] != 0.0 or c[a] != 0.0:
                        loads.setdefault((int(i), a), f"element {el.eid} (line {el.pos.line})")
        for el, nodes, k, c in zip(
            self.axial_elements, self.axial_nodes, self.axial_k, self.axial_c
        ):
            if k != 0.0 or c != 0.0:  # along its line, which may turn to any direction
                for i in nodes:
                    for a in range(3):
                        loads.setdefault((int(i), a), f"element {el.eid} (line {el.pos.line})")
        for t, nodes in zip(self.triangles, self.tri_nodes):
            for i in nodes:
                for a in range(3):
                    loads.setdefault(
                        (int(i), a),
                        f"the wall contact of the CONTACT triangle at line {t.pos.line}",
                    )
        for spec, (i, a) in self._external_loads():
            if a < 3:
                loads.setdefault((i, a), f"the USRFRC force {spec!r}")
        prescribed = np.zeros((len(self.ids), 6), dtype=bool)
        if self.motion:
            prescribed = prescribed_mask(
                motion_table(self.motion, self.ids, self.x0), len(self.ids)
            )
        for (i, a), what in sorted(loads.items()):
            if i >= self.pstart or prescribed[i, a]:
                continue
            body = self.slave_of.get(i, self.body_of_master.get(i))
            master = i if body is None else int(self.rigid_master[body])
            if master in self.modal_nodes:
                continue  # moved by the modes, whose mass is in them
            if body is None:
                if self.fixed[i, a] or self.mass[i] > 0.0:
                    continue
                nid = int(self.ids[i])
                raise self.error(
                    f"node {nid} has no mass but its free {_AXES[a]} DOF is loaded by {what}; add "
                    f"a MASS record for node {nid}, fix DOF {a + 1} in BOUNDARY CONDITIONS, or "
                    f"make the node a slave of a rigid body (RBEL)",
                    self.node_pos[nid],
                    "NODE COORDINATES",
                )
            m = int(self.rigid_master[body])
            if self.fixed[m, a] or self.rigid_mass[body] > 0.0:
                continue
            nid, mid = int(self.ids[i]), int(self.ids[m])
            raise self.error(
                f"the rigid body of master {mid} has no mass but its free {_AXES[a]} DOF is "
                f"loaded by {what} (on node {nid}); add a MASS record for node {mid} or fix "
                f"DOF {a + 1} of node {mid} in BOUNDARY CONDITIONS",
                self.node_pos[mid],
                "NODE COORDINATES",
            )
        self._zero_inertia_check()

    def _zero_inertia_check(self) -> None:
        """A free rotational DOF loaded by a rotational spring-damper (MATID type 3) needs a
        rotary inertia: without one its moment would be dropped."""
        for el, nodes, k, c in zip(
            self.rotational_elements, self.rotational_nodes, self.rotational_k, self.rotational_c
        ):
            for i in nodes[nodes >= 0]:
                for a in range(3):
                    if k[a] == 0.0 and c[a] == 0.0:
                        continue
                    body = self.slave_of.get(int(i), self.body_of_master.get(int(i)))
                    m = int(i) if body is None else int(self.rigid_master[body])
                    if m in self.modal_nodes:
                        continue  # turned by the modes, whose inertia is in them
                    inertia = self.inertia[m, a] if body is None else self.rigid_inertia[body, a, a]
                    if self.fixed[m, 3 + a] or inertia > 0.0:
                        continue
                    nid = int(self.ids[m])
                    owner = f"node {nid}" if body is None else f"the rigid body of master {nid}"
                    raise self.error(
                        f"{owner} has no rotary inertia about {_AXES[a]} but its free r{_AXES[a]} "
                        f"DOF is loaded by the rotational spring-damper element {el.eid} (line "
                        f"{el.pos.line}); give node {nid} an inertia I{_AXES[a] * 2} in MASS or "
                        f"fix DOF {a + 4} in BOUNDARY CONDITIONS",
                        self.node_pos[nid],
                        "NODE COORDINATES",
                    )

    def _all_usrfrc(self) -> tuple[str, ...]:
        return self._deck_usrfrc() + self.usrfrc

    def _deck_usrfrc(self) -> tuple[str, ...]:
        """The USRFRC card's specs, user force files resolved against the deck's folder.

        A deck and its force file travel together, so ``force.py`` on the card means the file
        beside the deck, whatever the working directory (``--usrfrc`` paths on the command line
        stay relative to the working directory, as shells expect). A missing file is an error at
        the card.
        """
        folder = self._deck_folder()
        out = []
        for card in self.deck.usrfrc:
            for spec in card.specs:
                if is_user_file(spec, folder):
                    path = Path(spec.strip())
                    if folder is not None and not path.is_absolute():
                        path = folder / path
                    if not path.is_file():
                        raise self.error(
                            f"user force file {spec.strip()!r} not found (looked for {path})",
                            card.pos,
                            "USRFRC",
                        )
                    spec = str(path)
                out.append(spec)
        return tuple(out)

    def _deck_folder(self) -> Path | None:
        """The folder the deck's USRFRC files are taken from (None: a deck without a file)."""
        known = self.deck.path not in ("<deck>", "<string>", "-")
        return Path(self.deck.path).parent if known else None

    def _external_loads(self) -> list[tuple[str, tuple[int, int]]]:
        """(spec, (node index, DOF column)) of every built-in force law (user files: unknown).

        A bad spec on the deck's USRFRC card is a DeckError at the card; a bad ``--usrfrc`` spec
        raises :class:`UsrfrcError`.
        """
        out = []
        for card in self.deck.usrfrc:
            builtin, _ = split_specs(card.specs, self._deck_folder())
            if not builtin:
                continue
            try:
                table = force_table(builtin, self.ids)
            except UsrfrcError as exc:
                raise self.error(str(exc), card.pos, "USRFRC") from None
            out += [(s, (int(r[1]), int(r[2]))) for s, r in zip(builtin, table)]
        builtin, _ = split_specs(self.usrfrc)
        if builtin:
            table = force_table(builtin, self.ids)
            out += [(s, (int(r[1]), int(r[2]))) for s, r in zip(builtin, table)]
        return out
