"""The pymunk world of the machine and the runner that detects its events.

The physics knows nothing of environments or agents; they use it.
"""

from .run import SimResult, Swing, simulate
from .world import World

__all__ = ["World", "simulate", "SimResult", "Swing"]
