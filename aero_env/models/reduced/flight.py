"""The flight between frames: a ballistic centre of mass, the arm snapping about it, and the landing test.

The centre of mass is ballistic (closed form); arm and torso turn about it with the robot's angular
momentum conserved and the leaf spring snapping the arm toward alpha_min (kinetic energy
Ka·wa²/2 + Kt·wt²/2 + Kat·cos(phi_a - phi_t)·wa·wt; inelastic arm stops; a step in which the arm reaches
its stop is split there). The landing is found geometrically (:mod:`.notch`): inside the next notch's
mouth (the hook's centre crossed it downward with the arm snapped forward) the hook meets a card's flat
side or rounded end, outside it a card's end; :func:`.catch.land` takes the impact there and the hooked
motion decides between a catch and a graze (or it reaches the seat's depth beside the corner: caught at
once, :func:`.catch.catch`). A frame that a grazing touch set swinging keeps swinging alone
(``free_frame_step``) and the hook is read in its coordinates. A transfer that is not caught ends as the
runner ends it (the centre of mass at the floor, the flight timeout, or decided: the hook fallen below the
next mouth) and is named as the runner's ``_classify_miss`` names it.
"""

from __future__ import annotations

import math

from .jit import kernel

from ... import units
from .catch import catch, land
from .constants import NOTCH_EXIT_MARGIN
from .hooked_dynamics import (axle_friction, distance, first_crossing, hook_from_com, skewer_friction, spring_energy,
                              spring_torque, stop_lets_go)
from .layout import (FLIGHT, R_AHEAD, R_BEHIND, R_GRAZE, R_LOW, R_NEVER_DOWN, R_STIFF, R_WEAK, P, X)
from .notch import CAUGHT, GRAZED, LANDED, NO_CATCH, end_reached, seat_reached
from .transitions import finish, parked_energy, track_energy

G = units.GRAVITY


@kernel
def flight_accel(p, arm_held, pa, pt, wa, wt):
    """Accelerations of (phi_a, phi_t) in flight, and the arm stop's load (generalised force on alpha)."""
    c, s = math.cos(pa - pt), math.sin(pa - pt)
    tau = spring_torque(p, pa - pt - p[P.alim], wa - wt)
    Ka, Kt = p[P.Ka], p[P.Kt]
    kc, ks = p[P.Kat] * c, p[P.Kat] * s
    ta = axle_friction(p, wa - wt)
    b0 = -ks * wt * wt - tau + ta
    b1 = ks * wa * wa + tau - ta
    if arm_held:  # the arm against a stop: the robot turns rigidly
        x0 = x1 = (b0 + b1) / (Ka + 2.0 * kc + Kt)
    else:
        inv = 1.0 / (Ka * Kt - kc * kc)
        x0, x1 = (Kt * b0 - kc * b1) * inv, (Ka * b1 - kc * b0) * inv
    return x0, x1, b1 - kc * x0 - Kt * x1


@kernel
def flight_rk4(p, arm_held, pa, pt, wa, wt, dt):
    """One RK4 step of the arm and torso about the centre of mass; the stop's load at the step's start."""
    h = 0.5 * dt
    a0, a1, lam = flight_accel(p, arm_held, pa, pt, wa, wt)
    u0, u1 = wa + h * a0, wt + h * a1
    b0, b1, _ = flight_accel(p, arm_held, pa + h * wa, pt + h * wt, u0, u1)
    z0, z1 = wa + h * b0, wt + h * b1
    c0, c1, _ = flight_accel(p, arm_held, pa + h * u0, pt + h * u1, z0, z1)
    e0, e1 = wa + dt * c0, wt + dt * c1
    d0, d1, _ = flight_accel(p, arm_held, pa + dt * z0, pt + dt * z1, e0, e1)
    k6 = dt / 6.0
    return (pa + k6 * (wa + 2.0 * u0 + 2.0 * z0 + e0), pt + k6 * (wt + 2.0 * u1 + 2.0 * z1 + e1),
            wa + k6 * (a0 + 2.0 * b0 + 2.0 * c0 + d0), wt + k6 * (a1 + 2.0 * b1 + 2.0 * c1 + d1), lam)


@kernel
def fall_end(p, x):
    """When the runner would end a decided transfer: the centre of mass below the floor, or the flight timeout."""
    r = p[P.rise] / p[P.pitch]
    # cy0 + vy0·tau - g·tau²/2 = (cx0 + vx0·tau)·r - floor_drop
    a, b = -0.5 * G, x[X.vy0] - x[X.vx0] * r
    c = x[X.cy0] - x[X.cx0] * r + p[P.floor_drop]
    tau = (-b - math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
    return min(x[X.t0f] + tau, x[X.t_rel] + p[P.flight_timeout])


@kernel
def classify_miss(p, x, out, t_end):
    """The runner's _classify_miss, in its order."""
    a_rel, nan = x[X.a_rel], math.nan
    if a_rel - p[P.amin] < 0.5 * (p[P.amax] - p[P.amin]):
        finish(x, out, R_STIFF, t_end, math.degrees(a_rel), nan)
    elif x[X.h_rel] < p[P.min_release_height]:
        finish(x, out, R_LOW, t_end, x[X.h_rel], nan)
    elif math.isfinite(x[X.graze]):
        finish(x, out, R_GRAZE, t_end, x[X.graze], nan)
    elif math.isnan(x[X.t_cross]):
        finish(x, out, R_NEVER_DOWN, t_end, nan, nan)
    elif math.isnan(x[X.t_snap]) or x[X.t_snap] > x[X.t_cross]:
        finish(x, out, R_WEAK, t_end, math.degrees(a_rel - x[X.a_cross]), nan)
    elif x[X.dx_cross] < 0.0:
        finish(x, out, R_BEHIND, t_end, -x[X.dx_cross], nan)
    else:
        finish(x, out, R_AHEAD, t_end, x[X.dx_cross], nan)


@kernel
def arm_stop_in_flight(p, x, pa, pt, wa, wt, force):
    """The arm past a stop in flight (or, with ``force``, at one and moving into it): an inelastic impact about
    the centre of mass. Returns the new state."""
    alpha = pa - pt - math.pi
    if x[X.lockA] != 0.0:
        return pa, pt, wa, wt
    if force:
        lim = p[P.amax] if alpha > 0.5 * (p[P.amin] + p[P.amax]) else p[P.amin]
    elif p[P.amin] <= alpha <= p[P.amax]:
        return pa, pt, wa, wt
    else:
        lim = p[P.amax] if alpha > p[P.amax] else p[P.amin]
    a, b, cc = p[P.Ka], p[P.Kat] * math.cos(pa - pt), p[P.Kt]
    err, da = alpha - lim, wa - wt
    w = 1.0 / (a + 2.0 * b + cc)
    xa, xt = (cc + b) * w, -(a + b) * w  # K^-1 J^T / (J K^-1 J^T), J = (1, -1)
    pa, pt = pa - xa * err, pt - xt * err
    into = da > 0.0 if lim == p[P.amax] else da < 0.0
    if into:  # moving further into it
        wa, wt = wa - xa * da, wt - xt * da
        x[X.lockA], x[X.lockAk] = 1.0, 2.0 if lim == p[P.amax] else 1.0
    return pa, pt, wa, wt


@kernel
def arm_stop_time(p, x, dt):
    """When, within the step dt, the free arm reaches a stop (inf if it does not): a trial RK4 step says whether,
    the arm's own quadratic (its relative rate and acceleration now) where, else the straight line between."""
    if x[X.lockA] != 0.0:
        return math.inf
    pa, pt, wa, wt = x[X.pa], x[X.pt], x[X.wa], x[X.wt]
    a1 = flight_rk4(p, False, pa, pt, wa, wt, dt)
    alpha0, alpha1 = pa - pt - math.pi, a1[0] - a1[1] - math.pi
    if p[P.amin] <= alpha1 <= p[P.amax]:
        return math.inf
    lim = p[P.amax] if alpha1 > p[P.amax] else p[P.amin]
    acc = flight_accel(p, False, pa, pt, wa, wt)
    h = first_crossing(lim - alpha0, wa - wt, acc[0] - acc[1])
    if not 0.0 < h < dt:
        h = dt * (lim - alpha0) / (alpha1 - alpha0)
    return min(max(h, 0.0), dt)


@kernel
def free_frame_accel(p, th, w):
    """theta1'' of a frame with no robot on it: its weights' moment and the skewer's friction."""
    return (p[P.cfr] * math.cos(th) + p[P.m3gh] * math.sin(th) + skewer_friction(p, w)) / p[P.If]


@kernel
def free_frame_step(p, th, w, dt):
    """One RK4 step of a frame swinging alone (a touch that grazed kicked it), its stops inelastic."""
    h = 0.5 * dt
    a0 = free_frame_accel(p, th, w)
    a1 = free_frame_accel(p, th + h * w, w + h * a0)
    a2 = free_frame_accel(p, th + h * (w + h * a0), w + h * a1)
    a3 = free_frame_accel(p, th + dt * (w + h * a1), w + dt * a2)
    th1 = th + dt * (w + dt * (a0 + a1 + a2) / 6.0)
    w1 = w + dt * (a0 + 2.0 * a1 + 2.0 * a2 + a3) / 6.0
    if th1 <= p[P.rest] and w1 <= 0.0:
        th1, w1 = p[P.rest], 0.0
    elif th1 >= p[P.stop] and w1 >= 0.0:
        th1, w1 = p[P.stop], 0.0
    return th1, w1


@kernel
def flight_stage(p, x, out, sw, t, dt, detail, parked):
    """Advance a flying design from t to t + dt: the arm's motion, the hook's path, the catch or the miss. A step
    in which the free arm reaches its stop is split there (the stop's impact turns the robot into one body: a step
    that took it at its end would snap the arm up to a step late, and land a hook whose arm had not yet snapped
    as if it had)."""
    if x[X.t0f] >= t + dt:  # released at the end of this step's hooked part: it flies from the next step
        return
    if x[X.t0f] > t:  # released inside the step: it flies the rest of it
        t, dt = x[X.t0f], t + dt - x[X.t0f]
    h = arm_stop_time(p, x, dt)
    if 0.0 < h < dt:
        flight_part(p, x, out, sw, t, h, detail, parked, True)
        if x[X.phase] != FLIGHT:
            return
        t, dt = t + h, dt - h
    flight_part(p, x, out, sw, t, dt, detail, parked, False)


@kernel
def flight_part(p, x, out, sw, t, dt, detail, parked, to_stop):
    """Advance a flying design from t to t + dt (``to_stop``: the arm reaches its stop at t + dt)."""
    pa0, pt0, wa0, wt0 = x[X.pa], x[X.pt], x[X.wa], x[X.wt]
    lock0, k_arm = x[X.lockA], x[X.lockAk]
    pa, pt, wa, wt, lamA = flight_rk4(p, lock0 > 0.0, pa0, pt0, wa0, wt0, dt)
    pa1, pt1, wa1, wt1 = pa, pt, wa, wt  # the step's end before the arm's stops act there
    unlock = stop_lets_go(k_arm, lamA, p[P.af])
    pa, pt, wa, wt = arm_stop_in_flight(p, x, pa, pt, wa, wt, to_stop)
    if unlock:
        x[X.lockA], x[X.lockAk] = 0.0, 0.0
    x[X.pa], x[X.pt], x[X.wa], x[X.wt] = pa, pt, wa, wt
    alpha = pa - pt - math.pi
    t1 = t + dt
    tau = t1 - x[X.t0f]
    cx = x[X.cx0] + x[X.vx0] * tau
    cy = x[X.cy0] + x[X.vy0] * tau - 0.5 * G * tau * tau
    rx, ry = hook_from_com(p, pa, pt)
    hx, hy = cx + rx, cy + ry
    hx0, hy0 = x[X.hx], x[X.hy]
    x[X.hx], x[X.hy] = hx, hy
    fi = int(x[X.fi])
    ox, oy = (fi + 1) * p[P.pitch], (fi + 1) * p[P.rise]
    seat_x, seat_y = ox + p[P.seatx], oy + p[P.seaty]
    if x[X.nmov] > 0.0:  # the next frame moves: read the hook in that frame's coordinates, set at rest
        d0 = p[P.rest] - x[X.nth]
        x[X.nth], x[X.nw] = free_frame_step(p, x[X.nth], x[X.nw], dt)
        d1 = p[P.rest] - x[X.nth]
        c0, s0, c1, s1 = math.cos(d0), math.sin(d0), math.cos(d1), math.sin(d1)
        hx0, hy0 = ox + c0 * (hx0 - ox) - s0 * (hy0 - oy), oy + s0 * (hx0 - ox) + c0 * (hy0 - oy)
        hx, hy = ox + c1 * (hx - ox) - s1 * (hy - oy), oy + s1 * (hx - ox) + c1 * (hy - oy)
    since = t1 - x[X.t_rel]
    x[X.closest] = min(x[X.closest], distance(hx - seat_x, hy - seat_y))
    if detail:
        vy = x[X.vy0] - G * tau
        kin = (0.5 * p[P.m] * (x[X.vx0] ** 2 + vy * vy) + 0.5 * (p[P.Ka] * wa * wa + p[P.Kt] * wt * wt)
               + p[P.Kat] * math.cos(pa - pt) * wa * wt)
        e = kin + p[P.m] * G * cy + spring_energy(p, alpha - p[P.amin]) + parked_energy(parked, fi, True)
        track_energy(out, e)
    # the runner's watch: the arm's snap, the hook sinking past the next seat
    snapped = alpha < p[P.snap]
    if snapped and math.isnan(x[X.t_snap]):
        x[X.t_snap] = since
    if hy < seat_y and math.isnan(x[X.t_cross]):
        x[X.t_cross], x[X.dx_cross], x[X.a_cross] = since, hx - seat_x, alpha
    # the notch's mouth: entering it downward with the arm snapped, then reaching the seat's depth
    ax, ay = ox + p[P.mbx], oy + p[P.mby]
    bx, by = ox + p[P.mfx] - ax, oy + p[P.mfy] - ay
    side0 = bx * (hy0 - ay) - by * (hx0 - ax)
    side1 = bx * (hy - ay) - by * (hx - ax)
    side_in = bx * (seat_y - ay) - by * (seat_x - ax)
    lam = side0 / (side0 - side1 if side0 != side1 else 1.0)
    mx, my = hx0 + lam * (hx - hx0) - ax, hy0 + lam * (hy - hy0) - ay
    mu = (mx * bx + my * by) / (bx * bx + by * by)
    on_mouth = 0.0 <= mu <= 1.0
    enter = on_mouth and side0 * side_in < 0.0 and side1 * side_in >= 0.0
    leave = on_mouth and side0 * side_in >= 0.0 and side1 * side_in < 0.0
    was_in = x[X.in_notch] > 0.0
    entered = enter and not was_in and snapped
    if entered:
        x[X.t_mouth] = t + lam * dt
    in_notch = (was_in or entered) and not (leave and was_in)
    if in_notch:
        verdict, lam_c, gap, face, along = seat_reached(p, hx0 - seat_x, hy0 - seat_y, hx - seat_x, hy - seat_y)
    else:
        verdict, lam_c, gap, face, along = end_reached(p, hx0 - seat_x, hy0 - seat_y, hx - seat_x, hy - seat_y)
    if verdict != NO_CATCH:
        if verdict == CAUGHT or verdict == LANDED:  # the state there: arm and torso interpolated inside the step
            x[X.in_notch] = 1.0
            # (the arm's stops act at the step's end, after this: the arm as it was at the step's start)
            x[X.pa], x[X.pt] = pa0 + lam_c * (pa1 - pa0), pt0 + lam_c * (pt1 - pt0)
            x[X.wa], x[X.wt] = wa0 + lam_c * (wa1 - wa0), wt0 + lam_c * (wt1 - wt0)
            x[X.lockA], x[X.lockAk] = lock0, k_arm
            if verdict == CAUGHT and x[X.nmov] == 0.0:
                catch(p, x, sw, t + lam_c * dt, t1, gap)
            elif verdict == CAUGHT:
                land(p, x, sw, t + lam_c * dt, t1, 0, 0.0)
            else:
                land(p, x, sw, t + lam_c * dt, t1, face, along)
            return
        if verdict == GRAZED:
            x[X.graze] = min(x[X.graze], gap)
            in_notch = False
    x[X.in_notch] = 1.0 if in_notch else 0.0
    # the end of a transfer that was not caught
    low_mouth = min(min(ay, oy + p[P.mfy]), seat_y) - NOTCH_EXIT_MARGIN
    vy = x[X.vy0] - G * tau
    floor = cy < cx * p[P.rise] / p[P.pitch] - p[P.floor_drop]
    timeout = since > p[P.flight_timeout]
    decided = not math.isnan(x[X.t_cross]) and not in_notch and hy < low_mouth and vy < 0.0
    if floor or timeout:
        classify_miss(p, x, out, t1)
    elif decided:
        classify_miss(p, x, out, fall_end(p, x))
