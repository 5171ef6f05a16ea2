"""The compile-time constants of one step-loop variant (x3dpd.solver.variants).

:func:`x3dpd.solver.variants.make_advance` writes this module anew for every variant, from
:meth:`Variant.header`: which effects exist, how many Maxwell terms, which friction and normal
laws, which analytic wall shapes, which effect units (their bundles and the slots' calls of
their hooks), which user forces. The step-loop template and its parts
import their constants from here, and numba freezes them into the machine code: an absent
effect is a constant-false branch that never reaches it. The values below (every effect on)
only make the template importable for reading and linting.
"""

# --- VARIANT BEGIN ---
HAS_SPRINGS = True
HAS_RIGID = True
HAS_RIGID_ROTATION = True
HAS_WALLS = True
HAS_PAIRS = True
HAS_FRICTION = True
HAS_VISCOELASTIC = True
HAS_EXTERNAL = True
HAS_USER_FORCE = False
HAS_PYTHON_FORCE = False
HAS_MOTION = True
N_MAXWELL = 1
HAS_WALLS_TRANSLATE = False
HAS_SHAPES = True
HAS_ONE_PARTICLE_KIND = False
HAS_ONE_WALL_KIND = True
HAS_MODAL = True
HAS_AXIAL_SPRINGS = True
HAS_ROTATIONAL_SPRINGS = True
HAS_THREADED = True
from x3dpd.physics.mindlin import tangential_force as TANGENTIAL_FORCE, stored_energy as TANGENTIAL_STORED_ENERGY, N_HISTORY as N_TANGENTIAL, STORES_ENERGY as TANGENTIAL_STORES  # noqa: F401,E402,E501
from x3dpd.physics.maxwell import wall_force as NORMAL_WALL_FORCE, pair_force as NORMAL_PAIR_FORCE, stored_energy as NORMAL_STORED_ENERGY, CLAMPED as NORMAL_CLAMPED, USES_RATE as NORMAL_USES_RATE, DAMPED as NORMAL_DAMPED, stiffness_shape as NORMAL_STIFFNESS_SHAPE  # noqa: F401,E402,E501
HAS_ROLLING = True
from x3dpd.physics.epsd import rolling_torque as ROLLING_TORQUE, N_HISTORY as N_ROLLING  # noqa: F401,E402,E501
SHAPE_LOCATE = None
SHAPE_CLEAR = None
# the effect units' bundles and slots (x3dpd.solver.unit_slots writes them per variant)
UNIT_BUNDLES = SLOT_FIRST_HALF_KICK = SLOT_DRIFT = SLOT_FOLLOW = SLOT_FORCE = None
SLOT_GATHER = SLOT_KICK = SLOT_SECOND_HALF_KICK = SLOT_PLACE = SLOT_ENERGY = None
FILLED_FIRST_HALF_KICK = FILLED_DRIFT = FILLED_FOLLOW = FILLED_FORCE = FILLED_GATHER = True
FILLED_KICK = FILLED_SECOND_HALF_KICK = FILLED_PLACE = FILLED_ENERGY = True
USER_FORCE = None
# --- VARIANT END ---
