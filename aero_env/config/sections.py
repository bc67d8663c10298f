"""The config's sections: ``design``, ``scene`` (with its ``effects``), ``sim`` and ``env``.

Every field is declared once here with :func:`spec` (default, unit, allowed range, meaning); the
field order is the order of the schema table. Also the fidelity presets, the cross-checks
between a section's fields, and the real-valued keys that list entries may name.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from ..parts.bodies import min_Ld, torso_build
from ..parts import build
from ..units import GRAVITY
from .validation import ConfigError, did_you_mean


def spec(default: Any, unit: str, doc: str, lo: float | None = None, hi: float | None = None,
         lo_open: bool = False, choices: tuple[str, ...] | None = None):
    """Declare one config field: default, unit, meaning and allowed range."""
    return field(default=default, metadata=dict(unit=unit, doc=doc, lo=lo, hi=hi,
                                                lo_open=lo_open, choices=choices))


@dataclass(frozen=True)
class Design:
    """What a designer changes. Table 1 and Table 3 (white/gray) of the article by default."""

    La: float = spec(0.0483, "m", "axis to counterbalance, along the frame", 0.0, 1.0, lo_open=True)
    Lb: float = spec(0.0517, "m", "axis to handrail (the hook's seat)", 0.0, 1.0, lo_open=True)
    Lc: float = spec(0.03, "m", "the arm (Table 1); the paper's two-link model: joint (hook) to robot centre, sets I2 "
                     "with Ld", 0.0, 0.3)
    Ld: float = spec(0.06, "m", "hook to the torso's bottom with the arm at alpha_max (Table 1, Appendix A): sets the "
                     "built torso's length; the paper's two-link model: sets I2 with Lc", 0.0, 0.5, lo_open=True)
    h: float = spec(0.005, "m", "counterbalance offset normal to the frame", -0.1, 0.1)
    m1: float = spec(0.004, "kg", "swing frame mass: its two side cards, whose inertia the world takes as the kit "
                     "builds them (aero_env/parts); the analytical models' A13: I1 = 2*m1/3*(La^2+Lb^2-La*Lb)", 0.0, 0.1,
                     lo_open=True)
    m2: float = spec(0.00771, "kg", "robot mass as Table 1 counts it: torso card + coins + arm + the handrail "
                     "(handrail_mass, which the world puts on the frame)", 0.0, 0.1, lo_open=True)
    m3: float = spec(0.0072, "kg", "counterbalance mass (point mass at (La, h))", 0.0, 0.1, lo_open=True)
    dT: float = spec(0.0, "N·m", "frame's own moment at theta1 = 0 without robot and counterbalance", -0.1, 0.1)
    spring_k: float = spec(8.77e-4, "N·m/rad", "leaf-spring stiffness (torque = k·(alpha - alpha_min))", 0.0, 0.1, lo_open=True)
    spring_damping: float = spec(0.0, "-", "the leaf spring card's internal damping as a damping ratio of the arm "
                                 "swinging on the spring about its axle (c = 2·zeta·sqrt(k·m_arm·arm_length²/3)); "
                                 "paper's loss tangent is a few hundredths, so zeta ~0.01-0.03 (0: none, no cost)",
                                 0.0, 2.0)
    mu_s: float = spec(0.542, "-", "static friction, arm tip on handrail", 0.0, 10.0)
    mu_k: float = spec(0.409, "-", "kinetic friction, arm tip on handrail (<= mu_s)", 0.0, 10.0)
    arm_length: float = spec(0.03, "m", "arm: torso axle to hook tip", 0.0, 0.3, lo_open=True)
    arm_mass: float = spec(0.0015, "kg", "arm mass (part of m2): a laminated card plate from behind the axle to the "
                           "hook, as the kit builds it (aero_env/parts)", 0.0, 0.1, lo_open=True)
    coin_mass: float = spec(0.004, "kg", "coins on the torso (part of m2; four 1-yen coins of 1 g)", 0.0, 0.1)
    coin_radius: float = spec(0.01, "m", "coin radius (a 1-yen coin is 20 mm across)", 0.0, 0.1)
    handrail_mass: float = spec(0.00021, "kg", "the handrail's card, counted in m2 by Table 1 and carried by the "
                                "frame at the seat (docs/physics.md: 0.21 g, not the 2.1 g the text prints)",
                                0.0, 0.01)
    pivot_friction: float = spec(1.185e-4, "N·m", "Coulomb friction torque of each frame's bamboo skewer in its card "
                                 "shaft hole (0: no part built)", 0.0, 0.01)
    axle_friction: float = spec(4.25e-5, "N·m", "Coulomb friction torque at the arm's axle in the torso (0: no part "
                                "built)", 0.0, 0.01)
    alpha_min_deg: float = spec(60.0, "deg", "arm angle with the spring straight (arm snapped forward)", 0.0, 180.0)
    alpha_max_deg: float = spec(120.0, "deg", "arm angle with the spring fully bent", 0.0, 180.0)
    rest_angle_deg: float = spec(55.0, "deg", "frame angle theta1 at rest, counterbalance against the stopper", -90.0, 270.0)
    stop_angle_deg: float = spec(180.0, "deg", "frame angle theta1 at the end stop", -90.0, 270.0)
    notch_angle_deg: float = spec(64.73, "deg", "handrail notch bisector direction (world) at the rest angle", -180.0, 180.0)
    notch_opening_deg: float = spec(90.0, "deg", "angle between the handrail notch's two faces", 30.0, 150.0)
    # a face at least 0.1 mm long: a shorter one is no card the hook can touch, and its segment in the engine
    # (corner + face x direction) rounds to a point, a zero-length segment the world cannot build
    notch_back_face: float = spec(0.00572, "m", "handrail notch face that rises toward the back (at rest)", 1e-4, 0.1)
    notch_front_face: float = spec(0.01095, "m", "handrail notch face that rises toward the front (at rest)", 1e-4, 0.1)
    handrail_thickness: float = spec(0.001, "m", "card thickness of the handrail faces", 0.0, 0.01, lo_open=True)
    hook_radius: float = spec(0.001, "m", "radius of the arm tip's contact edge", 0.0, 0.01, lo_open=True)
    Cd: float = spec(1.05, "-", "drag coefficient (drag effect)", 0.0, 10.0)
    rho: float = spec(1.29, "kg/m^3", "air density (drag effect)", 0.0, 100.0)
    frame_width: float = spec(0.01, "m", "projected width of a frame, per unit length (drag effect)", 0.0, 0.1)
    robot_width: float = spec(0.02, "m", "projected width of torso and arm (drag effect)", 0.0, 0.1)

    # Derived from Table 1, never set: a config that names one is told what it follows from.
    DERIVED = MappingProxyType({
        "torso_length": "the torso card's length follows from design.Ld (hook to the torso's bottom at "
                        "alpha_max), design.arm_length and design.alpha_max_deg; set design.Ld",
        "coin_offset": "the coins sit flush with the torso's bottom, one design.coin_radius above it; set design.Ld "
                       "or design.coin_radius",
    })

    @property
    def torso_length(self) -> float:
        """The torso card strip below the axle (m): its bottom Ld from the hook at alpha_max."""
        return float(torso_build(self.Ld, self.arm_length, self.alpha_max_deg, self.coin_radius)[0])

    @property
    def coin_offset(self) -> float:
        """Axle to the coins' centre along the torso (m): flush with its bottom."""
        return float(torso_build(self.Ld, self.arm_length, self.alpha_max_deg, self.coin_radius)[1])


@dataclass(frozen=True)
class Effects:
    """The effects a scene switches on; the builder adds only the parts named here."""

    drag: bool = spec(False, "-", "quadratic air drag on frames, torso and arm")
    friction: str = spec("static_kinetic", "-", "hook friction law: static_kinetic switches mu_s/mu_k by slip speed; "
                         "static or kinetic use one coefficient", choices=("static_kinetic", "static", "kinetic"))
    spring_law: str = spec("linear", "-", "leaf spring: linear k·da, or stiffening k/2·da^2",
                           choices=("linear", "stiffening"))
    live_frames: int = spec(1, "-", "frames ahead of the robot's frame that are simulated (others cost nothing)", 1, 100)
    hook: str = spec("contact", "-", "contact: the frictional hook on the notched handrail; pin: the two-link model "
                     "(hook pinned to frame 0, robot one rigid body with m2, Lc, I2; for checking the world)",
                     choices=("contact", "pin"))
    clearance: bool = spec(False, "-", "check first that the kit's parts clear each other as every frame turns "
                           "(its layout fitted, the row swept in 3D: up to half a minute a design, then kept); "
                           "a design whose parts meet ends as 'collides'")


@dataclass(frozen=True)
class Scene:
    """The row of frames and the start state."""

    frames: int = spec(8, "-", "swing frames in the row", 2, 1000)
    pitch: float = spec(0.076, "m", "horizontal distance between neighbouring frame axes", 0.0, 0.5, lo_open=True)
    rise: float = spec(0.002, "m", "height gained per frame (the incline of the row)", -0.1, 0.1)
    theta2_start_deg: float = spec(81.0, "deg", "robot line angle at the first catch (brief: 80-81)", 0.0, 180.0)
    floor_drop: float = spec(0.15, "m", "floor depth below the axis of the frame the robot left", 0.0, 2.0, lo_open=True)
    effects: Effects = field(default_factory=Effects, metadata=dict(unit="", doc="effects switched on", lo=None,
                                                                    hi=None, lo_open=False, choices=None))


# The fidelity ladder, cheapest to most accurate. A preset is data: it fills the sim fields it
# names, and a field the config names beside it wins (see ``from_dict``). ``model`` picks the
# engine: ``mbd`` is the pymunk world, ``reduced`` the two-link swing with ballistic flight and a
# geometric catch test (no pymunk; ``dt`` is then its integration step). ``reference`` is the step
# and iteration count past which refining (half the step, twice the iterations) keeps the traversal count of >= 99 %
# of random designs and moves the median first detach by <= one default step (measured: 99.0 %,
# 0.19 ms on 200 designs): docs/fidelity.md, "The ladder, measured", gives the study and the rungs.
FIDELITY_PRESETS: dict[str, dict[str, Any]] = {
    "reduced": dict(model="reduced", dt=0.004, iterations=1, substeps=1),
    "mbd": dict(model="mbd", dt=0.0005, iterations=30, substeps=1),
    "mbd-fine": dict(model="mbd", dt=0.00025, iterations=30, substeps=2),
    "reference": dict(model="mbd", dt=0.0000625, iterations=120, substeps=1),
}
DEFAULT_FIDELITY = "mbd"
# Rungs that left the ladder, and why: a config that names one gets this line, not only the list of rungs.
REMOVED_FIDELITIES = {
    "mbd-fast": "left the ladder: at its 1 ms step it agreed with the reference on 89.6 % of converged designs near "
                "the prototype, below the 90 % a rung must reach (docs/fidelity.md); the same step is still "
                "sim.fidelity=mbd with sim.dt=0.001",
}


def pymunk_fidelities() -> str:
    """The rungs that run the pymunk world, cheapest first, for messages."""
    return ", ".join(name for name, preset in FIDELITY_PRESETS.items() if preset["model"] == "mbd")


@dataclass(frozen=True)
class Sim:
    """Fidelity, time stepping, solver and event thresholds."""

    fidelity: str = spec(DEFAULT_FIDELITY, "-", "named preset of model, dt, iterations and substeps "
                         "(cheapest first); a field set beside it wins over the preset",
                         choices=tuple(FIDELITY_PRESETS))
    model: str = spec("mbd", "-", "mbd: the pymunk world; reduced: two-link swing + ballistic flight + geometric "
                      "catch test, no pymunk (set by the fidelity preset)", choices=("mbd", "reduced"))
    dt: float = spec(0.0005, "s", "physics time step (reduced: its integration step); set by the fidelity preset",
                     0.0, 0.01, lo_open=True)
    iterations: int = spec(30, "-", "pymunk solver iterations per step; set by the fidelity preset", 1, 1000)
    substeps: int = spec(1, "-", "pymunk steps of dt per runner step: events, friction switching and checks run "
                         "once per runner step; set by the fidelity preset", 1, 100)
    collision_slop: float = spec(2e-5, "m", "allowed contact overlap (pymunk slop)", 0.0, 0.001)
    slip_speed: float = spec(0.001, "m/s", "tangential speed above which the hook slides (mu_k)", 0.0, 1.0, lo_open=True)
    contact_hold: float = spec(0.01, "s", "contact must be lost (or kept) this long for a detach (or catch)", 0.0, 1.0, lo_open=True)
    catch_seat: float = spec(0.003, "m", "a touch of the next handrail held for contact_hold is a catch only if the "
                             "hook's centre came this close to the seat (the notch's corner) meanwhile; a seated hook "
                             "sits there up to its penetration (< 1 mm); farther touches are grazes", 0.0, 0.1,
                             lo_open=True)
    flight_timeout: float = spec(0.5, "s", "longest flight between detach and catch", 0.0, 10.0, lo_open=True)
    swing_timeout: float = spec(3.0, "s", "longest swing on one frame: past it the run counts as stalled, or as no_detach "
                                "when the frame has passed its balance angle with the robot still hooked", 0.0, 60.0,
                                lo_open=True)
    rest_timeout: float = spec(1.0, "s", "a frame that has not left its rest angle this long after the catch never "
                               "will (the hanging robot's swing only loses energy, so its largest pull comes "
                               "first): stalled", 0.0, 60.0, lo_open=True)
    stop_hold: float = spec(0.3, "s", "time hooked at the end stop before the run is no_detach", 0.0, 10.0, lo_open=True)
    t_max: float = spec(60.0, "s", "hard limit on simulated time for a run", 0.0, 3600.0, lo_open=True)
    energy_tolerance: float = spec(0.005, "-", "largest rise of mechanical energy above its running minimum before "
                                   "'unstable', as a fraction of (m2 + m3)·g·(La + Lb) + the spring's energy "
                                   "fully bent", 0.0, 1.0, lo_open=True)
    check_interval: float = spec(0.005, "s", "check energy, health and finiteness this often (at least every runner "
                                 "step; and every step while the hook is being caught, where penetration peaks)",
                                 0.0, 1.0, lo_open=True)
    min_release_height: float = spec(0.01, "m", "a hook letting go lower than this above the next handrail has fallen short", 0.0, 1.0)
    max_speed: float = spec(20.0, "m/s", "any body faster than this is 'unstable'", 0.0, 1e4, lo_open=True)
    max_joint_drift: float = spec(1e-3, "m", "a frame skewer, the arm's axle or a pinned hook coming apart by more "
                                  "than this is 'unstable'", 0.0, 0.1, lo_open=True)
    max_limit_overshoot_deg: float = spec(5.0, "deg", "a frame or the arm turning past its stopper by more than "
                                          "this is 'unstable'", 0.0, 90.0, lo_open=True)
    max_penetration: float = spec(0.8, "-", "the hook sinking into a handrail card deeper than this fraction of "
                                  "hook_radius + half the card is 'unstable' (at 1 its centre reaches the card's "
                                  "middle and it tunnels through)", 0.0, 1.0, lo_open=True)
    trace_every: int = spec(2, "-", "record the trace every this many runner steps", 1, 100000)


@dataclass(frozen=True)
class EnvOptions:
    """How the design environment treats actions, rewards and rendering."""

    action_out_of_box: str = spec("error", "-", "an action outside [-1, 1]: error names the dimension; clip clips it "
                                  "(NaN is always an error)", choices=("error", "clip"))
    reward_shaping: float = spec(0.0, "-", "partial credit for a failed transfer that flew (the hook let go): "
                                 "reward = traversals + reward_shaping·max(0, 1 - miss_distance/pitch); a hook that "
                                 "never let go (stalled, no_detach) earns none; 0 = off", 0.0, 0.99)
    record_trace: bool = spec(False, "-", "keep each step's time series (angles, speeds, energy every sim.trace_every "
                              "steps) in env.unwrapped.last_run.trace; off: last_run holds the summary only")
    render_width: int = spec(720, "px", "width of rendered frames", 64, 4096)
    render_height: int = spec(300, "px", "height of rendered frames", 64, 4096)
    render_slowmo: float = spec(4.0, "-", "rendered animations play this many times slower than real time",
                                0.1, 100.0)


SECTIONS = {"design": Design, "scene": Scene, "sim": Sim, "env": EnvOptions}


# The design's cross-checks, one field against others, each (broken, refusal): ``broken(d)`` is True where the
# rule is broken, on numbers and elementwise on arrays; ``refusal(d, at)`` is one design's one-line message naming
# the field, its value and the range the other fields allow it, ``at`` the index after the key ("" or "[i]").
_DESIGN_RULES = (
    (lambda d: d.mu_k > d.mu_s,
     lambda d, at: f"design.mu_k{at} = {d.mu_k!r}: must not exceed design.mu_s = {d.mu_s!r} "
                   f"(kinetic friction is at most static), allowed [0, {d.mu_s}]"),
    (lambda d: d.alpha_max_deg <= d.alpha_min_deg,
     lambda d, at: f"design.alpha_max_deg{at} = {d.alpha_max_deg!r}: must exceed design.alpha_min_deg = "
                   f"{d.alpha_min_deg!r}, allowed ({d.alpha_min_deg}, 180]"),
    (lambda d: (d.stop_angle_deg - d.rest_angle_deg < 10.0) | (d.stop_angle_deg - d.rest_angle_deg > 270.0),
     lambda d, at: f"design.stop_angle_deg{at} = {d.stop_angle_deg!r}: the frame must be able to turn from "
                   f"design.rest_angle_deg = {d.rest_angle_deg!r} by 10 to 270 deg, allowed "
                   f"[{d.rest_angle_deg + 10}, {d.rest_angle_deg + 270}]"),
    (lambda d: np.abs(d.dT) > d.m1 * GRAVITY * np.maximum(d.La, d.Lb),
     lambda d, at: f"design.dT{at} = {d.dT!r}: the frame's own moment would put its centre of mass beyond its "
                   f"ends, allowed [{-d.m1 * GRAVITY * max(d.La, d.Lb):.3g}, {d.m1 * GRAVITY * max(d.La, d.Lb):.3g}] "
                   f"N·m (m1·g·max(La, Lb) with design.m1 = {d.m1!r}, design.La = {d.La!r}, design.Lb = {d.Lb!r})"),
    (lambda d: np.abs(d.dT) > frame_moment_limit(d),
     lambda d, at: f"design.dT{at} = {d.dT!r}: would put the frame card's centre of mass "
                   f"{1e3 * abs(d.dT) / (d.m1 * GRAVITY):.3g} mm from its axis, beyond the side cards' radius of "
                   f"gyration about it ({1e3 * math.sqrt(build.frame_card_inertia(d) / d.m1):.3g} mm with design.m1 = "
                   f"{d.m1!r}, design.La = {d.La!r}, design.Lb = {d.Lb!r}): no card has its centre that far out, "
                   f"allowed [{-frame_moment_limit(d):.3g}, {frame_moment_limit(d):.3g}] N·m"),
    (lambda d: d.m1 < build.lightest_plate(build.side_card_length(d)) * 2.0,
     lambda d, at: f"design.m1{at} = {d.m1!r}: lighter than two side cards of one layer as wide as their "
                   f"{build.HOLE_D * 1e3:g} mm skewer hole, {1e3 * build.side_card_length(d):.4g} mm long "
                   f"(design.La = {d.La!r}, design.Lb = {d.Lb!r}): no frame can be cut so light, allowed "
                   f"[{2.0 * build.lightest_plate(build.side_card_length(d)):.4g}, "
                   f"{Design.__dataclass_fields__['m1'].metadata['hi']:g}] kg"),
    (lambda d: d.arm_mass < build.lightest_plate(build.arm_net_length(d)),
     lambda d, at: f"design.arm_mass{at} = {d.arm_mass!r}: lighter than an arm of one layer as wide as its "
                   f"{build.HOLE_D * 1e3:g} mm axle hole over its {1e3 * build.arm_net_length(d):.4g} mm net "
                   f"(design.arm_length = {d.arm_length!r} with the hole's end and the hook's lip): no arm can be cut "
                   f"so light, allowed [{build.lightest_plate(build.arm_net_length(d)):.4g}, "
                   f"{Design.__dataclass_fields__['arm_mass'].metadata['hi']:g}] kg"),
    (lambda d: d.Ld < min_Ld(d.arm_length, d.alpha_max_deg, d.coin_radius),
     lambda d, at: f"design.Ld{at} = {d.Ld!r}: the torso below the axle must hold the coins (2 x "
                   f"design.coin_radius = {d.coin_radius!r}) with design.arm_length = {d.arm_length!r} at "
                   f"design.alpha_max_deg = {d.alpha_max_deg!r}, allowed "
                   f"[{float(min_Ld(d.arm_length, d.alpha_max_deg, d.coin_radius)):.4g}, "
                   f"{Design.__dataclass_fields__['Ld'].metadata['hi']}] m"),
    (lambda d: d.arm_mass + d.coin_mass + d.handrail_mass >= d.m2,
     lambda d, at: f"design.m2{at} = {d.m2!r}: must exceed its listed parts design.arm_mass = {d.arm_mass!r} + "
                   f"design.coin_mass = {d.coin_mass!r} + design.handrail_mass = {d.handrail_mass!r} = "
                   f"{d.arm_mass + d.coin_mass + d.handrail_mass:.6g} kg (the torso card is the rest), allowed "
                   f"({d.arm_mass + d.coin_mass + d.handrail_mass:.6g}, "
                   f"{Design.__dataclass_fields__['m2'].metadata['hi']:g}] kg"),
    (lambda d: d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass < lightest_torso_card(d),
     lambda d, at: f"design.m2{at} = {d.m2!r}: leaves {1e3 * (d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass):.4g} "
                   f"g of torso card after design.arm_mass = {d.arm_mass!r}, design.coin_mass = {d.coin_mass!r} and "
                   f"design.handrail_mass = {d.handrail_mass!r}, less than one layer as wide as its "
                   f"{build.HOLE_D * 1e3:g} mm axle hole over its {1e3 * torso_card_length(d):.4g} mm (design.Ld = "
                   f"{d.Ld!r}, design.arm_length = {d.arm_length!r}, design.alpha_max_deg = {d.alpha_max_deg!r}): no "
                   f"torso can be cut so light, allowed "
                   f"[{d.arm_mass + d.coin_mass + d.handrail_mass + lightest_torso_card(d):.6g}, "
                   f"{Design.__dataclass_fields__['m2'].metadata['hi']:g}] kg"),
)


def frame_moment_limit(d):
    """The largest frame moment (N·m) whose centre of mass lies within the side cards' radius of gyration about the
    axis: a body's centre is never farther from an axis than that (its own inertia, I1 - m1·x², is not negative)."""
    return GRAVITY * np.sqrt(d.m1 * build.frame_card_inertia(d))


def torso_card_length(d):
    """The torso card's length (m), its bottom Ld from the hook at alpha_max (:func:`aero_env.parts.bodies.torso_build`)."""
    return build.torso_net_length(torso_build(d.Ld, d.arm_length, d.alpha_max_deg, d.coin_radius)[0])


def lightest_torso_card(d):
    """The least card a torso can be (kg): :func:`aero_env.parts.build.lightest_plate` of its length."""
    return build.lightest_plate(torso_card_length(d))


class _Entry:
    """Design ``i`` of designs given as arrays: each field a float."""

    def __init__(self, designs, i: int):
        self._designs, self._i = designs, i

    def __getattr__(self, name: str) -> float:
        return float(getattr(self._designs, name)[self._i])


def check_design(d) -> None:
    """The design's cross-checks (one field against others). ``d``: a :class:`Design`, or any object with the
    design's fields as attributes holding 1-D arrays of one length, one design per entry (the reduced model's fast
    path). A broken rule raises one line naming the field, its value and the range the others allow it; of arrays,
    the first design that breaks it, its index after the key (``design.mu_k[3] = 0.5: must not exceed ...``)."""
    for broken, refusal in _DESIGN_RULES:
        bad = broken(d)
        if np.ndim(bad) == 0:
            if bad:
                raise ConfigError(refusal(d, ""))
        elif np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ConfigError(refusal(_Entry(d, i), f"[{i}]"))


def check_sim(s: Sim) -> None:
    step = s.dt * s.substeps  # the pymunk runner samples contact once per runner step (reduced finds events exactly)
    if s.model == "mbd" and s.contact_hold < 5 * step:
        raise ConfigError(f"sim.contact_hold = {s.contact_hold!r}: must span at least 5 runner steps of sim.dt = "
                          f"{s.dt!r} x sim.substeps = {s.substeps} to tell a detach from a bounce, allowed "
                          f"[{5 * step:.3g}, 1.0] s")


@functools.cache
def _real_fields() -> Mapping[str, dataclasses.Field]:
    """Every real-valued ``design.*`` and ``scene.*`` field by its dotted key (read once: ``fields()`` costs more
    than the rest of a ``with_values`` call)."""
    return MappingProxyType({f"{sec}.{f.name}": f for sec, cls in (("design", Design), ("scene", Scene))
                             for f in fields(cls) if f.type in (float, "float")})


def real_field(key: Any, where: str) -> dataclasses.Field:
    """The declaration of a real-valued ``design.*`` or ``scene.*`` field, or a ConfigError naming ``where``."""
    f = _real_fields().get(key) if isinstance(key, str) else None
    if f is None:
        choices = real_keys()
        hint = did_you_mean(key, choices) or f" (aero-env schema lists the {len(choices)} of them)"
        raise ConfigError(f"{where} = {key!r}: not a real-valued design or scene field{hint}")
    return f


def real_keys() -> list[str]:
    """Every real-valued ``design.*`` and ``scene.*`` key (what tunable, context and tolerance entries name)."""
    return list(_real_fields())
