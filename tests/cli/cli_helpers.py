"""Helpers of the post-processing command tests: the shipped decks and an in-process CLI call."""

from __future__ import annotations

from pathlib import Path

from x3dpd.cli import main

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks"
#: Every shipped deck but appendix_a.inp (its printed geometry is refused: nothing to draw) and
#: hooke_wall.inp (impact_wall's picture with another contact law), with a run short enough
#: for a test: TMAX [s] (a few output times each).
SHORT_RUNS = {
    "appendix_a_cube.inp": 0.003,
    "beam_1.inp": 0.003,
    "beam_64.inp": 0.003,
    "beam_512.inp": 0.002,
    "cylinder_64.inp": 0.003,
    "capsule_64.inp": 0.003,
    "impact_wall.inp": 2e-7,  # ITRAC 10 x 1e-9 s: 21 output times
}


def with_card(text: str, card: str) -> str:
    """Deck ``text`` with its card named by ``card``'s first line (CYLINDER ...) replaced by
    ``card`` (keyword, records, END)."""
    start = text.index(f"\n{card.split()[0]}\n") + 1
    end = text.index("END", start) + 3
    return text[:start] + card + text[end:]


def first_record_line(text: str, keyword: str) -> int:
    """Line number of the first record of card ``keyword`` (right after its keyword and a
    header comment line, as the deck writer puts them)."""
    return text[: text.index(f"\n{keyword}\n")].count("\n") + 3


def run_cli(*args) -> int:
    """``x3dpd ARGS`` in this process; its exit status."""
    try:
        main([str(a) for a in args])
    except SystemExit as exc:
        return int(exc.code or 0)
    return 0


def folder_state(folder: Path) -> dict[str, tuple[int, bytes]]:
    """Every file and folder under ``folder`` with its mtime and bytes (folders: b"/"), for
    a test that something wrote nothing and overwrote nothing."""
    folder = Path(folder)
    if not folder.exists():
        return {}
    return {
        str(p.relative_to(folder)): (p.stat().st_mtime_ns, b"/" if p.is_dir() else p.read_bytes())
        for p in sorted(folder.rglob("*"))
    }


def refused(capsys, *args, message: str, folder: Path | None = None, silent: bool = False) -> str:
    """``x3dpd ARGS`` is refused as bad input: exit status 2, one line on stderr holding
    ``message``, no traceback, and nothing under ``folder`` written or changed (``silent``:
    nothing printed on stdout either, the input refused before any work). Returns the line."""
    capsys.readouterr()
    before = folder_state(folder) if folder is not None else None
    status = run_cli(*args)
    out, err = capsys.readouterr()
    assert status == 2, err
    assert not (silent and out), out
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert message in lines[0], lines[0]
    if folder is not None:
        assert folder_state(folder) == before
    return lines[0]
