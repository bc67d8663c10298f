"""A cutting template as SVG: every part a maker cuts at 1:1, and the stand's layout to scale.

Print at 100 %: one SVG unit is one millimetre and the page states its size in mm; a 50 mm bar
checks the print. Solid lines are cuts, dashed lines folds, small circles holes for a skewer or
the axle (each inside its card), gray dashed circles where coins go. Each part is a ``<g
class="part">``, and its caption (``<text class="caption">``) sits above it, never on it; the
browser test in tests/test_sheet_browser.py renders the page and checks that no caption
overlaps another or a part.

The model is 2D: it sets every length along the machine, not the widths across it. The strips are
cut ``STRIP_WIDTH`` wide and the handrail ``RAIL_SPAN`` long, choices named below, not modelled
values; the spring strip's width is the one width the model does set (``spring_strip.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from xml.sax.saxutils import escape

from ..config import Config
from .card import PAPER_CARD, Card
from .spring_strip import GLUE_TAB, STRIP_WIDTH, linear_equivalent, plan_strip

S = STRIP_WIDTH * 1e3  # mm, the drawn width of the frame, arm and torso cards
END = 4.0  # mm of card beyond a hole or a mark at a part's end, so the hole sits inside the card
HOLE = 1.2  # mm, hole radius for a 2 mm bamboo skewer (frames) or axle (the arm)
HOOK_LIP = 3.0  # mm: the arm's tip folded into the ⌜ hook; the model sees only its contact edge
RAIL_SPAN = 30.0  # mm: the handrail bridges a frame's two side cards; wider than the arm, not modelled
PIN = 1.0  # mm, a stopper skewer's radius as drawn
MARGIN = 10.0
PAGE_W = 190.0
CAPTION = 3.0  # font size, mm
LINE = 4.0  # caption line height, mm
GAP = 6.0  # between a part and the next caption

CUT = 'fill="none" stroke="black" stroke-width="0.25"'
FOLD = 'fill="none" stroke="black" stroke-width="0.25" stroke-dasharray="1.2,0.8"'
COIN = 'fill="none" stroke="gray" stroke-width="0.25" stroke-dasharray="0.8,0.8"'
MARK = 'stroke="red" stroke-width="0.3"'


def _rect(x, y, w, h, style=CUT) -> str:
    return f'<rect x="{x:.2f}" y="{y:.2f}" width="{w:.2f}" height="{h:.2f}" {style}/>'


def _line(x1, y1, x2, y2, style=FOLD) -> str:
    return f'<line x1="{x1:.2f}" y1="{y1:.2f}" x2="{x2:.2f}" y2="{y2:.2f}" {style}/>'


def _circle(x, y, r, style=CUT) -> str:
    return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{r:.2f}" {style}/>'


def _poly(points, style=CUT) -> str:
    return f'<polygon points="{" ".join(f"{x:.2f},{y:.2f}" for x, y in points)}" {style}/>'


@dataclass
class Part:
    """A part drawn in its own coordinates (mm, y down) inside [0, width] x [top, top + height]."""
    name: str
    caption: list[str]
    elements: list[str] = field(default_factory=list)
    width: float = 0.0
    top: float = 0.0
    height: float = 0.0


def swing_frame(cfg: Config) -> Part:
    d = cfg.design
    lb, la, h = d.Lb * 1e3, d.La * 1e3, d.h * 1e3
    seat, axis, cb = END, END + lb, END + lb + la
    right = cb + max(END, S / 2)
    half = S / 2
    if abs(h) <= half - END / 2:  # the counterbalance mark falls on the strip itself
        outline = [(0, -half), (right, -half), (right, half), (0, half)]
        top, bottom = -half, half
    elif h > 0:  # a tab across the frame line reaches the counterbalance (frame-local +y is up)
        reach = -h - END
        outline = [(0, -half), (cb - half, -half), (cb - half, reach), (right, reach), (right, half), (0, half)]
        top, bottom = reach, half
    else:
        reach = -h + END
        outline = [(0, -half), (right, -half), (right, reach), (cb - half, reach), (cb - half, half), (0, half)]
        top, bottom = -half, reach
    els = [_poly(outline), _circle(axis, 0, HOLE), _line(seat, -half - 1.5, seat, half + 1.5, MARK),
           _line(cb - 1.5, -h - 1.5, cb + 1.5, -h + 1.5, MARK), _line(cb - 1.5, -h + 1.5, cb + 1.5, -h - 1.5, MARK)]
    return Part("swing frame", [
        f"SWING FRAME: cut 2 per frame (its two side cards), {2 * cfg.scene.frames} in all. Hole: the skewer.",
        f"Red line: the handrail's seat, Lb = {lb:.1f} mm from the hole. Red cross: the counterbalance's centre,",
        f"La = {la:.1f} mm along and h = {h:+.1f} mm across (m3 = {d.m3 * 1e3:.2f} g per frame, between the two cards).",
    ], els, right, top, bottom - top)


def handrail(cfg: Config) -> Part:
    d = cfg.design
    back, front = d.notch_back_face * 1e3, d.notch_front_face * 1e3
    els = [_rect(0, 0, RAIL_SPAN, back + front), _line(0, back, RAIL_SPAN, back)]
    # beside it, the L's end view on the frame line at 1:1 (frame-local, the frame line horizontal)
    x0, y0 = RAIL_SPAN + 12.0, (back + front) / 2
    tilt = math.radians(d.notch_angle_deg - d.rest_angle_deg)
    half = math.radians(d.notch_opening_deg) / 2
    n_back = (math.cos(tilt - half), math.sin(tilt - half))
    n_front = (math.cos(tilt + half), math.sin(tilt + half))
    ends = [(x0 + n_front[0] * back, y0 - n_front[1] * back), (x0 + n_back[0] * front, y0 - n_back[1] * front)]
    els += [_line(x0 - 4, y0, x0 + 14, y0, 'stroke="gray" stroke-width="0.4"'),
            _line(x0, y0, *ends[0], 'stroke="black" stroke-width="0.6"'),
            _line(x0, y0, *ends[1], 'stroke="black" stroke-width="0.6"')]
    xs = [x0 - 4, x0 + 14, *(e[0] for e in ends)]
    ys = [0.0, back + front, *(e[1] for e in ends)]
    width = max(xs) - min(0.0, min(xs))
    top, bottom = min(ys), max(ys)
    return Part("handrail", [
        f"HANDRAIL: cut 1 per frame, {RAIL_SPAN:.0f} mm long to bridge the frame's two side cards. Fold the dashed",
        f"line to an L of {d.notch_opening_deg:.0f} deg: back leg {back:.1f} mm, front leg {front:.1f} mm. Right: its end view",
        f"at 1:1 on the frame line (gray), corner on the seat, the L's bisector {math.degrees(tilt):+.1f} deg from the line.",
    ], els, width, top, bottom - top)


def arm(cfg: Config) -> Part:
    d = cfg.design
    length = d.arm_length * 1e3
    tip = END + length
    els = [_rect(0, 0, tip + HOOK_LIP, S), _circle(END, S / 2, HOLE), _line(tip, 0, tip, S)]
    return Part("arm", [
        f"ARM: cut 1. Hole: the axle. Hole to the dashed fold: {length:.1f} mm; fold the {HOOK_LIP:.0f} mm lip 90 deg",
        f"into the hook (it hooks the handrail's L). The arm and its lip weigh {d.arm_mass * 1e3:.2f} g in the model.",
    ], els, tip + HOOK_LIP, 0.0, S)


def torso(cfg: Config) -> Part:
    d = cfg.design
    length, coin_at, r = d.torso_length * 1e3, d.coin_offset * 1e3, d.coin_radius * 1e3
    bottom = END + length
    els = [_rect(0, 0, bottom, S), _circle(END, S / 2, HOLE), _circle(END + coin_at, S / 2, r, COIN)]
    card = d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass
    return Part("torso", [
        f"TORSO: cut 1. Hole: the axle; {length:.1f} mm from it to the bottom edge (Ld = {d.Ld * 1e3:.0f} mm from the hook",
        f"to this edge with the arm at {d.alpha_max_deg:.0f} deg). Coins ({d.coin_mass * 1e3:.1f} g) in the gray circle, "
        f"flush with the bottom; torso card {card * 1e3:.2f} g.",
    ], els, max(bottom, END + coin_at + r), S / 2 - r if r > S / 2 else 0.0, max(S, 2 * r))


def spring(cfg: Config, card: Card) -> Part:
    d = cfg.design
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    plan = plan_strip(linear_equivalent(d.spring_k, cfg.scene.effects.spring_law, bend), card, d.arm_length, bend)
    if plan.strip is None:
        return Part("leaf spring", ["LEAF SPRING: no strip of this card fits: " + plan.why_not + "."], [], 0.0, 0.0, 0.0)
    w, free, tab = plan.strip.width * 1e3, plan.strip.free_length * 1e3, GLUE_TAB * 1e3
    els = []
    for i in range(plan.strip.layers):
        y = i * (w + 3.0)
        els += [_rect(0, y, free + 2 * tab, w), _line(tab, y, tab, y + w), _line(tab + free, y, tab + free, y + w)]
    n = plan.strip.layers
    return Part("leaf spring", [
        f"LEAF SPRING: cut {n} strip{'s' if n > 1 else ''} {w:.1f} mm wide, {free:.1f} mm free between two {tab:.0f} mm "
        f"glue tabs{' (stacked loose)' if n > 1 else ''};",
        f"fold the tabs, glue one to the torso and one to the arm, straight with the arm at {d.alpha_min_deg:.0f} deg "
        f"({plan.stiffness * 1e3:.3f} N·mm/rad).",
    ], els, free + 2 * tab, 0.0, n * w + (n - 1) * 3.0)


def stand_scale(cfg: Config) -> int:
    d, s = cfg.design, cfg.scene
    span = (s.frames - 1) * s.pitch * 1e3 + (d.La + d.Lb) * 1e3 + 2 * END
    return next((k for k in (1, 2, 4, 5, 10, 20, 50) if span / k <= PAGE_W - 2 * MARGIN), 100)


def stand(cfg: Config) -> Part:
    """A side view of the row at 1:k: the skewer axes, each frame at its rest angle on its stopper,
    the end stop's skewer, and the floor."""
    d, s = cfg.design, cfg.scene
    k = stand_scale(cfg)
    f = 1e3 / k  # metres to drawn mm

    def at(x_m, y_m):  # world (y up) to drawing (y down)
        return x_m * f, -y_m * f

    rest, stop = math.radians(d.rest_angle_deg), math.radians(d.stop_angle_deg)
    dot = min(PIN, 4.0 / k)  # markers shrink with the scale, so a long row stays legible
    els, pts = [], []
    for i in range(s.frames):
        ax, ay = i * s.pitch, i * s.rise
        c, sn = math.cos(rest), math.sin(rest)
        a = at(ax - d.Lb * c, ay - d.Lb * sn)
        b = at(ax + d.La * c, ay + d.La * sn)
        els.append(_line(*a, *b, 'stroke="sienna" stroke-width="0.5"'))
        els.append(_circle(*at(ax, ay), dot, 'fill="black"'))
        # stopper skewers, on the counterbalance's arm halfway out: under it at rest, over it at the end stop
        for angle, side in ((rest, -1.0), (stop, 1.0)):
            r, off = d.La / 2, side * (S / 2 + 1.0) / 1e3  # a 2 mm skewer against the card's edge
            px = ax + r * math.cos(angle) - off * math.sin(angle)
            py = ay + r * math.sin(angle) + off * math.cos(angle)
            els.append(_circle(*at(px, py), dot, 'fill="none" stroke="blue" stroke-width="0.3"'))
            pts.append(at(px, py))
        pts += [a, b]
    x_first, x_last = -d.Lb, (s.frames - 1) * s.pitch + d.La
    fa = at(x_first, x_first / s.pitch * s.rise - s.floor_drop)
    fb = at(x_last, x_last / s.pitch * s.rise - s.floor_drop)
    els.append(_line(*fa, *fb, 'stroke="gray" stroke-width="0.5"'))
    pts += [fa, fb]
    x0 = min(p[0] for p in pts) - 2
    y0 = min(p[1] for p in pts) - 2
    els = [f'<g transform="translate({-x0:.2f},{-y0:.2f})">'] + els + ["</g>"]
    width = max(p[0] for p in pts) - x0 + 2
    height = max(p[1] for p in pts) - y0 + 2
    return Part("stand", [
        f"THE STAND, side view at 1:{k} (dimensions in mm at full size). {s.frames} skewer axes (black), each "
        f"{s.pitch * 1e3:.1f} mm",
        f"after the last and {s.rise * 1e3:+.1f} mm higher; the first {s.floor_drop * 1e3:.0f} mm above the floor "
        f"(gray). Frames (brown) rest at {d.rest_angle_deg:.0f} deg",
        f"on a stopper skewer (blue) under the counterbalance's side, {d.La * 1e3 / 2:.1f} mm out; a second one stops "
        f"them at {d.stop_angle_deg:.0f} deg.",
    ], els, width, 0.0, height)


def svg(cfg: Config, card: Card = PAPER_CARD) -> str:
    """The whole template: the check bar, then each part under its caption, then the stand."""
    parts = [swing_frame(cfg), handrail(cfg), arm(cfg), torso(cfg), spring(cfg, card), stand(cfg)]
    out = [f'<text class="caption" x="{MARGIN}" y="{MARGIN + CAPTION:.2f}" font-size="3.6" '
           f'font-family="sans-serif">aero-env template: print at 100 % (no fit-to-page); the bar must measure '
           f'50 mm</text>',
           f'<rect class="scale-bar" x="{MARGIN}" y="{MARGIN + 6:.2f}" width="50" height="2" fill="black"/>',
           f'<text class="caption" x="{MARGIN + 53}" y="{MARGIN + 8:.2f}" font-size="{CAPTION}" '
           f'font-family="sans-serif">50 mm</text>']
    y = MARGIN + 8 + GAP
    width = PAGE_W
    for p in parts:
        for line in p.caption:
            y += LINE
            out.append(f'<text class="caption" x="{MARGIN}" y="{y:.2f}" font-size="{CAPTION}" '
                       f'font-family="sans-serif">{escape(line)}</text>')
        y += 2.0
        if p.elements:
            out.append(f'<g class="part" id="{p.name.replace(" ", "-")}" transform="translate({MARGIN:.2f},'
                       f'{y - p.top:.2f})">')
            out += p.elements
            out.append("</g>")
        y += p.height + GAP
        width = max(width, MARGIN * 2 + p.width)
    height = y + MARGIN
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.1f}mm" height="{height:.1f}mm" '
            f'viewBox="0 0 {width:.1f} {height:.1f}">\n' + "\n".join(out) + "\n</svg>\n")
