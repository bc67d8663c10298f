"""The rules that end a hooked frame's swing and make a catch a traversal, the same in both engines.

The pymunk runner (:mod:`.phases`) applies them to its world; the reduced model restates them in its compiled
phases (:mod:`aero_env.models.reduced.hooked_phase`, :mod:`aero_env.models.reduced.transitions`) and takes the
turn-back angle from :func:`held_past_angle`, the same function. Angles in degrees where the name says so.
"""

from __future__ import annotations

import math

import numpy as np

from ..units import GRAVITY as g

# ---- when a hooked frame's swing has ended ----
TURN_BACK_DEG = 20.0  # a hooked frame this far below its peak angle has turned back
NEAR_STOP_DEG = 10.0  # a turn-back this close to the stop is the high-friction failure (no_detach)
STOP_TOLERANCE = 1e-3  # rad: a frame this close to its stop angle is at its stop
REST_MOVE = math.radians(0.5)  # a frame that never turned this far from its rest angle has not moved

# ---- when a catch is a traversal ----
# A catch counts as a traversal only once the caught frame has *carried* the robot: turned it, hook still on,
# through its lowest point, theta1 >= CARRIED_THETA1_DEG (the handrail straight below the axis; the
# calibration's LOWEST_THETA1_DEG is this constant). A touch held sim.contact_hold with the hook
# within sim.catch_seat of the seat is a catch, but a hook can be caught 2.95 mm off its seat and fall out
# 0.08 s later: that catch did not hold, and the run ends there (missed_catch: catch_did_not_hold). The last
# frame's catch completes the row by the same rule, not by "the frame reached its stop": on every frame the
# prototype lets go near 160 deg, short of the 180 deg stop, so a stop rule would fail it on the last frame.
# The frame-0 swing is the start from rest, no catch: its t_carried is recorded but counts nothing.
CARRIED_THETA1_DEG = 90.0


def held_past_angle(d):
    """theta1 (rad) past which a hooked frame that turns back was carried by its momentum and kept the
    robot, so friction held the hook (no_detach); a turn-back before it had too little imbalance (stalled).

    It is where the quasi-static moment on the frame, Eq. (1)'s right side
    (m2·g·Lb + dT - m3·g·La)·cos θ + m3·g·h·sin θ = R·cos(θ - φ), changes sign from + to - (θ = φ + 90 deg:
    125.3 deg for the prototype, as the article states), at least the rest angle and at most NEAR_STOP_DEG
    short of the stop. ``d`` is a design, or an object with the design's fields as numpy arrays."""
    balance = np.arctan2(d.m3 * g * d.h, d.m2 * g * d.Lb + d.dT - d.m3 * g * d.La) + 0.5 * np.pi
    rest, stop = np.radians(d.rest_angle_deg), np.radians(d.stop_angle_deg)
    return np.minimum(stop - np.radians(NEAR_STOP_DEG), np.maximum(balance, rest))
