"""``x3dpd study``: what accuracy costs in time, measured on the user's own scene.

A deck is run at a ladder of time steps and at the fidelity choices its scene makes meaningful
(viscoelastic or elastic contact, regularised or bare Coulomb friction); each run's wall time per
simulated second is set against its error, relative to the finest run, in the quantities an
engineer reads (docs/study.md):

* an impact scene (no drive, no gravity): peak contact force (the main quantity), restitution and
  contact time;
* a driven damper: the drive node's amplitude (main), the power dissipated per cycle (from the
  energy ledger) and a trace norm; with several particles the trajectories are chaotic, so the
  statistics are compared with their run-to-run spread, measured from perturbed repeats;
* anything else (particles settling under gravity): the energy dissipated (main) and a trace norm.

Every row also has ``residual``: the energy ledger's residual at the end of the run relative to its
energy scale -- the energy an integration made or lost (an elastic sphere bouncing on a floor
shows its drift there).

Layers: this package runs decks through the Python API (:func:`x3dpd.run`) only.
"""

from x3dpd.study.study import StudyResult, run_study

__all__ = ["StudyResult", "run_study"]
