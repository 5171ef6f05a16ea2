r"""Energy-ledger tests that tell a sound run from a broken one (docs/physics.md, "Stopping").

Every function reads energy-ledger rows (the 12 columns of
``x3dpd.solver.simulation.ENERGY_COLUMNS``) and returns what is wrong, or ``None``; the
:class:`~x3dpd.solver.simulation.Simulation` turns a finding into an
:class:`~x3dpd.errors.UnstableRunError`.

Three laws are checked, each with an allowance for what a *sound* explicit run does:

* **Balance** -- the residual (stored energy change + dissipated - external work) stays within
  ``tolerance * scale``. Mid-contact the ledger's stored contact energy
  :math:`U_c = \tfrac25 F_N a` is only the Hertz estimate of the work the discrete forces did on
  the contact, so a stable impact resolved in a few steps shows a transient mismatch of the
  order of :math:`U_c` that is paid back when the contact opens (at 6280 in/s and 5e-7 s, six
  steps per contact, 5 % of the energy mid-contact, 0.3 % after). The allowance is therefore
  ``tolerance * scale + U_c``: what is left after every contact opened is judged by the
  tolerance alone.
* **Dissipation is never negative** -- viscoelastic contacts, friction and dampers only take
  energy out. The viscoelastic column is absorbed minus stored work, so an integration that
  *creates* energy in a viscoelastic contact books it there as negative dissipation and the
  residual stays closed; hence the separate test, with the same ``U_c`` allowance mid-contact.
* **Step stability** -- velocity Verlet conserves :math:`KE - S + U` (with
  :math:`S = \Delta t^2/8\,\sum|f|^2/m`) even when it is unstable, so the residual cannot see a
  step beyond the limit. For a linear mode :math:`S = (\omega\Delta t)^2/4\; U`, and on the
  growing mode of an unstable step (:math:`\omega\Delta t > 2`) :math:`S` grows without bound,
  whereas on a stable one it stays below
  :math:`\frac{(\omega\Delta t)^2/4}{1-(\omega\Delta t)^2/4}\,B`, with :math:`B` the energy the
  run received (initial energy, external work, gravity's work, dissipated energy:
  :func:`energy_budget`). The run is unstable when :math:`S > 1000\,B` (a stable step would
  need :math:`\omega\Delta t > 1.999`). :math:`B` includes the load's work, so a structure
  under a constant load whose rows fall where its spring energy is near zero is not flagged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# ledger columns (x3dpd.solver.simulation.ENERGY_COLUMNS)
TIME, KE_T, KE_R, U_GRAV, U_SPRING, U_CONTACT = 0, 1, 2, 3, 4, 5
D_VISCO, D_FRICTION, D_DAMPERS, W_EXT, E_TOTAL, RESIDUAL = 6, 7, 8, 9, 10, 11
D_ROLLING = 12   # a scene with a rolling law only (x3dpd.solver.simulation.energy_columns)


def _rolling(row: np.ndarray) -> float:
    """The rolling resistance's dissipation of a row that has the column, else 0."""
    return float(row[D_ROLLING]) if row.shape[0] > D_ROLLING else 0.0

#: S / B beyond which the step is unstable (see the module docstring).
SHADOW_LIMIT = 1000.0
#: Fraction of the critical step ``x3dpd check`` recommends for the structure.
SAFE_FRACTION = 0.2
_DISSIPATION = ((D_VISCO, "viscoelastic contacts"), (D_FRICTION, "friction"),
                (D_DAMPERS, "dampers"))


def verlet_correction(row: np.ndarray, e_ref: float) -> float:
    """S = E_total - (residual + e_ref - dissipated + W_ext): the ledger's Verlet term."""
    return float(row[E_TOTAL] - (row[RESIDUAL] + e_ref - row[D_VISCO] - row[D_FRICTION]
                                 - row[D_DAMPERS] - _rolling(row) + row[W_EXT]))


def energy_budget(row: np.ndarray, e_ref: float) -> float:
    """B = |e_ref| + |U_g| + |W_ext| + |D_visc| + |D_fric| + |D_damp|: energy that entered or
    left through a source, a bound on the energy a stable run can hold."""
    return float(abs(e_ref) + abs(row[U_GRAV]) + abs(row[W_EXT]) + abs(row[D_VISCO])
                 + abs(row[D_FRICTION]) + abs(row[D_DAMPERS]) + abs(_rolling(row)))


@dataclass(frozen=True)
class StepInstability:
    """A row where the Verlet correction outgrew the energy budget."""

    time: float
    correction: float
    budget: float
    omega: float  # estimated from S / U = (omega dt)^2 / 4 [rad/s]; nan when U = 0

    def critical_step(self) -> float:
        return 2.0 / self.omega if self.omega > 0 else math.nan


def step_instability(row: np.ndarray, e_ref: float, dt: float) -> StepInstability | None:
    """The finding when ``S > SHADOW_LIMIT * B`` (or S is not finite), else None."""
    s = verlet_correction(row, e_ref)
    b = energy_budget(row, e_ref)
    if not (s > SHADOW_LIMIT * b and s > 0.0) and math.isfinite(s):
        return None
    u = float(row[U_SPRING] + row[U_CONTACT])
    ratio = s / u if u > 0.0 else math.nan
    omega = 2.0 * math.sqrt(ratio) / dt if math.isfinite(ratio) else math.nan
    return StepInstability(float(row[TIME]), s, b, omega)


def unbalanced_row(energy: np.ndarray, scale, tolerance: float) -> int | None:
    """Index of the first row whose |residual| exceeds ``tolerance * scale + U_c``
    (``scale``: one energy scale, or one per row)."""
    allowed = tolerance * scale + np.maximum(energy[:, U_CONTACT], 0.0)
    bad = np.nonzero(~(np.abs(energy[:, RESIDUAL]) <= allowed))[0]
    return int(bad[0]) if bad.size else None


def negative_dissipation(energy: np.ndarray, scale, tolerance: float
                         ) -> tuple[int, str, float] | None:
    """(row, mechanism, amount) of the first row where a mechanism dissipated less than
    ``-(tolerance * scale)`` (viscoelastic: ``-(tolerance * scale + U_c)``), else None
    (``scale``: one energy scale, or one per row)."""
    first = None
    for col, name in _DISSIPATION:
        allowed = tolerance * scale + (np.maximum(energy[:, U_CONTACT], 0.0)
                                       if col == D_VISCO else 0.0)
        bad = np.nonzero(energy[:, col] < -allowed)[0]
        if bad.size and (first is None or bad[0] < first[0]):
            first = (int(bad[0]), name, float(energy[bad[0], col]))
    return first


__all__ = ["StepInstability", "energy_budget", "negative_dissipation", "step_instability",
           "unbalanced_row", "verlet_correction", "SHADOW_LIMIT", "SAFE_FRACTION"]
