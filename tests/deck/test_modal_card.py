"""The MODAL card: records read with their positions, bad records at FILE:LINE:COL, the
writer's round trip, and what the model builder makes of the modes (the deck's mass coupled
in, held DOFs, mass normalisation) -- no run."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from x3dpd.deck import format_deck, parse_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model

HEAD = """PARAMETERS
 0.0 1.0 0.0 1e-5 1e-5 0 1e12 0 5 0 10
END
NODE COORDINATES
 1 0 0 0
 2 1 0 0
END
"""


def _deck(modal: str, extra: str = "") -> str:
    return HEAD + "MODAL\n" + modal + "END\n" + extra


GOOD = """ MODE 1 10.0 0.02
 MODE 2 25.0 0.03
 SHAPE 1 1 20.0 15.0
 SHAPE 2 1 12.0, -30.0
"""


def test_records_read_with_their_values():
    d = parse_deck(_deck(GOOD))
    assert [(m.number, m.freq, m.zeta) for m in d.modal.modes] == [(1, 10.0, 0.02), (2, 25.0, 0.03)]
    assert [(s.node, s.dof, s.values) for s in d.modal.shapes] == [
        (1, 1, (20.0, 15.0)),
        (2, 1, (12.0, -30.0)),
    ]
    assert d.modal.housing == "added"


def test_writer_round_trip():
    d = parse_deck(_deck(GOOD + " HOUSING included\n"))
    again = parse_deck(format_deck(d))
    assert again.modal.lines == d.modal.lines
    assert [(s.node, s.values) for s in again.modal.shapes] == [
        (s.node, s.values) for s in d.modal.shapes
    ]
    assert again.modal.housing == "included"


@pytest.mark.parametrize(
    "modal, line, col, says",
    [
        (" MODE 1 10.0\n SHAPE 1 1 2.0\n", 9, 2, "MODE takes 3 or 4 values"),
        (" MODE 1 ten 0.01\n SHAPE 1 1 2.0\n", 9, 9, "expected a number"),
        (" MODE 1 10.0 -0.1\n SHAPE 1 1 2.0\n", 9, 14, "ZETA must be >= 0"),
        (" MODE 1 10.0 0.01\n SHAPE 1 7 2.0\n", 10, 10, "not one of 1..6"),
        (" MODE 1 10.0 0.01\n SHAPE 1 1 2.0 3.0\n", 10, 12, "one per MODE record"),
        (" MODE 1 10.0 0.01\n MODE 1 12.0 0.01\n SHAPE 1 1 2.0 3.0\n", 10, 7, "given twice"),
        (" MODE 1 10.0 0.01\n SHAPE 1 1 2.0\n SHAPE 1 1 3.0\n", 11, 2, "shape values twice"),
        (" MODE 1 10.0 0.01\n SHAPE 1 1 2.0\n HOUSING maybe\n", 11, 10, "HOUSING takes one word"),
        (" MODES 1 10.0 0.01\n", 9, 2, "unknown MODAL record"),
        (" FILE x.uff modes=3:1\n", 9, 19, "range is empty"),
        (" FILE x.uff band=5\n", 9, 18, "expected LO:HI"),
        (" FILE x.uff units=m,N\n", 9, 19, "FILE units"),
        (" MODE 1 10.0 0.01\n", 9, 2, "without SHAPE records"),
    ],
)
def test_bad_records_point_at_the_value(modal, line, col, says):
    with pytest.raises(DeckError) as err:
        parse_deck(_deck(modal), "m.inp")
    e = err.value
    assert (e.path, e.line, e.column, e.card) == ("m.inp", line, col, "MODAL"), str(e)
    assert says in e.message


def test_an_undefined_or_particle_node_is_reported_at_its_column():
    with pytest.raises(DeckError) as err:
        build_model(parse_deck(_deck(" MODE 1 10.0 0.01\n SHAPE 5 1 2.0\n")))
    assert (err.value.line, err.value.column) == (10, 8)
    assert "not defined" in err.value.message


def test_unnormalised_shapes_are_refused():
    with pytest.raises(DeckError) as err:
        build_model(parse_deck(_deck(" MODE 1 10.0 0.01 2.5\n SHAPE 1 1 2.0\n")))
    assert "not mass-normalised" in err.value.message


def test_added_mass_couples_the_modes_as_the_reduced_eigenproblem_says():
    """Two modes given at node 1 and 2, a MASS of 0.01 on node 2 (HOUSING added): the coupled
    frequencies are the eigenvalues of diag(w^2) psi = lambda (I + Phi^T M_a Phi) psi, computed
    here from the formula; HOUSING included leaves the modes as given."""
    mass = "MASS\n 2 0.01 0 0 0\nEND\n"
    model = build_model(parse_deck(_deck(GOOD, mass)))
    w = 2 * math.pi * np.array([10.0, 25.0])
    phi = np.array([[20.0, 15.0], [12.0, -30.0]])
    m_red = np.eye(2) + phi.T @ np.diag([0.0, 0.01]) @ phi
    lam = scipy.linalg.eigh(np.diag(w**2), m_red, eigvals_only=True)
    assert np.allclose(model.modal.omega, np.sqrt(lam), rtol=1e-12)
    # the coupled shapes are mass-normalised with the added mass: Phi'^T (I_modal) Phi' = I
    # means psi^T M psi = I; check the physical statement: the generalized mass of each coupled
    # mode over the given modes' mass plus the node mass is 1
    psi = np.linalg.lstsq(phi, model.modal.shape[:, 0, :], rcond=None)[0]
    assert np.allclose(psi.T @ m_red @ psi, np.eye(2), atol=1e-10)
    included = build_model(parse_deck(_deck(GOOD + " HOUSING included\n", mass)))
    assert np.allclose(included.modal.omega, w)


def test_boundary_and_missing_dofs_are_held():
    d = _deck(GOOD, "BOUNDARY CONDITIONS\n 2 2 1 1\nEND\n")
    ms = build_model(parse_deck(d)).modal
    assert ms.held[0].tolist() == [False] + [True] * 5
    assert ms.held[1].all()  # node 2's x fixed by BOUNDARY, the rest not given
    assert np.all(ms.shape[1] == 0.0)
