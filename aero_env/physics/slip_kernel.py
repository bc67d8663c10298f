"""The friction switch's per-step test, compiled: does the hook's tip slide over a face it touches?

:class:`~.hook_contact.StaticKineticFriction` asks this before every runner step the hook touches a
handrail, about 9 in 10 of a run's steps. As Python it cost 2.2 us a step, 0.6x of pymunk's own step,
the largest part of the runner's layer (``aero-env bench overhead``). Compiled by numba it reads the two
bodies' states from views of their C structs (:func:`.body_state.memory`, with the getters' arithmetic)
and costs one call.

The arithmetic is the Python switch's, operation for operation, so the answer is the same bit for bit
(``tests/test_physics_layer.py`` checks the slip against pymunk's own point calls at every step of two
swings). Two things make that hold: no ``fastmath`` (the compiler may not reorder or contract), and
:func:`python_hypot`, CPython 3.11's ``math.hypot`` for two arguments: numba's ``math.hypot`` calls the C
library's, which differs from CPython's in the last bit on about 1 pair in 500. ``cos`` and ``sin`` are
the C library's in both. (The port agrees with ``math.hypot`` wherever the larger argument is a normal
double; with both arguments subnormal, below 2.2e-308, it differs in the last bit on about 1 pair in
500, for a reason not found. No distance here, in mm, comes near that.)

Cached on disk like the reduced model's kernels (:mod:`aero_env.jit_cache`): a fresh cache compiles in
about a second, a warm one loads in a few milliseconds. With ``NUMBA_DISABLE_JIT=1`` the same code runs
as plain Python.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..jit_cache import cache_dir, caching_in
from . import body_state
from .body_state import memory_state

_T27 = 134217729.0  # 2**27 + 1: Veltkamp's splitter for a double's 53-bit significand
_DBL_MIN = 2.2250738585072014e-308


def python_hypot(a, b):
    """``math.hypot(a, b)`` as CPython 3.11 computes it (Modules/mathmodule.c, ``vector_norm``): the sum of
    squares kept exact in pieces (Veltkamp's split, compensated sums), its square root, and one differential
    correction; a subnormal largest value is scaled up first, as CPython does. Bit for bit with
    ``math.hypot`` over the normal range (see the module's docstring for subnormal arguments)."""
    a, b = abs(a), abs(b)
    if math.isinf(a) or math.isinf(b):
        return math.inf
    if math.isnan(a) or math.isnan(b):
        return math.nan
    top = a if a > b else b
    if top == 0.0:
        return top
    _, e = math.frexp(top)
    unscale = 1.0
    if e < -1023:
        a, b, unscale = a / _DBL_MIN, b / _DBL_MIN, _DBL_MIN
        _, e = math.frexp(top / _DBL_MIN)
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2, frac3 = 1.0, 0.0, 0.0, 0.0
    for x in (a, b):
        x *= scale
        t = x * _T27
        hi = t - (t - x)
        lo = x - hi
        x = hi * hi
        old = csum
        csum += x
        frac1 += (old - csum) + x
        x = 2.0 * hi * lo
        old = csum
        csum += x
        frac2 += (old - csum) + x
        frac3 += lo * lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2 + frac3))
    t = h * _T27
    hi = t - (t - h)
    lo = h - hi
    x = -hi * hi
    old = csum
    csum += x
    frac1 += (old - csum) + x
    x = -2.0 * hi * lo
    old = csum
    csum += x
    frac2 += (old - csum) + x
    x = -lo * lo
    old = csum
    csum += x
    frac3 += (old - csum) + x
    x = csum - 1.0 + (frac1 + frac2 + frac3)
    return unscale * ((h + x / (2.0 * h)) / scale)


def nearest_on_face(face, lx, ly):
    """The point of ``face``'s centre line nearest (lx, ly), frame-local: min(max(along, 0), length) written as
    the comparisons Python's min and max make, ties and NaN alike."""
    x0, y0, ux, uy, length = face[0], face[1], face[2], face[3], face[4]
    along = (lx - x0) * ux + (ly - y0) * uy
    if 0.0 > along:
        along = 0.0
    if length < along:
        along = length
    return x0 + along * ux, y0 + along * uy


def face_slides(face, lx, ly, gap, qx, qy, fc, fs, fx, fy, rail_radius, arm_gx, arm_gy, frame_gx, frame_gy,
                avx, avy, aw, fvx, fvy, fw, threshold):
    """Whether the tip, its centre at (lx, ly) in the frame and ``gap`` from the face's nearest point (qx, qy),
    slides along ``face`` faster than ``threshold``: its contact point's velocity relative to the card's."""
    ux, uy = face[2], face[3]
    # the contact point on the card's surface, between the face line and the tip's centre, then in the world
    f = rail_radius / gap if gap > 0.0 else 0.0
    px, py = qx + (lx - qx) * f, qy + (ly - qy) * f
    px, py = fc * px - fs * py + fx, fs * px + fc * py + fy
    tx, ty = ux * fc - uy * fs, ux * fs + uy * fc  # the face's direction in the world
    rax, ray, rfx, rfy = px - arm_gx, py - arm_gy, px - frame_gx, py - frame_gy
    return abs(((avx - ray * aw) - (fvx - rfy * fw)) * tx + ((avy + rax * aw) - (fvy + rfx * fw)) * ty) > threshold


def tip_slides(arm, frame, arm_data, frame_data, threshold):
    """The switch's test (:meth:`~.hook_contact.StaticKineticFriction.slides`).

    ``arm``, ``frame``: the two bodies' struct views; ``arm_data``: the tip's centre and the arm's centre of
    gravity, arm-local (x, y, x, y); ``frame_data``: row 0 the frame's centre of gravity, the card's
    half-thickness and the reach within which a face line touches the tip's centre (x, y, r, reach, -), then
    one row per handrail face (start x, y, unit direction x, y, length), frame-local. The first face found
    sliding decides; with no face within reach (the contact callbacks say the tip touches this frame) the
    nearest face is the one it touches."""
    # each body's state as cpBodyGetPosition, cpBodyGetAngle, cpBodyGetVelocity, cpBodyGetAngularVelocity give it
    ax, ay, arm_angle, avx, avy, aw = memory_state(arm)
    fx, fy, frame_angle, fvx, fvy, fw = memory_state(frame)
    ac, as_ = math.cos(arm_angle), math.sin(arm_angle)
    fc, fs = math.cos(frame_angle), math.sin(frame_angle)
    # the tip's centre in the world (arm.local_to_world), then in the frame (body.world_to_local)
    tlx, tly = arm_data[0], arm_data[1]
    cx, cy = ac * tlx - as_ * tly + ax, as_ * tlx + ac * tly + ay
    lx = fc * cx + fs * cy + (-(fs * fy) - fx * fc)
    ly = -(fs * cx) + fc * cy + (fx * fs - fc * fy)
    # the centres of gravity in the world, about which each body's point velocities turn
    agx, agy = arm_data[2], arm_data[3]
    arm_gx, arm_gy = ac * agx - as_ * agy + ax, as_ * agx + ac * agy + ay
    cgx, cgy, rail_radius, reach = frame_data[0, 0], frame_data[0, 1], frame_data[0, 2], frame_data[0, 3]
    frame_gx, frame_gy = fc * cgx - fs * cgy + fx, fs * cgx + fc * cgy + fy
    touched, nearest, nearest_gap = False, -1, 0.0
    for i in range(1, frame_data.shape[0]):
        face = frame_data[i]
        qx, qy = nearest_on_face(face, lx, ly)
        gap = python_hypot(lx - qx, ly - qy)
        if gap <= reach:
            touched = True
            if face_slides(face, lx, ly, gap, qx, qy, fc, fs, fx, fy, rail_radius, arm_gx, arm_gy, frame_gx,
                           frame_gy, avx, avy, aw, fvx, fvy, fw, threshold):
                return True
        elif nearest < 0 or gap < nearest_gap:
            nearest, nearest_gap = i, gap
    if touched:
        return False
    face = frame_data[nearest]
    qx, qy = nearest_on_face(face, lx, ly)
    return face_slides(face, lx, ly, python_hypot(lx - qx, ly - qy), qx, qy, fc, fs, fx, fy, rail_radius, arm_gx,
                       arm_gy, frame_gx, frame_gy, avx, avy, aw, fvx, fvy, fw, threshold)


def _compile() -> None:
    from numba import njit

    # as the reduced model's kernels (models/reduced/jit.py): no fastmath, no reference counting, and a division
    # by zero gives inf as numpy does (none happens: every division here is guarded). numba resolves the calls
    # between them when it compiles, by which time each name below is the compiled function.
    jit = njit(cache=True, error_model="numpy", _nrt=False)
    global memory_state, python_hypot, nearest_on_face, face_slides, tip_slides
    with caching_in(cache_dir(Path(__file__).parent, ("slip_kernel.py", "body_state.py"))):
        # body_state's struct read, compiled here for the kernels (body_state itself keeps the Python one)
        memory_state = jit(body_state.memory_state)
        python_hypot, nearest_on_face = jit(python_hypot), jit(nearest_on_face)
        face_slides, tip_slides = jit(face_slides), jit(tip_slides)


_compile()
