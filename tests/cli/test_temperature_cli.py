"""A deck at temperature through the command line (issue 31 item 6): ``--temperature`` on
``x3dpd run``, ``check``, ``sweep`` and ``ringdown``; bad input -- a temperature outside a
material's table, a TEMPERATURE card without units, an option the deck cannot take -- is one
line ``FILE:LINE:COL: CARD: message``, exit 2, nothing written."""

from __future__ import annotations

import re

from cli_helpers import DECKS, refused, run_cli

WC7 = DECKS / "capsule_wc7.inp"


def test_check_prints_the_clearances_at_assembly_and_at_the_operating_temperature(capsys):
    capsys.readouterr()
    assert run_cli("check", WC7, "--temperature", "850") == 0
    out = capsys.readouterr().out
    assert "  temperature      850 °F (--temperature); the deck's numbers at the assembly " in out
    assert "walls of sets 1-7: titanium, strain +0.004" in out
    found = re.search(
        r"clearance, sets 1-7, cylinder along its axis: 0\.15625 at 70 °F, "
        r"(\S+) at 850 °F",
        out,
    )
    assert found and float(found.group(1)) > 0.15625  # the titanium outgrows the carbide
    assert run_cli("check", WC7) == 0  # as written: 70 F, nothing moves
    assert "0.15625 at 70 °F, 0.15625 at 70 °F (+0)" in capsys.readouterr().out


def test_a_temperature_outside_a_table_is_refused_before_anything_is_written(capsys, tmp_path):
    line = refused(
        capsys,
        "run",
        WC7,
        "--temperature",
        "1200F",
        "--trace",
        tmp_path / "hot.trace.txt",
        message="TEMPERATURE: OPERATING 1200F (--temperature): material 'titanium': 1200 °F is "
        "outside its temperature table, -99.67 °F to 1000 °F",
        folder=tmp_path,
        silent=True,
    )
    assert re.match(rf"x3dpd: error: {re.escape(str(WC7))}:\d+:1: TEMPERATURE: ", line)
    refused(capsys, "check", WC7, "--temperature", "-200F", message="-200 °F is outside")


def test_a_card_without_units_is_refused(capsys, tmp_path):
    text = WC7.read_text().replace("UNITS\n   in lbf s\nEND\n", "")
    assert "\nUNITS\n" not in text
    deck = tmp_path / "bare.inp"
    deck.write_text(text)
    for command in (("run", deck, "--trace", tmp_path / "bare.trace.txt"), ("check", deck)):
        line = refused(
            capsys,
            *command,
            message="TEMPERATURE: OPERATING 70: a temperature without a unit needs the deck's "
            "UNITS card",
            folder=tmp_path,
        )
        assert line.startswith(f"x3dpd: error: {deck}:")


def test_the_option_needs_a_deck_with_the_card(capsys, tmp_path):
    beam = DECKS / "beam_1.inp"
    for command in (
        ("run", beam, "--trace", tmp_path / "b.trace.txt"),
        ("check", beam),
        ("sweep", beam, "--freq", "37", "--amp", "0.005", "--out", tmp_path / "sweep"),
        ("ringdown", beam, "--out", tmp_path / "rd"),
    ):
        refused(
            capsys,
            *command,
            "--temperature",
            "850F",
            message="--temperature 850F: ",
            folder=tmp_path,
        )
    trace = tmp_path / "x.trace.txt"
    trace.write_text("")
    refused(
        capsys,
        "ringdown",
        trace,
        "--node",
        "1",
        "--out",
        tmp_path / "rd",
        "--temperature",
        "850F",
        message="it applies to a deck",
    )


def test_a_run_at_temperature_resumes_only_at_the_same_temperature(capsys, tmp_path):
    """The operating temperature is part of the run's setup: a restart dump written at 850 F
    resumes with --temperature 850F (the card key: the same setup) and is refused without it;
    the resume command a run prints carries it."""
    from x3dpd.cli.resume import resume_command
    from x3dpd.cli.run import RunOptions

    trace = tmp_path / "hot.trace.txt"
    hot = ("--temperature", "850F", "--trace", trace, "--quiet")
    assert run_cli("run", WC7, *hot, "--tmax", "0.002") == 0
    refused(
        capsys,
        "run",
        WC7,
        "--trace",
        trace,
        "--tmax",
        "0.003",
        "--restart",
        message="written by a different setup",
        folder=tmp_path,
    )
    assert run_cli("run", WC7, *hot, "--tmax", "0.003", "--restart") == 0
    opts = RunOptions(deck="capsule_wc7.inp", temperature="850F")
    assert resume_command(opts) == "capsule_wc7.inp --restart --temperature 850F"
