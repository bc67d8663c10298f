"""What a reduced run returns: :class:`BatchResult` for many designs, a SimResult for one, the outcome's sentence."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ... import reasons as say
from ...physics.swing_rules import TURN_BACK_DEG
from ...results import COLLIDES, SimResult, Swing
from .layout import (OUTCOMES, R_AHEAD, R_AT_REST, R_BARRIER, R_BARRIER_REST, R_BEHIND, R_COMPLETED, R_GRAZE,
                     R_HELD_LONG, R_LET_GO, R_LOW, R_NEVER_DOWN, R_STIFF, R_STOP_HOLD, R_TIMEOUT, R_TURN_BACK,
                     R_T_MAX, R_TURN_NEAR_STOP, R_WEAK, REASON_OUTCOME, O, P, W)

# the constants a reason's sentence quotes
TEXT_KEYS = ("stop_hold", "stop", "held_past", "swing_timeout", "rest_timeout", "t_max")
_OUTCOME_OF_REASON = np.array([REASON_OUTCOME[r] for r in range(len(REASON_OUTCOME))])


@dataclass
class BatchResult:
    """What :func:`simulate_batch` returns: one entry per design (arrays of length n)."""

    traversals: np.ndarray  # int: consecutive successful transfers (catches whose frame carried the robot)
    outcome: np.ndarray  # str: completed, no_detach, stalled, fell_short, missed_catch
    t_detach: np.ndarray  # s: the first swing's detach time (NaN if the hook never let go of frame 0)
    theta1_detach_deg: np.ndarray  # deg: frame 0's angle at that detach (NaN likewise)
    sim_time: np.ndarray  # s: simulated time at the run's end (the runner's rules: see the package docstring)
    miss_distance: np.ndarray  # m: closest the hook came to the next seat after the last traversal (NaN if completed);
    # the hanging is included, so only a run that ``flew`` (the property below) missed by it in flight
    frames: int
    swings: dict = field(repr=False, default_factory=dict)  # per-frame arrays (n, frames), NaN where not reached
    reason_code: np.ndarray = field(repr=False, default=None)
    reason_values: np.ndarray = field(repr=False, default=None)
    last_frame: np.ndarray = field(repr=False, default=None)
    energy: dict | None = field(repr=False, default=None)
    wall_time: float = 0.0
    _text: dict = field(repr=False, default_factory=dict)
    collided: dict = field(repr=False, default_factory=dict)  # design i -> why its kit's parts meet (collides)

    def __len__(self) -> int:
        return len(self.traversals)

    def collide(self, i: int, reason: str) -> None:
        """Design i's kit does not clear (``scene.effects.clearance``): its run becomes ``collides``, no traversal,
        no miss, no flight, whatever the model swung."""
        self.outcome[i], self.traversals[i], self.miss_distance[i] = COLLIDES, 0, np.nan
        self.collided[i] = reason

    @property
    def flew(self) -> np.ndarray:
        """bool: the run ended in a flight, as :attr:`aero_env.results.SimResult.flew`: the hook let go of the
        last frame that caught it (that frame's ``t_detach`` is recorded) and the next frame did not catch it."""
        t_detach = self.swings["t_detach"][np.arange(len(self)), self.last_frame]
        flew = (self.outcome != "completed") & np.isfinite(t_detach)
        flew[list(self.collided)] = False
        return flew

    def miss(self, i: int) -> float | None:
        """Design i's miss distance (m) as :class:`~aero_env.results.SimResult` keeps it: None where the run
        completed or has none."""
        m = float(self.miss_distance[i])
        return None if self.outcome[i] == "completed" or not math.isfinite(m) else m

    def reason(self, i: int) -> str:
        """Design i's outcome as a sentence with numbers (the runner's wording)."""
        if i in self.collided:
            return self.collided[i]
        return reason_text(int(self.reason_code[i]), *self.reason_values[i], int(self.last_frame[i]),
                           {k: v[i] for k, v in self._text.items()})


def batch_result(table: np.ndarray, out: np.ndarray, sw: np.ndarray, frames: int, wall: float,
                 detail: bool) -> BatchResult:
    reason = out[:, O.reason].astype(np.int64)
    outcome = np.array(OUTCOMES, dtype=object)[_OUTCOME_OF_REASON[reason]].astype(str)
    miss = np.where(outcome == "completed", np.nan, out[:, O.miss])
    miss = np.where(np.isfinite(miss), miss, np.nan)
    swings = {w.name: sw[:, w, :] for w in W}
    energy = None
    if detail:
        energy = dict(initial=out[:, O.e_first], final=out[:, O.e_last], max_gain=out[:, O.e_gain],
                      max_rise=out[:, O.e_rise])
    return BatchResult(traversals=out[:, O.traversals].astype(np.int64), outcome=outcome,
                       t_detach=swings["t_detach"][:, 0].copy(), theta1_detach_deg=swings["theta1_detach"][:, 0].copy(),
                       sim_time=out[:, O.end_time].copy(), miss_distance=miss, frames=frames, swings=swings,
                       reason_code=reason, reason_values=out[:, [O.v1, O.v2, O.v3]].copy(),
                       last_frame=out[:, O.last_frame].astype(np.int64), energy=energy, wall_time=wall,
                       _text={k: table[:, P[k]].copy() for k in TEXT_KEYS})


def sim_result(res: BatchResult, i: int, fidelity: str) -> SimResult:
    """Design i of a batch as the pymunk runner's :class:`~aero_env.results.SimResult` (the energy is the
    model's: frames, robot parts and spring; health is all zeros). A design whose kit collides: nothing simulated."""
    if i in res.collided:
        return SimResult(traversals=0, frames=res.frames, outcome=COLLIDES, reason=res.collided[i], swings=[],
                         energy={}, sim_time=0.0, wall_time=res.wall_time, fidelity=fidelity)
    sw = res.swings
    opt = lambda v: None if np.isnan(v) else float(v)  # noqa: E731
    swings = []
    for j in range(res.frames):
        tc = sw["t_catch"][i, j]
        if np.isnan(tc):
            break
        td = sw["t_detach"][i, j]
        swings.append(Swing(j, float(tc), float(sw["theta1_catch"][i, j]), float(sw["theta2_catch"][i, j]),
                            t_detach=opt(td), theta1_detach_deg=opt(sw["theta1_detach"][i, j]),
                            swing_duration=None if np.isnan(td) else float(td - tc),
                            alpha_detach_deg=opt(sw["alpha_detach"][i, j]),
                            theta2_min_deg=opt(sw["theta2_min"][i, j]), theta2_max_deg=opt(sw["theta2_max"][i, j]),
                            catch_seat_mm=opt(sw["catch_seat"][i, j] * 1e3), t_carried=opt(sw["t_carried"][i, j])))
    outcome = str(res.outcome[i])
    energy = {k: float(v[i]) for k, v in res.energy.items()} if res.energy is not None else {}
    return SimResult(traversals=int(res.traversals[i]), frames=res.frames, outcome=outcome, reason=res.reason(i),
                     swings=swings, energy=energy, sim_time=float(res.sim_time[i]), wall_time=res.wall_time,
                     miss_distance=res.miss(i),
                     health=dict(joint_drift=0.0, limit_overshoot_deg=0.0, penetration=0.0), fidelity=fidelity)


# each reason code's sentence (aero_env.reasons, the pymunk runner's words) from the kernel's values v = (v1, v2, v3),
# the frame ``origin`` and the design's TEXT_KEYS constants ``c``; the energy-barrier stalls are this model's own
_SENTENCES = {
    R_COMPLETED: lambda v, origin, c: say.completed(origin),
    R_STOP_HOLD: lambda v, origin, c: say.held_at_stop(origin, c["stop_hold"], math.degrees(c["stop"])),
    R_TURN_NEAR_STOP: lambda v, origin, c: say.turned_back_holding(origin, v[0], math.degrees(c["held_past"])),
    R_TURN_BACK: lambda v, origin, c: say.turned_back(origin, v[0]),
    R_TIMEOUT: lambda v, origin, c: say.swing_too_long(origin, c["swing_timeout"]),
    R_HELD_LONG: lambda v, origin, c: say.held_past_balance(origin, v[0], math.degrees(c["held_past"]),
                                                            c["swing_timeout"]),
    R_BARRIER: lambda v, origin, c: say.cannot_climb(origin, c["swing_timeout"], TURN_BACK_DEG),
    R_AT_REST: lambda v, origin, c: say.never_left_rest(origin, c["rest_timeout"]),
    R_BARRIER_REST: lambda v, origin, c: say.cannot_leave_rest(origin, c["rest_timeout"]),
    R_STIFF: lambda v, origin, c: say.spring_too_stiff(origin, v[0]),
    R_LOW: lambda v, origin, c: say.released_low(origin, v[0]),
    R_GRAZE: lambda v, origin, c: say.grazed(origin, v[0]),
    R_LET_GO: lambda v, origin, c: say.catch_did_not_hold(origin - 1, *v),  # origin: the frame that caught the hook
    R_NEVER_DOWN: lambda v, origin, c: say.never_came_down(origin),
    R_WEAK: lambda v, origin, c: say.spring_too_weak(origin, v[0]),
    R_BEHIND: lambda v, origin, c: say.passed_behind(origin, v[0]),
    R_AHEAD: lambda v, origin, c: say.passed_ahead(origin, v[0]),
    R_T_MAX: lambda v, origin, c: say.reached_t_max(c["t_max"]),
}


def reason_text(code: int, v1: float, v2: float, v3: float, origin: int, c: dict) -> str:
    """The sentence for a reason code (:data:`_SENTENCES`). ``c``: the design's TEXT_KEYS constants."""
    return _SENTENCES[code]((v1, v2, v3), origin, c)
