"""A run with prescribed motion resumes bit for bit: the actuator's last forces are part of the
restart dump, so the resumed ledger counts the same work as the uninterrupted one."""

from __future__ import annotations

from cli_helpers import DECKS, run_cli

MOTION = "node=25,dof=1,amp=0.01,hz=37.21"


def test_motion_run_resumes_bytewise_identical(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    deck = DECKS / "appendix_a_cube.inp"
    assert (
        run_cli(deck, "--motion", MOTION, "--tmax", 0.004, "--trace", "full.trace.txt", "--quiet")
        == 0
    )
    assert (
        run_cli(deck, "--motion", MOTION, "--tmax", 0.002, "--trace", "part.trace.txt", "--quiet")
        == 0
    )
    assert (
        run_cli(
            deck,
            "--motion",
            MOTION,
            "--tmax",
            0.004,
            "--trace",
            "part.trace.txt",
            "--restart",
            "--quiet",
        )
        == 0
    )
    for suffix in (".trace.txt", ".energy.csv"):
        assert (tmp_path / f"part{suffix}").read_bytes() == (
            tmp_path / f"full{suffix}"
        ).read_bytes()
