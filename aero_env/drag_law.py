"""Quadratic drag on a straight strip whose normal velocity varies linearly along it.

Shared by the pymunk drag part and the analytical two-link model, so both integrate the
brief's drag the same way. Per unit of rho·Cd/2·width, the strip from l = 0 to l = L with
normal velocity v(l) = v0 + (v1 - v0)·l/L feels

    F = -∫ v|v| dl,        M = -∫ v|v|·l dl   (moment about l = 0).

The integrand changes sign where v does, so the integral is split there (the paper expands
tau2 for one sign only); each piece is a polynomial of degree <= 3, which 2-point
Gauss-Legendre quadrature integrates exactly.
"""

from __future__ import annotations

_G = 0.5773502691896257  # 2-point Gauss-Legendre nodes +-1/sqrt(3), weights 1


def strip_drag(v0: float, v1: float, length: float) -> tuple[float, float]:
    """(F, M) for normal velocities v0 at l = 0 and v1 at l = length; see the module docstring."""
    cuts = (0.0, length * v0 / (v0 - v1), length) if v0 * v1 < 0.0 else (0.0, length)
    force = moment = 0.0
    for a, c in zip(cuts[:-1], cuts[1:]):
        half, mid = (c - a) / 2.0, (c + a) / 2.0
        for l in (mid - half * _G, mid + half * _G):
            v = v0 + (v1 - v0) * l / length
            f = -v * abs(v) * half
            force += f
            moment += f * l
    return force, moment
