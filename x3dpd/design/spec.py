"""What a sweep is asked to do: parsing ``--freq``/``--amp`` and finding the driven node.

The default node and DOF of a force drive are the deck's USRFRC drive (its first
``sine``/``sweep``/... spec's ``node`` and ``dof``), else the first cavity's master node (the RBEL
master of the first CONTACT triangle's or analytic wall's first node) along x. A base drive
(``--drive base``, x3dpd.design.drive) names its base node; it measures the first cavity's
master along the same DOF unless ``--response`` says where.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

from x3dpd.api.decks import Deck
from x3dpd.design.baselines import cavity_master
from x3dpd.design.drive import parse_amplitudes
from x3dpd.design.steady_state import Criterion
from x3dpd.errors import InputError


@dataclass(frozen=True)
class AutoBand:
    """``--freq auto:LO:HI[:RES[:POINTS]]``: find the peak in [``lo``, ``hi``] Hz to ``resolution``
    Hz with at most ``max_points`` points per drive and chain (x3dpd.analysis.peak_search)."""

    lo: float
    hi: float
    resolution: float
    max_points: int = 7


@dataclass(frozen=True)
class SweepSpec:
    """What to sweep: the deck, frequencies [Hz], drive amplitudes, node, DOF, chains.

    ``quantity`` "force": ``drives`` are forces on ``node`` along ``dof``; "displacement",
    "velocity" or "acceleration": a base drive, ``node`` moved along ``dof`` with those
    amplitudes (x3dpd.design.drive)."""

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
    quantity: str = "force"
    #: ``--freq auto:...``: search the peak instead of a grid (``frequencies`` then empty)
    auto: AutoBand | None = None

    @property
    def base(self) -> bool:
        """Whether the node is moved (a base drive) rather than forced."""
        return self.quantity != "force"

    def settings(self) -> dict:
        """What makes two sweeps' points interchangeable (stored in DIR/sweep.json)."""
        out = {
            "deck_sha256": self.deck_text_hash,
            "node": self.node,
            "dof": self.dof,
            "dt": self.dt,
            "criterion": asdict(self.criterion),
        }
        if self.responses:
            out["responses"] = [list(r) for r in self.responses]
        if self.base:
            out["drive"] = "base"
            out["quantity"] = self.quantity
        if self.auto is not None:
            out["auto"] = asdict(self.auto)
        return out


def parse_auto_band(text: str) -> AutoBand | None:
    """``auto:LO:HI[:RES[:POINTS]]`` -> an AutoBand (RES default (HI - LO) / 100 Hz, POINTS
    default 7); None for any other ``--freq`` text."""
    parts = str(text).strip().split(":")
    if parts[0].strip().lower() != "auto":
        return None
    usage = (
        f"--freq {text!r}: expected auto:LO:HI[:RES[:POINTS]] (0 < LO < HI Hz; RES > 0 Hz the "
        "resolution of the peak's frequency; POINTS >= 5 the most points per drive and chain)"
    )
    try:
        lo, hi = float(parts[1]), float(parts[2])
        res = float(parts[3]) if len(parts) > 3 else (hi - lo) / 100.0
        points = int(parts[4]) if len(parts) > 4 else 7
    except (IndexError, ValueError):
        raise InputError(usage) from None
    ok = all(math.isfinite(v) for v in (lo, hi, res)) and 0 < lo < hi and res > 0
    if not ok or points < 5 or len(parts) > 5:
        raise InputError(usage)
    return AutoBand(lo, hi, res, points)


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
        raise InputError(
            f"--freq {text!r}: expected START:STOP:STEP (STEP > 0, STOP >= START)"
            " or a comma list of frequencies in Hz"
        ) from None
    if not values or any(not (v > 0 and math.isfinite(v)) for v in values):
        raise InputError(f"--freq {text!r}: frequencies must be finite and > 0 Hz")
    return tuple(sorted(set(values)))


def parse_drives(texts: Sequence[str]) -> tuple[float, ...]:
    """``--amp`` values (repeatable, each a number or a comma list), force units."""
    return parse_amplitudes(texts, "force", math.nan)[1]


def parse_point(text: str, what: str) -> tuple[int, int]:
    """``NODE:DOF`` -> (node id, dof 1..6)."""
    node, colon, dof = str(text).partition(":")
    try:
        point = int(node), int(dof)
    except ValueError:
        point = (0, 0)
    if not colon or point[1] not in range(1, 7) or point[0] < 0:
        raise InputError(f"{what} {text!r}: expected NODE:DOF (a node id and a DOF 1..6)")
    return point


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
            raise InputError(
                f"--response {text!r}: expected NODE:DOF with DOF 1, 2 or 3 (a translation)"
            )
        if pair[0] not in nodes:
            raise InputError(f"--response {text!r}: node {pair[0]} is not a node of {deck.path}")
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
    master = cavity_master(deck)
    if master is not None:
        return master, 1
    raise InputError(
        f"{deck.path}: no USRFRC drive and no cavity master node to drive; give --node N --dof D"
    )


def check_base(
    deck: Deck, node: int | None, dof: int | None, responses: tuple[tuple[int, int], ...]
) -> tuple[int, int, tuple[tuple[int, int], ...]]:
    """(node, dof, responses) of a base drive (``--drive base``), checked: the base a node of
    the deck that is neither a particle nor a rigid body's slave (its master moves it), a
    translation (DOF 1-3; default 1); without ``responses``, the first cavity's master along
    ``dof``. Raises InputError saying what is wrong."""
    if node is None:
        raise InputError(
            "--drive base: give --node N, the base node the shaker moves (and --dof D, default 1)"
        )
    dof = 1 if dof is None else dof
    if dof not in (1, 2, 3):
        raise InputError(
            f"--drive base --dof {dof}: a base drive moves a translation, dof 1, 2 or 3"
        )
    nodes = {n.nid for n in deck.nodes}
    if node not in nodes:
        raise InputError(f"--drive base --node {node}: node {node} is not a node of {deck.path}")
    if deck.pdmp and node > min(p.nodlim for p in deck.pdmp):
        raise InputError(
            f"--drive base --node {node}: node {node} is a particle; the base is a structure node"
        )
    for rb in deck.rbels:
        if node in rb.slaves:
            raise InputError(
                f"--drive base --node {node}: node {node} is a slave of rigid "
                f"body master {rb.master}, which moves it; move the master"
            )
    if not responses:
        master = cavity_master(deck)
        if master is None or master == node:
            raise InputError(
                "--drive base: give --response NODE:DOF, where to measure the transmissibility"
            )
        responses = ((master, dof),)
    return node, dof, responses


def check_node(deck: Deck, node: int, option: str = "--node") -> None:
    """InputError unless ``node`` is a node of the deck."""
    if node not in {n.nid for n in deck.nodes}:
        raise InputError(f"{option} {node}: node {node} is not a node of {deck.path}")
