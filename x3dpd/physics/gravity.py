"""Body (gravity) acceleration from the BODY card.

Every node with mass feels :math:`\\mathbf f = m\\,\\mathbf g`; the potential energy, measured from
the initial configuration, is :math:`U = -\\sum m\\,\\mathbf g\\cdot(\\mathbf x - \\mathbf x_0)`.
Units: g in length/s^2 (the report's decks: -386.1 in/s^2 along y).
"""

from __future__ import annotations

from x3dpd._jit import kernel


@kernel
def _gravity_energy(mass, x, x0, g):
    """U = -sum m g . (x - x0) [energy]."""
    u = 0.0
    for i in range(mass.shape[0]):
        m = mass[i]
        if m != 0.0:
            for d in range(3):
                u -= m * g[d] * (x[i, d] - x0[i, d])
    return u
