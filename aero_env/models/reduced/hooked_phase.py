"""One step of a hooked design: the constraints at t, RK4 under them to t + dt, the events at t + dt.

The handrail's force and the stops' loads at the step's start decide the constraints: the hook holds
while the force lies in the notch's static friction cone, slides along a face when it leaves the cone
pressing on that face (kinetic friction), lets go when no face can push; a held stop lets go when its
load turns to a pull. After the step: impacts at the stops, the slide's end (past the face's end: the
hook lets go), and the runner's swing checks (held at the stop, turned back, timeouts, the model's own
stall test).
"""

from __future__ import annotations

import math

from .jit import kernel

from ...physics.swing_rules import REST_MOVE, STOP_TOLERANCE, TURN_BACK_DEG
from .constants import CAP_STEP, S_CORNER, STALL_WINDOW
from .hooked_dynamics import (distance, face_end, first_crossing, friction_cone, hook_on_frame, hook_place,
                              hooked_energy, normal_sum, slide_eval, slide_step, stick_eval, stick_step, stop_lets_go,
                              theta2)
from .hook_impulse import corner_stop
from .impacts import impact
from .layout import (HOOKED, R_AT_REST, R_BARRIER, R_BARRIER_REST, R_HELD_LONG, R_STOP_HOLD, R_TIMEOUT,
                     R_TURN_BACK, R_TURN_NEAR_STOP, P, W, X)
from .next_card import next_card
from .transitions import (CARRIED, carried, end_slide, finish, graze_off, parked_energy, release_hook, start_slide,
                          track_energy)


@kernel
def stops_let_go(p, x, lam1, lamA):
    """Free a held stop whose load turned to a pull that its joint's dry friction cannot hold; True if either did."""
    changed = False
    k1, kA = x[X.lock1k], x[X.lockAk]
    if stop_lets_go(k1, lam1, p[P.pf]):
        x[X.lock1], x[X.lock1k] = 0.0, 0.0
        changed = True
    if stop_lets_go(kA, lamA, p[P.af]):
        x[X.lockA], x[X.lockAk] = 0.0, 0.0
        changed = True
    return changed


@kernel
def tip_turning(p, wa, w1):
    """Whether the hook's tip turns in the notch faster than sim.slip_speed (its surface slipping over the faces at
    r·|w_arm - w_frame|): kinetic friction then, static below (the pymunk world's switch)."""
    return p[P.r_hook] * abs(wa - w1) > p[P.slip_speed]


@kernel
def into_corner(p, x, Fx, Fy, c1, s1, turning):
    """A hook on one face (s > 0) that the force (Fx, Fy) pulls off it: inside the notch it crosses to the corner
    (a few mm, in a few ms), unless the force would pull it out of the corner too. Sets it there (an inelastic
    stop, :func:`.hook_impulse.corner_stop`) and returns True; False where it lets go of the handrail."""
    if x[X.s] <= S_CORNER or x[X.s] >= face_end(p, x) or x[X.cap] > 0.0:
        # in the corner already, or on the card's rounded end (it leaves the card there; a slide split at the face's
        # end stands at s_end less a rounding error there, on the end already: x[cap])
        return False
    if friction_cone(p, 0.0, x[X.face], Fx, Fy, c1, s1, p[P.phi_k] if turning else p[P.phi_s])[0]:
        return False
    x[X.s], x[X.cap] = 0.0, 0.0
    corner_stop(p, x)
    return True


@kernel
def roll(p, x, turn):
    """A sticking hook on one face rolls along it as the arm turns by ``turn`` relative to the frame: its contact
    point stays on the card, so its centre moves r·turn·perp(n) (perp(n) = (-ny, nx), n the face's inward normal:
    the centre's velocity is w x (r·n)), along the face r·turn·(perp(n)·u). The pymunk world's hook creeps so, a
    few mm/s. The move's own inertia is left out (r·w ~ 5 mm/s). Back at the corner it sits there; it does not
    roll past the face's end."""
    ux, uy, nx, ny = x[X.ux], x[X.uy], x[X.nx], x[X.ny]
    s = x[X.s] + p[P.r_hook] * turn * (nx * uy - ny * ux)
    x[X.s] = min(max(s, 0.0), face_end(p, x))


@kernel
def stick_stage(p, x, out, sw, t, dt, hold, detail, parked):
    """A sticking hook's step. Returns False where it did not step (it let go, or started a slide)."""
    px, py, A = hook_on_frame(p, x)
    th1, pa, pt, w1, wa, wt = x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt]
    a0, a1, a2, Fx, Fy, lam1, lamA, c1, s1 = stick_eval(p, x, px, py, A, th1, pa, pt, w1, wa, wt)
    # a stop that lets go first, and the step evaluated again without it (its load is the handrail's too: an arm
    # that lifts off its stop presses the hook on under its spring); a stop let go loads the other differently:
    # again, at most twice
    for again in range(2):
        if not stops_let_go(p, x, lam1, lamA):
            break
        a0, a1, a2, Fx, Fy, lam1, lamA, c1, s1 = stick_eval(p, x, px, py, A, th1, pa, pt, w1, wa, wt)
    # the tip turning in the notch: its surface slides over the faces at r·|w_arm - w_frame| (the pymunk switch
    # reads the slip at the contact point): kinetic friction above sim.slip_speed, static below, for the tip's
    # turning torque and for the cone that holds the hook alike
    # On one face (off the corner) the tip turning rolls along the card, its contact point at rest on it: static
    # friction holds it (the pymunk switch reads the contact point's slip), and rolling takes no turning friction
    # (the friction that holds the hook has its moment about the tip's centre all the same: tq below).
    in_corner = x[X.s] <= S_CORNER
    turning = tip_turning(p, wa, w1) and in_corner
    mu = p[P.mu_k] if turning else p[P.mu_s]
    release, slide, face, sig = friction_cone(p, x[X.s], x[X.face], Fx, Fy, c1, s1,
                                              p[P.phi_k] if turning else p[P.phi_s])
    if hold:
        release, slide = False, False
    # the step uses the turning torque the last step found; this one is the next step's
    piv = mu * p[P.r_hook] * normal_sum(p, x, Fx, Fy, c1, s1, mu) if in_corner else 0.0
    if release:
        x[X.piv] = piv
        if not into_corner(p, x, Fx, Fy, c1, s1, turning):
            release_hook(p, x, out, sw, t, t)
        return False
    if slide:
        x[X.piv] = piv
        start_slide(p, x, face, sig)
        return False
    # held on one face, the hook's static friction (the force's component along its path) acts at the tip's surface:
    # a moment about the tip's centre, as a slide's kinetic friction has (slide_part); the next step's
    tq = 0.0
    if not in_corner:
        ux, uy = hook_place(p, x, x[X.s])[2:4]
        tq = -p[P.r_hook] * (Fx * (c1 * ux - s1 * uy) + Fy * (s1 * ux + c1 * uy)) * (1.0 - 2.0 * x[X.face])
    x[X.th1], x[X.pa], x[X.pt], x[X.w1], x[X.wa], x[X.wt] = stick_step(p, x, px, py, A, dt, a0, a1, a2)
    if not in_corner and x[X.cap] == 0.0:
        roll(p, x, (x[X.pa] - pa) - (x[X.th1] - th1))
    x[X.piv] = piv
    x[X.tq0] = tq
    hooked_events(p, x, out, sw, t, dt, False, detail, parked)
    return True


@kernel
def slide_stage(p, x, out, sw, t, dt, detail, parked):
    """A sliding hook's step, split where it reaches the corner (the other face stops it there: a step past it
    would carry the robot past the corner before the stop puts the hook back) or its face's end (the path turns
    there onto the card's rounded end, whose curvature one RK4 step across the kink would integrate with an
    O(dt) error), or where its rate reaches zero (kinetic friction stops it there and the rest of the step sticks:
    a step past it would let the friction, still set against the old sense, drive the hook back). The split is
    where the slide's own quadratic (its rate and acceleration now) crosses."""
    s_end = face_end(p, x)
    s, ws = x[X.s], x[X.ws]
    x[X.cap] = 1.0 if s > s_end else 0.0
    h, h_end, h_rest = 0.0, math.inf, math.inf
    if 0.0 < s < s_end:
        a = slide_eval(p, x, x[X.th1], s, x[X.pa], x[X.pt], x[X.w1], ws, x[X.wa], x[X.wt])[1]
        h_end = first_crossing(s_end - s, ws, a)
        if ws * a < 0.0:  # the slide's rate reaching zero: kinetic friction stops a slide, it never turns it back
            h_rest = -ws / a
        h = min(h_end, first_crossing(-s, ws, a), h_rest)
    elif s > s_end and ws < 0.0:  # on the rounded end, sliding back toward the flat side (a hook that landed there)
        a = slide_eval(p, x, x[X.th1], s, x[X.pa], x[X.pt], x[X.w1], ws, x[X.wa], x[X.wt])[1]
        h = h_end = first_crossing(s_end - s, ws, a)
    if 0.0 < h < dt:
        slide_part(p, x, out, sw, t, h, detail, parked)
        if x[X.phase] != HOOKED:
            return
        if h == h_rest:  # at rest on the face (its end check may have stuck it): it sticks for the rest of the step
            end_slide(x)
            stick_stage(p, x, out, sw, t + h, dt - h, False, detail, parked)
            return
        if x[X.slide] == 0.0:  # (a stick for the rest of the step waits a step)
            return
        t, dt = t + h, dt - h
        if h == h_end:  # on to the rounded end, or off it onto the flat side
            x[X.cap] = 1.0 - x[X.cap]
    slide_part(p, x, out, sw, t, dt, detail, parked)


@kernel
def slide_part(p, x, out, sw, t, dt, detail, parked):
    """A sliding hook's step: kinetic friction along the face; a tensile face lets go."""
    y = (x[X.th1], x[X.s], x[X.pa], x[X.pt], x[X.w1], x[X.ws], x[X.wa], x[X.wt])
    a0, a1, a2, a3, N, lam1, lamA = slide_eval(p, x, *y)
    for again in range(2):  # a stop that lets go first (as stick_stage)
        if not stops_let_go(p, x, lam1, lamA):
            break
        a0, a1, a2, a3, N, lam1, lamA = slide_eval(p, x, *y)
    # the moment of the sliding friction about the tip's centre, r·mu_k·N·sig·cross(n, u), on the arm (the next
    # step's, as the turning torque)
    x[X.piv] = 0.0
    tq0 = p[P.r_hook] * x[X.mu_sig] * max(N, 0.0) * (1.0 - 2.0 * x[X.face])
    if N < 0.0:
        x[X.tq0] = tq0
        px, py, A = hook_on_frame(p, x)
        Fx, Fy, _, _, c1, s1 = stick_eval(p, x, px, py, A, y[0], y[2], y[3], y[4], y[6], y[7])[3:]
        turning = tip_turning(p, x[X.wa], x[X.w1])
        if into_corner(p, x, Fx, Fy, c1, s1, turning):
            stick_stage(p, x, out, sw, t, dt, False, detail, parked)
        else:
            release_hook(p, x, out, sw, t, t)
        return
    (x[X.th1], x[X.s], x[X.pa], x[X.pt],
     x[X.w1], x[X.ws], x[X.wa], x[X.wt]) = slide_step(p, x, dt, a0, a1, a2, a3)
    x[X.tq0] = tq0
    hooked_events(p, x, out, sw, t, dt, True, detail, parked)


@kernel
def hooked_events(p, x, out, sw, t, dt, was_sliding, detail, parked):
    """After a hooked step to t + dt: impacts at the stops, the slide's end, the runner's swing checks."""
    t1 = t + dt
    th1, w1, k1 = x[X.th1], x[X.w1], x[X.lock1k]
    if (th1 >= p[P.stop] and w1 > 0.0 and k1 != 2.0) or (th1 <= p[P.rest] and w1 < 0.0 and k1 != 1.0):
        impact(p, x, out, sw, t1, True)
    if x[X.phase] == HOOKED and x[X.lockA] == 0.0:
        alpha = x[X.pa] - x[X.pt] - math.pi
        if alpha > p[P.amax] or alpha < p[P.amin]:
            impact(p, x, out, sw, t1, False)
    if x[X.phase] != HOOKED:
        return
    if next_card(p, x, sw.shape[1]):  # the next frame's card in the way (a steep row)
        was_sliding = False  # (a slide it starts waits a step, as an impact's)
    if was_sliding and x[X.slide] > 0.0:  # the slide's end (a slide an impact has just started waits a step)
        s, sig = x[X.s], x[X.sig]
        s_end = face_end(p, x)
        if s >= s_end + 0.5 * math.pi * p[P.clear]:  # round the card's end to its far side: it lets go there
            release_hook(p, x, out, sw, t1, t1)
            return
        if s > s_end and x[X.ws] * sig <= 0.0:  # turned back on the rounded end: it slides back (no hold there)
            x[X.sig], x[X.mu_sig] = -sig, -x[X.mu_sig]
            swing_checks(p, x, out, sw, t1, detail, parked)
            return
        back = s <= 0.0  # back in the corner, where the other face stops it: an inelastic stop
        if back:
            x[X.s], x[X.cap] = 0.0, 0.0
            corner_stop(p, x)
        if back or x[X.ws] * sig <= 0.0:  # ... or the slide came to rest: it sticks
            end_slide(x)
            x[X.cap] = 0.0
    swing_checks(p, x, out, sw, t1, detail, parked)


@kernel
def swing_checks(p, x, out, sw, t1, detail, parked):
    """The runner's checks on a hooked swing at t1 (aero_env.physics.run's rules), and the records."""
    fi = int(x[X.fi])
    th1 = x[X.th1]
    if detail:
        th2 = math.degrees(theta2(p, x[X.pa], x[X.pt]))
        if not th2 >= sw[W.theta2_min, fi]:  # NaN (not yet recorded) compares False
            sw[W.theta2_min, fi] = th2
        if not th2 <= sw[W.theta2_max, fi]:
            sw[W.theta2_max, fi] = th2
        track_energy(out, hooked_energy(p, x, fi * p[P.rise]) + parked_energy(parked, fi, False))
    if x[X.touch] > 0.0:  # a touch, not yet a catch: the runner's Catching, which only watches the seat
        gap = x[X.touch_gap] = min(x[X.touch_gap], x[X.s])
        x[X.closest] = min(x[X.closest], gap)
        if t1 - x[X.t_touch] >= p[P.contact_hold] and gap <= p[P.catch_seat]:
            x[X.touch] = 0.0  # held that long, and seated at some time: a catch
            sw[W.catch_seat, fi] = gap
        elif t1 - x[X.t_rel] > p[P.flight_timeout]:  # the runner's flight timeout, still touching unseated
            graze_off(p, x, sw, t1)
            return
        else:
            return
    # the catch state as the runner records it: when it makes the catch (contact_hold after the first touch, or
    # later, once a touch held that long comes within sim.catch_seat of the seat)
    if x[X.rec] == 0.0 and t1 - x[X.t_catch] >= p[P.contact_hold]:
        sw[W.theta1_catch, fi] = math.degrees(th1)
        sw[W.theta2_catch, fi] = math.degrees(theta2(p, x[X.pa], x[X.pt]))
        x[X.rec] = 1.0
    # the frame carried the robot through its lowest point: its catch is a traversal (the last frame's: the row)
    if th1 >= CARRIED and math.isnan(sw[W.t_carried, fi]) and carried(x, out, sw, t1):
        return
    # the distance from the hook to the next frame's seat (once this frame's catch is a traversal: until then the
    # transfer onto it goes on, and the model holds the hook on its seat)
    if x[X.carried] > 0.0:
        c1, s1 = math.cos(th1), math.sin(th1)
        px, py = hook_place(p, x, x[X.s])[:2]
        hx = fi * p[P.pitch] + c1 * px - s1 * py
        hy = fi * p[P.rise] + s1 * px + c1 * py
        nx = (fi + 1) * p[P.pitch] + p[P.seatx]
        ny = (fi + 1) * p[P.rise] + p[P.seaty]
        x[X.closest] = min(x[X.closest], distance(hx - nx, hy - ny))
    # the runner's checks
    peak = x[X.peak] = max(x[X.peak], th1)
    at_stop = th1 >= p[P.stop] - STOP_TOLERANCE
    if not at_stop:
        x[X.t_stop] = math.nan
    elif math.isnan(x[X.t_stop]):
        x[X.t_stop] = t1
    turn_back = math.radians(TURN_BACK_DEG)
    since = t1 - x[X.t_catch]
    rest = p[P.rest]
    unmoved = peak < rest + REST_MOVE
    nan = math.nan
    if at_stop and t1 - x[X.t_stop] >= p[P.stop_hold]:
        finish(x, out, R_STOP_HOLD, t1, nan, nan)
    elif not at_stop and th1 < peak - turn_back:
        near = peak >= p[P.held_past]
        finish(x, out, R_TURN_NEAR_STOP if near else R_TURN_BACK, t1, math.degrees(peak), nan)
    elif since > p[P.swing_timeout]:  # past the balance angle and still hooked: friction holds it (results)
        held = peak >= p[P.held_past]
        finish(x, out, R_HELD_LONG if held else R_TIMEOUT, t1, math.degrees(peak), nan)
    elif unmoved and since > p[P.rest_timeout]:
        finish(x, out, R_AT_REST, t1, nan, nan)
    elif since >= STALL_WINDOW and (x[X.barrier] > 0.0 or (x[X.lock1k] == 1.0 and peak < rest + turn_back)):
        # the model's own early end (STALL_WINDOW): the runner would run these to its timeouts
        if unmoved:
            finish(x, out, R_BARRIER_REST, x[X.t_catch] + min(p[P.rest_timeout], p[P.swing_timeout]), nan, nan)
        else:
            finish(x, out, R_BARRIER, x[X.t_catch] + p[P.swing_timeout], nan, nan)


@kernel
def hooked_step(p, x, out, sw, t, dt, hold, detail, parked):
    """Advance a hooked design from t to t + dt (a sticking hook that starts to slide slides from t). A slide that
    may reach the face's end or the corner within the step is stepped at CAP_STEP: the roll over the card's end
    lasts a few ms, and each event is met in a short step. So is a hook pressed against the next frame's card
    (its push is an impulse at each step's end: next_card)."""
    n = 1
    if x[X.card] > 0.0:  # pressed against the next frame's card (next_card): short steps while it lasts
        n = int(math.ceil(dt / CAP_STEP - 1e-9))
    elif x[X.slide] > 0.0:  # within reach of the face's end or of the corner (twice the slide's own reach: it
        # accelerates) the step is split, so each event falls in a short step (slide_stage splits that one there)
        s_end = face_end(p, x)
        reach = 2.0 * abs(x[X.ws]) * dt
        if x[X.s] + reach > s_end or x[X.s] - reach < 0.0:
            n = int(math.ceil(dt / CAP_STEP - 1e-9))
    h = dt / n
    for i in range(n):
        ti = t + i * h
        stepped = False
        if x[X.slide] == 0.0:
            stepped = stick_stage(p, x, out, sw, ti, h, hold, detail, parked)
            if not stepped and x[X.phase] == HOOKED and x[X.slide] == 0.0:  # it crossed into the corner: step there
                stepped = stick_stage(p, x, out, sw, ti, h, hold, detail, parked)
        if not stepped and x[X.phase] == HOOKED and x[X.slide] > 0.0:
            slide_stage(p, x, out, sw, ti, h, detail, parked)
        if x[X.phase] != HOOKED:
            return
