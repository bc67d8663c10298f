"""Convert a validated SI config into the engine's scale (mm, g, s, radians).

This is the single place where SI values cross into the engine (see :mod:`aero_env.units`):
every length, mass, inertia, torque, speed and angle the world uses is converted here once,
and the world converts nothing. Every body's mass, centre and inertia comes from
:mod:`aero_env.parts.bodies` (the frame's card, the robot's torso with its coins and its arm), the same values
the reduced model and the analytical ``parts`` convention read; the handrail's card, which Table 1 counts in m2,
rides on the frame at the seat.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymunk

from .. import units
from ..config import Config, ConfigError
from ..parts.bodies import RobotParts, frame_card, spring_damping_coefficient
from .swing_rules import held_past_angle


@dataclass(frozen=True)
class EngineParams:
    # frames
    La: float
    Lb: float
    h: float
    m_frame: float
    m_cb: float
    m_handrail: float  # the handrail's card, a point mass at the seat (-Lb, 0)
    pivot_friction: float  # Coulomb torque at each frame's skewer (0: no part)
    frame_com_x: float  # the frame's own centre of mass along its axis, from dT
    I_frame_axis: float  # the frame's two side cards about its axis, as the kit builds them (aero_env/parts)
    rest_angle: float
    stop_angle: float
    held_past: float  # a hooked frame turning back after passing this angle was held by friction (results)
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
    arm_com: float  # the arm's centre of mass, from the axle along the arm
    torso_com: float
    torso_length: float  # the torso card strip, axle to its bottom
    coin_offset: float  # axle to the coins' centre
    I_arm: float  # about the arm's own centre of mass
    I_torso: float  # about the torso's own centre of mass
    axle_friction: float  # Coulomb torque at the arm's axle (0: no part)
    Lc: float  # pinned-hook scene: hook to the rigid robot's centre (the parts held at alpha_max)
    I2: float  # pinned-hook scene: the rigid robot about its centre of mass (the parts held at alpha_max)
    alpha_min: float
    alpha_max: float
    spring_k: float
    spring_c: float  # the leaf spring's damping, torque per rate of alpha (0: none)
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
    # event thresholds the runner compares engine values with
    catch_seat: float  # a held touch counts as a catch only with the hook centre this close to the seat
    min_release_height: float


def to_engine(cfg: Config) -> EngineParams:
    d, s, sim = cfg.design, cfg.scene, cfg.sim
    L, M, I = units.LENGTH, units.MASS, units.INERTIA
    rad = math.radians

    parts = RobotParts(d)
    # the pinned-hook scene's robot: the parts held rigid at alpha_max (two_link's "parts" convention)
    rigid_Lc, rigid_I = (float(v) for v in parts.rigid(math.radians(d.alpha_max_deg)))
    _, card_x, I_card = frame_card(d)  # the side cards about the axis, their centre moved by dT

    return EngineParams(
        La=d.La * L, Lb=d.Lb * L, h=d.h * L,
        m_frame=d.m1 * M, m_cb=d.m3 * M, m_handrail=d.handrail_mass * M,
        pivot_friction=d.pivot_friction * units.TORQUE, frame_com_x=card_x * L,
        I_frame_axis=I_card * I,
        rest_angle=rad(d.rest_angle_deg), stop_angle=rad(d.stop_angle_deg), held_past=float(held_past_angle(d)),
        notch_angle=rad(d.notch_angle_deg), notch_opening=rad(d.notch_opening_deg),
        notch_back_face=d.notch_back_face * L, notch_front_face=d.notch_front_face * L,
        rail_radius=d.handrail_thickness * L / 2.0, hook_radius=d.hook_radius * L,
        m_robot=parts.mass * M, m_arm=parts.m_arm * M, m_torso=parts.m_torso * M,
        arm_length=d.arm_length * L, arm_com=float(parts.arm_com) * L, torso_com=parts.torso_com * L,
        torso_length=float(parts.torso_length) * L, coin_offset=float(parts.coin_offset) * L,
        I_arm=parts.I_arm * I, I_torso=parts.I_torso * I, axle_friction=d.axle_friction * units.TORQUE,
        Lc=rigid_Lc * L, I2=rigid_I * I,
        alpha_min=rad(d.alpha_min_deg), alpha_max=rad(d.alpha_max_deg),
        spring_k=d.spring_k * units.TORQUE, mu_s=d.mu_s, mu_k=d.mu_k,
        spring_c=float(spring_damping_coefficient(d.spring_k, d.spring_damping, d.arm_mass, d.arm_length))
        * units.TORQUE * units.TIME,
        drag_coeff=0.5 * d.rho * units.DENSITY * d.Cd,
        frame_width=d.frame_width * L, robot_width=d.robot_width * L,
        frames=s.frames, pitch=s.pitch * L, rise=s.rise * L, theta2_start=rad(s.theta2_start_deg),
        floor_drop=s.floor_drop * L,
        gravity=units.GRAVITY * units.ACCELERATION, dt=sim.dt * units.TIME,
        substeps=sim.substeps, step=sim.dt * sim.substeps * units.TIME, iterations=sim.iterations,
        collision_slop=sim.collision_slop * L, slip_speed=sim.slip_speed * units.VELOCITY,
        max_speed=sim.max_speed * units.VELOCITY,
        catch_seat=sim.catch_seat * L, min_release_height=sim.min_release_height * L,
    )


def rigid_body(mass: float, moment: float, part: str, fields: str) -> pymunk.Body:
    """A pymunk body of ``mass`` and ``moment`` (engine units, about its centre of gravity), both checked first.

    Chipmunk aborts the whole process (SIGABRT, which Python cannot catch: a training run or a tuning worker dies
    with it) on a mass or moment that is not positive. The config's cross-checks refuse every design whose parts
    cannot be cut (:mod:`aero_env.config.sections`), so this is the last guard, not the rule: a body that still
    comes out so is refused in one line naming the ``part`` and the design ``fields`` it is made from."""
    if not (math.isfinite(mass) and mass > 0.0 and math.isfinite(moment) and moment > 0.0):
        raise ConfigError(f"design ({fields}): the {part} comes out with mass {mass / units.MASS:.4g} kg and "
                          f"inertia {moment / units.INERTIA:.4g} kg·m² about its centre; a body needs both positive "
                          f"and finite")
    return pymunk.Body(mass, moment)
