"""The baselines' FRFs that ``x3dpd frf --baseline undamped,added-mass`` overlays: the run's own
structure without its particles, and with their mass added rigidly, in closed form
(x3dpd.design.closed_form: an SDOF, the modes, a base SDOF, or any linear structure of
x3dpd.design.linear_system), as the same quantity per unit drive as the estimated H1.

The structure is the deck the run read (the trace's sidecar ``deck_path``, checked against its
``deck_sha256``), or ``--deck``. A force drive's FRF is the receptance H = X / F times (i w)^q
(q = 0, 1, 2 for displacement, velocity, acceleration); a base drive's (``--motion``, the drive
then the base's acceleration) is T (i w)^(q - 2) with T = X / U the absolute motion's
transmissibility, so an acceleration response per base acceleration is T itself.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from x3dpd.api import TraceData
from x3dpd.api.decks import build_model, read_deck
from x3dpd.api.figures import Curve
from x3dpd.api.measurements import QUANTITY_ORDER
from x3dpd.design.baselines import base_mass_node, baseline_decks
from x3dpd.design.closed_form import base_response_structure, force_structure
from x3dpd.errors import InputError


def run_deck(trace: TraceData, trace_path: str, deck: str | None):
    """The deck of a run: ``deck`` as given, else the sidecar's ``deck_path`` (as written, or
    beside the trace), which must still have the bytes the run read."""
    if deck is not None:
        return read_deck(deck)
    recorded = trace.meta.get("deck_path")
    if not recorded:
        raise InputError(
            f"{trace_path}: the sidecar names no deck (a run from the Python API "
            "with a Deck object); give --deck DECK for the baselines"
        )
    candidates = [Path(recorded), Path(trace_path).parent / Path(recorded).name]
    found = next((p for p in candidates if p.is_file()), None)
    if found is None:
        raise InputError(
            f"{trace_path}: the run's deck {recorded} is not found; give --deck "
            "DECK for the baselines"
        )
    sha = trace.meta.get("deck_sha256")
    if sha and hashlib.sha256(found.read_bytes()).hexdigest() != sha:
        raise InputError(
            f"{trace_path}: {found} has changed since the run (its SHA-256 is not "
            "the sidecar's); give --deck DECK for the baselines"
        )
    return read_deck(found)


def baseline_frfs(
    deck,
    names: Sequence[str],
    *,
    base: bool,
    node: int,
    dof: int,
    responses: Sequence[tuple[int, int]],
    quantity: str,
    frequency: np.ndarray,
) -> list[tuple[str, tuple[int, int], np.ndarray]]:
    """[(baseline name, response, FRF at ``frequency`` [Hz])] for every baseline and response
    (module doc); an InputError when one is not in closed form."""
    if dof not in (1, 2, 3) or any(d not in (1, 2, 3) for _, d in responses):
        raise InputError("--baseline: the baselines' FRFs are between translations (DOF 1-3)")
    mass_node = base_mass_node(deck, node, dof) if base else node
    if "added-mass" not in names:
        mass_node = node
    decks = baseline_decks(deck, names, mass_node)
    w = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    q = QUANTITY_ORDER[quantity] - (2 if base else 0)
    out = []
    for name, bare in decks.items():
        model = build_model(bare)
        for response in responses:
            structure = (
                base_response_structure(model, node, dof, response)
                if base
                else force_structure(model, node, dof, response)
            )
            if structure is None:
                raise InputError(
                    f"--baseline {name}: the {name} structure of {deck.path} driven at {node}:"
                    f"{dof} and measured at {response[0]}:{response[1]} is not linear in closed "
                    "form (particles, axial or rotational springs, a turning body; "
                    "docs/design-guide.md); run that deck and give its trace instead"
                )
            frf = structure.transmissibility if base else structure.receptance
            h = np.array([frf(x) for x in w]) * (1j * w) ** q
            out.append((name, tuple(response), h))
    return out


def baseline_curves(
    first,
    deck: str | None,
    names: Sequence[str],
    drive: tuple[int, int],
    points,
    quantity: str,
    rows: list[dict],
) -> list[Curve]:
    """The baselines' closed-form FRFs (x3dpd.testlab.frf_baselines) on a fine grid over the
    first run's lines, drawn dash-dotted; their values at those lines appended to ``rows``
    (DIR/baselines.csv)."""
    trace, path, kind, lines = first
    lines = lines[lines > 0]
    if lines.size < 2:
        raise InputError(
            "--baseline: the band holds fewer than two frequency lines above 0 Hz; "
            "widen --band or use longer segments"
        )
    structure = run_deck(trace, path, deck)
    fine = np.linspace(lines[0], lines[-1], 2001)
    args = dict(
        base=kind != "force", node=drive[0], dof=drive[1], responses=points, quantity=quantity
    )
    curves = []
    at_lines = baseline_frfs(structure, names, frequency=lines, **args)
    for (name, (node, dof), h), (_, _, h_fine) in zip(
        at_lines, baseline_frfs(structure, names, frequency=fine, **args)
    ):
        run = f"{name} (closed form)"
        curves.append(
            Curve(run if len(points) == 1 else f"{run} {node}:{dof}", fine, h_fine, baseline=True)
        )
        rows += [
            {
                "baseline": name,
                "response": f"{node}:{dof}",
                "frequency_hz": x,
                "re": v.real,
                "im": v.imag,
                "mag": abs(v),
                "phase_deg": math.degrees(np.angle(v)),
            }
            for x, v in zip(lines, h)
        ]
    return curves
