"""100 MB of garbage fails fast, with bounded memory, and with one DeckError at its first line."""

from __future__ import annotations

import random
import time
import tracemalloc

import pytest

from x3dpd.deck import read_deck
from x3dpd.errors import DeckError

MB = 1 << 20
DECK_HEAD = b"TITLE\nsome deck\nEND\nBODY\n 0 -386.1 0\nEND\nNODE COORDINATES\n 1 0 0 0\n"


def _write(path, head: bytes, chunk: bytes, total: int = 100 * MB) -> None:
    with open(path, "wb") as f:
        f.write(head)
        f.writelines(chunk for _ in range((total - len(head)) // len(chunk)))


#: A text card (its records are words, read to its END) before the garbage: the reader's gate
#: reads such a card's lines as text. It once knew only TITLE, USRFRC, UNITS and TEMPERATURE,
#: stopped at a MODAL, PLATES or FRICTION record and read the rest of the file whole (100 MB in
#: memory) before the garbage's error.
TEXT_CARD_HEADS = {
    "MODAL": b"MODAL\n MODE 1 38.27 0.0032\n SHAPE 1 1 70.9\nEND\n",
    "FRICTION": b"FRICTION\n 1 coulomb 0.3 0.3\nEND\n",
    "TEMPERATURE": b"TEMPERATURE\n OPERATING 850F\n PARTICLES tungsten-carbide\nEND\n",
}


@pytest.mark.parametrize(
    ("kind", "line", "phrase"),
    [
        ("binary", 1, "binary"),
        ("text", 1, "unknown card keyword 'lorem'"),
        ("deck then garbage", 9, "X (field 2) must be a number"),
        ("no newline", 1, "line longer than"),
        *((f"{card} then garbage", 13, "X (field 2) must be a number") for card in TEXT_CARD_HEADS),
    ],
)
def test_100_mb_of_garbage_fails_fast(tmp_path, kind, line, phrase):
    path = tmp_path / "garbage.inp"
    if kind == "binary":
        # seeded, and opening with a byte that is never UTF-8: unseeded random bytes whose
        # first line happened to be valid text (a newline among the first few ASCII bytes,
        # about 1 run in 256) put the error on line 2
        _write(path, b"", b"\xb9" + random.Random(1).randbytes(MB - 1))
    elif kind == "text":
        _write(path, b"", b"lorem ipsum dolor sit amet, 12 34\n" * 1000)
    elif kind == "deck then garbage":
        _write(path, DECK_HEAD, b" 2 lorem ipsum dolor sit amet\n" * 1000)
    elif kind.endswith(" then garbage"):
        head = TEXT_CARD_HEADS[kind.split()[0]]
        head = head + b"\n" * (4 - head.count(b"\n"))  # every head 4 lines: the error on line 13
        _write(path, head + DECK_HEAD, b" 2 lorem ipsum dolor sit amet\n" * 1000)
    else:
        _write(path, b"", b"x" * MB)
    assert path.stat().st_size > 99 * MB
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        with pytest.raises(DeckError) as info:
            read_deck(path)
        elapsed = time.perf_counter() - t0
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert elapsed < 2.0
    assert peak < 32 * MB  # a few 1 MiB blocks, never the whole file
    assert info.value.line == line and phrase in info.value.message
