"""The paper's inertias (A13-A15), as pure functions of a design, in SI.

Shared by the pymunk world and the analytical models so that both use one definition.
"""

from __future__ import annotations

from typing import Any

# a design: an aero_env.config.Design, or any object with its fields. The config's checks use this module
# (min_Ld, torso_build), so it does not import the config, not even for a type.
Design = Any


def frame_inertia(d: Design, convention: str = "consistent") -> float:
    """I1, the swing frame's own moment of inertia about its axis (kg·m²).

    ``consistent``: 2·m1/3·(La² + Lb² - La·Lb), A13's frame alone. ``paper``: A13 as printed,
    which adds I3 although the two-link eta1 already holds the counterbalance. ``parts``: the two
    side cards as the kit builds them (:func:`aero_env.parts.build.frame_card_inertia`), what the
    pymunk world and the reduced model swing.
    """
    if convention == "parts":
        from .parts.build import frame_card_inertia

        return frame_card_inertia(d)
    i1 = 2.0 * d.m1 / 3.0 * (d.La**2 + d.Lb**2 - d.La * d.Lb)
    if convention == "consistent":
        return i1
    if convention == "paper":
        return i1 + counterbalance_inertia(d)
    raise ValueError(f"inertia convention {convention!r}: must be 'consistent', 'paper' or 'parts'")


def robot_inertia(d: Design) -> float:
    """I2 = m2/3·(Ld² + Ld·Lc + Lc²), the robot about its own centre of mass (kg·m²)."""
    return d.m2 / 3.0 * (d.Ld**2 + d.Ld * d.Lc + d.Lc**2)


def counterbalance_inertia(d: Design) -> float:
    """I3 = m3·(La² + h²), the counterbalance about the frame axis (kg·m²)."""
    return d.m3 * (d.La**2 + d.h**2)


# ---- the robot as built from its parts (what the pymunk world swings) ----
def torso_build(Ld, arm_length, alpha_max_deg, coin_radius):
    """(torso_length, coin_offset) of the robot Table 1 describes, in the units given; floats or arrays.

    Ld is the distance from the hook to the torso's bottom (Appendix A) with the arm fully bent at
    alpha_max, where the hook sits arm_length·sin(alpha_max) ahead of the axle and
    -arm_length·cos(alpha_max) above it; the torso card runs straight down from the axle, so its
    length is what puts its bottom Ld from the hook. The coins are glued flush with the bottom
    (their centre one coin radius above it): the paper puts "the torso containing the weight" at Ld.
    """
    import numpy as np

    a = np.radians(alpha_max_deg)
    ahead, above = arm_length * np.sin(a), -arm_length * np.cos(a)
    torso_length = np.sqrt(np.maximum(Ld**2 - ahead**2, 0.0)) - above
    return torso_length, torso_length - coin_radius


def spring_damping_coefficient(spring_k, spring_damping, arm_mass, arm_length):
    """The leaf spring's damping (torque per rate of alpha, N·m·s/rad in SI): the damping ratio
    ``spring_damping`` of the arm swinging on the spring about its axle, 2·zeta·sqrt(k·I_arm), with
    I_arm = m_arm·L²/3 the arm about the axle. Floats or arrays."""
    import numpy as np

    return 2.0 * spring_damping * np.sqrt(spring_k * arm_mass * arm_length**2 / 3.0)


def hook_to_torso_bottom(torso_length, arm_length, alpha_max_deg):
    """The inverse of :func:`torso_build`: the hook's distance to the torso's bottom at alpha_max."""
    import numpy as np

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
    import numpy as np

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
        from .parts.build import arm_plate, torso_plate

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
        import numpy as np

        hook, arm_c, torso_c, com = self.layout(alpha)
        I = (self.I_arm + self.I_torso
             + self.m_arm * ((arm_c[0] - com[0]) ** 2 + (arm_c[1] - com[1]) ** 2)
             + self.m_torso * ((torso_c[0] - com[0]) ** 2 + (torso_c[1] - com[1]) ** 2))
        return np.hypot(hook[0] - com[0], hook[1] - com[1]), I
