"""What a run returns and how it names its end, the same at every fidelity.

Both engines (the pymunk runner, :mod:`aero_env.physics.run`, and the reduced model,
:mod:`aero_env.models.reduced`) return a :class:`SimResult`, judge a hooked frame by the same
thresholds, and write the same sentence for the same cause, so a result reads alike whichever
fidelity made it. Sentences take SI values (m, s) and angles in degrees. Nothing here imports
an engine.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

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
    import numpy as np

    from .units import GRAVITY as g

    balance = np.arctan2(d.m3 * g * d.h, d.m2 * g * d.Lb + d.dT - d.m3 * g * d.La) + 0.5 * np.pi
    rest, stop = np.radians(d.rest_angle_deg), np.radians(d.stop_angle_deg)
    return np.minimum(stop - np.radians(NEAR_STOP_DEG), np.maximum(balance, rest))

FRICTION_HELD = ": friction held the hook"  # how a no_detach says the hook's friction is what held it


@dataclass
class Swing:
    frame: int
    t_catch: float
    theta1_catch_deg: float
    theta2_catch_deg: float
    t_detach: float | None = None
    theta1_detach_deg: float | None = None
    swing_duration: float | None = None
    alpha_detach_deg: float | None = None
    theta2_min_deg: float | None = None
    theta2_max_deg: float | None = None
    catch_seat_mm: float | None = None  # the hook centre's closest approach to the seat while the catch held
    # s: when the frame, the hook still on, had turned the robot through its lowest point (theta1 reached
    # CARRIED_THETA1_DEG): from then the catch counts as a traversal. None where it never did.
    t_carried: float | None = None
    # The state when a catch is committed (sim.contact_hold after the first touch, the step theta2_catch_deg is
    # read at); the pymunk runner fills them for catches made from a flight, None for the start and the reduced model.
    omega1_catch: float | None = None  # rad/s: the caught frame's rate theta1'
    robot_speed_catch: float | None = None  # m/s: the robot's centre-of-mass speed
    hook_along_catch_mm: float | None = None  # the hook centre from the seat along the frame (+: towards its axis)
    hook_across_catch_mm: float | None = None  # ... and across it (+: the frame's own +y, up at theta1 = 0)


@dataclass
class SimResult:
    traversals: int  # catches on frames 1, 2, ... in turn that carried the robot (Swing.t_carried; CARRIED_THETA1_DEG)
    frames: int
    outcome: str
    reason: str
    swings: list[Swing]
    energy: dict
    sim_time: float
    wall_time: float
    miss_distance: float | None = None  # m: closest the hook came to the next handrail's seat in the failed transfer
    # (from the last counted traversal on, the hanging included: whether the transfer was a flight is ``flew``; a
    # catch that did not hold is still that transfer, so its miss is how close the hook came to that frame's seat)
    health: dict = field(default_factory=dict)  # largest joint drift (m), limit overshoot (deg), penetration (m)
    fidelity: str = "mbd"  # the sim.fidelity preset the run was made at
    trace: dict | None = field(default=None, repr=False)
    poses: list | None = field(default=None, repr=False)
    geometry: dict | None = field(default=None, repr=False)

    @property
    def flew(self) -> bool:
        """Whether the run ended in a flight: the hook let go of the last frame that caught it (that swing
        records its detach, ``t_detach``) and the robot flew towards the next frame, which did not catch it, or
        (a catch that did not hold) it let go of that frame before the frame carried it.
        False for a completed run and for runs whose hook never let go (stalled, no_detach), whatever
        ``miss_distance`` says (it is measured from the last traversal on, the hanging included)."""
        return self.outcome != "completed" and bool(self.swings) and self.swings[-1].t_detach is not None

    def to_json_dict(self) -> dict:
        """The fields of ``aero-env simulate --json`` (no trace or poses)."""
        return dict(traversals=self.traversals, frames=self.frames, outcome=self.outcome, reason=self.reason,
                    swings=[asdict(s) for s in self.swings], energy=dict(self.energy),
                    sim_time=self.sim_time, wall_time=self.wall_time, miss_distance=self.miss_distance,
                    health=dict(self.health), fidelity=self.fidelity)


# ---- the sentences (``SimResult.reason``) ----
def completed(last: int) -> str:
    return f"caught by the last frame ({last})"


def held_at_stop(frame: int, stop_hold: float, stop_deg: float, note: str = FRICTION_HELD) -> str:
    return f"hook still on frame {frame} {stop_hold} s after it reached its stop ({stop_deg:.0f} deg){note}"


def turned_back_holding(frame: int, peak_deg: float, past_deg: float, note: str = FRICTION_HELD) -> str:
    return (f"frame {frame} reached {peak_deg:.1f} deg, past {past_deg:.1f} deg where the weights stop driving it, "
            f"and turned back under the robot{note}")


def turned_back(frame: int, peak_deg: float) -> str:
    return (f"frame {frame} turned back at {peak_deg:.1f} deg, short of its stop, with the robot hooked: too little "
            f"moment imbalance")


def never_left_rest(frame: int, rest_timeout: float) -> str:
    return (f"frame {frame} never left its rest angle in {rest_timeout} s with the robot hooked: the counterbalance "
            f"outweighs the robot")


def held_past_balance(frame: int, peak_deg: float, past_deg: float, swing_timeout: float,
                      note: str = FRICTION_HELD) -> str:
    return (f"frame {frame} reached {peak_deg:.1f} deg, past {past_deg:.1f} deg where the weights stop driving it, "
            f"and still held the robot after {swing_timeout} s{note}")


def swing_too_long(frame: int, swing_timeout: float) -> str:
    return f"swing on frame {frame} lasted over {swing_timeout} s"


def reached_t_max(t_max: float) -> str:
    return f"reached sim.t_max = {t_max} s"


def _after(origin: int) -> str:
    return f"after leaving frame {origin}"


def spring_too_stiff(origin: int, alpha_deg: float) -> str:
    return (f"{_after(origin)}: the arm was at {alpha_deg:.0f} deg when the hook let go, with no swing left to reach "
            f"frame {origin + 1} (spring too stiff to bend)")


def released_low(origin: int, height: float) -> str:
    level = f"only {height * 1e3:.1f} mm above" if height >= 0 else f"{-height * 1e3:.1f} mm below"
    return (f"{_after(origin)}: the hook slipped off {level} frame {origin + 1}'s handrail, before the frame had "
            f"lifted the robot high enough")


def grazed(origin: int, distance: float) -> str:
    return (f"{_after(origin)}: the hook touched frame {origin + 1}'s handrail but never seated in its corner "
            f"(closest {distance * 1e3:.1f} mm from the seat): a graze")


def never_came_down(origin: int) -> str:
    return f"{_after(origin)}: the hook never came down to frame {origin + 1}'s handrail"


def spring_too_weak(origin: int, swung_deg: float) -> str:
    return (f"{_after(origin)}: the arm had swung only {swung_deg:.0f} deg forward when the hook came down to frame "
            f"{origin + 1}'s handrail (spring too weak)")


def catch_did_not_hold(origin: int, seat: float, held: float, theta1_deg: float) -> str:
    return (f"{_after(origin)}: frame {origin + 1} caught the hook {seat * 1e3:.1f} mm from its seat but it let go "
            f"after {held:.2f} s at theta1 = {theta1_deg:.0f} deg, before the frame carried the robot through its "
            f"lowest point (a catch that did not hold)")


def passed_behind(origin: int, distance: float) -> str:
    return f"{_after(origin)}: the hook passed {distance * 1e3:.1f} mm behind frame {origin + 1}'s handrail"


def passed_ahead(origin: int, distance: float) -> str:
    return (f"{_after(origin)}: the hook passed {distance * 1e3:.1f} mm ahead of frame {origin + 1}'s handrail or "
            f"bounced off")
