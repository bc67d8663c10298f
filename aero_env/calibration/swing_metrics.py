"""One swing of a traced run, and the numbers measured on it.

A run's swings are numbered by the frame that holds the robot: swing 0 starts from rest (the
run begins hooked on frame 0), swing 1 is the first one entered from a flight, the machine's
repeating cycle that the paper measures (Sec. 7.3; ``/work/shared/BRIEF.md``, "Which swing the
paper measures").

:func:`swing_trace` cuts swing N out of ``SimResult.trace``: the rows whose active frame is N,
from its catch to its detach, with time re-zeroed at the catch and angles in degrees. The
runner confirms a catch ``sim.contact_hold`` (10 ms) after the hook first touches, and until
then its trace rows record the previous frame's theta1 and theta1'. So the frame's angle and
rate are cut from the rows whose active frame is N, which start a few milliseconds after t = 0
(frame N still near its rest angle), while the robot's angles (theta2, alpha), which do not
depend on the frame, are cut from every row from the catch on: theta2 moves fast right after
the catch, and a video's first sample is at t = 0.

:func:`swing_metrics` measures the swing. The event numbers (duration, theta1 and theta2 at the
catch, theta1 at the detach, theta2's range) are the run's own ``Swing`` record, so a metric
reads exactly as ``aero-env simulate --json`` prints it; the rest come from the cut trace. A
metric the swing does not produce (no crossing of 90 deg, say) is ``None``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..physics.swing_rules import CARRIED_THETA1_DEG
from ..results import SimResult, Swing

# the handrail is straight below the axis here: the robot is at its lowest (the angle through which a frame
# must carry the robot for its catch to count, one definition for both)
LOWEST_THETA1_DEG = CARRIED_THETA1_DEG
OMEGA1_PROBE_DEG = 80.0  # the paper's MBD quotes theta1' (~1.1 rad/s) near theta1 = 80 deg (Sec. 7.3)
# Where theta1's dip is looked for: past the catch's first 10 deg (the catch's own transient) and up to
# Eq. (1)'s balance near 125 deg, past which every swing slows as the moment turns against it; the paper's
# dip (~1.1 rad/s near 80 deg) and its contact-shift jump near 115 deg lie inside.
DIP_WINDOW_DEG = (65.0, 125.0)

# name -> (unit, meaning); the metrics a targets file may name, in report order
METRICS: dict[str, tuple[str, str]] = {
    "swing_duration": ("s", "catch to slip-off"),
    "theta1_catch_deg": ("deg", "frame angle at the catch"),
    "theta2_catch_deg": ("deg", "robot line angle at the catch"),
    "theta1_detach_deg": ("deg", "frame angle at the slip-off"),
    "theta2_min_deg": ("deg", "smallest robot line angle while hooked"),
    "theta2_max_deg": ("deg", "largest robot line angle while hooked"),
    "theta2_mid_deg": ("deg", "the middle of theta2's range while hooked: the angle it oscillates about"),
    "t_lowest": ("s", f"time from the catch when theta1 first rises through {LOWEST_THETA1_DEG:g} deg (robot lowest)"),
    "alpha_at_lowest_deg": ("deg", f"arm angle alpha when theta1 first rises through {LOWEST_THETA1_DEG:g} deg"),
    "omega1_at_80_deg": ("rad/s", f"theta1' when theta1 first rises through {OMEGA1_PROBE_DEG:g} deg"),
    "mean_omega1": ("rad/s", "mean theta1' over the swing: (detach - catch angle) / duration"),
    "omega1_dip": ("rad/s", f"lowest theta1' while theta1 turns from {DIP_WINDOW_DEG[0]:g} to {DIP_WINDOW_DEG[1]:g} deg"),
    "theta1_at_dip_deg": ("deg", "theta1 where that lowest theta1' falls"),
}


class SwingMissing(LookupError):
    """The run has no swing N that ends in a slip-off (never caught by frame N, or never let go)."""


@dataclass(frozen=True)
class SwingTrace:
    """Swing N of a run: time from the catch (s), angles (deg), theta1' (rad/s).

    ``t`` times the frame's rows (``theta1``, ``omega1``), ``t_robot`` the robot's (``theta2``,
    ``alpha``), which start at the catch itself (see the module doc)."""

    swing: Swing
    t: np.ndarray
    theta1: np.ndarray
    omega1: np.ndarray
    t_robot: np.ndarray
    theta2: np.ndarray
    alpha: np.ndarray


def find_swing(result: SimResult, n: int) -> Swing:
    """The run's swing on frame ``n``, which must have ended in a slip-off."""
    for s in result.swings:
        if s.frame == n:
            if s.t_detach is None:
                raise SwingMissing(f"swing {n} never slipped off ({result.outcome}: {result.reason})")
            return s
    raise SwingMissing(f"the run never reached swing {n} ({result.outcome}: {result.reason})")


def swing_trace(result: SimResult, n: int) -> SwingTrace:
    """Swing ``n`` cut out of the run's trace, from its catch to its detach (see the module doc)."""
    if result.trace is None:
        raise ValueError("this result has no trace: simulate(..., trace=True)")
    s = find_swing(result, n)
    tr = result.trace
    t = tr["t"]
    robot_rows = (t >= s.t_catch) & (t <= s.t_detach)
    frame_rows = robot_rows & (tr["frame"] == n)
    if np.count_nonzero(frame_rows) < 2:
        raise SwingMissing(f"swing {n} has fewer than 2 trace rows between its catch and its detach")
    return SwingTrace(swing=s, t=t[frame_rows] - s.t_catch, theta1=np.degrees(tr["theta1"][frame_rows]),
                      omega1=np.asarray(tr["omega1"][frame_rows], dtype=float), t_robot=t[robot_rows] - s.t_catch,
                      theta2=np.degrees(tr["theta2"][robot_rows]), alpha=np.degrees(tr["alpha"][robot_rows]))


def rising_crossing(t: np.ndarray, y: np.ndarray, level: float) -> float | None:
    """The first time ``y`` rises through ``level`` (linear between samples), or None."""
    above = y >= level
    hits = np.flatnonzero(above[1:] & ~above[:-1])
    if hits.size == 0:
        return None
    i = hits[0]
    frac = (level - y[i]) / (y[i + 1] - y[i])
    return float(t[i] + frac * (t[i + 1] - t[i]))


def value_at(t: np.ndarray, y: np.ndarray, when: float | None) -> float | None:
    """``y`` at time ``when`` (linear between samples), or None when ``when`` is None."""
    return None if when is None else float(np.interp(when, t, y))


def swing_metrics(result: SimResult, n: int) -> dict[str, float | None]:
    """Every metric of :data:`METRICS` for swing ``n`` (raises :class:`SwingMissing`)."""
    sw = swing_trace(result, n)
    return metrics_of(sw)


def metrics_of(sw: SwingTrace) -> dict[str, float | None]:
    """The metrics of an already cut swing."""
    s = sw.swing
    t_lowest = rising_crossing(sw.t, sw.theta1, LOWEST_THETA1_DEG)
    t_probe = rising_crossing(sw.t, sw.theta1, OMEGA1_PROBE_DEG)
    mean_omega1 = math.radians(s.theta1_detach_deg - s.theta1_catch_deg) / s.swing_duration
    dip_rate, dip_at = theta1_dip(sw.theta1, sw.omega1)
    values = dict(swing_duration=s.swing_duration, theta1_catch_deg=s.theta1_catch_deg,
                  theta2_catch_deg=s.theta2_catch_deg, theta1_detach_deg=s.theta1_detach_deg,
                  theta2_min_deg=s.theta2_min_deg, theta2_max_deg=s.theta2_max_deg,
                  theta2_mid_deg=0.5 * (s.theta2_min_deg + s.theta2_max_deg), t_lowest=t_lowest,
                  alpha_at_lowest_deg=value_at(sw.t_robot, sw.alpha, t_lowest),
                  omega1_at_80_deg=value_at(sw.t, sw.omega1, t_probe), mean_omega1=mean_omega1,
                  omega1_dip=dip_rate, theta1_at_dip_deg=dip_at)
    return {name: (None if values[name] is None else float(values[name])) for name in METRICS}


def theta1_dip(theta1_deg: np.ndarray, omega1: np.ndarray) -> tuple[float | None, float | None]:
    """(theta1' at its lowest within :data:`DIP_WINDOW_DEG`, theta1 there), or (None, None) when the
    swing has no row in the window."""
    lo, hi = DIP_WINDOW_DEG
    inside = np.flatnonzero((theta1_deg >= lo) & (theta1_deg <= hi))
    if inside.size == 0:
        return None, None
    i = inside[int(np.argmin(omega1[inside]))]
    return float(omega1[i]), float(theta1_deg[i])
