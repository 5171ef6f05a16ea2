"""The benchmark's multiple individual particle (MIP) scene: decks/mip_apparatus_05.inp with
``n`` holes (four plates of n/4, the deck's 0.5 in SS-302 spheres, HOOKE contact, pitch and
free lengths), driven at 800 lbf and 128 Hz (Figure 72's level at its peak), the spheres in
flight after ``SETTLE`` s. ``n = 884`` is the deck itself at that drive.

    python tools/bench/count_instructions.py --prepare mip_884      # once per count (native)
    valgrind ... python tools/bench/count_instructions.py mip_884 1000
    python tools/bench/mip_scaling.py                               # the table for 100..4000
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from x3dpd.deck.parser import parse_deck
from x3dpd.model.build import build_model

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "mip_apparatus_05.inp"
DRIVE = "sine:node=1,dof=2,amp=800.0,hz=128.0"
#: simulated seconds before a count: 0.15 s is 4 time constants 1/(zeta omega) of the
#: apparatus (zeta 0.047 at 132 Hz): the response has built up, the spheres fly
SETTLE = 0.15
HOLE_COUNTS = (100, 250, 500, 884, 1000, 2000, 4000)


def mip_deck_text(n: int) -> str:
    """decks/mip_apparatus_05.inp with n holes (n/4 per plate, rounded up; plates as large as
    the grid needs), the 800 lbf drive, node 1 traced."""
    text = DECK.read_text()
    per = math.ceil(n / 4)
    cols = math.ceil(math.sqrt(per))
    size = cols * 0.6 + 1.0
    text = re.sub(r"holes=\d+", f"holes={per}", text)
    text = re.sub(r"size=[\d.,]+", f"size={size!r}", text)
    text = re.sub(r"\nTRACE\n[^E]*END", "\nTRACE\n   1\nEND", text)  # the spheres' ids move
    return re.sub(r"sine:node=1,dof=2,amp=[^\n]*", DRIVE, text)


def mip_model(n: int):
    """The scene's Model."""
    return build_model(parse_deck(mip_deck_text(n), f"<mip_{n}>"))
