"""``x3dpd sweep --measured FILE[@NODE:DOF]``: a measured FRF drawn on the sweep's plots in the
plot's own quantity (the amplitude a linear structure with that FRF would have at each drive, an
accelerance, a transmissibility), and bad measured input refused before anything is written."""

from __future__ import annotations

import math

import numpy as np
import pytest

from factories import TABLE4_C, TABLE4_K, TABLE4_MASS, base_sdof_deck, sdof_deck
from test_measured import write_uff58
from test_run import x3dpd

from x3dpd.deck.parser import read_deck
from x3dpd.deck.writer import write_deck
from x3dpd.design.spec import SweepSpec
from x3dpd.design.sweep import deck_hash
from x3dpd.design.sweep_measured import measured_curves, read_measured
from x3dpd.errors import InputError
from x3dpd.io.measured import write_frf_csv

F = np.linspace(30.0, 50.0, 81)
W = 2 * np.pi * F


def receptance(w):
    return 1.0 / (TABLE4_K - TABLE4_MASS * w * w + 1j * TABLE4_C * w)


def transmissibility(w):
    return (TABLE4_K + 1j * TABLE4_C * w) / (TABLE4_K - TABLE4_MASS * w * w + 1j * TABLE4_C * w)


def _spec(tmp_path, deck, **kw) -> SweepSpec:
    path = tmp_path / "d.inp"
    write_deck(deck, path)
    return SweepSpec(
        deck=read_deck(path),
        deck_text_hash=deck_hash(path),
        frequencies=(35.0, 45.0),
        node=1,
        dof=1,
        **kw,
    )


def test_a_force_drives_measured_curve_is_the_amplitude_that_frf_gives(tmp_path):
    """An accelerance file (UFF, says acceleration) and a receptance CSV (says displacement) of
    the same SDOF give the same curve: X = |H| F, at every drive; clipped to the swept band."""
    write_uff58(tmp_path / "acc.uff", F, -(W**2) * receptance(W), binary=1)
    write_frf_csv(tmp_path / "rec.csv", F, receptance(W), quantity="displacement")
    spec = _spec(tmp_path, sdof_deck(dt=1e-5, hz=37.0), drives=(1e-3, 4e-3))
    frfs = read_measured([str(tmp_path / "acc.uff"), f"{tmp_path / 'rec.csv'}@1:1"], [(1, 1)])
    curves = measured_curves(frfs, spec, (1, 1))
    assert len(curves) == 4  # two files x two drives
    keep = (F >= 35.0) & (F <= 45.0)
    for (label, drive), (f, x) in curves.items():
        assert label.startswith("measured")
        np.testing.assert_array_equal(f, F[keep])
        np.testing.assert_allclose(x, drive * np.abs(receptance(W[keep])), rtol=1e-12)
    # the scale multiplies the file's values (a unit conversion)
    scaled = measured_curves(frfs, spec, (1, 1), 386.1)
    for key, (_f, x) in scaled.items():
        np.testing.assert_allclose(x, 386.1 * curves[key][1], rtol=1e-12)
    assert measured_curves(frfs, spec, (2, 1)) == {}  # drawn at its own point only


def test_a_base_drives_measured_curve_is_the_transmissibility_times_the_base(tmp_path):
    """A base drive at 2g: a transmissibility file (acceleration per base acceleration, the
    quantity not said: taken as acceleration) drawn as X = |T| U(f), U = 2 g / w^2."""
    write_frf_csv(tmp_path / "t.csv", F, transmissibility(W))
    spec = _spec(
        tmp_path,
        base_sdof_deck(dt=1e-5),
        drives=(772.2,),
        quantity="acceleration",
        responses=((1, 1),),
    )
    (((label, drive), (f, x)),) = measured_curves(
        read_measured([str(tmp_path / "t.csv")], [(1, 1)]), spec, (1, 1)
    ).items()
    w = 2 * np.pi * f
    np.testing.assert_allclose(x, np.abs(transmissibility(w)) * 772.2 / w**2, rtol=1e-12)


def test_the_sweep_draws_it_and_bad_measured_input_writes_nothing(tmp_path, capsys):
    """Through the CLI: a short base-drive sweep with a measured transmissibility on its plot;
    then a CSV without the columns, a UFF of another dataset type and a point the sweep does
    not measure are each one line, exit 2, and no output folder."""
    deck = tmp_path / "shaker.inp"
    write_deck(base_sdof_deck(dt=1e-5), deck)
    write_frf_csv(tmp_path / "t.csv", F, transmissibility(W))
    common = (
        "sweep",
        deck,
        "--drive",
        "base",
        "--node",
        2,
        "--dof",
        1,
        "--response",
        "1:1",
        "--freq",
        "38,40",
        "--amp",
        "0.01g",
        "--workers",
        1,
        "--max-cycles",
        15,
        "--window",
        5,
        "--baseline",
        "undamped",
        "-q",
    )
    code, _, err = x3dpd(
        capsys, *common, "--measured", tmp_path / "t.csv", "--out", tmp_path / "ok"
    )
    assert code == 0, err
    assert (tmp_path / "ok" / "sweep.png").stat().st_size > 10_000
    (tmp_path / "bad.csv").write_text("freq,real,imag\n1,2,3\n2,3,4\n3,4,5\n")
    import pyuff

    nodes = pyuff.prepare_15(
        node_nums=[1], def_cs=[0], disp_cs=[0], color=[1], x=[0.0], y=[0.0], z=[0.0]
    )
    pyuff.UFF(str(tmp_path / "nodes.uff")).write_sets(nodes, mode="add")
    for measured, message in (
        (tmp_path / "bad.csv", "bad.csv:1:1: a measured FRF needs the columns"),
        (tmp_path / "nodes.uff", "holds UFF dataset type(s) 15, not 58"),
        (f"{tmp_path / 't.csv'}@7:1", "the sweep does not measure node 7 dof 1"),
        (f"{tmp_path / 't.csv'}@1", "expected NODE:DOF"),
    ):
        out = tmp_path / "out"
        code, _, err = x3dpd(capsys, *common, "--measured", measured, "--out", out)
        assert code == 2 and message in err and "Traceback" not in err, err
        assert len(err.strip().splitlines()) == 1
        assert not out.exists()


def test_a_bad_scale_is_refused():
    with pytest.raises(InputError, match="--measured-scale"):
        read_measured([], [(1, 1)], math.nan)
