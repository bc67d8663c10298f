"""Inelastic impacts of a hooked design at the frame's stops and the arm's stops.

The velocity along the stopped coordinate goes to zero with the hook holding (s held: the face takes
the impulse), if the handrail can take the impulse. At the end stop a pull that no face can hold
throws the robot off: the frame stays stopped and the robot flies on with the velocities it had (the
jolt release pymunk shows at 180 deg). With the hook out of the corner on one face the end stop is
:func:`end_stop_on_face`: the robot meets that face with the hook free to slide along it, and a hook
thrown off that the robot's own motion brings back within contact_hold bounces (:func:`hook_meets`).
The rest stop never throws the hook (the robot hangs below it). At the arm's stops a pull lifts the
hook off the handrail; it is a detach only if the hook stays off for the runner's contact_hold (else
the load sets it back in the notch: a bounce).
"""

from __future__ import annotations

import math

from .jit import kernel

from ... import units
from .constants import S_CORNER
from .flight import flight_rk4
from .hook_impulse import corner_stop, robot_at_hook
from .hooked_dynamics import (com_velocity_from_hook, distance, friction_cone, hook_from_com, hook_motion, hook_place,
                              stop_lets_go)
from .layout import P, X
from .transitions import end_slide, release_hook, start_slide

G = units.GRAVITY


@kernel
def arm_impact_lifts(p, x, tensile, jv, err, c1, s1, Hx, Hy):
    """For an arm impact whose held impulse would pull on the handrail: does the hook, free, leave the handrail
    for the runner's contact_hold? It leaves with the velocity the free robot's arm impact gives it (about the
    robot's centre of mass) and falls back under gravity and the handrail's centripetal motion.
    Returns (lifts, phi_a, phi_t, w_a, w_t): the free robot's state after the impact."""
    pa, pt = x[X.pa], x[X.pt]
    a, b, cc = p[P.Ka], p[P.Kat] * math.cos(pa - pt), p[P.Kt]
    w = 1.0 / (a + 2.0 * b + cc)
    xa, xt = (cc + b) * w, -(a + b) * w
    dwa, dwt = -xa * jv, -xt * jv
    dvx = (p[P.Pa] * math.sin(pa) * dwa + p[P.Pt] * math.sin(pt) * dwt) / p[P.m]
    dvy = -(p[P.Pa] * math.cos(pa) * dwa + p[P.Pt] * math.cos(pt) * dwt) / p[P.m]
    # the way out of the notch: its bisector (in the corner), the face's normal (on a face)
    if x[X.s] <= S_CORNER:
        nlx, nly = math.cos(p[P.beta]), math.sin(p[P.beta])
    else:
        nlx, nly = x[X.nx], x[X.ny]
    nx, ny = c1 * nlx - s1 * nly, s1 * nlx + c1 * nly
    v_sep = dvx * nx + dvy * ny
    a_rel = -G * ny + (Hx * nx + Hy * ny) * x[X.w1] * x[X.w1]
    T = p[P.contact_hold]
    lifts = tensile and v_sep * T + 0.5 * a_rel * T * T > 0.0
    return lifts, pa - xa * err, pt - xt * err, x[X.wa] + dwa, x[X.wt] + dwt


@kernel
def impact(p, x, out, sw, t1, frame):
    """An inelastic impact at the frame's stops (frame=True) or the arm's, at t1."""
    th1, pa, pt, s = x[X.th1], x[X.pa], x[X.pt], x[X.s]
    w1, wa, wt = x[X.w1], x[X.wa], x[X.wt]
    c1, s1 = math.cos(th1), math.sin(th1)
    ca, sa = math.cos(pa), math.sin(pa)
    ct, st = math.cos(pt), math.sin(pt)
    m, Pa, Pt = p[P.m], p[P.Pa], p[P.Pt]
    px, py = hook_place(p, x, s)[:2]
    A = p[P.If] + m * (px * px + py * py)
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    D, E = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
    F = p[P.Pat] * (ca * ct + sa * st)
    B, C = p[P.Ja], p[P.Jt]
    c00, c01, c02 = B * C - F * F, E * F - D * C, D * F - E * B
    c11, c12, c22 = A * C - E * E, D * E - A * F, A * B - D * D
    u0, u1, u2 = c00, c01, c02  # M^-1·e0 (times det)
    v0, v1, v2 = c01 - c02, c11 - c12, c12 - c22  # M^-1·(0, 1, -1) (times det)
    # The other coordinate's stop is one-sided too: the impulse is first taken with it free, and only where that
    # would drive it into its stop is it held there (a frame on its rest stop that the arm's impact throws
    # forward leaves the stop, as pymunk's frame does)
    if frame:
        lim = p[P.stop] if th1 >= p[P.stop] else p[P.rest]
        err, jv = th1 - lim, w1
        j0, j1, j2 = u0, u1, u2  # the arm free
        other_rate, other_gain, other_lock, other_kind = wa - wt, (u1 - u2) / u0, X.lockA, X.lockAk
        upper = p[P.stop]
    else:
        alpha = pa - pt - math.pi
        lim = p[P.amax] if alpha >= p[P.amax] else p[P.amin]
        err, jv = alpha - lim, wa - wt
        j0, j1, j2 = v0, v1, v2  # the frame free
        other_rate, other_gain, other_lock, other_kind = w1, v0 / (v1 - v2), X.lock1, X.lock1k
        upper = p[P.amax]
    into = err * jv > 0.0  # moving further past the stop
    if frame and into and lim == upper and s > S_CORNER:
        end_stop_on_face(p, x, out, sw, t1)
        return
    if into and x[other_lock] > 0.0:
        after = other_rate - jv * other_gain  # the other coordinate's rate after the free impulse
        if (x[other_kind] == 2.0 and after > 0.0) or (x[other_kind] == 1.0 and after < 0.0):
            if frame:  # hold the arm: J = (0, 1, -1)
                k = (u1 - u2) / (v1 - v2)
                j0, j1, j2 = u0 - k * v0, u1 - k * v1, u2 - k * v2
            else:  # hold the frame
                k = v0 / u0
                j0, j1, j2 = v0 - k * u0, v1 - k * u1, v2 - k * u2
        else:  # the impulse takes it off its stop
            x[other_lock], x[other_kind] = 0.0, 0.0
    jx = j0 if frame else j1 - j2
    lam = -jv / jx if into else 0.0
    dq0, dq1, dq2 = j0 * lam, j1 * lam, j2 * lam
    Px = -m * Hy * dq0 - Pa * sa * dq1 - Pt * st * dq2
    Py = m * Hx * dq0 + Pa * ca * dq1 + Pt * ct * dq2
    # a hook that has slid less than the hook/card clearance from the corner still has the other face under it:
    # the impulse meets the corner's two faces, and a hold sets it back in the corner
    near = s < p[P.clear]
    release, slide, face, sig = friction_cone(p, 0.0 if near else s, x[X.face], Px, Py, c1, s1, p[P.phi_s])
    if frame:
        at_rest = lim == p[P.rest]
        go = into and release and not at_rest
        free = False
    else:
        at_rest = True
        free, fpa, fpt, fwa, fwt = arm_impact_lifts(p, x, into and release, jv, err, c1, s1, Hx, Hy)
        go = free
    kind = 2.0 if lim == upper else 1.0
    if free:  # the arm stops about the robot's own centre: the robot's momentum is unchanged
        x[X.pa], x[X.pt], x[X.wa], x[X.wt] = fpa, fpt, fwa, fwt
        x[X.lockA], x[X.lockAk] = 1.0, kind
    if go:
        release_hook(p, x, out, sw, t1, t1)
        return
    was_sliding = x[X.slide] > 0.0
    to_corner = near and s > 0.0 and not (into and slide)
    if to_corner:  # (its slide's motion stops in the corner after the impact: corner_stop below)
        x[X.s], x[X.slide], x[X.mu_sig], x[X.tq0], x[X.cap] = 0.0, 0.0, 0.0, 0.0, 0.0
    corr = -err / jx
    x[X.th1] = th1 + j0 * corr
    x[X.pa], x[X.pt] = pa + j1 * corr, pt + j2 * corr
    x[X.w1], x[X.wa], x[X.wt] = w1 + dq0, wa + dq1, wt + dq2
    if frame:
        x[X.lock1], x[X.lock1k] = 1.0, kind
        x[X.th1] = lim
    else:
        x[X.lockA], x[X.lockAk] = 1.0, kind
    if to_corner and x[X.ws] != 0.0:
        corner_stop(p, x)
    # an impulse outside the static cone but pressing on a face starts (or continues) a slide along it
    if into and slide and not was_sliding and not at_rest:
        start_slide(p, x, face, sig)


@kernel
def end_stop_on_face(p, x, out, sw, t1):
    """The frame reaches its end stop with the hook on one card face, off the corner: the stop ends the frame's
    turn, and the robot, its hook moving on with the frame's motion, meets the face it is on (hook_impulse): the
    face's impulse is inelastic along its normal, and the hook sticks or slides on along the card as the friction
    cone allows. A hook moving off the face flies on with the velocities it had (the jolt release) if it stays off
    for the runner's contact_hold (:func:`hook_meets`); one that the robot's own motion brings back sooner
    bounces, and the runner sees no detach: it slides on along the face (the pymunk world's hook, out on the back
    card at the stop, lifts 0.2 mm and is back in 6 ms)."""
    pa, pt, wa, wt = x[X.pa], x[X.pt], x[X.wa], x[X.wt]
    vx, vy = hook_motion(p, x)[2:]  # the hook's velocity: the frame's point's (it stops) and its slide along the face
    # where it meets the face: the hook and the face at the stop
    lim = p[P.stop]
    px, py, lux, luy, lnx, lny = hook_place(p, x, x[X.s])[:6]
    c1, s1 = math.cos(lim), math.sin(lim)
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    ux, uy, nx, ny = c1 * lux - s1 * luy, s1 * lux + c1 * luy, c1 * lnx - s1 * lny, s1 * lnx + c1 * lny
    bounce = vx * nx + vy * ny >= 0.0  # moving off the face
    meets = BACK_ON
    if bounce:
        # the notch's other face, inside the notch: its inward normal and the hook's distance from it
        onx, ony = (p[P.nbx], p[P.nby]) if x[X.face] > 0.5 else (p[P.nfx], p[P.nfy])
        gap_o = (px - p[P.p0x]) * onx + (py - p[P.p0y]) * ony if x[X.cap] == 0.0 else -1.0
        meets = hook_meets(p, x, pa, pt, wa, wt, vx, vy, Hx, Hy, nx, ny, c1 * onx - s1 * ony, s1 * onx + c1 * ony, gap_o)
    if meets == OFF:  # off for contact_hold: it flies on
        release_hook(p, x, out, sw, t1, t1)
        return
    Px, Py, sliding, sig, _, arm_held, wa2, wt2 = robot_at_hook(p, x, pa, pt, wa, wt, vx, vy, ux, uy, nx, ny,
                                                              Hx, Hy, True, False, bounce)
    if not bounce and Px * nx + Py * ny <= 0.0:  # friction stopped it with a pull no face gives
        release_hook(p, x, out, sw, t1, t1)
        return
    m = p[P.m]
    dvx0, dvy0 = com_velocity_from_hook(p, pa, pt, wa, wt)
    dvx1, dvy1 = com_velocity_from_hook(p, pa, pt, wa2, wt2)
    # the hook's velocity after: the centre of mass' (its impulse) less the robot's turn about it
    hvx, hvy = vx + dvx0 + Px / m - dvx1, vy + dvy0 + Py / m - dvy1
    x[X.th1], x[X.w1], x[X.wa], x[X.wt] = lim, 0.0, wa2, wt2
    x[X.lock1], x[X.lock1k] = 1.0, 2.0
    if x[X.lockA] > 0.0 and not arm_held:  # lifted off its stop
        x[X.lockA], x[X.lockAk] = 0.0, 0.0
    if sliding:
        x[X.ws] = hvx * ux + hvy * uy
        x[X.sig], x[X.slide], x[X.mu_sig] = sig, 1.0, p[P.mu_k] * sig
    else:
        end_slide(x)
        x[X.sig] = 1.0
    if meets == OTHER_FACE:  # it crosses to the other face, a few ms: set in the corner (as into_corner does)
        x[X.s], x[X.cap] = 0.0, 0.0
        corner_stop(p, x)


BOUNCE_STEPS = 5  # the free robot's motion over contact_hold in this many RK4 steps (its return is read at each)
OFF, BACK_ON, OTHER_FACE = 0, 1, 2  # what a hook moving off a still face meets within contact_hold


@kernel
def hook_meets(p, x, pa, pt, wa, wt, vx, vy, Hx, Hy, nx, ny, onx, ony, gap_o):
    """A hook at H = (Hx, Hy) from its frame's axis (world), moving with velocity (vx, vy) off the still face it is
    on (the face's inward normal (nx, ny); on the card's rounded end, the normal there): does it meet a face within
    the runner's contact_hold? Its own (BACK_ON), the notch's other face, whose inward normal is (onx, ony) and
    which is gap_o away (OTHER_FACE; gap_o < 0: none), or none (OFF). The robot flies free meanwhile (flight_rk4:
    the leaf spring turns the arm about the centre of mass, which is ballistic; the arm's stop lets go as in
    flight, and the arm's stops are not met in so short a time)."""
    h = p[P.contact_hold] / BOUNCE_STEPS
    cvx, cvy = com_velocity_from_hook(p, pa, pt, wa, wt)
    cvx, cvy = cvx + vx, cvy + vy
    hx0, hy0 = hook_from_com(p, pa, pt)
    rx, ry = p[P.clear] * nx, p[P.clear] * ny  # the rounded end's centre, from the hook
    held = x[X.lockA] > 0.0
    for i in range(1, BOUNCE_STEPS + 1):
        pa, pt, wa, wt, lam = flight_rk4(p, held, pa, pt, wa, wt, h)
        held = held and not stop_lets_go(x[X.lockAk], lam, p[P.af])  # the spring lifts the arm off its stop
        t = i * h
        hx, hy = hook_from_com(p, pa, pt)
        qx, qy = Hx + cvx * t + hx - hx0, Hy + cvy * t - 0.5 * G * t * t + hy - hy0  # the hook, world
        dx, dy = qx - Hx, qy - Hy  # its move
        if x[X.cap] > 0.0:
            gap = distance(rx + dx, ry + dy) - p[P.clear]
        else:
            gap = dx * nx + dy * ny
        if gap <= 0.0:
            return BACK_ON
        if gap_o >= 0.0 and gap_o + dx * onx + dy * ony <= 0.0:
            return OTHER_FACE
    return OFF
