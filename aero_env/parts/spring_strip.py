"""The leaf-spring strip a design's stiffness asks for, and the bench test that checks it.

:func:`plan_strip` turns a stiffness (N·m/rad) into a strip of the card (``card.py``'s bending model)
that fits the robot, or says why none does. The limits are named below, each with its reason:

- width: at least ``MIN_WIDTH`` (a narrower strip tears when cut by hand) and at most the arm's
  card (``STRIP_WIDTH``: a wider spring overhangs the arm and torso it is glued to);
- free length: at most the arm's length less a glue tab (the strip must end before the hook), and
  at least the prototype's free length scaled by the design's bend over the prototype's. A strip
  bent more sharply than the prototype's (the one strip known to survive the bend) may crease;
- layers: up to ``MAX_LAYERS`` strips stacked loose, for a spring stiffer than one strip can be.

The search keeps the prototype's free length where it can and changes the width; then it adds
layers; then it moves the length to the nearest limit. :func:`bench_loads` gives the paper's own
check (Fig. 18): a load pulling at the hook tip at right angles to the arm turns it by m·g·Lc / k.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .card import PAPER_BEND_DEG, PROTOTYPE_STRIP, Card, Strip, strip_stiffness

STRIP_WIDTH = 8e-3  # m: the width the template cuts the arm and torso (a maker's choice, not modelled)
MIN_WIDTH = 3e-3  # m: the narrowest strip scissors cut cleanly (a narrower one tears or curls)
MAX_LAYERS = 3
GLUE_TAB = 5e-3  # m: card glued flat at each end of the strip
G = 9.81
BAG_G = 0.3  # the paper's plastic bag, g (Sec. 5)
CLIP_G = 0.25  # one clip, g (Sec. 5)


@dataclass(frozen=True)
class StripPlan:
    strip: Strip | None  # None: no strip of this card fits
    stiffness: float  # what the planned strip gives, N·m/rad (nan without a strip)
    why_not: str = ""

    @property
    def cut_length(self) -> float:
        return self.strip.free_length + 2 * GLUE_TAB


def linear_equivalent(k: float, law: str, bend: float) -> float:
    """The linear stiffness a strip must have (the bending model is linear): the design's own, or for
    the stiffening law (torque k/2·da², physics/leaf_spring.py) the one with its torque at full bend."""
    return k if law == "linear" else k * bend / 2


def length_limits(arm_length: float, bend: float) -> tuple[float, float]:
    """(shortest, longest) free length, m: no sharper a bend than the prototype's strip, and ending
    a glue tab before the hook."""
    shortest = PROTOTYPE_STRIP.free_length * bend / math.radians(PAPER_BEND_DEG)
    return shortest, arm_length - GLUE_TAB


def plan_strip(k: float, card: Card, arm_length: float, bend: float) -> StripPlan:
    """The strip that gives stiffness ``k`` (N·m/rad) with a bend of ``bend`` rad on an arm of
    ``arm_length`` m, or the reason none fits."""
    shortest, longest = length_limits(arm_length, bend)
    if shortest > longest:
        return StripPlan(None, math.nan, f"the bend of {math.degrees(bend):.0f} deg needs at least "
                                         f"{shortest * 1e3:.1f} mm of free strip, and the arm leaves room for "
                                         f"{longest * 1e3:.1f} mm")
    length = min(max(PROTOTYPE_STRIP.free_length, shortest), longest)
    for layers in range(1, MAX_LAYERS + 1):
        width = k * length / (layers * card.bending_stiffness)
        if width <= STRIP_WIDTH:
            break
    if width > STRIP_WIDTH:  # even stacked, the full width is too soft at this length: shorten it
        width = STRIP_WIDTH
        length = layers * card.bending_stiffness * width / k
        if length < shortest:
            return StripPlan(None, math.nan, f"{k * 1e3:.3g} N·mm/rad needs {MAX_LAYERS} strips "
                                             f"{STRIP_WIDTH * 1e3:.0f} mm wide with only {length * 1e3:.1f} mm "
                                             f"free, and a strip shorter than {shortest * 1e3:.1f} mm creases "
                                             f"at this bend: use a thicker card")
    elif width < MIN_WIDTH:  # too soft for the narrowest strip at this length: lengthen it
        width = MIN_WIDTH
        length = card.bending_stiffness * width / k
        if length > longest:
            return StripPlan(None, math.nan, f"{k * 1e3:.3g} N·mm/rad needs a strip {MIN_WIDTH * 1e3:.0f} mm "
                                             f"wide with {length * 1e3:.1f} mm free, and the arm leaves room for "
                                             f"{longest * 1e3:.1f} mm: use a thinner card")
    strip = Strip(width=width, free_length=length, layers=layers)
    return StripPlan(strip, strip_stiffness(card.bending_stiffness, strip))


def bench_loads(k: float, arm_length: float, bend: float) -> list[tuple[float, float]]:
    """The paper's bench test (Fig. 18) for a spring of stiffness ``k``: (load in g, the arm's turn in
    deg) for the bag alone and with each added clip, up to the load that bends it fully."""
    rows, clips = [], 0
    while True:
        grams = BAG_G + clips * CLIP_G
        turn = grams * 1e-3 * G * arm_length / k
        rows.append((grams, math.degrees(turn)))
        if turn >= bend or clips >= 12:
            return rows
        clips += 1
