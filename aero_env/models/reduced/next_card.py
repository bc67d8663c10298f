"""The hook, still hooked on frame i, meeting frame i + 1's cards: a contact of a steep row.

On a row that rises steeply for its pitch, frame i carries the hook up past the next frame's handrail: in
``steep`` the hook in frame i's corner passes within the hook/card clearance of frame i + 1's back card
(its end) at theta1 ~ 146 deg on 98 of 100 designs near the stored solution, and on none of 300 uniform
designs or 100 near ``six_coins``. The pymunk world's hook hits the card there (frame i + 1 stays on its
rest stop, pressed into it) and is thrown out of the corner along frame i's back card (0.2 m/s, 1.7 mm),
which decides where it lets go.

Frame i + 1 at rest is fixed here (its rest stop takes the push). Each card is a capsule: its centre line
from the seat's corner to the card's end, the hook's centre kept the hook/card clearance from it. Where the
hook's centre comes inside, the contact is an inelastic impact along the line from the card to the hook,
with the card's Coulomb friction along it (:func:`card_impulse`; the notch's face's friction is left to the
motion after it), in the hooked coordinates (theta1, s, phi_a, phi_t): the hook may slide along the face of
its own notch that leads away from the card (out of the corner; on a face, along it), else it is held at s
and the impulse turns the frame and the robot. The hook is then set back on the capsule along its face.
Repeated every step while the card stays in the way (a pressed contact, taken as a run of small impacts;
while it lasts the steps are CAP_STEP long, as the world's: within a 4 ms step the hook's own slide would
come to rest against its friction while the world's card keeps pushing it, and the next step's impulse
would be the step's push at once).
"""

from __future__ import annotations

import math

from .jit import kernel

from .constants import S_CORNER
from .hooked_dynamics import distance, hook_place, hooked_mass, solve_eliminated, solve_hooked
from .layout import P, X
from .notch import card_at_rest
from .transitions import start_slide

# The hook is set back out of the card along its own face only where that face leads away from the card at least
# this much (the cosine between them: 78 deg); more nearly across the card the move would grow without bound, and
# the impulse alone acts.
ESCAPE_MIN = 0.2


@kernel
def card_contact(p, dx, dy):
    """The hook's centre at (dx, dy) from the next notch's seat (that frame at rest): the card it is inside the
    clearance of, if any. Returns (face or -1, the depth inside, the contact's normal (from the card to the
    hook))."""
    r = p[P.clear]
    best, face, nx_, ny_ = 0.0, -1, 0.0, 0.0
    for k in range(2):
        ux, uy, nx, ny, s_end = card_at_rest(p, k)[:5]
        # the card's centre line: seat + s·u - r·n for s in [0, s_end]
        s = min(max((dx + r * nx) * ux + (dy + r * ny) * uy, 0.0), s_end)
        vx, vy = dx - (s * ux - r * nx), dy - (s * uy - r * ny)
        d = distance(vx, vy)
        if d < r and r - d > best and d > 0.0:
            best, face, nx_, ny_ = r - d, k, vx / d, vy / d
    return face, best, nx_, ny_


@kernel
def unit_impulse(p, x, jth, js, slide_free):
    """The rates' changes over (theta1, s, phi_a, phi_t) under a unit impulse along a contact whose rate is
    jth·w1 + js·ws (generalised impulses (jth, js, 0, 0)), the held stops kept; the hook's place s kept unless
    ``slide_free`` (s eliminated as slide_eval eliminates it). Returns the changes and the contact's rate change."""
    A, M01, D, E, M12, M13, F = hooked_mass(p, x, x[X.s])[:7]
    B, C, m = p[P.Ja], p[P.Jt], p[P.m]
    frame_held, arm_held = x[X.lock1] > 0.0, x[X.lockA] > 0.0
    if not slide_free:
        x0, x1, x2 = solve_hooked(A, B, C, D, E, F, jth, 0.0, 0.0, frame_held, arm_held)
        return x0, 0.0, x1, x2, jth * x0
    im = 1.0 / m
    a0, a2, a3, q1 = M01 * im, M12 * im, M13 * im, js * im
    x0, x1, x2 = solve_eliminated(A - M01 * a0, D - M01 * a2, E - M01 * a3,
                                  D - M12 * a0, B - M12 * a2, F - M12 * a3,
                                  E - M13 * a0, F - M13 * a2, C - M13 * a3,
                                  jth - M01 * q1, -M12 * q1, -M13 * q1, frame_held, arm_held)
    xs = q1 - a0 * x0 - a2 * x1 - a3 * x2
    return x0, xs, x1, x2, jth * x0 + js * xs


@kernel
def card_impulse(p, x, jth, js, kth, ks, vn, vt, slide_free):
    """The contact's impulse (normal, along the card) for a hook meeting the card at normal rate vn < 0 and rate
    vt along it, the contact's rates being (jth, js)·(w1, ws) and (kth, ks)·(w1, ws): inelastic along the
    normal; along the card its friction stops the slip if the impulse that does so lies in the cone, else it
    acts at mu_k against the slip, as the pymunk world's card does (its contacts at the kick carry a
    tangential impulse of mu_k times the normal one: scripts/world_contacts.py). The cone is mu_k's for a hook
    slipping faster than sim.slip_speed, mu_s's below (the world's switch). Where friction would jam the
    contact (no normal impulse stops it) the impact is frictionless."""
    n0, ns = unit_impulse(p, x, jth, js, slide_free)[:2]
    t0, ts = unit_impulse(p, x, kth, ks, slide_free)[:2]
    Knn, Knt, Ktt = jth * n0 + js * ns, jth * t0 + js * ts, kth * t0 + ks * ts  # (the matrix is symmetric)
    mu = p[P.mu_k] if abs(vt) > p[P.slip_speed] else p[P.mu_s]
    det = Knn * Ktt - Knt * Knt
    # det vanishes, up to rounding, where the hook is held at s (both impulses then turn the frame alone, and the
    # slip cannot be stopped apart from the approach); else: does the impulse that stops the slip lie in the cone?
    if det > 1e-12 * Knn * Ktt:
        ln, lt = (-vn * Ktt + vt * Knt) / det, (-vt * Knn + vn * Knt) / det
        if ln > 0.0 and abs(lt) <= mu * ln:
            return ln, lt
    sg = 1.0 if vt > 0.0 else -1.0
    rate = Knn - sg * p[P.mu_k] * Knt
    if vt == 0.0 or rate <= 0.0:
        return -vn / Knn, 0.0
    ln = -vn / rate
    return ln, -sg * p[P.mu_k] * ln


@kernel
def next_card(p, x, n_frames):
    """After a hooked step: is frame i's hook inside the clearance of frame i + 1's cards (at rest)? Then the
    inelastic contact and the hook set back on the card's capsule (module docstring). Returns True if that started
    a slide (its slide-end checks wait a step, as after an impact)."""
    fi = int(x[X.fi])
    if p[P.next_card] == 0.0:  # (params.next_card_reach)
        return False
    x[X.card] = 0.0
    if fi + 1 >= n_frames or x[X.nmov] > 0.0:
        return False
    th1, s = x[X.th1], x[X.s]
    was_stuck = x[X.slide] == 0.0
    c1, s1 = math.cos(th1), math.sin(th1)
    px, py = hook_place(p, x, s)[:2]
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    face, depth, nx, ny = card_contact(p, Hx - p[P.pitch] - p[P.seatx], Hy - p[P.rise] - p[P.seaty])
    if face < 0:
        return False
    x[X.card] = 1.0  # (the next steps are short while it stays: hooked_step)
    # the face of its own notch it may slide along: on a face, that face; in the corner, the one leading most along
    # the card's push, if either leads away from the card
    if s > S_CORNER:
        along = (c1 * x[X.ux] - s1 * x[X.uy]) * nx + (s1 * x[X.ux] + c1 * x[X.uy]) * ny
        slide_free = True
    else:
        ab = (c1 * p[P.ubx] - s1 * p[P.uby]) * nx + (s1 * p[P.ubx] + c1 * p[P.uby]) * ny
        af = (c1 * p[P.ufx] - s1 * p[P.ufy]) * nx + (s1 * p[P.ufx] + c1 * p[P.ufy]) * ny
        along = max(ab, af)
        slide_free = along > 0.0
        if slide_free:  # (from the corner: a slide starts)
            start_slide(p, x, 0.0 if ab >= af else 1.0, 1.0)
            x[X.ws], x[X.tq0] = 0.0, 0.0
    uwx, uwy = c1 * x[X.ux] - s1 * x[X.uy], s1 * x[X.ux] + c1 * x[X.uy]
    jth, js = -Hy * nx + Hx * ny, (uwx * nx + uwy * ny) if slide_free else 0.0
    vn = jth * x[X.w1] + js * x[X.ws]
    if vn < 0.0:  # moving into the card
        tx, ty = -ny, nx  # along the card at the contact
        kth, ks = -Hy * tx + Hx * ty, (uwx * tx + uwy * ty) if slide_free else 0.0
        ln, lt = card_impulse(p, x, jth, js, kth, ks, vn, kth * x[X.w1] + ks * x[X.ws], slide_free)
        d0, ds, d2, d3 = unit_impulse(p, x, ln * jth + lt * kth, ln * js + lt * ks, slide_free)[:4]
        x[X.w1] += d0
        x[X.ws] += ds
        x[X.wa] += d2
        x[X.wt] += d3
    started = slide_free and was_stuck
    if slide_free:
        if along > ESCAPE_MIN:  # set back on the capsule along its face
            x[X.s] += depth / along
        # the slide's sense after the impulse; only an impulse sets it (a slide whose own motion turns back came to
        # rest: the slide's end check sticks it, and kinetic friction never drives it the other way)
        if vn < 0.0 and x[X.ws] > 0.0:
            x[X.sig], x[X.slide], x[X.mu_sig] = 1.0, 1.0, p[P.mu_k]
        elif vn < 0.0 and x[X.ws] < 0.0:
            x[X.sig], x[X.slide], x[X.mu_sig] = -1.0, 1.0, -p[P.mu_k]
    return started
