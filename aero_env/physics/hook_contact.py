"""The frictional hook contact between the arm tip and a handrail notch.

pymunk gives each contact pair one friction coefficient, the product of the two shapes'
coefficients, which Chipmunk recomputes every step for every touching pair. Static and
kinetic friction are modelled by switching the hook's coefficient once per runner step,
before the step (:meth:`StaticKineticFriction.before_step`): if the tip's surface slides over
a handrail face it touches faster than ``slip_speed`` it gets mu_k, otherwise mu_s. Below the
threshold the solver's Coulomb cone holds the tip with mu_s, so the tip sticks until the
tangential load exceeds mu_s·N and slides on with mu_k until it slows below the threshold
again.

The slip is read where the surfaces meet: the velocity of the tip's contact point (its centre's
velocity plus the arm's spin times the radius) relative to the card's point under it, along the
face. A tip that turns in the corner while its centre stays put is sliding on both faces, and
counts as such. The contact points come from geometry (the tip's centre against the faces of the
frame it touches), not from a ``pre_solve`` callback, which would cross from C into Python for
every touching face and build a contact point set each time. The test itself is compiled
(:mod:`.slip_kernel`, reading the two bodies' C structs): it runs before nine steps in ten. A scene
that asks for one coefficient gets no switch at all: the coefficient is set on the shape and the C
solver does the rest.

The part also keeps track of which frame's handrail the tip touches (begin/separate
callbacks), which is what the event detector reads; it costs nothing between contacts.
"""

from __future__ import annotations

import numpy as np
import pymunk

from ..reasons import FRICTION_HELD
from . import body_state
from .body_state import handle, state
from .swing_frame import HANDRAIL, HOOK


def _unheard(_what: str, _value: float) -> None:
    pass


class _GetterView:
    """A body's state in an array laid out as its C struct's view (:func:`.body_state.memory`), filled from
    Chipmunk's getters at each :meth:`read`: for a pymunk whose cpBody the view does not fit."""

    def __init__(self, body: pymunk.Body):
        self.c, self.words = handle(body), np.zeros(body_state.WORDS)

    def read(self):
        w = self.words
        w[body_state.TX], w[body_state.TY], w[body_state.ANGLE], w[body_state.VX], w[body_state.VY], \
            w[body_state.SPIN] = state(self.c)
        return w


class StaticKineticFriction:
    """mu_s while the tip sticks, mu_k while it slides (switched by slip speed)."""

    def __init__(self, mu_s: float, mu_k: float, slip_speed: float, contact_band: float):
        self.mu_s, self.mu_k, self.slip_speed = mu_s, mu_k, slip_speed
        self.contact_band = contact_band  # a face this close to the tip's surface is touching it
        self.initial = mu_s
        self.sliding = False
        self.log = _unheard

    def log_to(self, log) -> None:
        """``log(what, value)`` hears each change of the hook's coefficient (rare: at most one per step)."""
        self.log = log

    def bind(self, contact: "HookContact") -> None:
        from .slip_kernel import tip_slides

        self.touching = contact.touching  # the contact's own dict, kept current by its callbacks
        self.hook = contact.hook_shape
        self.arm = self.hook.body
        # What never changes during a run, read from pymunk once.
        self.tip_local = tuple(self.hook.offset)
        self.arm_cog = tuple(self.arm.center_of_gravity)
        self.arm_data = np.array([*self.tip_local, *self.arm_cog])
        # per frame index, what the compiled test takes: the body's struct view and one array of the frame's centre of
        # gravity, the card's half-thickness, the reach within which a face line touches the tip's centre (the tip's
        # and card's radii and the band) and the faces (slip_kernel.tip_slides)
        # (the views read the live state; with another pymunk's layout, arrays the getters fill before each test)
        view = body_state.memory if body_state.MEMORY_LAYOUT_HOLDS else _GetterView
        tip_radius, band = self.hook.radius, self.contact_band
        self.frame_args = tuple(
            (view(f.body), np.array([(*f.body.center_of_gravity, f.rail_radius, tip_radius + f.rail_radius + band, 0.0),
                                     *f.faces]))
            for f in contact.frames)
        self.arm_view = view(self.arm)
        self._tip_slides = tip_slides

    def slides(self) -> bool:
        """Whether the tip's surface slides faster than ``slip_speed`` over a face it touches.

        The slip is read where the surfaces meet: the velocity of the tip's contact point relative to the card's
        point under it, along the face, computed from the arm's and the touched frame's states as pymunk would
        compute the two points' velocities (Munk2D's cpBody.c and cpTransform.h), bit for bit
        (tests/test_physics_layer.py checks it). The first face found sliding decides. The test is compiled
        (:mod:`.slip_kernel`): it runs before 9 in 10 of a run's steps."""
        frame, data = self.frame_args[next(iter(self.touching))]
        arm = self.arm_view
        if not body_state.MEMORY_LAYOUT_HOLDS:
            arm, frame = arm.read(), frame.read()
        return self._tip_slides(arm, frame, self.arm_data, data, self.slip_speed)

    def before_step(self) -> None:
        if not self.touching:
            return
        sliding = self.slides()
        if sliding != self.sliding:
            self.sliding = sliding
            mu = self.mu_k if sliding else self.mu_s
            self.hook.friction = mu
            self.log("friction", mu)


class SingleFriction:
    """One coefficient for sticking and sliding alike (no per-step work)."""

    before_step = None

    def __init__(self, mu: float):
        self.initial = mu

    def bind(self, contact: "HookContact") -> None:
        pass

    def log_to(self, log) -> None:
        pass  # never changes the space


def friction_law(name: str, mu_s: float, mu_k: float, slip_speed: float, contact_band: float):
    if name == "static_kinetic":
        return StaticKineticFriction(mu_s, mu_k, slip_speed, contact_band)
    if name == "static":
        return SingleFriction(mu_s)
    if name == "kinetic":
        return SingleFriction(mu_k)
    raise ValueError(f"scene.effects.friction = {name!r}: must be static_kinetic, static or kinetic")


class HookContact:
    """Registers the hook/handrail collision handler and tracks which frames the tip touches."""

    holding_note = FRICTION_HELD

    def __init__(self, hook_shape: pymunk.Shape, frames, law):
        self.law = law
        self.frames = frames
        # Handrail shape -> frame index. pymunk hands callbacks the same shape objects we created.
        self.frame_of_shape = {shape: f.index for f in frames for shape in f.shapes}
        self.touching: dict[int, int] = {}  # frame index -> number of touching faces
        self.touch_counts = np.zeros(len(frames), dtype=np.int64)  # the same, by frame, for compiled code
        self.hook_shape = hook_shape
        hook_shape.friction = law.initial  # pair coefficient = product of the shapes' (handrails carry 1.0)
        law.bind(self)
        self.before_step = law.before_step  # None when the law needs no per-step work

    def log_to(self, log) -> None:
        """``log(what, value)`` hears every change this part makes to the space between steps."""
        self.law.log_to(log)

    def add_to(self, space: pymunk.Space) -> None:
        space.on_collision(HOOK, HANDRAIL, begin=self._begin, separate=self._separate)

    def _begin(self, arbiter, _space, _data) -> None:
        i = self.frame_of_shape[arbiter.shapes[1]]
        self.touching[i] = self.touch_counts[i] = self.touching.get(i, 0) + 1

    def _separate(self, arbiter, _space, _data) -> None:
        # Also called when a retired frame's shapes leave the space, or when the space is freed.
        i = self.frame_of_shape.get(arbiter.shapes[1])
        if i is None:
            return
        n = self.touching.get(i, 0) - 1
        if n > 0:
            self.touching[i] = self.touch_counts[i] = n
        else:
            self.touching.pop(i, None)
            self.touch_counts[i] = 0

    def touches(self, frame_index: int) -> bool:
        return frame_index in self.touching

    def joint_drift(self) -> float:
        return 0.0  # a contact, not a joint: its error is the hook's penetration

    def penetration(self, frames_and_states, hook_centre: tuple[float, float]) -> float:
        """How deep the hook, its centre at ``hook_centre`` (world), sits inside the handrail card of
        any of the given (frame, read state) pairs (engine units)."""
        r = self.hook_shape.radius
        return max(f.penetration(st, hook_centre, r) for f, st in frames_and_states)


class PinnedHook:
    """The pinned-hook scene: the robot's hook is a pin joint at frame 0's handrail (no friction,
    no detach). With :class:`~aero_env.physics.robot.RigidRobot` this is the two-link model in
    pymunk (Appendix B of the article), the check that the world is built right."""

    holding_note = " (the hook is pinned: scene.effects.hook = pin)"
    before_step = None

    def __init__(self, robot, frame):
        self.frame_index = frame.index
        self.frame, self.robot = frame, robot
        self.joint = pymunk.PivotJoint(frame.body, robot.bodies[0], frame.hook_seat_local, robot.hook_local)
        self.touching = {frame.index: 1}  # frame index -> touching faces, as HookContact keeps it: always held

    def joint_drift(self) -> float:
        return (self.frame.hook_seat_world() - self.robot.hook_world()).length

    def penetration(self, _frames_and_states, _hook_centre) -> float:
        return 0.0  # no contact shape: the hook is a joint

    def add_to(self, space: pymunk.Space) -> None:
        space.add(self.joint)

    def log_to(self, _log) -> None:
        pass  # a joint: nothing changes between steps

    def touches(self, frame_index: int) -> bool:
        return frame_index == self.frame_index
