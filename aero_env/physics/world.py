"""The pymunk world of one scene, composed from parts the way dm_control composes entities.

Always built: the row of :class:`SwingFrame` s, the :class:`Robot`, its leaf spring (the
scene's spring law picks the part), the :class:`HookContact` (the scene's friction law picks
its callback) and the floor. Built only when the scene names it: :class:`AirDrag`. The
``hook: pin`` scene swaps robot, spring and contact for the two-link model's parts
(:class:`RigidRobot`, :class:`NoSpring`, :class:`PinnedHook`).

Frames are simulated only inside a live window around the robot's frame: the one it just
left (still turning to its stopper), its own, and ``effects.live_frames`` ahead. Frames
further back have reached their stop and are retired from the space; frames further ahead
wait at rest and are not in the space yet. The step loop itself has no per-effect branches: a
part that must act once per step (the static/kinetic friction switch) hands the world its
``before_step``, and the world runs the ones it was given.

A step calls Chipmunk's ``cpSpaceStep`` directly (:meth:`World.step` says when pymunk's wrapper is
still needed), and a check's read of the world is compiled (:mod:`.check_kernel`), with
:meth:`World.sample_python` as its reference: the runner's layer around pymunk costs about 0.4x of
pymunk's own stepping (``aero-env bench overhead``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import lib as _cp

from .. import units
from ..config import Config
from ..parts.build import stopper_offsets
from . import body_state, check_kernel
from .drag import AirDrag
from .engine_params import EngineParams, to_engine
from .hook_contact import HookContact, PinnedHook, friction_law
from .leaf_spring import SPRING_LAWS, NoSpring
from .robot import RigidRobot, Robot
from .swing_frame import FLOOR, SwingFrame


FLOOR_RADIUS = 1.0  # engine units (mm): the floor segment's half thickness
_cp_space_step = _cp.cpSpaceStep


class Sample(NamedTuple):
    """What one read of the world gives the runner's checks."""

    energy: float  # J
    max_speed: float  # engine units: the fastest live body's centre of gravity
    theta2: float  # rad: robot line from its centre of mass to the hook
    hook: tuple[float, float]  # engine units
    # How far the solver lets the machine's constraints give, SI, near zero in a healthy run: joint
    # drift (m: frame skewers, robot axle, pinned hook), limit overshoot (rad: frame stoppers, arm
    # stopper), hook penetration into a handrail card (m).
    health: tuple[float, float, float]
    frames: dict  # live frame index -> its read state (x, y, angle, vx, vy, omega), engine units


class World:
    def __init__(self, cfg: Config):
        self.cfg = cfg
        p: EngineParams = to_engine(cfg)
        self.p = p
        fx = cfg.scene.effects
        space = pymunk.Space()
        space.gravity = (0.0, -p.gravity)
        space.iterations = p.iterations
        space.collision_slop = p.collision_slop
        self.space = space
        self._cs = space._space  # its C handle (pymunk's own, as body_state's)
        self._through_wrapper = True  # the next step goes through pymunk's Space.step (see step)

        self.frames = [SwingFrame(i, p) for i in range(p.frames)]
        if fx.hook == "pin":  # the two-link model built in pymunk
            self.robot = RigidRobot(p)
            self.spring = NoSpring()
            self.contact = PinnedHook(self.robot, self.frames[0])
        else:
            self.robot = Robot(p)
            self.spring = SPRING_LAWS[fx.spring_law](self.robot, p.spring_k, p.alpha_min, p.spring_c)
            self.contact = HookContact(self.robot.tip, self.frames,
                                       friction_law(fx.friction, p.mu_s, p.mu_k, p.slip_speed,
                                                    p.collision_slop))
        self.robot.add_to(space)
        self.spring.add_to(space)
        self.drag = AirDrag(self.frames, self.robot, p) if fx.drag else None
        # Parts that act once per runner step, before it (only those the scene switched on).
        self._before_step = tuple(f for f in (self.contact.before_step,) if f is not None)
        self._dt, self._step_s = p.dt, p.step
        self._substep_range = range(p.substeps)
        self.live_ahead = fx.live_frames
        # The floor follows the row's incline, floor_drop below the frame axes.
        x0, x1 = -2.0 * p.pitch, (p.frames + 1) * p.pitch
        self.floor_a = pymunk.Vec2d(x0, x0 / p.pitch * p.rise - p.floor_drop)
        self.floor_b = pymunk.Vec2d(x1, x1 / p.pitch * p.rise - p.floor_drop)
        floor = pymunk.Segment(space.static_body, self.floor_a, self.floor_b, FLOOR_RADIUS)
        floor.collision_type = FLOOR
        space.add(floor)

        # Mass, moment and centre of gravity never change: read them from pymunk once.
        self._mass_props = {b: (b.mass, b.moment, b.center_of_gravity.x, b.center_of_gravity.y)
                            for b in (*(f.body for f in self.frames), *self.robot.bodies)}
        self._c = {b: body_state.handle(b) for b in self._mass_props}  # C handles, read on every check
        self.t = 0.0
        self.steps = 0
        # What the Python layer changed in the space between steps, in order: (runner steps taken, what,
        # value), "active" (the live window moved to a frame) or "friction" (the hook's coefficient).
        # Rare (a few dozen per run); replaying them around bare space.step calls reproduces the run
        # bit for bit, which is what `aero-env bench overhead` measures the Python layer against.
        self.inputs: list[tuple[int, str, float]] = []
        self.contact.log_to(self._note_input)
        self.active = -1
        self._live: list[SwingFrame] = []  # every frame starts parked, at rest
        self._parked_energy = sum(self._body_energy(f.body) for f in self.frames)
        self._check = None  # the compiled check (check_kernel.read_world), where it covers this world
        if body_state.MEMORY_LAYOUT_HOLDS and isinstance(self.robot, Robot) and isinstance(self.contact, HookContact):
            self._compile_check()
        self._move_window(0)
        self.robot.place_hanging(self.frames[0].hook_seat_world(), p.theta2_start, p.alpha_max)
        self.contact.add_to(space)  # after placing: a pin joint anchors where the bodies are

    # -- live window --
    def _body_energy(self, b: pymunk.Body) -> float:
        return self._energy_of(b, body_state.read(b))

    def _note_input(self, what: str, value: float) -> None:
        self.inputs.append((self.steps, what, value))

    def set_active(self, i: int) -> None:
        """Make frame i the robot's frame: keep i-1 (still turning), i and live_ahead frames ahead."""
        self._note_input("active", i)
        self._move_window(i)

    def _compile_check(self) -> None:
        """The compiled check's arguments: what never changes in a run, as arrays (check_kernel.read_world)."""
        ck, p, bodies = check_kernel, self.p, (*(f.body for f in self.frames), *self.robot.bodies)
        self._consts = consts = np.zeros(ck.N_CONSTS)
        consts[[ck.GRAVITY, ck.ARM_LENGTH, ck.TORSO_COM, ck.M_TORSO, ck.M_ARM, ck.ALPHA_MAX, ck.ALPHA_MIN,
                ck.HOOK_RADIUS, ck.ARM_COM]] = (p.gravity, p.arm_length, p.torso_com, p.m_torso, p.m_arm, p.alpha_max,
                                                p.alpha_min, self.contact.hook_shape.radius, p.arm_com)
        frame_table = np.array([(f.axis.x, f.axis.y, f.stop_angle, f.rest_angle, f.rail_radius) for f in self.frames])
        # the arguments before and after the live frames' indices, which each window move sets
        self._check_head = (np.array([body_state.address(b) for b in bodies], dtype=np.int64),
                            np.array([self._mass_props[b] for b in bodies]))
        self._check_tail = (self.contact.touch_counts, frame_table, np.array([f.faces for f in self.frames]), consts)
        self._check_out = np.zeros(ck.FRAME_STATES + 6 * len(self.frames))
        self._check = ck.read_world

    def _move_window(self, i: int) -> None:
        self.active = i
        self._through_wrapper = True  # frames join or leave the space: pymunk's Space.step checks and tidies
        lo, hi = max(0, i - 1), min(len(self.frames) - 1, i + self.live_ahead)
        # Frames out of the space do not move: their energy is booked once as they park or leave the
        # park, so neither a check nor a catch costs more on a longer row.
        window = self.frames[lo:hi + 1]
        for f in self._live:
            if not lo <= f.index <= hi:
                f.retire(self.space)
                self._parked_energy += self._body_energy(f.body)
        for f in window:
            if not f.live:
                self._parked_energy -= self._body_energy(f.body)
                f.attach(self.space)
        self._live = window
        self._live_indices = tuple(f.index for f in window)
        if self._check is not None:
            self._consts[check_kernel.PARKED_ENERGY] = self._parked_energy
            self._check_args = (*self._check_head, np.array(self._live_indices, dtype=np.int64),
                                *self._check_tail)

    def live_frames(self):
        return list(self._live)

    # -- stepping --
    def step(self) -> None:
        """One runner step: the per-step parts, then ``sim.substeps`` pymunk steps of ``sim.dt``.

        The pymunk steps are Chipmunk's ``cpSpaceStep`` called directly, not :meth:`pymunk.Space.step`: the C
        step is the same, and the wrapper's Python around it (0.6 us a step, a sixth of the C step's cost) only
        serves what this world never does during a step: bodies, shapes or constraints added or removed from a
        callback, post-step callbacks, and the mass check of bodies added since the last step (the world adds
        and removes frames between steps, and then takes one step through the wrapper).
        ``tests/test_physics_layer.py`` checks both ways give the same run, bit for bit."""
        for part in self._before_step:
            part()
        if self._through_wrapper:
            self._through_wrapper = False
            space_step, dt = self.space.step, self._dt
            for _ in self._substep_range:
                space_step(dt)
        else:
            c_step, cs, dt = _cp_space_step, self._cs, self._dt
            for _ in self._substep_range:
                c_step(cs, dt)
        self.steps += 1
        self.t = self.steps * self._step_s  # no accumulated round-off in the clock

    # -- measurements (engine units inside, SI where it says so) --
    def floor_y(self, x: float) -> float:
        a, b = self.floor_a, self.floor_b
        return a.y + (x - a.x) * (b.y - a.y) / (b.x - a.x)

    def on_floor(self, x: float, y: float, radius: float) -> bool:
        """Whether a disc of ``radius`` centred at (``x``, ``y``) (engine units) touches the floor segment."""
        return y - radius <= self.floor_y(x) + FLOOR_RADIUS

    def sample(self) -> "Sample":
        """Read every live body once (position, angle, velocities) and derive what the runner checks:
        energy, the fastest body, theta2, the hook's position and the health monitors.

        Frames outside the space are at rest (ahead) or at their stop (behind): their potential
        energy is constant and still counted, so the total is comparable across window moves.

        Compiled (:mod:`.check_kernel`) where the kernel covers the world (the jointed robot on a hook
        contact, pymunk's struct layout known), else :meth:`sample_python`; the two agree bit for bit.
        """
        if self._check is None:
            return self.sample_python()
        out, ck = self._check_out, check_kernel
        self._check(*self._check_args, out)
        v = out.tolist()
        e = v[ck.ENERGY] + self.spring.energy_for(v[ck.ALPHA])
        k = ck.FRAME_STATES
        frames = {}
        for i in self._live_indices:
            frames[i] = tuple(v[k:k + 6])
            k += 6
        return Sample(units.energy_to_si(e), math.sqrt(v[ck.V2MAX]), v[ck.THETA2], (v[ck.HOOK_X], v[ck.HOOK_Y]),
                      (units.length_to_si(v[ck.DRIFT]), v[ck.OVERSHOOT], units.length_to_si(v[ck.PENETRATION])), frames)

    def sample_python(self) -> "Sample":
        """:meth:`sample` in Python: the reference the compiled read is checked against, and the path for a world
        it does not cover."""
        drift, over = 0.0, 0.0
        frame_states = {}
        read, c = body_state.state, self._c
        for f in self._live:
            st = frame_states[f.index] = read(c[f.body])
            d, o = f.health(st)
            drift, over = max(drift, d), max(over, o)
        robot = self.robot
        states = [read(c[b]) for b in robot.bodies]
        # every live body's energy and speed in one loop: _energy_of written out (same operations, same order),
        # since a call per body is a tenth of a check's cost
        g, mass_props, sin, cos = self.p.gravity, self._mass_props, math.sin, math.cos
        e, v2max = self._parked_energy, 0.0
        for b, (x, y, a, vx, vy, w) in zip((*(f.body for f in self._live), *robot.bodies),
                                           (*frame_states.values(), *states)):
            mass, moment, cgx, cgy = mass_props[b]
            v2 = vx * vx + vy * vy
            e += 0.5 * (mass * v2 + moment * w * w) + mass * g * (y + cgx * sin(a) + cgy * cos(a))
            v2max = max(v2max, v2)
        m = robot.measure(states)
        e += self.spring.energy_for(m.alpha)
        drift = max(drift, m.drift, self.contact.joint_drift())
        over = max(over, m.overshoot)
        # Any overlap of hook and card is a contact, so only the frames the hook touches can hold it.
        touching = self.contact.touching
        pen = self.contact.penetration([(self.frames[i], frame_states[i]) for i in touching if i in frame_states],
                                       m.hook) if touching else 0.0
        return Sample(units.energy_to_si(e), math.sqrt(v2max), math.atan2(m.hook[1] - m.com[1], m.hook[0] - m.com[0]),
                      m.hook, (units.length_to_si(drift), over, units.length_to_si(pen)), frame_states)

    def energy(self) -> float:
        """Total mechanical energy in joules: kinetic + gravitational + spring, over every frame and the robot."""
        return self.sample().energy

    def _energy_of(self, b: pymunk.Body, st: tuple) -> float:
        m, moment, cgx, cgy = self._mass_props[b]
        x, y, a, vx, vy, w = st
        y_cog = y + cgx * math.sin(a) + cgy * math.cos(a)
        return 0.5 * (m * (vx * vx + vy * vy) + moment * w * w) + m * self.p.gravity * y_cog

    def spring_capacity(self) -> float:
        """Energy (J) the spring stores fully bent, at alpha_max."""
        return units.energy_to_si(self.spring.capacity(self.p.alpha_max))

    def geometry(self) -> dict:
        """The machine's fixed geometry in SI, for drawing."""
        s = 1.0 / units.LENGTH
        p = self.p
        return dict(
            axes=[(f.axis.x * s, f.axis.y * s) for f in self.frames],
            faces_local=[[((a.x * s, a.y * s), (b.x * s, b.y * s)) for a, b in self.frames[0].faces_local]],
            La=p.La * s, Lb=p.Lb * s, h=p.h * s, rest_angle=p.rest_angle, stop_angle=p.stop_angle,
            arm_length=p.arm_length * s, torso_length=p.torso_length * s, coin_offset=p.coin_offset * s,
            floor=((self.floor_a.x * s, self.floor_a.y * s), (self.floor_b.x * s, self.floor_b.y * s)),
            # the two stopper skewers, offsets from each axis: where the kit's crossbeam puts them (aero_env/parts)
            stoppers=stopper_offsets(self.cfg.design),
        )

    def pose(self) -> tuple:
        """Current pose in SI: frame angles, torso position and angle, arm angle."""
        s = 1.0 / units.LENGTH
        axle, torso_angle, arm_angle = self.robot.pose()
        return [f.body.angle for f in self.frames], (axle.x * s, axle.y * s), torso_angle, arm_angle
