"""Fixtures for the io tests: small synthetic traces."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.io.trace import TraceWriter


def synthetic(k: int, node_ids, seed: int = 0):
    """Times 0, 1e-3, ... and reproducible random (k, R, 9) data spanning many magnitudes."""
    rng = np.random.default_rng(seed)
    times = np.arange(k) * 1e-3
    data = rng.normal(size=(k, len(node_ids), 9)) * 10.0 ** rng.integers(-8, 4, size=(1, 1, 9))
    return times, data


@pytest.fixture
def make_trace(tmp_path):
    """make_trace(name, node_ids, times, data, **writer_kwargs) -> path of a finished trace."""

    def _make(name, node_ids, times, data, sidecar=None, **kw):
        path = tmp_path / name
        with TraceWriter(path, node_ids, sidecar or {"dt": 5e-7, "itrac": 2000}, **kw) as w:
            w.write_block(times, data)
        return path

    return _make


@pytest.fixture(name="synthetic")
def synthetic_fixture():
    """The :func:`synthetic` data generator."""
    return synthetic
