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
from .layout import CLEAR, counterbalance_stacks, crossbeam_gap, kit_layout, nested_refusal
from .layout import moments as layout_moments
from .spring_strip import GLUE_TAB, linear_equivalent, plan_strip

MM = 1e3  # the kit draws in mm; build.py is SI


@dataclass(frozen=True)
class Shape:
    """One drawn element in the piece's own mm coordinates (y down): ``rect`` (x, y, w, h), ``circle``
    (cx, cy, r), ``line`` (x1, y1, x2, y2) or ``polygon`` (x1, y1, x2, y2, ..., closed); ``kind`` cut, fold or
    mark."""
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
    share: float = 1.0  # of the row's units of its field this piece makes (a kind of frame's own piece: its frames')

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
                    sets=self.sets, per_unit=self.per_unit, part_of=list(self.part_of), share=self.share)


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


def _which(frames: list[int], total: int, kind: str) -> tuple[str, str]:
    """(title's suffix, caption's words) for a piece that serves only some frames of the row."""
    if len(frames) == total:
        return "", ""
    return f", {kind.upper()} FRAMES", f"frames {', '.join(str(i) for i in frames)} ({kind}); "


def side_card(cfg, frames_served: list[int] | None = None, kind: str = "") -> Piece:
    """The hollow side card, for every frame (or ``frames_served``, the ``kind`` of frame that keeps it whole)."""
    d = cfg.design
    served = list(range(cfg.scene.frames)) if frames_served is None else frames_served
    frames = len(served)
    title, which = _which(served, cfg.scene.frames, kind)
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
        "swing frame side card" + (f", {kind} frames" if title else ""),
        "part-frame-side-card" + (f"-{kind}" if title else ""), 2 * frames, n,
        area, (), "design.m1", 2, (),
        (f"SWING FRAME SIDE CARD{title}: {_plural(2 * frames, 'card')} ({2 * frames * n} cuts): {which}2 per frame, "
         f"each {_layers_text(n)}; {shape}",
         f"{HOLE_TEXT} (the frame's axis). Black line: the handrail's seat, Lb = {d.Lb * MM:.1f} mm from the hole.",
         f"Black cross: the counterbalance's centre, La = {d.La * MM:.1f} mm along and h = {h:+.1f} mm across "
         f"(above the line when the seat is on the left).{off_card}{'' if hollow else _too_narrow('side card', D)}"),
        tuple(shapes), share=frames / cfg.scene.frames)


def cut_side_card(cfg, frames_served: list[int], kind) -> Piece:
    """A side card cut away where its neighbours' parts pass (:mod:`aero_env.parts.layout`): its outline as drawn,
    the hole at its origin, the seat's line and the counterbalance's cross as on the hollow card."""
    d = cfg.design
    frames, n = len(frames_served), kind.layers
    title, which = _which(frames_served, cfg.scene.frames, kind.name)
    half = float(build.side_card(d)["half_length"]) * MM
    polys = [[(float(u), float(v)) for u, v in poly] for poly in kind.outline.to_polygons()]

    def signed(poly):  # shoelace: positive for an outline, negative for a hole in it
        return sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1])) / 2

    hole_r = build.HOLE_D * MM / 2
    holes = [p for p in polys if signed(p) < 0]
    shapes = [Shape("polygon", "cut", tuple(c for u, v in p for c in (u + half, -v)))
              for p in sorted(polys, key=signed, reverse=True)  # the outline first, then its windows
              if signed(p) > 0 or max(math.hypot(u, v) for u, v in p) > hole_r + 1e-6]
    shapes.append(_circle(half, 0, HOLE_R))
    area = layout_moments(kind.outline)[0]
    vs = [v for p in polys for _, v in p]
    seat, cb, h = half - d.Lb * MM, half + d.La * MM, d.h * MM
    shapes += [_line(seat, -max(vs), seat, -min(vs), "mark"), *_cross(cb, -h)]
    us = [u for p in polys for u, _ in p]
    assert len(holes) >= 1  # the skewer's hole is a hole in the card
    return Piece(
        f"swing frame side card, {kind.name} frames", f"part-frame-side-card-{kind.name}", 2 * frames, n,
        area / MM**2, (), "design.m1", 2, (),
        (f"SWING FRAME SIDE CARD{title}: {_plural(2 * frames, 'card')} ({2 * frames * n} cuts): {which}2 per "
         f"frame, each {_layers_text(n)}; cut along the red outline ({max(us) - min(us):.1f} x {max(vs) - min(vs):.1f}"
         f" mm overall): it keeps {CLEAR:.0f} mm clear of where the neighbouring frames' handrails and the skewers "
         f"pass, and weighs, balances and swings as the hollow card.",
         f"{HOLE_TEXT} (the frame's axis). Black line: the handrail's seat, Lb = {d.Lb * MM:.1f} mm from the hole.",
         f"Black cross: the counterbalance's centre, La = {d.La * MM:.1f} mm along and h = {h:+.1f} mm across "
         f"(above the line when the seat is on the left)."),
        tuple(shapes), share=frames / cfg.scene.frames)


def side_cards(cfg) -> list[Piece]:
    """The side cards the kit's layout asks for: one hollow card for every frame, or in the nested layout the
    narrow frames' (cut away, if their card is cut) and the wide frames'."""
    row = kit_layout(cfg)
    if row.name != "nested":
        return [side_card(cfg)]
    return [side_card(cfg, served, kind.name) if kind.extents is None else cut_side_card(cfg, served, kind)
            for kind, served in row.by_kind()]


def no_ring(d) -> str:
    """Why a design's side cards are flat: the stopper's window needs a travel under 178 deg."""
    return (f"the frame's travel, {d.stop_angle_deg - d.rest_angle_deg:g} deg, leaves no window the stopper fits"
            if not math.isfinite(float(build.stopper_reach(d)[0])) else
            f"no hollow card of 1-{build.RING_LAYERS_MAX} layers at most {build.RING_DEPTH_MAX * MM:.0f} mm deep "
            f"weighs design.m1 / 2")


def handrail(cfg, frames_served: list[int] | None = None, kind: str = "", span_m: float = build.RAIL_SPAN) -> Piece:
    """The handrail L for every frame (or ``frames_served``, whose cards stand ``span_m`` apart)."""
    d = cfg.design
    served = list(range(cfg.scene.frames)) if frames_served is None else frames_served
    frames = len(served)
    title, which = _which(served, cfg.scene.frames, kind)
    hr = build.handrail_card(d)
    span = span_m * MM
    back, front, length = d.notch_back_face * MM, d.notch_front_face * MM, hr["length"] * MM
    tab = (length - span) / 2
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
    suffix = f"-{kind}" if title else ""
    return Piece(
        f"handrail{', ' + kind + ' frames' if title else ''}", f"part-handrail{suffix}", frames, 1,
        length * legs / MM**2, (), "design.handrail_mass", 1, ("design.m2",),
        (f"HANDRAIL{title}: {_plural(frames, 'piece')}, {which}1 per frame, {length:.1f} x {legs:.1f} mm. Fold the "
         f"long dashed line to an L of {d.notch_opening_deg:.0f} deg:",
         f"back leg {back:.1f} mm, front leg {front:.1f} mm; {tab_text}, the L {span:.1f} mm between the cards.",
         f"Right: its end view at 1:1 on the frame line (horizontal), corner on the seat, the L's bisector "
         f"{math.degrees(tilt):+.1f} deg from the line."),
        tuple(shapes), share=frames / cfg.scene.frames)


def handrails(cfg) -> list[Piece]:
    """One handrail for every frame, or in the nested layout the narrow frames' and the wide frames' (the same L,
    its tabs shorter where the cards stand wider apart)."""
    row = kit_layout(cfg)
    if row.name != "nested":
        return [handrail(cfg)]
    return [handrail(cfg, served, kind.name, kind.span) for kind, served in row.by_kind()]


def counterbalance(cfg) -> Piece:
    d, frames = cfg.design, cfg.scene.frames
    load = build.counterbalance_load(d.m3)
    coins, clay, seats = int(load["coins"]), float(load["clay"]), float(load["seats"])
    r = build.YEN_COIN_RADIUS * MM
    added = ((f"{_plural(coins, 'one-yen coin')}", coins * build.YEN_COIN),) if coins else ()
    added += (("modelling clay", clay),) if clay > 0 else ()
    return Piece(
        "counterbalance", "part-counterbalance", frames, 0, 0.0, added, "design.m3", 1, (),
        (f"COUNTERBALANCE: {frames}, 1 per frame: {_plural(coins, 'one-yen coin')} and {clay * 1e3:.2f} g of "
         f"modelling clay, on {build.COIN_SEATS} coin seats of card ({seats * 1e3:.2f} g): {d.m3 * 1e3:.2f} g in all,",
         _placement(cfg)),
        (_circle(r, 0, r, "mark"), *_cross(r, 0)))


def coin_seat(cfg) -> Piece:
    """The counterbalance's coin seats: a square of card a little wider than a coin under each stack."""
    frames, n = cfg.scene.frames, build.COIN_SEATS
    r = (build.YEN_COIN_RADIUS + build.COIN_RIM) * MM
    return Piece(
        "coin seat", "part-coin-seat", n * frames, 1, build.coin_seat_area(), (), "design.m3", n, (),
        (f"COIN SEAT: {_plural(n * frames, 'square')} ({n * frames} cuts), {n} per frame, one layer: {2 * r:.1f} x "
         f"{2 * r:.1f} mm, {build.COIN_RIM * MM:.1f} mm wider each side than a coin (the circle).",
         "Glue one on each side card's face where its stack of the counterbalance goes, centred on the black cross, "
         "then the stack on it: it holds the coins on card whatever the card's windows do under them. The seats are "
         "part of m3."),
        (_rect(0, 0, 2 * r, 2 * r), _circle(r, r, build.YEN_COIN_RADIUS * MM, "mark"), *_cross(r, r)))


def _placement(cfg) -> str:
    """Where the counterbalance goes, in the kit's layout."""
    row = kit_layout(cfg)
    clay = float(build.counterbalance_load(cfg.design.m3)["clay"]) > 0

    def stack(coins: int, with_clay: bool) -> str:
        return " and ".join([_plural(coins, "coin")] * (coins > 0) + ["the clay"] * (with_clay and clay)) or "nothing"

    near, far = counterbalance_stacks(cfg.design)
    stacks = (f"{stack(*near[1:])} on the near card, {stack(*far[1:])} on the far card, each on its coin seat, "
              f"centred on the card's black cross (the circle: a coin's size, not a cut).")
    inside = f"glued on the side cards' inner faces: {stacks}"
    if row.name != "nested":
        return f"In two stacks {inside}"
    narrow, wide = (", ".join(str(i) for i in row.frames_of(kind)) for kind in ("narrow", "wide"))
    return (f"In two stacks. Narrow frames ({narrow}): {inside} Wide frames ({wide}): outside, where no other "
            f"frame's card passes, glued on the cards' outer faces, the same stacks.")


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
    out = [*crossbeam_segments(cfg), *uprights(cfg), *side_cards(cfg), *handrails(cfg), counterbalance(cfg),
           coin_seat(cfg), torso(cfg), arm(cfg)]
    strip = spring(cfg, card)
    return out + ([strip] if strip is not None else [])


MASS_FIELDS = ("design.m1", "design.m2", "design.m3", "design.arm_mass", "design.handrail_mass")


def field_masses(ps: list[Piece]) -> dict[str, float]:
    """What the pieces make of each mass field: the sum over the pieces that set it (or are part of it) of
    their mass times ``per_unit`` (that many of the piece make one of the field) times ``share`` (the part of the
    row's frames it serves, where each kind of frame has its own piece)."""
    out: dict[str, float] = {}
    for p in ps:
        for key in (p.sets, *p.part_of):
            if key in MASS_FIELDS:
                out[key] = out.get(key, 0.0) + p.mass_kg * p.per_unit * p.share
    return out


def parts_json(cfg, config_name: str = "") -> dict:
    ps = pieces(cfg)
    made = field_masses(ps)
    row = kit_layout(cfg)
    layout = dict(name=row.name, frames=[k.name for k in row.kinds],
                  nested_refused=nested_refusal(cfg))
    return dict(config=config_name, grammage_kg_m2=build.GRAMMAGE, card_thickness_m=build.CARD_THICKNESS,
                layout=layout, parts=[p.json() for p in ps],
                fields={k: dict(config=float(cfg.value(k)), parts=float(v)) for k, v in made.items()})


# ---- the stand at 1:1 ------------------------------------------------------------------------------------------
SEGMENT_MAX = 170.0  # mm: a crossbeam segment fits the template's width, so it prints at 1:1 on A4 and Letter
CROSSBEAM_LAYERS = 3  # a stiff strip: three layers glued flat (a choice; the stand's mass is not modelled)
UPRIGHT_WIDTH = 10.0  # mm
UPRIGHT_FOOT = 10.0  # mm: the upright's foot, folded and glued to the base
SNUG_R = build.SKEWER_D * MM / 2  # the crossbeam holds each skewer snug: the frames turn on it, it does not turn
SKEWER_PROUD = 2.0e-3  # m: a skewer stands this far out of what holds it at each end, to grip and push it back out


def axle_length(d) -> float:
    """m: the robot's axle runs through the torso and across the arm's width, ``SKEWER_PROUD`` out at each end."""
    torso = float(build.torso_plate(d, d.torso_length)["layers"]) * build.CARD_THICKNESS
    return float(build.arm_plate(d)["width"]) + torso + 2 * SKEWER_PROUD


def skewer_lengths(cfg, layout=None) -> dict[str, float]:
    """Each skewer piece's length (m): an ``axis`` or a ``stopper`` spans the stand from one crossbeam's outer face
    to the other's (:func:`aero_env.parts.layout.crossbeam_gap`, in the kit's layout unless ``layout`` is given);
    the robot's ``axle`` (:func:`axle_length`). Each stands ``SKEWER_PROUD`` out at both ends. The bill of
    materials and the 3D stand read these."""
    beam = CROSSBEAM_LAYERS * build.CARD_THICKNESS
    across = crossbeam_gap(cfg, layout) + 2 * beam + 2 * SKEWER_PROUD
    return dict(axis=across, stopper=across, axle=axle_length(cfg.design))


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

    rest, stop = (along(w) for w in build.stopper_offsets(d))
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


def check_stand(cfg) -> None:
    """Refuse, in one line naming the field, a row whose lowest axis stands below the uprights' foot: there is no
    upright to cut. The sheet asks before any work (the layout's fit takes seconds to a minute)."""
    s, foot = cfg.scene, UPRIGHT_FOOT
    low = (s.floor_drop + min(0.0, (s.frames - 1) * s.rise)) * MM
    if low < foot:  # the lowest axis at or below the foot
        from ..config import ConfigError

        if s.floor_drop * MM < foot:  # the first axis itself: no rise can lift it
            raise ConfigError(f"scene.floor_drop = {s.floor_drop!r}: the first axis would stand "
                              f"{s.floor_drop * MM:.1f} mm above the base; the stand needs at least {foot:.0f} mm, "
                              f"allowed floor_drop >= {foot / MM:g} m")
        # a descending row that ends at or below the base
        raise ConfigError(f"scene.rise = {s.rise!r}: over {s.frames} frames the last axis would stand {low:.1f} mm "
                          f"above the base (scene.floor_drop = {s.floor_drop!r}); the stand needs at least "
                          f"{foot:.0f} mm, allowed rise >= {(foot / MM - s.floor_drop) / (s.frames - 1):.4g} m")


def check_counterbalance(cfg) -> None:
    """Refuse, in one line naming the field, a counterbalance lighter than the coin seats it sits on: no kit makes it.
    The simulator runs such an m3 as given (a unit slip warns, an experiment may mean it); the sheet cannot draw it."""
    seats = build.coin_seats_mass()
    if cfg.design.m3 < seats:
        from ..config import ConfigError

        raise ConfigError(f"design.m3 = {cfg.design.m3!r}: lighter than the {build.COIN_SEATS} coin seats of card the "
                          f"counterbalance sits on ({seats:.4g} kg): no kit can make it, allowed m3 >= {seats:.4g} kg")


def uprights(cfg) -> list[Piece]:
    """The four legs that hold the crossbeams: the first axis floor_drop above a level floor, the last one the row's
    rise higher (the world's floor follows the row; a table does not, and only a fall reaches it)."""
    check_stand(cfg)
    s = cfg.scene
    w, foot = UPRIGHT_WIDTH, UPRIGHT_FOOT
    out = []
    for end, frame, height in (("first", 0, s.floor_drop * MM), ("last", s.frames - 1,
                                                                   (s.floor_drop + (s.frames - 1) * s.rise) * MM)):
        length = height + foot
        caption = (f"UPRIGHT UNDER THE {end.upper()} AXIS: cut 2, {_layers_text(CROSSBEAM_LAYERS)}; {length:.1f} x "
                   f"{w:.0f} mm: frame {frame}'s axis {height:.1f} mm above the base; fold the {foot:.0f} mm foot and "
                   f"glue it to the base.",)
        if end == "last":
            base = base_board(cfg)
            caption += (f"BASE: any stiff board {base[0] * MM:.0f} x {base[1] * MM:.0f} mm, level; the two "
                        f"crossbeams stand {crossbeam_gap(cfg) * MM:.1f} mm apart, the frames between them.",)
        out.append(Piece(f"upright under the {end} axis", f"part-upright-{end}", 2, CROSSBEAM_LAYERS,
                         length * w / MM**2, (), "scene.floor_drop", 1, (), caption,
                         (_rect(0, 0, w, length), _line(0, length - foot, w, length - foot))))  # upright
    return out
