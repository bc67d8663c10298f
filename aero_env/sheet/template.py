"""A 1:1 cutting template as SVG: print at 100 % and the parts are their config's size.

The world is 2D, so it knows each part's length but not its width; the template draws every
strip ``STRIP_MM`` wide (any width that stays stiff will do) and says so on the sheet. A 50 mm
scale bar checks the print's scale.
"""

from __future__ import annotations

from xml.sax.saxutils import escape

from ..config import Config

STRIP_MM = 8.0  # drawn width of the card strips: not a modelled value
MARGIN_MM = 10.0
GAP_MM = 14.0  # between parts
HOLE_MM = 1.2  # skewer / axle hole radius, for marking (a 2 mm skewer)
PAGE_W_MM = 190.0


def _text(x, y, s, size=3.2) -> str:
    return f'<text x="{x:.2f}" y="{y:.2f}" font-size="{size}" font-family="sans-serif">{escape(s)}</text>'


def _strip(x, y, length) -> str:
    return (f'<rect x="{x:.2f}" y="{y:.2f}" width="{length:.2f}" height="{STRIP_MM:.2f}" fill="none" '
            f'stroke="black" stroke-width="0.25"/>')


def _hole(x, y) -> str:
    return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{HOLE_MM}" fill="none" stroke="black" stroke-width="0.25"/>'


def _mark(x, y, label) -> str:
    return (f'<line x1="{x:.2f}" y1="{y - 2:.2f}" x2="{x:.2f}" y2="{y + STRIP_MM + 2:.2f}" stroke="red" '
            f'stroke-width="0.3"/>' + _text(x + 1, y - 1, label, 2.6))


def svg(cfg: Config) -> str:
    """The template of one swing frame, its handrail, the arm and the torso, at 1:1 in mm."""
    d = cfg.design
    la, lb, h = d.La * 1e3, d.Lb * 1e3, d.h * 1e3
    back, front = d.notch_back_face * 1e3, d.notch_front_face * 1e3
    arm, torso = d.arm_length * 1e3, d.torso_length * 1e3
    coin_at, coin_r = d.coin_offset * 1e3, d.coin_radius * 1e3
    x0, y, out = MARGIN_MM, MARGIN_MM, []

    out.append(_text(x0, y, "aero-env build template: print at 100 % (no fit-to-page); the bar must measure 50 mm", 3.6))
    y += 4
    out.append(f'<rect x="{x0}" y="{y}" width="50" height="2" fill="black"/>' + _text(x0 + 52, y + 2, "50 mm", 3))
    y += GAP_MM

    # swing frame: handrail end at the left, skewer hole, counterbalance end at the right
    out.append(_text(x0, y - 3, f"swing frame (x{cfg.scene.frames}): seat {lb:.1f} mm | skewer | "
                                f"counterbalance {la:.1f} mm, {h:+.1f} mm across", 3.2))
    out.append(_strip(x0, y, lb + la))
    out.append(_hole(x0 + lb, y + STRIP_MM / 2))
    out.append(_mark(x0, y, "seat"))
    out.append(_mark(x0 + lb + la, y, "m3"))
    out.append(f'<circle cx="{x0 + lb + la:.2f}" cy="{y + STRIP_MM / 2 - h:.2f}" r="1.5" fill="orange"/>')
    y += STRIP_MM + GAP_MM

    # handrail: one strip, folded to an L at the corner (90 deg)
    out.append(_text(x0, y - 3, f"handrail (x{cfg.scene.frames}): fold at the dashed line to an L, "
                                f"{d.notch_opening_deg:.0f} deg; back leg {back:.1f} mm, front leg {front:.1f} mm", 3.2))
    out.append(_strip(x0, y, back + front))
    out.append(f'<line x1="{x0 + back:.2f}" y1="{y:.2f}" x2="{x0 + back:.2f}" y2="{y + STRIP_MM:.2f}" '
               f'stroke="black" stroke-width="0.25" stroke-dasharray="1,1"/>')
    y += STRIP_MM + GAP_MM

    # arm: axle hole at the left, hook tip at the right
    out.append(_text(x0, y - 3, f"arm: axle hole to hook tip {arm:.1f} mm", 3.2))
    out.append(_strip(x0, y, arm))
    out.append(_hole(x0, y + STRIP_MM / 2))
    out.append(_mark(x0 + arm, y, "hook tip"))
    y += STRIP_MM + GAP_MM

    # torso: axle hole at the left, the coins centred at coin_offset
    out.append(_text(x0, y - 3, f"torso: {torso:.1f} mm below the axle; coins centred {coin_at:.1f} mm from it", 3.2))
    out.append(_strip(x0, y, torso))
    out.append(_hole(x0, y + STRIP_MM / 2))
    out.append(f'<circle cx="{x0 + coin_at:.2f}" cy="{y + STRIP_MM / 2:.2f}" r="{coin_r:.2f}" fill="none" '
               f'stroke="gray" stroke-width="0.25" stroke-dasharray="0.8,0.8"/>')
    y += max(STRIP_MM, coin_r + STRIP_MM / 2) + GAP_MM

    out.append(_text(x0, y, f"strips are drawn {STRIP_MM:.0f} mm wide: the model is 2D and does not set a width", 2.8))
    height = y + MARGIN_MM
    width = max(PAGE_W_MM, x0 + max(la + lb, torso + coin_r, back + front) + MARGIN_MM)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.1f}mm" height="{height:.1f}mm" '
            f'viewBox="0 0 {width:.1f} {height:.1f}">\n' + "\n".join(out) + "\n</svg>\n")
