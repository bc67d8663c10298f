"""The hook meeting the next frame's notch in flight: the cards' flat sides and rounded ends.

Each card is a surface the hook's centre cannot come within the hook/card clearance of: a flat side (the line
from the seat along the face, up to the face's end) and a rounded end (a circle of the clearance about the
card's end). Inside the notch's mouth :func:`seat_reached` tests both faces and the seat's depth; outside it
:func:`end_reached` tests the two card ends, which the pymunk world's hook touches wherever it meets them.
Each returns a verdict, the fraction of the step at which it came, the distance from the seat there, the face
and the place on it (s from the seat; on a rounded end, the face's end plus the arc over it).
"""

from __future__ import annotations

import math

from .jit import kernel

from .hooked_dynamics import distance
from .layout import P

NO_CATCH, CAUGHT, GRAZED, LANDED = 0, 1, 2, 3  # the verdicts


@kernel
def card_at_rest(p, face):
    """Face ``face``'s card (0 back, 1 front) in a notch at rest, world directions: the face's direction and inward
    normal, where its flat side ends (s from the seat) and its end's centre from the seat (the hook/card clearance
    inside the face's line: the hook's centre keeps that far from it)."""
    if face == 0:
        ux, uy, nx, ny, s_end = p[P.rbux], p[P.rbuy], p[P.rbnx], p[P.rbny], p[P.s_end_b]
    else:
        ux, uy, nx, ny, s_end = p[P.rfux], p[P.rfuy], p[P.rfnx], p[P.rfny], p[P.s_end_f]
    r = p[P.clear]
    return ux, uy, nx, ny, s_end, s_end * ux - r * nx, s_end * uy - r * ny


@kernel
def cap_entry(ex, ey, r, dx0, dy0, dx1, dy1):
    """The fraction of the step at which the path (dx0, dy0) -> (dx1, dy1) first comes within r of (ex, ey),
    or 2.0 if it does not (a card's rounded end: the hook's centre cannot come closer than the clearance)."""
    mx, my = dx1 - dx0, dy1 - dy0
    fx, fy = dx0 - ex, dy0 - ey
    a, b, c = mx * mx + my * my, 2.0 * (fx * mx + fy * my), fx * fx + fy * fy - r * r
    if c <= 0.0:
        return 0.0
    disc = b * b - 4.0 * a * c
    if a == 0.0 or disc < 0.0:
        return 2.0
    lam = (-b - math.sqrt(disc)) / (2.0 * a)
    return lam if 0.0 <= lam <= 1.0 else 2.0


@kernel
def seat_reached(p, dx0, dy0, dx1, dy1):
    """Inside the next notch's mouth, the hook's centre moved from (dx0, dy0) to (dx1, dy1) (from the seat) in a
    step: did it meet the notch? Returns (verdict, fraction of the step, distance from the seat there, face, s).

    Each face is a card whose surface the hook's centre cannot come within the hook/card clearance of: a flat
    side (the line from the seat along the face, up to the face's end) and a rounded end. Meeting the flat side
    it lands on that face at s along it from the seat (``LANDED``: :func:`.catch.land` takes the impact, and
    the hooked motion decides whether it slides into the corner, a catch, or off the card, a graze). Meeting the
    rounded end it lands there or grazes (:func:`end_touched`). Crossing the face's line past its end it has
    passed the card: a graze. Reaching the seat's depth first (beside the corner, that the faces would guide it
    into), it is caught at once."""
    first, face, kind = 2.0, -1, 0  # kind: 0 the flat side, 1 the rounded end, 2 past the end
    for k in range(2):
        ux, uy, nx, ny, s_end, ex, ey = card_at_rest(p, k)
        d0, d1 = dx0 * nx + dy0 * ny, dx1 * nx + dy1 * ny
        cap = cap_entry(ex, ey, p[P.clear], dx0, dy0, dx1, dy1)
        if d1 < 0.0:  # past this face's line by the step's end
            lam = min(max(d0 / (d0 - d1), 0.0), 1.0) if d0 > 0.0 else 0.0
            along = (dx0 + lam * (dx1 - dx0)) * ux + (dy0 + lam * (dy1 - dy0)) * uy
            if along <= s_end:  # on the flat side
                if lam < first:
                    first, face, kind = lam, k, 0
            elif cap > 1.0 and lam < first:  # past the end, the rounded end untouched: beside the card
                first, face, kind = lam, k, 2
        if cap <= 1.0 and cap < first:
            first, face, kind = cap, k, 1
    b0, b1 = dx0 * p[P.bisx] + dy0 * p[P.bisy], dx1 * p[P.bisx] + dy1 * p[P.bisy]
    if b1 <= 0.0:  # the seat's depth
        lam = min(max(b0 / (b0 - b1 if b0 != b1 else 1.0), 0.0), 1.0)
        if lam < first:
            first, face = lam, -2
    if face == -1:
        return NO_CATCH, 0.0, 0.0, 0, 0.0
    hx, hy = dx0 + first * (dx1 - dx0), dy0 + first * (dy1 - dy0)
    gap = distance(hx, hy)
    if face == -2:
        return CAUGHT, first, gap, 0, 0.0
    if kind == 2:
        return GRAZED, first, gap, face, 0.0
    if kind == 1:
        return end_touched(p, face, first, hx, hy, gap)
    ux, uy, _, _, s_end = card_at_rest(p, face)[:5]
    return LANDED, first, gap, face, min(max(hx * ux + hy * uy, 0.0), s_end)


@kernel
def end_touched(p, face, first, hx, hy, gap):
    """The hook's centre at (hx, hy) (from the seat) met face ``face``'s rounded end: where on it, by its normal
    there (from the end's centre to the hook's). On its top (nearer the face's inward normal than its outward
    direction) it lands there, s past the face's end by the arc from the end's top (hooked_dynamics.hook_place);
    on its far side it slides off the card's end: a graze."""
    ux, uy, nx, ny, s_end, ex, ey = card_at_rest(p, face)
    ox, oy = hx - ex, hy - ey
    if ox * nx + oy * ny < ox * ux + oy * uy:
        return GRAZED, first, gap, face, 0.0
    psi = max(math.atan2(ox * ux + oy * uy, ox * nx + oy * ny), 0.0)
    return LANDED, first, gap, face, s_end + p[P.clear] * psi


@kernel
def end_reached(p, dx0, dy0, dx1, dy1):
    """Outside the next notch's mouth, the hook's centre moved from (dx0, dy0) to (dx1, dy1) (from the seat) in a
    step: did it meet one of the notch's card ends, coming from outside its clearance? The pymunk world's hook
    touches a card wherever it meets it: a hook that comes down onto the front card's end just outside the mouth
    lands there (:func:`end_touched`), one that meets an end from below or beside it grazes. Returns what
    :func:`seat_reached` returns."""
    first, face = 2.0, -1
    r = p[P.clear]
    for k in range(2):
        ex, ey = card_at_rest(p, k)[5:]
        if distance(dx0 - ex, dy0 - ey) <= r:  # inside it already (a graze passed through the card)
            continue
        cap = cap_entry(ex, ey, r, dx0, dy0, dx1, dy1)
        if cap <= 1.0 and cap < first:
            first, face = cap, k
    if face == -1:
        return NO_CATCH, 0.0, 0.0, 0, 0.0
    hx, hy = dx0 + first * (dx1 - dx0), dy0 + first * (dy1 - dy0)
    return end_touched(p, face, first, hx, hy, distance(hx, hy))
