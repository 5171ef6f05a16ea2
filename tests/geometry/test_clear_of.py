"""Every analytic wall shape's ``clear_of`` (the step loop skips a sphere it calls clear whose
contacts are all closed, x3dpd.geometry.shapes) against its own locator: never clear where a
part touches -- also with the sphere's centre a few units in the last place from touching --
and clear where every part keeps its distance, so that the skip does happen."""

from __future__ import annotations

import numpy as np
import pytest

from x3dpd.geometry.shapes import MAX_SHAPE_PARTS, SHAPES

WITH_CLEAR = [s for s in SHAPES if s.clear_of is not None]


def _wall(shape, rng):
    """Nodes A, B (a tilted axis), the shape's parameter row, the wall's radius."""
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    a = rng.uniform(-1, 1, size=3)
    length, big_r = 0.8, 0.3
    lengths = (big_r, 0.7)[: len(shape.param_fields)]  # RADIUS (and a holes' PITCH)
    ends = np.stack([a, a + length * u])
    row = list(lengths) + (list(shape.constants(ends, lengths)) if shape.constants else [])
    return ends, np.array([row]), big_r


def test_the_shapes_that_skip_clear_spheres():
    assert {s.name for s in WITH_CLEAR} == {"cylinder", "capsule", "holes"}


@pytest.mark.parametrize("shape", WITH_CLEAR, ids=lambda s: s.name)
def test_clear_only_where_no_part_touches(shape):
    rng = np.random.default_rng(11)
    ends, params, big_r = _wall(shape, rng)
    out = np.zeros((MAX_SHAPE_PARTS, 9))
    clear_count = touching_count = 0
    for n in range(4000):
        r = rng.uniform(0.05, 0.25)
        # a centre in the wall's box, every fourth at the sphere's touching distance from the
        # nearest part within a few units in the last place
        p = ends[0] + rng.uniform(-0.1, 1.0) * (ends[1] - ends[0]) + rng.normal(size=3) * big_r
        if n % 4 == 0:
            gap, _ = shape.clearance(p[None, :], np.array([0.0]), ends, params[0, :2])
            # the centre's own gap: a sphere of that radius just touches
            r = float(gap[0]) * (1.0 + rng.integers(-30, 31) * np.finfo(float).eps)
            if not r > 0.0:
                continue
        shape.locate_parts(ends, 0, 1, params, 0, *p, r, out)
        touching = any(out[k, 0] != 0.0 and out[k, 1] > 0.0 for k in range(shape.parts))
        clear = shape.clear_of(ends, 0, 1, params, 0, *p, r)
        assert not (clear and touching), (shape.name, p, r, out[: shape.parts])
        gap, inside = shape.clearance(p[None, :], np.array([r]), ends, params[0, :2])
        if inside[0] and gap[0] > 1e-9 * big_r:
            assert clear, (shape.name, p, r, gap)
        clear_count += clear
        touching_count += touching
    assert clear_count > 300 and touching_count > 300
