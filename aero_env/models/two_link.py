"""The dynamic two-link model (double pendulum), the article's Eqs. (A25) and (A30).

Frame (theta1) and robot (theta2) are two links jointed at the handrail:

    eta1·theta1'' + eta2·theta2'' + eta3 = 0
    eta4·theta1'' + eta5·theta2'' + eta6 = 0

    eta1 = m2·Lb² + m3·(La² + h²) + I1          eta2 = eta4 = m2·Lb·Lc·cos(theta1 - theta2)
    eta3 = m2·Lb·Lc·theta2'²·sin(theta1 - theta2) - m2·g·Lb·cos theta1 - dT·cos theta1
           + m3·g·La·cos theta1 - m3·g·h·sin theta1 - tau1
    eta5 = m2·Lc² + I2                           eta6 = -m2·Lb·Lc·theta1'²·sin(theta1 - theta2)
           - m2·g·Lc·cos theta2 - tau2

dT (``design.dT``) is the frame's own moment, a torque dT·cos theta1 about its axis: it enters the
theta1 equation only, beside the robot's drive m2·g·Lb·cos theta1 (as in Eq. (1)), and its
potential is -dT·sin theta1. I1 stays the frame's inertia about its axis.

Two conventions, each a named option of :func:`coefficients` (and of :func:`simulate`,
:func:`time_to_angle_batch`):

``inertia`` (the frame, I1): ``"consistent"`` uses I1 = 2·m1/3·(La²+Lb²-La·Lb); ``"paper"`` adds
I3 as A13 does (counting the counterbalance twice, since eta1 already holds it); ``"parts"`` is the
frame's two side cards as the kit builds them, what the pymunk world swings (``aero-env compare``
uses it with ``robot="parts"``, so that it compares models of one machine).

``robot`` (the robot link: its mass m2, hook-to-centre distance Lc, inertia I2 about its centre,
and what the frame carries at the seat):

- ``"paper"`` (default): the model exactly as written, m2 and Lc from Table 1 and A14's
  I2 = m2/3·(Ld² + Ld·Lc + Lc²). A14 integrates l² from Lc to Ld measured from the hook, so it is
  already an inertia about the hook (of a uniform line whose centre is at (Lc+Ld)/2, not at Lc);
  eta5 = m2·Lc² + I2 then adds a parallel-axis term on top, counting the robot's distance from the
  hook twice. Kept because it is the paper's model.
- ``"parts"``: the robot as the pymunk world builds it (:class:`aero_env.parts.bodies.RobotParts`:
  arm and torso plates as the kit builds them, coins), held rigid with the arm fully bent (alpha_max, how the robot
  hangs all swing long on a working design): m2 = the parts' mass, Lc and I2 the parts'
  hook-to-centre distance and inertia about their centre, so eta5 = m2·Lc² + I2 is the parts'
  inertia about the hook. The handrail's card (``handrail_mass``), which Table 1 counts in m2,
  rides on the frame at the seat (distance Lb from the axis): it adds handrail_mass·Lb² to eta1 and
  its weight handrail_mass·g·Lb·cos theta1 to the drive, and does not swing with the robot.

Drag (``drag=True``): the frame's tau1 = -(1/8)·rho·Cd·A·theta1'|theta1'|·(La⁴+Lb⁴), and the
robot link's drag from the joint to its centre (l in [0, Lc]) with normal velocity
v_n(l) = v_J·n + l·theta2', integrated with its sign changes (:mod:`aero_env.drag_law`). Its
generalised force on theta2 is the brief's tau2; its generalised force on theta1 (through the
joint) is added to tau1, so drag power is never positive and energy falls monotonically.

Integrator: scipy's DOP853 (explicit Runge-Kutta 8(5,3)) with dense output. The system is
smooth and not stiff over a swing, so a high-order explicit method reaches rtol 1e-10 in a
few hundred steps; the time theta1 reaches ``until_theta1`` is located by root finding on the
dense output (accurate to ~1e-9 s at the defaults). :func:`time_to_angle_batch` is the fast
path: fixed-step RK4 vectorised over many designs at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..config import Design
from ..drag_law import strip_drag
from ..inertia import counterbalance_inertia, frame_inertia, robot_inertia
from ..parts.bodies import RobotParts
from ..units import GRAVITY as G

ROBOT_CONVENTIONS = ("paper", "parts")


@dataclass
class SwingResult:
    """A swing sampled on a uniform grid (SI, radians). theta2 and its rates are NaN for one-link models."""

    t: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    omega1: np.ndarray
    omega2: np.ndarray
    alpha1: np.ndarray
    alpha2: np.ndarray
    t_until: float | None  # first time theta1 reaches until_theta1 (event location), None if never


@dataclass(frozen=True)
class RobotLink:
    """The robot as the two-link model's second link, under one ``robot`` convention (SI)."""

    mass: float  # m2: the mass that swings with the robot, hanging at the joint
    Lc: float  # joint (hook) to the robot's centre of mass
    I_centre: float  # I2: inertia about the robot's centre of mass
    seat_mass: float  # mass the frame carries at the seat (distance Lb), counted in Table 1's m2


def robot_link(d: Design, robot: str = "paper") -> RobotLink:
    """The robot link of the named convention (see the module docstring)."""
    if robot == "paper":
        return RobotLink(mass=d.m2, Lc=d.Lc, I_centre=robot_inertia(d), seat_mass=0.0)
    if robot == "parts":
        parts = RobotParts(d)
        # hanging, the robot's weight holds the leaf spring fully bent: the arm sits at alpha_max
        lc, i_centre = parts.rigid(math.radians(d.alpha_max_deg))
        return RobotLink(mass=parts.mass, Lc=float(lc), I_centre=float(i_centre), seat_mass=d.handrail_mass)
    raise ValueError(f"robot convention {robot!r}: must be one of {ROBOT_CONVENTIONS}")


@dataclass(frozen=True)
class Coefficients:
    """The constant parts of the eta's for one design (m2, Lc: the robot link of the convention)."""

    eta1: float  # inertia about the frame axis: robot at the joint, seat mass, counterbalance, frame
    m2LbLc: float  # coupling, eta2 = m2·Lb·Lc·cos(theta1 - theta2)
    eta5: float  # the robot's inertia about the joint, m2·Lc² + I2
    drive: float  # (m2 + seat mass)·g·Lb + dT: the moment turning the frame forward is drive·cos theta1
    m3gLa: float
    m3gh: float
    m2gLc: float
    Lb: float
    Lc: float
    frame_drag: float  # (1/8)·rho·Cd·A_frame·(La⁴ + Lb⁴)
    robot_drag: float  # (1/2)·rho·Cd·A_robot


def coefficients(d: Design, inertia: str = "consistent", robot: str = "paper") -> Coefficients:
    """The eta coefficients of design ``d`` under the named I1 (``inertia``) and robot conventions."""
    link = robot_link(d, robot)
    # everything at the joint turns with the frame at radius Lb: the robot's mass and the seat's
    at_joint = link.mass + link.seat_mass
    return Coefficients(
        eta1=at_joint * d.Lb**2 + counterbalance_inertia(d) + frame_inertia(d, inertia),
        m2LbLc=link.mass * d.Lb * link.Lc, eta5=link.mass * link.Lc**2 + link.I_centre,
        drive=at_joint * G * d.Lb + d.dT,
        m3gLa=d.m3 * G * d.La, m3gh=d.m3 * G * d.h, m2gLc=link.mass * G * link.Lc,
        Lb=d.Lb, Lc=link.Lc,
        frame_drag=d.rho * d.Cd * d.frame_width * (d.La**4 + d.Lb**4) / 8.0,
        robot_drag=0.5 * d.rho * d.Cd * d.robot_width,
    )


def drag_torques(c: Coefficients, th1: float, th2: float, w1: float, w2: float) -> tuple[float, float]:
    """Generalised drag forces (tau1, tau2), N·m."""
    if c.Lc == 0.0:
        return -c.frame_drag * w1 * abs(w1), 0.0
    n = (np.sin(th2), -np.cos(th2))  # robot link normal; the link runs from the joint along -(cos, sin)
    dj = (c.Lb * np.sin(th1), -c.Lb * np.cos(th1))  # d(joint)/d(theta1)
    vj_n = w1 * (dj[0] * n[0] + dj[1] * n[1])
    force, moment = strip_drag(vj_n, vj_n + c.Lc * w2, c.Lc)
    tau1 = -c.frame_drag * w1 * abs(w1) + c.robot_drag * force * (dj[0] * n[0] + dj[1] * n[1])
    return tau1, c.robot_drag * moment


def accelerations(c: Coefficients, th1, th2, w1, w2, tau1=0.0, tau2=0.0):
    """(theta1'', theta2'') from the two equations; works on scalars or numpy arrays."""
    s, co = np.sin(th1 - th2), np.cos(th1 - th2)
    eta2 = c.m2LbLc * co
    eta3 = c.m2LbLc * w2**2 * s - c.drive * np.cos(th1) + c.m3gLa * np.cos(th1) - c.m3gh * np.sin(th1) - tau1
    eta6 = -c.m2LbLc * w1**2 * s - c.m2gLc * np.cos(th2) - tau2
    det = c.eta1 * c.eta5 - eta2 * eta2
    return (-eta3 * c.eta5 + eta2 * eta6) / det, (-c.eta1 * eta6 + eta2 * eta3) / det


def energy(c: Coefficients, th1, th2, w1, w2):
    """Kinetic + potential energy (J), zero of height at the frame axis.

    The drive's potential is -drive·sin theta1: gravity on the masses at the joint (height
    -Lb·sin theta1) and dT's, since its torque dT·cos theta1 = -dV/dtheta1 gives V = -dT·sin theta1.
    """
    kin = 0.5 * c.eta1 * w1**2 + 0.5 * c.eta5 * w2**2 + c.m2LbLc * np.cos(th1 - th2) * w1 * w2
    pot = -c.drive * np.sin(th1) - c.m2gLc * np.sin(th2) + c.m3gLa * np.sin(th1) + c.m3gh * np.cos(th1)
    return kin + pot


def simulate(d: Design, theta1_0: float, theta2_0: float, omega1_0: float = 0.0, omega2_0: float = 0.0,
             t_end: float = 2.0, until_theta1: float | None = None, drag: bool = False,
             inertia: str = "consistent", robot: str = "paper", rtol: float = 1e-10,
             atol: float = 1e-12) -> SwingResult:
    """Integrate the two-link model from the given state (radians, rad/s) to t_end or until_theta1."""
    c = coefficients(d, inertia, robot)

    def rhs(_t, y):
        tau1, tau2 = drag_torques(c, *y) if drag else (0.0, 0.0)
        a1, a2 = accelerations(c, y[0], y[1], y[2], y[3], tau1, tau2)
        return np.array([y[2], y[3], a1, a2])

    return integrate(rhs, np.array([theta1_0, theta2_0, omega1_0, omega2_0]), t_end, until_theta1, rtol, atol)


def integrate(rhs, y0, t_end, until_theta1, rtol, atol, one_link: bool = False) -> SwingResult:
    events = None
    if until_theta1 is not None:
        def reach(_t, y):
            return y[0] - until_theta1

        reach.terminal, reach.direction = True, 1.0
        events = reach
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                    events=events)
    if sol.status == -1:
        raise RuntimeError(f"two-link integration failed: {sol.message}")
    t_until = float(sol.t_events[0][0]) if events is not None and len(sol.t_events[0]) else None
    t_final = sol.t[-1]
    t = np.linspace(0.0, t_final, max(201, int(round(t_final / 1e-3)) + 1))
    y = sol.sol(t)
    acc = np.array([rhs(ti, yi)[len(y0) // 2:] for ti, yi in zip(t, y.T)]).T
    if one_link:
        nan = np.full_like(t, np.nan)
        return SwingResult(t, y[0], nan, y[1], nan, acc[0], nan, t_until)
    return SwingResult(t, y[0], y[1], y[2], y[3], acc[0], acc[1], t_until)


def time_to_angle_batch(designs, theta1_0, theta2_0, until_theta1: float, t_end: float = 2.0,
                        dt: float = 5e-4, inertia: str = "consistent", robot: str = "paper") -> np.ndarray:
    """Time (s) for theta1 to reach ``until_theta1`` for many designs at once (NaN if it never does).

    Fixed-step RK4 vectorised over the batch, no drag; the crossing is located by cubic Hermite
    interpolation inside the step. ``theta1_0``/``theta2_0`` may be scalars or per-design arrays.
    """
    cs = [coefficients(d, inertia, robot) for d in designs]
    c = Coefficients(*(np.array([getattr(ci, f) for ci in cs]) for f in Coefficients.__dataclass_fields__))
    n = len(cs)
    th1 = np.full(n, theta1_0, dtype=float)
    th2 = np.full(n, theta2_0, dtype=float)
    w1 = np.zeros(n)
    w2 = np.zeros(n)
    out = np.full(n, np.nan)
    active = np.ones(n, dtype=bool)

    def f(a, b, x, y):
        return accelerations(c, a, b, x, y)

    for k in range(int(np.ceil(t_end / dt))):
        a1, a2 = f(th1, th2, w1, w2)
        k1 = (w1, w2, a1, a2)
        b1, b2 = f(th1 + dt / 2 * k1[0], th2 + dt / 2 * k1[1], w1 + dt / 2 * k1[2], w2 + dt / 2 * k1[3])
        k2 = (w1 + dt / 2 * k1[2], w2 + dt / 2 * k1[3], b1, b2)
        c1, c2 = f(th1 + dt / 2 * k2[0], th2 + dt / 2 * k2[1], w1 + dt / 2 * k2[2], w2 + dt / 2 * k2[3])
        k3 = (w1 + dt / 2 * k2[2], w2 + dt / 2 * k2[3], c1, c2)
        d1, d2 = f(th1 + dt * k3[0], th2 + dt * k3[1], w1 + dt * k3[2], w2 + dt * k3[3])
        k4 = (w1 + dt * k3[2], w2 + dt * k3[3], d1, d2)
        new = [s + dt / 6 * (p + 2 * q + 2 * r + u) for s, p, q, r, u in zip((th1, th2, w1, w2), k1, k2, k3, k4)]
        crossed = active & (new[0] >= until_theta1)
        if crossed.any():
            out[crossed] = k * dt + dt * _hermite_root(th1[crossed], new[0][crossed], w1[crossed] * dt,
                                                       new[2][crossed] * dt, until_theta1)
            active &= ~crossed
        th1, th2, w1, w2 = new
        if not active.any():
            break
    return out


def _hermite_root(p0, p1, m0, m1, target) -> np.ndarray:
    """Fraction s in [0, 1] of the step where the cubic Hermite curve through (p0, m0), (p1, m1) hits target."""
    s = np.clip((target - p0) / np.where(p1 != p0, p1 - p0, 1.0), 0.0, 1.0)
    for _ in range(4):  # Newton on the cubic, started from the linear guess
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        val = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1 - target
        der = (6 * s**2 - 6 * s) * p0 + (3 * s**2 - 4 * s + 1) * m0 + (-6 * s**2 + 6 * s) * p1 + (3 * s**2 - 2 * s) * m1
        s = np.clip(s - val / np.where(der != 0, der, 1.0), 0.0, 1.0)
    return s
