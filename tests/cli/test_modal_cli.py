"""An engineer's path with a mode file: a universal file of a cantilever's modes (tests/fixtures/
modes/cantilever.uff, dataset 55), beam_64's cavity and spheres put on its tip node with a MODAL
FILE record, `x3dpd check` it, `x3dpd sweep` it with both baselines -- through the CLI."""

from __future__ import annotations

import csv
import re
import shutil
import subprocess
import sys
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]
FIXTURE = ROOT / "tests" / "fixtures" / "modes" / "cantilever.uff"


def _cantilever_deck(tmp_path: Path) -> Path:
    """decks/beam_64.inp with its spring-mounted node 9 replaced by the cantilever's tip (file
    node 6, mapped to 9): the SDOF's MATID, ELEMENTS and BOUNDARY cards dropped, its MASS (the
    SDOF's equivalent mass and App. A's 1e20 rotary inertias) replaced by the cavity's
    5.45e-6 lbf s^2/in, a MODAL card naming the file (in lbf s, as the deck), damping 0.5 %."""
    text = (ROOT / "decks" / "beam_64.inp").read_text()
    for card in ("MATID", "ELEMENTS", "BOUNDARY CONDITIONS", "MASS"):
        text = re.sub(rf"(?ms)^{card}\n.*?^END\n", "", text)
    text += "MASS\n  9 5.45e-6 0 0 0\nEND\n"
    text = re.sub(r"(?m)^USRFRC\n.*?^END\n", "", text, flags=re.S)
    shutil.copy(FIXTURE, tmp_path / "cantilever.uff")
    text += "MODAL\n  FILE cantilever.uff map=6:9 zeta=0.005\nEND\n"
    path = tmp_path / "tip.inp"
    path.write_text(text)
    return path


def _x3dpd(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "x3dpd", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=900,
    )


def test_a_mode_file_deck_checks_and_sweeps_with_closed_form_baselines(tmp_path):
    deck = _cantilever_deck(tmp_path)
    chk = _x3dpd("check", deck, cwd=tmp_path)
    assert chk.returncode == 0, chk.stdout + chk.stderr
    assert "4 modes from cantilever.uff; housing added" in chk.stdout
    assert "node 9 (rigid body master): moves in y, z, ry, rz" in chk.stdout
    assert "warning" not in chk.stdout
    out = tmp_path / "sw"
    run = _x3dpd(
        "sweep",
        deck,
        "--freq",
        "150",
        "--amp",
        "0.02",
        "--node",
        "9",
        "--dof",
        "3",
        "--baseline",
        "undamped,added-mass",
        "--max-cycles",
        "15",
        "--window",
        "5",
        "--out",
        out,
        "--workers",
        "1",
        cwd=tmp_path,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    by = {r["config"]: r for r in rows}
    assert set(by) == {"deck", "undamped", "added-mass"}
    assert by["undamped"]["method"] == by["added-mass"]["method"] == "closed-form"
    assert by["deck"]["method"] == "simulated"
    # the added-mass structure is heavier at the tip: below its resonance it moves more
    assert float(by["added-mass"]["amplitude"]) > float(by["undamped"]["amplitude"])
    assert float(by["deck"]["amplitude"]) > 0.0
    assert (out / "sweep.png").exists()


def test_check_warns_when_the_decks_mass_swamps_the_modes(tmp_path):
    """beam_64's own MASS record (Appendix A's 1e20 rotary inertias) on the tip: check says
    that the deck's mass dominates the modes, naming the node and the ratio."""
    deck = _cantilever_deck(tmp_path)
    deck.write_text(deck.read_text().replace("  9 5.45e-6 0 0 0", "  9 2.04213e-4 1e20 1e20 1e20"))
    chk = _x3dpd("check", deck, cwd=tmp_path)
    assert chk.returncode == 1
    assert "warning: the deck's mass on modal nodes outweighs the modes" in chk.stdout


def test_a_mode_file_that_is_not_what_it_claims_is_a_deck_error(tmp_path):
    deck = _cantilever_deck(tmp_path)
    (tmp_path / "cantilever.uff").write_text("this is not a universal file\n")
    res = _x3dpd("check", deck, cwd=tmp_path)
    assert res.returncode == 2
    line = res.stderr.strip().splitlines()[-1]
    assert re.search(r"tip\.inp:\d+:3: MODAL: mode file cantilever\.uff: ", line), line
    assert not (tmp_path / "tip.trace.txt").exists()
