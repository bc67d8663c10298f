"""The check's read of the world, compiled: every live body's state, the energy, the fastest body,
the robot's hook, centre of mass and alpha, and the health monitors (joint drift, limit overshoot,
the hook's penetration into a touched card).

:meth:`World.sample <aero_env.physics.world.World.sample>` runs on the check cadence (every 5 ms, and
every step of a catch): about a thousand times in the prototype's row. As Python it cost about 9 us,
0.4x of pymunk's own stepping over the run (``aero-env bench overhead``); compiled it is one call that
reads the bodies' C structs at their addresses (:func:`.body_state.address`, with the getters'
arithmetic) and writes one array.

The arithmetic is :meth:`World.sample_python <aero_env.physics.world.World.sample_python>`'s,
operation for operation, in the same order, with Python's ``max`` written out as the comparisons it
makes and CPython's ``hypot`` (:func:`.slip_kernel.python_hypot`), so the two agree bit for bit
(``tests/test_physics_layer.py`` compares them at every step of several runs). ``sample_python`` stays
the reference, and the path for a world the kernel does not cover (the pinned-hook scene, another
pymunk's struct layout).
"""

from __future__ import annotations

import math
from pathlib import Path

from ..jit_cache import cache_dir, caching_in
from .body_state import WORDS
from .slip_kernel import memory_state, python_hypot

# consts: what the kernel needs besides the bodies, engine units
GRAVITY, PARKED_ENERGY, ARM_LENGTH, TORSO_COM, M_TORSO, M_ARM, ALPHA_MAX, ALPHA_MIN, HOOK_RADIUS, ARM_COM = range(10)
N_CONSTS = 10
# frame_table columns, one row per frame of the row
AXIS_X, AXIS_Y, STOP_ANGLE, REST_ANGLE, RAIL_RADIUS = range(5)
# out: the sample in engine units, then each live frame's state (x, y, angle, vx, vy, omega) in window order
ENERGY, V2MAX, THETA2, HOOK_X, HOOK_Y, DRIFT, OVERSHOOT, PENETRATION, ALPHA = range(9)
FRAME_STATES = 9


def words_at(address):
    """The float64 words of the C struct at ``address`` (plain Python: with ``NUMBA_DISABLE_JIT=1``)."""
    import numpy as np
    from pymunk._chipmunk_cffi import ffi

    return np.frombuffer(ffi.buffer(ffi.cast("double *", int(address)), WORDS * 8), dtype=np.float64)


def body_energy(props, b, g, y, a, vx, vy, w):
    """Body ``b``'s kinetic and potential energy (``World._energy_of``'s operations) and its speed squared."""
    mass, moment, cgx, cgy = props[b, 0], props[b, 1], props[b, 2], props[b, 3]
    v2 = vx * vx + vy * vy
    return 0.5 * (mass * v2 + moment * w * w) + mass * g * (y + cgx * math.sin(a) + cgy * math.cos(a)), v2


def read_world(addresses, props, live, touch, frame_table, faces, consts, out):
    """Fill ``out`` with the sample of the world whose bodies' structs are at ``addresses``.

    ``addresses``, ``props`` (mass, moment, centre of gravity x, y): one row per frame of the row, then the
    torso and the arm; ``live``: the live frames' indices, in window order; ``touch``: faces of each frame the
    hook touches (the contact's callbacks keep it); ``frame_table``: each frame's axis, stop, rest angle and
    card half-thickness; ``faces``: the handrail faces, frame-local, one set per frame; ``consts``: see the
    names above."""
    g = consts[GRAVITY]
    e, v2max, drift, over = consts[PARKED_ENERGY], 0.0, 0.0, 0.0
    n_frames = frame_table.shape[0]
    base = FRAME_STATES
    for k in range(live.shape[0]):  # the frames: state, health, energy
        i = live[k]
        x, y, a, vx, vy, w = memory_state(words_at(addresses[i]))
        out[base], out[base + 1], out[base + 2], out[base + 3], out[base + 4], out[base + 5] = x, y, a, vx, vy, w
        base += 6
        d = python_hypot(x - frame_table[i, AXIS_X], y - frame_table[i, AXIS_Y])
        o = 0.0
        if a - frame_table[i, STOP_ANGLE] > o:
            o = a - frame_table[i, STOP_ANGLE]
        if frame_table[i, REST_ANGLE] - a > o:
            o = frame_table[i, REST_ANGLE] - a
        if d > drift:
            drift = d
        if o > over:
            over = o
        de, v2 = body_energy(props, i, g, y, a, vx, vy, w)
        e += de
        if v2 > v2max:
            v2max = v2
    # the robot: torso, then arm
    tx, ty, ta, tvx, tvy, tw = memory_state(words_at(addresses[n_frames]))
    ax, ay, aa, avx, avy, aw = memory_state(words_at(addresses[n_frames + 1]))
    for b, y, a, vx, vy, w in ((n_frames, ty, ta, tvx, tvy, tw), (n_frames + 1, ay, aa, avx, avy, aw)):
        de, v2 = body_energy(props, b, g, y, a, vx, vy, w)
        e += de
        if v2 > v2max:
            v2max = v2
    # Robot.measure: the hook, the centre of mass, alpha, the axle's drift and the arm's overshoot
    length, torso_com, mt, ma = consts[ARM_LENGTH], consts[TORSO_COM], consts[M_TORSO], consts[M_ARM]
    arm_com = consts[ARM_COM]
    ca, sa = math.cos(aa), math.sin(aa)
    hx, hy = ax + length * ca, ay + length * sa
    cx = (mt * (tx + torso_com * math.sin(ta)) + ma * (ax + arm_com * ca)) / (mt + ma)
    cy = (mt * (ty - torso_com * math.cos(ta)) + ma * (ay + arm_com * sa)) / (mt + ma)
    alpha = aa - ta + math.pi / 2
    axle = python_hypot(tx - ax, ty - ay)
    arm_over = 0.0
    if alpha - consts[ALPHA_MAX] > arm_over:
        arm_over = alpha - consts[ALPHA_MAX]
    if consts[ALPHA_MIN] - alpha > arm_over:
        arm_over = consts[ALPHA_MIN] - alpha
    if axle > drift:
        drift = axle
    if 0.0 > drift:  # the hook contact's joint drift: a contact, not a joint
        drift = 0.0
    if arm_over > over:
        over = arm_over
    # the hook's penetration into each touched live frame's card (SwingFrame.penetration), the deepest
    pen, first = 0.0, True
    radius = consts[HOOK_RADIUS]
    for k in range(live.shape[0]):
        i = live[k]
        if touch[i] <= 0:
            continue
        base = FRAME_STATES + 6 * k
        x, y, a = out[base], out[base + 1], out[base + 2]
        c, s = math.cos(a), math.sin(a)
        dx, dy = hx - x, hy - y
        px, py = c * dx + s * dy, -s * dx + c * dy  # the hook in frame-local coordinates
        depth = 0.0
        for f in range(faces.shape[1]):
            fx, fy, ux, uy, flen = faces[i, f, 0], faces[i, f, 1], faces[i, f, 2], faces[i, f, 3], faces[i, f, 4]
            along = (px - fx) * ux + (py - fy) * uy
            if 0.0 > along:
                along = 0.0
            if flen < along:
                along = flen
            v = radius + frame_table[i, RAIL_RADIUS] - python_hypot(px - fx - along * ux, py - fy - along * uy)
            if v > depth:
                depth = v
        if first or depth > pen:
            pen, first = depth, False
    out[ENERGY], out[V2MAX], out[THETA2] = e, v2max, math.atan2(hy - cy, hx - cx)
    out[HOOK_X], out[HOOK_Y], out[DRIFT], out[OVERSHOOT], out[PENETRATION], out[ALPHA] = hx, hy, drift, over, pen, alpha


def _compile() -> None:
    import numba
    from numba import njit, types
    from numba.extending import intrinsic

    global words_at, body_energy, read_world
    if numba.config.DISABLE_JIT:
        return

    @intrinsic
    def _words_at(typingctx, address):
        # the struct's address as a pointer to its doubles: m[k] reads word k
        sig = types.CPointer(types.float64)(types.int64)

        def codegen(context, builder, signature, args):
            return builder.inttoptr(args[0], context.get_value_type(types.CPointer(types.float64)))

        return sig, codegen

    # as slip_kernel's: no fastmath, no reference counting, numpy's division
    with caching_in(cache_dir(Path(__file__).parent, ("check_kernel.py", "slip_kernel.py", "body_state.py"))):
        jit = njit(cache=True, error_model="numpy", _nrt=False)
        words_at, body_energy, read_world = _words_at, jit(body_energy), jit(read_world)


_compile()
