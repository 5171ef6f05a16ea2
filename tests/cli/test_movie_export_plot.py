"""``x3dpd movie``, ``export`` and ``plot`` on a short run of every shipped deck that runs."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import DECKS, SHORT_RUNS, run_cli

from x3dpd.analysis.export import read_lammps_dump
from x3dpd.analysis.scene import CYLINDER_FACETS, scene_from_model
from x3dpd.analysis.trace_plot import collect
from x3dpd.deck import read_deck
from x3dpd.io.trace import read_trace
from x3dpd.io.trace_stream import iter_blocks
from x3dpd.model.build import build_model

DECK_NAMES = sorted(SHORT_RUNS)


def _scene(name):
    tr = read_trace(SHORT_RUNS_TRACES[name])
    model = build_model(read_deck(DECKS / name))
    return tr, model, scene_from_model(model, tr.node_ids)


SHORT_RUNS_TRACES: dict[str, Path] = {}


@pytest.fixture(autouse=True)
def _traces(short_traces):
    SHORT_RUNS_TRACES.update(short_traces)


@pytest.mark.parametrize("name", DECK_NAMES)
def test_streamed_blocks_equal_the_whole_trace(name):
    tr = read_trace(SHORT_RUNS_TRACES[name])
    got = list(iter_blocks(SHORT_RUNS_TRACES[name], tr.node_ids.size, every=2))
    assert [t for t, _ in got] == tr.times[::2].tolist()
    for (_, data), ref in zip(got, tr.data[::2]):
        np.testing.assert_array_equal(data, ref)


@pytest.mark.parametrize("name", DECK_NAMES)
def test_cavity_moves_with_its_master_node(name):
    tr, model, scene = _scene(name)
    last = tr.data[-1]
    moved = scene.vertices(last) - scene.vertex_x0
    for v in range(scene.vertex_x0.shape[0]):
        m = scene.vertex_master_row[v]
        if m >= 0:  # a rigid slave: the master's translation since t = 0
            np.testing.assert_allclose(
                moved[v], tr.data[-1, m, :3] - tr.data[0, m, :3], rtol=0, atol=1e-12
            )
        elif scene.vertex_row[v] < 0:
            assert np.all(moved[v] == 0.0)  # a fixed wall stays put
    # the outline of a box is its 12 edges (no face diagonals); Fig. 28's lone square: 4; a
    # drawn cylinder its two rims of CYLINDER_FACETS edges; a capsule the two circles where its
    # hemispheres meet the bore
    n_edges = {
        "impact_wall.inp": 4,
        "cylinder_64.inp": 2 * CYLINDER_FACETS,
        "capsule_64.inp": 2 * CYLINDER_FACETS,
    }.get(name, 12)
    assert scene.outline.shape == (n_edges, 2)


@pytest.mark.parametrize("name", DECK_NAMES)
@pytest.mark.parametrize("ext", [".mp4", ".gif"])
def test_movie_has_one_frame_per_output_time(name, ext, tmp_path):
    import imageio_ffmpeg

    trace = SHORT_RUNS_TRACES[name]
    n = read_trace(trace).times.size
    out = tmp_path / f"m{ext}"
    assert run_cli("movie", trace, "-o", out, "--fps", 10) == 0
    if ext == ".mp4":
        reader = imageio_ffmpeg.read_frames(str(out))
        meta = reader.__next__()
        frames = sum(1 for _ in reader)
        assert meta["size"] == (768, 576) and frames == n
    else:
        from PIL import Image

        with Image.open(out) as im:
            assert im.n_frames == n and im.size == (768, 576)


def test_movie_still_shades_by_depth_and_every_skips(tmp_path):
    trace = SHORT_RUNS_TRACES["beam_64.inp"]
    assert run_cli("movie", trace, "-o", tmp_path / "a.png", "--at", 0.002) == 0
    from PIL import Image

    pixels = np.asarray(Image.open(tmp_path / "a.png").convert("RGB")).reshape(-1, 3)
    blues = {tuple(p) for p in pixels.astype(int) if p[2] > p[0] + 40}
    assert len(blues) > 3  # particles at several depths get several shades
    assert run_cli("movie", trace, "-o", tmp_path / "b.gif", "--every", 2) == 0
    from PIL import Image as I2

    with I2.open(tmp_path / "b.gif") as im:
        assert im.n_frames == math.ceil(read_trace(trace).times.size / 2)


@pytest.mark.parametrize("name", DECK_NAMES)
def test_vtk_export_reads_back_with_meshio(name, tmp_path):
    import meshio

    tr, model, scene = _scene(name)
    folder = tmp_path / "vtk"
    assert run_cli("export", SHORT_RUNS_TRACES[name], "--vtk", folder) == 0
    entries = ET.parse(folder / "run.pvd").getroot().find("Collection")
    parts = {}
    for ds in entries:
        parts.setdefault(ds.get("part"), []).append((float(ds.get("timestep")), ds.get("file")))
    assert [t for t, _ in parts["0"]] == tr.times.tolist()
    k = len(parts["0"]) - 1
    mesh = meshio.read(folder / parts["0"][k][1])
    p = scene.particle_rows
    np.testing.assert_array_equal(mesh.points, tr.data[k, p, :3])
    np.testing.assert_array_equal(mesh.point_data["velocity"], tr.data[k, p, 3:6])
    np.testing.assert_array_equal(mesh.point_data["spin"], tr.data[k, p, 6:9])
    ids = tr.node_ids[p]
    np.testing.assert_array_equal(
        mesh.point_data["radius"],
        model.radius[np.searchsorted(model.node_ids, ids) - model.particle_start],
    )
    cav = meshio.read(folder / parts["1"][k][1])
    np.testing.assert_array_equal(cav.cells_dict["triangle"], scene.tri)
    np.testing.assert_allclose(cav.points, scene.vertices(tr.data[k]), rtol=0, atol=0)


def test_lammps_dump_reads_back(tmp_path):
    tr, _, scene = _scene("beam_64.inp")
    out = tmp_path / "run.dump"
    assert run_cli("export", SHORT_RUNS_TRACES["beam_64.inp"], "--lammps", out) == 0
    frames = read_lammps_dump(out)
    assert [f[0] for f in frames] == tr.times.tolist()
    t, ids, cols = frames[-1]
    np.testing.assert_array_equal(ids, tr.node_ids[scene.particle_rows])
    np.testing.assert_allclose(
        cols[:, :9], tr.data[-1, scene.particle_rows], rtol=1e-9, atol=1e-15
    )  # 10 significant digits in the dump
    assert np.all(cols[:, 9] == 0.03125)


def test_lammps_dump_box_bounds_are_numbers_a_reader_parses(tmp_path):
    """Each frame's BOX BOUNDS are three lines of two plain numbers (LAMMPS's dump format), the
    cavity's bounding box at that time: at t0 the deck's beam cavity, x 0..0.263, y and z
    0..0.372 in. They were written as ``np.float64(0.0) np.float64(0.263)`` under numpy 2, which
    no dump reader (OVITO, LAMMPS's read_dump) parses; read_lammps_dump skipped them."""
    out = tmp_path / "run.dump"
    assert run_cli("export", SHORT_RUNS_TRACES["beam_64.inp"], "--lammps", out) == 0
    lines = out.read_text(encoding="ascii").splitlines()
    frames = [k for k, line in enumerate(lines) if line == "ITEM: BOX BOUNDS ff ff ff"]
    assert len(frames) == len(read_lammps_dump(out))
    for k in frames:
        bounds = [[float(v) for v in lines[k + 1 + a].split()] for a in range(3)]
        assert all(len(b) == 2 and b[0] < b[1] for b in bounds)
    first = [[float(v) for v in lines[frames[0] + 1 + a].split()] for a in range(3)]
    np.testing.assert_allclose(first, [[0.0, 0.263], [0.0, 0.372], [0.0, 0.372]], atol=1e-12)
    assert float(lines[3]) == 0.0  # ITEM: TIME, a plain number too


@pytest.mark.parametrize("name", DECK_NAMES)
def test_plot_writes_a_png_and_the_particle_kinetic_energy_is_right(name, tmp_path):
    tr, model, scene = _scene(name)
    out = tmp_path / "p.png"
    assert (
        run_cli(
            "plot",
            SHORT_RUNS_TRACES[name],
            "-o",
            out,
            "--quantity",
            "velocity",
            "--quantity",
            "acceleration",
        )
        == 0
    )
    assert out.stat().st_size > 10_000
    # KE from the deck's PDMP cards, computed here: m = rho 4/3 pi R^3, I = 2/5 m R^2
    deck = read_deck(DECKS / name)
    rho, r = deck.pdmp[0].prho, deck.pdmp[0].rzero
    m = rho * 4.0 / 3.0 * math.pi * r**3
    parts = [k for k, nid in enumerate(tr.node_ids) if nid > deck.pdmp[0].nodlim]
    v = tr.data[:, parts]
    expect = 0.5 * m * np.sum(v[..., 3:6] ** 2, axis=(1, 2)) + 0.5 * 0.4 * m * r * r * np.sum(
        v[..., 6:9] ** 2, axis=(1, 2)
    )
    hist = collect(iter_blocks(SHORT_RUNS_TRACES[name], tr.node_ids.size), scene, [(0, 0)])
    np.testing.assert_allclose(hist.ke_particles, expect, rtol=1e-12, atol=0)


@pytest.mark.parametrize(
    "args, words",
    [
        (["movie", "{trace}", "-o", "{tmp}/m.avi"], ["format"]),
        (["movie", "{trace}", "-o", "{tmp}/m.mp4", "--deck", "{tmp}/none.inp"], ["--deck"]),
        (["movie", "{tmp}/none.txt", "-o", "{tmp}/m.mp4"], ["no such trace"]),
        (["movie", "{trace}", "-o", "{tmp}/nodir/m.mp4"], ["does not exist"]),
        (["plot", "{trace}", "-o", "{tmp}/p.png", "--node", "99999"], ["not traced"]),
        (["plot", "{trace}", "-o", "{tmp}/p.png", "--dof", "rx"], ["rotation"]),
        (["export", "{trace}"], ["--vtk"]),
    ],
)
def test_bad_requests_are_one_line_errors(args, words, tmp_path, capsys):
    trace = SHORT_RUNS_TRACES["beam_1.inp"]
    argv = [a.format(trace=trace, tmp=tmp_path) for a in args]
    assert run_cli(*argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("x3dpd: error:") and "Traceback" not in err
    for w in words:
        assert w in err


def test_existing_outputs_are_kept_without_overwrite(tmp_path, capsys):
    trace = SHORT_RUNS_TRACES["beam_1.inp"]
    out = tmp_path / "m.gif"
    out.write_bytes(b"keep")
    assert run_cli("movie", trace, "-o", out) == 2
    assert out.read_bytes() == b"keep" and "--overwrite" in capsys.readouterr().err
    assert run_cli("movie", trace, "-o", out, "--overwrite") == 0
    assert out.read_bytes() != b"keep"


def test_deck_is_found_beside_a_moved_trace(tmp_path):
    """The sidecar's deck_path is relative to where the run started; a trace moved next to a
    copy of its deck still finds it."""
    import shutil

    src = SHORT_RUNS_TRACES["beam_1.inp"]
    for suffix in ("", ".json"):
        shutil.copy(str(src) + suffix, tmp_path / ("t.txt" + suffix))
    shutil.copy(DECKS / "beam_1.inp", tmp_path / "beam_1.inp")
    assert run_cli("movie", tmp_path / "t.txt", "-o", tmp_path / "m.png") == 0


def test_labels_follow_the_decks_declared_units(tmp_path):
    from x3dpd.cli._trace_scene import load_scene

    si = tmp_path / "beam_1_si.inp"
    si.write_text("UNITS\n  m N s\nEND\n" + (DECKS / "beam_1.inp").read_text())
    _, _, scene = load_scene(str(SHORT_RUNS_TRACES["beam_1.inp"]), str(si))
    assert (scene.units["length"], scene.units["energy"], scene.units["velocity"]) == (
        "m",
        "J",
        "m/s",
    )
    _, _, scene = load_scene(str(SHORT_RUNS_TRACES["beam_1.inp"]), None)
    assert scene.units["length"] == "in"


@pytest.mark.parametrize("name", DECK_NAMES)
def test_still_frames_the_particles(name, tmp_path):
    """The view holds the cavity and the particles (Fig. 28's sphere sits beside its lone wall,
    outside the wall's own extent)."""
    from PIL import Image

    from x3dpd.analysis.movie import write_movie

    tr, _, scene = _scene(name)
    lo, hi = scene.bounds(tr.data[0])
    p = tr.data[0, scene.particle_rows, :3]
    assert np.all(p - scene.radius[:, None] >= lo - 1e-12)
    assert np.all(p + scene.radius[:, None] <= hi + 1e-12)
    out = tmp_path / "s.png"
    assert write_movie(out, scene, iter([(tr.times[0], tr.data[0])])) == 1
    pixels = np.asarray(Image.open(out).convert("RGB")).reshape(-1, 3).astype(int)
    assert np.count_nonzero(pixels[:, 2] > pixels[:, 0] + 40) > 500  # particles drawn


def test_a_cavity_whose_master_is_not_traced_is_flagged(tmp_path, capsys):
    """beam_1 traced without its master node 9: the cavity cannot be placed; the command warns
    and draws it where the deck puts it."""
    text = (DECKS / "beam_1.inp").read_text()
    deck = tmp_path / "beam_1.inp"
    deck.write_text(text.replace("TRACE\n   9 10\n", "TRACE\n   10\n"))
    assert "TRACE\n   10\n" in deck.read_text()
    trace = tmp_path / "b.trace.txt"
    assert run_cli(deck, "--tmax", 0.001, "--trace", trace, "--quiet") == 0
    capsys.readouterr()
    assert run_cli("movie", trace, "-o", tmp_path / "m.png") == 0
    assert "8 wall vertices can move" in capsys.readouterr().err
    assert run_cli("movie", SHORT_RUNS_TRACES["beam_1.inp"], "-o", tmp_path / "n.png") == 0
    assert "warning" not in capsys.readouterr().err


def test_a_movie_outside_the_trace_s_times_says_where_they_are(tmp_path, capsys):
    """beam_64's short run writes output times from 0 to its end: a still --at after the end or
    a movie from after it is refused naming the trace's span (it said only "no output time in
    the requested range"), and nothing is written."""
    from cli_helpers import refused

    trace = SHORT_RUNS_TRACES["beam_64.inp"]
    last = float(read_trace(trace).times[-1])
    span = f"its output times run from 0 to {last:g} s: "
    refused(capsys, "movie", trace, "-o", tmp_path / "a.png", "--at", 99,
            message=span + "none at or after --at 99 s", folder=tmp_path)  # fmt: skip
    refused(capsys, "movie", trace, "-o", tmp_path / "b.gif", "--from", 98, "--to", 99,
            message=span + "none from 98 s to 99 s", folder=tmp_path)  # fmt: skip
