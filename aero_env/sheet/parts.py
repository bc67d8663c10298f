"""What a maker needs to build a design, read off its config: the parts in mm and g.

Every value comes from the config (SI) and the kit's pieces (``aero_env/parts``) and is converted
here for the workbench only: lengths in mm, masses in g, coins as whole one-yen coins (1.00 g each)
and modelling clay, the card pair whose measured friction (the paper's Table 3) is closest to the
design's, and the spring as the paper measures it (N·mm/rad, and the torque when fully bent).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..config import CARD_PAIRS, Config
from ..parts.build import COIN_SEATS, counterbalance_load, side_card
from ..parts.card import PAPER_CARD, Card
from ..parts.kit import pieces, shapes_extent
from ..parts.layout import kit_layout
from ..parts.spring_strip import GLUE_TAB, bench_loads, linear_equivalent, plan_strip


CARD_PAIR_SPREAD = 0.10  # the robustness study's friction tolerance (±10 %): a pair this close is "that pair"


@dataclass(frozen=True)
class Line:
    part: str
    what: str
    value: str


def mm(x_m: float) -> str:
    return f"{x_m * 1e3:.1f} mm"


def grams(x_kg: float) -> str:
    return f"{x_kg * 1e3:.2f} g"


def coins_and_clay(x_kg: float, seats: bool = True) -> str:
    """A mass as whole one-yen coins and the modelling clay for the rest; a counterbalance's (``seats``) on its coin
    seats, whose card is part of it."""
    load = counterbalance_load(x_kg, seats=None if seats else 0.0)
    coins, clay = int(load["coins"]), float(load["clay"])
    on = f" + {COIN_SEATS} coin seats" if seats else ""
    return f"{coins} one-yen coin{'' if coins == 1 else 's'} + {clay * 1e3:.2f} g clay{on} ({grams(x_kg)})"


def cut_extent(piece) -> tuple[float, float]:
    """(length, depth) in mm of a cut piece's outline overall."""
    x0, y0, x1, y1 = shapes_extent([s for s in piece.shapes if s.kind == "cut"])
    return x1 - x0, y1 - y0


def laminate(piece_or_layers) -> str:
    n = piece_or_layers if isinstance(piece_or_layers, int) else piece_or_layers.layers
    return "one layer" if n == 1 else f"{n} layers glued flat"


def kind_frames(cfg: Config, kind: str) -> str:
    """The frames of a kind in the nested layout, as the sheet names them: "0, 2, 4, 6"."""
    return ", ".join(str(i) for i in kit_layout(cfg).frames_of(kind))


def workbench(key: str, value: float, cfg: Config) -> str:
    """A tuned value as a maker reads it: a length in mm, a mass in g (m3 and the coins as whole one-yen coins and
    clay), a friction as the nearest measured card pair, a spring in N·mm/rad; "" for a value with no such reading.
    ``cfg`` is the design ``value`` belongs to: a friction is read with its own mu_k."""
    from ..config.sections import real_field

    unit = real_field(key, "workbench").metadata["unit"]
    if key in ("design.m3", "design.coin_mass"):
        return coins_and_clay(value, seats=key == "design.m3")
    if key == "design.mu_s":
        pair, off = card_pair(value, cfg.design.mu_k)
        return f"nearest card pair: {pair}, {100 * off:.0f} % off"
    if unit == "m":
        return mm(value)
    if unit == "kg":
        return grams(value)
    if unit == "N·m/rad":
        return f"{value * 1e3:.3f} N·mm/rad"
    return ""


def card_pair(mu_s: float, mu_k: float) -> tuple[str, float]:
    """The Table 3 pair nearest the design's friction, and its relative distance in mu_s."""
    name, s, _k = min(CARD_PAIRS, key=lambda p: math.hypot(p[1] - mu_s, p[2] - mu_k))
    return name, abs(s - mu_s) / s


def spring_lines(cfg: Config, card: Card = PAPER_CARD) -> list[Line]:
    """The strip to cut for the design's spring (card.py's bending model), and the paper's bench test
    that checks it: the arm's turn under a load at the hook tip."""
    d = cfg.design
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    k = linear_equivalent(d.spring_k, cfg.scene.effects.spring_law, bend)
    plan = plan_strip(k, card, d.arm_length, bend)
    if plan.strip is None:
        return [Line("leaf spring", "strip to cut (0.4 mm card)", f"**none fits**: {plan.why_not}")]
    st = plan.strip
    layers = f"{st.layers} strips stacked loose, each " if st.layers > 1 else ""
    checks = ", ".join(f"{g:.2f} g: {turn:.0f} deg" for g, turn in bench_loads(k, d.arm_length, bend)[::2])
    return [
        Line("leaf spring", "strip to cut (0.4 mm card; the bending model of aero_env/parts/card.py)",
             f"{layers}{st.width * 1e3:.1f} mm wide, {st.free_length * 1e3:.1f} mm free between two "
             f"{GLUE_TAB * 1e3:.0f} mm glue tabs ({plan.cut_length * 1e3:.1f} mm cut)"),
        Line("leaf spring", "bench check (the paper's Fig. 18): load at the hook tip, pulling at right angles to "
                            "the arm, and the arm's turn; trim the width in proportion if yours turns more or less",
             checks),
    ]


def lines(cfg: Config) -> list[Line]:
    """The build sheet's rows, part by part."""
    d, s = cfg.design, cfg.scene
    pair, off = card_pair(d.mu_s, d.mu_k)
    pair_text = (f"{pair}: Table 3 gives the design's mu_s {d.mu_s:.3g} / mu_k {d.mu_k:.3g} within "
                 f"{100 * off:.0f} %" if off <= CARD_PAIR_SPREAD else
                 f"no card pair of Table 3 is within {100 * CARD_PAIR_SPREAD:.0f} % of mu_s {d.mu_s:.3g} / mu_k "
                 f"{d.mu_k:.3g}; nearest: {pair} (coat or sand a face, then measure)")
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    # the scene's spring law (physics/leaf_spring.py): linear k·da, or stiffening k/2·da²
    full_torque = d.spring_k * (bend if cfg.scene.effects.spring_law == "linear" else bend * bend / 2)
    ps = pieces(cfg)
    kit = {p.id: p for p in ps}
    arm, torso = kit["part-arm"], kit["part-torso"]
    sc = side_card(d)
    cut = [Line("swing frame", f"the {kind} frames' side cards instead ({kind_frames(cfg, kind)}: cut where the "
                               f"neighbours pass)",
                f"{grams(p.mass_kg)} each: {mm(cut_extent(p)[0] * 1e-3)} x {mm(cut_extent(p)[1] * 1e-3)} overall, "
                f"{laminate(p)}")
           for p in ps for kind in ("narrow", "wide")
           if p.id == f"part-frame-side-card-{kind}" and any(sh.tag == "polygon" for sh in p.shapes)]
    return [
        Line("swing frame", "skewer hole to counterbalance (La)", mm(d.La)),
        Line("swing frame", "skewer hole to handrail seat (Lb)", mm(d.Lb)),
        Line("swing frame", "counterbalance offset across the frame line (h)", mm(d.h)),
        Line("swing frame", "its card (m1): two side cards, each of them", f"{grams(d.m1 / 2)} (both: {grams(d.m1)}): "
             f"{mm(sc['length'])} x {mm(sc['depth'])}, {'hollow, ' if sc['hollow'] else ''}"
             f"{laminate(int(sc['layers']))}"),
        *cut,
        Line("swing frame", "rest angle (the stopper skewer holds it there) / end stop",
             f"{d.rest_angle_deg:.1f} deg / {d.stop_angle_deg:.1f} deg"),
        Line("counterbalance", "mass at (La, h) (m3)", coins_and_clay(d.m3)),
        Line("handrail", "an L of card: back leg / front leg", f"{mm(d.notch_back_face)} / {mm(d.notch_front_face)}"),
        Line("handrail", "the L's bisector at rest: from the frame line / from the horizontal / opening",
             f"{d.notch_angle_deg - d.rest_angle_deg:+.1f} deg / {d.notch_angle_deg:.1f} deg / "
             f"{d.notch_opening_deg:.0f} deg"),
        Line("handrail", "its mass (counted in m2 by the paper, carried by the frame)", grams(d.handrail_mass)),
        Line("handrail + arm", "the card pair that gives the friction", pair_text),
        Line("robot", "whole robot, handrail included (m2)", grams(d.m2)),
        Line("robot", "arm: axle hole to hook tip / mass / card",
             f"{mm(d.arm_length)} / {grams(d.arm_mass)} / {laminate(arm)}"),
        Line("robot", "torso below the axle / its card (m2 less the parts listed here)",
             f"{mm(d.torso_length)} / {grams(d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass)}, {laminate(torso)}"),
        Line("robot", "coins on the torso: total / centre from the axle",
             f"{grams(d.coin_mass)} / {mm(d.coin_offset)}"),
        Line("leaf spring", "stiffness as the paper measures it (torque per radian of bend from alpha_min)",
             f"{d.spring_k * 1e3:.3f} N·mm/rad ({cfg.scene.effects.spring_law})"),
        Line("leaf spring", f"straight at alpha = {d.alpha_min_deg:.0f} deg; torque when fully bent "
                            f"({d.alpha_max_deg:.0f} deg)",
             f"{full_torque * 1e3:.2f} N·mm"),
        *spring_lines(cfg),
        Line("row", "frames / skewer holes apart (pitch) / each higher than the last (rise)",
             f"{s.frames} / {mm(s.pitch)} / {mm(s.rise)}"),
    ]
