"""The article's inertias (A13-A15), as pure functions of a design, in SI: the analytical models' ``consistent``
and ``paper`` conventions. The bodies the world swings (and the models' ``parts`` convention) are the parts'
own, computed in :mod:`aero_env.parts.bodies`.
"""

from __future__ import annotations

from typing import Any

Design = Any  # an aero_env.config.Design, or any object with its fields


def frame_inertia(d: Design, convention: str = "consistent") -> float:
    """I1, the swing frame's own moment of inertia about its axis (kg·m²).

    ``consistent``: 2·m1/3·(La² + Lb² - La·Lb), A13's frame alone. ``paper``: A13 as printed,
    which adds I3 although the two-link eta1 already holds the counterbalance. ``parts``: the two
    side cards as the kit builds them (:func:`aero_env.parts.bodies.frame_card`), what the
    pymunk world and the reduced model swing.
    """
    if convention == "parts":
        from .parts.bodies import frame_card

        return frame_card(d)[2]
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
