"""MATID types 2 (axial spring-damper) and 3 (rotational spring-damper) in the deck, the model
and `x3dpd check`: what a deck builds, the errors at FILE:LINE:COL, the writer's round trip and
the step estimate. (Their dynamics: tests/physics/test_axial_rotational_springs.py.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

import x3dpd
from x3dpd.deck import format_deck, parse_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model

#: Line numbers of the records below (1-based).
DECK = """\
PARAMETERS
   0.0 1.0 0.0 1e-5 1e-5 0 1e12 0 5 0 10
END
MATID
   1 1 0.0 1.0 5.0 6.0 7.0 0.1
   2 2 0.2 3.0 40.0 0.0 0.0 0.5
   3 3 0.0 2.0 10.0 20.0 30.0 0.25
END
NODE COORDINATES
   1 0.0 0.0 0.0
   2 3.0 4.0 12.0
   3 1.0 1.0 1.0
   4 2.0 2.0 2.0
END
ELEMENTS
   1 1 3
   2 2 1 2
   3 3 3 4
   4 3 4
END
MASS
   2 1.5
   3 1.0 0.5 0.5 0.5
   4 1.0 2.0 3.0 4.0
END
BOUNDARY CONDITIONS
   1 1 1 1 2 3 4 5 6
   2 2 1 4 5 6
END
"""
LINE_MATID = 5  # first MATID record
LINE_ELEMENTS = 16  # first ELEMENTS record


def _lines(text: str, **changes: str) -> str:
    """``text`` with line n (1-based) replaced: ``_lines(DECK, l6="...")``."""
    lines = text.splitlines()
    for key, value in changes.items():
        lines[int(key[1:]) - 1] = value
    return "\n".join(lines) + "\n"


def _error(text: str) -> DeckError:
    with pytest.raises(DeckError) as info:
        build_model(parse_deck(text, "springs.inp"))
    return info.value


def test_the_three_types_build_their_own_arrays():
    model = build_model(parse_deck(DECK, "springs.inp"))
    ix = model.index_of
    # type 1: as X3D's, axis-aligned, SCALE 1
    np.testing.assert_array_equal(model.spring_nodes, [[ix(3), -1]])
    np.testing.assert_array_equal(model.spring_k, [[5.0, 6.0, 7.0]])
    np.testing.assert_array_equal(model.spring_c, [[0.1, 0.1, 0.1]])
    # type 2: along the line of nodes 1 and 2, L0 = |(3, 4, 12)| = 13, SCALE 3 on k and c
    np.testing.assert_array_equal(model.axial_nodes, [[ix(1), ix(2)]])
    np.testing.assert_array_equal(model.axial_k, [120.0])
    np.testing.assert_array_equal(model.axial_c, [1.5])
    np.testing.assert_array_equal(model.axial_length, [13.0])
    # type 3: between nodes 3 and 4, and node 4 to ground; SCALE 2
    np.testing.assert_array_equal(model.rotational_nodes, [[ix(3), ix(4)], [ix(4), -1]])
    np.testing.assert_array_equal(model.rotational_k, [[20.0, 40.0, 60.0]] * 2)
    np.testing.assert_array_equal(model.rotational_c, [[0.5, 0.5, 0.5]] * 2)
    # element mass lumped half on each end as for type 1 (0.2 of material 2)
    assert model.mass[ix(1)] == 0.1 and model.mass[ix(2)] == 1.5 + 0.1
    assert {"axial_springs", "rotational_springs", "springs", "dampers"} <= model.effects


def test_a_deck_of_type_1_only_calls_for_no_new_effect():
    text = _lines(DECK, l6="   2 1 0.0 1.0 1.0 0.0 0.0 0.0", l7="   3 1 0.0 1.0 1.0 1.0 1.0 0.0")
    model = build_model(parse_deck(text, "springs.inp"))
    assert not {"axial_springs", "rotational_springs"} & model.effects
    assert model.axial_nodes.shape == (0, 2) and model.rotational_nodes.shape == (0, 2)


def test_unknown_type_is_an_error_at_its_record():
    err = _error(_lines(DECK, l6="   2 4 0.2 3.0 40.0 0.0 0.0 0.5"))
    assert str(err).startswith(f"springs.inp:{LINE_MATID + 1}:4: MATID: material 2 has type 4")
    assert "1 = spring-damper along the global x, y, z axes" in err.message
    assert "2 = spring-damper along the line between two nodes" in err.message
    assert "3 = rotational spring-damper" in err.message


def test_type_2_to_ground_is_an_error_at_the_element():
    err = _error(_lines(DECK, l17="   2 2 2"))
    assert str(err).startswith(
        f"springs.inp:{LINE_ELEMENTS + 1}:4: ELEMENTS: element 2 uses material 2 of type 2"
    )
    assert "has one node" in err.message and "type 1" in err.message


def test_type_2_between_coincident_nodes_is_an_error_at_the_element():
    err = _error(_lines(DECK, l11="   2 0.0 0.0 0.0"))
    assert str(err).startswith(f"springs.inp:{LINE_ELEMENTS + 1}:4: ELEMENTS: element 2 ")
    assert "nodes 1 and 2 have the same coordinates (lines 10 and 11)" in err.message


def test_type_2_takes_kx_alone():
    err = _error(_lines(DECK, l6="   2 2 0.2 3.0 40.0 1.0 0.0 0.5"))
    assert str(err).startswith(f"springs.inp:{LINE_MATID + 1}:4: MATID: material 2 is of type 2")
    assert "KY and KZ must be 0" in err.message


def test_rotational_spring_on_a_node_without_inertia_is_an_error():
    err = _error(_lines(DECK, l24="   4 1.0 2.0 0.0 4.0"))  # Iyy = 0, ry free
    assert str(err).startswith(
        "springs.inp:13:4: NODE COORDINATES: node 4 has no rotary inertia about y"
    )
    assert "element 3 (line 18)" in err.message and "fix DOF 5" in err.message
    # a fixed DOF needs none
    fixed = _lines(DECK, l24="   4 1.0 2.0 0.0 4.0", l28="   2 2 1 4 5 6\n   4 4 1 5")
    build_model(parse_deck(fixed, "springs.inp"))


def test_the_writer_round_trips_the_new_types():
    deck = parse_deck(DECK, "springs.inp")
    again = parse_deck(format_deck(deck), "again.inp")
    assert [m.mtype for m in again.materials] == [1, 2, 3]
    a, b = build_model(deck), build_model(again)
    for name in (
        "spring_nodes",
        "spring_k",
        "spring_c",
        "axial_nodes",
        "axial_k",
        "axial_c",
        "axial_length",
        "rotational_nodes",
        "rotational_k",
        "rotational_c",
        "mass",
    ):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def _check_omega(text: str):
    ts = x3dpd.check(parse_deck(text, "springs.inp")).time_step
    return ts.omega_max, ts.omega_node, ts.omega_dof


def _only(
    records_matid: list[str], elements: list[str], masses: list[str], boundaries: list[str]
) -> str:
    nodes = ["1 0.0 0.0 0.0", "2 3.0 4.0 12.0"]

    def card(name, records):
        return [name, *(f"   {r}" for r in records), "END"]

    return (
        "\n".join(
            [
                "PARAMETERS",
                "   0.0 1.0 0.0 1e-5 1e-5 0 1e12 0 5 0 10",
                "END",
                *card("MATID", records_matid),
                *card("NODE COORDINATES", nodes),
                *card("ELEMENTS", elements),
                *card("MASS", masses),
                *card("BOUNDARY CONDITIONS", boundaries),
            ]
        )
        + "\n"
    )


def test_check_bounds_an_axial_spring_by_sqrt_k_over_m():
    """A mass m on an axial spring k to a fixed node has the one frequency sqrt(k/m), whatever
    the spring's direction: the check's bound is that exactly (each axis counts k)."""
    text = _only(
        ["2 2 0.0 1.0 400.0 0.0 0.0 0.0"],
        ["1 2 1 2"],
        ["2 4.0"],
        ["1 1 1 1 2 3 4 5 6", "2 2 1 4 5 6"],
    )
    omega, node, dof = _check_omega(text)
    assert omega == pytest.approx(math.sqrt(400.0 / 4.0), rel=1e-15)
    assert node == 2 and dof in "xyz"


def test_check_bounds_a_rotational_spring_by_sqrt_k_over_i():
    """A node of inertia I on a rotational spring k to ground: sqrt(k/I), about the stiffest
    axis (here z: 90 / 0.1)."""
    text = _only(
        ["3 3 0.0 1.0 10.0 20.0 90.0 0.0"], ["1 3 2"], ["2 0.0 1.0 1.0 0.1"], ["2 2 1 1 2 3"]
    )
    omega, node, dof = _check_omega(text)
    assert omega == pytest.approx(math.sqrt(90.0 / 0.1), rel=1e-15)
    assert (node, dof) == (2, "rz")


def test_the_linear_sdof_baseline_leaves_the_new_types_out():
    """Sweeps predict a start and draw baselines from a closed-form SDOF of type 1 springs to
    ground; a deck with an axial or rotational element is not in that form."""
    from x3dpd.design.baselines import linear_sdof

    fixed = ["1 1 1 1 2 3 4 5 6", "2 2 1 2 3 4 5 6"]  # node 2 free along x only
    for extra, element in (
        ("2 2 0.0 1.0 50.0 0.0 0.0 0.0", "2 2 1 2"),
        ("3 3 0.0 1.0 1.0 1.0 1.0 0.0", "2 3 2"),
    ):
        text = _only(
            ["1 1 0.0 1.0 400.0 0.0 0.0 0.0", extra],
            ["1 1 2", element],
            ["2 4.0 1.0 1.0 1.0"],
            fixed,
        )
        assert linear_sdof(build_model(parse_deck(text, "springs.inp")), 2, 1) is None
    plain = build_model(
        parse_deck(
            _only(["1 1 0.0 1.0 400.0 0.0 0.0 0.0"], ["1 1 2"], ["2 4.0"], fixed), "springs.inp"
        )
    )
    assert linear_sdof(plain, 2, 1) is not None
