"""The one boundary between SI configs and the engine's internal scale.

Configs and every public result are in SI (m, kg, s, N, N·m/rad). Inside pymunk the
machine is simulated in millimetres and grams: a 5 cm swing frame is 50 units long,
which sits well above pymunk's collision slop and keeps masses (grams) and moments
(g·mm²) near 1..1e5 instead of 1e-3..1e-7. Seconds stay seconds.

Only :mod:`aero_env.physics.engine_params` converts a config into engine units and
only the result builders convert back; nothing else multiplies by these factors.
"""

from __future__ import annotations

GRAVITY = 9.81  # m/s², the one value of g used by the configs, the world and the models

LENGTH = 1e3  # engine length units (mm) per metre
MASS = 1e3  # engine mass units (g) per kilogram
TIME = 1.0  # engine time units per second

# Derived factors (engine units per SI unit).
VELOCITY = LENGTH / TIME
ACCELERATION = LENGTH / TIME**2
FORCE = MASS * LENGTH / TIME**2
TORQUE = FORCE * LENGTH  # also energy: N·m and J
ENERGY = TORQUE
INERTIA = MASS * LENGTH**2
DENSITY = MASS / LENGTH**3


def length_to_engine(x_m: float) -> float:
    return x_m * LENGTH


def length_to_si(x: float) -> float:
    return x / LENGTH


def energy_to_si(e: float) -> float:
    return e / ENERGY


def velocity_to_si(v: float) -> float:
    return v / VELOCITY
