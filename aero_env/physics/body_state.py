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

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import ffi, lib

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


# -- the struct itself, for compiled code --
# cpBody's leading fields in pymunk 7.3.1's Chipmunk (Munk2D), as doubles from the struct's start: two function
# pointers, m, m_inv, i, i_inv, cog (2), p (2, the centre of gravity), v (2), f (2), a, w, t, then the transform
# (a, b, c, d, tx, ty). Compiled code (:mod:`.slip_kernel`) reads a body's state from a view of these words with
# the getters' own arithmetic: cpBodyGetPosition is cpTransformPoint(transform, cpvzero).
VX, VY, ANGLE, SPIN, TA, TB, TC, TD, TX, TY = 10, 11, 14, 15, 17, 18, 19, 20, 21, 22
WORDS = 23


def memory(body: pymunk.Body):
    """A float64 view of the body's C struct's first :data:`WORDS` words: each read of it is the live state.
    Valid while the body lives (the view holds the buffer, the world holds the body)."""
    return np.frombuffer(ffi.buffer(body._body, WORDS * 8), dtype=np.float64)


def address(body: pymunk.Body) -> int:
    """The address of the body's C struct, for compiled code that reads it (valid while the body lives)."""
    return int(ffi.cast("uintptr_t", body._body))


def memory_state(m) -> tuple[float, float, float, float, float, float]:
    """:func:`state` computed from a :func:`memory` view (or, in compiled code, a pointer to the struct's words) as
    the getters compute it. The compiled parts call it compiled (:mod:`.slip_kernel`), so this one function is
    the struct read everywhere."""
    return (m[TA] * 0.0 + m[TC] * 0.0 + m[TX], m[TB] * 0.0 + m[TD] * 0.0 + m[TY], m[ANGLE], m[VX], m[VY], m[SPIN])


def _layout_holds() -> bool:
    """Whether this pymunk's cpBody has the layout above: a probe body with a distinct value in every field the
    view reads gives the getters' values through it, bit for bit."""
    b = pymunk.Body(1.5, 2.5)
    b.center_of_gravity = (0.3, -0.7)
    b.position, b.angle = (1.2345678, -9.87654321), 2.123456789
    b.velocity, b.angular_velocity = (3.1415, -2.7182), -0.987654321
    return tuple(memory_state(memory(b))) == state(b._body)


MEMORY_LAYOUT_HOLDS = _layout_holds()
