"""``x3dpd frf`` and ``spectrum`` on input a user can get wrong: a window scipy does not know, a
trace cut after its run ended, a bad measured file (refused before the estimate), a trace whose
output interval does not divide the periodic drive's period (said), and a progress line while a
big trace is read."""

from __future__ import annotations

import dataclasses
import math

import pytest
from cli_helpers import refused, run_cli
from factories import TABLE4_K, TABLE4_MASS, sdof_deck

from x3dpd.deck.cards import Usrfrc
from x3dpd.deck.writer import write_deck

C = 2.0 * 0.05 * math.sqrt(TABLE4_K * TABLE4_MASS)
SPEC = "random:node=1,dof=1,rms=0.01,band=10:150,seed=5,period=8"


def _sdof(folder, itrac: int):
    deck = folder / f"sdof_{itrac}.inp"
    cards = sdof_deck(dt=1e-4, hz=1.0, drive=0.0, c=C, itrac=itrac)
    write_deck(dataclasses.replace(cards, usrfrc=(Usrfrc((SPEC,)),)), deck)
    return deck


@pytest.fixture(scope="module")
def traces(tmp_path_factory):
    """Two periods (16 s) of the random-driven SDOF traced every 10 steps (1e-3 s: 8000
    samples a period) and every 7 steps (7e-4 s: 11428.57 samples a period)."""
    folder = tmp_path_factory.mktemp("frf_input")
    out = {}
    for itrac in (10, 7):
        out[itrac] = folder / f"run_{itrac}.trace.txt"
        assert run_cli(_sdof(folder, itrac), "--tmax", 16, "--trace", out[itrac], "-q") == 0
    return out


def _frf(trace, out, *options):
    return ("frf", trace, "--drive", "1:1", "--response", "1:1", "--out", out, *options)


def test_an_unknown_window_is_refused_before_anything(traces, tmp_path, capsys):
    """Refused even with --overwrite: an earlier result in DIR is left as it was."""
    out = tmp_path / "out"
    out.mkdir()
    for name in ("frf.csv", "frf.png", "spectrum.csv", "spectrum.png"):
        (out / name).write_text("an earlier result\n")
    message = "--window 'rectangle-ish': not a window scipy.signal.get_window knows"
    bad = ("--window", "rectangle-ish", "--overwrite")
    refused(capsys, *_frf(traces[10], out, *bad), message=message, folder=out)
    refused(
        capsys,
        *("spectrum", traces[10], "--node", 1, "--out", out, *bad),
        message=message,
        folder=out,
    )


def test_a_trace_cut_after_its_run_ended_is_refused(traces, tmp_path, capsys):
    """The file cut mid-row, its sidecar intact (status complete, 16001 output times): the
    record is short, which frf once analysed without a word."""
    data = traces[10].read_bytes()
    cut = tmp_path / "cut.trace.txt"
    cut.write_bytes(data[:-70])
    cut.with_name(cut.name + ".json").write_bytes(
        traces[10].with_name(traces[10].name + ".json").read_bytes()
    )
    out = tmp_path / "out"
    line = refused(
        capsys,
        *_frf(cut, out),
        message=f"{cut}: the record is short: the file holds 16000 output times",
        folder=tmp_path,
    )
    assert "its sidecar says the run wrote 16001" in line


def test_a_bad_measured_file_is_refused_before_the_estimate(traces, tmp_path, capsys):
    (tmp_path / "bad.csv").write_text("freq,real,imag\n1,2,3\n2,3,4\n3,4,5\n")
    out = tmp_path / "out"
    refused(
        capsys,
        *_frf(traces[10], out, "--measured", tmp_path / "bad.csv"),
        message="bad.csv:1:1: a measured FRF needs the columns frequency_hz and re, im",
        folder=tmp_path,
        silent=True,
    )


def test_a_period_that_is_no_whole_number_of_samples_is_said(traces, tmp_path, capsys):
    """period=8 s over an output interval of 7e-4 s is 11428.57 samples: no segment holds
    whole periods, so the periodic drive's lines leak; frf says so. At 1e-3 s (8000 samples)
    it says nothing."""
    args = ("--segment", 8, "--overlap", 0, "--window", "boxcar")
    assert run_cli(*_frf(traces[7], tmp_path / "a", *args)) == 0
    out = capsys.readouterr().out
    assert (
        f"note: {traces[7]}: the drive's period 8 s is 11428.57 output intervals of 0.0007 s" in out
    )
    assert "leak" in out and "ITRAC" in out
    assert run_cli(*_frf(traces[10], tmp_path / "b", *args)) == 0
    assert "output intervals" not in capsys.readouterr().out


def test_reading_a_big_trace_shows_progress(traces, tmp_path, capsys, monkeypatch):
    """A trace above the progress threshold (lowered here: the shipped one is 4 MB) gets a
    reading line on stderr; --quiet keeps it off."""
    from x3dpd.cli import progress

    monkeypatch.setattr(progress, "READ_PROGRESS_BYTES", 1000)
    assert run_cli(*_frf(traces[10], tmp_path / "a")) == 0
    err = capsys.readouterr().err
    assert f"reading {traces[10]} (2.7 MB)" in err and "100 %" in err
    assert run_cli(*_frf(traces[10], tmp_path / "b", "--quiet")) == 0
    assert capsys.readouterr().err == ""


def test_a_record_too_short_for_eight_welch_averages_says_what_to_give(tmp_path, capsys):
    """The default Welch segment is the record / (1 + 7 (1 - overlap)): 8 averages. A 21-sample
    record gives 4-sample segments, under the 8 a segment needs; the refusal says the record's
    length and the --nperseg range that works (it said only "segment length 4 samples: at least
    8 are needed"), and --nperseg 16 then works."""
    deck = tmp_path / "short.inp"
    write_deck(sdof_deck(dt=1e-4, hz=37.0, drive=1e-3, c=C, itrac=10), deck)
    trace = tmp_path / "short.trace.txt"
    assert run_cli(deck, "--tmax", 0.02, "--trace", trace, "-q") == 0
    out = tmp_path / "sp"
    line = refused(
        capsys,
        *("spectrum", trace, "--node", 1, "--method", "welch", "--out", out),
        message="the record holds 21 samples (0.021 s): 8 Welch averages of it would be 4",
        folder=tmp_path,
    )
    assert "give --nperseg 8..21 (fewer averages), --method fft, or a longer run" in line
    assert run_cli("spectrum", trace, "--node", 1, "--method", "welch", "--nperseg", 16,
                   "--out", out, "-q") == 0  # fmt: skip
