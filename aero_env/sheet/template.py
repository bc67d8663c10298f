"""A cutting template as SVG: every piece of the kit at 1:1, and the stand's layout to scale.

Print at 100 %: one SVG unit is one millimetre and the page states its size in mm; a 50 mm bar
checks the print. The pieces are the kit's (``aero_env/parts/kit.py``), drawn from the same
dimensions the physics swings. Each is a ``<g class="part" id="part-...">``; inside it every line
says what it is twice, by its class and by its colour, the convention cutting plotters and laser
cutters read as layers: ``cut`` (red, solid: cut through, holes included), ``fold`` (blue, dashed:
score, then fold) and ``mark`` (black: print only; where the handrail sits, the counterbalance's
centre, a coin's place). Each caption (``<text class="caption">``) sits above its piece, never on
it; the browser test in tests/test_sheet_browser.py renders the page and checks that no caption
overlaps another or a part.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass, field
from xml.sax.saxutils import escape

from ..config import Config
from ..parts.build import END as END_M
from ..parts.build import side_card, stopper_radius
from ..parts.card import PAPER_CARD, Card
from ..parts.build import stopper_offsets
from ..parts.kit import HOLE_R, Piece, Shape, no_spring, pieces, shapes_extent

END = END_M * 1e3  # mm
HOLE = HOLE_R  # mm, the hole radius for a skewer (frames) or the axle (the arm and torso)
PIN = 1.0  # mm, a stopper skewer's radius as drawn
MARGIN = 10.0
PAGE_W = 190.0  # mm: fits A4 (210 mm) and US Letter (215.9 mm) with a printer's margins
CAPTION = 3.0  # font size, mm
LINE = 4.0  # caption line height, mm
GAP = 6.0  # between a part and the next caption
WRAP = 100  # characters to a caption line: 3 mm sans-serif stays inside the page's 170 mm

CUT = 'fill="none" stroke="#ff0000" stroke-width="0.25"'
FOLD = 'fill="none" stroke="#0000ff" stroke-width="0.25" stroke-dasharray="1.2,0.8"'
MARK = 'fill="none" stroke="black" stroke-width="0.3"'
LEGEND = ("Red solid: cut (holes too). Blue dashed: score, then fold. Black: marks, not cut. "
          "Cut every piece as many times as its caption says.")


def _rect(x, y, w, h, style=CUT) -> str:
    return f'<rect x="{x:.2f}" y="{y:.2f}" width="{w:.2f}" height="{h:.2f}" {style}/>'


def _line(x1, y1, x2, y2, style=FOLD) -> str:
    return f'<line x1="{x1:.2f}" y1="{y1:.2f}" x2="{x2:.2f}" y2="{y2:.2f}" {style}/>'


def _circle(x, y, r, style=CUT) -> str:
    return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{r:.2f}" {style}/>'


STYLES = {"cut": CUT, "fold": FOLD, "mark": MARK}


def render(shape: Shape) -> str:
    """One kit shape as SVG, its kind as its class (cut, fold, mark) and its stroke (the plotter's colour)."""
    style = f'class="{shape.kind}" ' + STYLES[shape.kind]
    if shape.tag == "rect":
        return _rect(*shape.xy, style)
    if shape.tag == "circle":
        return _circle(*shape.xy, style)
    if shape.tag == "polygon":
        points = " ".join(f"{shape.xy[k]:.2f},{shape.xy[k + 1]:.2f}" for k in range(0, len(shape.xy), 2))
        return f'<polygon points="{points}" {style}/>'
    return _line(*shape.xy, style)


@dataclass
class Part:
    """A part drawn in its own coordinates (mm, y down) inside [0, width] x [top, top + height]."""
    name: str
    caption: list[str]
    elements: list[str] = field(default_factory=list)
    width: float = 0.0
    top: float = 0.0
    height: float = 0.0
    id: str = ""


def drawn(piece: Piece) -> Part:
    """A kit piece as a template part: its shapes shifted so its left edge is at 0."""
    x0, y0, x1, y1 = shapes_extent(piece.shapes)
    els = [f'<g transform="translate({-x0:.2f},0)">', *(render(s) for s in piece.shapes), "</g>"] if x0 else \
        [render(s) for s in piece.shapes]
    return Part(piece.name, list(piece.caption), els, x1 - x0, y0, y1 - y0, piece.id)


SCALES = (1, 2, 4, 5, 10, 20, 50, 100)


def stand(cfg: Config) -> Part:
    """The side view at the largest of ``SCALES``' 1:k that fits the page's width."""
    for k in SCALES:
        part = stand_at(cfg, k)
        if part.width <= PAGE_W - 2 * MARGIN:
            return part
    return part


def stand_at(cfg: Config, k: int) -> Part:
    """A side view of the row at 1:k: the skewer axes, each frame at its rest angle on its stopper,
    the end stop's skewer, and the floor."""
    d, s = cfg.design, cfg.scene
    f = 1e3 / k  # metres to drawn mm

    def at(x_m, y_m):  # world (y up) to drawing (y down)
        return x_m * f, -y_m * f

    rest = math.radians(d.rest_angle_deg)
    dot = min(PIN, 4.0 / k)  # markers shrink with the scale, so a long row stays legible
    els, pts = [], []
    for i in range(s.frames):
        ax, ay = i * s.pitch, i * s.rise
        c, sn = math.cos(rest), math.sin(rest)
        a = at(ax - d.Lb * c, ay - d.Lb * sn)
        b = at(ax + d.La * c, ay + d.La * sn)
        els.append(_line(*a, *b, 'stroke="sienna" stroke-width="0.5"'))
        els.append(_circle(*at(ax, ay), dot, 'fill="black"'))
        for ox, oy in stopper_offsets(d):  # the rest and the end stopper skewers, where the crossbeam holds them
            els.append(_circle(*at(ax + ox, ay + oy), dot, 'fill="none" stroke="blue" stroke-width="0.3"'))
            pts.append(at(ax + ox, ay + oy))
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
        (f"on a stopper skewer (blue) in the side cards' window, {float(stopper_radius(d)) * 1e3:.1f} mm from the "
         f"axis, against the hub bar; a second one beside it stops them at {d.stop_angle_deg:.0f} deg."
         if side_card(d)["hollow"] else
         f"on a stopper skewer (blue) under the counterbalance's side, {d.La * 1e3 / 2:.1f} mm out; a second one stops "
         f"them at {d.stop_angle_deg:.0f} deg."),
    ], els, width, 0.0, height)


def svg(cfg: Config, card: Card = PAPER_CARD) -> str:
    """The whole template: the check bar and the legend, then each piece under its caption, then the stand."""
    parts = [drawn(p) for p in pieces(cfg, card)]
    why = no_spring(cfg, card)
    if why:
        parts.append(Part("leaf spring", ["LEAF SPRING: no strip of this card fits: " + why + "."]))
    parts.append(stand(cfg))
    out = [f'<text class="caption" x="{MARGIN}" y="{MARGIN + CAPTION:.2f}" font-size="3.6" '
           f'font-family="sans-serif">aero-env template: print at 100 % (no fit-to-page); the bar must measure '
           f'50 mm</text>',
           f'<rect class="scale-bar" x="{MARGIN}" y="{MARGIN + 6:.2f}" width="50" height="2" fill="black"/>',
           f'<text class="caption" x="{MARGIN + 53}" y="{MARGIN + 8:.2f}" font-size="{CAPTION}" '
           f'font-family="sans-serif">50 mm</text>',
           f'<text class="caption" x="{MARGIN}" y="{MARGIN + 13:.2f}" font-size="{CAPTION}" '
           f'font-family="sans-serif">{escape(LEGEND)}</text>']
    y = MARGIN + 13 + GAP
    width = PAGE_W
    for p in parts:
        for line in (wrapped for text in p.caption for wrapped in textwrap.wrap(text, WRAP)):
            y += LINE
            out.append(f'<text class="caption" x="{MARGIN}" y="{y:.2f}" font-size="{CAPTION}" '
                       f'font-family="sans-serif">{escape(line)}</text>')
        y += 2.0
        if p.elements:
            out.append(f'<g class="part" id="{p.id or p.name.replace(" ", "-")}" transform="translate({MARGIN:.2f},'
                       f'{y - p.top:.2f})">')
            out += p.elements
            out.append("</g>")
        y += p.height + GAP
        width = max(width, MARGIN * 2 + p.width)
    height = y + MARGIN
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.1f}mm" height="{height:.1f}mm" '
            f'viewBox="0 0 {width:.1f} {height:.1f}">\n' + "\n".join(out) + "\n</svg>\n")
