"""Naming a failed transfer by its cause (the brief's failure modes), from what the flight saw."""

from __future__ import annotations

import math

from .. import reasons as say
from .. import units


class FlightRecord:
    """What happened since the hook last touched frame ``origin`` (engine units, radians): the
    state at the detach, and in flight the arm's snap and the hook's descent past the next seat."""

    def __init__(self, origin: int, t_detach: float, theta1_detach: float, alpha_detach: float, hook_y: float,
                 seat, snapped_alpha: float):
        self.origin = origin
        self.t_detach = t_detach
        self.theta1_detach = theta1_detach
        self.alpha_detach = alpha_detach
        # the next frame's seat (None on the last frame, which a detach never flies from: see phases.LettingGo);
        # the arm half-way snapped
        self.seat, self.snapped_alpha = seat, snapped_alpha
        self.height = hook_y - seat.y if seat is not None else math.nan  # hook height above it when it let go
        self.crossing: tuple[float, float] | None = None  # (hook x - seat x, alpha) as the hook sinks below the seat
        self.t_cross: float | None = None
        self.t_snap: float | None = None  # when the arm had swung through half its range
        self.graze: float | None = None  # closest the hook came to the next seat while touching without seating
        self.watching = True  # until both the snap and the crossing are seen

    def observe(self, t: float, robot) -> None:
        """Per runner step until both the snap and the crossing are seen."""
        if not self.watching:
            return
        if self.t_snap is None and robot.alpha < self.snapped_alpha:
            self.t_snap = t - self.t_detach
        if self.crossing is None and self.seat is not None:
            hook = robot.hook_world()
            if hook.y < self.seat.y:
                self.crossing = (hook.x - self.seat.x, robot.alpha)
                self.t_cross = t - self.t_detach
        self.watching = self.t_snap is None or self.crossing is None

    def note_graze(self, gap: float) -> None:
        """The hook touched the next handrail and came no closer than ``gap`` to its seat."""
        self.graze = gap if self.graze is None else min(self.graze, gap)


def classify_miss(flight: FlightRecord, p) -> tuple[str, str]:
    """Name a failed transfer by its cause, in this order:

    1. the arm had less than half its range left at detach -> ``missed_catch`` (spring too stiff:
       it never bent, so it has no motion left);
    2. the hook left the handrail less than ``sim.min_release_height`` above the next handrail ->
       ``fell_short`` (it slipped off before the frame had lifted the robot);
    3. the hook touched the next handrail but never seated in its corner -> ``missed_catch`` (a graze);
    4. the arm was still swinging when the hook came down to the next handrail -> ``missed_catch``
       (spring too weak for the fall);
    5. the arm was ready: the hook passed behind the handrail -> ``fell_short``, ahead -> ``missed_catch``.
    """
    si = units.length_to_si
    half_range = 0.5 * (p.alpha_max - p.alpha_min)
    if flight.alpha_detach - p.alpha_min < half_range:
        return "missed_catch", say.spring_too_stiff(flight.origin, math.degrees(flight.alpha_detach))
    if flight.height < p.min_release_height:
        return "fell_short", say.released_low(flight.origin, si(flight.height))
    if flight.graze is not None:
        return "missed_catch", say.grazed(flight.origin, si(flight.graze))
    if flight.crossing is None:
        return "missed_catch", say.never_came_down(flight.origin)
    dx, alpha_cross = flight.crossing
    if flight.t_snap is None or flight.t_snap > flight.t_cross:
        return "missed_catch", say.spring_too_weak(flight.origin, math.degrees(flight.alpha_detach - alpha_cross))
    if dx < 0:
        return "fell_short", say.passed_behind(flight.origin, si(-dx))
    return "missed_catch", say.passed_ahead(flight.origin, si(dx))
