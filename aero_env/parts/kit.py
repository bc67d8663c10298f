"""The kit: every piece a maker cuts for a design, as drawn shapes (mm) and as what it weighs.

:func:`pieces` turns a config into :class:`Piece`s, each drawn from :mod:`aero_env.parts.build`'s
dimensions (the same numbers the physics swings), and :func:`parts_json` lists them for
``parts.json``. The template (``aero_env/sheet/template.py``) only renders these shapes: ``cut``
outlines (holes included), ``fold`` lines, and ``mark``s that are neither (where a coin or the
handrail goes). A piece's card is its cut outline less its holes, times its layers, times the
card's grammage; its mass adds what is glued or pressed onto it (``added``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import build
from .card import PAPER_CARD, Card
from .spring_strip import GLUE_TAB, linear_equivalent, plan_strip

MM = 1e3  # the kit draws in mm; build.py is SI


@dataclass(frozen=True)
class Shape:
    """One drawn element in the piece's own mm coordinates (y down): ``rect`` (x, y, w, h), ``circle``
    (cx, cy, r), ``line`` (x1, y1, x2, y2) or ``polyline`` (x1, y1, x2, y2, ...); ``kind`` cut, fold or mark."""
    tag: str
    kind: str
    xy: tuple[float, ...]


@dataclass(frozen=True)
class Piece:
    name: str
    id: str  # its SVG group's id, "part-..."
    count: int  # pieces in the kit (each of ``layers`` layers)
    layers: int
    card_area_m2: float  # one layer's card: the cut outline less its holes
    added: tuple[tuple[str, float], ...]  # (what, kg) glued or pressed onto it
    sets: str  # the model field it makes up
    per_unit: int  # how many pieces make one of that field
    part_of: tuple[str, ...]  # other fields it is counted in (Table 1 counts the handrail in m2)
    caption: tuple[str, ...]
    shapes: tuple[Shape, ...] = field(default=())
    grammage: float = build.GRAMMAGE

    def __post_init__(self):  # plain floats and ints, whatever arrays build.py computed them with
        object.__setattr__(self, "card_area_m2", float(self.card_area_m2))
        object.__setattr__(self, "added", tuple((w, float(kg)) for w, kg in self.added))

    @property
    def cuts(self) -> int:
        """Copies to cut from card: every layer of every one of the kit's ``count`` (none for coins and clay)."""
        return self.count * self.layers if self.shapes else 0

    @property
    def mass_kg(self) -> float:
        return self.card_area_m2 * self.layers * self.grammage + sum(kg for _, kg in self.added)

    def json(self) -> dict:
        return dict(name=self.name, id=self.id, count=self.count, layers=self.layers,
                    grammage_kg_m2=self.grammage, card_area_m2=self.card_area_m2,
                    added=[dict(what=w, mass_kg=kg) for w, kg in self.added], mass_kg=self.mass_kg,
                    sets=self.sets, per_unit=self.per_unit, part_of=list(self.part_of))


def shapes_extent(shapes) -> tuple[float, float, float, float]:
    """(x0, y0, x1, y1): the box round a piece's shapes, in its own mm (y down)."""
    xs, ys = [], []
    for s in shapes:
        if s.tag == "rect":
            x, y, w, h = s.xy
            xs += [x, x + w]
            ys += [y, y + h]
        elif s.tag == "circle":
            x, y, r = s.xy
            xs += [x - r, x + r]
            ys += [y - r, y + r]
        else:
            xs += list(s.xy[0::2])
            ys += list(s.xy[1::2])
    return min(xs), min(ys), max(xs), max(ys)


def _rect(x, y, w, h, kind="cut") -> Shape:
    return Shape("rect", kind, (x, y, w, h))


def _circle(x, y, r, kind="cut") -> Shape:
    return Shape("circle", kind, (x, y, r))


def _line(x1, y1, x2, y2, kind="fold") -> Shape:
    return Shape("line", kind, (x1, y1, x2, y2))


def _cross(x, y, s=1.5) -> list[Shape]:
    return [_line(x - s, y - s, x + s, y + s, "mark"), _line(x - s, y + s, x + s, y - s, "mark")]


HOLE_R = build.HOLE_D * MM / 2
HOLE_TEXT = (f"Hole Ø{build.HOLE_D * MM:.1f} mm (punch or drill): a Ø{build.SKEWER_D * MM:.0f} mm bamboo skewer "
             f"turns in it")


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _layers_text(n: int) -> str:
    return "one layer" if n == 1 else f"{n} layers glued flat"


NARROWEST = max(build.MIN_STRIP, build.HOLE_D + 2 * 1e-3) * MM  # mm: scissors, and card around a hole


def _too_narrow(what: str, width: float) -> str:
    """A caption's warning for a piece narrower than scissors cut or than a hole needs, "" otherwise."""
    return (f" NOTE: {width:.1f} mm is narrower than the {NARROWEST:.1f} mm scissors and a hole need: this {what} "
            f"cannot be cut as the model has it (a lighter design than card allows)" if width < NARROWEST else "")


def side_card(cfg) -> Piece:
    d, frames = cfg.design, cfg.scene.frames
    sc = build.side_card(d)
    n, L, D, half = int(sc["layers"]), sc["length"] * MM, sc["depth"] * MM, sc["half_length"] * MM
    hollow, end, hub = bool(sc["hollow"]), float(sc["end"]) * MM, sc["hub"] * MM
    w_l, w_d = float(sc["window"]) * MM, float(sc["window_depth"]) * MM
    seat, cb, h = half - d.Lb * MM, half + d.La * MM, d.h * MM
    off_card = (f" NOTE: the cross lies {abs(d.h) * MM - D / 2:.1f} mm off the card (|h| > half its depth): glue a "
                f"scrap of card there to hold the counterbalance; the model leaves that scrap out."
                if abs(d.h) * MM > D / 2 else
                f" NOTE: the cross lies over a window (La < {half - end:.1f} mm from the hole): glue a scrap of card "
                f"across it to hold the counterbalance; the model leaves that scrap out."
                if hollow and d.La * MM < half - end - 1e-9 and abs(d.h) * MM < w_d / 2 else "")
    windows = [_rect(end, -w_d / 2, w_l, w_d), _rect(half + hub / 2, -w_d / 2, w_l, w_d)] if hollow else []
    shapes = [_rect(0, -D / 2, L, D), *windows, _circle(half, 0, HOLE_R),
              _line(seat, -D / 2, seat, D / 2, "mark"), *_cross(cb, -h)]
    area = (L * D - len(windows) * w_l * w_d - math.pi * HOLE_R**2) / MM**2
    shape = (f"{L:.1f} x {D:.1f} mm, hollow (the article's frame): two windows {w_l:.1f} x {w_d:.1f} mm cut out, "
             f"leaving strips {sc['strip'] * MM:.1f} mm wide along both edges, an end bar {end:.1f} mm long at each "
             f"end and a bar {hub:.1f} mm wide across the middle with the hole."
             if hollow else f"{L:.1f} x {D:.1f} mm, flat (no window of this design's fits: {no_ring(d)}).")
    return Piece(
        "swing frame side card", "part-frame-side-card", 2 * frames, n, area, (), "design.m1", 2, (),
        (f"SWING FRAME SIDE CARD: {_plural(2 * frames, 'card')} ({2 * frames * n} cuts): 2 per frame, each "
         f"{_layers_text(n)}; {shape}",
         f"{HOLE_TEXT} (the frame's axis). Black line: the handrail's seat, Lb = {d.Lb * MM:.1f} mm from the hole.",
         f"Black cross: the counterbalance's centre, La = {d.La * MM:.1f} mm along and h = {h:+.1f} mm across "
         f"(above the line when the seat is on the left).{off_card}{'' if hollow else _too_narrow('side card', D)}"),
        tuple(shapes))


def no_ring(d) -> str:
    """Why a design's side cards are flat: the stopper's window needs a travel under 178 deg."""
    return (f"the frame's travel, {d.stop_angle_deg - d.rest_angle_deg:g} deg, leaves no window the stopper fits"
            if not math.isfinite(float(build.stopper_reach(d)[0])) else
            f"no hollow card of 1-{build.RING_LAYERS_MAX} layers at most {build.RING_DEPTH_MAX * MM:.0f} mm deep "
            f"weighs design.m1 / 2")


def handrail(cfg) -> Piece:
    d, frames = cfg.design, cfg.scene.frames
    hr = build.handrail_card(d)
    back, front, tab, length = d.notch_back_face * MM, d.notch_front_face * MM, hr["tab"] * MM, hr["length"] * MM
    span = build.RAIL_SPAN * MM
    legs = back + front
    shapes = [_rect(0, 0, length, legs), _line(0, back, length, back)]
    if tab > 0:
        shapes += [_line(tab, 0, tab, legs), _line(tab + span, 0, tab + span, legs)]
    # beside it, the L's end view on the frame line at 1:1 (frame-local, the frame line horizontal)
    x0, y0 = length + 12.0, legs / 2
    tilt = math.radians(d.notch_angle_deg - d.rest_angle_deg)
    half = math.radians(d.notch_opening_deg) / 2
    n_back, n_front = (math.cos(tilt - half), math.sin(tilt - half)), (math.cos(tilt + half), math.sin(tilt + half))
    ends = [(x0 + n_front[0] * back, y0 - n_front[1] * back), (x0 + n_back[0] * front, y0 - n_back[1] * front)]
    shapes += [_line(x0 - 4, y0, x0 + 14, y0, "mark"), _line(x0, y0, *ends[0], "mark"),
               _line(x0, y0, *ends[1], "mark")]
    tab_text = (f"fold the {tab:.1f} mm tab at each end 90 deg and glue it inside a side card" if tab >= build.MIN_TAB
                * MM else f"its end tabs come out {tab:.1f} mm, shorter than the {build.MIN_TAB * MM:.0f} mm a glue "
                f"joint needs: design.handrail_mass is lighter than this L of card")
    return Piece(
        "handrail", "part-handrail", frames, 1, length * legs / MM**2, (), "design.handrail_mass", 1, ("design.m2",),
        (f"HANDRAIL: {_plural(frames, 'piece')}, 1 per frame, {length:.1f} x {legs:.1f} mm. Fold the long dashed line "
         f"to an L of {d.notch_opening_deg:.0f} deg:",
         f"back leg {back:.1f} mm, front leg {front:.1f} mm; {tab_text}, the L {span:.0f} mm between the cards.",
         f"Right: its end view at 1:1 on the frame line (horizontal), corner on the seat, the L's bisector "
         f"{math.degrees(tilt):+.1f} deg from the line."),
        tuple(shapes))


def counterbalance(cfg) -> Piece:
    d, frames = cfg.design, cfg.scene.frames
    load = build.counterbalance_load(d.m3)
    coins, clay = int(load["coins"]), float(load["clay"])
    r = 10.0
    added = ((f"{_plural(coins, 'one-yen coin')}", coins * build.YEN_COIN),) if coins else ()
    added += (("modelling clay", clay),) if clay > 0 else ()
    return Piece(
        "counterbalance", "part-counterbalance", frames, 0, 0.0, added, "design.m3", 1, (),
        (f"COUNTERBALANCE: {frames}, 1 per frame, no card: {_plural(coins, 'one-yen coin')} and {clay * 1e3:.2f} g of "
         f"modelling clay ({d.m3 * 1e3:.2f} g),",
         "pressed between the side cards, centred on the side card's black cross (the circle: a coin's size, "
         "not a cut)."),
        (_circle(r, 0, r, "mark"), *_cross(r, 0)))


def arm(cfg) -> Piece:
    d = cfg.design
    a = build.arm_plate(d)
    n, w, length = int(a["layers"]), a["width"] * MM, a["net_length"] * MM
    end, tip = build.END * MM, build.END * MM + d.arm_length * MM
    return Piece(
        "arm", "part-arm", 1, n, (length * w - math.pi * HOLE_R**2) / MM**2, (), "design.arm_mass", 1, ("design.m2",),
        (f"ARM: 1, {_layers_text(n)}; {length:.1f} x {w:.1f} mm. {HOLE_TEXT} (the robot's axle, through the "
         f"torso).{_too_narrow('arm', w)}",
         f"Hole to the dashed fold: {d.arm_length * MM:.1f} mm; fold the {build.HOOK_LIP * MM:.0f} mm lip 90 deg into "
         f"the hook that hooks the handrail's L ({d.arm_mass * 1e3:.2f} g)."),
        (_rect(0, 0, length, w), _circle(end, w / 2, HOLE_R), _line(tip, 0, tip, w)))


def torso(cfg) -> Piece:
    d = cfg.design
    t = build.torso_plate(d, d.torso_length)
    n, w, length = int(t["layers"]), t["width"] * MM, t["length"] * MM
    end, coin_at, r = build.END * MM, d.coin_offset * MM, d.coin_radius * MM
    stack = build.coin_stack(d)
    coins_text = f"{stack['coins']:.0f} one-yen coins" if stack["whole"] else f"{d.coin_mass * 1e3:.2f} g of coins"
    return Piece(
        "torso", "part-torso", 1, n, (length * w - math.pi * HOLE_R**2) / MM**2, ((coins_text, d.coin_mass),),
        "design.m2", 1, (),
        (f"TORSO: 1, {_layers_text(n)}; {length:.1f} x {w:.1f} mm. {HOLE_TEXT} (the axle).{_too_narrow('torso', w)}",
         f"Hole to the bottom edge: {d.torso_length * MM:.1f} mm (Ld = {d.Ld * MM:.0f} mm from the hook with the arm "
         f"at {d.alpha_max_deg:.0f} deg). Glue the {coins_text} in the black circle, flush with the bottom."),
        (_rect(0, 0, length, w), _circle(end, w / 2, HOLE_R), _circle(end + coin_at, w / 2, r, "mark")))


def spring_plan(cfg, card: Card = PAPER_CARD):
    """The strip of ``card`` that makes the design's spring (its ``strip`` None, with ``why_not``, when none can)."""
    d = cfg.design
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    return plan_strip(linear_equivalent(d.spring_k, cfg.scene.effects.spring_law, bend), card, d.arm_length, bend)


def no_spring(cfg, card: Card = PAPER_CARD) -> str:
    """Why no strip of ``card`` makes the design's spring, or "" when one does."""
    return spring_plan(cfg, card).why_not


def spring(cfg, card: Card = PAPER_CARD) -> Piece | None:
    d = cfg.design
    plan = spring_plan(cfg, card)
    if plan.strip is None:
        return None
    w, free, tab = plan.strip.width * MM, plan.strip.free_length * MM, GLUE_TAB * MM
    n = plan.strip.layers
    length = free + 2 * tab
    shapes = (_rect(0, 0, length, w), _line(tab, 0, tab, w), _line(tab + free, 0, tab + free, w))
    return Piece(
        "leaf spring", "part-leaf-spring", n, 1, length * w / MM**2, (), "design.spring_k", n, (),
        (f"LEAF SPRING: cut {_plural(n, 'strip')} {w:.1f} mm wide, {free:.1f} mm free between two {tab:.0f} mm glue "
         f"tabs{' (stacked loose, not glued to each other)' if n > 1 else ''}.",
         f"Fold the tabs; glue one to the torso and one to the arm, straight with the arm at {d.alpha_min_deg:.0f} deg "
         f"({plan.stiffness * 1e3:.3f} N·mm/rad)."),
        shapes)


def pieces(cfg, card: Card = PAPER_CARD) -> list[Piece]:
    """Every piece of the kit, in the order of work: the stand, the frames, the robot."""
    out = [*crossbeam_segments(cfg), *uprights(cfg), side_card(cfg), handrail(cfg), counterbalance(cfg), torso(cfg),
           arm(cfg)]
    strip = spring(cfg, card)
    return out + ([strip] if strip is not None else [])


MASS_FIELDS = ("design.m1", "design.m2", "design.m3", "design.arm_mass", "design.handrail_mass")


def field_masses(ps: list[Piece]) -> dict[str, float]:
    """What the pieces make of each mass field: the sum over the pieces that set it (or are part of it) of
    their mass times ``per_unit`` (that many of the piece make one of the field)."""
    out: dict[str, float] = {}
    for p in ps:
        for key in (p.sets, *p.part_of):
            if key in MASS_FIELDS:
                out[key] = out.get(key, 0.0) + p.mass_kg * p.per_unit
    return out


def parts_json(cfg, config_name: str = "") -> dict:
    ps = pieces(cfg)
    made = field_masses(ps)
    return dict(config=config_name, grammage_kg_m2=build.GRAMMAGE, card_thickness_m=build.CARD_THICKNESS,
                parts=[p.json() for p in ps],
                fields={k: dict(config=float(cfg.value(k)), parts=float(v)) for k, v in made.items()})


# ---- the stand at 1:1 ------------------------------------------------------------------------------------------
SEGMENT_MAX = 170.0  # mm: a crossbeam segment fits the template's width, so it prints at 1:1 on A4 and Letter
CROSSBEAM_LAYERS = 3  # a stiff strip: three layers glued flat (a choice; the stand's mass is not modelled)
UPRIGHT_WIDTH = 10.0  # mm
SNUG_R = build.SKEWER_D * MM / 2  # the crossbeam holds each skewer snug: the frames turn on it, it does not turn
CROSSBEAM_GAP = build.RAIL_SPAN + 20.0e-3  # m: the two crossbeams' inner faces apart, the frames between them
SKEWER_PROUD = 2.0e-3  # m: a skewer stands this far out of what holds it at each end, to grip and push it back out


def skewer_lengths(d) -> dict[str, float]:
    """Each skewer piece's length (m): an ``axis`` or a ``stopper`` spans the stand from one crossbeam's outer face
    to the other's; the robot's ``axle`` runs through the torso and across the arm's width. Each stands
    ``SKEWER_PROUD`` out at both ends. The bill of materials and the 3D stand read these."""
    beam = CROSSBEAM_LAYERS * build.CARD_THICKNESS
    torso = float(build.torso_plate(d, d.torso_length)["layers"]) * build.CARD_THICKNESS
    arm = float(build.arm_plate(d)["width"])
    across = CROSSBEAM_GAP + 2 * beam + 2 * SKEWER_PROUD
    return dict(axis=across, stopper=across, axle=arm + torso + 2 * SKEWER_PROUD)


def stopper_offsets(d) -> tuple[tuple[float, float], tuple[float, float]]:
    """World offsets (m) from a frame's axis of its two stopper skewers' centres, (rest, end). In the hollow card's
    window (:func:`aero_env.parts.build.stopper_radius`): the rest stopper meets the hub bar's edge with the frame at
    its rest angle, the end stopper with it at the end stop; each turns through the window between, so no other
    frame's card comes near it. A flat card's (no window): the rest stopper touches the card's edge below the
    counterbalance's arm, halfway out, at rest, and the end stopper the other edge at the end stop. The world's rotary
    limits are where these skewers hold the card."""
    sc = build.side_card(d)
    out = []
    for angle_deg, side in ((d.rest_angle_deg, 1.0), (d.stop_angle_deg, -1.0)):
        a = math.radians(angle_deg)
        if sc["hollow"]:  # against the hub bar's edge on the counterbalance's side, above the line at rest
            s = build.HUB_BAR / 2 + build.SKEWER_D / 2
            off = side * math.sqrt(float(build.stopper_radius(d)) ** 2 - s * s)
        else:  # against the card's edge, La/2 out: below the line at rest, above it at the end stop
            s, off = d.La / 2, -side * (float(sc["depth"]) / 2 + build.SKEWER_D / 2)
        out.append((s * math.cos(a) - off * math.sin(a), s * math.sin(a) + off * math.cos(a)))
    return out[0], out[1]


FRAME_MARK = 12.0  # mm: the frame line at rest, marked from each axis hole on the crossbeam (the card holds it)
STOPPERS_IN_WINDOW = " (through the side cards' window, against the hub bar)"


def crossbeam_band(cfg) -> dict:
    """The crossbeam's lay-out in its own coordinates (mm): u along the row's incline from frame 0's axis, v up from
    the axes' line. ``beta`` (rad) the incline, ``step`` axis to axis, ``rest`` and ``stop`` the stopper holes' (u, v)
    from their axis, and the band's edges about one axis: ``u_lo``, ``u_hi``, ``v_lo``, ``v_hi``, each hole ``END``
    inside the card. The kit's segments and the 3D stand (:mod:`aero_env.parts.solids`) both read it."""
    d, s = cfg.design, cfg.scene
    beta = math.atan2(s.rise, s.pitch)
    cb, sb = math.cos(beta), math.sin(beta)

    def along(w):  # a world offset (m) to crossbeam coordinates (mm): u along the incline, v up from it
        return (w[0] * cb + w[1] * sb) * MM, (-w[0] * sb + w[1] * cb) * MM

    rest, stop = (along(w) for w in stopper_offsets(d))
    ray = math.radians(d.rest_angle_deg) - beta  # the frame line at rest, in the beam's frame: its mark on the card
    mark = (FRAME_MARK * math.cos(ray), FRAME_MARK * math.sin(ray))
    vs = [0.0, rest[1], stop[1], mark[1]]
    us = [0.0, rest[0], stop[0], mark[0]]
    return dict(beta=beta, step=math.hypot(s.pitch, s.rise) * MM, rest=rest, stop=stop,
                u_lo=min(us) - build.END * MM - SNUG_R, u_hi=max(us) + build.END * MM + SNUG_R,
                v_lo=min(vs) - build.END * MM - SNUG_R, v_hi=max(vs) + build.END * MM + SNUG_R)


def crossbeam_segments(cfg) -> list[Piece]:
    """The crossbeam at 1:1, along the row's incline: every frame's axis hole and both its stopper holes, the
    rest angle and the counterbalance's side marked. A long row is cut in segments that overlap by one axis:
    a skewer through the shared holes lines them up before they are glued."""
    d, s = cfg.design, cfg.scene
    band = crossbeam_band(cfg)
    beta, step, rest, stop = band["beta"], band["step"], band["rest"], band["stop"]
    u_lo, u_hi, v_lo, v_hi = band["u_lo"], band["u_hi"], band["v_lo"], band["v_hi"]
    per = max(1, int((SEGMENT_MAX - (u_hi - u_lo)) // step))  # axis steps a segment spans
    starts = list(range(0, s.frames - 1, per)) or [0]
    segments = []
    ray = math.radians(d.rest_angle_deg) - beta  # the frame line at rest, counterbalance side, in the beam's frame
    in_window = STOPPERS_IN_WINDOW if build.side_card(d)["hollow"] else ""
    for k, a in enumerate(starts):
        b = min(a + per, s.frames - 1)
        x0 = a * step + u_lo
        width, height = (b - a) * step + (u_hi - u_lo), v_hi - v_lo
        shapes = [_rect(0, 0, width, height)]
        holes = 0
        for i in range(a, b + 1):
            ux, vy = i * step - x0, v_hi  # the axis, in the drawing (y down)
            shapes.append(_circle(ux, vy, SNUG_R))
            for su, sv in (rest, stop):
                shapes.append(_circle(ux + su, vy - sv, SNUG_R))
            holes += 3
            shapes.append(_line(ux, vy, ux + FRAME_MARK * math.cos(ray), vy - FRAME_MARK * math.sin(ray), "mark"))
        area = width * height - holes * math.pi * SNUG_R**2
        n = len(starts)
        first = (f"CROSSBEAM{f', SEGMENT {k + 1} of {n}' if n > 1 else ''}: cut 2 (one per side of the row), "
                 f"{_layers_text(CROSSBEAM_LAYERS)}; {width:.1f} x {height:.1f} mm, frames {a}-{b}.")
        rest_text = (f"Holes Ø{2 * SNUG_R:.1f} mm, the skewers snug: on the beam's line each frame's axis, "
                     f"{step:.1f} mm apart ({s.pitch * MM:.1f} mm pitch, {s.rise * MM:+.1f} mm rise); beside each, the "
                     f"rest stopper and the end stopper{in_window}. Black line: the frame line at rest "
                     f"({d.rest_angle_deg:.0f} deg from level), pointing to the counterbalance's side; the "
                     f"crossbeam's line rises {math.degrees(beta):.1f} deg, so stand it with the line at that angle "
                     f"to the floor.")
        caption = (first, rest_text) if k == 0 else (
            first, f"Overlap segment {k}'s last axis: a skewer through the shared holes lines them up; glue.")
        segments.append(Piece(f"crossbeam {k + 1}", f"part-crossbeam-{k + 1}", 2, CROSSBEAM_LAYERS, area / MM**2, (),
                              "scene.pitch", 1, ("scene.rise", "design.rest_angle_deg", "design.stop_angle_deg"),
                              caption, tuple(shapes)))
    return segments


def base_board(cfg) -> tuple[float, float]:
    """(length, width) in m of the board the stand stands on: the row's length and 60 mm each way past the end
    axes; 60 mm across, wider than the crossbeams' span."""
    return (cfg.scene.frames - 1) * cfg.scene.pitch + 0.12, 0.06


def uprights(cfg) -> list[Piece]:
    """The four legs that hold the crossbeams: the first axis floor_drop above a level floor, the last one the row's
    rise higher (the world's floor follows the row; a table does not, and only a fall reaches it)."""
    s = cfg.scene
    w, foot = UPRIGHT_WIDTH, 10.0
    out = []
    low = (s.floor_drop + min(0.0, (s.frames - 1) * s.rise)) * MM
    if low < foot:  # the lowest axis at or below the foot: there is no upright to cut
        from ..config import ConfigError

        if s.floor_drop * MM < foot:  # the first axis itself: no rise can lift it
            raise ConfigError(f"scene.floor_drop = {s.floor_drop!r}: the first axis would stand "
                              f"{s.floor_drop * MM:.1f} mm above the base; the stand needs at least {foot:.0f} mm, "
                              f"allowed floor_drop >= {foot / MM:g} m")
        # a descending row that ends at or below the base
        raise ConfigError(f"scene.rise = {s.rise!r}: over {s.frames} frames the last axis would stand {low:.1f} mm "
                          f"above the base (scene.floor_drop = {s.floor_drop!r}); the stand needs at least "
                          f"{foot:.0f} mm, allowed rise >= {(foot / MM - s.floor_drop) / (s.frames - 1):.4g} m")
    for end, frame, height in (("first", 0, s.floor_drop * MM), ("last", s.frames - 1,
                                                                   (s.floor_drop + (s.frames - 1) * s.rise) * MM)):
        length = height + foot
        caption = (f"UPRIGHT UNDER THE {end.upper()} AXIS: cut 2, {_layers_text(CROSSBEAM_LAYERS)}; {length:.1f} x "
                   f"{w:.0f} mm: frame {frame}'s axis {height:.1f} mm above the base; fold the {foot:.0f} mm foot and "
                   f"glue it to the base.",)
        if end == "last":
            base = base_board(cfg)
            caption += (f"BASE: any stiff board {base[0] * MM:.0f} x {base[1] * MM:.0f} mm, level; the two "
                        f"crossbeams stand {CROSSBEAM_GAP * MM:.0f} mm apart, the frames between them.",)
        out.append(Piece(f"upright under the {end} axis", f"part-upright-{end}", 2, CROSSBEAM_LAYERS,
                         length * w / MM**2, (), "scene.floor_drop", 1, (), caption,
                         (_rect(0, 0, w, length), _line(0, length - foot, w, length - foot))))  # upright
    return out
