"""Where each frame's parts sit across the row, so that neighbours clear each other as they swing (issue 49 §2).

The world is 2D: every frame swings in one plane. The toy is not, and frames drawn alike, their side cards in the
same two planes, run into each other (docs/make-your-own.md, *The toy in 3D*). This module chooses where each
frame's parts go across the row and cuts the cards where a neighbour's part still passes:

- **Nested frames.** Frames alternate. Even frames (0, 2, ...) are *narrow*: their side cards' inner faces
  ``RAIL_SPAN`` apart, as the robot needs. Odd frames are *wide*: their cards ``GAP`` outside the narrow cards'
  outer faces. So no card meets a neighbour's card, and what lies between a narrow frame's cards (its handrail,
  its counterbalance, half on each card's inner face) never reaches a wide frame's. The wide frames' counterbalance
  goes outside, half on each card's outer face, where no other card is.
- **What still crosses a card's plane**: the wide frames' handrails (each an L spanning its wide frame, so through
  the narrow cards' planes) and every skewer (the axes and the stoppers run from crossbeam to crossbeam).
- **Cut-away cards.** A card is cut away where those parts sweep: each neighbour turning from rest to its end stop
  with this frame at rest and at its end stop, and this frame turning with the neighbour at rest and at its end
  stop (the static sweep's cases, :mod:`aero_env.parts.clearance`), ``CLEAR`` clear of them. Slivers narrower than
  scissors cut go, and what stays joined to the hole is the card. Its free extents (how deep it runs below the
  frame line and above it, its end bars, its strips' widths, a cap over the hub, how far the end bars drop) are
  then fitted so that the card weighs, balances and swings as the hollow card does (:func:`build.side_card`, A13):
  the world swings every frame alike. A card no part crosses stays the hollow card.

Outlines are manifold3d ``CrossSection``s in mm, in the card's own coordinates (the hole at the origin, u along the
frame line towards the counterbalance, v across it); :func:`moments` gives their mass properties by Green's
theorem. :func:`nested_layout` is the one home of the layout: the 3D solids read it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import manifold3d as m3
import numpy as np
from scipy.optimize import minimize

from . import build

CS = m3.CrossSection
MM = 1e3
GAP = 1.0e-3  # m: a narrow card's outer face to the wide card beside it; a crossbeam's inner face to the frames
CROSSBEAM_GAP_MIN = build.RAIL_SPAN + 20.0e-3  # m: the two crossbeams' inner faces apart at the least
CLEAR = 1.0  # mm: the least room a cut-away card keeps from a neighbour's part as it sweeps
SLIVER = 1.4  # mm: half the narrowest strip kept (a strip under 2.8 mm is dropped: scissors cut 3 mm cleanly)
SWEEP_STEP_DEG = 1.0  # the sweeps' step; consecutive poses are joined by their hull
ROUND = 48  # sides of a hole or a skewer's circle
TOUCH_AREA = 0.05  # mm²: a card sharing less with what it keeps out of only touches it (0.06 mm³ for 3 layers)
FIT_MASS, FIT_CENTRE_MM = 1e-4, 0.01  # a fit holds when mass and inertia are within 1e-4 and the centre 0.01 mm


def rect(u0: float, u1: float, v0: float, v1: float) -> m3.CrossSection:
    return CS.square((u1 - u0, v1 - v0)).translate((u0, v0))


def disc(u: float, v: float, r: float, segments: int = ROUND) -> m3.CrossSection:
    return CS.circle(r, segments).translate((u, v))


def moments(outline: m3.CrossSection) -> tuple[float, float, float, float]:
    """(area mm², ∫u, ∫v mm³, ∫(u² + v²) mm⁴) over the outline, by Green's theorem over its polygons (holes
    wind the other way and subtract themselves)."""
    area = su = sv = j = 0.0
    for poly in outline.to_polygons():
        p = np.asarray(poly, float)
        x, y = p[:, 0], p[:, 1]
        x1, y1 = np.roll(x, -1), np.roll(y, -1)
        c = x * y1 - x1 * y
        area += c.sum() / 2
        su += ((x + x1) * c).sum() / 6
        sv += ((y + y1) * c).sum() / 6
        j += ((x * x + x * x1 + x1 * x1 + y * y + y * y1 + y1 * y1) * c).sum() / 12
    return area, su, sv, j


def hollow_outline(sc: dict) -> m3.CrossSection:
    """The hollow side card (:func:`build.side_card`) as an outline, hole included."""
    half, depth = float(sc["half_length"]) * MM, float(sc["depth"]) * MM
    out = rect(-half, half, -depth / 2, depth / 2)
    if sc["hollow"]:
        w_l, w_d, hub = float(sc["window"]) * MM, float(sc["window_depth"]) * MM, float(sc["hub"]) * MM
        out = out - rect(hub / 2, hub / 2 + w_l, -w_d / 2, w_d / 2) - rect(-hub / 2 - w_l, -hub / 2, -w_d / 2, w_d / 2)
    return out - disc(0.0, 0.0, build.HOLE_D * MM / 2, 256)


def handrail_footprint(d) -> m3.CrossSection:
    """The handrail L's two faces in its frame's coordinates (mm), as the world and the solids place them."""
    faces = build.notch_faces(d.Lb * MM, math.radians(d.notch_angle_deg), math.radians(d.notch_opening_deg),
                              math.radians(d.rest_angle_deg), d.notch_back_face * MM, d.notch_front_face * MM,
                              (d.handrail_thickness / 2 + d.hook_radius) * MM)
    t = d.handrail_thickness * MM
    legs = [CS.square((math.hypot(bx - ax, by - ay), t)).translate((0.0, -t / 2))
            .rotate(math.degrees(math.atan2(by - ay, bx - ax))).translate((ax, ay)) for (ax, ay), (bx, by) in faces]
    return CS.batch_boolean(legs, m3.OpType.Add)


def skewer_footprints(d) -> list[m3.CrossSection]:
    """A frame's axis skewer and its two stopper skewers, about its axis (mm): they stand still in the world."""
    r = build.SKEWER_D * MM / 2
    return [disc(0.0, 0.0, r)] + [disc(ox * MM, oy * MM, r) for ox, oy in build.stopper_offsets(d)]


def _angles(d) -> list[float]:
    n = max(1, math.ceil((d.stop_angle_deg - d.rest_angle_deg) / SWEEP_STEP_DEG - 1e-9))
    return [float(a) for a in np.linspace(d.rest_angle_deg, d.stop_angle_deg, n + 1)]


def _swept(poses: list[m3.CrossSection]) -> m3.CrossSection:
    if len(poses) == 1:
        return poses[0]
    return CS.batch_boolean([CS.batch_hull([p, q]) for p, q in zip(poses, poses[1:])], m3.OpType.Add)


def forbidden(cfg, turning_parts: list[m3.CrossSection], still_parts: list[m3.CrossSection]) -> m3.CrossSection:
    """Where a card may not go, in its own coordinates (mm), ``CLEAR`` wide: ``turning_parts`` of the neighbours one
    axis step either side (in their frame's coordinates) as they and this frame sweep, ``still_parts`` of the
    neighbours (about their axis, in the world's orientation: skewers) as this frame turns."""
    d, s = cfg.design, cfg.scene
    thetas = _angles(d)
    regions = []
    for ax, ay in ((-s.pitch * MM, -s.rise * MM), (s.pitch * MM, s.rise * MM)):
        for part in turning_parts:
            def local(th_other: float, th_self: float) -> m3.CrossSection:
                return part.rotate(th_other).translate((ax, ay)).rotate(-th_self)
            for fixed in (d.rest_angle_deg, d.stop_angle_deg):
                regions.append(_swept([local(t, fixed) for t in thetas]))  # the neighbour turns, this one waits
                regions.append(_swept([local(fixed, t) for t in thetas]))  # this one turns, the neighbour waits
        for part in still_parts:
            regions.append(_swept([part.translate((ax, ay)).rotate(-t) for t in thetas]))
    if not regions:
        return CS()
    return CS.batch_boolean(regions, m3.OpType.Add).offset(CLEAR, m3.JoinType.Round, circular_segments=ROUND)


# ---- the cut-away card, fitted ---------------------------------------------------------------------------------
PARAMS = ("below", "above", "end_back", "end_front", "strip_back", "strip_front", "cap", "drop")


def cut_card(sc: dict, p, keep_out: m3.CrossSection, pins: float) -> m3.CrossSection:
    """A card of the hollow card's length with free extents ``p`` (mm, in the order of ``PARAMS``): the frame line
    to its lower edge and to its upper edge, each end bar's length (seat side, counterbalance side), each lower
    strip's width, the half-width of a cap over the hub, how far the end bars reach below the lower edge. Its
    windows always reach ``pins`` (mm) either side of the frame line, where its own stopper skewers turn, and the
    cap sits beyond them. Less ``keep_out``, slivers under ``2·SLIVER`` dropped, only what is joined to the hole
    kept."""
    below, above, end_b, end_f, strip_b, strip_f, cap, drop = (float(x) for x in p)
    half, hub, top = float(sc["half_length"]) * MM, float(sc["hub"]) * MM, build.MIN_STRIP * MM
    low = min(-below + strip_f, -pins)  # the counterbalance side's window holds the stoppers' sweep
    card = (rect(-half, half, -below, above) + rect(-half, -half + end_b, -below - drop, 0.0)
            + rect(half - end_f, half, -below - drop, 0.0)
            - rect(-half + end_b, -hub / 2, -below + strip_b, above - top)
            - rect(hub / 2, half - end_f, low, max(above - top, pins))
            + rect(-max(cap, hub / 2), max(cap, hub / 2), pins, max(above, pins)))
    card = (card - keep_out).offset(-SLIVER, m3.JoinType.Round, circular_segments=ROUND).offset(
        SLIVER, m3.JoinType.Round, circular_segments=ROUND)
    r = build.HOLE_D * MM / 2
    around = disc(0.0, 0.0, r + 2.0) - disc(0.0, 0.0, r)
    joined = [piece for piece in card.decompose() if (piece ^ around).area() > 0]
    return (CS.batch_boolean(joined, m3.OpType.Add) if joined else CS()) - disc(0.0, 0.0, r, 256)


def _misfit(sc: dict, card: m3.CrossSection) -> np.ndarray:
    """(mass, inertia about the hole) relative to the hollow card's, and the centre (u, v) in 10 mm, of one card."""
    area, su, sv, j = moments(card)
    if area <= 0:
        return np.full(4, 1e3)
    sigma = build.GRAMMAGE * float(sc["layers"])
    return np.array([(sigma * area * 1e-6 - sc["mass"]) / sc["mass"], (sigma * j * 1e-12 - sc["I_axis"]) / sc["I_axis"],
                     su / area / 10.0, sv / area / 10.0])


def _fits(misfit: np.ndarray) -> bool:
    return bool(np.all(np.abs(misfit[:2]) <= FIT_MASS) and np.all(np.abs(misfit[2:]) * 10.0 <= FIT_CENTRE_MM))


def fit_cut_card(sc: dict, keep_out: m3.CrossSection, pins: float) -> tuple[np.ndarray | None, np.ndarray,
                                                                             m3.CrossSection | None]:
    """The extents (``PARAMS``, mm) whose :func:`cut_card` weighs, balances and swings as the hollow card, or None,
    the last misfit, and the card that fits (cut from the keep-out as the fit saw it: the one to draw, so that what is
    drawn is what fits). Nelder-Mead from a few fixed starts (deterministic), the first that fits wins."""
    half, V, e = float(sc["half_length"]) * MM, float(sc["depth"]) * MM / 2, float(sc["end"]) * MM
    strip = build.MIN_STRIP * MM
    lo = np.array([pins + strip, pins + strip, strip, strip, strip, strip, 0.0, 0.0])
    hi = np.array([60.0, 60.0, half - 5.0, half - 5.0, 20.0, 20.0, 30.0, 40.0])

    # only what a card of these extents can reach, its outline's corners to 0.01 mm: the fit's booleans run faster
    keep_out = (keep_out ^ rect(-half - 5.0, half + 5.0, -hi[0] - hi[7] - 5.0, hi[1] + 5.0)).simplify(0.01)

    def misfit(p):
        return _misfit(sc, cut_card(sc, np.clip(p, lo, hi), keep_out, pins))

    class Fitted(Exception):
        pass

    def cost(p):
        card = cut_card(sc, np.clip(p, lo, hi), keep_out, pins)
        m = _misfit(sc, card)
        if _fits(m):  # the first point that fits ends the search: what comes after only polishes digits
            raise Fitted(np.clip(p, lo, hi), m, card)
        return float(np.sum(m**2))

    starts = ([V, V, e, e, strip, strip, 3.0, 0.0], [pins + strip + 1, V, e, e, strip, strip, 4.0, 0.5 * V],
              [V, V, 0.8 * e, 0.8 * e, strip, strip, 9.0, 0.6 * V])
    last = misfit(starts[0])
    for start in starts:
        try:
            run = minimize(cost, np.array(start), method="Nelder-Mead",
                           options=dict(maxiter=3000, xatol=1e-7, fatol=1e-16, adaptive=True))
        except Fitted as done:
            return done.args
        last = misfit(np.clip(run.x, lo, hi))
    return None, last, None


# ---- the row ----------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FrameKind:
    """One kind of frame: ``name`` narrow or wide; ``span`` (m) its side cards' inner faces apart; ``outline`` (mm)
    its side card, of ``layers`` layers; ``extents`` the fitted :data:`PARAMS` of a cut-away card (None: the hollow
    card as it is); ``coins_outside``: its counterbalance on its cards' outer faces (else on their inner faces)."""
    name: str
    span: float
    outline: m3.CrossSection
    extents: tuple[float, ...] | None
    coins_outside: bool
    layers: int


@dataclass(frozen=True)
class RowLayout:
    """``kinds[i]`` is frame i's :class:`FrameKind`; ``found`` False (with ``reason``) where a card could not be cut
    to weigh and swing as the hollow card (its frames then keep the hollow card, and the row may not clear)."""
    name: str
    kinds: tuple[FrameKind, ...]
    found: bool
    reason: str

    def by_kind(self) -> list[tuple[FrameKind, list[int]]]:
        """Each kind of frame in the row, in the order it first appears, with the frames of that kind."""
        out: dict[str, tuple[FrameKind, list[int]]] = {}
        for i, kind in enumerate(self.kinds):
            out.setdefault(kind.name, (kind, []))[1].append(i)
        return list(out.values())

    def frames_of(self, name: str) -> list[int]:
        """The frames of the kind ``name`` ([] where the row has none)."""
        return [i for i, kind in enumerate(self.kinds) if kind.name == name]


def _key(cfg) -> tuple:
    """What a row's layout depends on."""
    d, s = cfg.design, cfg.scene
    return (d.La, d.Lb, d.m1, d.rest_angle_deg, d.stop_angle_deg, d.notch_angle_deg, d.notch_opening_deg,
            d.notch_back_face, d.notch_front_face, d.handrail_thickness, d.hook_radius, s.pitch, s.rise, s.frames)


def is_kept(cfg) -> bool:
    """Whether ``cfg``'s layout is kept from before in this process (:func:`nested_layout` then costs nothing)."""
    return _key(cfg) in _KEPT


def forget(cfg=None) -> None:
    """Drop ``cfg``'s kept layout, if any, or every kept layout (the next :func:`nested_layout` fits again)."""
    if cfg is None:
        _KEPT.clear()
    else:
        _KEPT.pop(_key(cfg), None)


def nested_layout(cfg) -> RowLayout:
    """The nested layout for ``cfg``, kept per design and scene (a fit takes seconds)."""
    key = _key(cfg)
    if key not in _KEPT:
        if len(_KEPT) >= 64:
            _KEPT.pop(next(iter(_KEPT)))
        _KEPT[key] = _build_nested(cfg)
    return _KEPT[key]


_KEPT: dict = {}  # the layouts worked out in this process, by what they depend on


def _build_nested(cfg) -> RowLayout:
    d, s = cfg.design, cfg.scene
    sc = build.side_card(d)
    n = int(sc["layers"])
    hollow = hollow_outline(sc)
    skewers = skewer_footprints(d)
    # the frame's own stopper skewers turn through its windows: the card keeps out of their way (no room to spare:
    # its hub bar meets them at the rest angle and the end stop)
    own = CS.batch_boolean([_swept([pin.rotate(-t) for t in _angles(d)]) for pin in skewers[1:]], m3.OpType.Add)
    pins = float(build.stopper_reach(d)[1]) * MM
    rail = handrail_footprint(d)  # the neighbours' handrails cross a narrow card; its own sits at its seat
    found, reasons = {}, []
    # a narrow card's plane: the wide neighbours' handrails cross it, and every skewer; a wide card's: the skewers
    for name, turning in (("narrow", [rail]), ("wide", [])):
        if reasons:  # no narrow card: the row is refused whatever the wide card does, and a fit that fails runs
            found[name] = (hollow, None, n)  # every start and layer count (20-40 s): the wide card is left hollow
            continue
        keep_out = forbidden(cfg, turning, skewers)
        if (hollow ^ (keep_out + own)).area() <= TOUCH_AREA:
            found[name] = (hollow, None, n)
            continue
        if name == "narrow" and (rail ^ keep_out).area() > TOUCH_AREA:
            # the card must carry its own handrail's tabs at the seat, where a neighbour's handrail passes: the two
            # handrails meet (they both span the robot's arm), and no card can be cut around that
            reasons.append("a frame's handrail lies in its neighbour's handrail's path (they meet as the frames "
                           "turn): no layout across the row separates them")
            found[name] = (hollow, None, n)
            continue
        nearest = None  # (misfit's sum of squares, layers, misfit) of the nearest miss
        for layers in layers_tried(n):  # fewer layers leave more card to place, more leave less for the cut to take
            card = dict(sc, layers=layers)
            extents, misfit, outline = fit_cut_card(card, keep_out, pins)
            if extents is not None:
                found[name] = (outline, tuple(float(x) for x in extents), layers)
                break
            miss = float(np.sum(misfit**2))
            if nearest is None or miss < nearest[0]:
                nearest = (miss, layers, misfit)
        else:
            _, layers, misfit = nearest
            reasons.append(f"no {name} card cut clear of its neighbours weighs and swings as the hollow card "
                           f"(nearest, {layers} layer{'s' if layers > 1 else ''}: mass {misfit[0]:+.1e}, inertia "
                           f"{misfit[1]:+.1e}, centre ({10 * misfit[2]:+.2f}, {10 * misfit[3]:+.2f}) mm)")
            found[name] = (hollow, None, n)
    narrow_t = found["narrow"][2] * build.CARD_THICKNESS
    spans = {"narrow": build.RAIL_SPAN, "wide": build.RAIL_SPAN + 2 * narrow_t + 2 * GAP}
    kinds = {name: FrameKind(name, spans[name], outline, extents, name == "wide", layers)
             for name, (outline, extents, layers) in found.items()}
    row = tuple(kinds["narrow" if i % 2 == 0 else "wide"] for i in range(s.frames))
    return RowLayout("nested", row, not reasons, "; ".join(reasons))


def layers_tried(n: int) -> tuple[int, ...]:
    """The layer counts a cut-away card tries, in order: the hollow card's, then more, then fewer."""
    return tuple(k for k in (n, n + 1, n + 2, n - 1) if 1 <= k <= build.RING_LAYERS_MAX + 2)


def identical_layout(cfg) -> RowLayout:
    """Every frame alike, its hollow side cards ``RAIL_SPAN`` apart in the same two planes, its counterbalance
    between them: the kit where no nested layout is found (and the kit as it was first drawn)."""
    sc = build.side_card(cfg.design)
    kind = FrameKind("identical", build.RAIL_SPAN, hollow_outline(sc), None, False, int(sc["layers"]))
    return RowLayout("identical", (kind,) * cfg.scene.frames, True, "")


def kit_layout(cfg) -> RowLayout:
    """The layout the kit draws: the nested one where it is found, else every frame alike (which then does not
    clear: the sheet says so)."""
    row = nested_layout(cfg)
    return row if row.found else identical_layout(cfg)


def nested_refusal(cfg) -> str:
    """Why the kit does not draw the nested layout ("" where it does)."""
    row = nested_layout(cfg)
    return "" if row.found else row.reason


def counterbalance_stacks(d) -> list[tuple[str, int, bool]]:
    """How a frame's counterbalance is stacked: (where, coins, clay on it) per stack. Two stacks, each on its coin seat
    on one side card's face (the narrow frames' inner faces, the wide frames' outer ones): the coins halved, the odd
    one on the near card, the clay on the far stack."""
    coins = int(build.counterbalance_load(d.m3)["coins"])
    return [(" (near)", (coins + 1) // 2, False), (" (far)", coins // 2, True)]


def reach_across(d, layout: RowLayout) -> float:
    """m: how far from the row's middle plane any frame's part reaches across (its cards' outer faces, its coin seats,
    coins and clay on them)."""
    load = build.counterbalance_load(d.m3)
    clay = float(load["clay"]) / build.CLAY_DENSITY / (math.pi * build.YEN_COIN_RADIUS**2)
    reach = 0.0
    for k in layout.kinds:
        outer = k.span / 2 + k.layers * build.CARD_THICKNESS
        if k.coins_outside:
            outer += build.CARD_THICKNESS + max(n * build.YEN_COIN_THICKNESS + (clay if with_clay else 0.0)
                                                for _, n, with_clay in counterbalance_stacks(d))
        reach = max(reach, outer)
    return reach


def crossbeam_gap(cfg, layout: RowLayout | None = None) -> float:
    """m: the two crossbeams' inner faces apart, ``CROSSBEAM_GAP_MIN`` or wider, ``GAP`` clear of every frame's
    parts in ``layout`` (the kit's unless given)."""
    row = layout or kit_layout(cfg)
    return max(CROSSBEAM_GAP_MIN, 2 * (reach_across(cfg.design, row) + GAP))
