"""Load the pymunk world's compiled parts (:mod:`.slip_kernel`, :mod:`.check_kernel`) once per process.

numba compiles a function, or loads it from the disk cache, at its first call: about 0.2 s from the
cache, a second or two when the source changed. :func:`load_kernels` makes that first call on a
probe body, so :func:`~aero_env.physics.run.simulate` can call it before it starts a run's clock and
no run's ``wall_time`` holds the one-time cost (as the reduced model's ``compile_kernels`` does).
The probe's arguments have the types a run passes, so the run finds the same compiled version.
"""

from __future__ import annotations

import time

import numpy as np
import pymunk

from . import body_state, check_kernel
from .slip_kernel import tip_slides

_loaded = False


def load_kernels() -> float:
    """Compile or load the kernels in this process; the seconds it took (about 0 after the first call)."""
    global _loaded
    t0 = time.perf_counter()
    if not _loaded:
        probe = pymunk.Body(1.0, 1.0)
        view = body_state.memory(probe)
        tip_slides(view, view, np.zeros(4), np.zeros((2, 5)), 1.0)
        address = body_state.address(probe)
        check_kernel.read_world(np.array([address] * 3, dtype=np.int64), np.ones((3, 4)), np.zeros(1, dtype=np.int64),
                                np.zeros(1, dtype=np.int64), np.zeros((1, 5)), np.zeros((1, 2, 5)),
                                np.zeros(check_kernel.N_CONSTS), np.zeros(check_kernel.FRAME_STATES + 6))
        _loaded = True
    return time.perf_counter() - t0
