"""Physical invariants of the pymunk world, each measured independently of the runner's own monitors.

The runner (:mod:`aero_env.physics.monitors`) aborts a run as ``unstable`` from :meth:`World.sample`:
energy booked by ``World._energy_of`` and the spring part's ``energy_for``, joint drift from
``SwingFrame.health`` / ``Robot.measure``, penetration from ``SwingFrame.penetration`` (the hook's
centre against the faces' centre lines, in the frame's own arithmetic). None of that is used here.
Instead, an :class:`Observer` reads the pymunk bodies and shapes directly after every runner step
(not only on the runner's 5 ms check cadence) and recomputes:

1. **Energy** from each body's pymunk ``mass``, ``moment``, ``velocity``, ``angular_velocity`` and its
   centre of gravity placed by pymunk's own ``local_to_world``, plus the leaf spring's energy with
   k taken from the *config* (not from the spring part or the pymunk constraint), its law written
   out here (linear 0.5·k·da², stiffening k·|da|³/6) and da from the two bodies' angles. In SI, with
   g = 9.81 m/s².
2. **Penetration** with pymunk's own ``Shape.point_query`` on the handrail shapes in the space (signed
   distance from the hook's centre to each rounded card segment), against the hook circle's radius; and,
   between every two consecutive steps, whether the hook's centre crossed a card's middle line (the
   segment's ``a``-``b`` in its body's coordinates at each step): a hook that went through a card in one
   step sank at least its radius + half the card into it, though after the step it reads shallow on the far
   side.
3. **Joint drift** from body positions: each pivot's anchor mapped to the world on both of its bodies
   with ``local_to_world``. The anchors are the model's facts (frame i turns about
   (i·pitch, i·rise) at its body origin; torso and arm share their origin at the axle; the pinned hook
   sits at the frame's (-Lb, 0) and the rigid robot's origin), so a joint missing from the space
   still shows; every ``PivotJoint`` the space does hold is checked with its own anchors as well.
4. **Limit overshoot** from body angles against the config's stoppers: each frame's angle against
   [rest_angle_deg, stop_angle_deg], the arm's interior angle against [alpha_min_deg, alpha_max_deg].
5. **Speed**: the fastest dynamic body's centre of gravity in the space, pymunk's ``velocity``.

The observer wraps :meth:`World.step` (a subclass patched into :mod:`aero_env.physics.run` for the
length of one run), so the runner's events (catches moving the live window) happen as in any run; the
environment's runs go through the same runner, so :func:`observing` watches ``env.step`` too. Bodies
outside the space (frames parked behind the robot or waiting ahead) are not stepped by pymunk: their
energy and drift are recounted whenever the set of bodies in the space changes, and carried as they are
in between. Engine units are mm, g, s (``aero_env.units``); the conversions below are written out here.

:func:`check_run` is what every run must satisfy, judged on these measurements: a run the runner
calls healthy stayed within the config's limits at every step; a run it calls ``unstable`` did
break one of them (or went non-finite) before it was stopped.
"""

from __future__ import annotations

import contextlib
import math
from unittest import mock

import pymunk

import aero_env.physics.run as run_module
from aero_env.physics.world import World

G = 9.81  # m/s^2, the brief's g
MM = 1e-3  # m per engine length unit
GRAM = 1e-3  # kg per engine mass unit
AUDIT_EVERY = 25  # rows between reads of World.energy for the audit (test_invariants only)

OUTCOMES = {"completed", "no_detach", "stalled", "fell_short", "missed_catch", "unstable"}


# ------------------------------------------------------------------------- independent measurements
def spring_energy(law: str, k_si: float, da: float) -> float:
    """The leaf spring's stored energy (J) at deflection da (rad) from alpha_min, for the config's law:
    linear (torque k·da) or stiffening (torque k/2·da², aero_env.physics.leaf_spring's docstring)."""
    if law == "linear":
        return 0.5 * k_si * da * da
    if law == "stiffening":
        return k_si * abs(da) ** 3 / 6.0
    raise AssertionError(f"no energy written out here for spring law {law!r}")


def body_energy(b: pymunk.Body) -> float:
    """Kinetic + gravitational energy (J) of one pymunk body: its centre of gravity's ``velocity`` and
    its height from ``local_to_world``."""
    m, inertia = b.mass * GRAM, b.moment * GRAM * MM * MM
    v = b.velocity * MM
    y = b.local_to_world(b.center_of_gravity).y * MM
    return 0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * inertia * b.angular_velocity ** 2 + m * G * y


def alpha_of(arm: pymunk.Body, torso: pymunk.Body) -> float:
    """The interior angle at the axle: arm +x against torso -y."""
    return arm.angle - torso.angle + math.pi / 2


def mechanical_energy(bodies, arm, torso, k_si: float, alpha_min: float, law: str = "linear") -> float:
    """Kinetic + gravitational energy of ``bodies`` and the leaf spring's (J), from pymunk's body state.
    ``arm`` None: no spring."""
    e = sum(body_energy(b) for b in bodies)
    if arm is not None:
        e += spring_energy(law, k_si, alpha_of(arm, torso) - alpha_min)
    return e


def kinetic_energy(bodies) -> float:
    """The kinetic part alone (J): shows that a conserving swing did trade energy."""
    return sum(0.5 * b.mass * GRAM * (b.velocity * MM).length_squared
               + 0.5 * b.moment * GRAM * MM * MM * b.angular_velocity ** 2 for b in bodies)


def hook_depth(hook: pymunk.Circle, rails) -> float:
    """How deep the hook's disc overlaps any of the ``rails`` (engine units; 0 when apart): its radius
    minus the signed distance from its centre to the rail's surface by pymunk's ``point_query``
    (negative inside), which for a disc against a rounded segment is the overlap along the normal.

    Not the deepest of points sampled on the hook's boundary: those cannot sink deeper than the card's
    half-thickness (0.5 mm), since a hook straddling the card has its whole boundary outside it. The
    prototype's catches reach that: sampled boundary points read 0.4999 mm where the overlap is 0.56 mm."""
    centre = hook.body.local_to_world(hook.offset)
    depth = 0.0
    for rail in rails:
        depth = max(depth, hook.radius - rail.point_query(centre).distance)
    return depth


def swing_scale(d) -> float:
    """The energy scale of a swing, S = (m2 + m3)·g·(La + Lb) (J): the robot and the counterbalance
    falling the frame's length (0.0146 J for the prototype)."""
    return (d.m2 + d.m3) * G * (d.La + d.Lb)


def energy_scale(cfg) -> float:
    """What sim.energy_tolerance is a fraction of: S plus what the fully bent spring stores (none
    when the hook is a pin: the rigid robot has no spring)."""
    d = cfg.design
    spring = 0.0
    if cfg.scene.effects.hook != "pin":
        spring = spring_energy(cfg.scene.effects.spring_law, d.spring_k, math.radians(d.alpha_max_deg - d.alpha_min_deg))
    return swing_scale(d) + spring


def _gap(a: pymunk.Vec2d, b: pymunk.Vec2d) -> float:
    return (a - b).length


def _crosses(p0, p1, a, b) -> bool:
    """Whether the straight path p0 -> p1 crosses the segment a-b (strictly from one side to the other)."""
    def side(p, q, r):
        return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)

    s0, s1 = side(a, b, p0), side(a, b, p1)
    return s0 * s1 < 0.0 and side(p0, p1, a) * side(p0, p1, b) <= 0.0


class Observer:
    """Reads a world's pymunk bodies and shapes after each step.

    Keeps one row per ``every``-th step (SI) when ``keep_rows``, and in any case the worst of each
    measurement over every measured step (``worst``)."""

    def __init__(self, world: World, every: int = 1, keep_rows: bool = True):
        cfg = world.cfg
        d, s = cfg.design, cfg.scene
        self.world, self.every, self.keep_rows = world, every, keep_rows
        self.frames = [f.body for f in world.frames]
        self.robot_bodies = list(world.robot.bodies)
        self.pinned = s.effects.hook == "pin"
        if self.pinned:
            self.torso = self.arm = None
        else:
            self.torso, self.arm = self.robot_bodies
        self.k, self.law = d.spring_k, s.effects.spring_law
        self.alpha_min, self.alpha_max = math.radians(d.alpha_min_deg), math.radians(d.alpha_max_deg)
        self.rest, self.stop = math.radians(d.rest_angle_deg), math.radians(d.stop_angle_deg)
        self.axes = {b: pymunk.Vec2d(i * s.pitch / MM, i * s.rise / MM) for i, b in enumerate(self.frames)}
        self.seat = pymunk.Vec2d(-d.Lb / MM, 0.0)
        hooks = [sh for b in self.robot_bodies for sh in b.shapes if isinstance(sh, pymunk.Circle)]
        assert len(hooks) == (0 if self.pinned else 1), "the contact robot carries exactly one hook circle"
        self.hook = hooks[0] if hooks else None
        self._counted = set(self.frames) | set(self.robot_bodies)
        self._live = None  # the frames in the space when the parked part was last recounted
        self._parked_energy = self._parked_skewer = 0.0
        self.rows: list[dict] = []
        self._hook_on = {}  # handrail segment -> the hook's centre in its body's coordinates after the last step
        self._swept = 0.0  # deepest a crossing of a card's middle line since the last measured row (engine units)
        self.steps = 0
        self.worst = {"rise": 0.0, "gain": 0.0, "drift": 0.0, "depth": 0.0, "overshoot": 0.0, "speed": 0.0,
                      "finite": True}
        self.e0 = self.e_min = None
        self()  # the state before the first step

    # -- bodies in and out of the space --
    def _space_frames(self) -> tuple[list, list]:
        """(dynamic bodies in the space, the frames among them); recounts the parked frames if the window moved."""
        dynamic = [b for b in self.world.space.bodies if b.body_type == pymunk.Body.DYNAMIC]
        stray = [b for b in dynamic if b not in self._counted]
        assert not stray, f"{len(stray)} dynamic bodies in the space that the energy would not count"
        live = [b for b in dynamic if b in self.axes]
        key = frozenset(live)
        if key != self._live:  # the window moved: recount the frames pymunk is not stepping
            parked = [b for b in self.frames if b not in key]
            self._parked_energy = sum(body_energy(b) for b in parked)
            self._parked_skewer = max((_gap(self.axes[b], b.local_to_world((0.0, 0.0))) for b in parked), default=0.0)
            self._live = key
        return dynamic, live

    # -- measurements --
    def energy(self, live=None) -> float:
        """J: every frame (those out of the space as last recounted), the robot and the spring."""
        live = self._space_frames()[1] if live is None else live
        return self._parked_energy + mechanical_energy(live + self.robot_bodies, self.arm, self.torso, self.k,
                                                       self.alpha_min, self.law)

    def drift(self, live=None) -> tuple[float, float, float]:
        """(worst skewer, robot axle or pinned hook, any PivotJoint in the space), m."""
        live = self._space_frames()[1] if live is None else live
        skewer = max([self._parked_skewer] + [_gap(self.axes[b], b.local_to_world((0.0, 0.0))) for b in live])
        if self.pinned:
            robot = _gap(self.frames[0].local_to_world(self.seat), self.robot_bodies[0].local_to_world((0.0, 0.0)))
        else:
            robot = _gap(self.torso.local_to_world((0.0, 0.0)), self.arm.local_to_world((0.0, 0.0)))
        joints = [c for c in self.world.space.constraints if isinstance(c, pymunk.PivotJoint)]
        any_joint = max((_gap(c.a.local_to_world(c.anchor_a), c.b.local_to_world(c.anchor_b)) for c in joints),
                        default=0.0)
        return skewer * MM, robot * MM, any_joint * MM

    def _rails(self) -> list:
        return [sh for sh in self.world.space.shapes
                if isinstance(sh, pymunk.Segment) and sh.body.body_type == pymunk.Body.DYNAMIC]

    def sweep(self) -> None:
        """Every step: did the hook's centre cross a card's middle line since the step before? (straight between
        the two steps, in the card's own coordinates; a segment new to the space starts afresh)"""
        if self.hook is None:
            return
        centre = self.hook.body.local_to_world(self.hook.offset)
        seen = {}
        for rail in self._rails():
            now = rail.body.world_to_local(centre)
            seen[rail] = now
            before = self._hook_on.get(rail)
            if before is not None and _crosses(before, now, rail.a, rail.b):
                self._swept = max(self._swept, self.hook.radius + rail.radius)
        self._hook_on = seen

    def depth(self) -> float:
        if self.hook is None:
            return 0.0
        swept, self._swept = self._swept, 0.0
        return max(hook_depth(self.hook, self._rails()), swept) * MM

    def overshoot(self, live=None) -> float:
        """rad: the farthest any frame in the space has turned outside [rest, stop], or the arm outside
        [alpha_min, alpha_max] (frames outside the space sit at rest or at their stop)."""
        live = self._space_frames()[1] if live is None else live
        worst = max((max(0.0, b.angle - self.stop, self.rest - b.angle) for b in live), default=0.0)
        if self.arm is not None:
            a = alpha_of(self.arm, self.torso)
            worst = max(worst, a - self.alpha_max, self.alpha_min - a)
        return worst

    def measure(self) -> dict:
        w = self.world
        dynamic, live = self._space_frames()
        skewer, robot, any_joint = self.drift(live)
        row = {"t": w.t, "energy": self.energy(live), "skewer": skewer, "robot_joint": robot,
               "any_joint": any_joint, "depth": self.depth(), "overshoot": self.overshoot(live),
               "speed": max(b.velocity.length for b in dynamic) * MM}  # m/s: the fastest dynamic body
        if self.keep_rows:
            row.update(active=w.active, theta1=w.frames[w.active].body.angle,
                       kinetic=kinetic_energy(self.frames + self.robot_bodies),
                       alpha=None if self.arm is None else alpha_of(self.arm, self.torso))
        return row

    def __call__(self) -> None:
        self.steps += 1
        self.sweep()
        if (self.steps - 1) % self.every:
            return
        row = self.measure()
        values = [v for v in row.values() if isinstance(v, float)]
        if not all(math.isfinite(v) for v in values):
            self.worst["finite"] = False
            return
        e, worst = row["energy"], self.worst
        if self.e0 is None:
            self.e0 = self.e_min = e
        self.e_min = min(self.e_min, e)
        worst["rise"] = max(worst["rise"], e - self.e_min)
        worst["gain"] = max(worst["gain"], e - self.e0)
        worst["drift"] = max(worst["drift"], row["skewer"], row["robot_joint"], row["any_joint"])
        for key in ("depth", "overshoot", "speed"):
            worst[key] = max(worst[key], row[key])
        if self.keep_rows:
            if len(self.rows) % AUDIT_EVERY == 0:
                row["world_energy"] = self.world.energy()  # for the audit test only; no check here uses it
            self.rows.append(row)

    def column(self, key: str, t_from: float = -math.inf, t_to: float = math.inf) -> list[float]:
        return [r[key] for r in self.rows if t_from <= r["t"] < t_to]


@contextlib.contextmanager
def observing(every: int = 1, keep_rows: bool = True):
    """Every world the runner builds inside the block gets an :class:`Observer`; yields the list of
    them, one per run, in order (``env.step`` runs through the same runner)."""
    seen: list[Observer] = []

    class ObservedWorld(World):
        def __init__(self, cfg):
            super().__init__(cfg)
            self._observer = Observer(self, every, keep_rows)
            seen.append(self._observer)

        def step(self):
            super().step()
            self._observer()

    with mock.patch.object(run_module, "World", ObservedWorld):
        yield seen


def observed_run(cfg, every: int = 1, keep_rows: bool = True):
    """Run ``cfg`` through the runner with an :class:`Observer` after every step: (result, observer)."""
    with observing(every, keep_rows) as seen:
        result = run_module.simulate(cfg)
    assert len(seen) == 1, "simulate() no longer builds its world as aero_env.physics.run.World: observe it another way"
    return result, seen[0]


def stepped(cfg, until, t_max: float = 2.0):
    """Step a bare :class:`World` (no runner) with an :class:`Observer` until ``until(world)``, or
    ``t_max`` simulated seconds (a broken world may never get there; the tests check where it got)."""
    world = World(cfg)
    obs = Observer(world)
    while not until(world) and world.t < t_max:
        world.step()
        obs()
    obs.reached = until(world)
    return world, obs


# ------------------------------------------------------------------------- the check every run must pass
def finite_everywhere(x, path="result"):
    if isinstance(x, dict):
        for k, v in x.items():
            finite_everywhere(v, f"{path}.{k}")
    elif isinstance(x, (list, tuple)):
        for i, v in enumerate(x):
            finite_everywhere(v, f"{path}[{i}]")
    elif isinstance(x, float):
        assert math.isfinite(x), f"{path} = {x}"


def limits(cfg) -> dict:
    """The config's limits on what an :class:`Observer` measures, SI (the runner's abort rules, as
    documented in the config's schema; computed here from the config's fields)."""
    d, s = cfg.design, cfg.sim
    return {"rise": s.energy_tolerance * energy_scale(cfg), "drift": s.max_joint_drift,
            "overshoot": math.radians(s.max_limit_overshoot_deg),
            "depth": s.max_penetration * (d.hook_radius + 0.5 * d.handrail_thickness), "speed": s.max_speed}


def breaches(obs: Observer, cfg) -> dict:
    """Each limit the observed run went past: {name: (worst measured, limit)}; 'finite' when a
    measurement was NaN or infinite."""
    lim = limits(cfg)
    out = {k: (obs.worst[k], v) for k, v in lim.items() if obs.worst[k] > v}
    if not obs.worst["finite"]:
        out["finite"] = (math.nan, math.nan)
    return out


def check_run(result, obs: Observer, cfg) -> None:
    """What must hold for every run, judged on the observer's own measurements: a known outcome within its
    time limit and no NaN or inf in the result; a run not called ``unstable`` stayed within every limit of
    the config at every step; a run called ``unstable`` says why and did break a limit before it stopped."""
    finite_everywhere(result.to_json_dict())
    assert result.outcome in OUTCOMES, result.reason
    assert result.sim_time <= cfg.sim.t_max
    broken = breaches(obs, cfg)
    if result.outcome == "unstable":
        assert "sim." in result.reason, result.reason  # it names the setting to change
        assert broken, f"called unstable ({result.reason}) but every independent measurement was within its limit"
    else:
        assert not broken, f"{result.outcome} ({result.reason}), yet the observer measured {broken}"
