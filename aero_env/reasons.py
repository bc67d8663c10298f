"""How a run names its end (``SimResult.reason``): one sentence per cause, the same at every fidelity.

The pymunk runner (:mod:`aero_env.physics`) writes them at its events, the reduced model
(:mod:`aero_env.models.reduced.outputs`) from its reason codes, so a result reads alike whichever fidelity made
it. Sentences take SI values (m, s) and angles in degrees.
"""

from __future__ import annotations

FRICTION_HELD = ": friction held the hook"  # how a no_detach says the hook's friction is what held it


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


def cannot_climb(frame: int, swing_timeout: float, climb_deg: float) -> str:
    return (f"swing on frame {frame} would last over {swing_timeout} s: the frame cannot climb "
            f"{climb_deg:.0f} deg above its rest with the energy it has, or fell back to its rest stop "
            f"(too little moment imbalance)")


def cannot_leave_rest(frame: int, rest_timeout: float) -> str:
    return (f"frame {frame} would never leave its rest angle in {rest_timeout} s with the robot hooked "
            f"(it cannot climb with the energy it has): the counterbalance outweighs the robot")
