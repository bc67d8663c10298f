"""Convert a validated SI config into the engine's scale (mm, g, s, radians).

This is the single place where SI values cross into the engine (see :mod:`aero_env.units`).
It also derives the robot's part geometry: the torso's own moment of inertia is chosen so
that the whole robot, with its arm fully bent (alpha_max), has the paper's inertia I2 about
its centre of mass; the two-link model and the pymunk robot then swing the same body.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import units
from ..config import Config, ConfigError
from ..inertia import frame_inertia, robot_inertia



@dataclass(frozen=True)
class EngineParams:
    # frames
    La: float
    Lb: float
    h: float
    m_frame: float
    m_cb: float
    frame_com_x: float  # the frame's own centre of mass along its axis, from dT
    I_frame_axis: float  # frame alone about its axis (consistent I1)
    rest_angle: float
    stop_angle: float
    notch_angle: float  # world direction of the notch bisector at the rest angle
    notch_opening: float
    notch_back_face: float
    notch_front_face: float
    rail_radius: float
    hook_radius: float
    # robot
    m_robot: float
    m_arm: float
    m_torso: float
    arm_length: float
    torso_com: float
    I_arm: float  # about the arm's own centre of mass
    I_torso: float  # about the torso's own centre of mass
    Lc: float  # two-link joint-to-centre distance (pinned-hook scene)
    I2: float  # the robot about its centre of mass (paper A14)
    alpha_min: float
    alpha_max: float
    spring_k: float
    mu_s: float
    mu_k: float
    # drag
    drag_coeff: float  # rho*Cd/2 in engine units
    frame_width: float
    robot_width: float
    # scene
    frames: int
    pitch: float
    rise: float
    theta2_start: float
    floor_drop: float
    # sim
    gravity: float
    dt: float  # one pymunk step
    substeps: int  # pymunk steps per runner step
    step: float  # one runner step, dt·substeps
    iterations: int
    collision_slop: float
    slip_speed: float
    max_speed: float


def robot_mass_layout(arm_length: float, torso_com: float, m_arm: float, m_torso: float, alpha: float):
    """Torso-frame positions (axle at the origin, torso hanging along -y) of the hook, the arm's
    centre, the torso's centre and the robot's centre of mass, for arm angle ``alpha``.

    alpha is the interior angle at the axle between the torso (axle -> torso centre) and the
    arm (axle -> hook): 180 deg would be a straight robot, alpha_min the spring's straight shape.
    """
    hook = (arm_length * math.sin(alpha), -arm_length * math.cos(alpha))
    arm_c = (hook[0] / 2.0, hook[1] / 2.0)
    torso_c = (0.0, -torso_com)
    m = m_arm + m_torso
    com = ((m_arm * arm_c[0] + m_torso * torso_c[0]) / m, (m_arm * arm_c[1] + m_torso * torso_c[1]) / m)
    return hook, arm_c, torso_c, com


def to_engine(cfg: Config) -> EngineParams:
    d, s, sim = cfg.design, cfg.scene, cfg.sim
    L, M, I = units.LENGTH, units.MASS, units.INERTIA
    rad = math.radians

    m_arm, m_robot = d.arm_mass * M, d.m2 * M
    m_torso = m_robot - m_arm
    arm_length, torso_com = d.arm_length * L, d.torso_com * L
    alpha_max = rad(d.alpha_max_deg)
    # Torso inertia: the robot at alpha_max must have I2 about its centre of mass.
    _, arm_c, torso_c, com = robot_mass_layout(arm_length, torso_com, m_arm, m_torso, alpha_max)
    I_arm = m_arm * arm_length**2 / 12.0
    I_torso = (robot_inertia(d) * I - I_arm
               - m_arm * ((arm_c[0] - com[0]) ** 2 + (arm_c[1] - com[1]) ** 2)
               - m_torso * ((torso_c[0] - com[0]) ** 2 + (torso_c[1] - com[1]) ** 2))
    if I_torso <= 0.0:
        raise ConfigError(
            f"design.Ld = {d.Ld!r}: the robot inertia I2 = m2/3*(Ld^2+Ld*Lc+Lc^2) is smaller than its parts "
            f"(arm_length, torso_com) allow; raise Ld or Lc, or shorten arm_length/torso_com")
    # Eq. (1) adds +dT·cos(theta1); a centre of mass at x along the frame gives -m1·g·x·cos(theta1).
    frame_com_x = -(d.dT / (d.m1 * units.GRAVITY)) * L

    return EngineParams(
        La=d.La * L, Lb=d.Lb * L, h=d.h * L,
        m_frame=d.m1 * M, m_cb=d.m3 * M, frame_com_x=frame_com_x,
        I_frame_axis=frame_inertia(d, "consistent") * I,
        rest_angle=rad(d.rest_angle_deg), stop_angle=rad(d.stop_angle_deg),
        notch_angle=rad(d.notch_angle_deg), notch_opening=rad(d.notch_opening_deg),
        notch_back_face=d.notch_back_face * L, notch_front_face=d.notch_front_face * L,
        rail_radius=d.handrail_thickness * L / 2.0, hook_radius=d.hook_radius * L,
        m_robot=m_robot, m_arm=m_arm, m_torso=m_torso, arm_length=arm_length, torso_com=torso_com,
        I_arm=I_arm, I_torso=I_torso, Lc=d.Lc * L, I2=robot_inertia(d) * I,
        alpha_min=rad(d.alpha_min_deg), alpha_max=alpha_max,
        spring_k=d.spring_k * units.TORQUE, mu_s=d.mu_s, mu_k=d.mu_k,
        drag_coeff=0.5 * d.rho * units.DENSITY * d.Cd,
        frame_width=d.frame_width * L, robot_width=d.robot_width * L,
        frames=s.frames, pitch=s.pitch * L, rise=s.rise * L, theta2_start=rad(s.theta2_start_deg),
        floor_drop=s.floor_drop * L,
        gravity=units.GRAVITY * units.ACCELERATION, dt=sim.dt * units.TIME,
        substeps=sim.substeps, step=sim.dt * sim.substeps * units.TIME, iterations=sim.iterations,
        collision_slop=sim.collision_slop * L, slip_speed=sim.slip_speed * units.VELOCITY,
        max_speed=sim.max_speed * units.VELOCITY,
    )
