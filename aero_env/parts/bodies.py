"""The rigid bodies the physics swings, computed once from the parts (:mod:`aero_env.parts.build`).

One home for each body's mass, centre and inertia: the pymunk world (``physics/engine_params.py`` converts the
values to its units, ``physics/swing_frame.py`` and ``physics/robot.py`` build the bodies), the reduced model
(``models/reduced/params.py``, arrays of designs) and the two-link model's ``parts`` convention all read them
here; :mod:`aero_env.inertia` keeps only the article's own formulas (A13-A15), for the analytical models'
``paper`` and ``consistent`` conventions.

- **The swing frame** (:func:`frame_card`, :func:`frame_body`): its card (the two side cards, m1) with its
  inertia about the axis as the kit builds them and its centre moved along the frame line by the frame's own
  moment dT (which moves the centre, not the inertia about the axis); the counterbalance m3, a point at (La, h);
  the handrail's card, a point at the seat (-Lb, 0). One rigid body about the axis.
- **The robot** (:class:`RobotParts`): the torso card with its coins, and the arm, each its own body on the axle.

Every function takes floats or numpy arrays (the reduced model builds a batch of designs with the same
arithmetic); the composition rules take any one consistent set of units, so the world composes in its own units
exactly as before.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..units import GRAVITY
from . import build
from .build import arm_plate, torso_plate

# a design: an aero_env.config.Design, or any object with its fields. The config's checks use this module
# (min_Ld, torso_build), so it does not import the config, not even for a type.
Design = Any


# ---- the swing frame ----
def frame_card(d: Design) -> tuple:
    """(mass, centre along the frame line, inertia about the axis) of the frame's card, SI: the two side cards
    (:func:`aero_env.parts.build.frame_card_inertia`); the frame's own moment dT (the article's Eq. (1) adds
    +dT·cos(theta1)) puts the centre at x = -dT/(m1·g), and leaves the inertia about the axis as it is."""
    return d.m1, -(d.dT / (d.m1 * GRAVITY)), build.frame_card_inertia(d)


def frame_body(m_card, card_x, I_card_axis, m_cb, La, h, m_rail, Lb) -> tuple:
    """(mass, (x, y) centre, inertia about the axis) of a whole swing frame in frame coordinates (the axis at the
    origin, +x to the counterbalance): its card (``m_card`` centred at (``card_x``, 0), ``I_card_axis`` about the
    axis), the counterbalance a point ``m_cb`` at (La, h), the handrail's card a point ``m_rail`` at the seat
    (-Lb, 0). Any one consistent set of units."""
    m = m_card + m_cb + m_rail
    centre = ((m_card * card_x + m_cb * La - m_rail * Lb) / m, m_cb * h / m)
    return m, centre, I_card_axis + m_cb * (La**2 + h**2) + m_rail * Lb**2


# ---- the robot as built from its parts (what the pymunk world swings) ----
def torso_build(Ld, arm_length, alpha_max_deg, coin_radius):
    """(torso_length, coin_offset) of the robot Table 1 describes, in the units given; floats or arrays.

    Ld is the distance from the hook to the torso's bottom (Appendix A) with the arm fully bent at
    alpha_max, where the hook sits arm_length·sin(alpha_max) ahead of the axle and
    -arm_length·cos(alpha_max) above it; the torso card runs straight down from the axle, so its
    length is what puts its bottom Ld from the hook. The coins are glued flush with the bottom
    (their centre one coin radius above it): the paper puts "the torso containing the weight" at Ld.
    """
    a = np.radians(alpha_max_deg)
    ahead, above = arm_length * np.sin(a), -arm_length * np.cos(a)
    torso_length = np.sqrt(np.maximum(Ld**2 - ahead**2, 0.0)) - above
    return torso_length, torso_length - coin_radius


def spring_damping_coefficient(spring_k, spring_damping, arm_mass, arm_length):
    """The leaf spring's damping (torque per rate of alpha, N·m·s/rad in SI): the damping ratio
    ``spring_damping`` of the arm swinging on the spring about its axle, 2·zeta·sqrt(k·I_arm), with
    I_arm = m_arm·L²/3 the arm about the axle. Floats or arrays."""
    return 2.0 * spring_damping * np.sqrt(spring_k * arm_mass * arm_length**2 / 3.0)


def hook_to_torso_bottom(torso_length, arm_length, alpha_max_deg):
    """The inverse of :func:`torso_build`: the hook's distance to the torso's bottom at alpha_max."""
    a = np.radians(alpha_max_deg)
    return np.hypot(arm_length * np.sin(a), torso_length - arm_length * np.cos(a))


def min_Ld(arm_length, alpha_max_deg, coin_radius):
    """The shortest Ld whose torso still holds the coins on the card (torso_length >= 2·coin_radius)."""
    return hook_to_torso_bottom(2.0 * coin_radius, arm_length, alpha_max_deg)


def part_layout(arm_length, torso_com, m_arm, m_torso, alpha, arm_com):
    """Torso-frame positions (axle at the origin, torso along -y) of the hook, the arm's centre (``arm_com``
    from the axle along the arm), the torso's centre and the robot's centre of mass at arm angle ``alpha``
    (rad): the interior angle at the axle between torso and arm (alpha_min: spring straight; 180 deg: a
    straight robot). Any consistent units; floats or numpy arrays."""
    hook = (arm_length * np.sin(alpha), -arm_length * np.cos(alpha))
    arm_c = (arm_com / arm_length * hook[0], arm_com / arm_length * hook[1])
    torso_c = (0.0 * hook[0], -torso_com + 0.0 * hook[1])
    m = m_arm + m_torso
    com = ((m_arm * arm_c[0] + m_torso * torso_c[0]) / m, (m_arm * arm_c[1] + m_torso * torso_c[1]) / m)
    return hook, arm_c, torso_c, com


class RobotParts:
    """The robot as the kit builds it (:mod:`aero_env.parts.build`), in SI: the torso, a laminated card
    plate hanging from the axle with its bottom Table 1's Ld from the hook with the arm fully bent
    (:func:`torso_build`), with the coins glued flat on it, flush with its bottom; and the arm, a
    laminated plate from behind the axle to the hook, its lip folded at the tip. The handrail's card,
    which Table 1 counts in m2, belongs to the frame and is not part of the robot.

    Every attribute is a plain float (or a numpy array when the design's fields are arrays, so the
    reduced model can build a batch of robots with the same arithmetic).
    """

    def __init__(self, d):
        self.arm_length = d.arm_length
        # torso: its bottom Ld from the hook at alpha_max; the coins (discs in the plane) flush with its bottom
        self.torso_length, self.coin_offset = torso_build(d.Ld, d.arm_length, d.alpha_max_deg, d.coin_radius)
        plate, arm = torso_plate(d, self.torso_length), arm_plate(d)
        self.m_arm = arm["mass"]  # = design.arm_mass
        self.arm_com = arm["com"]  # from the axle along the arm
        self.I_arm = arm["I_com"]  # about the arm's own centre
        self.m_coins = d.coin_mass
        self.m_card = plate["mass"]  # the torso card: m2 less the arm, the coins and the handrail
        self.m_torso = self.m_card + self.m_coins
        self.mass = self.m_torso + self.m_arm
        c = self.coin_offset
        self.torso_com = (self.m_card * plate["com"] + self.m_coins * c) / self.m_torso
        self.I_torso = (plate["I_com"] + self.m_card * (plate["com"] - self.torso_com) ** 2
                        + self.m_coins * (0.5 * d.coin_radius**2 + (c - self.torso_com) ** 2))

    def layout(self, alpha):
        """:func:`part_layout` of these parts."""
        return part_layout(self.arm_length, self.torso_com, self.m_arm, self.m_torso, alpha, self.arm_com)

    def rigid(self, alpha):
        """(hook-to-centre distance, inertia about the centre of mass) of the robot held rigid at
        ``alpha``: the two-link model's link, built from the parts."""
        hook, arm_c, torso_c, com = self.layout(alpha)
        I = (self.I_arm + self.I_torso
             + self.m_arm * ((arm_c[0] - com[0]) ** 2 + (arm_c[1] - com[1]) ** 2)
             + self.m_torso * ((torso_c[0] - com[0]) ** 2 + (torso_c[1] - com[1]) ** 2))
        return np.hypot(hook[0] - com[0], hook[1] - com[1]), I
