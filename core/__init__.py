"""Shakedown Explorer core: the physics of a rocking cylindrical contact."""
from .analytical import *  # noqa: F401,F403
from .contact import Contact, PAPER_SIMULATION, PAPER_EXPERIMENT, BETA_WARNING_LEVEL  # noqa: F401
from . import approximations  # noqa: F401
from .kernels import influence_matrix, strip_u0  # noqa: F401
from .schedule import Schedule, rocking_schedule  # noqa: F401
from .result import CycleResult, SolverError, SolveCancelled, STATE_NAMES  # noqa: F401
from .solver import simulate_cycles, simulate_contact, solve_schedule, strip_options  # noqa: F401
from .sweeps import (sweep, sweep_grid, run_points, numerical_w_limit, numerical_limit,  # noqa: F401
                    numerical_limit_curve, LimitResult, SweepCancelled, load_default_map)
from .point_contact import Ellipsoid, Sphere, PointContact, POINT_BODIES  # noqa: F401
from .halfspace import HalfSpaceOperator  # noqa: F401
from .solver3d import (simulate_point_contact, solve_point_schedule, mindlin_state, shakedown_state_3d,  # noqa: F401
                       PointContactResult, StaticResult3D)
