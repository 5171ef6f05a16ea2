"""What a sweep is asked to do: parsing ``--freq``/``--amp`` and finding the driven node.

The default node and DOF are the deck's USRFRC drive (its first ``sine``/``sweep``/... spec's
``node`` and ``dof``), else the first cavity's master node (the RBEL master of the first CONTACT
triangle's first node) along x.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

from x3dpd.deck.cards import Deck
from x3dpd.design.steady_state import Criterion
from x3dpd.errors import InputError


@dataclass(frozen=True)
class SweepSpec:
    """What to sweep: the deck, frequencies [Hz], drive amplitudes [force], node, DOF, chains."""

    deck: Deck
    deck_text_hash: str
    frequencies: tuple[float, ...]
    drives: tuple[float, ...]
    node: int
    dof: int
    direction: str | None = None
    baselines: tuple[str, ...] = ()
    dt: float | None = None
    criterion: Criterion = field(default_factory=Criterion)
    #: (node, dof) pairs measured besides the driven one (``--response NODE:DOF``)
    responses: tuple[tuple[int, int], ...] = ()

    def settings(self) -> dict:
        """What makes two sweeps' points interchangeable (stored in DIR/sweep.json)."""
        out = {"deck_sha256": self.deck_text_hash, "node": self.node, "dof": self.dof,
               "dt": self.dt, "criterion": asdict(self.criterion)}
        if self.responses:
            out["responses"] = [list(r) for r in self.responses]
        return out


def parse_frequencies(text: str) -> tuple[float, ...]:
    """``START:STOP:STEP`` (STOP included when on the grid) or a comma list, in Hz."""
    try:
        if ":" in text:
            start, stop, step = (float(x) for x in text.split(":"))
            if step <= 0 or stop < start:
                raise ValueError
            n = int(math.floor((stop - start) / step + 1e-9)) + 1
            values = [round(start + k * step, 12) for k in range(n)]
        else:
            values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"--freq {text!r}: expected START:STOP:STEP (STEP > 0, STOP >= START)"
                         " or a comma list of frequencies in Hz") from None
    if not values or any(not (v > 0 and math.isfinite(v)) for v in values):
        raise InputError(f"--freq {text!r}: frequencies must be finite and > 0 Hz")
    return tuple(sorted(set(values)))


def parse_drives(texts: Sequence[str]) -> tuple[float, ...]:
    """``--amp`` values (repeatable, each a number or a comma list), force units."""
    out = []
    for text in texts:
        for part in str(text).split(","):
            try:
                v = float(part.replace("d", "e").replace("D", "e"))
            except ValueError:
                raise InputError(f"--amp {text!r}: expected a drive amplitude (force), "
                                 "or a comma list of them") from None
            if not (math.isfinite(v) and v != 0):
                raise InputError(f"--amp {text!r}: a drive amplitude must be finite and not 0")
            out.append(v)
    if not out:
        raise InputError("--amp: give at least one drive amplitude")
    return tuple(dict.fromkeys(out))


def parse_responses(texts: Sequence[str], deck: Deck) -> tuple[tuple[int, int], ...]:
    """``--response NODE:DOF`` values (repeatable): nodes of the deck, translations 1-3."""
    nodes = {n.nid for n in deck.nodes}
    out = []
    for text in texts:
        node, colon, dof = str(text).partition(":")
        try:
            pair = (int(node), int(dof))
        except ValueError:
            raise InputError(f"--response {text!r}: expected NODE:DOF, e.g. 9:1") from None
        if not colon or pair[1] not in (1, 2, 3):
            raise InputError(f"--response {text!r}: expected NODE:DOF with DOF 1, 2 or 3 "
                             "(a translation)")
        if pair[0] not in nodes:
            raise InputError(f"--response {text!r}: node {pair[0]} is not a node of "
                             f"{deck.path}")
        out.append(pair)
    return tuple(dict.fromkeys(out))


def default_drive_point(deck: Deck) -> tuple[int, int]:
    """(node, dof) of the deck's USRFRC drive, else the first cavity's master along x."""
    for card in deck.usrfrc:
        for spec in card.specs:
            node = re.search(r"\bnode\s*=\s*(\d+)", spec, re.I)
            dof = re.search(r"\bdof\s*=\s*(\d+)", spec, re.I)
            if node and dof:
                return int(node.group(1)), int(dof.group(1))
    for contact in deck.contacts:
        for tri in contact.triangles:
            for rb in deck.rbels:
                if tri.nodes[0] in rb.slaves or tri.nodes[0] == rb.master:
                    return rb.master, 1
    raise InputError(f"{deck.path}: no USRFRC drive and no cavity master node to drive; "
                     "give --node N --dof D")

