"""Closed-form rows and curves of a sweep's linear baselines (x3dpd.design.baselines): a force
drive's SDOF or modal structure, X = F H(w); a base drive's SDOF on its base, X = T(w) U; any
other linear structure (lumped, modal, or both, on springs to ground and base) through
x3dpd.design.linear_system.
"""

from __future__ import annotations

import math

import numpy as np

from x3dpd.api.decks import build_model
from x3dpd.design.baselines import base_mass_node, base_structure, baseline_decks, linear_structure
from x3dpd.design.drive import displacement_amplitude
from x3dpd.design.linear_system import linear_system
from x3dpd.design.spec import SweepSpec


#: The fields of a closed-form point: exact, so converged at once, with nothing stepped.
_EXACT = {
    "cycles": 0,
    "kept_cycles": 0,
    "tau_cycles": math.nan,
    "stopped_by": "closed-form",
    "dissipated_per_cycle_ci": 0.0,
    "converged": True,
    "extrapolated": False,
    "irregular": False,
    "change": 0.0,
    "method": "closed-form",
    "start": "",
    "t_start": 0.0,
    "t_end": 0.0,
    "steps": 0,
    "compile_s": 0.0,
    "wall_s": 0.0,
}


def _motion(a: float, phase_deg: float, w: float, accelerance: float, transmissibility: float):
    """A harmonic response's columns: displacement amplitude ``a`` [length], phase [deg],
    velocity w a and acceleration w^2 a at w [rad/s], the accelerance and transmissibility given
    (NaN where the drive does not define one)."""
    return {
        "amplitude": a,
        "amplitude_ci": 0.0,
        "phase": phase_deg,
        "phase_ci": 0.0,
        "velocity": w * a,
        "acceleration": w * w * a,
        "accelerance": accelerance,
        "transmissibility": transmissibility,
        "peak": a,
        "mean": math.nan,
        "spread": 0.0,
    }


def mass_node(spec: SweepSpec) -> int | None:
    """The node that takes the particles' mass in the added-mass baseline: the driven one, or
    for a base drive the body on the base (x3dpd.design.baselines.base_mass_node)."""
    if not spec.base:
        return spec.node
    if "added-mass" not in spec.baselines:
        return None
    return base_mass_node(spec.deck, spec.node, spec.dof)


def force_structure(model, node: int, dof: int, response: tuple[int, int] | None = None):
    """The closed-form structure of a particle-free model under a force on ``node`` along
    ``dof``, measured at ``response`` (default the driven DOF): an Sdof or ModalLinear
    (x3dpd.design.baselines.linear_structure), else a LinearSystem, else None (simulated)."""
    return linear_structure(model, node, dof, response) or linear_system(model, node, dof, response)


def base_response_structure(model, base: int, dof: int, response: tuple[int, int]):
    """The closed-form structure of a particle-free model whose ``base`` node is moved along
    ``dof``, measured at ``response``: a BaseSdof (x3dpd.design.baselines.base_structure), else
    a LinearSystem, else None (simulated)."""
    return base_structure(model, base, dof, response) or linear_system(
        model, base, dof, response, base=True
    )


def base_closed_form_rows(config: str, spec: SweepSpec, structures) -> list[dict]:
    """Rows of a base-driven linear baseline (``structures``: a BaseSdof or LinearSystem per
    response, :func:`base_response_structure`) at
    every frequency and drive: the base's own row (its prescribed motion) and one per
    response, X = T(w) U (x3dpd.design.baselines.BaseSdof)."""
    rows = []
    for drive in spec.drives:
        for f in sorted(spec.frequencies):
            w = 2.0 * math.pi * f
            u = displacement_amplitude(drive, spec.quantity, w)
            measured = []
            for (node, dof), sdof in zip(spec.responses, structures):
                a, p = sdof.response(u, w)
                measured.append(
                    {
                        "response_node": node,
                        "response_dof": dof,
                        **_motion(a, math.degrees(p), w, math.nan, a / u),
                        "measured_amplitude": a,
                        "change": 0.0,
                        "converged": True,
                    }
                )
            work = structures[0].dissipated_per_cycle(u, w)
            rows.append(
                {
                    "config": config,
                    "frequency_hz": f,
                    "drive": drive,
                    "drive_quantity": spec.quantity,
                    "direction": "",
                    **_motion(u, 0.0, w, math.nan, 1.0),
                    "dissipated_per_cycle": work,
                    "dissipated_particles_per_cycle": 0.0,
                    "input_work_per_cycle": work,
                    "measured_amplitude": u,
                    **_EXACT,
                    "response_node": spec.node,
                    "response_dof": spec.dof,
                    "responses": measured,
                }
            )
    return rows


def closed_form_rows(config: str, sdof, spec: SweepSpec, responses=()) -> list[dict]:
    """Rows of a linear baseline (SDOF or modal) at every frequency and drive (``baselines.py``);
    ``responses``: the structure measured at each of ``spec.responses``."""
    rows = []
    for drive in spec.drives:
        for f in sorted(spec.frequencies):
            w = 2.0 * math.pi * f
            amp, phi = sdof.response(drive, w)
            measured = []
            for (node, dof), structure in zip(spec.responses, responses):
                a, p = structure.response(drive, w)
                measured.append(
                    {
                        "response_node": node,
                        "response_dof": dof,
                        **_motion(a, math.degrees(p), w, w * w * a / abs(drive), math.nan),
                        "measured_amplitude": a,
                        "change": 0.0,
                        "converged": True,
                    }
                )
            rows.append(
                {
                    "config": config,
                    "frequency_hz": f,
                    "drive": drive,
                    "drive_quantity": "force",
                    "direction": "",
                    **_motion(amp, math.degrees(phi), w, w * w * amp / abs(drive), math.nan),
                    "dissipated_per_cycle": sdof.dissipated_per_cycle(amp, w),
                    "dissipated_particles_per_cycle": 0.0,
                    "input_work_per_cycle": sdof.dissipated_per_cycle(amp, w),
                    "measured_amplitude": amp,
                    **_EXACT,
                    "response_node": spec.node,
                    "response_dof": spec.dof,
                    **({"responses": measured} if measured else {}),
                }
            )
    return rows


def baseline_curves(
    spec: SweepSpec, n: int = 2001, response: tuple[int, int] | None = None
) -> dict:
    """Closed-form baseline curves on a fine grid over the swept band: {(config, drive): (f, X)}
    at the driven DOF, or at ``response`` (node, dof). A base drive's are at its responses
    only, X the displacement amplitude (the transmissibility is X / U(f))."""
    out = {}
    f = np.linspace(min(spec.frequencies), max(spec.frequencies), n)
    for config, deck in baseline_decks(spec.deck, spec.baselines, mass_node(spec)).items():
        if spec.base:
            sdof = (
                base_response_structure(build_model(deck), spec.node, spec.dof, response)
                if response is not None
                else None
            )
            for drive in [] if sdof is None else spec.drives:
                w = 2 * math.pi * f
                u = np.array([displacement_amplitude(drive, spec.quantity, x) for x in w])
                out[(config, drive)] = (
                    f,
                    np.abs(u * np.array([sdof.transmissibility(x) for x in w])),
                )
            continue
        sdof = force_structure(build_model(deck), spec.node, spec.dof, response)
        if sdof is None:
            continue
        for drive in spec.drives:
            out[(config, drive)] = (
                f,
                np.array([sdof.response(drive, 2 * math.pi * x)[0] for x in f]),
            )
    return out
