"""Quasi-static single link (Nishibori), the article's Eq. (1):

    I·theta1'' = (m2·g·Lb + dT)·cos theta1 - m3·g·La·cos theta1 + m3·g·h·sin theta1,   I = I1 + I2 + I3

The robot is a point mass at the handrail that does not swing; only the frame moves. dT
(``design.dT``) is the frame's own moment at theta1 = 0, a torque dT·cos theta1 about the axis beside
the robot's m2·g·Lb·cos theta1 (the two-link model carries it the same way). m2 and I2 are the
paper's (Table 1, A14), as in the two-link ``robot="paper"`` convention. With Table 1 the right side
is positive up to theta1 ~ 125 deg and negative beyond.
"""

from __future__ import annotations

import numpy as np

from ..config import Design
from ..inertia import counterbalance_inertia, frame_inertia, robot_inertia
from .two_link import G, SwingResult, coefficients, integrate


def moment(d: Design, theta1) -> np.ndarray:
    """The right side of Eq. (1), N·m, vectorised over theta1 (rad)."""
    th = np.asarray(theta1, dtype=float)
    return (d.m2 * G * d.Lb + d.dT) * np.cos(th) - d.m3 * G * d.La * np.cos(th) + d.m3 * G * d.h * np.sin(th)


def inertia(d: Design, convention: str = "consistent") -> float:
    """I = I1 + I2 + I3 of Eq. (1) (kg·m²), I1 by the named convention (see :func:`frame_inertia`)."""
    return frame_inertia(d, convention) + robot_inertia(d) + counterbalance_inertia(d)


def angular_acceleration(d: Design, theta1, I: float | None = None, convention: str = "consistent") -> np.ndarray:
    """theta1'' (rad/s²) of Eq. (1), vectorised over theta1 (rad); uses design.dT.

    ``I`` overrides the inertia (e.g. the two-link eta1 to compare the two models).
    """
    return moment(d, theta1) / (inertia(d, convention) if I is None else I)


def zero_crossing(d: Design, lo: float = np.radians(60.0), hi: float = np.radians(179.0)) -> float | None:
    """The angle (rad) in [lo, hi] where the moment of Eq. (1) turns from positive to negative."""
    th = np.linspace(lo, hi, 20001)
    m = moment(d, th)
    idx = np.nonzero((m[:-1] > 0) & (m[1:] <= 0))[0]
    if idx.size == 0:
        return None
    i = idx[0]
    return float(th[i] - m[i] * (th[i + 1] - th[i]) / (m[i + 1] - m[i]))


def simulate(d: Design, theta1_0: float, omega1_0: float = 0.0, t_end: float = 2.0,
             until_theta1: float | None = None, I: float | None = None, convention: str = "consistent",
             drag: bool = False, rtol: float = 1e-10, atol: float = 1e-12) -> SwingResult:
    """Integrate Eq. (1) from (theta1_0, omega1_0); theta2 is not modelled (NaN in the result).

    ``drag`` adds the frame's tau1 = -(1/8)·rho·Cd·A·theta1'|theta1'|·(La⁴+Lb⁴) (the robot does not swing here).
    """
    inertia_value = inertia(d, convention) if I is None else I
    frame_drag = coefficients(d).frame_drag if drag else 0.0

    def rhs(_t, y):
        return np.array([y[1], (moment(d, y[0]) - frame_drag * y[1] * abs(y[1])) / inertia_value])

    return integrate(rhs, np.array([theta1_0, omega1_0]), t_end, until_theta1, rtol, atol, one_link=True)
