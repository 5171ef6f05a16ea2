"""The FRICTION card (our extension, docs/deck-reference.md): per PDMP group the tangential
law, static and kinetic mu and the rolling-resistance law; parsed, checked with
FILE:LINE:COL messages, written back by the deck writer, and chosen by the run unless
``--friction`` overrides it."""

from __future__ import annotations

import pytest

import x3dpd
from x3dpd.deck.writer import format_deck
from x3dpd.errors import DeckError
from x3dpd.model.build import build_model
from x3dpd.physics.rolling import ROLLING_LAWS as ROLLING_REGISTRY
from x3dpd.physics.tangential_laws import TANGENTIAL_LAWS

HEAD = """PARAMETERS
   0.0 1e-5 0.0 5e-07 5e-07 0 1000000000.0 0 5 0 1
END
PDMP
 4 0.0625 7.33e-4 0.33 30e6 0 1 0.3
 5 0.0625 7.33e-4 0.33 30e6 0 1 0.2
END
"""
TAIL = """TRACE
5
END
NODE
1 -.5 0 -.5
2 .5 0 -.5
3 .5 0 .5
4 -.5 0 .5
5 0 0.0625 0
6 0.3 0.0625 0
END
BOUNDARY
1 4 1 1 2 3 4 5 6
END
CONTACT
1 1 2 3
1 1 3 4
END
1 5 6
END
"""


def _deck(tmp_path, card: str):
    path = tmp_path / "d.inp"
    path.write_text(HEAD + card + TAIL)
    return path


@pytest.mark.parametrize("law", list(TANGENTIAL_LAWS))
@pytest.mark.parametrize("roll", list(ROLLING_REGISTRY))
def test_the_deck_reads_every_registered_law(tmp_path, law, roll):
    """The FRICTION card's LAW and ROLL words are the registries' names, nothing else: a law's
    registration line is all it takes for the deck to accept it."""
    deck = x3dpd.load_deck(_deck(tmp_path, f"FRICTION\n 4 {law} 0.3 0.3 {roll} 0.01\nEND\n"))
    assert (deck.friction[0].law, deck.friction[0].roll) == (law, roll)


def test_the_run_option_offers_every_registered_law():
    """``x3dpd run --friction`` takes its choices from the registry (a law's registration line
    is all it takes; the option listed three names by hand)."""
    from x3dpd.cli.run import run

    option = next(p for p in run.params if p.name == "friction")
    assert list(option.type.choices) == list(TANGENTIAL_LAWS)


def test_parse_model_and_roundtrip(tmp_path):
    path = _deck(
        tmp_path,
        "FRICTION\n$ group law mu_s mu_k\n 4 mindlin 0.4 0.3 epsd 0.01\n 5 MINDLIN 0.2 0.2\nEND\n",
    )
    deck = x3dpd.load_deck(path)
    assert [(r.nodlim, r.law, r.mu_s, r.mu_k, r.roll, r.mu_r) for r in deck.friction] == [
        (4, "mindlin", 0.4, 0.3, "epsd", 0.01),
        (5, "mindlin", 0.2, 0.2, "none", 0.0),
    ]
    model = build_model(deck)
    assert model.friction_law == "mindlin" and model.rolling_law == "epsd"
    assert list(model.mu) == [0.4, 0.2] and list(model.mu_kinetic) == [0.3, 0.2]
    assert list(model.mu_roll) == [0.01, 0.0]
    again = tmp_path / "again.inp"
    again.write_text(format_deck(deck))
    assert x3dpd.load_deck(again).friction == tuple(
        r.__class__(**{**r.__dict__, "pos": x3dpd.load_deck(again).friction[k].pos})
        for k, r in enumerate(deck.friction)
    )
    assert format_deck(x3dpd.load_deck(again)) == format_deck(deck)


@pytest.mark.parametrize(
    "card, line, col, phrase",
    [
        (
            "FRICTION\n 4 stick 0.3 0.3\nEND\n",
            9,
            4,
            "LAW must be one of " + ", ".join(TANGENTIAL_LAWS) + "; got stick",
        ),
        ("FRICTION\n 4 mindlin 0.3\nEND\n", 9, 2, "needs 4 or 6 values: NODLIM LAW MUS MUK"),
        ("FRICTION\n 4 mindlin 0.3 0.4\nEND\n", 9, 16, "MUK (kinetic) must not exceed MUS"),
        (
            "FRICTION\n 4 coulomb 0.3 0.2\nEND\n",
            9,
            16,
            "the coulomb law has one friction coefficient",
        ),
        (
            "FRICTION\n 4 mindlin 0.3 0.3 spin 0.1\nEND\n",
            9,
            20,
            "ROLL must be one of " + ", ".join(ROLLING_REGISTRY) + "; got spin",
        ),
        ("FRICTION\n 4 mindlin -0.3 -0.3\nEND\n", 9, 12, "MUS must be >= 0"),
        ("FRICTION\n 4 mindlin 0.3 0.3 epsd\nEND\n", 9, 24, "ROLL needs its MUR"),
    ],
)
def test_bad_records_point_at_the_field(tmp_path, card, line, col, phrase):
    path = _deck(tmp_path, card)
    with pytest.raises(DeckError) as err:
        x3dpd.load_deck(path)
    text = str(err.value)
    assert text.startswith(f"{path}:{line}:{col}: FRICTION: "), text
    assert phrase in text


@pytest.mark.parametrize(
    "card, phrase",
    [
        (
            "FRICTION\n 4 mindlin 0.3 0.3\n 5 coulomb 0.3 0.3\nEND\n",
            "a scene runs one tangential law",
        ),
        ("FRICTION\n 7 mindlin 0.3 0.3\nEND\n", "NODLIM 7 names no PDMP group"),
        ("FRICTION\n 4 mindlin 0.3 0.3\n 4 mindlin 0.3 0.3\nEND\n", "is given twice"),
    ],
)
def test_bad_groups_are_refused(tmp_path, card, phrase):
    path = _deck(tmp_path, card)
    with pytest.raises(DeckError) as err:
        x3dpd.run(path, tmax=1e-6)
    assert phrase in str(err.value) and ": FRICTION: " in str(err.value)


def test_the_card_chooses_the_law_and_the_option_overrides_it(tmp_path):
    path = _deck(tmp_path, "FRICTION\n 4 mindlin 0.3 0.3\n 5 mindlin 0.2 0.2\nEND\n")
    from x3dpd.solver.simulation import Simulation

    model = build_model(x3dpd.load_deck(path))
    assert Simulation(model).variant.friction_law == "mindlin"
    assert Simulation(model, friction="coulomb").variant.friction_law == "coulomb"


def test_the_step_estimate_sees_the_tangential_spring(tmp_path):
    """Under mindlin the spring's half period pi sqrt(m_t / k_t,max) (m_t = 2m/7 on a wall,
    k_t,max = 8 G* sqrt(R a_max)) is shorter than the Hertz contact and sets the step."""
    import math

    from x3dpd.model.timestep import recommended_time_step
    from x3dpd.physics.hertz import hertz_impact

    plain = recommended_time_step(build_model(x3dpd.load_deck(_deck(tmp_path, ""))))
    path = _deck(tmp_path, "FRICTION\n 4 mindlin 0.3 0.3\n 5 mindlin 0.2 0.2\nEND\n")
    ts = recommended_time_step(build_model(x3dpd.load_deck(path)))
    assert ts.contact_kind == "particle-wall tangential spring"
    m = 7.33e-4 * 4.0 / 3.0 * math.pi * 0.0625**3
    e_star, g_star = 30e6 / (1 - 0.33**2), 30e6 / (2 * 1.33) / (2 - 0.33)
    a_max = hertz_impact(m, 4.0 / 3.0 * e_star * math.sqrt(0.0625), plain.impact_speed)[0]
    k_t = 8.0 * g_star * math.sqrt(0.0625 * a_max)
    assert ts.t_contact == pytest.approx(math.pi * math.sqrt(2.0 * m / 7.0 / k_t), rel=1e-12)
    assert ts.t_contact < plain.t_contact


def test_the_run_option_accepts_mindlin(tmp_path):
    """``x3dpd run --friction mindlin`` (the CLI, in process) runs a deck without the card
    under Hertz-Mindlin: its sidecar records the law; an unknown law is refused (exit 2)."""
    import json

    from click.testing import CliRunner

    from x3dpd.cli import _register, cli

    _register()
    # one PDMP group: the scene compiles the loop the Mindlin floor-and-box tests compile
    path = _deck(tmp_path, "")
    path.write_text(path.read_text().replace(" 5 0.0625 7.33e-4 0.33 30e6 0 1 0.2\n", ""))
    trace = tmp_path / "d.trace.txt"
    result = CliRunner().invoke(
        cli,
        [
            "run",
            str(path),
            "--friction",
            "mindlin",
            "--trace",
            str(trace),
            "--tmax",
            "2e-6",
            "--quiet",
        ],
    )
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "d.trace.txt.json").read_text())["friction"] == "mindlin"
    bad = CliRunner().invoke(cli, ["run", str(path), "--friction", "sticky"])
    assert bad.exit_code == 2
