"""aero-env: the paper-craft aerial acrobat robot as a pymunk world, analytical models and a
Gymnasium design environment.

``import aero_env`` registers the environments (``aero_env/AerialAcrobat-v0`` and its
variants, listed in ``aero_env.registration.ENVIRONMENTS``); the physics is imported only when
an environment is made.
"""

from .registration import register_environments

__version__ = "0.1.0"

register_environments()
