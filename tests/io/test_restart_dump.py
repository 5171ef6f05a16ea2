"""Restart dumps: bit-exact round trips, atomic replacement, refusal of foreign files."""

from __future__ import annotations

import json
import os
import zipfile

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from x3dpd.errors import InputError
from x3dpd.io.restart import META_MEMBER, RESTART_FORMAT, load_restart, save_restart


def assert_same(a: np.ndarray, b: np.ndarray) -> None:
    """Bit-exact equality: dtype (with byte order), shape and bytes."""
    assert a.dtype == b.dtype and a.shape == b.shape
    assert a.tobytes() == b.tobytes()


def state(seed=0):
    rng = np.random.default_rng(seed)
    return {
        "x": rng.normal(size=(5, 3)),
        "v": np.asfortranarray(rng.normal(size=(5, 6))),
        "step": np.int64(123456789),
        "contact_history": np.zeros((0, 3)),
        "pairs": np.zeros((0,), dtype=np.int32),
        "flags": np.array([True, False, True]),
        "omega_f32": rng.normal(size=4).astype(np.float32),
        "big_endian": np.arange(4, dtype=">f8"),
        "c": np.array([1 + 2j, np.nan + 1j]),
        "u8": np.array([0, 255], dtype=np.uint8),
        "i16": np.array([-32768, 32767], dtype=np.int16),
        "u64": np.array([2**64 - 1], dtype=np.uint64),
        "f16": np.array([1.5, -0.0], dtype=np.float16),
        "special": np.array([np.nan, np.inf, -np.inf, -0.0, 5e-324]),
        "names": np.array(["cavity", "particle"]),
        "raw": np.array([b"ab", b""]),
        "when": np.array(["2003-01-01"], dtype="datetime64[D]"),
        "scalar": np.array(2.5),
        "empty_3d": np.empty((2, 0, 4), dtype=np.int64),
        "rec": np.array([(1, 2.0)], dtype=[("id", "<i4"), ("m", "<f8")]),
    }


def test_round_trip_many_dtypes_and_shapes(tmp_path):
    arrays = state()
    meta = {
        "time": 1.25e-3,
        "step": np.int64(2500),
        "trace": {"bytes": 1020, "blocks": 2},
        "deck_sha256": "ab" * 32,
        "effects": ["gravity"],
        "ratio": np.float32(0.5),
    }
    path = tmp_path / "run.restart.npz"
    save_restart(path, arrays, meta)
    got, gmeta = load_restart(path)
    assert list(got) == list(arrays)
    for name, arr in arrays.items():
        assert_same(got[name], np.asarray(arr))
    assert got["v"].flags.f_contiguous
    assert gmeta == {
        "time": 1.25e-3,
        "step": 2500,
        "trace": {"bytes": 1020, "blocks": 2},
        "deck_sha256": "ab" * 32,
        "effects": ["gravity"],
        "ratio": 0.5,
    }
    with zipfile.ZipFile(path) as zf:  # one uncompressed .npz, numpy can open it
        assert all(i.compress_type == zipfile.ZIP_STORED for i in zf.infolist())
        assert json.loads(zf.read(META_MEMBER))["format"] == RESTART_FORMAT
    with np.load(path, allow_pickle=False) as npz:
        np.testing.assert_array_equal(npz["x"], arrays["x"])


@settings(max_examples=60, deadline=None)
@given(
    arr=hnp.arrays(
        dtype=st.one_of(hnp.scalar_dtypes(), hnp.byte_string_dtypes(), hnp.unicode_string_dtypes()),
        shape=hnp.array_shapes(min_dims=0, max_dims=4, min_side=0, max_side=4),
    )
)
def test_round_trip_property(tmp_path_factory, arr):
    path = tmp_path_factory.mktemp("rs") / "d.npz"
    save_restart(path, {"a": arr, "b": arr.T}, {"n": int(arr.size)})
    got, meta = load_restart(path)
    assert_same(got["a"], arr)
    assert_same(got["b"], arr.T)
    assert meta == {"n": arr.size}


def test_empty_dump(tmp_path):
    save_restart(tmp_path / "d.npz", {}, {})
    assert load_restart(tmp_path / "d.npz") == ({}, {})


@pytest.mark.parametrize("crash_in", ["replace", "write"])
def test_crash_mid_write_keeps_previous_dump(tmp_path, monkeypatch, crash_in):
    path = tmp_path / "run.restart.npz"
    old = state(1)
    save_restart(path, old, {"step": 1})
    before = path.read_bytes()

    if crash_in == "replace":

        def boom(*args, **kwargs):
            raise OSError("simulated crash before rename")

        monkeypatch.setattr(os, "replace", boom)
    else:
        real = np.lib.format.write_array
        calls = []

        def boom(*args, **kwargs):
            calls.append(1)
            if len(calls) == 3:
                raise KeyboardInterrupt  # interrupted half-way through the archive
            return real(*args, **kwargs)

        monkeypatch.setattr(np.lib.format, "write_array", boom)
    with pytest.raises((OSError, KeyboardInterrupt)):
        save_restart(path, state(2), {"step": 2})
    monkeypatch.undo()
    assert path.read_bytes() == before
    arrays, meta = load_restart(path)
    assert meta == {"step": 1}
    for name in old:
        assert_same(arrays[name], np.asarray(old[name]))
    assert os.listdir(tmp_path) == ["run.restart.npz"]  # no temporary left behind


def test_foreign_and_corrupt_files(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        load_restart(tmp_path / "none.npz")
    text = tmp_path / "deck.inp"
    text.write_text("TITLE\n")
    with pytest.raises(InputError, match="not a readable x3dpd restart dump"):
        load_restart(text)
    np.savez(tmp_path / "other.npz", x=np.arange(3))
    with pytest.raises(InputError, match="not an x3dpd restart dump"):
        load_restart(tmp_path / "other.npz")

    good = tmp_path / "good.npz"
    save_restart(good, {"x": np.arange(1000.0)}, {"step": 1})
    raw = good.read_bytes()
    (tmp_path / "trunc.npz").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(InputError, match="truncated or corrupt"):
        load_restart(tmp_path / "trunc.npz")
    flipped = bytearray(raw)
    i = raw.index(np.arange(1000.0)[500:501].tobytes())
    flipped[i] ^= 0xFF
    (tmp_path / "flip.npz").write_bytes(bytes(flipped))
    with pytest.raises(InputError, match="'x' of the restart dump is corrupt"):
        load_restart(tmp_path / "flip.npz")

    with zipfile.ZipFile(tmp_path / "future.npz", "w") as zf:
        zf.writestr(
            META_MEMBER, json.dumps({"format": "x3dpd-restart/9", "arrays": [], "meta": {}})
        )
    with pytest.raises(InputError, match="'x3dpd-restart/9'"):
        load_restart(tmp_path / "future.npz")
    with zipfile.ZipFile(tmp_path / "missing.npz", "w") as zf:
        zf.writestr(
            META_MEMBER, json.dumps({"format": RESTART_FORMAT, "arrays": ["x"], "meta": {}})
        )
    with pytest.raises(InputError, match=r"missing members \['x.npy'\]"):
        load_restart(tmp_path / "missing.npz")


def test_programming_errors(tmp_path):
    with pytest.raises(ValueError, match="object"):
        save_restart(tmp_path / "d.npz", {"o": np.array([{}, 1], dtype=object)}, {})
    for bad in ["", "a/b", ".hidden", META_MEMBER]:
        with pytest.raises(ValueError, match="not allowed"):
            save_restart(tmp_path / "d.npz", {bad: np.zeros(1)}, {})
    with pytest.raises(TypeError):
        save_restart(tmp_path / "d.npz", {}, {"f": object()})
    assert not os.listdir(tmp_path)
