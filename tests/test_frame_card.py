"""The frames' side cards as the article builds them (aero_env/parts/build.py): hollow rectangles that weigh m1 and
swing about the skewer as A13 says, worked out on their own here (tests/test_kit_readback.py's hollow_card, a fine
scan and brentq over the same rectangles, written out rectangle by rectangle) and compared with the kit's."""

from __future__ import annotations

import types

import numpy as np
import pytest

from aero_env.parts import build

from .test_kit_readback import HOLE_AREA, hollow_card, hollow_card_full, ring_polar

G = 0.310  # kg/m²


def _design(La, Lb=0.0517, m1=0.004, rest=55.0, stop=180.0, h=0.005):
    return types.SimpleNamespace(La=La, Lb=Lb, m1=m1, h=h, rest_angle_deg=rest, stop_angle_deg=stop)


GRID = [(La, m1) for La in (0.036, 0.0425, 0.0483, 0.055, 0.065) for m1 in (0.0015, 0.004, 0.007)]


@pytest.mark.parametrize("La, m1", GRID)
def test_each_side_card_weighs_half_m1_and_swings_as_a13_says(La, m1):
    d = _design(La, m1=m1)
    sc = build.side_card(d)
    layers, depth, end = hollow_card(d)
    assert end is not None and sc["hollow"]
    assert (sc["layers"], sc["depth"] * 1e3, sc["end"] * 1e3) == pytest.approx((layers, depth, end), abs=1e-6)
    H = sc["half_length"] * 1e3
    area, polar = ring_polar(H, depth / 2, end)  # mm², mm⁴ of one layer
    assert area * 1e-6 * G * layers == pytest.approx(m1 / 2, rel=1e-9)
    a13 = 2 * m1 / 3 * (La**2 + 0.0517**2 - La * 0.0517)
    assert 2 * sc["I_axis"] == pytest.approx(2 * polar * 1e-12 * G * layers, rel=1e-9)
    if depth < 40.0:  # a card at most 40 mm deep swings as A13 says
        assert 2 * sc["I_axis"] == pytest.approx(a13, rel=1e-9)
    else:  # none does: the 40 mm card of the layer count that comes nearest, and no other comes nearer
        miss = abs(2 * sc["I_axis"] - a13)
        for n in range(1, 7):
            e = H - 3.0 - (4 * H * 20.0 - HOLE_AREA - m1 / 2 / G * 1e6 / n) / 2 / (2 * (20.0 - 3.0))
            if 3.0 <= e < H - 3.0:
                assert miss <= abs(2 * ring_polar(H, 20.0, e)[1] * 1e-12 * G * n - a13) + 1e-15, n


def test_a_batch_of_designs_gets_each_designs_own_card():
    """The reduced model builds its frames as arrays of designs: each row is the card the design alone gets, the
    cards that hold their coins and those that do not side by side."""
    La = np.array([g[0] for g in GRID] + [0.1, 0.02])
    m1 = np.array([g[1] for g in GRID] + [0.0015, 0.0003])
    h = np.resize([0.005, -0.002, 0.009, 0.015], La.shape)
    batch = build.side_card(_design(La, Lb=np.full(La.shape, 0.0517), m1=m1, rest=np.full(La.shape, 55.0),
                                    stop=np.full(La.shape, 180.0), h=h))
    assert 0 < np.sum(batch["holds_coins"]) < len(La)
    for k in range(len(La)):
        one = build.side_card(_design(float(La[k]), m1=float(m1[k]), h=float(h[k])))
        for key in ("layers", "half_length", "depth", "I_axis", "end", "window", "window_depth"):
            assert float(np.asarray(batch[key])[k]) == pytest.approx(float(one[key]), rel=1e-12, abs=1e-15), (k, key)
        assert bool(np.asarray(batch["hollow"])[k]) == bool(one["hollow"])
        assert bool(np.asarray(batch["holds_coins"])[k]) == bool(one["holds_coins"])


COIN_SEAT = 11.0  # mm: a one-yen coin's radius and 1 mm of card round it


@pytest.mark.parametrize("La, m1, h", [(0.0483, 0.004, 0.005), (0.0483, 0.004, -0.008), (0.04, 0.006, 0.0),
                                       (0.0483, 0.0015, 0.005), (0.055, 0.004, 0.005), (0.0483, 0.004, 0.012),
                                       (0.036, 0.003, 0.0)])
def test_the_card_holds_the_counterbalances_coins_where_a_card_that_swings_as_a13_can(La, m1, h):
    # 36 mm and 3 g: a card deep enough for the coins has windows reaching under them; no card reaches A13 40 mm deep
    _card_and_coins(La, m1, h, a13=(La, m1) != (0.036, 0.003))


def _card_and_coins(La, m1, h, a13=True) -> bool:
    """Whether the card holds the coins, each side of it checked. The coins (20 mm across, on the mark (La, h)) lie
    on card with 1 mm to spare: the card runs past them, is deep enough, and its windows stop short of them, so the
    end bar carries the whole stack. Where no such card weighs m1/2 and swings as A13 says (a light frame, a long
    arm, a mark far off the line), the shortest card, 4 mm past the farther of the seat and the mark, still swinging
    as A13 says; the coins then overhang it or a window."""
    d = _design(La, m1=m1, h=h)
    sc = build.side_card(d)
    H, layers, depth, end = hollow_card_full(d)
    assert end is not None and sc["hollow"]
    assert (sc["half_length"] * 1e3, sc["layers"], sc["depth"] * 1e3, sc["end"] * 1e3) == pytest.approx(
        (H, layers, depth, end), abs=1e-6)
    assert (2 * sc["I_axis"] == pytest.approx(2 * m1 / 3 * (La**2 + 0.0517**2 - La * 0.0517), rel=1e-9)) == a13
    x, y = La * 1e3, h * 1e3
    on_card = H >= x + COIN_SEAT and depth / 2 >= abs(y) + COIN_SEAT and H - end <= x - COIN_SEAT
    assert bool(sc["holds_coins"]) == on_card
    if not on_card:  # the shortest card
        assert H == pytest.approx(max(La, 0.0517) * 1e3 + 4.0, abs=1e-9)
    return on_card


def test_the_prototypes_card_holds_its_coins_and_a_light_frames_does_not():
    """Both sides of the rule happen: the prototype's card holds its coins, the light frame's 1.5 g card does not."""
    assert _card_and_coins(0.0483, 0.004, 0.005) and not _card_and_coins(0.0483, 0.0015, 0.005)
    assert _card_and_coins(0.04, 0.006, 0.0)
    assert not any(_card_and_coins(La, 0.004, h) for La, h in ((0.0483, -0.008), (0.055, 0.005), (0.0483, 0.012)))


def test_where_no_card_reaches_a13_the_nearest_40_mm_card_and_where_none_fits_flat_cards():
    """A light frame 100 mm long, its counterbalance 12 mm off the line (no card 40 mm deep holds its coins): no
    card 40 mm deep or less swings as A13 says; the kit cuts the 40 mm one of the layer count that comes nearest
    (short of A13). A frame lighter than any window allows: flat cards, the fewest layers at most 20 mm deep."""
    d = _design(0.1, Lb=0.1, m1=0.004, h=0.012)
    sc = build.side_card(d)
    a13 = 2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb)
    layers, depth, end = hollow_card(d)
    assert sc["hollow"] and sc["depth"] == pytest.approx(0.040, abs=1e-12) and depth == pytest.approx(40.0)
    assert (sc["layers"], sc["end"] * 1e3) == pytest.approx((layers, end), abs=1e-9)
    assert 0.85 * a13 < 2 * sc["I_axis"] < a13
    flat = build.side_card(_design(0.0483, m1=0.00028))
    assert not flat["hollow"] and flat["window"] == 0.0
    length = 2 * (0.0517 + 0.004)
    assert flat["depth"] == pytest.approx((0.00014 / G + HOLE_AREA * 1e-6) / length, rel=1e-12)  # one layer
