"""What a run returns, the same at every fidelity: :class:`SimResult` and its :class:`Swing` records.

Both engines (the pymunk runner, :mod:`aero_env.physics.run`, and the reduced model,
:mod:`aero_env.models.reduced`) return a :class:`SimResult`; they judge a hooked frame by the same rules
(:mod:`aero_env.physics.swing_rules`) and word its end in the same sentences (:mod:`aero_env.reasons`), so a
result reads alike whichever fidelity made it. Nothing here imports an engine.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

COLLIDES = "collides"  # the outcome of a run whose kit's parts meet (scene.effects.clearance): not simulated


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
    traversals: int  # catches on frames 1, 2, ... in turn that carried the robot (Swing.t_carried; swing_rules.CARRIED_THETA1_DEG)
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
