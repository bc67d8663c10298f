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
from aero_env.models.reduced import simulate_batch, simulate_reduced
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
