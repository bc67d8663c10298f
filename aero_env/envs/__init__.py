"""Gymnasium environments built on the physics (the physics knows nothing of them)."""

from .aerial_acrobat import AerialAcrobatEnv
from .aerial_acrobat_vector import AerialAcrobatVectorEnv

__all__ = ["AerialAcrobatEnv", "AerialAcrobatVectorEnv"]
