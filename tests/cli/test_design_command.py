"""``x3dpd design`` on the command line: a malformed design file is one line at its place,
exit 2, nothing written; the command is registered with its options."""

from __future__ import annotations

from pathlib import Path

from cli_helpers import DECKS, run_cli


def test_a_malformed_design_file_is_one_line_at_its_place_exit_2_nothing_written(tmp_path, capsys):
    spec = tmp_path / "bad.toml"
    spec.write_text(
        f'structure = "{DECKS / "beam_1.inp"}"\n[vary]\nradius = [0.1]\n'
        'colour = ["red"]\n[evaluate]\nkind = "sweep"\ndrives = [1e-3]\n'
        "frequencies = [37.0]\n"
    )
    assert run_cli("design", spec, "--out", tmp_path / "out") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(
        f"x3dpd: error: {spec}:4: vary.colour: unknown key 'colour'; "
        "expected one of material, radius, count, fill_ratio"
    )
    assert not Path(tmp_path / "out").exists()


def test_design_is_a_command_with_its_options(capsys):
    assert run_cli("design", "--help") == 0
    text = capsys.readouterr().out
    for option in ("--out", "--workers", "--scheduler", "--overwrite"):
        assert option in text
