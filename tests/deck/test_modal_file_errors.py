"""Every bad mode file is one ModeFileError (an InputError: exit status 2 at the CLI) whose
message starts with the file's name (and line, for CSV) and says what is wrong and what was
expected -- never a traceback from numpy, pyNastran or pyuff."""

from __future__ import annotations

import struct
import sys

import numpy as np
import pytest
import pyuff
from modal_models import FIXTURES, make_mode_files, need_pynastran
from pyuff.datasets.dataset_55 import prepare_55
from pyuff.datasets.dataset_58 import prepare_58
from pyuff.datasets.dataset_164 import prepare_164

from x3dpd.errors import InputError, ModeFileError
from x3dpd.deck.modes import ModeFileWarning, ModeSet, read_modes, write_modes_npz


def fails(path, *words, fmt=None, line=None):
    """Read ``path``; assert one ModeFileError that starts ``path:`` (``path:line:``) and
    contains each of ``words``."""
    with pytest.raises(ModeFileError) as e:
        read_modes(path, fmt)
    text = str(e.value)
    assert isinstance(e.value, InputError)
    start = f"{path}:{line}: " if line else f"{path}: "
    assert text.startswith(start), text
    for w in words:
        assert w in text, text
    return text


# -- any format ---------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".op2", ".uff", ".unv", ".csv", ".npz"])
def test_a_missing_file(tmp_path, suffix):
    fails(tmp_path / f"gone{suffix}", "no such file")


def test_a_directory_an_unknown_suffix_an_unknown_format(tmp_path):
    (tmp_path / "d.csv").mkdir()
    fails(tmp_path / "d.csv", "is a directory")
    (tmp_path / "modes.txt").write_text("freq_hz,,1\nnode,dof,1\n1,x,1\n")
    fails(tmp_path / "modes.txt", "suffix '.txt'", "expected .op2, .uff, .unv, .csv or .npz")
    assert read_modes(tmp_path / "modes.txt", fmt="CSV").n_modes == 1  # the format given wins
    fails(tmp_path / "modes.txt", "unknown mode-file format 'bdf'", fmt="bdf")


@pytest.mark.parametrize(
    "source, target, words",
    [
        ("chain3.npz", "x.csv", "binary data (a NUL byte); expected a CSV text file"),
        ("chain3.csv", "x.npz", "not a numpy .npz archive"),
        ("chain3.uff", "x.op2", "does not start as an OP2 file does"),
        ("chain3.op2", "x.uff", "no universal-file datasets"),
        ("chain3.csv", "x.unv", "no universal-file datasets"),
    ],
)
def test_a_file_that_is_not_what_its_suffix_says(tmp_path, source, target, words):
    if source == "chain3.npz":
        write_modes_npz(tmp_path / source, read_modes(FIXTURES / "chain3.csv"))
        data = (tmp_path / source).read_bytes()
    else:
        data = (FIXTURES / source).read_bytes()
    (tmp_path / target).write_bytes(data)
    fails(tmp_path / target, words, line=1 if target.endswith(".csv") else None)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"mode_numbers": [], "freq_hz": [], "shapes": np.zeros((0, 1, 6))}, "holds no modes"),
        ({"node_ids": [], "shapes": np.zeros((1, 0, 6))}, "gives no node values"),
        ({"mode_numbers": [0]}, "mode number 0: expected mode numbers >= 1"),
        ({"freq_hz": [-1.0]}, "mode 1 has frequency -1 Hz; expected a finite number >= 0"),
        ({"freq_hz": [np.nan]}, "mode 1 has frequency nan Hz"),
        ({"damping": [1.0]}, "mode 1 has damping ratio 1; expected a finite number in [0, 1)"),
        ({"modal_mass": [0.0]}, "mode 1 has modal mass 0; expected a finite number > 0"),
        ({"shapes": np.full((1, 1, 6), np.inf)}, "mode 1 has an infinite value at node 4 x"),
        ({"shapes": np.full((1, 1, 6), np.nan)}, "mode 1 has no shape values"),
        ({"shapes": np.zeros((1, 2, 6))}, "shapes have shape (1, 2, 6); expected (1, 1, 6)"),
        ({"units": ("m", "kg", "s")}, "units: FORCE unit 'kg': expected one of lbf, N, kN, dyn"),
        ({"mode_numbers": [1.5]}, "mode numbers must be integers"),
        ({"node_ids": [4, 4], "shapes": np.zeros((1, 2, 6))}, "node id 4 appears more than once"),
    ],
)
def test_a_mode_set_that_does_not_hold_together(kwargs, words):
    fields = {
        "mode_numbers": [1],
        "freq_hz": [1.0],
        "node_ids": [4],
        "shapes": np.zeros((1, 1, 6)),
    } | kwargs
    with pytest.raises(ModeFileError) as e:
        ModeSet("f.npz", **fields)
    assert str(e.value).startswith("f.npz: ") and words in str(e.value), str(e.value)


# -- CSV ------------------------------------------------------------------------------------------

GOOD = [
    "units,m,N,s",
    "freq_hz,,10,20",
    "damping,,0.01,0.02",
    "node,dof,1,2",
    "1,x,1,2",
    "1,y,3,4",
    "2,z,5,6",
]


def csv_with(tmp_path, replace: dict[int, str] | None = None, lines=None):
    lines = list(GOOD if lines is None else lines)
    for i, text in sorted((replace or {}).items(), reverse=True):
        if text is None:
            del lines[i]
        else:
            lines[i] = text
    path = tmp_path / "m.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_good_csv_reads(tmp_path):
    modes = read_modes(csv_with(tmp_path))
    assert modes.n_modes == 2 and modes.node_ids.tolist() == [1, 2]


@pytest.mark.parametrize(
    "replace, line, words",
    [
        ({3: None}, None, "no 'node,dof,MODE,...' header row"),
        ({3: "node,comp,1,2"}, 4, "header row reads 'node,comp,1,2'; expected node,dof,MODE1"),
        ({3: "node,dof"}, 4, "the header row names no mode"),
        ({3: "node,dof,1,one"}, 4, "mode number 'one': expected an integer"),
        ({3: "node,dof,1,1"}, 4, "mode 1 heads more than one column"),
        ({1: None}, 3, "no freq_hz row; expected freq_hz,,F1,F2,"),
        ({1: "freq_hz,,10,-20"}, 2, "freq_hz of mode 2 is -20; expected >= 0 Hz"),
        ({1: "freq_hz,,10,"}, 2, "freq_hz: 1 value(s) for 2 mode columns"),
        ({1: "freq_hz,,,10"}, 2, "freq_hz of mode 1 is empty; expected a number"),
        ({1: "freq_hz,,10,20,30"}, 2, "freq_hz: 3 value(s) for 2 mode columns"),
        ({1: "freq_hz,,10,nan"}, 2, "freq_hz of mode 2 is 'nan'; expected a finite number"),
        ({2: "damping,,0.01,1.5"}, 3, "damping of mode 2 is 1.5; expected in [0, 1)"),
        ({2: "modal_mass,,1,0"}, 3, "modal_mass of mode 2 is 0; expected > 0"),
        ({2: "freq_hz,,1,2"}, 3, "a second freq_hz row (the first is at line 2)"),
        ({2: "frequency,,1,2"}, 3, "row 'frequency' before the node,dof header; expected one of"),
        ({0: "units,m,kg,s"}, 1, "units: FORCE unit 'kg'"),
        ({4: "1,x,1,inf"}, 5, "node 1 x of mode 2 is 'inf'; expected a finite number"),
        ({4: "1,x,1,NaN"}, 5, "node 1 x of mode 2 is 'NaN'; expected a finite number"),
        ({4: "1,x,1,0x3"}, 5, "node 1 x of mode 2: '0x3' is not a number"),
        ({4: "1,x,1,2,3"}, 5, "node 1 x: 3 value(s) for 2 mode columns"),
        ({5: "1,tx,3,4"}, 6, "node 1 x already has a row at line 5; expected one row per node"),
        ({5: "1,q,3,4"}, 6, "DOF 'q': expected 1-6 or one of x, y, z, rx, ry, rz"),
        ({5: "1.5,y,3,4"}, 6, "node id '1.5': expected an integer"),
        ({5: "7"}, 6, "row '7': expected NODE,DOF,VALUE"),
        ({5: "damping,,1,2"}, 6, "damping row after the node,dof header; expected it before"),
        ({4: None, 5: None, 6: None}, 4, "the table has no node rows"),
        ({4: "1,x,1,", 5: "1,y,3,", 6: "2,z,5,"}, 4, "mode 2 has no value in any row"),
        ({4: "1;x;1;2"}, 5, "cells separated by ';'; expected commas"),
    ],
)
def test_csv_errors_name_the_line(tmp_path, replace, line, words):
    fails(csv_with(tmp_path, replace), words, line=line)


def test_csv_bytes_that_are_not_text(tmp_path):
    path = tmp_path / "m.csv"
    path.write_bytes(b"freq_hz,,1\nnode,dof,1\n1,x,\xff\xfe\n")
    fails(path, "bytes that are not UTF-8 text", line=3)
    path.write_bytes(b"")
    fails(path, "no 'node,dof,MODE,...' header row")


# -- NPZ ------------------------------------------------------------------------------------------


def npz_with(tmp_path, drop=(), **arrays):
    base = {
        "mode_numbers": np.array([1, 2]),
        "freq_hz": np.array([1.0, 2.0]),
        "node_ids": np.array([5]),
        "shapes": np.ones((2, 1, 6)),
    }
    base.update(arrays)
    path = tmp_path / "m.npz"
    np.savez(path, **{k: v for k, v in base.items() if k not in drop})
    return path


@pytest.mark.parametrize(
    "drop, arrays, words",
    [
        (("shapes",), {}, "no array shapes; it holds freq_hz, mode_numbers, node_ids"),
        ((), {"dampng": np.zeros(2)}, "unknown array(s) dampng; expected mode_numbers"),
        (
            (),
            {"shapes": np.ones((2, 1, 3))},
            "array shapes has shape (2, 1, 3); expected (2, 1, 6)",
        ),
        ((), {"freq_hz": np.array([1.0])}, "array freq_hz has 1 values for 2 modes"),
        ((), {"freq_hz": np.array([1.0, np.nan])}, "mode 2 has frequency nan Hz"),
        ((), {"freq_hz": np.array([1.0, -2.0])}, "mode 2 has frequency -2 Hz; expected"),
        ((), {"shapes": np.full((2, 1, 6), -np.inf)}, "mode 1 has an infinite value at node 5 x"),
        ((), {"mode_numbers": np.array([3, 3])}, "mode number 3 appears more than once"),
        (
            (),
            {"node_ids": np.array([5, 5]), "shapes": np.ones((2, 2, 6))},
            "node id 5 appears more than once",
        ),
        (
            (),
            {
                "mode_numbers": np.zeros(0, int),
                "freq_hz": np.zeros(0),
                "shapes": np.ones((0, 1, 6)),
            },
            "holds no modes",
        ),
        ((), {"units": np.array([1, 2, 3])}, "array units is int64 (3,); expected 3 strings"),
        ((), {"units": np.array(["m", "N", "h"])}, "units: TIME unit 'h'"),
        (
            (),
            {"node_ids": np.array([[5]])},
            "array node_ids has shape (1, 1); expected one dimension",
        ),
        ((), {"damping": np.array(["a", "b"])}, "array damping holds <U1 values; expected numbers"),
    ],
)
def test_npz_errors(tmp_path, drop, arrays, words):
    fails(npz_with(tmp_path, drop, **arrays), words)


def test_npz_that_is_a_single_array_or_an_object_array(tmp_path):
    path = tmp_path / "m.npz"
    with open(path, "wb") as f:
        np.save(f, np.zeros(3))
    fails(path, "a single .npy array, not a .npz archive")
    fails(
        npz_with(tmp_path, freq_hz=np.array([1.0, None], dtype=object)), "an array cannot be read"
    )


# -- UFF ------------------------------------------------------------------------------------------


def mode55(mode=1, freq=10.0, nodes=(1, 2), values=None, ndv=3, **kw):
    values = (
        np.arange(1.0, 1 + len(nodes) * ndv).reshape(len(nodes), ndv)
        if values is None
        else np.asarray(values, dtype=float)
    )
    fields = dict(
        model_type=1,
        analysis_type=2,
        data_ch=2 if ndv == 3 else 3,
        spec_data_type=8,
        data_type=2,
        n_data_per_node=ndv,
        node_nums=np.asarray(nodes),
        load_case=1,
        mode_n=mode,
        freq=freq,
        modal_m=0.0,
        modal_damp_vis=0.0,
        modal_damp_his=0.0,
        **{f"r{c + 1}": values[:, c] for c in range(ndv)},
    )
    fields.update(kw)
    return prepare_55(**fields)


def units164(code, length=1.0, force=1.0):
    return prepare_164(
        units_code=code,
        units_description="test",
        temp_mode=1,
        length=length,
        force=force,
        temp=1.0,
        temp_offset=273.15,
    )


def frf58():
    return prepare_58(
        binary=0,
        id1="frf",
        func_type=4,
        rsp_node=1,
        rsp_dir=1,
        ref_node=1,
        ref_dir=1,
        data=np.ones(4) + 0j,
        x=np.arange(4.0),
        abscissa_spacing=1,
        abscissa_spec_data_type=18,
        ordinate_spec_data_type=12,
        orddenom_spec_data_type=13,
    )


def uff_with(tmp_path, *sets, name="m.uff"):
    path = tmp_path / name
    pyuff.UFF(str(path)).write_sets(list(sets), mode="overwrite")
    return path


def test_uff_with_no_dataset_55_says_what_it_holds(tmp_path):
    fails(
        uff_with(tmp_path, units164(1), frf58(), frf58()),
        "no dataset 55 (normal modes); it holds dataset 164 (units), 2 datasets 58 "
        "(function at nodal DOF)",
    )


def test_uff_with_other_analysis_types(tmp_path):
    frf = mode55(analysis_type=5, freq_step_n=1)
    fails(
        uff_with(tmp_path, frf),
        "its datasets 55 are frequency response data; expected analysis type 2 (normal mode)",
    )


@pytest.mark.parametrize(
    "sets, words",
    [
        ([mode55(1), mode55(1, freq=20.0)], "mode number 1 appears more than once"),
        ([mode55(1, freq=-5.0)], "mode 1 has frequency -5 Hz; expected a finite number >= 0"),
        ([mode55(2, nodes=(3, 3))], "node 3 appears more than once in mode 2's dataset 55"),
        ([mode55(1, values=[[1, np.nan, 2]], nodes=(4,))], "mode 1 has value nan at node 4"),
        ([mode55(1, modal_m=1.0), mode55(2, modal_m=0.0)], "mode 2 has modal mass 0; expected"),
        ([mode55(1, modal_damp_vis=2.0)], "mode 1 has damping ratio 2; expected"),
        (
            [units164(5, 1000.0, 1000.0), mode55()],
            (
                "dataset 164 declares units code 5 (test) with length factor 1000.0 and force factor "
                "1000.0, which x3dpd cannot name"
            ),
        ),
        ([units164(1), units164(7), mode55()], "its datasets 164 declare different units"),
    ],
)
def test_uff_errors(tmp_path, sets, words):
    fails(uff_with(tmp_path, *sets), words)


def test_uff_tensor_data_is_not_a_mode_shape(tmp_path):
    path = uff_with(tmp_path, mode55(ndv=6, data_ch=4))  # 4: symmetric global tensor (stress)
    fails(path, "mode 1 gives 6 values per node (data characteristic 4); expected 3 (x y z) or 6")


def test_uff_damaged_dataset(tmp_path):
    path = uff_with(tmp_path, mode55())
    text = path.read_text().splitlines()
    text[10] = "  not a number"
    path.write_text("\n".join(text) + "\n")
    fails(path, "a dataset 55 cannot be read")


def test_uff_units_from_factors_and_what_is_left_out(tmp_path):
    modes = read_modes(
        uff_with(
            tmp_path,
            units164(9, 1000.0, 1.0),
            mode55(3, nodes=(1, 2)),
            mode55(1, nodes=(2,), ndv=6, values=[[1, 2, 3, 4, 5, 6]]),
        )
    )
    assert modes.units == ("mm", "N", "s")
    assert modes.mode_numbers.tolist() == [1, 3]
    # mode 1 leaves node 1 out: 0 there (UFF note 9); mode 3 gives 3 values: rotations NaN
    np.testing.assert_array_equal(modes.shapes[0, 0], 0.0)
    np.testing.assert_array_equal(modes.shapes[0, 1], [1, 2, 3, 4, 5, 6])
    assert np.isnan(modes.shapes[1, :, 3:]).all()
    assert modes.damping is None and modes.modal_mass is None


def test_uff_hysteretic_damping_is_not_read_and_says_so(tmp_path):
    path = uff_with(tmp_path, mode55(modal_damp_his=0.02))
    with pytest.warns(ModeFileWarning, match="hysteretic damping ratios are not read"):
        modes = read_modes(path)
    assert modes.damping is None


# -- OP2 ------------------------------------------------------------------------------------------


def test_op2_that_is_not_one(tmp_path):
    (tmp_path / "e.op2").write_bytes(b"")
    fails(tmp_path / "e.op2", "0 bytes long; expected a Nastran OP2 file")
    (tmp_path / "t.op2").write_text("SOL 103\nCEND\n")
    fails(tmp_path / "t.op2", "does not start as an OP2 file does (it starts 'SOL ')")


def test_op2_without_pynastran_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyNastran.op2.op2", None)
    fails(
        FIXTURES / "chain3.op2",
        "reading OP2 files needs pyNastran",
        "pip install --no-deps pyNastran==1.4.1",
    )


def test_op2_cut_short(tmp_path):
    need_pynastran()
    data = (FIXTURES / "chain3.op2").read_bytes()
    (tmp_path / "c.op2").write_bytes(data[: len(data) // 2])
    fails(tmp_path / "c.op2", "ends inside an OP2 record (cut short?)")
    (tmp_path / "c.op2").write_bytes(data[:200])  # inside LAMA's header: pyNastran's own words
    fails(tmp_path / "c.op2", "pyNastran cannot read it as an OP2 file (", "table_name=b'LAMA'")


def test_op2_without_eigenvectors_or_without_lama(tmp_path):
    need_pynastran()
    tool = make_mode_files()
    chain = tool.chain_modes()
    tool.write_op2(tmp_path / "lama.op2", chain, tool.CHAIN["nodes"], tables=("LAMA",))
    fails(
        tmp_path / "lama.op2",
        "no real eigenvectors (SOL 103 OUGV1, table code 7) in the file; it holds the tables LAMA",
    )
    tool.write_op2(tmp_path / "vec.op2", chain, tool.CHAIN["nodes"], tables=("OUGV1",))
    modes = read_modes(tmp_path / "vec.op2")  # frequency from the eigenvalues: sqrt(lambda)/2pi
    np.testing.assert_allclose(modes.freq_hz, chain.freq_hz, rtol=1e-7)  # float32 lambda
    assert modes.modal_mass is None


def test_op2_with_a_nan(tmp_path):
    need_pynastran()
    data = (FIXTURES / "chain3.op2").read_bytes()
    value = struct.pack("<f", np.float32(read_modes(FIXTURES / "chain3.op2").shapes[0, 2, 0]))
    assert data.count(value) >= 1  # the shapes come after LAMA: the first is a shape value
    (tmp_path / "n.op2").write_bytes(data.replace(value, struct.pack("<f", np.nan), 1))
    fails(tmp_path / "n.op2", "NaN in the eigenvectors; expected finite numbers")
