"""The quantities read at each catch, and the window of the last K catches.

Every quantity is one number per swing (a swing starts at a catch), read from the run's
:class:`~aero_env.results.Swing` list. The catch-state fields are read when the catch is committed
(``sim.contact_hold`` after the hook's first touch, the step ``theta2_catch_deg`` is read at);
the slip-off fields end the swing that catch started. A swing without the value (the start from
rest, the last frame's catch, which ends the run before any slip-off, or a fidelity that does not
record it) leaves the series shorter, so each quantity says how many catches it covers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..results import SimResult, Swing


@dataclass(frozen=True)
class Quantity:
    name: str  # the key in the JSON object
    label: str  # the table's row name
    unit: str
    digits: int  # decimals in the table
    read: Callable[[list[Swing], int], float | None]  # (the run's swings, index) -> value or None
    meaning: str


def _field(name: str) -> Callable[[list[Swing], int], float | None]:
    return lambda swings, i: getattr(swings[i], name)


def _catch_period(swings: list[Swing], i: int) -> float | None:
    """Time from the previous catch to this one (None for the start: no previous catch)."""
    return swings[i].t_catch - swings[i - 1].t_catch if i > 0 else None


QUANTITIES: tuple[Quantity, ...] = (
    Quantity("theta2_catch_deg", "theta2 at catch", "deg", 2, _field("theta2_catch_deg"),
             "the robot line's angle from the horizontal (90: hanging straight down)"),
    Quantity("hook_along_catch_mm", "hook along frame", "mm", 3, _field("hook_along_catch_mm"),
             "the hook centre's offset from the handrail's seat along the frame (+: towards its axis)"),
    Quantity("hook_across_catch_mm", "hook across frame", "mm", 3, _field("hook_across_catch_mm"),
             "the hook centre's offset from the seat across the frame (+: the frame's own +y)"),
    Quantity("omega1_catch", "frame rate theta1'", "rad/s", 3, _field("omega1_catch"),
             "the caught frame's angular rate (it rattles on its rest stopper as the robot lands)"),
    Quantity("robot_speed_catch", "robot speed", "m/s", 4, _field("robot_speed_catch"),
             "the robot's centre-of-mass speed"),
    Quantity("catch_period", "catch to catch", "s", 4, _catch_period,
             "time from the previous catch: the cycle's period"),
    Quantity("swing_duration", "swing duration", "s", 4, _field("swing_duration"),
             "catch to slip-off on this frame"),
    Quantity("theta1_detach_deg", "theta1 at slip-off", "deg", 2, _field("theta1_detach_deg"),
             "the frame's angle when the hook slipped off"),
)

CATCH_STATE = ("theta2_catch_deg", "hook_along_catch_mm", "hook_across_catch_mm", "omega1_catch",
               "robot_speed_catch")  # the state at the catch itself, as the issue names it


def window_of(result: SimResult, last: int) -> range:
    """Indices into ``result.swings`` of the last ``last`` catches (fewer when the run made fewer)."""
    n = len(result.swings)
    return range(max(0, n - last), n)


def catch_series(result: SimResult, quantity: Quantity, window: range) -> tuple[list[int], list[float]]:
    """(frame numbers, values) of ``quantity`` over the catches in ``window``, skipping those without it."""
    frames, values = [], []
    for i in window:
        v = quantity.read(result.swings, i)
        if v is not None:
            frames.append(result.swings[i].frame)
            values.append(float(v))
    return frames, values
