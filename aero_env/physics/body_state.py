"""A pymunk body's state read straight from its C struct, for the runner's per-step paths.

``body.position`` builds a :class:`pymunk.Vec2d` from the C vector through a Python property; a
read of position, angle, velocity and spin that way costs about 1.2 us, three times the C calls
under it. The per-step friction switch reads two bodies every 0.5 ms step and a check reads every
live body, so the runner calls Chipmunk's getters itself (``cpBodyGetPosition`` and the rest, the
same calls pymunk's properties make) and takes the doubles as they are: every value is the one the
property returns, bit for bit (``tests/test_physics_layer.py`` checks it). pymunk is pinned, and
its ``Body._body`` handle and cffi ``lib`` are what its own properties use.
"""

from __future__ import annotations

import pymunk
from pymunk._chipmunk_cffi import lib

_position, _velocity = lib.cpBodyGetPosition, lib.cpBodyGetVelocity
_angle, _spin = lib.cpBodyGetAngle, lib.cpBodyGetAngularVelocity


def handle(body: pymunk.Body):
    """The body's C handle, for :func:`state` and the getters below (valid while the body lives)."""
    return body._body


def state(cb) -> tuple[float, float, float, float, float, float]:
    """(x, y, angle, vx, vy, omega) of the body with C handle ``cb``: its origin, its angle, its centre
    of gravity's velocity and its angular velocity."""
    p, v = _position(cb), _velocity(cb)
    return p.x, p.y, _angle(cb), v.x, v.y, _spin(cb)


def read(body: pymunk.Body) -> tuple[float, float, float, float, float, float]:
    """:func:`state` of a :class:`pymunk.Body`."""
    return state(body._body)


def pose(cb) -> tuple[float, float, float]:
    """(x, y, angle) of the body with C handle ``cb``."""
    p = _position(cb)
    return p.x, p.y, _angle(cb)


angle = _angle  # angle(cb): the body's angle
