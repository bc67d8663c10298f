"""The paper leaf spring between torso and arm: one part per spring law.

The paper fits the measured spring as K_T = 0.877·da (N·mm/rad, da = alpha - alpha_min) and
its MBD uses a linear torsional spring, which is the default. ``stiffening`` reads the same
fit as a torque that grows with the square of the deflection, torque = k/2·da².

pymunk's DampedRotarySpring measures its angle as ``a.angle - b.angle`` (the opposite of
RotaryLimitJoint's ``b.angle - a.angle``). With a = torso and b = arm that angle is
``pi/2 - alpha``, so the spring's rest angle is ``pi/2 - alpha_min`` and its torque argument
is ``-da``. tests/test_physics.py checks the sign: a free robot's arm snaps to alpha_min.

``damping`` (``design.spring_damping`` as a coefficient) is the card's internal loss: pymunk's own
damping term of the same constraint, which opposes the relative rate of torso and arm inside the C
solver, so it costs nothing when 0 and no Python per step when on; with ``stiffening`` pymunk still
applies it beside the custom torque.
"""

from __future__ import annotations

import math

import pymunk

from .robot import Robot


class LinearLeafSpring:
    name = "linear"

    def __init__(self, robot: Robot, k: float, alpha_min: float, damping: float = 0.0):
        self.robot, self.k, self.alpha_min = robot, k, alpha_min
        # Runs entirely inside pymunk's C solver: no Python per step.
        self.constraint = pymunk.DampedRotarySpring(robot.torso, robot.arm, math.pi / 2 - alpha_min, k, damping)

    def add_to(self, space: pymunk.Space) -> None:
        space.add(self.constraint)

    def torque(self, da: float) -> float:
        return self.k * da

    def energy_at(self, da: float) -> float:
        return 0.5 * self.k * da * da

    def energy(self) -> float:
        return self.energy_for(self.robot.alpha)

    def energy_for(self, alpha: float) -> float:
        """The energy stored at arm angle ``alpha``."""
        return self.energy_at(alpha - self.alpha_min)

    def capacity(self, alpha_max: float) -> float:
        """The energy stored fully bent."""
        return self.energy_at(alpha_max - self.alpha_min)


class StiffeningLeafSpring(LinearLeafSpring):
    name = "stiffening"

    def __init__(self, robot: Robot, k: float, alpha_min: float, damping: float = 0.0):
        super().__init__(robot, k, alpha_min, damping)
        rest = self.constraint.rest_angle
        half_k = 0.5 * k

        def torque_func(_spring, relative_angle, rest=rest, half_k=half_k):
            da = rest - relative_angle  # = alpha - alpha_min
            return -half_k * da * abs(da)

        self.constraint.torque_func = torque_func

    def torque(self, da: float) -> float:
        return 0.5 * self.k * da * abs(da)

    def energy_at(self, da: float) -> float:
        return self.k * abs(da) ** 3 / 6.0


SPRING_LAWS = {"linear": LinearLeafSpring, "stiffening": StiffeningLeafSpring}


class NoSpring:
    """The pinned-hook scene's robot is one rigid body: no arm, no spring, no stored energy."""

    name = "none"

    def add_to(self, space: pymunk.Space) -> None:
        pass

    def energy(self) -> float:
        return 0.0

    def energy_for(self, _alpha: float) -> float:
        return 0.0

    def capacity(self, _alpha_max: float) -> float:
        return 0.0
