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
from .hook_impulse import corner_stop, robot_at_hook
from .hooked_dynamics import (com_velocity_from_hook, first_crossing, hook_from_com, hook_on_frame, slide_eval,
                              slide_step, solve_hooked, stick_eval, stick_step)
from .layout import HOOKED, P, W, X
from .notch import card_at_rest
from .transitions import set_face, start_swing

G = units.GRAVITY


@kernel
def rest_of_step_hooked(p, x, dt):
    """The hooked motion over the rest of the step a catch or a landing fell in (dt), from the state it set;
    the frame no lower than its rest stop. A slide that reaches the corner within it stops there (the corner's
    impact, :func:`.hook_impulse.corner_stop`) and sticks for what is left of the step."""
    if x[X.slide] > 0.0:
        y = (x[X.th1], x[X.s], x[X.pa], x[X.pt], x[X.w1], x[X.ws], x[X.wa], x[X.wt])
        a0, a1, a2, a3 = slide_eval(p, x, *y)[:4]
        h = first_crossing(-x[X.s], x[X.ws], a1) if x[X.s] > 0.0 else math.inf
        if h >= dt:
            (x[X.th1], x[X.s], x[X.pa], x[X.pt],
             x[X.w1], x[X.ws], x[X.wa], x[X.wt]) = slide_step(p, x, dt, a0, a1, a2, a3)
            x[X.s] = max(x[X.s], 0.0)
            x[X.th1] = max(x[X.th1], p[P.rest])
            return
        (x[X.th1], x[X.s], x[X.pa], x[X.pt],
         x[X.w1], x[X.ws], x[X.wa], x[X.wt]) = slide_step(p, x, h, a0, a1, a2, a3)
        x[X.s], x[X.cap] = 0.0, 0.0
        corner_stop(p, x)
        dt -= h
    hpx, hpy, hA = hook_on_frame(p, x)
    a0, a1, a2 = stick_eval(p, x, hpx, hpy, hA, x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt])[:3]
    x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt] = stick_step(p, x, hpx, hpy, hA, dt, a0, a1, a2)
    x[X.th1] = max(x[X.th1], p[P.rest])


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
    set_face(p, x, 0.0)
    x[X.sig], x[X.slide], x[X.mu_sig] = 1.0, 0.0, 0.0
    x[X.lock1] = x[X.lock1k] = 1.0 if pushed_back else 0.0
    x[X.piv], x[X.tq0] = 0.0, 0.0
    x[X.rec] = 0.0
    x[X.phase] = HOOKED
    rest_of_step_hooked(p, x, t1 - t_c)
    start_swing(p, x, t_m)


@kernel
def land(p, x, sw, t_c, t1, face, s0):
    """The hook met face ``face`` (0 back, 1 front) of frame fi + 1's notch at ``s0`` from its seat at t_c (x holds
    the robot's angles and rates then): a touch, not yet a catch. The impact is inelastic along the face's normal;
    along it the card's friction stops the hook if the impulse that does so lies in the static cone (mu_s), else
    the hook slides on with kinetic friction (mu_k) in the sense it was moving. The frame starts at rest and stays
    on its rest stop if pushed into it. Then the hooked motion to t1, the hook on the face at s0: sliding into the
    corner, it seats (``hooked_phase.swing_checks`` makes the touch a catch as the runner does: held
    ``sim.contact_hold``, within ``sim.catch_seat`` of the seat); leaving the face, it grazes
    (``transitions.graze_off``)."""
    j = int(x[X.fi]) + 1
    x[X.fi] = j
    x[X.carried] = 0.0
    sw[W.t_catch, j] = t_c  # the first touch, as the runner records a catch
    x[X.closest] = min(x[X.closest], s0)
    m = p[P.m]
    pa, pt, wa, wt = x[X.pa], x[X.pt], x[X.wa], x[X.wt]
    tau = t_c - x[X.t0f]
    vcx, vcy = x[X.vx0], x[X.vy0] - G * tau
    # the hook's motion from the robot's: d(hook)/d(phi_a) and d(hook)/d(phi_t) (hook_from_com's derivatives)
    gax, gay = p[P.Pa] * math.sin(pa) / m, -p[P.Pa] * math.cos(pa) / m
    gtx, gty = p[P.Pt] * math.sin(pt) / m, -p[P.Pt] * math.cos(pt) / m
    kc = p[P.Kat] * math.cos(pa - pt)
    on_stop = x[X.lockA] > 0.0
    if on_stop:  # on its stop the robot turns as one body (the state inside the step may still hold the stop's impact)
        wa = wt = ((p[P.Ka] + kc) * wa + (kc + p[P.Kt]) * wt) / (p[P.Ka] + 2.0 * kc + p[P.Kt])
    vx, vy = vcx + gax * wa + gtx * wt, vcy + gay * wa + gty * wt
    # where on the card: the face's direction and inward normal there, and the hook's centre from the frame's axis
    ux, uy, nx, ny, s_end = card_at_rest(p, face)[:5]
    on_end = s0 > s_end
    if on_end:  # on the card's rounded end: its normal there turned psi from the face's toward the face's direction
        r, psi = p[P.clear], (s0 - s_end) / p[P.clear]
        c, sn = math.cos(psi), math.sin(psi)
        ex, ey = p[P.seatx] + s_end * ux - r * nx, p[P.seaty] + s_end * uy - r * ny  # the card's end
        ux, uy, nx, ny = c * ux - sn * nx, c * uy - sn * ny, sn * ux + c * nx, sn * uy + c * ny
        Hx, Hy = ex + r * nx, ey + r * ny
    else:
        Hx, Hy = p[P.seatx] + s0 * ux, p[P.seaty] + s0 * uy
    th, w0 = p[P.rest], 0.0
    if x[X.nmov] > 0.0:  # a frame a graze kicked: where it has turned to, and its rate
        th, w0 = x[X.nth], x[X.nw]
        cd, sd = math.cos(th - p[P.rest]), math.sin(th - p[P.rest])
        ux, uy, nx, ny = cd * ux - sd * uy, sd * ux + cd * uy, cd * nx - sd * ny, sd * nx + cd * ny
        Hx, Hy = cd * Hx - sd * Hy, sd * Hx + cd * Hy
    x[X.nmov] = 0.0
    vx, vy = vx + w0 * Hy, vy - w0 * Hx  # relative to the frame's point there
    # The impact with the frame and the arm free; a stop whose body the impulse would turn into it (the frame at
    # rest on its rest stop, the arm on its stop) holds, and the impact is taken again with that body held: the
    # stops push, never pull, so the landing may lift the arm off its stop as it does in the pymunk world.
    at_rest = th <= p[P.rest] and w0 <= 0.0
    Px, Py, sliding, sig, frame_held, arm_held, wa, wt = robot_at_hook(p, x, pa, pt, wa, wt, vx, vy, ux, uy, nx, ny,
                                                                      Hx, Hy, False, at_rest, False)
    # the rates after the impulse
    vcx, vcy = vcx + Px / m, vcy + Py / m
    w1 = 0.0 if frame_held else w0 - (Hx * Py - Hy * Px) * (1.0 / p[P.If])
    vx, vy = vcx + gax * wa + gtx * wt, vcy + gay * wa + gty * wt
    ws = ((vx + w1 * Hy) * ux + (vy - w1 * Hx) * uy) if sliding else 0.0
    if on_stop and not arm_held:  # lifted off its stop
        x[X.lockA], x[X.lockAk] = 0.0, 0.0
    # the hooked state: the hook on the face at s0
    x[X.th1], x[X.s], x[X.w1], x[X.ws], x[X.wa], x[X.wt] = th, s0, w1, ws, wa, wt
    set_face(p, x, float(face))
    x[X.cap] = 1.0 if on_end else 0.0
    x[X.sig] = sig if sliding else 1.0
    x[X.slide] = 1.0 if sliding else 0.0
    x[X.mu_sig] = p[P.mu_k] * sig if sliding else 0.0
    x[X.lock1] = x[X.lock1k] = 1.0 if frame_held else 0.0
    x[X.piv], x[X.tq0] = 0.0, 0.0
    x[X.rec] = 0.0
    x[X.touch], x[X.t_touch], x[X.touch_gap] = 1.0, t_c, s0
    x[X.phase] = HOOKED
    rest_of_step_hooked(p, x, t1 - t_c)
    start_swing(p, x, t_c)  # (its stall test reads the frame's energy, its motion included)
