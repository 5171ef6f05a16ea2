"""Decks whose MODAL card reads a mode file (tests/fixtures/modes/, written from a 3-mass chain
whose modes are known): the run has the chain's closed-form FRF, in the file's units and
converted to the deck's; bad FILE records are deck errors at their place, nothing run."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
from modal_decks import receptance, steady_state

import x3dpd
from x3dpd.errors import DeckError

HERE = pathlib.Path(__file__).resolve().parent
FIXTURES = HERE.parent / "fixtures" / "modes"
#: tests/fixtures/modes/README.md: three 2 kg masses, springs 1e4 N/m, fixed-free, along x;
#: damping ratios 0.01, 0.02, 0.03 in chain3.uff
CHAIN_M, CHAIN_K, CHAIN_ZETA = 2.0, 1.0e4, (0.01, 0.02, 0.03)
LBF, INCH = 4.4482216152605, 0.0254


def _chain():
    m = np.eye(3) * CHAIN_M
    k = CHAIN_K * np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    lam, phi = np.linalg.eigh(np.linalg.solve(np.sqrt(m), np.linalg.solve(np.sqrt(m), k).T))
    omega = np.sqrt(lam)
    phi = phi / math.sqrt(CHAIN_M)  # mass-normalised (M = m I)
    c = m @ phi @ np.diag(2 * np.array(CHAIN_ZETA) * omega) @ phi.T @ m
    return m, k, c, omega


def _deck(
    tmp_path,
    file_record: str,
    units: str,
    hz: float,
    amp: float,
    dt: float,
    tmax: float,
    name: str = "chain.inp",
) -> pathlib.Path:
    text = "\n".join(
        [
            "PARAMETERS",
            f" 0.0 {tmax!r} 0.0 {dt!r} {dt!r} 0 1e12 0 5 0 4",
            "END",
            "NODE COORDINATES",
            " 1 0 0 0",
            " 2 1 0 0",
            " 3 2 0 0",
            "END",
            "MODAL",
            f" {file_record}",
            "END",
            "UNITS",
            f" {units}",
            "END",
            "USRFRC",
            f" sine:node=3,dof=1,amp={amp!r},hz={hz!r}",
            "END",
            "",
        ]
    )
    path = tmp_path / name
    path.write_text(text)
    return path


def _frf_run(path, hz):
    res = x3dpd.run(str(path))
    out = []
    for row in range(3):
        x = res.trace.position[:, row, 0]
        out.append(steady_state(res.trace.times, x - x[0], hz, 5))
    return np.array(out)


@pytest.mark.parametrize("hz", [5.0, 14.0])
def test_a_uff_file_in_si_units_gives_the_chains_frf(tmp_path, hz):
    """chain3.uff (SI, damping in the file) in an SI deck: nodes 10, 20, 30 mapped to 1, 2, 3;
    force at node 3; every node's steady state within 0.5 % and 0.5 degrees of the chain's
    (K - w^2 M + i w C)^-1 F."""
    m, k, c, omega = _chain()
    settle = math.log(1e7) / (min(CHAIN_ZETA[0] * omega[0], CHAIN_ZETA[1] * omega[1]))
    dt = 2e-4
    path = _deck(
        tmp_path,
        f"FILE {FIXTURES / 'chain3.uff'} map=10:1,20:2,30:3",
        "m N s",
        hz,
        1.0,
        dt,
        round((settle + 5 / hz) / dt) * dt,
    )
    got = _frf_run(path, hz)
    want = receptance(hz, m, k, c)[:, 2] * 1.0
    assert np.allclose(np.abs(got), np.abs(want), rtol=5e-3)
    assert np.degrees(np.abs(np.angle(got / want))).max() < 0.5


def test_an_op2_file_converted_to_inch_units(tmp_path):
    """chain3.op2 holds no units and no damping: ``units=m,N,s`` says what it is in and
    ``zeta=`` gives the damping; the deck is in inch, lbf, s, so frequencies stay and shapes are
    converted (sqrt of the mass unit ratio). The response in inches to a force in lbf equals the
    SI chain's, converted."""
    pytest.importorskip("pyNastran", reason="OP2 needs pyNastran (README: the op2 install)")
    m, k, c, omega = _chain()
    hz, amp = 5.0, 0.2
    settle = math.log(1e7) / (CHAIN_ZETA[0] * omega[0])
    dt = 2e-4
    path = _deck(
        tmp_path,
        f"FILE {FIXTURES / 'chain3.op2'} map=10:1,20:2,30:3 units=m,N,s zeta=0.01,0.02,0.03",
        "in lbf s",
        hz,
        amp,
        dt,
        round((settle + 5 / hz) / dt) * dt,
    )
    got = _frf_run(path, hz)
    want = receptance(hz, m, k, c)[:, 2] * amp * LBF / INCH
    # OP2 stores 32-bit floats: shapes to ~1e-7
    assert np.allclose(np.abs(got), np.abs(want), rtol=5e-3)
    assert np.degrees(np.abs(np.angle(got / want))).max() < 0.5


@pytest.mark.parametrize(
    "record, at, says",
    [
        ("FILE no_such_file.uff", "FILE", "mode file no_such_file.uff"),
        ("FILE {f} map=10:1,20:2,30:7", "map=", "not defined in NODE COORDINATES"),
        ("FILE {f} map=10:1,20:2,30:3 modes=1:4", "modes=", "has no mode 4"),
        ("FILE {f} map=10:1,20:2,30:3 units=in,lbf,s", "units=", "contradicts"),
        ("FILE {f} map=10:1,99:2", "map=", "does not hold"),
        ("FILE {f} map=10:1,20:2,30:3 band=100:200", "FILE", "no mode"),
        ("FILE {f} map=10:1 zeta=0.1,0.2", "zeta=", "3 kept modes"),
        ("FILE {f} colour=red", "colour", "unknown FILE option"),
        ("FILE {f}", "FILE", "no node of mode file"),
    ],
)
def test_bad_file_records_are_deck_errors_at_their_place(tmp_path, record, at, says):
    """Every problem of a FILE record is FILE:LINE:COL: MODAL: ... at the record or at the
    value of its option (line 10 of the deck), raised before anything runs."""
    f = "chain3.uff"
    (tmp_path / f).write_bytes((FIXTURES / f).read_bytes())
    record = record.format(f=f)
    path = _deck(tmp_path, record, "m N s", 5.0, 1.0, 1e-3, 0.01)
    with pytest.raises(DeckError) as err:
        x3dpd.run(str(path))
    e = err.value
    assert says in e.message
    assert (e.path, e.line, e.card) == (str(path), 10, "MODAL")
    column = 2 + record.index(at) + (len(at) if at.endswith("=") else 0)
    assert e.column == column
    assert not (tmp_path / "chain.trace.txt").exists()
