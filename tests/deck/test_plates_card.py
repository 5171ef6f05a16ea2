"""The PLATES card (x3dpd.deck.plates_card, x3dpd.deck.plates): drilled plates built into the
deck's cards, the numbering docs/deck-reference.md gives, the writer's round trip, and bad
input as one line ``FILE:LINE:COL: PLATES: message`` (exit 2 from the CLI, nothing written)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from x3dpd.cli import main
from x3dpd.deck import format_deck, parse_deck, read_deck
from x3dpd.deck.plates import expand_plates, plated_deck, plates_from_specs, sphere_ids
from x3dpd.errors import DeckError, InputError

STRUCTURE = """$ a 350 lb SDOF along y
PARAMETERS
   0.0 0.001 0.0 1e-06 1e-06 0 1e9 0 5 0 100
END
MATID
   2 1 1e-12 1.0 1e12 625000.0 1e12 113.0
END
PDMP
   3 0.25 7.485e-4 0.29 2.8e7 0.0 1.0 0.42 0.0 0.0 0.0
END
HOOKE
   3 1.0e6 0.6
END
BODY
   0.0 -386.1 0.0
END
NODE COORDINATES
   1 0.0 0.0 0.0
   2 0.0 -1.0 0.0
   3 1.0 -1.0 0.0
END
ELEMENTS
   1 2 1
END
MASS
   1 0.9065 1e20 1e20 1e20
END
BOUNDARY CONDITIONS
   1 1 1 1 3 4 5 6
   2 3 1 1 2 3 4 5 6
END
USRFRC
   sine:node=1,dof=2,amp=800,hz=128
END
"""
PLATE = "set=1 master=1 holes=221 pitch=0.6 hole=0.504 thickness=0.501 shim=0.009 size=10"


def deck_text(*records: str) -> str:
    return STRUCTURE + "PLATES\n" + "".join(f"  {r}\n" for r in records) + "END\n"


def test_plates_are_built_into_holes_nodes_and_spheres():
    deck = parse_deck(
        deck_text(PLATE, PLATE.replace("set=1", "set=2").replace("0.501", "0.503") + " end=0.05")
    )
    assert deck.plates is None  # built
    # the plates' nodes follow NODLIM 3: 4, 5 and 6, 7; NODLIM moves to 7 (PDMP and HOOKE)
    assert deck.pdmp[0].nodlim == 7 and deck.hooke[0].nodlim == 7
    walls = deck.analytic_walls
    assert [(w.shape, w.set_id, w.nodes, w.params) for w in walls] == [
        ("holes", 1, (4, 5), (0.252, 0.6)),
        ("holes", 2, (6, 7), (0.252, 0.6)),
    ]
    assert deck.rbels[0].master == 1 and deck.rbels[0].slaves == (4, 5, 6, 7)
    sets = deck.contacts[0].slaves
    assert [s.set_id for s in sets] == [1, 2]
    assert sets[0].nodes == tuple(range(8, 229)) and sets[1].nodes == tuple(range(229, 450))
    xyz = {n.nid: np.array([n.x, n.y, n.z]) for n in deck.nodes}
    # plate 1 sits on the master (end 0), plate 2 an end plate of 0.05 above it; each hole
    # 0.51 and 0.512 long, the spheres resting on the holes' bottoms (centre R above A)
    assert xyz[5][1] - xyz[4][1] == pytest.approx(0.51) and xyz[4][1] == 0.0
    assert xyz[6][1] == pytest.approx(0.51 + 0.05) and xyz[7][1] - xyz[6][1] == pytest.approx(0.512)
    ys = np.array([xyz[k][1] for k in sets[0].nodes])
    assert np.allclose(ys, 0.25)
    # 15 x 15 grid at pitch 0.6 (221 holes: 14 full rows and 11), centred on the master
    lateral = np.array([[xyz[k][0], xyz[k][2]] for k in sets[0].nodes])
    assert len({tuple(np.round(p, 9)) for p in lateral}) == 221
    assert lateral.max(axis=0) == pytest.approx([4.2, 4.2])
    assert lateral.min(axis=0) == pytest.approx([-4.2, -4.2])


def test_sphere_ids_and_the_writer_round_trip(tmp_path):
    template = read_deck_text(STRUCTURE, tmp_path)
    plates = plates_from_specs([PLATE, PLATE.replace("set=1", "set=2") + " start=random seed=3"])
    deck = plated_deck(template, plates)
    assert sphere_ids(deck) == [(8, 228), (229, 449)]
    assert deck.trace.nodes == (8, 229)  # the template traced nothing but particles (none)
    text = format_deck(deck)
    assert "PLATES" in text and "start=random seed=3" in text
    again = parse_deck(text)
    built = expand_plates(deck)
    assert [(n.nid, n.x, n.y, n.z) for n in again.nodes] == [
        (n.nid, n.x, n.y, n.z) for n in built.nodes
    ]
    # random starts: every sphere somewhere along its free length (plate 2 stacked on plate 1)
    ys = np.array([n.y for n in built.nodes if n.nid >= 229]) - 0.51
    assert ys.min() >= 0.25 and ys.max() <= 0.51 - 0.25 and np.ptp(ys) > 0.005


def test_a_lumped_plate_is_one_sphere_of_all_its_holes():
    deck = parse_deck(deck_text(PLATE + " lumped=yes"))
    pd = deck.pdmp[0]
    assert len(deck.contacts[0].slaves[0].nodes) == 1
    assert pd.prho == pytest.approx(221 * 7.485e-4) and pd.e0 == pytest.approx(221 * 2.8e7)
    assert deck.hooke[0].kn == pytest.approx(221 * 1.0e6)


def read_deck_text(text, tmp_path):
    path = tmp_path / "structure.inp"
    path.write_text(text)
    return read_deck(path)


COL = {m.group(1): m.start() + 3 for m in re.finditer(r"(\w+)=", PLATE)}  # "  " + 1-based
BAD = [
    # a hole larger than the plate: the pattern (15 x 15 at 0.6) spans 8.904 in
    ("size=10", "size=8", "size", "span 8.904 x 8.904: larger than the plate, 8 x 8"),
    ("size=10", "size=0.4", "size", "larger than the plate"),
    # a shim that makes the free length negative
    (
        "shim=0.009",
        "shim=-0.01",
        "shim",
        "free length = thickness + shim - sphere diameter = "
        "0.501 + -0.01 - 0.5 = -0.009: it must be > 0",
    ),
    ("thickness=0.501", "thickness=0.49", "shim", "it must be > 0"),
    ("hole=0.504", "hole=0.5", "hole", "must exceed the sphere's diameter 0.5"),
    ("pitch=0.6", "pitch=0.5", "pitch", "holes wider than the pitch overlap"),
    ("master=1", "master=9", "master", "master node 9 is not defined"),
    ("holes=221", "holes=2.5", "holes", "holes must be a positive integer"),
    ("hole=0.504", "hole=wide", "hole", "hole must be a number"),
    ("size=10", "size=10 colour=red", None, "expected key=value with a key of set, master"),
    ("pitch=0.6 ", "", 1, "missing pitch"),
]


@pytest.mark.parametrize("old,new,key,message", BAD, ids=[b[1] or "missing" for b in BAD])
def test_bad_plates_are_one_line_at_the_word(old, new, key, message, tmp_path):
    record = PLATE.replace(old, new)
    path = tmp_path / "bad.inp"
    text = deck_text(record)
    path.write_text(text)
    with pytest.raises(DeckError) as exc:
        read_deck(path)
    line = text.count("\n", 0, text.index("PLATES\n")) + 2
    if key is None:
        col = record.index("colour") + 3
    elif isinstance(key, int):
        col = 3
    else:
        col = record.index(f"{key}=") + 3
    assert str(exc.value).startswith(f"{path}:{line}:{col}: PLATES: "), str(exc.value)
    assert message in str(exc.value)
    assert "\n" not in str(exc.value)


def test_a_deck_with_its_own_particles_or_two_sets_alike_is_refused(tmp_path):
    with pytest.raises(DeckError, match="node 9 is above PDMP NODLIM 3"):
        parse_deck(
            deck_text(PLATE).replace("   3 1.0 -1.0 0.0\n", "   3 1.0 -1.0 0.0\n   9 0 0 0\n")
        )
    with pytest.raises(DeckError, match="set 1 is already used by the plate at line"):
        parse_deck(deck_text(PLATE, PLATE))
    with pytest.raises(InputError, match="--plates 'set=1 master=1 holes=0"):
        plates_from_specs([PLATE.replace("holes=221", "holes=0")])


def run_cli(*args) -> int:
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in args])
    return exc.value.code or 0


@pytest.mark.parametrize("command", ["run", "check"])
def test_the_cli_says_one_line_exits_2_and_writes_nothing(command, tmp_path, capsys):
    path = tmp_path / "bad.inp"
    path.write_text(deck_text(PLATE.replace("shim=0.009", "shim=-0.002")))
    trace = tmp_path / "bad.trace.txt"
    args = [command, path] + (["--trace", trace] if command == "run" else [])
    assert run_cli(*args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"x3dpd: error: {path}:36:")
    assert ": PLATES: free length" in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.inp"]


def test_fill_writes_the_plates_card_and_the_step(tmp_path, capsys):
    """``x3dpd fill --plates``: the template's structure, the PLATES card as given, the step
    the spheres' impacts need; a bad plate names its --plates value, exit 2, nothing written."""
    template = tmp_path / "structure.inp"
    template.write_text(STRUCTURE)
    out = tmp_path / "mip.inp"
    second = PLATE.replace("set=1", "set=2") + " end=0.05"
    assert run_cli("fill", template, "--plates", PLATE, "--plates", second, "-o", out) == 0
    text = out.read_text()
    assert f"   {PLATE}".replace("size=10", "size=10.0") in text
    deck = read_deck(out)
    assert len(deck.contacts[0].slaves[1].nodes) == 221 and deck.trace.nodes == (8, 229)
    assert "DTMAX" in capsys.readouterr().out  # the step recommended for the spheres
    bad = tmp_path / "bad.inp"
    assert run_cli("fill", template, "--plates", PLATE.replace("0.009", "-0.01"), "-o", bad) == 2
    err = capsys.readouterr().err
    assert "--plates 'set=1" in err and "free length" in err and not bad.exists()
