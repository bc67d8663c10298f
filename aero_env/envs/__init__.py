"""Gymnasium environments built on the physics (the physics knows nothing of them)."""

from .aerial_acrobat import AerialAcrobatEnv

__all__ = ["AerialAcrobatEnv"]
