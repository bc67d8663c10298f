"""The impulse at the hook when it meets a card face it moves into: the landing, the frame's end stop, and the
corner that ends a slide (corner_stop).

The robot (the arm and torso, their rates about the hook's axle) meets a card at the hook with a velocity
relative to the card's point there. The impact is inelastic along the face's normal; along the face the
card's friction stops the hook if the impulse that does so lies in the friction cone, else the hook
slides on against kinetic friction. The frame either takes its share of the impulse (free to turn about
its axis) or is held (on a stop the impulse presses it into, or stopped by its own impact); the arm's
stop holds only if the impulse presses the arm into it (stops push, never pull).
"""

from __future__ import annotations

import math

from .jit import kernel

from .hooked_dynamics import hooked_mass, solve_hooked
from .layout import P, X
from .transitions import end_slide


@kernel
def hook_impulse(W00, W01, W11, vx, vy):
    """The impulse (Px, Py) that stops a contact point whose relative velocity is (vx, vy): -W^-1·v."""
    inv = 1.0 / (W00 * W11 - W01 * W01)
    return -(W11 * vx - W01 * vy) * inv, -(W00 * vy - W01 * vx) * inv


@kernel
def landing_impulse(p, W00, W01, W11, vx, vy, ux, uy, nx, ny):
    """The landing's impulse (Px, Py) at a contact of inverse inertia W whose relative velocity is (vx, vy), on a
    face along (ux, uy) with normal (nx, ny): inelastic along the normal; along the face the card's friction stops
    the hook if the impulse that does so lies in the friction cone (kinetic for a hook that arrives slipping),
    else the hook slides on against kinetic friction (mu_k) in the sense it was moving. Returns (Px, Py, sliding,
    the friction's sense)."""
    vn = vx * nx + vy * ny
    if vn >= 0.0:  # not moving into the face (it met the face's line at the step's start): no impact
        return 0.0, 0.0, False, 0.0
    Px, Py = hook_impulse(W00, W01, W11, vx, vy)
    pn, pu = Px * nx + Py * ny, Px * ux + Py * uy
    # the hook meets the card slipping over it: kinetic friction acts while it slips, so the slip ends inside the
    # impact only if the impulse that ends it lies in the kinetic cone (the static one for a hook that arrives
    # slower than sim.slip_speed along the card, as the pymunk world's switch reads it)
    mu = p[P.mu_k] if abs(vx * ux + vy * uy) > p[P.slip_speed] else p[P.mu_s]
    if abs(pu) <= mu * pn:
        return Px, Py, False, 0.0
    # the impulse leaves the static cone: it slides, against kinetic friction
    sig = -1.0 if pu > 0.0 else 1.0  # friction along +u stops a hook moving inward (-u)
    dx_, dy_ = nx - sig * p[P.mu_k] * ux, ny - sig * p[P.mu_k] * uy
    lam = -vn / (nx * (W00 * dx_ + W01 * dy_) + ny * (W01 * dx_ + W11 * dy_))
    qx, qy = lam * dx_, lam * dy_
    vrx, vry = vx + W00 * qx + W01 * qy, vy + W01 * qx + W11 * qy
    if (vrx * ux + vry * uy) * sig > 0.0:  # still moving that way after the impact
        return qx, qy, True, sig
    return Px, Py, False, 0.0  # friction stopped it


@kernel
def bounce_impulse(W00, W01, W11, vx, vy, ux, uy, nx, ny):
    """The impulse along the face's normal (nx, ny) alone that ends the contact point's motion off the face: a hook
    that leaves the face and is back on it within the runner's contact_hold (a bounce, no detach; no friction
    while it is off). Returns (Px, Py, the sense of its motion along the face after: +1 along u, -1 against)."""
    lam = -(vx * nx + vy * ny) / (nx * (W00 * nx + W01 * ny) + ny * (W01 * nx + W11 * ny))
    Px, Py = lam * nx, lam * ny
    vu = (vx + W00 * Px + W01 * Py) * ux + (vy + W01 * Px + W11 * Py) * uy
    return Px, Py, 1.0 if vu > 0.0 else -1.0


@kernel
def robot_at_hook(p, x, pa, pt, wa, wt, vx, vy, ux, uy, nx, ny, Hx, Hy, frame_held, frame_may_press, bounce):
    """The impact of the robot (its arm at phi_a, torso at phi_t) meeting a face along (ux, uy), inward normal
    (nx, ny), at the hook H = (Hx, Hy) from the frame's axis, with the hook's velocity (vx, vy) relative to the
    frame's point there (world) and the arm's and torso's rates wa, wt. The frame takes its share unless
    ``frame_held``; where ``frame_may_press`` (at rest on its rest stop) an impulse turning it into that stop holds
    it. The arm on its stop (``x[X.lockA]``) is held only if the impulse presses it in. Returns (Px, Py, sliding, sig, frame_held, arm_held, wa, wt): the
    impulse on the robot, the slide it leaves, the stops that hold, the arm's and torso's rates after it. With
    ``bounce`` the hook moves off the face and the face takes it back (:func:`bounce_impulse`): it slides on."""
    m = p[P.m]
    # the hook's motion from the robot's: d(hook)/d(phi_a) and d(hook)/d(phi_t) (hook_from_com's derivatives)
    gax, gay = p[P.Pa] * math.sin(pa) / m, -p[P.Pa] * math.cos(pa) / m
    gtx, gty = p[P.Pt] * math.sin(pt) / m, -p[P.Pt] * math.cos(pt) / m
    kc = p[P.Kat] * math.cos(pa - pt)
    on_stop = x[X.lockA] > 0.0
    iF = 1.0 / p[P.If]
    arm_held = False
    into_arm = 1.0 if x[X.lockAk] == 2.0 else -1.0  # the sense of alpha that presses the arm into its stop
    for _ in range(3):
        if arm_held:  # the robot's inverse inertia at the hook: 1/m + G·K^-1·G^T (held: one rigid turn)
            k00 = k01 = k11 = 1.0 / (p[P.Ka] + 2.0 * kc + p[P.Kt])
        else:
            inv = 1.0 / (p[P.Ka] * p[P.Kt] - kc * kc)
            k00, k01, k11 = p[P.Kt] * inv, -kc * inv, p[P.Ka] * inv
        W00 = 1.0 / m + gax * gax * k00 + 2.0 * gax * gtx * k01 + gtx * gtx * k11
        W01 = gax * gay * k00 + (gax * gty + gtx * gay) * k01 + gtx * gty * k11
        W11 = 1.0 / m + gay * gay * k00 + 2.0 * gay * gty * k01 + gty * gty * k11
        if not frame_held:  # ... and the frame's at the contact (a rotation about its axis)
            W00, W01, W11 = W00 + Hy * Hy * iF, W01 - Hx * Hy * iF, W11 + Hx * Hx * iF
        if bounce:
            Px, Py, sig = bounce_impulse(W00, W01, W11, vx, vy, ux, uy, nx, ny)
            sliding = True
        else:
            Px, Py, sliding, sig = landing_impulse(p, W00, W01, W11, vx, vy, ux, uy, nx, ny)
        ga, gt = gax * Px + gay * Py, gtx * Px + gty * Py
        press_frame = frame_may_press and not frame_held and Hx * Py - Hy * Px > 0.0
        press_arm = on_stop and not arm_held and ((k00 - k01) * ga + (k01 - k11) * gt) * into_arm > 0.0
        if not (press_frame or press_arm):
            break
        frame_held, arm_held = frame_held or press_frame, arm_held or press_arm
    return Px, Py, sliding, sig, frame_held, arm_held, wa + k00 * ga + k01 * gt, wt + k01 * ga + k11 * gt


@kernel
def corner_stop(p, x):
    """A hook sliding along a face reaches the corner (s = 0), where the other face stops it: an inelastic
    impact that ends the slide. The corner's impulse acts only on the hook's place on the frame, so the momenta
    of the frame angle and the robot's two angles carry through it; the frame stays on its rest stop if the
    impact pushes it there, and the arm on its stop only if the impact presses it in (stops push, never pull:
    an arm the impact opens leaves its stop, as at a landing). Sets the rates and ends the slide (end_slide)."""
    w1, ws, wa, wt = x[X.w1], x[X.ws], x[X.wa], x[X.wt]
    A, M01, D, E, M12, M13, F = hooked_mass(p, x, 0.0)[:7]
    B, C = p[P.Ja], p[P.Jt]
    r0 = A * w1 + M01 * ws + D * wa + E * wt
    r1 = D * w1 + M12 * ws + B * wa + F * wt
    r2 = E * w1 + M13 * ws + F * wa + C * wt
    held = x[X.lock1] > 0.0
    on_stop = x[X.lockA] > 0.0
    into_arm = 1.0 if x[X.lockAk] == 2.0 else -1.0  # the sense of alpha that presses the arm into its stop
    arm_held = False
    for _ in range(3):
        q0, q1, q2 = solve_hooked(A, B, C, D, E, F, r0, r1, r2, held, arm_held)
        press_frame = not held and q0 < 0.0 and x[X.th1] <= p[P.rest]  # pushed into the rest stop: it holds
        press_arm = on_stop and not arm_held and (q1 - q2) * into_arm > 0.0
        if not (press_frame or press_arm):
            break
        held, arm_held = held or press_frame, arm_held or press_arm
    if held:
        x[X.lock1], x[X.lock1k] = 1.0, 1.0
    if on_stop and not arm_held:  # opened off its stop
        x[X.lockA], x[X.lockAk] = 0.0, 0.0
    x[X.w1], x[X.wa], x[X.wt] = q0, q1, q2
    end_slide(x)
