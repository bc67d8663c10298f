"""How each part of the toy is built from card, and what that card weighs and where it sits.

One description per part, read by both sides of the project: the physics takes each body's mass,
centre and inertia from here (through :mod:`aero_env.parts.bodies`), and the kit draws the same pieces at
1:1 (:mod:`aero_env.parts.kit`). Every function takes a design (an ``aero_env.config.Design``, or
any object with its fields, floats or numpy arrays of one length so the reduced model can build a
batch with the same arithmetic) and returns SI values.

**The constructions.** Table 1 gives each part's mass, and at the paper's 310 g/m² a single flat
strip of a part's outline weighs a tenth of it (docs/make-your-own.md, "Why the parts are
laminated"). The article's text gives no nets, so each build below is a stated choice, made so
that the part as drawn weighs what Table 1 says:

- **Swing frame** ("a hollow rectangular shape", the article's Sec. 2): two side cards, the
  skewer through a hole in each, held apart by the handrail at one end, the counterbalance on their faces at
  the other. Each side card is ``layers`` layers of card glued flat, cut symmetric about its hole,
  so that it balances on the skewer by itself (the paper's frame moment dT is 0; a dT a config
  names still moves the centre, as before): a rectangle running ``END`` past the farther of the
  seat and the counterbalance, hollow, with a window each side of a ``HUB_BAR`` across the middle
  that carries the hole, ``MIN_STRIP`` strips along both edges and an end bar at each end. Its
  depth and its end bars are what make the two cards weigh m1 and swing about the skewer as the
  article's A13 says (:func:`fit_ring`), with the fewest layers that keep it at most
  ``RING_DEPTH_MAX`` deep; the windows hold the stopper skewers (:func:`stopper_radius`). A design
  no such card swings as A13 says gets the deepest that comes nearest; one no window fits gets
  flat cards, as deep as their card makes them, at most ``FRAME_DEPTH_MAX`` a layer.
- **Handrail**: an L of one card folded along its length, its two legs the notch's faces, bridging
  the side cards ``RAIL_SPAN`` apart, with a glue tab at each end onto the cards' inner faces. The
  tabs are as long as the handrail's mass (0.21 g, Table 1) makes them.
- **Counterbalance**: two coin seats (squares of card ``COIN_RIM`` wider than a coin, one layer each), whole one-yen
  coins (1.00 g each) and modelling clay for the rest of m3, in two stacks centred on the counterbalance's mark
  (La, h), each glued on its seat on a side card's face (:mod:`aero_env.parts.layout` says which faces). The seats
  hold a stack on card whatever the card's windows and cuts do under it; where a side card can be cut so that it
  holds the coins itself (:func:`fit_ring`), it is.
- **Arm**: a plate of ``layers`` layers glued flat, its length along the arm from ``END`` behind
  the axle hole to the hook, plus the ``HOOK_LIP`` folded into the hook (counted at the tip), its
  width across the machine what makes it weigh the arm's mass, at most ``ARM_WIDTH_MAX`` so it
  passes between the side cards. The model is 2D: a plate across the plane swings as a rod.
- **Torso**: a plate of ``layers`` layers glued flat in the plane of the swing, from ``END``
  above the axle hole to its bottom edge (Ld from the hook at alpha_max), its width what makes it
  weigh the torso's card (m2 less the arm, the coins and the handrail), at most
  ``TORSO_WIDTH_MAX``; the coins glued flat on its face, flush with its bottom.

Holes are the skewer's and the axle's (``HOLE_D``): their card is taken off the mass and inertia.
The leaf-spring strip (``spring_strip.py``, about 0.05 g) is drawn in the kit but is not in the
model's masses: Table 1 does not list it.
"""

from __future__ import annotations

import functools
import math
import types
from typing import Any

import numpy as np

from .card import PAPER_CARD

Design = Any  # see aero_env.parts.bodies: the config's checks read this module, so it does not import the config

GRAMMAGE = PAPER_CARD.grammage  # kg/m², the paper's JOHOKU WB310g (Sec. 6)
CARD_THICKNESS = PAPER_CARD.thickness
YEN_COIN = 1.0e-3  # kg: a one-yen coin weighs 1.00 g (the paper's robot carries four)
YEN_COIN_THICKNESS = 1.5e-3  # m
CLAY_STEP = 1.0e-4  # kg: modelling clay, weighed to the 0.1 g a kitchen scale reads
CLAY_DENSITY = 1.6e3  # kg/m³: oil-based modelling clay (about 1.5-1.8 g/cm³); only its volume in 3D reads it
YEN_COIN_RADIUS = 10.0e-3  # m: a one-yen coin is 20 mm across

SKEWER_D = 2.0e-3  # m: a thin bamboo skewer for every axis, stopper and the robot's axle (a choice)
HOLE_D = 2.4e-3  # m: a hole the skewer turns in freely (0.4 mm play; design.pivot_friction is its fit)
END = 4.0e-3  # m: card beyond a hole or a mark at a part's end, so the hole sits inside the card
HOOK_LIP = 3.0e-3  # m: the arm's tip folded 90 deg into the hook; the model sees only its contact edge
RAIL_SPAN = 30.0e-3  # m: the side cards' spacing, the handrail's length between its glue tabs
MIN_STRIP = 3.0e-3  # m: the narrowest strip scissors cut cleanly (the 'about 3 mm')
MIN_TAB = 3.0e-3  # m: the shortest glue tab that holds
FRAME_DEPTH_MAX = 20.0e-3  # m: a side card's depth across the frame line, at most (then another layer)
ARM_WIDTH_MAX = 26.0e-3  # m: the arm's width across, at most: it swings between side cards RAIL_SPAN apart
TORSO_WIDTH_MAX = 26.0e-3  # m: the torso's width in the plane, at most (a coin is 20 mm across)
HUB_BAR = 6.0e-3  # m: the hollow side card's bar across its middle, the hole in it with 1.8 mm of card each side
RING_DEPTH_MAX = 40.0e-3  # m: a hollow side card's depth across the frame line, at most (then another layer)
STOPPER_SPARE_DEG = 15.0  # deg a rest stopper may move lower and still turn in the window (troubleshooting's reach)
RING_LAYERS_MAX = 6  # layers a hollow side card may have; a design no ring of these fits has flat side cards
COIN_RIM = 1.0e-3  # m: card all round the counterbalance's coins, so that a stack a little off its mark stays on card
COIN_SEATS = 2  # a frame's counterbalance: two stacks, each glued on a card face on its own coin seat (one layer)


def laminate(area, length, max_width):
    """(layers, width): the fewest whole layers of a ``length``-long plate that carry ``area`` of card
    with each layer at most ``max_width`` wide, and the width that then gives exactly ``area``."""
    per_layer_max = length * max_width
    layers = np.maximum(np.ceil(area / per_layer_max - 1e-9), 1.0)
    return layers, area / (layers * length)


def hole_area():
    return math.pi * (HOLE_D / 2) ** 2


def lightest_plate(length):
    """kg: the least card a plate ``length`` long with a hole in it can be, one layer exactly as wide as the hole
    (narrower, the hole cuts it in two: no part, and a model of it whose inertia about its centre can come out
    negative). The config refuses a lighter part (:mod:`aero_env.config.sections`); the kit warns from a little
    wider, where scissors need card around the hole (``kit.NARROWEST``)."""
    return GRAMMAGE * (HOLE_D * length - hole_area())


# ---- the swing frame ------------------------------------------------------------------------------------------
def side_card_length(d: Design):
    """The shortest side card's length (m): symmetric about its hole, ``END`` past the farther of the seat and the
    counterbalance's mark. A card that holds the counterbalance's coins may be longer (:func:`coin_card_length`)."""
    return 2.0 * (np.maximum(d.La, d.Lb) + END)


def coin_card_length(d: Design):
    """A side card's length (m) that also runs ``COIN_RIM`` past the counterbalance's coins (:func:`coin_seat`)."""
    return np.maximum(side_card_length(d), 2.0 * coin_seat(d)["outer"])


def coin_seat(d: Design) -> dict:
    """The card the counterbalance's coins need under them on a side card: a coin's disc on the mark (La, h) and
    ``COIN_RIM`` round it. ``outer`` (the card must run that far from the hole), ``half_depth`` (that far either side
    of the frame line) and ``inner`` (how far from the hole a window may reach towards the counterbalance: the end
    bar then holds the whole stack). m, floats or arrays."""
    rim = YEN_COIN_RADIUS + COIN_RIM
    return dict(outer=d.La + YEN_COIN_RADIUS + COIN_RIM, half_depth=np.abs(d.h) + rim, inner=d.La - rim)


def a13_inertia(d: Design):
    """The article's frame inertia about its axis, A13: 2·m1/3·(La² + Lb² - La·Lb) (kg·m²). The hollow side cards
    (:func:`side_card`) are sized to swing so."""
    return 2.0 * d.m1 / 3.0 * (d.La**2 + d.Lb**2 - d.La * d.Lb)


def stopper_radius(d: Design):
    """m: how far from the axis the two stopper skewers stand, inside the side card's window beside the hub bar. The
    rest one meets the hub bar's edge at the rest angle, the end one at the end stop, each at ``stopper_angle`` off
    the frame line, so each turns through the window between (the frame's travel with ``STOPPER_SPARE_DEG`` to spare:
    the rest stopper may move that much lower and still clear). Infinite where no window holds such stops (a travel
    and its spare of 178 deg or more)."""
    a = stopper_angle(d)
    ok = a < math.radians(89.0)
    return np.where(ok, (HUB_BAR / 2 + SKEWER_D / 2) / np.cos(np.where(ok, a, 0.0)), np.inf)


def stopper_angle(d: Design):
    """rad: each stopper skewer's angle off the frame line where it meets the hub bar (:func:`stopper_radius`)."""
    return np.radians(d.stop_angle_deg - d.rest_angle_deg + STOPPER_SPARE_DEG) / 2.0


def stopper_reach(d: Design):
    """(u, v) m: how far along and across the frame line, from the hole, the stopper skewers reach inside the
    window as the frame turns (:func:`stopper_radius`): the window must hold both."""
    r = stopper_radius(d)
    return r + SKEWER_D / 2, np.where(np.isfinite(r), r * np.sin(stopper_angle(d)), np.inf) + SKEWER_D / 2


def ring_moments(half_length, half_depth, end, strip=MIN_STRIP, hub=HUB_BAR):
    """(area m², polar second moment about the hole m⁴) of one layer of a hollow side card: the rectangle
    2·half_length x 2·half_depth about its hole, less two windows (one each side of a ``hub`` bar across the
    middle, each ``strip`` inside the long edges and ``end`` inside the card's end) and the hole."""
    w_l = half_length - end - hub / 2.0  # each window along the frame line
    w_d = 2.0 * (half_depth - strip)  # and across it
    c = hub / 2.0 + w_l / 2.0  # its centre's distance from the hole
    window = w_l * w_d
    area = 4.0 * half_length * half_depth - 2.0 * window - hole_area()
    J = (4.0 * half_length * half_depth * (half_length**2 + half_depth**2) / 3.0
         - 2.0 * (window * (w_l**2 + w_d**2) / 12.0 + window * c**2) - math.pi * (HOLE_D / 2) ** 4 / 2.0)
    return area, J


RING_GRID = 64  # depths tried per layer count before the root is bisected: a fixed grid keeps it deterministic


def fit_ring(d: Design):
    """The hollow side card that weighs m1/2 and swings as A13 says (half of :func:`a13_inertia` about its hole),
    per design (floats or arrays): ``hollow`` (found), ``layers``, ``half_length``, ``half_depth`` and ``end`` (m).

    The fewest layers (1 to ``RING_LAYERS_MAX``) whose card is at most ``RING_DEPTH_MAX`` deep, its end bars at
    least a strip long and its windows at least the stopper's (:func:`stopper_reach`); the shallowest such card. First
    a card that holds the counterbalance's coins (:func:`coin_card_length` long, deep enough and its windows short of
    the coins, :func:`coin_seat`); where none swings as A13 says, the shortest card (:func:`side_card_length`),
    which may leave the coins over its edge or a window (the kit says so). Where no card reaches A13 that way, the
    shortest card ``RING_DEPTH_MAX`` deep whose layer count comes nearest; ``hollow`` is False only where no such
    card fits at all (then :func:`side_card` cuts flat cards)."""
    plain = np.atleast_1d(np.asarray(side_card_length(d) / 2.0, float))
    long_ = np.broadcast_to(np.asarray(coin_card_length(d) / 2.0, float), plain.shape)
    rows = np.arange(len(plain))
    each = np.broadcast_to(np.asarray(d.m1 / 2.0, float), plain.shape)
    target = np.broadcast_to(np.asarray(a13_inertia(d) / 2.0, float), plain.shape)
    reach_u, reach_v = (np.broadcast_to(np.asarray(r, float), plain.shape) for r in stopper_reach(d))
    seat = coin_seat(d)
    seat_v, seat_u = (np.broadcast_to(np.asarray(seat[k], float), plain.shape) for k in ("half_depth", "inner"))
    anywhere = np.full(plain.shape, np.inf)

    def shape_at(half, V, layer_area, inner):  # the end bars that make one layer carry layer_area at depth V, and
        window = (4.0 * half[:, None] * V - hole_area() - layer_area[:, None]) / 2.0  # whether they can, the windows
        w_l = window / (2.0 * (V - MIN_STRIP))  # reaching at most ``inner`` from the hole
        e = half[:, None] - HUB_BAR / 2 - w_l
        return e, ((w_l > 0) & (e >= MIN_STRIP) & (HUB_BAR / 2 + w_l >= reach_u[:, None])
                   & (HUB_BAR / 2 + w_l <= inner[:, None]))

    def fit(half, v_least, inner, todo):  # (found, layers, half depth, end) of the rows ``todo``
        found = np.zeros(plain.shape, bool)
        layers_out, v_out, e_out = np.ones(plain.shape), np.full(plain.shape, np.nan), np.full(plain.shape, np.nan)
        v_lo = np.minimum(v_least, RING_DEPTH_MAX / 2)
        V = v_lo[:, None] + np.linspace(0.0, 1.0, RING_GRID)[None, :] * (RING_DEPTH_MAX / 2 - v_lo[:, None])
        for layers in range(1, RING_LAYERS_MAX + 1):
            if found[todo].all():
                break
            layer_area = each / (GRAMMAGE * layers)
            aim = target / (GRAMMAGE * layers)
            e, ok = shape_at(half, V, layer_area, inner)
            gap = np.where(ok, ring_moments(half[:, None], V, e)[1] - aim[:, None], np.nan)
            cross = ok[:, :-1] & ok[:, 1:] & (np.sign(gap[:, :-1]) != np.sign(gap[:, 1:]))
            has = cross.any(axis=1) & ~found & todo
            if not has.any():
                continue
            k = np.argmax(cross, axis=1)
            lo, hi, g_lo = V[rows, k], V[rows, k + 1], gap[rows, k]
            for _ in range(60):  # bisection: the gap keeps its sign at lo
                mid = (lo + hi) / 2.0
                g = ring_moments(half, mid, shape_at(half, mid[:, None], layer_area, inner)[0][:, 0])[1] - aim
                same = np.sign(g) == np.sign(g_lo)
                lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
            v_star = (lo + hi) / 2.0
            layers_out = np.where(has, layers, layers_out)
            v_out = np.where(has, v_star, v_out)
            e_out = np.where(has, shape_at(half, v_star[:, None], layer_area, inner)[0][:, 0], e_out)
            found |= has
        return found, layers_out, v_out, e_out

    v_least = MIN_STRIP + np.minimum(reach_v, RING_DEPTH_MAX)
    held = fit(long_, np.maximum(v_least, seat_v), seat_u, seat_v <= RING_DEPTH_MAX / 2)
    plain_fit = fit(plain, v_least, anywhere, ~held[0])
    found = held[0] | plain_fit[0]
    layers_out, v_out, e_out = (np.where(held[0], a, b) for a, b in zip(held[1:], plain_fit[1:]))
    half_out = np.where(held[0], long_, plain)
    # where no card reaches A13 within the depth limit: the card at the limit, of the layer count that comes nearest
    # (a light, long frame's falls short), so that I1 moves on smoothly past the limit rather than dropping to a
    # flat card's
    nearest = np.full(plain.shape, np.inf)
    near = [np.ones(plain.shape), np.full(plain.shape, np.nan), np.full(plain.shape, np.nan)]
    V_max = np.full((len(plain), 1), RING_DEPTH_MAX / 2)
    for layers in range(1, RING_LAYERS_MAX + 1):
        e, ok = shape_at(plain, V_max, each / (GRAMMAGE * layers), anywhere)
        miss = np.where(ok[:, 0], np.abs(GRAMMAGE * layers * ring_moments(plain, V_max[:, 0], e[:, 0])[1] - target),
                        np.inf)
        better = miss < nearest
        nearest = np.where(better, miss, nearest)
        near = [np.where(better, layers, near[0]), np.where(better, V_max[:, 0], near[1]),
                np.where(better, e[:, 0], near[2])]
    use_near = ~found & np.isfinite(nearest)
    layers_out, v_out, e_out = (np.where(use_near, n, o) for n, o in zip(near, (layers_out, v_out, e_out)))
    hollow = found | use_near
    pick = (lambda a: a[0].item()) if np.ndim(side_card_length(d)) == 0 else (lambda a: a)
    return dict(hollow=pick(hollow), layers=pick(layers_out), half_length=pick(half_out), half_depth=pick(v_out),
                end=pick(e_out))


@functools.lru_cache(maxsize=4096)
def _fit_ring_one(La: float, Lb: float, m1: float, h: float, rest_angle_deg: float, stop_angle_deg: float) -> dict:
    """:func:`fit_ring` of one design, kept: a world is built per episode, the same frame over and over."""
    return fit_ring(types.SimpleNamespace(La=La, Lb=Lb, m1=m1, h=h, rest_angle_deg=rest_angle_deg,
                                          stop_angle_deg=stop_angle_deg))


def side_card(d: Design) -> dict:
    """One of a frame's two side cards: ``half_length`` (hole to each end), ``depth``, ``layers``, ``mass``,
    ``I_axis`` (about the skewer, which is its centre) and, for the article's hollow frame (``hollow``), ``end``
    (each end bar's length), ``window`` and ``window_depth`` (each of the two windows along and across the frame
    line, 0 for a flat card), ``strip`` (the long strips' width), ``hub`` (the bar across the middle) and
    ``holds_coins`` (the counterbalance's coins lie wholly on card, :func:`coin_seat`). Both
    cards together weigh m1. Hollow where :func:`fit_ring` finds a card that swings as A13 says; else a flat card
    of the fewest layers at most ``FRAME_DEPTH_MAX`` deep, as wide as its card makes it."""
    flat_length = side_card_length(d)
    mass = d.m1 / 2.0
    card = mass / GRAMMAGE  # m² of card over all layers, the hole's card already gone
    flat_layers, _ = laminate(card, flat_length, FRAME_DEPTH_MAX)
    # each layer is length x depth less the hole: solve depth so that it carries card / layers exactly
    flat_depth = (card / flat_layers + hole_area()) / flat_length
    flat_I = GRAMMAGE * flat_layers * (flat_length * flat_depth * (flat_length**2 + flat_depth**2) / 12.0
                                       - math.pi * (HOLE_D / 2) ** 4 / 2.0)
    ring = fit_ring(d) if np.ndim(flat_length) else _fit_ring_one(float(d.La), float(d.Lb), float(d.m1), float(d.h),
                                                                 float(d.rest_angle_deg), float(d.stop_angle_deg))
    hollow = ring["hollow"]
    half = np.where(hollow, ring["half_length"], flat_length / 2.0)
    length = 2.0 * half
    ring_V = np.where(hollow, ring["half_depth"], flat_depth / 2.0)
    ring_e = np.where(hollow, ring["end"], half)
    ring_I = GRAMMAGE * ring["layers"] * ring_moments(half, ring_V, ring_e)[1]
    pick = (lambda a: np.asarray(a).item()) if np.ndim(flat_length) == 0 else np.asarray
    window = np.where(hollow, half - ring_e - HUB_BAR / 2, 0.0)
    seat = coin_seat(d)  # the coins on card: within its length and depth, clear of its windows (to 1 nm: the fit's)
    holds_coins = ((half >= seat["outer"] - 1e-9) & (ring_V >= seat["half_depth"] - 1e-9)
                   & (~np.asarray(hollow) | (HUB_BAR / 2 + window <= seat["inner"] + 1e-9)))
    return dict(half_length=pick(half), length=pick(length), depth=pick(np.where(hollow, 2.0 * ring_V, flat_depth)),
                layers=pick(np.where(hollow, ring["layers"], flat_layers)), mass=mass,
                I_axis=pick(np.where(hollow, ring_I, flat_I)), hollow=pick(hollow), end=pick(ring_e),
                window=pick(window), window_depth=pick(np.where(hollow, 2.0 * (ring_V - MIN_STRIP), 0.0)),
                strip=MIN_STRIP, hub=HUB_BAR, holds_coins=pick(holds_coins))


def stopper_offsets(d) -> tuple[tuple[float, float], tuple[float, float]]:
    """World offsets (m) from a frame's axis of its two stopper skewers' centres, (rest, end). In the hollow card's
    window (:func:`stopper_radius`): the rest stopper meets the hub bar's edge with the frame at
    its rest angle, the end stopper with it at the end stop; each turns through the window between, so no other
    frame's card comes near it. A flat card's (no window): the rest stopper touches the card's edge below the
    counterbalance's arm, halfway out, at rest, and the end stopper the other edge at the end stop. The world's rotary
    limits are where these skewers hold the card."""
    sc = side_card(d)
    out = []
    for angle_deg, side in ((d.rest_angle_deg, 1.0), (d.stop_angle_deg, -1.0)):
        a = math.radians(angle_deg)
        if sc["hollow"]:  # against the hub bar's edge on the counterbalance's side, above the line at rest
            s = HUB_BAR / 2 + SKEWER_D / 2
            off = side * math.sqrt(float(stopper_radius(d)) ** 2 - s * s)
        else:  # against the card's edge, La/2 out: below the line at rest, above it at the end stop
            s, off = d.La / 2, -side * (float(sc["depth"]) / 2 + SKEWER_D / 2)
        out.append((s * math.cos(a) - off * math.sin(a), s * math.sin(a) + off * math.cos(a)))
    return out[0], out[1]


def frame_card_inertia(d: Design):
    """The frame's card (both side cards, m1) about its axis, kg·m²: what the world swings as I1."""
    return 2.0 * side_card(d)["I_axis"]


def handrail_card(d: Design) -> dict:
    """The handrail L: ``legs`` (its two faces, across its fold), ``tab`` (each end's glue tab), ``length``
    (``RAIL_SPAN`` plus both tabs) and ``mass`` (design.handrail_mass when the tabs can make it)."""
    legs = d.notch_back_face + d.notch_front_face
    length = d.handrail_mass / GRAMMAGE / legs
    tab = (length - RAIL_SPAN) / 2.0
    return dict(legs=legs, tab=tab, length=length, mass=d.handrail_mass)


def notch_faces(Lb, notch_angle, notch_opening, rest_angle, back_face, front_face, clearance):
    """The handrail L's two faces in frame-local coordinates: ``((corner, back end), (corner, front end))``,
    each point an (x, y) pair, in whatever one length unit the arguments are in (angles in rad).

    The hook's centre sits in the corner at the seat (-Lb, 0), ``clearance`` (the card's half thickness plus the
    hook's radius) from both faces; at the rest angle the corner's bisector points along ``notch_angle`` (world),
    the faces ``notch_opening`` apart. Each face runs from the corner along the other face's normal. The world
    (:mod:`aero_env.physics.swing_frame`, engine units) and the solids (:mod:`aero_env.parts.solids`, SI) read
    these; the arithmetic is what pymunk's Vec2d did there, operation for operation, so the world's faces are
    unchanged bit for bit."""
    a_back = notch_angle - notch_opening / 2 - rest_angle
    a_front = notch_angle + notch_opening / 2 - rest_angle
    nbx, nby = math.cos(a_back), math.sin(a_back)  # = Vec2d(1, 0).rotated(a) exactly (1·c - 0·s is c)
    nfx, nfy = math.cos(a_front), math.sin(a_front)
    k = clearance / (1.0 + (nbx * nfx + nby * nfy))
    cx, cy = -Lb - (nbx + nfx) * k, 0.0 - (nby + nfy) * k
    return (((cx, cy), (cx + nfx * back_face, cy + nfy * back_face)),
            ((cx, cy), (cx + nbx * front_face, cy + nby * front_face)))


def coin_seat_area():
    """m²: one coin seat, a square of card ``COIN_RIM`` wider each side than a coin (scissors cut a square cleanly),
    one layer."""
    return (2.0 * (YEN_COIN_RADIUS + COIN_RIM)) ** 2


def coin_seats_mass():
    """kg: a frame's ``COIN_SEATS`` coin seats."""
    return COIN_SEATS * GRAMMAGE * coin_seat_area()


def counterbalance_load(m3, seats=None) -> dict:
    """What m3 (kg) is made of: its coin seats (``seats``, kg: ``COIN_SEATS`` of them unless given; 0 for coins glued
    on card, as the robot's), whole one-yen coins, and the clay for the rest (unrounded: the design space's grid
    rounds m3). The sheet refuses an m3 lighter than the seats (:func:`aero_env.parts.kit.check_counterbalance`)."""
    seats = coin_seats_mass() if seats is None else seats
    coins = np.maximum(np.floor((m3 - seats) / YEN_COIN + 1e-9), 0.0)
    clay = m3 - seats - coins * YEN_COIN
    return dict(coins=coins, clay=np.where(clay < 1e-9, 0.0, clay), seats=seats, mass=m3)  # no -0.00 g of clay


# ---- the robot ---------------------------------------------------------------------------------------------------
def arm_net_length(d: Design):
    """The arm's net (m): ``END`` behind the axle hole to the hook, and the lip unfolded."""
    return END + d.arm_length + HOOK_LIP


def arm_plate(d: Design) -> dict:
    """The arm: ``layers``, ``width`` across, ``start`` (behind the axle, negative) and ``tip`` along the arm
    from the axle, ``mass``, ``com`` (along the arm from the axle) and ``I_com`` (about its centre)."""
    length = arm_net_length(d)
    card = d.arm_mass / GRAMMAGE
    layers, _ = laminate(card, length, ARM_WIDTH_MAX)
    width = (card / layers + hole_area()) / length
    sigma = GRAMMAGE * layers
    # along the arm: the plate from -END to arm_length, the lip's card at the tip, less the hole at the axle
    m_plate = sigma * width * (END + d.arm_length)
    m_lip = sigma * width * HOOK_LIP
    m_hole = sigma * hole_area()
    mass = m_plate + m_lip - m_hole
    x_plate = (d.arm_length - END) / 2.0
    com = (m_plate * x_plate + m_lip * d.arm_length) / mass
    I_com = (m_plate * ((END + d.arm_length) ** 2 / 12.0 + (x_plate - com) ** 2) + m_lip * (d.arm_length - com) ** 2
             - m_hole * com**2)
    return dict(layers=layers, width=width, start=-END, tip=d.arm_length, net_length=length, mass=mass,
                com=com, I_com=I_com)


def torso_card_mass(d: Design):
    """The torso's card: Table 1's m2 less the arm, the coins and the handrail (which it counts)."""
    return d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass


def torso_net_length(torso_length):
    """The torso card's length (m): ``END`` above its axle hole to its bottom edge, ``torso_length`` below it."""
    return END + torso_length


def torso_plate(d: Design, torso_length) -> dict:
    """The torso's card plate, ``torso_length`` (axle to bottom edge) given: ``layers``, ``width``, ``mass``,
    ``com`` (below the axle) and ``I_com`` (about its own centre, in the plane)."""
    length = torso_net_length(torso_length)
    card = torso_card_mass(d) / GRAMMAGE
    layers, _ = laminate(card, length, TORSO_WIDTH_MAX)
    width = (card / layers + hole_area()) / length
    sigma = GRAMMAGE * layers
    m_full = sigma * width * length
    m_hole = sigma * hole_area()
    mass = m_full - m_hole
    y_full = (torso_length - END) / 2.0  # below the axle
    com = m_full * y_full / mass  # the hole sits at the axle (0)
    I_com = (m_full * ((length**2 + width**2) / 12.0 + (y_full - com) ** 2)
             - m_hole * ((HOLE_D / 2) ** 2 / 2.0 + com**2))
    return dict(layers=layers, width=width, length=length, mass=mass, com=com, I_com=I_com)


def coin_stack(d: Design) -> dict:
    """The torso's coins: how many one-yen coins design.coin_mass is (not rounded here), and whether that is a
    ``whole`` number of them (else the kit and the bill speak of grams of coins or metal)."""
    coins = d.coin_mass / YEN_COIN
    return dict(coins=coins, whole=np.abs(coins - np.round(coins)) < 1e-6, mass=d.coin_mass)
