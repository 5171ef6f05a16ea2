"""Mode files read back to the analytic modes they were written from (tests/fixtures/modes/,
tools/make_mode_files.py), CSV and NPZ round trips are exact, ModeSet.select and
modes_from_matrices do what they say. Bad input: test_modal_file_errors.py."""

from __future__ import annotations

import numpy as np
import pytest
from modal_models import (
    CANTILEVER_BETA_L,
    FIXTURES,
    aligned,
    cantilever_fe,
    chain_closed_form,
    make_mode_files,
    need_pynastran,
)

from x3dpd.errors import ModeFileError
from x3dpd.deck.modes import (
    ModeSet,
    modes_from_matrices,
    read_modes,
    write_modes_csv,
    write_modes_npz,
)

TOOL = make_mode_files()

# An OP2 stores 32-bit floats: rounding to the nearest float32 changes a value by at most
# 2^-24 = 6.0e-8 of it, so 1e-7 relative holds every value.
OP2_RTOL = 1e-7
# A UFF dataset 55 writes E13.5, 6 significant digits: d.ddddd x 10^e is off by at most
# 0.5e-5 x 10^e <= 5e-6 of the value.
UFF_RTOL = 5e-6


def atol(shapes) -> float:
    """Slack for the two independent eigen-solutions (the tool's and the test's): round-off
    of a few eps times the largest value, far below the files' own rounding."""
    return 1e-12 * np.nanmax(np.abs(shapes))


def chain_expected():
    p = TOOL.CHAIN
    freq, phi = chain_closed_form(p["m"], p["k"], len(p["nodes"]))
    shapes = np.zeros((len(freq), len(p["nodes"]), 6))
    shapes[:, :, 0] = phi
    return freq, shapes


@pytest.mark.parametrize("name, rtol", [("chain3.op2", OP2_RTOL), ("chain3.uff", UFF_RTOL)])
def test_chain_reads_back_to_its_closed_form(name, rtol):
    if name.endswith(".op2"):
        need_pynastran()
    modes = read_modes(FIXTURES / name)
    freq, shapes = chain_expected()
    assert modes.path == str(FIXTURES / name)
    assert modes.mode_numbers.tolist() == [1, 2, 3]
    assert modes.node_ids.tolist() == list(TOOL.CHAIN["nodes"])
    np.testing.assert_allclose(modes.freq_hz, freq, rtol=rtol)
    # the OP2 gives all six components (0 off the x axis); the UFF file 3 (rotations NaN)
    got = modes.shapes
    if name.endswith(".uff"):
        assert np.isnan(got[:, :, 3:]).all()
        got, shapes = got[:, :, :3], shapes[:, :, :3]
    np.testing.assert_allclose(got, aligned(got, shapes), rtol=rtol, atol=atol(shapes))
    assert modes.shapes.dtype == np.float64 and modes.freq_hz.dtype == np.float64
    np.testing.assert_array_equal(modes.modal_mass, 1.0)  # LAMA / dataset 55: mass-normalised


def test_what_each_chain_file_declares():
    uff = read_modes(FIXTURES / "chain3.uff")
    assert uff.units == ("m", "N", "s")
    np.testing.assert_allclose(uff.damping, TOOL.CHAIN["damping"], rtol=UFF_RTOL)
    csv = read_modes(FIXTURES / "chain3.csv")
    assert csv.units == ("m", "N", "s") and csv.modal_mass is None
    np.testing.assert_array_equal(csv.damping, TOOL.CHAIN["damping"])
    freq, shapes = chain_expected()
    # the CSV holds the tool's float64 values: only the two eigen-solutions' round-off differs
    np.testing.assert_allclose(csv.freq_hz, freq, rtol=1e-12)
    np.testing.assert_allclose(
        csv.shapes[:, :, 0], aligned(csv.shapes, shapes)[:, :, 0], rtol=1e-12, atol=atol(shapes)
    )
    assert np.isnan(csv.shapes[:, :, 1:]).all()


@pytest.mark.parametrize("name, rtol", [("cantilever.op2", OP2_RTOL), ("cantilever.uff", UFF_RTOL)])
def test_cantilever_reads_back_to_its_beam_elements(name, rtol):
    if name.endswith(".op2"):
        need_pynastran()
    modes = read_modes(FIXTURES / name)
    freq, shapes = cantilever_fe(TOOL.CANTILEVER)
    assert modes.node_ids.tolist() == list(range(1, TOOL.CANTILEVER["elements"] + 2))
    np.testing.assert_allclose(modes.freq_hz, freq, rtol=rtol)
    np.testing.assert_allclose(
        modes.shapes, aligned(modes.shapes, shapes), rtol=rtol, atol=atol(shapes)
    )
    assert (modes.shapes[:, 0] == 0).all()  # the clamped node
    assert (modes.shapes[:, :, [0, 3]] == 0).all()  # no axial, no torsion freedom
    assert modes.units == (None if name.endswith(".op2") else ("in", "lbf", "s"))
    assert modes.damping is None


def test_cantilever_elements_approach_the_euler_bernoulli_beam():
    """The fixture's physics: frequencies from above (consistent-mass Hermite elements are a
    Rayleigh-Ritz approximation) within 0.1 % -- the element error is O(h^4) in the eigenvalue;
    five elements leave 5.0e-4 on the second bending mode (`python tools/make_mode_files.py`
    prints 1024.56 Hz against the 1024.05 Hz of f = (beta L)^2 / (2 pi L^2) sqrt(EI / rho A));
    and the tip of the first mode, mass-normalised, at 2 / sqrt(rho A L) (a clamped-free mode
    normalised to integral phi^2 dx = L is +-2 at the tip)."""
    modes = read_modes(FIXTURES / "cantilever.uff")
    p = TOOL.CANTILEVER
    area, L = p["b"] * p["h"], p["L"]
    exact = []
    for bl in CANTILEVER_BETA_L:
        for inertia in (p["b"] * p["h"] ** 3 / 12, p["h"] * p["b"] ** 3 / 12):  # z then y
            exact.append(bl**2 / (2 * np.pi * L**2) * np.sqrt(p["E"] * inertia / (p["rho"] * area)))
    exact = np.array(exact)
    assert (modes.freq_hz >= exact * (1 - UFF_RTOL)).all()
    assert (modes.freq_hz <= exact * 1.001).all()
    tip = modes.shapes[0, -1, 2]  # mode 1 bends in z (the thin direction)
    assert abs(abs(tip) - 2 / np.sqrt(p["rho"] * area * L)) <= 1e-3 * abs(tip)


def test_op2_and_uff_of_one_model_agree():
    need_pynastran()
    op2, uff = read_modes(FIXTURES / "cantilever.op2"), read_modes(FIXTURES / "cantilever.uff")
    np.testing.assert_allclose(uff.freq_hz, op2.freq_hz, rtol=UFF_RTOL + OP2_RTOL)
    np.testing.assert_allclose(
        uff.shapes, op2.shapes, rtol=UFF_RTOL + OP2_RTOL, atol=atol(op2.shapes)
    )


def rich_mode_set(path="rich"):
    """Values over many magnitudes, NaN for some components of some modes and for every
    component of one node, damping, modal masses and units: everything a ModeSet can hold."""
    rng = np.random.default_rng(7)
    shapes = rng.normal(size=(3, 4, 6)) * 10.0 ** rng.integers(-12, 6, size=(3, 4, 6))
    shapes[:, 1, 3:] = np.nan
    shapes[2, 3, :] = np.nan
    shapes[:, 2, :] = np.nan  # node 100: no value at all
    return ModeSet(
        path,
        [2, 5, 9],
        [0.0, 1 / 3, 12345.678901234567],
        [3, 7, 100, 2_000_000_000],
        shapes,
        damping=[0.0, 0.05, 0.999],
        modal_mass=[1.0, 2.5, 1e-9],
        units=("mm", "N", "s"),
    )


def assert_same(a: ModeSet, b: ModeSet):
    for field in ("mode_numbers", "freq_hz", "node_ids", "shapes", "damping", "modal_mass"):
        x, y = getattr(a, field), getattr(b, field)
        assert (x is None) == (y is None), field
        if x is not None:
            assert x.dtype == y.dtype, field
            np.testing.assert_array_equal(x, y, err_msg=field)  # exact; NaN where NaN
    assert a.units == b.units


@pytest.mark.parametrize("write, suffix", [(write_modes_csv, ".csv"), (write_modes_npz, ".npz")])
@pytest.mark.parametrize("source", ["rich", "chain3.uff", "cantilever.uff", "chain3.csv"])
def test_csv_and_npz_round_trips_are_exact(tmp_path, write, suffix, source):
    modes = rich_mode_set() if source == "rich" else read_modes(FIXTURES / source)
    path = tmp_path / ("copy" + suffix)
    write(path, modes)
    back = read_modes(path)
    assert back.path == str(path)
    assert_same(back, modes)


def test_csv_layout_as_a_person_or_a_spreadsheet_writes_it(tmp_path):
    path = tmp_path / "hand.csv"
    path.write_bytes(
        "\ufeff# modes of a test article\r\n"  # Excel's BOM, CRLF lines, a comment
        "units, in, lbf, s\r\n"
        "freq_hz,12.5,80\r\n"  # no blank second cell: fine
        "\r\n"
        "modal_mass,,2,2,,\r\n"  # trailing empty cells: padding
        "Node,DOF,1,2\r\n"
        "5,1,0.5,-0.25\r\n"
        "5,rz,1e-3,\r\n"  # an empty cell: no value
        '"3",Y,-1.5,2\r\n'
        "3,6.0,7,8\r\n".encode("utf-8")
    )
    modes = read_modes(path)
    assert modes.units == ("in", "lbf", "s")
    np.testing.assert_array_equal(modes.freq_hz, [12.5, 80.0])
    np.testing.assert_array_equal(modes.modal_mass, [2.0, 2.0])
    assert modes.damping is None
    assert modes.node_ids.tolist() == [3, 5]  # sorted
    expected = np.full((2, 2, 6), np.nan)
    expected[:, 1, 0] = [0.5, -0.25]
    expected[0, 1, 5] = 1e-3
    expected[:, 0, 1] = [-1.5, 2.0]
    expected[:, 0, 5] = [7.0, 8.0]
    np.testing.assert_array_equal(modes.shapes, expected)


def test_modes_and_nodes_come_sorted(tmp_path):
    path = tmp_path / "unsorted.csv"
    path.write_text("freq_hz,,30,10,20\nnode,dof,3,1,2\n9,x,3,1,2\n4,x,6,4,5\n")
    modes = read_modes(path)
    assert modes.mode_numbers.tolist() == [1, 2, 3]
    np.testing.assert_array_equal(modes.freq_hz, [10, 20, 30])
    assert modes.node_ids.tolist() == [4, 9]
    np.testing.assert_array_equal(modes.shapes[:, :, 0], [[4, 1], [5, 2], [6, 3]])


def test_select_by_numbers_and_band():
    modes = rich_mode_set()  # modes 2, 5, 9 at 0, 1/3, 12345.67... Hz
    one = modes.select(5)
    assert one.mode_numbers.tolist() == [5]
    np.testing.assert_array_equal(one.shapes, modes.shapes[1:2])
    np.testing.assert_array_equal(one.damping, [0.05])
    np.testing.assert_array_equal(one.modal_mass, [2.5])
    assert one.node_ids is modes.node_ids or np.array_equal(one.node_ids, modes.node_ids)
    assert modes.select([9, 2]).mode_numbers.tolist() == [2, 9]
    assert modes.select(band=(0.0, 1 / 3)).mode_numbers.tolist() == [2, 5]  # ends included
    assert modes.select(band=(0.1, np.inf)).mode_numbers.tolist() == [5, 9]
    assert modes.select([2, 9], band=(1, 1e6)).mode_numbers.tolist() == [9]
    assert modes.select().mode_numbers.tolist() == [2, 5, 9]


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"modes": [2, 4, 6]}, "rich: no mode 4, 6 in the file; it has modes 2, 5, 9"),
        ({"band": (1, 100)}, "rich: no mode between 1 and 100 Hz"),
        (
            {"modes": 2, "band": (1, 1e6)},
            "rich: no mode between 1 and 1e+06 Hz; the modes are at 0 Hz",
        ),
        ({"band": (5, 1)}, "rich: band (5, 1) Hz: expected lo <= hi"),
        ({"band": 5}, "rich: band must be (lo, hi) in Hz"),
        ({"modes": [1.5]}, "rich: modes to select must be mode numbers"),
    ],
)
def test_select_says_what_it_cannot_do(kwargs, words):
    with pytest.raises(ModeFileError) as e:
        rich_mode_set().select(**kwargs)
    assert str(e.value).startswith(words)


def test_mass_normalised_divides_by_the_root_of_the_modal_mass():
    modes = rich_mode_set()
    unit = modes.mass_normalised()
    np.testing.assert_array_equal(unit.modal_mass, 1.0)
    np.testing.assert_allclose(
        unit.shapes * np.sqrt([1.0, 2.5, 1e-9])[:, None, None], modes.shapes, rtol=1e-15
    )
    assert read_modes(FIXTURES / "chain3.csv").mass_normalised().modal_mass is None


def test_modes_from_matrices_matches_the_chain_closed_form():
    m, k, n = 3.0, 250.0, 5
    K = k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = k
    modes = modes_from_matrices(
        K,
        m * np.eye(n),
        [50, 40, 30, 20, 10],
        ["z"] * n,
        n_modes=4,
        damping=0.02,
        units=("m", "N", "s"),
    )
    freq, phi = chain_closed_form(m, k, n)
    np.testing.assert_allclose(modes.freq_hz, freq[:4], rtol=1e-12)
    # nodes come sorted: node 10 is the chain's last mass
    got = modes.shapes[:, ::-1, 2]
    np.testing.assert_allclose(got, aligned(got, phi[:4]), rtol=1e-10, atol=1e-13)
    big = np.abs(got).argmax(axis=1)
    assert (got[np.arange(4), big] > 0).all()  # the documented sign
    assert np.isnan(modes.shapes[:, :, [0, 1, 3, 4, 5]]).all()
    np.testing.assert_array_equal(modes.damping, 0.02)
    assert modes.path == "<matrices>" and modes.units == ("m", "N", "s")


def test_modes_from_matrices_keeps_rigid_body_modes_at_zero_hertz():
    K = 100.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])  # two free masses on one spring
    modes = modes_from_matrices(K, np.eye(2), [1, 2], [1, 1])
    assert modes.freq_hz[0] == 0.0
    np.testing.assert_allclose(modes.freq_hz[1], np.sqrt(200.0) / (2 * np.pi), rtol=1e-12)


@pytest.mark.parametrize(
    "K, M, nodes, dofs, words",
    [
        ([[1.0, 2.0], [0.0, 1.0]], np.eye(2), [1, 2], [1, 1], "K is not symmetric"),
        (np.eye(2), [[1.0, 0.0], [0.0, -1.0]], [1, 2], [1, 1], "M is not positive definite"),
        (-np.eye(2), np.eye(2), [1, 2], [1, 1], "K is not positive semi-definite"),
        (np.eye(2), np.eye(2), [1, 1], ["x", 1], "node 1 DOF 1 names more than one matrix row"),
        (np.eye(2), np.eye(2), [1, 2], [1, 7], "DOF '7': expected 1-6"),
        (np.eye(2), np.eye(3), [1, 2], [1, 1], "must be square matrices of one size"),
        (
            np.eye(2),
            np.eye(2),
            [1, 2, 3],
            [1, 1, 1],
            "3 node ids and 3 DOFs for matrices of size 2",
        ),
    ],
)
def test_modes_from_matrices_refuses_what_is_not_a_structure(K, M, nodes, dofs, words):
    with pytest.raises(ValueError, match=words):
        modes_from_matrices(K, M, nodes, dofs)


def test_the_csv_example_of_the_deck_reference_reads(tmp_path):
    doc = (FIXTURES.parents[2] / "docs" / "deck-reference.md").read_text()
    section = doc[doc.index("### CSV layout") :]
    block = section[section.index("    # comment") : section.index("\n\n*")]
    path = tmp_path / "example.csv"
    path.write_text("\n".join(line[4:] for line in block.splitlines()) + "\n")
    modes = read_modes(path)
    assert modes.mode_numbers.tolist() == [1, 2, 3] and modes.node_ids.tolist() == [101, 102]
    np.testing.assert_array_equal(modes.freq_hz, [12.5, 80.1, 220.4])
    np.testing.assert_array_equal(modes.shapes[:, 0, 1], [0.0001, 0.0002, np.nan])
    assert modes.units == ("m", "N", "s")
