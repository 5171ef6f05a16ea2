"""``x3dpd DECK`` / ``x3dpd run DECK``: outputs, refusals, exit statuses, energy file, progress.

The runs here use decks/impact_wall.inp (one sphere, 12 000 steps, well under a second once its
step loop is compiled) or tiny generated decks; the restart machinery is in test_restart.py.
"""

from __future__ import annotations

import io
import os
import shutil
from pathlib import Path

import click
import numpy as np
import pytest

from x3dpd.cli import _register, cli, main
from x3dpd.cli.progress import Progress
from x3dpd.api.outputs import deck_key
from x3dpd.cli.resume import resume_command
from x3dpd.cli.run import RunOptions, default_paths
from x3dpd.deck import parse_deck, read_deck
from x3dpd.io.energy import EnergyWriter, read_energy
from x3dpd.io.trace import read_trace
from x3dpd.solver.simulation import ENERGY_COLUMNS

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks"
IMPACT = DECKS / "impact_wall.inp"
DRIVE = "sine:node=25,dof=1,amp=4.84040e-3,hz=37.21"


def x3dpd(capsys, *args):
    """Run ``x3dpd ARGS`` in-process; return (exit status, stdout, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    code = exc.value.code
    return (0 if code is None else code), out, err


@pytest.fixture
def impact(tmp_path, monkeypatch):
    """decks/impact_wall.inp copied to a fresh working directory (outputs land there)."""
    monkeypatch.chdir(tmp_path)
    deck = tmp_path / "impact_wall.inp"
    shutil.copy(IMPACT, deck)
    return deck


# ---------------------------------------------------------------------------------- a full run


def test_run_writes_trace_energy_and_summary(capsys, impact):
    code, out, err = x3dpd(capsys, impact)
    assert code == 0, err
    tr = read_trace("impact_wall.trace.txt")
    assert tr.status == "complete"
    # 1.2e-5 s / 1e-9 s = 12 000 steps, a row every 10 steps, plus t = 0
    assert tr.times.size == 1201
    np.testing.assert_allclose(tr.times, np.arange(1201) * 1e-8, rtol=0, atol=1e-20)
    assert tr.meta["deck_path"] == str(impact)
    assert tr.meta["effects"] == ["wall_contact"]
    assert tr.meta["tmax"] == 1.2e-5
    en = read_energy("impact_wall.energy.csv")
    assert en.columns == ENERGY_COLUMNS
    np.testing.assert_allclose(en.times, tr.times, rtol=1e-9)  # a row per trace time
    assert abs(en.column("residual")[-1]) < 1e-6 * en.column("total_energy")[0]
    # the elastic sphere leaves the wall at its impact speed
    assert tr.node(9)[-1, 3] == pytest.approx(62.832, rel=1e-6)
    for word in (
        "effects",
        "wall_contact",
        "steps",
        "12000",
        "wall time",
        "compile",
        "steps/s",
        "us/step",
        "energy ledger",
        "kinetic_translation",
        "dissipated (total)",
        "residual",
        "of the energy scale",
    ):
        assert word in out, word
    assert "Traceback" not in err


def test_run_subcommand_and_options(capsys, impact, tmp_path):
    (tmp_path / "out").mkdir()
    code, out, err = x3dpd(
        capsys,
        "run",
        impact,
        "--trace",
        "out/a.trace.txt",
        "--tmax",
        "2e-6",
        "--dt",
        "2e-9",
        "--quiet",
    )
    assert code == 0, err
    assert out == "" and err == ""  # --quiet prints errors only
    tr = read_trace("out/a.trace.txt")
    assert tr.meta["dt"] == 2e-9
    assert tr.times[-1] == pytest.approx(2e-6)
    assert tr.times.size == 101  # 1000 steps, a row every 10
    assert os.path.isfile("out/a.energy.csv")  # beside the trace, named after it


def test_resume_command_repeats_what_matters():
    opts = RunOptions(
        deck="d.inp",
        trace="a b.txt",
        usrfrc=(DRIVE,),
        tmax=0.5,
        dt=2.5e-7,
        friction="coulomb",
        plot="p.png",
        quiet=True,
    )
    assert resume_command(opts) == (
        f"d.inp --restart --trace 'a b.txt' --usrfrc {DRIVE} --dt 2.5e-07 --tmax 0.5 "
        "--friction coulomb"
    )
    assert resume_command(RunOptions(deck="d.inp")) == "d.inp --restart"


def test_default_paths():
    assert default_paths(RunOptions(deck="decks/x.inp")) == (
        "x.trace.txt",
        "x.energy.csv",
        "x.trace.txt.restart.npz",
    )
    assert default_paths(RunOptions(deck="x.inp", trace="o/t.txt")) == (
        "o/t.txt",
        "o/t.txt.energy.csv",
        "o/t.txt.restart.npz",
    )
    assert default_paths(RunOptions(deck="x.inp", energy="e.csv"))[1] == "e.csv"


def test_plot(capsys, impact):
    code, out, err = x3dpd(capsys, impact, "--plot", "run.png", "--tmax", "1e-6")
    assert code == 0, err
    with open("run.png", "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert "run.png" in out


# ------------------------------------------------------------------------------------ refusals


def test_printed_appendix_a_deck_is_refused(capsys, tmp_path, monkeypatch):
    """The report's Appendix A deck puts its walls through the particle cloud: exit 2, one
    message naming a particle, a triangle and a depth, pointing to `x3dpd check` and the
    repaired deck; no trace is created."""
    monkeypatch.chdir(tmp_path)
    code, out, err = x3dpd(capsys, DECKS / "appendix_a.inp", "--usrfrc", DRIVE)
    assert code == 2
    assert err.startswith("x3dpd: error: ") and err.count("\n") == 1
    for word in (
        "particle node 26",
        "triangle 3 (nodes 5 8 6)",
        "0.0625 (2 R) deep",
        "x3dpd check",
        "decks/appendix_a_cube.inp",
        "penetration limit",
    ):
        assert word in err, word
    assert "Traceback" not in err
    assert not os.path.exists("appendix_a.trace.txt")


def test_existing_outputs_are_never_destroyed(capsys, impact):
    assert x3dpd(capsys, impact, "--tmax", "1e-7")[0] == 0
    first = Path("impact_wall.trace.txt").read_bytes()
    first_energy = Path("impact_wall.energy.csv").read_bytes()
    code, out, err = x3dpd(capsys, impact, "--tmax", "2e-7")
    assert code == 2 and "already exists" in err and "--overwrite" in err
    assert Path("impact_wall.trace.txt").read_bytes() == first
    # the energy file alone in the way is refused before the trace is touched
    os.rename("impact_wall.trace.txt", "moved.txt")
    os.rename("impact_wall.trace.txt.json", "moved.txt.json")
    code, out, err = x3dpd(capsys, impact, "--tmax", "2e-7")
    assert code == 2 and "energy file impact_wall.energy.csv already exists" in err
    assert not os.path.exists("impact_wall.trace.txt")
    os.rename("moved.txt", "impact_wall.trace.txt")
    os.rename("moved.txt.json", "impact_wall.trace.txt.json")
    code, out, err = x3dpd(capsys, impact, "--tmax", "2e-7", "--overwrite")
    assert code == 0, err
    assert Path("impact_wall.trace.txt.bak").read_bytes() == first
    assert Path("impact_wall.energy.csv.bak").read_bytes() == first_energy
    assert read_trace("impact_wall.trace.txt").times.size == 21


def test_bad_input_exits_2(capsys, impact):
    code, _, err = x3dpd(capsys, impact, "--usrfrc", "sine:node=999,dof=1,amp=1,hz=1")
    assert code == 2 and "999" in err and "Traceback" not in err
    code, _, err = x3dpd(capsys, impact, "--tmax", "-1")
    assert code == 2 and "before the start time" in err
    code, _, err = x3dpd(capsys, "missing.inp")
    assert code == 2
    assert not os.path.exists("impact_wall.trace.txt")


def test_irest_without_dump_exits_2(capsys, impact):
    text = impact.read_text().replace(
        "1e-09 1e-09 0 1000000000.0 0 5 0", "1e-09 1e-09 0 1000000000.0 1 5 0"
    )
    assert text != impact.read_text()
    impact.write_text(text)
    code, _, err = x3dpd(capsys, impact)
    assert code == 2 and "IREST = 1" in err and "does not exist" in err


def test_unstable_run_exits_3_and_keeps_the_trace(capsys, impact):
    """A step 2000 times too large: the sphere tunnels/explodes; diagnosis, exit 3, trace kept
    with sidecar status "unstable"."""
    code, out, err = x3dpd(capsys, impact, "--dt", "2e-6", "--tmax", "1e-3")
    assert code == 3, err
    # the first message (after the compile notice of a cold kernel cache, if any)
    before, found, _ = err.partition("x3dpd: error: unstable run")
    assert found and (before == "" or before.startswith("x3dpd: compiling")), err
    assert "Traceback" not in err
    tr = read_trace("impact_wall.trace.txt")
    assert tr.status == "unstable"
    assert tr.times[0] == 0.0
    assert "(unstable)" in out


# ------------------------------------------------------------------------------ CLI plumbing


def test_main_passes_on_ctx_exit_codes(capsys):
    _register()

    @click.command("_exit5")
    @click.pass_context
    def exit5(ctx):
        ctx.exit(5)

    cli.add_command(exit5)
    try:
        with pytest.raises(SystemExit) as exc:
            main(["_exit5"])
        assert exc.value.code == 5
    finally:
        cli.commands.pop("_exit5", None)


def test_progress_terminal_and_plain():
    class Tty(io.StringIO):
        def isatty(self):
            return True

    s = Tty()
    p = Progress(False, 15.0, stream=s)
    p.update(1.5, 50_000.0, 270.0, -1.2e-9, force=True)
    p.update(3.0, 51_000.0, 240.0, -1.3e-9, force=True)
    p.done()
    text = s.getvalue()
    assert text.startswith("\rt = 1.5 / 15 s") and text.count("\r") == 2
    assert "50.0k steps/s" in text and "ETA 4:30" in text and "-1.20e-09" in text
    assert text.endswith("\n") and text.count("\n") == 1
    plain = io.StringIO()
    p = Progress(False, 15.0, stream=plain)
    p.update(1.5, 5e4, 270.0, 0.0)  # less than 10 s since start: nothing
    p.update(1.5, 5e4, 270.0, 0.0, force=True)
    assert plain.getvalue().count("\n") == 1 and "\r" not in plain.getvalue()
    quiet = io.StringIO()
    Progress(True, 15.0, stream=quiet).update(1.0, 1.0, 1.0, 0.0, force=True)
    assert quiet.getvalue() == ""


def test_deck_key_masks_tmax_trest_irest_and_comments():
    base = read_deck(IMPACT)
    text = IMPACT.read_text()
    changed = text.replace(
        "0.0 1.2e-05 0.0 1e-09 1e-09 0 1000000000.0 0",
        "0.0 5.0e-05 1.0e-6 1e-09 1e-09 0 1000000000.0 1",
    )
    assert changed != text
    assert deck_key(parse_deck("$ another comment\n" + changed, "x.inp")) == deck_key(base)
    other = text.replace("-62.832", "-60.0")
    assert deck_key(parse_deck(other, "x.inp")) != deck_key(base)


# ---------------------------------------------------------------------------------- energy file


def test_energy_writer_streams_and_resumes(tmp_path):
    path = tmp_path / "e.csv"
    cols = ("time", "a", "b")
    with EnergyWriter(path, cols) as w:
        w.write_rows(np.array([[0.0, 1.0, 2.0]]))
        w.write_rows(np.array([[1e-3, 0.1 + 0.2, -1e-300], [2e-3, 3.0, 4.0]]))
        off, rows = w.tell(), w.rows_written
        w.write_rows(np.array([3e-3, 5.0, 6.0]))
    last = b"3.000000000e-03,5.0000000000000000e+00,6.0000000000000000e+00\n"
    assert rows == 3 and off == path.stat().st_size - len(last)
    e = read_energy(path)
    assert e.columns == cols and e.data.shape == (4, 3)
    # 17 digits read back exactly; the time has the trace's 10 digits
    assert e.data[1, 1] == 0.1 + 0.2 and e.data[1, 2] == -1e-300
    assert path.read_text().splitlines()[2].startswith("1.000000000e-03,")
    with pytest.raises(Exception, match="already exists"):
        EnergyWriter(path, cols)
    with open(path, "ab") as f:
        f.write(b"0.004,7")  # a cut row (killed run)
    assert read_energy(path).data.shape == (4, 3)
    with EnergyWriter(path, cols, append_at=(off, rows)) as w:
        w.write_rows(np.array([[3e-3, 5.0, 6.0]]))
    assert read_energy(path).data.shape == (4, 3)
    assert path.read_bytes().endswith(last)
    with pytest.raises(Exception, match="cannot resume"):
        EnergyWriter(path, cols, append_at=(off, rows + 1))
    w = EnergyWriter(path, cols, overwrite=True)
    w.close()
    assert (tmp_path / "e.csv.bak").is_file() and read_energy(path).data.shape == (0, 3)


def test_energy_times_are_written_as_the_trace_writes_them(tmp_path):
    """t = 7 ms computed as 14000 * 5e-7 is 0.006999999999999999 in binary; the trace prints
    7.000000000e-03 and so does the energy file, so rows of one time match textually."""
    from x3dpd.io.trace import NUMBER_FORMAT

    t = 14000 * 5e-7
    assert repr(t) == "0.006999999999999999"
    path = tmp_path / "e.csv"
    with EnergyWriter(path, ("time", "a")) as w:
        w.write_rows(np.array([[t, 1.0]]))
    row = path.read_text().splitlines()[1]
    assert row.split(",")[0] == (NUMBER_FORMAT % t).strip() == "7.000000000e-03"


# ------------------------------------------------------------------- rough edges of a run


def test_bad_plot_path_is_refused_before_the_run(capsys, impact):
    code, out, err = x3dpd(capsys, impact, "--plot", "no/such/folder/run.png")
    assert code == 2 and "--plot" in err and "does not exist" in err
    code, out, err = x3dpd(capsys, impact, "--plot", "run.txt")
    assert code == 2 and ".png" in err
    assert not os.path.exists("impact_wall.trace.txt")


def test_usrfrc_replaces_the_decks_drive_and_says_so(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(DECKS / "beam_1.inp", "beam_1.inp")
    other = "sine:node=9,dof=1,amp=4.84040e-3,hz=38"
    code, out, err = x3dpd(capsys, "beam_1.inp", "--usrfrc", other, "--tmax", "1e-3")
    assert code == 0, err
    assert (
        f"drive          {other} (replaces the deck's USRFRC "
        "sine:node=9,dof=1,amp=4.84040e-3,hz=37.21"
    ) in out
    side = read_trace("beam_1.trace.txt").meta
    assert side["usrfrc"] == [other]
    assert side["usrfrc_replaced"] == ["sine:node=9,dof=1,amp=4.84040e-3,hz=37.21"]
    code, out, err = x3dpd(
        capsys,
        "beam_1.inp",
        "--usrfrc",
        other,
        "--usrfrc-add",
        "--tmax",
        "1e-3",
        "--trace",
        "add.trace.txt",
    )
    assert code == 0, err
    assert read_trace("add.trace.txt").meta["usrfrc"] == [
        "sine:node=9,dof=1,amp=4.84040e-3,hz=37.21",
        other,
    ]


def test_unstable_summary_agrees_with_the_error_line(capsys, impact):
    code, out, err = x3dpd(capsys, impact, "--dt", "2e-6", "--tmax", "1e-3")
    assert code == 3
    t_err = float(err.split("unstable run at t = ")[1].split(" s")[0])
    t_sum = float(out.split("t = 0 .. ")[1].split(" s")[0])
    assert t_sum == pytest.approx(t_err, rel=1e-5)
    assert read_trace("impact_wall.trace.txt").times[-1] <= t_err * (1 + 1e-6)
