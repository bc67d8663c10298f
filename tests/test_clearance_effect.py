"""``scene.effects.clearance``: a design whose kit's parts meet as its frames turn ends as ``collides`` (issue 49 §3).

The verdict is the static sweep of the row as the kit draws it (aero_env/parts/clearance.py, test_solids.py); here
the effect's plumbing is checked against plane geometry and against the run with the effect off: the single env,
the vector env at both engines, robustness and robust scoring, and that the effect off costs nothing.
"""

import math

import numpy as np
import pytest

from aero_env.cli import main
from aero_env.config import load_config
from aero_env.simulation import simulate

from .conftest import PAPER, ROOT
from .test_kit_readback import card_half_length, hollow_card
from .test_solids import ring, rings_overlap

# the prototype on a row that climbs 10 mm a frame: its handrails meet in any layout (test_nested_layout.py)
STEEP = ROOT / "configs/scenes/steep.yaml"
ON = {"scene.effects.clearance": True}


def test_a_design_whose_kit_collides_ends_as_collides_naming_the_parts_the_frame_and_the_angle():
    """The prototype on the steep scene's row: every frame drawn alike (the nested layout refuses it), and frame 1
    turning from rest meets frame 0's side card at its end stop at once: in the plane, the two hollow cards (the
    rectangles they are made of, placed by pitch and rise) overlap with frame 1 at its rest angle."""
    cfg = load_config(STEEP, ON)
    r = simulate(cfg)
    assert (r.outcome, r.traversals, r.swings, r.sim_time, r.miss_distance) == ("collides", 0, [], 0.0, None)
    assert not r.flew
    assert r.reason.startswith("the kit's parts meet (") and r.reason.endswith("(scene.effects.clearance)")
    assert "every frame drawn alike, as the nested layout does not serve this design: a frame's handrail lies in " \
           "its neighbour's handrail's path" in r.reason
    d, s = cfg.design, cfg.scene
    said = r.reason.split("): ", 1)[1]
    assert said.startswith("frame 1's side card (far) meets the side card (far) of frame 0 at its end stop from "
                           f"theta1 = {d.rest_angle_deg:.1f} deg")
    _, depth, end = hollow_card(d)
    half = card_half_length(d) * 1e-3
    turning = ring(s.pitch, s.rise, math.radians(d.rest_angle_deg), half, depth * 5e-4, end * 1e-3)
    still = ring(0.0, 0.0, math.radians(d.stop_angle_deg), half, depth * 5e-4, end * 1e-3)
    assert rings_overlap(turning, still)
    # the same design with the effect off: simulated as before (it falls short after two transfers)
    off = simulate(load_config(STEEP))
    assert off.outcome != "collides" and off.traversals == 2


def test_a_kit_that_clears_runs_bit_for_bit_as_with_the_effect_off(paper_cfg):
    on, off = simulate(paper_cfg.replace(ON)), simulate(paper_cfg)
    a, b = on.to_json_dict(), off.to_json_dict()
    a.pop("wall_time"), b.pop("wall_time")
    assert a == b and on.outcome == "completed"


def test_the_effect_off_never_checks(monkeypatch, paper_cfg):
    """Off (every shipped scene), the run never asks: the check is not made, however cheap."""
    from aero_env.parts import clearance

    def refuse(cfg):
        raise AssertionError("checked with the effect off")

    monkeypatch.setattr(clearance, "kit_clearance", refuse)
    assert simulate(paper_cfg.replace({"scene.frames": 3})).outcome == "completed"
    with pytest.raises(AssertionError, match="checked with the effect off"):
        simulate(paper_cfg.replace({"scene.frames": 3, **ON}))


def test_the_env_and_the_vector_env_at_both_engines_pay_a_collision_nothing():
    """The steep scene's own design through gym's single env and the vector env at mbd and at reduced (whose batch
    runs every design, then marks the colliding ones): outcome collides, reward 0, in every sub-env."""
    from aero_env.envs import AerialAcrobatEnv
    from aero_env.envs.aerial_acrobat_vector import AerialAcrobatVectorEnv

    env = AerialAcrobatEnv(STEEP, ON)
    env.reset(seed=0)
    action = env.space.action_for()
    _, reward, terminated, _, info = env.step(action)
    assert (reward, terminated, info["outcome"], info["traversals"]) == (0.0, True, "collides", 0)
    env.close()
    for fidelity in ("mbd", "reduced"):
        venv = AerialAcrobatVectorEnv(2, STEEP, {**ON, "sim.fidelity": fidelity})
        venv.reset(seed=0)
        _, rewards, _, _, infos = venv.step(np.stack([action, action]))
        assert rewards.tolist() == [0.0, 0.0], fidelity
        assert list(infos["final_info"]["outcome"]) == ["collides", "collides"], fidelity
        assert all(r.startswith("the kit's parts meet") for r in infos["final_info"]["reason"]), fidelity
        venv.close()
    # at reduced without the effect, the same design swings (and is paid what it traverses)
    venv = AerialAcrobatVectorEnv(1, STEEP, {"sim.fidelity": "reduced"})
    venv.reset(seed=0)
    step = venv.step(action[None])
    assert step[4]["final_info"]["outcome"][0] != "collides" and step[1][0] == step[4]["final_info"]["traversals"][0]
    venv.close()


def test_hand_made_builds_are_judged_by_the_kit_of_their_design(capsys):
    """Robustness and tune --robust: a build is cut from the kit drawn for the design, so every build of a design
    whose kit collides collides (its runs not simulated), and the builds of one that clears run as with the effect
    off (their small errors are not swept again)."""
    from agents.design_eval import DesignEvaluator, robust_factors

    assert main(["robustness", str(STEEP), "--draws", "3", "--set", "scene.effects.clearance=true",
                 "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "completed the row: 0 of 3 builds" in out and "collides 3" in out
    factors = robust_factors(0, 2)
    for config, expect in ((STEEP, ["collides"] * 2), (PAPER, None)):
        on = DesignEvaluator(load_config(config, {**ON, "scene.frames": 3}), [0], factors)
        off = DesignEvaluator(load_config(config, {"scene.frames": 3}), [0], factors)
        a, b = on.score_design(on.start_design), off.score_design(off.start_design)
        if expect is not None:
            assert list(a.outcomes) == expect and a.rewards == (0.0, 0.0)
        else:
            assert a == b


def test_forgetting_one_designs_verdict_keeps_the_others(monkeypatch):
    """The effects bench times each design's first check: it forgets that design's verdict and layout only, so a
    design checked before (another seed, another caller in the process) is not fitted again. Counted by the sweeps
    and fits that run."""
    from aero_env.parts import clearance, layout

    clearance.forget_verdicts()
    sweeps, fits = [], []
    sweep, fit = clearance.static_sweep, layout._build_nested
    monkeypatch.setattr(clearance, "static_sweep", lambda *a, **k: sweeps.append(1) or sweep(*a, **k))
    monkeypatch.setattr(layout, "_build_nested", lambda cfg: fits.append(1) or fit(cfg))
    steep, solved = load_config(STEEP), load_config(ROOT / "configs/scenes/solutions/steep.yaml")
    first = [clearance.kit_clearance(c) for c in (steep, solved)]
    counted = (len(sweeps), len(fits))
    assert fits == [1, 1] and layout.is_kept(steep) and layout.is_kept(solved)
    clearance.forget_verdicts(steep)
    assert not layout.is_kept(steep) and layout.is_kept(solved)
    assert clearance.kit_clearance(solved) == first[1] and (len(sweeps), len(fits)) == counted  # kept: nothing runs
    assert clearance.kit_clearance(steep) == first[0] and len(fits) == 3 and len(sweeps) > counted[0]  # checked again
    clearance.forget_verdicts()
    assert not layout.is_kept(solved)
