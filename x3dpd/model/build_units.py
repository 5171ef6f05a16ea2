"""Model builder step for the effect units' own cards (x3dpd.physics.effect_units): each
unit's records, their node ids turned into node indices, built into the unit's arrays by the
unit's ``build`` (``Model.unit_data``), and the unit's effect named when its card has records.
Every message is a DeckError at the record (``FILE:LINE:COL: CARD: message``)."""

from __future__ import annotations

from x3dpd.model.build_base import BuilderBase, _pos_at
from x3dpd.physics.effect_units import UNITS


class UnitSteps(BuilderBase):
    """The effect units' own cards."""

    def _unit_data(self) -> dict:
        """Unit name -> its arrays (its ``build`` of its card's records), for every unit whose
        card the deck has; sets ``self.unit_effects``."""
        out: dict = {}
        self.unit_effects: set[str] = set()
        for unit in UNITS:
            records = [r for r in self.deck.unit_records or () if r.unit == unit.name]
            if unit.card is None or not records:
                continue
            card = unit.card
            rows = []
            for r in records:
                row = {}
                for k, (name, value) in enumerate(zip(card.fields, r.values)):
                    if name in card.node_fields:
                        value = self.node(
                            int(value),
                            _pos_at(r.positions, k, r.pos),
                            card.name,
                            f"{name} (field {k + 1}): node",
                        )
                    row[name] = value
                rows.append(row)

            def fail(k: int, message: str, _records=records, _card=card.name):
                return self.error(message, _records[k].pos, _card)

            out[unit.name] = unit.build(rows, fail)
            self.unit_effects.add(unit.effects[0])
        return out
