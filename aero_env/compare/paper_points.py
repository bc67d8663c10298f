"""The paper's own words about the swing it measures, checked one by one against the MBD.

Sec. 7.3 and Figs. 40-43 describe the flight-entered swing (t = 0 when the arm, having slipped
off the preceding handrail, catches on the next one) in sentences, not tables. Each sentence
becomes a :class:`PaperPoint`: the figure the paper gives, how far from it still counts as the
same (the issue's tolerance where it names one, otherwise stated here as loose), and a function
that reads the same quantity off the MBD's swing. ``aero-env compare --json`` carries the result,
and ``docs/physics.md`` prints it beside the paper's sentence.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..calibration.swing_metrics import LOWEST_THETA1_DEG, rising_crossing, theta1_dip
from ..models.two_link import SwingResult
from .mbd import MbdSwing

AFTER_CATCH_DEG = 5.0  # theta1'' is read past the catch's own transient (the frame leaving its stopper)


@dataclass(frozen=True)
class PaperPoint:
    key: str
    paper: str  # the paper's sentence, shortened
    value: float  # the paper's figure
    tolerance: float | None  # how far from it still counts as agreeing; None: shown, not checked (why: ``paper``)
    unit: str
    measure: Callable[[MbdSwing, SwingResult], float | None]


def _deg(x) -> float:
    return float(np.degrees(x))


def _theta1_rate_dip(m: MbdSwing) -> tuple[float | None, float | None]:
    """theta1' at its lowest while the frame turns through the dip's window, and theta1 (deg) there: the
    calibration's own measure (:func:`aero_env.calibration.swing_metrics.theta1_dip`), so compare and the
    fit read one dip."""
    r = m.run
    return theta1_dip(np.degrees(r.theta1), r.omega1)


def _t_lowest(m: MbdSwing) -> float | None:
    """Time from the catch when theta1 first rises through 90 deg: the handrail straight below the axis."""
    return rising_crossing(m.run.t, np.degrees(m.run.theta1), LOWEST_THETA1_DEG)


def _alpha_when_lowest(m: MbdSwing) -> float | None:
    t = _t_lowest(m)
    return None if t is None else _deg(np.interp(t, m.run.t, m.alpha))


def _sign_turns(m: MbdSwing) -> tuple[float | None, float | None]:
    """theta1 (deg) where theta1'' first goes from + to - past the catch transient, and where it
    next comes back to +."""
    r = m.run
    past = r.theta1 >= m.start["theta1"] + math.radians(AFTER_CATCH_DEG)
    th, a = r.theta1[past], r.alpha1[past]
    down = np.nonzero((a[:-1] > 0) & (a[1:] <= 0))[0]
    if not down.size:
        return None, None
    up = np.nonzero((a[down[0]:-1] <= 0) & (a[down[0] + 1:] > 0))[0]
    return _deg(th[down[0]]), (_deg(th[down[0] + up[0]]) if up.size else None)


def _opposite_accelerations(m: MbdSwing) -> float:
    r = m.run
    return float(np.mean(np.sign(r.alpha1) * np.sign(r.alpha2) < 0))


def _two_link_alpha1_rms(m: MbdSwing, tl: SwingResult) -> float:
    """RMS difference of theta1'' (two-link minus MBD) at the same theta1, over max |MBD theta1''|
    outside the catch transient: the paper's "closely match" as a number."""
    r = m.run
    past = r.theta1 >= m.start["theta1"] + math.radians(AFTER_CATCH_DEG)
    th, a = r.theta1[past], r.alpha1[past]
    keep = np.concatenate([[True], np.diff(np.maximum.accumulate(th)) > 0])
    order = np.argsort(tl.theta1)
    model = np.interp(th[keep], tl.theta1[order], tl.alpha1[order])
    return float(np.sqrt(np.mean((model - a[keep]) ** 2)) / np.abs(a[keep]).max())


POINTS = (
    PaperPoint("swing_duration", "the arm slips off at ~165 deg at t = 0.62 s", 0.62, 0.06, "s",
               lambda m, _tl: m.run.t_until),
    PaperPoint("theta1_catch", "the initial angles are approximately theta1 = 55", 55.0, 5.0, "deg",
               lambda m, _tl: _deg(m.start["theta1"])),
    PaperPoint("theta1_detach", "the arm slips off the handrail at approximately theta1 = 165", 165.0, 5.0, "deg",
               lambda m, _tl: _deg(m.angle)),
    PaperPoint("theta2_catch", "... and theta2 = 81 (Sec. 7.3; ~80-81 read off Fig. 40)", 81.0, 6.0, "deg",
               lambda m, _tl: _deg(m.start["theta2"])),
    PaperPoint("theta2_centre", "theta2 oscillates around 90 deg (Sec. 7.3): the middle of its range while hooked",
               90.0, 5.0, "deg", lambda m, _tl: _deg(0.5 * (m.run.theta2.min() + m.run.theta2.max()))),
    PaperPoint("t_lowest", "the robot passes its lowest point (theta1 = 90 deg) at t ~0.3 s", 0.3, 0.05, "s",
               lambda m, _tl: _t_lowest(m)),
    PaperPoint("alpha_when_lowest", "the spring fully bent (alpha ~120 deg) when the robot is lowest",
               120.0, 5.0, "deg", lambda m, _tl: _alpha_when_lowest(m)),
    PaperPoint("theta1_rate_dip", "theta1' decreases to around 1.1 rad/s ...", 1.1, 0.3, "rad/s",
               lambda m, _tl: _theta1_rate_dip(m)[0]),
    PaperPoint("theta1_rate_dip_at", "... when theta1 reaches approximately 80 deg (the video: turns near 90)",
               80.0, 10.0, "deg", lambda m, _tl: _theta1_rate_dip(m)[1]),
    # Below ~90 deg theta1' falls and above it rises (MBD and video, Sec. 7.3), with the dip near 80-90 deg:
    # theta1'' turns - after the catch's push and before the dip, and + again at the dip.
    PaperPoint("alpha1_turns_negative", "theta1'' changes sign (+, -, +) between 55 and 125 deg: to - before the "
               "dip (between the catch and 80 deg)", 67.5, 12.5, "deg", lambda m, _tl: _sign_turns(m)[0]),
    PaperPoint("alpha1_turns_positive", "... and back to + where theta1' turns from falling to rising, near "
               "80 deg (MBD) to 90 deg (video)", 85.0, 10.0, "deg", lambda m, _tl: _sign_turns(m)[1]),
    PaperPoint("opposite_accelerations", "theta1'' and theta2'' of opposite sign for much of the swing "
               "(share of the swing; loose)", 0.7, 0.2, "-", lambda m, _tl: _opposite_accelerations(m)),
    PaperPoint("two_link_alpha1", "the two-link model's theta1'' closely matches the MBD's (RMS over the "
               "largest MBD value; loose)", 0.0, 0.25, "-", _two_link_alpha1_rms),
    PaperPoint("mean_theta1_rate", "mean theta1' 1.7 rad/s (MBD), 1.5 (video): not checked, the paper's own "
               "figures do not add up (110 deg in 0.62 s is a mean of 3.1 rad/s)", 1.7, None, "rad/s",
               lambda m, _tl: (m.angle - m.start["theta1"]) / m.run.t_until if m.run.t_until else None),
)


def paper_points(mbd: MbdSwing, two_link_run: SwingResult) -> list[dict]:
    """Each of the paper's statements with the MBD's value and whether it lies within tolerance."""
    out = []
    for p in POINTS:
        ours = p.measure(mbd, two_link_run)
        ours = None if ours is None else float(ours)
        holds = None if p.tolerance is None else (ours is not None and abs(ours - p.value) <= p.tolerance)
        out.append(dict(key=p.key, paper=p.paper, paper_value=p.value, tolerance=p.tolerance, unit=p.unit,
                        ours=ours, holds=holds))
    return out
