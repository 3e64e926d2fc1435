"""Shakedown Explorer core: the physics of a rocking cylindrical contact."""
from .analytical import *  # noqa: F401,F403
from .contact import Contact, PAPER_SIMULATION, PAPER_EXPERIMENT, BETA_WARNING_LEVEL  # noqa: F401
from . import approximations  # noqa: F401
