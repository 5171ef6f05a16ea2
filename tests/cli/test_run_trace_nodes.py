"""``x3dpd run --trace-nodes structure``: the TRACE card's structure nodes only (beam_64's 64
particles left out), for the post-processing commands that read a trace's structure; node ids
given; bad values refused."""

from __future__ import annotations

import json

from cli_helpers import DECKS, refused, run_cli

from x3dpd.io.trace import read_trace


def test_structure_only_traces_the_structure_and_frf_reads_it(tmp_path, capsys):
    full, light = tmp_path / "full.trace.txt", tmp_path / "light.trace.txt"
    deck = DECKS / "beam_64.inp"
    assert run_cli(deck, "--tmax", 0.003, "--trace", full, "-q") == 0
    assert run_cli(deck, "--tmax", 0.003, "--trace", light, "--trace-nodes", "structure", "-q") == 0
    a, b = read_trace(full), read_trace(light)
    assert a.node_ids.tolist() == list(range(9, 74)) and b.node_ids.tolist() == [9]
    assert (b.data[:, 0] == a.data[:, 0]).all()  # the same run: node 9's rows bit for bit
    assert light.stat().st_size * 60 < full.stat().st_size
    assert json.loads(light.with_name(light.name + ".json").read_text())["node_ids"] == [9]
    ids = tmp_path / "ids.trace.txt"
    assert run_cli(deck, "--tmax", 0.003, "--trace", ids, "--trace-nodes", "9,12", "-q") == 0
    assert read_trace(ids).node_ids.tolist() == [9, 12]


def test_bad_trace_nodes_are_refused_with_nothing_written(tmp_path, capsys):
    trace = tmp_path / "x.trace.txt"
    common = ("--tmax", 2e-8, "--trace", trace)
    refused(
        capsys,
        DECKS / "beam_64.inp",
        *common,
        "--trace-nodes",
        "tip",
        message="--trace-nodes 'tip': expected structure or node ids (9,12)",
        folder=tmp_path,
    )
    refused(
        capsys,
        DECKS / "impact_wall.inp",
        *common,
        "--trace-nodes",
        "structure",
        message="the deck's TRACE card names particles only",
        folder=tmp_path,
    )
