"""Sample USRFRC routine of AFRL-VA-WP-TR-2003-3053, Appendix C, as an x3dpd user force file.

Run with ``x3dpd run DECK --usrfrc decks/appendix_c.py``. The Fortran original::

    c     37.21 Hz = 233.7973253 rad/sec
          FRCNEW = 4.84040e-3 * SIN (233.7973253 * TIME)
          CALL GETIDN ( 25, NODE )
          FORCE(1,NODE) = FORCE(1,NODE) + FRCNEW

Argument roles are X3D's: ``coords`` (n, 3) are the coordinates at the last time step and
``vels`` (n, 6) the current velocities (DO NOT MODIFY either); ``force`` (n, 6) holds the force
sums, to which the routine ADDs. Arrays are indexed by node *index*; ``NODE_INDEX`` (injected by
x3dpd before compiling) maps a user node id to it, like ``GETIDN``. Fortran's ``FORCE(1, NODE)``
is ``force[node, 0]``.

The same force as a built-in law: ``--usrfrc sine:node=25,dof=1,amp=4.84040e-3,omega=233.7973253``
(identical) or ``hz=37.21`` (233.7973253 / 2 pi = 37.21000000316 Hz, so the phases drift apart by
2.0e-8 rad per second of simulated time).
"""

import math

NODE_INDEX = None  # replaced by x3dpd with the node id -> index array


def usrfrc(time, coords, vels, force):
    """ADD the Appendix C drive force, 4.84040e-3 sin(233.7973253 t), to FORCE(1, node 25)."""
    # 37.21 Hz = 233.7973253 rad/sec
    frcnew = 4.84040e-3 * math.sin(233.7973253 * time)
    node = NODE_INDEX[25]  # CALL GETIDN ( 25, NODE )
    force[node, 0] = force[node, 0] + frcnew
