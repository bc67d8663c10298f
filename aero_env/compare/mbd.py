"""The MBD side of the comparison: one swing of the pymunk run, with the state the analytical models start from."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..config import Config, ConfigError
from ..models.two_link import SwingResult
from ..physics import simulate

FLIGHT_ENTERED = 1  # swing 1: caught from a flight, as in the paper's Sec. 7.3 and Figs. 40-43
FALLBACK_ANGLE_DEG = 150.0  # compared up to here when the MBD never lets go
SMOOTH_S = 0.01  # the MBD's theta1'' is a numerical derivative: averaged over 10 ms


def _first_time(t, theta1, angle) -> float | None:
    idx = np.nonzero(theta1 >= angle)[0]
    if idx.size == 0 or idx[0] == 0:
        return None
    i = idx[0]
    return float(t[i - 1] + (angle - theta1[i - 1]) / (theta1[i] - theta1[i - 1]) * (t[i] - t[i - 1]))


def _smooth(x, n):
    if n <= 1:
        return x
    kernel = np.ones(n) / n
    return np.convolve(np.pad(x, (n // 2, n - 1 - n // 2), mode="edge"), kernel, mode="valid")


@dataclass(frozen=True)
class MbdSwing:
    """One swing of the pymunk run, with the state the analytical models start from."""

    run: SwingResult  # t = 0 at the catch (the paper's Sec. 7.3 origin), up to the detach or 150 deg
    angle: float  # rad: the detach angle the models are compared up to
    outcome: str  # of the run (scene.frames = swing + 2)
    start: dict  # t (s after the catch), theta1, theta2, omega1, omega2 (rad, rad/s) of the first held row
    alpha: np.ndarray  # rad: the arm's angle to the torso at the run's samples (the leaf spring's bend)


def mbd_swing(cfg: Config, swing: int = FLIGHT_ENTERED, drag: bool = False) -> MbdSwing:
    """Swing ``swing`` of the pymunk run (0: the first, from rest; 1: the first entered from a flight,
    the one the paper measures) to its detach, or to 150 deg if it never lets go.

    The trace names a new frame once the catch has held (``sim.contact_hold``); the models start from
    that first row, at its time after the first touch, so every curve shares the paper's t = 0.
    """
    run_cfg = cfg.replace({"scene.frames": swing + 2, "scene.effects.drag": drag, "sim.trace_every": 1})
    r = simulate(run_cfg, trace=True)
    if len(r.swings) <= swing:
        raise ConfigError(f"compare --swing {swing}: the MBD robot never catches frame {swing} "
                          f"({r.outcome}: {r.reason}); choose a swing in 0..{len(r.swings) - 1}")
    tr = r.trace
    s = r.swings[swing]
    angle = math.radians(s.theta1_detach_deg if s.theta1_detach_deg is not None else FALLBACK_ANGLE_DEG)
    on = tr["frame"] == swing
    t = tr["t"] - s.t_catch
    t_end = s.swing_duration if s.t_detach is not None else t[on][-1]
    n = max(1, int(round(SMOOTH_S / cfg.sim.dt)))
    first = on & (t <= t_end + 1e-12)
    i0 = int(np.argmax(first))
    if swing == 0:  # the scene's own start state: at rest, before the world's first step settles it
        start = dict(t=0.0, theta1=math.radians(cfg.design.rest_angle_deg),
                     theta2=math.radians(cfg.scene.theta2_start_deg), omega1=0.0, omega2=0.0)
    else:
        start = dict(t=float(t[i0]), theta1=float(tr["theta1"][i0]), theta2=float(tr["theta2"][i0]),
                     omega1=float(tr["omega1"][i0]), omega2=float(tr["omega2"][i0]))
    # drop the first and last half-window: a moving average of a derivative is one-sided there
    keep = first & (t >= start["t"] + n * cfg.sim.dt / 2) & (t <= t_end - n * cfg.sim.dt / 2)
    a1 = _smooth(np.gradient(tr["omega1"], tr["t"]), n)[keep]
    a2 = _smooth(np.gradient(tr["omega2"], tr["t"]), n)[keep]
    t_angle = s.swing_duration if s.t_detach is not None else _first_time(t[first], tr["theta1"][first], angle)
    run = SwingResult(t[keep], tr["theta1"][keep], tr["theta2"][keep], tr["omega1"][keep], tr["omega2"][keep],
                      a1, a2, t_angle)
    return MbdSwing(run, angle, r.outcome, start, tr["alpha"][keep])
