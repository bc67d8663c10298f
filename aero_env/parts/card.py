"""The card the toy is cut from, and the leaf spring it makes: a bending model with one fitted unknown.

The paper builds everything from one board, JOHOKU WB310g: about 0.4 mm thick, 310 g/m² (Sec. 6).
Its leaf spring is a strip of that card between the torso and the arm, straight at alpha_min and
bent by the arm's turn; the paper measures the strip's torque with a pulley (Figs. 18-22) and fits
it as linear, K_T = 0.877·Δα N·mm/rad.

**The bending model.** A strip of width ``w`` glued to the torso at one end and to the arm at the
other, with a free length ``L`` between the glue lines, bends uniformly as the arm turns by Δα
(Euler-Bernoulli pure bending): torque = n·D·w·Δα / L. ``D`` is the card's bending stiffness per
unit width (E·t³/12, in N·m); ``n`` strips stacked loose (not glued to each other) each take the same
bend and add their torques. The law is linear in Δα, as the paper's measurement is.

**What is fitted, and on what.** ``D`` is the one unknown. It is fitted on the paper's 0.877 N·mm/rad
for the prototype's strip (:func:`fit_bending_stiffness`, ``python scripts/fit_card_bending.py``).
The paper shows that strip (Figs. 19 and 21) but gives neither its width nor its free length, so
they are named assumptions here (:data:`PROTOTYPE_STRIP`): the fit pins D·w/L, not D alone. Every
strip the sheet gives therefore scales with the prototype's assumed width-to-length ratio, which is
why the sheet also prints the paper's own bench test (a load at the hook tip and the arm's turn) for
the maker to check the strip they cut and trim it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

PAPER_SPRING_K = 8.77e-4  # N·m/rad: the paper's K_T = 0.877 N·mm/rad (Fig. 22)
PAPER_BEND_DEG = 60.0  # the prototype's strip is straight at alpha 60 deg and fully bent at 120 deg


@dataclass(frozen=True)
class Strip:
    """A leaf-spring strip: SI metres. ``free_length`` is the card between the two glue lines."""
    width: float
    free_length: float
    layers: int = 1


# ASSUMED (the paper gives no dimensions): a 5 mm wide strip with 20 mm of card free between its glue
# lines, one layer. Only D·width/free_length is fitted, so this choice rescales every strip the sheet
# gives; the bench test on the sheet is the maker's check of it.
PROTOTYPE_STRIP = Strip(width=5e-3, free_length=20e-3, layers=1)


def strip_stiffness(bending_stiffness: float, strip: Strip) -> float:
    """The strip's torque per radian of bend, N·m/rad (pure bending, the module's model)."""
    return strip.layers * bending_stiffness * strip.width / strip.free_length


def fit_bending_stiffness(k: float, strip: Strip) -> float:
    """The card's bending stiffness D (N·m) that gives ``strip`` the measured stiffness ``k``: the model
    inverted on one measurement (one unknown, one figure)."""
    return k * strip.free_length / (strip.layers * strip.width)


@dataclass(frozen=True)
class Card:
    thickness: float  # m
    grammage: float  # kg/m²
    bending_stiffness: float  # N·m per unit width (E·t³/12)

    @property
    def modulus(self) -> float:
        """The Young's modulus the fitted D implies for a solid sheet of this thickness, Pa."""
        return 12.0 * self.bending_stiffness / self.thickness**3

    def mass(self, area_m2: float) -> float:
        return self.grammage * area_m2


# The paper's board. bending_stiffness is fitted: python scripts/fit_card_bending.py
# (= fit_bending_stiffness(PAPER_SPRING_K, PROTOTYPE_STRIP); tests/test_sheet.py keeps the two equal).
PAPER_CARD = Card(thickness=0.4e-3, grammage=0.310, bending_stiffness=3.508e-3)


def bend_of(alpha_min_deg: float, alpha_max_deg: float) -> float:
    return math.radians(alpha_max_deg - alpha_min_deg)
