"""The reduced model's contacts at the handrail, against the pymunk world: the hook rolling over a card's
rounded end before it lets go, a catch made as the runner makes one (a touch held within ``sim.catch_seat``)
and a touch that slides off the card (a graze), and the events a slide meets (the corner, the card's end)
met without adding energy. Each compares the model with the world on the same design, not with a number
the model once gave."""

from __future__ import annotations

import numpy as np
import pytest

from aero_env.bench.designs import draw_designs
from aero_env.config import load_config
from aero_env.models.reduced import simulate_batch, simulate_reduced, swing_trace
from aero_env.simulation import simulate

PAPER = "configs/paper.yaml"

# Draws 3 and 40 of `draw_designs(paper, 100, seed 4, near paper, spread 0.15)` (docs/fidelity.md's near sample):
# the hook meets frame 1's front card near its rounded end, about 10 mm from the seat, and slides back off it
# in the pymunk world. The model's catch once set every such touch on the seat: it counted 7 traversals here.
OFF_THE_CARD = {
    3: {"design.m3": 0.0069, "design.h": 0.00907690239608288, "design.La": 0.05202995532050729,
        "design.spring_k": 0.0006550227805195056},
    40: {"design.m3": 0.008, "design.h": 0.006799290188848972, "design.La": 0.05112476210217924,
         "design.spring_k": 0.0006829768673176666},
}


def near_prototype(n: int, seed: int):
    base = load_config(PAPER)
    return draw_designs(base, n, seed, near=base, spread=0.15).configs


@pytest.fixture(scope="module")
def near_runs():
    """40 designs near the prototype (a seed the docs do not use), at mbd and at reduced."""
    cfgs = near_prototype(40, 31)
    world = [simulate(c) for c in cfgs]
    model = simulate_batch([c.replace({"sim.fidelity": "reduced"}) for c in cfgs])
    single = [simulate_reduced(c.replace({"sim.fidelity": "reduced"})) for c in cfgs]
    return world, model, single


def test_the_hook_lets_go_when_the_pymunk_worlds_does_after_rolling_over_the_cards_end(near_runs):
    """The first swing ends with the hook sliding out along a face; pymunk's hook then rolls 2-5 ms over the card's
    rounded end before it leaves. Releasing at the face's end instead lets go early (here 5.5 ms, median; with the
    roll 2.2 ms) and throws the flight off by about a millimetre at the next notch, where a catch is decided by
    that much."""
    world, _, single = near_runs
    dt = [m.swings[0].t_detach - w.swings[0].t_detach for w, m in zip(world, single)
          if w.swings[0].t_detach is not None and m.swings[0].t_detach is not None]
    assert len(dt) >= 20  # (the others stall or hold on: no detach to compare)
    assert abs(float(np.median(dt))) < 3e-3, f"median first-detach offset {np.median(dt) * 1e3:.2f} ms"


@pytest.mark.parametrize("draw", sorted(OFF_THE_CARD))
def test_a_hook_that_slides_back_off_the_card_is_a_graze_as_in_the_pymunk_world(draw):
    cfg = load_config(PAPER, OFF_THE_CARD[draw])
    world = simulate(cfg)
    model = simulate_reduced(cfg.replace({"sim.fidelity": "reduced"}))
    assert "never seated" in world.reason and world.traversals == 0
    assert (model.outcome, model.traversals) == (world.outcome, world.traversals), model.reason
    assert "never seated" in model.reason
    # it came as close to the seat as the world's hook did (the card's end, ~10 mm out), never closer
    assert model.miss_distance == pytest.approx(world.miss_distance, abs=1.5e-3)


def test_a_catch_is_a_touch_held_within_catch_seat_as_the_runner_makes_one():
    """The prototype's catches: a catch's time is its first touch (the runner's t_catch), so each flight, detach to
    touch, lasts about as long as the world's (the model's 1-9 ms longer); the catch is a touch that came within
    sim.catch_seat of the seat, and its catch_seat_mm is that touch's closest approach (the model once set every
    hook on the seat from wherever it met the notch: 4-6 mm here). Each swing then lets go within 3 deg of the
    world's."""
    cfg = load_config(PAPER)
    world = simulate(cfg)
    model = simulate_reduced(cfg.replace({"sim.fidelity": "reduced"}))
    assert model.traversals == world.traversals == 7
    for k in range(1, 8):
        w, m = world.swings[k], model.swings[k]
        flight_w = w.t_catch - world.swings[k - 1].t_detach
        flight_m = m.t_catch - model.swings[k - 1].t_detach
        assert flight_m == pytest.approx(flight_w, abs=0.012)
        assert 0.0 <= m.catch_seat_mm <= cfg.sim.catch_seat * 1e3
        if k < 7:
            assert m.theta1_detach_deg == pytest.approx(w.theta1_detach_deg, abs=3.0)


def test_near_the_prototype_the_model_agrees_with_the_pymunk_world_on_most_designs(near_runs):
    """The measure docs/fidelity.md reports against the reference, here against the default rung on a seed the
    docs do not use: the landing catch and the roll over the card's end took it from 29 of 40 to 34 of 40."""
    world, model, single = near_runs
    same = [w.traversals == int(m) for w, m in zip(world, model.traversals)]
    assert sum(same) >= 33, f"{sum(same)} of {len(same)}"
    assert [s.traversals for s in single] == model.traversals.tolist()  # one at a time or batched: one answer


@pytest.mark.parametrize("over", [{}, {"design.pivot_friction": 0.0, "design.axle_friction": 0.0}],
                         ids=["prototype", "no dry friction"])
def test_the_events_a_slide_meets_add_no_energy(over):
    """Past its face's end the hook's path turns onto the card's rounded end, and the path's curvature jumps there:
    which of the two a step is on is decided at its start (a step that took the curvature from its crossing on
    integrated it from the middle of the step, +4 uJ without the dry friction). The energy's rise over its running
    minimum, with and without the skewer's and the axle's friction, stays at the integrator's level."""
    r = simulate_reduced(load_config(PAPER, {**over, "sim.fidelity": "reduced"}))
    assert r.traversals == 7
    assert r.energy["max_gain"] <= 0.0
    assert r.energy["max_rise"] < 1e-6


# Draws of `draw_designs(paper, 100, seed S, near paper, spread 0.15)` (seeds the docs do not use), each showing
# one contact the pymunk world makes and the model once made differently.
LANDS_MID_SNAP = {"design.m3": 0.0068, "design.h": 0.007662236007750035, "design.La": 0.04670423440665007,
                  "design.spring_k": 0.000638246727790853}  # seed 5, draw 7
ONTO_THE_CARDS_END = {"design.m3": 0.0079, "design.h": 0.006115570955649019, "design.La": 0.05166113453082741,
                      "design.spring_k": 0.0008122969832136702}  # seed 4, draw 32
ARM_LIFTS_AT_THE_END = {"design.m3": 0.0072, "design.h": 0.005001966483760627, "design.La": 0.05228691437467933,
                        "design.spring_k": 0.0007655779767848191}  # seed 4, draw 5
# the frame reaching its end stop with the hook slid out along the back card (uniform draws 27 and 100, seed 7)
BOUNCES_AT_THE_STOP = {
    27: {"design.La": 0.05116484694963322, "design.h": 0.01875183987915516, "design.m3": 0.0076,
         "design.spring_k": 0.0009301683057300715},
    100: {"design.La": 0.060208246951103224, "design.h": 0.014336857547163968, "design.m3": 0.0074,
          "design.spring_k": 0.000805947465609484},
}
ROUNDS_THE_CARDS_END = {"design.La": 0.038670868763923644, "design.h": 0.014875094048380855, "design.m3": 0.0085,
                        "design.spring_k": 0.00044148403232269835}  # uniform, seed 7, draw 126
STEEP = "configs/scenes/steep.yaml"
# near steep's stored solution (seed 84, spread 0.15): draw 1 (the next frame's card kicks the hook out of the
# corner), draws 19 and 21 (then the hook creeps back along the back card, rolling, before it slides out)
KICKED_BY_THE_NEXT_CARD = {"design.La": 0.04652581157505513, "design.h": 0.009274969431459907, "design.m3": 0.0081,
                           "design.spring_k": 0.0010870393190985936}
ROLLS_ON_THE_BACK_CARD = {
    19: {"design.La": 0.049641660612970595, "design.h": 0.012306553730964663, "design.m3": 0.0073,
         "design.spring_k": 0.0011746434731393903},
    21: {"design.La": 0.04612453218251467, "design.h": 0.006662682867050172, "design.m3": 0.0073,
         "design.spring_k": 0.001902629603777864},
}
# near steep's stored solution (seed 84, spread 0.15), draw 4: after the kick the hook's slide out along the back card
# slows to rest while the next card still presses it
COMES_TO_REST = {"design.La": 0.047091632010340695, "design.h": 0.010899508810043337, "design.m3": 0.0082,
                 "design.spring_k": 0.0010607164763398696}
# ... draw 75: the next card meets the hook slipping across it
SLIPS_ACROSS_THE_CARD = {"design.La": 0.051956008971109996, "design.h": 0.005106028781589121, "design.m3": 0.0077,
                         "design.spring_k": 0.001145621911210433}
# ... draw 51: the next card presses the hook out along the back card for 20 ms
PRESSED_BY_THE_NEXT_CARD = {"design.La": 0.04972213297069073, "design.h": 0.012300938140153888, "design.m3": 0.0065,
                            "design.spring_k": 0.0013693889415210107}
# seed 4, draw 72: the hook lands on frame 1's back card and slides into its corner while the arm, just snapped,
# rests on its stop
OPENED_BY_THE_CORNER = {"design.La": 0.04417154983520508, "design.h": 0.008412264360934497, "design.m3": 0.0077,
                        "design.spring_k": 0.0013722392991503515}
# near steep's stored solution (seed 84), draw 68: the hook lands on frame 1's front card and reaches its corner within
# the landing's step
LANDS_BY_THE_CORNER = {"design.La": 0.044087845835387704, "design.h": 0.010273819111883643, "design.m3": 0.0076,
                       "design.spring_k": 0.0015856717017310455}
HELD_BY_THE_SKEWER = {"design.m3": 0.0076, "design.h": 0.004476120561920107, "design.La": 0.050056463856585326,
                      "design.spring_k": 0.0006478498642928119}  # seed 6, draw 85


# near steep's stored solution (seed 84, spread 0.15), draws 7 and 2: after the kick the hook sits out on its back card,
# held there by static friction while the frame climbs
HELD_OUT_ON_THE_BACK_CARD = {
    7: {"design.La": 0.04686206170052291, "design.h": 0.007692499050199987, "design.m3": 0.0082,
        "design.spring_k": 0.0014510609564788333},
    2: {"design.La": 0.04768178012296558, "design.h": 0.006968123462051155, "design.m3": 0.0068,
        "design.spring_k": 0.001111545721814054},
}


@pytest.fixture(autouse=True)
def _flat_frames(flat_side_cards):
    """Every scenario here was found on the frames' flat side cards (42.7 g·cm² for the prototype), before they were
    built hollow as the article's (66.9): the module keeps that machine, whose swings make these contacts."""


def _both(over, path=PAPER):
    cfg = load_config(path, over)
    return simulate(cfg), simulate_reduced(cfg.replace({"sim.fidelity": "reduced"}))


def test_a_landing_takes_the_arm_as_it_is_and_leaves_the_frame_on_its_rest_stop():
    """The hook meets frame 1's front card on its rounded end while the arm is still snapping (the step's end
    would already have it on its stop). The impact lifts the arm back and slips the hook in along the card; the
    frame stays on its rest stop. The model once took the arm as already stopped (the hook met the card at
    0.13 m/s, the world's at 1.17), let the sticking impulse decide the frame's stop and kicked the frame up
    0.7 deg."""
    world, model = _both(LANDS_MID_SNAP)
    w, m = world.swings[1], model.swings[1]
    assert m.t_catch == pytest.approx(w.t_catch, abs=1e-3)
    assert m.theta1_catch_deg == pytest.approx(w.theta1_catch_deg, abs=0.01)
    assert m.theta2_catch_deg == pytest.approx(w.theta2_catch_deg, abs=2.0)


def test_a_hook_meets_a_cards_end_outside_the_notchs_mouth():
    """The hook comes down onto the top of frame 1's front card end just outside the notch's mouth, its arm still
    snapping: it stops there and slides off the card, a graze ~10.5 mm from the seat, in the world. The model
    once tested the cards only inside the mouth: the hook passed through the card's end, met it 3 ms later with
    the arm on its stop, and slid in to a catch."""
    world, model = _both(ONTO_THE_CARDS_END)
    assert (model.outcome, model.traversals) == (world.outcome, world.traversals) == ("missed_catch", 0)
    assert "never seated" in world.reason and "never seated" in model.reason
    assert model.miss_distance == pytest.approx(world.miss_distance, abs=1e-3)


def test_the_arm_lifts_off_its_stop_over_the_cards_end_before_the_hook_lets_go():
    """At the first swing's end the hook rolls over the back card's rounded end; the arm's spring lifts the arm
    off its stop there and presses the hook on, so it lets go a few ms later with the arm already turning. The
    model let go 4.0 ms early; held on its stop by the axle's friction but with the hook judged before the stop,
    6.9 ms early with the arm still on its stop at 120 deg; with the stop freed first, 2.5 ms."""
    world, model = _both(ARM_LIFTS_AT_THE_END)
    w, m = world.swings[0], model.swings[0]
    assert m.t_detach == pytest.approx(w.t_detach, abs=3e-3)
    assert m.alpha_detach_deg == pytest.approx(w.alpha_detach_deg, abs=0.5)
    assert m.alpha_detach_deg < 119.5


def test_a_frame_on_its_stop_stays_there_until_the_pull_beats_its_skewers_friction():
    """At the start the robot's pull on frame 0 turns it off its rest stop, but for the first ~60 ms less than
    the skewer's dry friction holds: the world's frame stays put (the capped motor). The model's regularised
    friction once let it creep off (0.04 deg by 50 ms)."""
    cfg = load_config(PAPER, HELD_BY_THE_SKEWER)
    world = simulate(cfg, poses_every=5e-4)
    trace = swing_trace(cfg.replace({"sim.fidelity": "reduced"}), 0.056, detach=True)
    at = {round(t, 4): th[0] for t, th, *_ in world.poses}
    gaps = [abs(np.degrees(th - at[round(float(t), 4)])) for t, th in zip(trace["t"], trace["theta1"])]
    assert max(gaps) < 0.02, f"{max(gaps):.3f} deg"


@pytest.mark.parametrize("draw", sorted(BOUNCES_AT_THE_STOP))
def test_the_end_stop_throws_the_hook_off_the_back_card_and_the_robot_brings_it_back(draw):
    """The frame reaches its end stop with the hook 1-4 mm out along the back card. The pymunk world's hook
    lifts a fraction of a mm off the card and is back on it within sim.contact_hold (no detach), slides out over
    the card's end and lets go there. The model once held it at its place for the stop's impulse, which pulls
    on the card, and let go at the stop: 42 ms (draw 27) and 29 ms (draw 100) early. (Draw 100's flight after the
    detach parts from the world's: the model caught 61 ms before the world did even when this test was written,
    and its count of 1 matched the world's by chance, so the count is checked on draw 27 only.)"""
    world, model = _both(BOUNCES_AT_THE_STOP[draw])
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=2e-3)
    if draw == 27:
        assert model.traversals == world.traversals


def test_a_hook_that_slid_onto_the_cards_rounded_end_leaves_it_there():
    """The hook slides out along the back card onto its rounded end, where the face turns tensile: it leaves the
    card, as the world's does (the world's rolls a few ms further first). The model once set it back in the
    corner from there (the split at the face's end leaves s a rounding error short of it), three times, and
    let go 59 ms after the world."""
    world, model = _both(ROUNDS_THE_CARDS_END)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=15e-3)
    assert model.traversals == world.traversals


def test_on_a_steep_row_the_next_frames_card_kicks_the_hook_out_of_the_corner():
    """At theta1 ~ 145 deg frame 0 carries the hook past frame 1's back card, which the world's hook hits: it
    is thrown 1.7 mm out along frame 0's back card, and that decides where it lets go. The model without that
    contact passed the hook through the card and counted 1 traversal where the world counts 7. (Its first detach:
    7.5 ms before the world's without the kick, 10 ms with it alone, 2.5 ms with the hook rolling on the back card
    after it: test_a_hook_held_on_one_face_rolls_with_the_static_cone.)"""
    world, model = _both(KICKED_BY_THE_NEXT_CARD, STEEP)
    assert world.traversals == 7
    assert model.traversals == world.traversals, model.reason


@pytest.mark.parametrize("draw", sorted(ROLLS_ON_THE_BACK_CARD))
def test_a_hook_held_on_one_face_rolls_with_the_static_cone(draw):
    """After the kick the hook sits out on the back card while the arm turns: on one face the tip rolls (its
    contact point at rest on the card, static friction, no turning friction), creeping back along it, and slides
    out later than a tip held by the kinetic cone. The model with the kinetic cone let go 31 ms (draw 19) and
    6.5 ms (draw 21) early, and counted 1 and 5 traversals where the world counts 0 and 1."""
    world, model = _both(ROLLS_ON_THE_BACK_CARD[draw], STEEP)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=5e-3)
    assert model.traversals == world.traversals


@pytest.mark.parametrize("draw", sorted(HELD_OUT_ON_THE_BACK_CARD))
def test_the_friction_holding_the_hook_on_one_face_turns_the_robot_about_the_tip(draw):
    """A hook held out on one face sits on it by static friction, the force's component along the face, which acts
    at the tip's surface, a tip radius from the centre the robot turns about: a moment, as a slide's kinetic friction
    has (on steep draw 25 the reference world's single contact there carries r·jt = 21 uN·m: docs/fidelity.md).
    Without it the model let go 3.4 ms (draw 7) and 2.3 ms (draw 2) after the reference world and caught the next
    frame 7.0 and 2.2 ms late. Compared with the reference rung: the default world's own detach is up to 1 ms late
    here."""
    cfg = load_config(STEEP, HELD_OUT_ON_THE_BACK_CARD[draw])
    world = simulate(cfg.replace({"sim.fidelity": "reference"}))
    model = simulate_reduced(cfg.replace({"sim.fidelity": "reduced"}))
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=1.5e-3)
    assert model.swings[1].t_catch == pytest.approx(world.swings[1].t_catch, abs=1.5e-3)
    assert model.traversals == world.traversals


def test_kinetic_friction_stops_a_slide_and_never_turns_it_back():
    """A slide whose rate reaches zero within a step comes to rest there and sticks; the model once stepped on
    past it with the friction still set against the old sense, which then drove the hook back (and the next card's
    contact relabelled that as a slide the other way, 0.1 m/s out of 1 mm/s in one step). It let go 15.5 ms
    before the world's hook."""
    world, model = _both(COMES_TO_REST, STEEP)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=3e-3)
    assert model.traversals == world.traversals


def test_the_next_card_holds_the_hook_back_by_its_friction():
    """The hook meets the next frame's card slipping across it: the world's contact there carries a tangential
    impulse of mu_k times its normal one (scripts/world_contacts.py). With a frictionless contact the model let
    go 27 ms before the world and counted 1 traversal where the world counts 0."""
    world, model = _both(SLIPS_ACROSS_THE_CARD, STEEP)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=3e-3)
    assert model.traversals == world.traversals


def test_a_hook_pressed_by_the_next_card_is_pushed_all_along():
    """After the kick the world's next card keeps pressing the hook for some 20 ms, rounding its end, while the
    hook slides out along its own back card. The model's push came once per 4 ms step: within a step the hook's
    slide could slow to rest against its friction, and the next step's impulse threw it out again and the frame
    with it (steep draw 39: the frame 0.3 rad/s fast after the kick). Here it let go 11.5 ms after the world and
    counted 4 traversals where the world counts 7; its steps are now CAP_STEP long while the card presses."""
    world, model = _both(PRESSED_BY_THE_NEXT_CARD, STEEP)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=3e-3)
    assert model.traversals == world.traversals


def test_the_corner_stops_the_hook_and_lets_the_arm_open_off_its_stop():
    """The corner's impact ends the hook's slide into it; its impulse opens the arm, which lifts off its stop, as at
    a landing (stops push, never pull). The model once kept the arm on its stop through it, the robot turning as
    one body, and the second swing let go 84 ms after the world's."""
    world, model = _both(OPENED_BY_THE_CORNER)
    assert model.swings[0].t_detach == pytest.approx(world.swings[0].t_detach, abs=2e-3)
    assert model.swings[1].t_catch == pytest.approx(world.swings[1].t_catch, abs=2e-3)
    assert model.swings[1].t_detach == pytest.approx(world.swings[1].t_detach, abs=3e-3)


def test_a_landing_that_slides_into_the_corner_within_its_step_stops_there():
    """The hook lands on a face and reaches the corner before the landing's step ends: the corner stops it there,
    and the rest of the step sticks. The model once set it at the corner with its slide's rate still on (0.53
    m/s) and met the corner a step later, the robot having moved on as if the face went on past it; the second
    swing let go 23 ms before the world's."""
    world, model = _both(LANDS_BY_THE_CORNER, STEEP)
    assert model.swings[1].t_catch == pytest.approx(world.swings[1].t_catch, abs=3e-3)
    assert model.swings[1].t_detach == pytest.approx(world.swings[1].t_detach, abs=3e-3)


@pytest.mark.parametrize("scene", ["configs/paper.yaml", "configs/scenes/steep.yaml", "configs/scenes/wide_pitch.yaml"])
def test_the_next_card_test_is_skipped_only_where_no_hook_can_reach_the_next_card(scene):
    """params.next_card_reach skips next_card's test on designs whose hook cannot come near the next frame's cards
    (the test costs 9 % of the model's time). Run with the test forced on for every design, a batch gives the same
    records: the skip never drops a contact. On steep the test is needed (on every design resting at 55 deg; with
    the rest angle a choice, 50-70 deg, on about half), and on the prototype's scene it is off."""
    from aero_env.models.reduced import _run_table, check_scene
    from aero_env.models.reduced.constants import STEP
    from aero_env.models.reduced.layout import P
    from aero_env.models.reduced.params import param_table, raw_from_configs

    base = load_config(scene)
    cfgs = [c.replace({"sim.fidelity": "reduced"}) for c in draw_designs(base, 200, 5).configs]
    frames = check_scene(cfgs)
    table = param_table(raw_from_configs(cfgs), STEP)
    forced = table.copy()
    forced[:, P.next_card] = 1.0
    gated, always = _run_table(table, frames, STEP, True), _run_table(forced, frames, STEP, True)
    assert np.array_equal(gated.traversals, always.traversals)
    assert np.array_equal(np.nan_to_num(gated.t_detach), np.nan_to_num(always.t_detach))
    reach = table[:, P.next_card].mean()
    if "steep" in scene:
        assert 0.3 < reach and reach_at(table, cfgs, 55.0) == 1.0
    if "paper" in scene:
        assert reach == 0.0


def reach_at(table, cfgs, rest_deg: float) -> float:
    """The share of the designs resting at ``rest_deg`` whose hook can reach the next frame's card."""
    from aero_env.models.reduced.layout import P

    at = [i for i, c in enumerate(cfgs) if c.design.rest_angle_deg == rest_deg]
    assert at, f"no design rests at {rest_deg} deg"
    return float(table[at, P.next_card].mean())


def test_world_contacts_lists_the_steep_kick_and_refuses_a_bad_window_in_one_line(capsys):
    """scripts/world_contacts.py, the tool that found the steep kick: on KICKED_BY_THE_NEXT_CARD it shows the hook,
    in frame 0's corner (both of frame 0's cards), meeting frame 1's back card at theta1 ~ 144.9 deg, a new contact
    with a normal impulse several times the corner's, and its friction's across it."""
    import importlib.util

    from .conftest import ROOT

    spec = importlib.util.spec_from_file_location("world_contacts", ROOT / "scripts" / "world_contacts.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    sets = [a for k, v in KICKED_BY_THE_NEXT_CARD.items() for a in ("--set", f"{k}={v}")]
    assert script.main([STEEP, "--from", "0.4995", "--to", "0.5012", *sets]) == 0
    lines = capsys.readouterr().out.splitlines()[1:]
    before = next(ln for ln in lines if "frame1" not in ln)
    kick = next(ln for ln in lines if "frame1.back" in ln)
    assert "frame0.back" in before and "frame0.front" in before
    assert kick.split("frame1.back")[1].split()[3] == "new" and 144.5 < float(kick.split()[1]) < 145.5
    impulse = lambda line, card: float(line.split(card)[1].split()[1])  # noqa: E731
    assert impulse(kick, "frame1.back") > 3.0 * impulse(before, "frame0.back")
    assert script.main([PAPER, "--from", "1", "--to", "0.5"]) == 2
    assert capsys.readouterr().err.strip().count("\n") == 0


# ---- the next card's impulse, worked by hand ----
# next_card.card_impulse on a contact whose mass matrix is given: the rates (w1, ws) change by M^-1 J^T·impulse,
# M = diag(2, 0.5) here, the contact's normal rate 1·w1 + 0.5·ws and its rate along the card 0.2·w1 + 1·ws. Then
# K = J M^-1 J^T: Knn = 1·0.5·1 + 0.5·2·0.5 = 1.0, Knt = 1·0.5·0.2 + 0.5·2·1 = 1.1, Ktt = 0.2·0.5·0.2 + 1·2·1 = 2.02.
# (unit_impulse, which solves the hooked mass matrix, is replaced by this one: the test is of the Coulomb impact.)
J_N, J_T = (1.0, 0.5), (0.2, 1.0)
M_INV = (0.5, 2.0)


def _card_impulse(monkeypatch, vn, vt, mu_s, mu_k, slip_speed=0.01, j_t=J_T):
    from aero_env.models.reduced import next_card
    from aero_env.models.reduced.layout import P

    def unit_impulse(p, x, jth, js, slide_free):
        d0, ds = M_INV[0] * jth, M_INV[1] * js
        return d0, ds, 0.0, 0.0, jth * d0 + js * ds

    monkeypatch.setattr(next_card, "unit_impulse", unit_impulse)  # the plain-Python function looks it up
    p = np.zeros(len(P))
    p[P.mu_s], p[P.mu_k], p[P.slip_speed] = mu_s, mu_k, slip_speed
    return next_card.card_impulse.py_func(p, np.zeros(1), *J_N, *j_t, vn, vt, True)


def test_the_next_card_stops_a_slip_its_static_cone_holds(monkeypatch):
    """Slipping slower than sim.slip_speed, the cone is mu_s's: the impulse that stops the slip (and the approach)
    lies in it. Solving Knn·ln + Knt·lt = 1, Knt·ln + Ktt·lt = -0.005 (det 0.81): ln = 2.0255/0.81, lt = -1.105/0.81,
    |lt|/ln = 0.546, inside mu_s 0.6 and outside mu_k 0.3."""
    ln, lt = _card_impulse(monkeypatch, vn=-1.0, vt=0.005, mu_s=0.6, mu_k=0.3)
    assert (ln, lt) == pytest.approx((2.0255 / 0.81, -1.105 / 0.81), rel=1e-12)
    assert -1.0 + 1.0 * ln + 1.1 * lt == pytest.approx(0.0, abs=1e-12)  # the approach stopped
    assert 0.005 + 1.1 * ln + 2.02 * lt == pytest.approx(0.0, abs=1e-12)  # the slip stopped


def test_the_next_cards_sliding_impulse_is_kinetic_friction(monkeypatch):
    """Slipping at 2 m/s (faster than slip_speed) the stopping impulse, ln = 4.22/0.81, lt = -3.1/0.81
    (|lt|/ln = 0.73), lies outside the kinetic cone (mu_k 0.3), though inside the static one (mu_s 0.8): the hook
    slides on, and the card's friction is mu_k·ln against the slip, with ln what stops the approach:
    -1 + Knn·ln - Knt·mu_k·ln = 0, ln = 1/(1 - 0.33) = 1/0.67. With mu_s there it would be 1/(1 - 0.88) = 1/0.12,
    eight times as large; with mu_s's cone the slip would stop."""
    ln, lt = _card_impulse(monkeypatch, vn=-1.0, vt=2.0, mu_s=0.8, mu_k=0.3)
    assert ln == pytest.approx(1 / 0.67, rel=1e-12) and lt == pytest.approx(-0.3 / 0.67, rel=1e-12)
    assert -1.0 + 1.0 * ln + 1.1 * lt == pytest.approx(0.0, abs=1e-12)  # inelastic along the normal
    assert abs(lt) == pytest.approx(0.3 * ln, rel=1e-12)  # kinetic friction, against the slip
    # the same slip the other way: the friction turns with it (sg = -1: ln = 1/(1 + 0.33))
    ln, lt = _card_impulse(monkeypatch, vn=-1.0, vt=-2.0, mu_s=0.8, mu_k=0.3)
    assert ln == pytest.approx(1 / 1.33, rel=1e-12) and lt == pytest.approx(0.3 / 1.33, rel=1e-12)


def test_a_slow_slip_outside_the_static_cone_slides_with_kinetic_friction(monkeypatch):
    """Below slip_speed but outside mu_s's cone (mu_s 0.5 < 0.546): it slides, and the sliding friction is still
    mu_k's: ln = 1/(1 - 0.3·1.1)."""
    ln, lt = _card_impulse(monkeypatch, vn=-1.0, vt=0.005, mu_s=0.5, mu_k=0.3)
    assert (ln, lt) == pytest.approx((1 / 0.67, -0.3 / 0.67), rel=1e-12)


def test_a_contact_held_in_place_slides_with_kinetic_friction_or_jams_frictionless(monkeypatch):
    """Along the card the same direction as the normal's, (2, 1) = 2·(1, 0.5): K is singular (Knn 1, Knt 2, Ktt 4),
    no impulse stops the slip apart from the approach (the hook held at s). It slides: ln = 1/(1 - 2·mu_k) with
    mu_k 0.3, 2.5; with mu_k 0.5 and more no normal impulse stops the approach against the friction (1 - 2·mu_k
    <= 0): a frictionless impact, ln = 1/Knn."""
    held = (2.0, 1.0)
    assert _card_impulse(monkeypatch, vn=-1.0, vt=2.0, mu_s=0.9, mu_k=0.3, j_t=held) == pytest.approx((2.5, -0.75),
                                                                                                    rel=1e-12)
    assert _card_impulse(monkeypatch, vn=-1.0, vt=2.0, mu_s=0.9, mu_k=0.5, j_t=held) == (1.0, 0.0)
    assert _card_impulse(monkeypatch, vn=-1.0, vt=2.0, mu_s=0.9, mu_k=0.6, j_t=held) == (1.0, 0.0)
    assert _card_impulse(monkeypatch, vn=-1.0, vt=0.0, mu_s=0.9, mu_k=0.3, j_t=held) == (1.0, 0.0)  # no slip
