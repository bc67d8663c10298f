"""The catch: the hook set on the next frame's seat, an inelastic impulse, then the hooked motion.

The hooked coordinates' generalised momenta are conserved through the impulse at the hook (the whole
system's angular momentum about the new frame's axis, the robot's about the hook, the torso's about
the axle); the frame starts at rest and stays on its rest stop if pushed into it. Setting the hook
on the seat never adds energy: where it lifts the robot (a hook that reached the seat's depth beside
it, that a face would have guided in) the lift's energy comes out of the motion.
"""

from __future__ import annotations

import math

from .jit import kernel

from ... import units
from .hooked_dynamics import com_velocity_from_hook, hook_from_com, hook_on_frame, solve_hooked, stick_eval, stick_step
from .layout import HOOKED, P, W, X
from .transitions import start_swing

G = units.GRAVITY


@kernel
def catch(p, x, sw, t_c, t1, gap):
    """The hook reached the seat of frame fi + 1 at t_c (x holds the robot's angles and rates then): the inelastic
    catch, then the hooked motion to t1. The catch is a traversal (on the last frame: the row complete) once the
    frame has carried the robot through its lowest point (transitions.carried)."""
    j = int(x[X.fi]) + 1
    t_m = x[X.t_mouth]
    x[X.fi] = j
    x[X.carried] = 0.0
    sw[W.t_catch, j] = t_m
    sw[W.catch_seat, j] = gap  # the model then sets the hook on the seat: 0 for the rest of the swing
    # the transfer goes on until the frame carries the robot: its miss distance is the hook's closest approach to
    # this seat, which the model sets the hook on (no nearer approach is measured after the catch)
    x[X.closest] = min(x[X.closest], gap)
    pa, pt, wa, wt = x[X.pa], x[X.pt], x[X.wa], x[X.wt]
    tau = t_c - x[X.t0f]
    vcx, vcy = x[X.vx0], x[X.vy0] - G * tau
    dvx, dvy = com_velocity_from_hook(p, pa, pt, wa, wt)
    vHx, vHy = vcx - dvx, vcy - dvy
    ca, sa = math.cos(pa), math.sin(pa)
    ct, st = math.cos(pt), math.sin(pt)
    cat = ca * ct + sa * st
    Hx, Hy = p[P.seatx], p[P.seaty]  # the hook on the seat, from the new frame's axis
    m, Pa, Pt, Pat, Ja, Jt = p[P.m], p[P.Pa], p[P.Pt], p[P.Pat], p[P.Ja], p[P.Jt]
    p0 = m * (Hx * vcy - Hy * vcx)
    p2 = Pa * (ca * vHy - sa * vHx) + Ja * wa + Pat * cat * wt
    p3 = Pt * (ct * vHy - st * vHx) + Pat * cat * wa + Jt * wt
    # the hooked mass matrix at the seat, the frame at rest
    c1, s1 = math.cos(p[P.rest]), math.sin(p[P.rest])
    px, py = p[P.p0x], p[P.p0y]
    Hwx, Hwy = c1 * px - s1 * py, s1 * px + c1 * py
    A = p[P.If] + m * (px * px + py * py)
    D, E = Pa * (Hwx * ca + Hwy * sa), Pt * (Hwx * ct + Hwy * st)
    F = Pat * cat
    arm_held = x[X.lockA] > 0.0
    q0, q1, q2 = solve_hooked(A, Ja, Jt, D, E, F, p0, p2, p3, False, arm_held)
    pushed_back = q0 < 0.0  # pushed into the rest stop: the frame stays there
    if pushed_back:
        q0, q1, q2 = solve_hooked(A, Ja, Jt, D, E, F, p0, p2, p3, True, arm_held)
    cy = x[X.cy0] + x[X.vy0] * tau - 0.5 * G * tau * tau
    hy_old = cy + hook_from_com(p, pa, pt)[1]
    lift = m * G * (j * p[P.rise] + p[P.seaty] - hy_old)
    kin = 0.5 * (A * q0 * q0 + Ja * q1 * q1 + Jt * q2 * q2) + D * q0 * q1 + E * q0 * q2 + F * q1 * q2
    scale = math.sqrt(min(max(1.0 - max(lift, 0.0) / max(kin, 1e-300), 0.0), 1.0))
    x[X.th1], x[X.s] = p[P.rest], 0.0
    x[X.w1], x[X.ws], x[X.wa], x[X.wt] = q0 * scale, 0.0, q1 * scale, q2 * scale
    x[X.ux], x[X.uy], x[X.nx], x[X.ny] = p[P.ubx], p[P.uby], p[P.nbx], p[P.nby]
    x[X.face], x[X.sig], x[X.slide], x[X.mu_sig] = 0.0, 1.0, 0.0, 0.0
    x[X.lock1] = x[X.lock1k] = 1.0 if pushed_back else 0.0
    x[X.piv], x[X.tq0] = 0.0, 0.0
    x[X.rec] = 0.0
    x[X.phase] = HOOKED
    # the rest of the step, hooked
    hpx, hpy, hA = hook_on_frame(p, x)
    a0, a1, a2 = stick_eval(p, x, hpx, hpy, hA, x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt])[:3]
    x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt] = stick_step(p, x, hpx, hpy, hA, t1 - t_c, a0, a1, a2)
    x[X.th1] = max(x[X.th1], p[P.rest])
    start_swing(p, x, t_m)
