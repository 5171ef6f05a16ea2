"""``x3dpd fill``: a deck's cavity filled with particles, on every shipped deck with a cavity."""

from __future__ import annotations

import math

import numpy as np
import pytest
from cli_helpers import DECKS, run_cli

from x3dpd.deck import read_deck
from x3dpd.model.build import build_model
from x3dpd.model.check import check_model

BOXES = ["appendix_a_cube.inp", "beam_1.inp", "beam_64.inp", "beam_512.inp"]


@pytest.mark.parametrize("name", BOXES)
@pytest.mark.parametrize("packing", ["cubic", "hcp", "random"])
def test_filled_deck_checks_clean_and_reports_its_fill(name, packing, tmp_path, capsys):
    out = tmp_path / "out.inp"
    tpl = read_deck(DECKS / name)
    r = tpl.pdmp[0].rzero
    assert (
        run_cli(
            "fill",
            DECKS / name,
            "--n",
            20,
            "--radius",
            r,
            "--packing",
            packing,
            "--gap",
            0.02 * r,
            "--seed",
            1,
            "-o",
            out,
        )
        == 0
    )
    msg = capsys.readouterr().out
    deck = read_deck(out)
    model = build_model(deck)
    report = check_model(model)
    assert not report.errors
    assert not [
        w
        for w in report.warnings
        if "overlap" in w.headline or "outside" in w.headline or "penetrat" in w.headline
    ]
    n = model.n_particles
    fits = "only" not in msg
    assert n == 20 or not fits
    # the reported fill ratio, recomputed from the deck: N 4/3 pi R^3 / cavity volume
    cav = report.cavities[0]
    ratio = n * 4 / 3 * math.pi * r**3 / cav.volume
    assert f"fill ratio {ratio:.3f}" in msg
    # structure untouched, particles after NODLIM, traced after the structure's nodes
    nodlim = tpl.pdmp[0].nodlim
    assert [(nd.nid, nd.x, nd.y, nd.z) for nd in deck.nodes if nd.nid <= nodlim] == [
        (nd.nid, nd.x, nd.y, nd.z) for nd in tpl.nodes if nd.nid <= nodlim
    ]
    assert deck.trace.nodes[-n:] == tuple(range(nodlim + 1, nodlim + 1 + n))


def test_as_many_as_fit_in_a_box_is_the_cubic_lattice_count(tmp_path, capsys):
    """beam_64's cavity 0.263 x 0.372 x 0.372, R = 0.03125, no gap: floor((L - 2R) / 2R) + 1
    per axis = 4 x 5 x 5 = 100."""
    out = tmp_path / "out.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "-o", out) == 0
    size = np.array([0.263, 0.372, 0.372])
    r = 0.03125
    expect = int(np.prod(np.floor((size - 2 * r) / (2 * r) + 1e-9) + 1))
    assert build_model(read_deck(out)).n_particles == expect == 100
    assert "100 particles" in capsys.readouterr().out


def test_refill_of_a_shipped_beam_deck_reproduces_it(tmp_path):
    """tools/make_decks.py builds the beam decks through the same library: filling beam_64 with
    its own recipe gives its particles back exactly."""
    out = tmp_path / "out.inp"
    assert (
        run_cli(
            "fill",
            DECKS / "beam_64.inp",
            "--n",
            64,
            "--gap",
            0.05 * 0.03125,
            "--jitter",
            0.5,
            "--seed",
            2003,
            "-o",
            out,
        )
        == 0
    )
    a, b = read_deck(DECKS / "beam_64.inp"), read_deck(out)
    strip = [(n.nid, n.x, n.y, n.z) for n in a.nodes]
    assert strip == [(n.nid, n.x, n.y, n.z) for n in b.nodes]


def test_impossible_fill_is_an_error_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "out.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--radius", 1.0, "-o", out) == 2
    assert "no particle of radius 1" in capsys.readouterr().err and not out.exists()
    assert run_cli("fill", DECKS / "impact_wall.inp", "-o", out) == 2  # an open wall: no cavity
    assert "not a closed surface" in capsys.readouterr().err and not out.exists()
    # the printed Appendix A deck: its triangles do not close either (docs/running.md)
    assert run_cli("fill", DECKS / "appendix_a.inp", "-o", out) == 2
    assert "not a closed surface" in capsys.readouterr().err and not out.exists()


def test_short_fill_says_so(tmp_path, capsys):
    out = tmp_path / "out.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 500, "-o", out) == 0
    assert "asked for 500: only 100 fit" in capsys.readouterr().out


def _fill20(out, *extra) -> int:
    """20 spheres from a random lattice in beam_64's cavity, at the template's 5e-7 s step
    (--keep-dt: settling is about where they rest, and the recommended 9.5e-8 s would make
    these tests 5 times longer)."""
    return run_cli(
        "fill", DECKS / "beam_64.inp", "--n", 20, "--packing", "random", "--seed", 4,
        "--keep-dt", "-o", out, *extra,
    )  # fmt: skip


def test_settle_auto_runs_until_the_particles_rest_on_the_floor(tmp_path, capsys):
    """20 spheres stacked up from y = R + gap with 0.05 R gaps: after falling they rest on the
    floor (y = R within the Hertz approach under their weight, << 1 % of R), none left the
    cavity, none overlaps (x3dpd check); the run says they rest, after more than one free
    fall across the cavity, sqrt(2 h / g) with h = 0.372 in."""
    out = tmp_path / "out.inp"
    r = 0.03125
    assert _fill20(out, "--settle", "auto") == 0
    said = capsys.readouterr()
    assert ": at rest (the fastest particle at " in said.out and not said.err
    seconds = float(said.out.split("settled for ")[1].split(" s")[0])
    assert seconds > math.sqrt(2.0 * 0.372 / 386.1)
    model = build_model(read_deck(out))
    y = model.x0[model.particle_start :, 1]
    report = check_model(model)
    assert not report.errors
    assert not [w for w in report.warnings if "overlap" in w.headline or "outside" in w.headline]
    lowest = np.sort(y)[:5]
    np.testing.assert_allclose(lowest, r, rtol=1e-2)  # several resting on the floor


def test_settle_for_too_short_a_time_does_not_call_the_particles_at_rest(tmp_path, capsys):
    """Released at rest, the spheres fall at g t: after 1 ms the fastest is at 0.386 in/s, below
    the rest speed sqrt(2 g 0.01 R) = 0.491 in/s -- one look would call the bed at rest. Two
    looks 3 v_rest / g = 3.8 ms apart cannot fit in 1 or 2 ms: too early to tell, a warning.
    After 10 ms both looks see spheres still falling or bouncing (the lowest reach the floor at
    2.9 ms): they still move. The closed forms: v = g t before any contact, the rest speed and
    the fall time sqrt(2 h / g) across the 0.372 in cavity."""
    from x3dpd.api.settle import settle

    plain = tmp_path / "plain.inp"
    assert _fill20(plain) == 0
    capsys.readouterr()
    rest = math.sqrt(2.0 * 386.1 * 0.01 * 0.03125)
    for t in (0.001, 0.002):
        got = settle(read_deck(plain), t)
        assert not got.at_rest and not got.told
        assert got.fastest == pytest.approx(386.1 * t, rel=1e-6)  # free fall, one look
        assert got.rest_speed == pytest.approx(rest)
        assert got.look_gap == pytest.approx(3.0 * rest / 386.1)
    assert got.fall_time == pytest.approx(math.sqrt(2.0 * 0.372 / 386.1), rel=1e-3)
    assert settle(read_deck(plain), 0.001).fastest < rest  # what one look would have believed
    later = settle(read_deck(plain), 0.01)
    assert later.told and not later.at_rest and later.fastest > 2.0 * rest
    out = tmp_path / "out.inp"
    assert _fill20(out, "--settle", 0.002) == 0
    said = capsys.readouterr()
    assert (
        "x3dpd: warning: " in said.err
        and "too early to tell whether the particles rest" in said.err
    )
    assert "give a longer --settle, or --settle auto" in said.err
    assert out.is_file()
    assert _fill20(tmp_path / "later.inp", "--settle", 0.01) == 0
    assert "the particles still move: the fastest at " in capsys.readouterr().err


def test_settle_refuses_a_deck_without_gravity_and_a_time_that_is_not_one(tmp_path, capsys):
    from dataclasses import replace

    from x3dpd.deck import write_deck

    weightless = tmp_path / "weightless.inp"
    write_deck(replace(read_deck(DECKS / "beam_64.inp"), body=None), weightless)
    out = tmp_path / "out.inp"
    args = ("fill", weightless, "--n", 5, "--keep-dt", "-o", out, "--settle")
    assert run_cli(*args, "auto") == 2
    assert "has no BODY gravity, so nothing pulls the particles down" in capsys.readouterr().err
    assert not out.exists()
    for bad in ("soon", "0", "-1", "inf"):
        assert run_cli(*args, bad) == 2
        assert "expected a time > 0 [s] or auto" in capsys.readouterr().err
        assert not out.exists()


def test_cards_only_holds_what_changes(tmp_path):
    out = tmp_path / "cards.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 10, "--cards", "-o", out) == 0
    deck = read_deck(out)
    assert deck.parameters is None and not deck.rbels and not deck.materials
    assert [nd.nid for nd in deck.nodes] == list(range(10, 20))
    assert deck.contacts[0].slaves[0].nodes == tuple(range(10, 20))
    assert deck.trace.nodes == (9, *range(10, 20)) and deck.pdmp[0].nodlim == 9


def test_the_written_deck_s_time_step_is_reported(tmp_path, capsys):
    """Without --dt or --keep-dt the deck gets the recommended step, and fill says so (with the
    template's step it replaced); with --keep-dt it says nothing of the step."""
    out = tmp_path / "out.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 5, "-o", out) == 0
    said = capsys.readouterr().out
    assert f"x3dpd: {out}: DTMAX " in said and " s recommended (" in said
    assert "was 5e-07 s; ITRAC " in said
    kept = tmp_path / "kept.inp"
    assert run_cli("fill", DECKS / "beam_64.inp", "--n", 5, "--keep-dt", "-o", kept) == 0
    assert "DTMAX" not in capsys.readouterr().out


def test_settle_refuses_a_deck_without_particles():
    """The API's settle on a structure alone (it took the smallest radius of no particles: a
    numpy traceback)."""
    from dataclasses import replace

    from factories import sdof_deck

    from x3dpd.api.settle import settle
    from x3dpd.deck.cards import Body
    from x3dpd.errors import InputError

    deck = replace(sdof_deck(dt=1e-5, hz=37.0), body=Body(0.0, -386.1, 0.0))
    with pytest.raises(InputError, match="has no particles to settle"):
        settle(deck, 0.01)
