"""How far one simulated run is from what it is fitted to; lower is better.

**A measured swing** (``--trace``): swing N is sampled at the measured times (linear between
trace rows) and the score is the RMS angle error in degrees over every compared value (theta1,
plus theta2 when measured). The measurement stops at the slip-off, while the simulated frame
turns on after its detach; so a measured time past the simulated detach is compared with the
simulated angle held at its last value before the detach, not with the freed frame's later
angle, which the video never saw. A run that detaches too early then pays for every degree the
measured theta1 still rises. Measured times before the first frame row (the few milliseconds in
which the runner confirms the catch, :mod:`.swing_metrics`) compare theta1 with that first row,
the frame near rest; theta2 has rows from the catch itself.

**Targets** (``--targets``): z = (simulated - value) / tolerance per target and the score is
sqrt(mean(z^2)): 1 means "off by one tolerance on average".

A run that has no swing N ending in a slip-off, or a target metric its swing does not produce,
gets a large but finite score (:data:`MISS_PENALTY`, :data:`MISSING_TARGET_Z`) so that the search
can still rank it below every real swing; the report names it a miss.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import simulation
from ..config import Config
from .measured import MeasuredSwing
from .swing_metrics import SwingMissing, SwingTrace, metrics_of, swing_trace
from .targets import Targets

MISS_PENALTY = 1e3  # score of a run without swing N: deg RMS (trace) or tolerances RMS (targets); finite, ranks
MISSING_TARGET_Z = 1e3  # z of a target metric the swing does not produce (e.g. theta1 never reaches 90 deg)


@dataclass
class Evaluation:
    """One run scored: the score, and what it was made of."""

    score: float
    miss: str | None = None  # why the run has no usable swing N; None when it has one
    metrics: dict | None = None  # swing_metrics.METRICS of swing N
    rms_theta1_deg: float | None = None
    rms_theta2_deg: float | None = None
    targets: list | None = None  # per target: metric, value, tolerance, unit, simulated, z
    swing: SwingTrace | None = None


def evaluate(cfg: Config, reference: MeasuredSwing | Targets, swing: int) -> Evaluation:
    """Simulate ``cfg`` with its trace and score swing ``swing`` against ``reference``."""
    result = simulation.simulate(cfg, trace=True)
    try:
        sw = swing_trace(result, swing)
    except SwingMissing as exc:
        return missed(str(exc), reference)
    metrics = metrics_of(sw)
    if isinstance(reference, MeasuredSwing):
        return Evaluation(**score_measured(sw, reference), metrics=metrics, swing=sw)
    return Evaluation(**score_targets(metrics, reference), metrics=metrics, swing=sw)


def missed(why: str, reference: MeasuredSwing | Targets) -> Evaluation:
    """The evaluation of a run without a usable swing."""
    targets = None
    if isinstance(reference, Targets):
        targets = [_target_row(t, None, None) for t in reference.targets]
    return Evaluation(score=MISS_PENALTY, miss=why, targets=targets)


def simulated_at(t: np.ndarray, times: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """A swing's ``angle`` (rows at ``t``) at ``times``: linear between rows, held beyond the ends."""
    return np.interp(times, t, angle)


def rms(x: np.ndarray) -> float:
    return float(math.sqrt(np.mean(np.square(x))))


def score_measured(sw: SwingTrace, measured: MeasuredSwing) -> dict:
    """RMS angle error (deg) of the swing against a measured one: overall, theta1, theta2."""
    err1 = simulated_at(sw.t, measured.t, sw.theta1) - measured.theta1
    errors = [err1]
    rms2 = None
    if measured.theta2 is not None:
        err2 = simulated_at(sw.t_robot, measured.t, sw.theta2) - measured.theta2
        errors.append(err2)
        rms2 = rms(err2)
    return dict(score=rms(np.concatenate(errors)), rms_theta1_deg=rms(err1), rms_theta2_deg=rms2)


def score_targets(metrics: dict, targets: Targets) -> dict:
    """sqrt(mean(z^2)) over the targets, z in tolerances; a metric the swing lacks counts MISSING_TARGET_Z."""
    rows = []
    for t in targets.targets:
        simulated = metrics.get(t.metric)
        z = None if simulated is None else (simulated - t.value) / t.tolerance
        rows.append(_target_row(t, simulated, z))
    zs = np.array([MISSING_TARGET_Z if r["z"] is None else r["z"] for r in rows])
    return dict(score=rms(zs), targets=rows)


def _target_row(t, simulated: float | None, z: float | None) -> dict:
    return dict(metric=t.metric, value=t.value, tolerance=t.tolerance, unit=t.unit, simulated=simulated, z=z,
                source=t.source)
