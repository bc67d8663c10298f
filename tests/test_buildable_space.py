"""A design space of a maker's choices (issue 34 §2): ``step`` snaps a tunable to what a maker can set (m3 to the
0.1 g of a kitchen scale: whole coins and clay), ``choices`` picks one of a list of measured values (the card pairs
of Table 3, each mu_s with its own mu_k). Checked on every action of a dense sample, by arithmetic written here."""

import math
from pathlib import Path

import numpy as np
import pytest

from aero_env.config import ConfigError, load_config
from aero_env.design_space import DesignSpace

ROOT = Path(__file__).resolve().parents[1]
SMALL = ROOT / "configs/small_frames.yaml"
TABLE_3 = {(0.507, 0.337), (0.542, 0.409), (0.283, 0.149)}  # the paper's measured card pairs


@pytest.fixture(scope="module")
def space():
    return DesignSpace(load_config(SMALL))


def test_every_action_names_whole_coins_and_clay_to_a_tenth_of_a_gram_and_a_measured_card_pair(space):
    actions = np.random.default_rng(5).uniform(-1, 1, (2000, space.dim)).astype(np.float32)
    actions[:8] = np.sign(actions[:8])  # the box's corners too
    (m3_lo, m3_hi), pairs = space.ranges[0], set()
    for a in actions:
        v = space.values(a)
        tenths = v["design.m3"] * 1e4  # kg to 0.1 g
        assert abs(tenths - round(tenths)) < 1e-6 and m3_lo <= v["design.m3"] <= m3_hi, v
        pair = (v["design.mu_s"], v["design.mu_k"])
        assert pair in TABLE_3, pair
        pairs.add(pair)
    assert pairs == TABLE_3  # every pair is reachable
    # the batch path (the vector env, the reduced model's screen) names the same designs, bit for bit
    cols = space.values_columns(actions)
    for i in range(0, len(actions), 97):
        one = space.values(actions[i])
        assert {k: cols[k][i] for k in cols} == one


def test_the_card_pair_is_an_equal_bin_of_the_box_per_choice_in_the_order_listed(space):
    j = [t.name for t in space.tunables].index("design.mu_s")
    a = space.action_for()
    seen = []
    for x in np.linspace(-1, 1, 301):
        a[j] = x
        seen.append(space.values(a)["design.mu_s"])
    # thirds of [-1, 1]: 0.507 below -1/3, 0.542 up to 1/3, 0.283 above
    assert seen[:100] == [0.507] * 100 and seen[101:200] == [0.542] * 99 and seen[201:] == [0.283] * 100


def test_the_configs_own_design_is_a_point_of_the_space(space):
    cfg = space.cfg
    a = space.action_for()
    v = space.values(a)
    assert v["design.m3"] == pytest.approx(cfg.design.m3, abs=1e-12) and v["design.mu_s"] == cfg.design.mu_s
    assert v["design.mu_k"] == cfg.design.mu_k


@pytest.mark.parametrize("entry, needle", [
    ({"name": "design.mu_s", "linked": ["design.mu_k"], "choices": [[0.5, 0.3], [0.6]]}, "choices[1]"),
    ({"name": "design.mu_s", "linked": ["design.mu_k"], "choices": [[0.5, 0.3], [0.5, 0.2]]}, "the same value"),
    ({"name": "design.mu_s", "choices": [[0.5]]}, "at least 2 choices"),
    ({"name": "design.mu_s", "linked": ["design.mu_k"], "choices": [[0.5, 0.3], [0.6, 0.4]], "step": 0.1},
     "tunable[0].step: not allowed with choices"),
    ({"name": "design.mu_s", "linked": ["design.mu_k"], "choices": [[0.5, 0.3], [-1.0, 0.4]]}, "choices[1][0]"),
    ({"name": "design.m3", "low": 0.005, "high": 0.009, "step": -0.001}, "tunable[0].step = -0.001"),
    ({"name": "design.m3", "low": 0.0051, "high": 0.0059, "step": "1 g"}, "no multiple of it lies in"),
])
def test_a_bad_choice_or_step_is_one_line_naming_it(entry, needle):
    with pytest.raises(ConfigError) as e:
        load_config(SMALL, {"tunable": [entry]})
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_a_design_off_the_makers_grid_is_refused_by_name(space):
    with pytest.raises(ConfigError, match=r"design.m3 = 0.00912: not a multiple of tunable\[0\].step"):
        space.action_for({"design.m3": 0.00912})
    with pytest.raises(ConfigError, match=r"design.mu_s = 0.6: not one of tunable\[4\]'s choices"):
        space.action_for({"design.mu_s": 0.6})


def test_a_tuned_buildable_design_reads_as_whole_coins_and_a_card_pair_on_its_sheet(tmp_path, space):
    """What the tune writes (the config with the design in) is read back as the sheet prints it: no fraction of a
    coin, and the card pair Table 3 measured, 0 % off."""
    from aero_env.cli import main

    a = np.array([0.37, 0.1, -0.2, 0.5, 0.9], np.float32)
    cfg = space.cfg.replace(space.values(a))
    path = tmp_path / "tuned.yaml"
    path.write_text(cfg.to_yaml())
    assert load_config(path) == cfg  # the step and the choices survive the round trip
    assert main(["sheet", str(path), "--out", str(tmp_path / "s.md"), "--draws", "0"]) == 0
    sheet = (tmp_path / "s.md").read_text()
    rest = cfg.design.m3 * 1e3 - 2 * 22.0**2 * 0.310e-3  # g: m3 less its two coin seats (card 22 mm a side)
    coins = math.floor(rest + 1e-9)
    assert f"{coins} one-yen coins + {rest - coins:.2f} g clay + 2 coin seats" in sheet
    assert "gray arm on gray handrail" in sheet and "within 0 %" in sheet


SOLUTIONS = sorted((ROOT / "configs/scenes/solutions").glob("*.yaml"))


@pytest.mark.parametrize("path", SOLUTIONS, ids=lambda p: p.stem)
def test_every_stored_scene_solution_is_a_design_a_maker_can_build(path):
    """Each scene's answer is a point of its own space of a maker's choices: its counterbalance a whole number of
    tenths of a gram (coins and clay), its card pair one Table 3 measured."""
    cfg = load_config(path)
    space = DesignSpace(cfg)
    assert any(t.step for t in space.tunables if t.name == "design.m3")
    tenths = cfg.design.m3 * 1e4
    assert abs(tenths - round(tenths)) < 1e-6, cfg.design.m3
    assert (cfg.design.mu_s, cfg.design.mu_k) in TABLE_3
    v = space.values(space.action_for(dtype=np.float64))  # refused if off the grid or not a choice
    # the action is read as float32 (the space's dtype), a step of 6e-8 of the box: a continuous field comes back
    # within 1e-6 of the stored value, a stepped one or a choice exactly
    assert all(v[k] == pytest.approx(cfg.value(k), rel=1e-6) for k in v)
    assert v["design.m3"] == cfg.design.m3
    assert all(v[k] == cfg.value(k) for k in v if k in ("design.mu_s", "design.mu_k"))


@pytest.mark.parametrize("override, needle", [
    ({"tunable": [{"name": "design.mu_s", "linked": ["design.mu_k"],
                   "choices": [[0.507, 0.337], [0.3, 0.6], [0.542, 0.409]]}]},
     "tunable[0].choices[1] = [0.3, 0.6]: not a valid design"),  # a middle choice, which no corner reaches
    ({"tunable": [{"name": "design.m3", "low": 0.7835, "high": 0.7875, "relative_to": "design.m2", "step": "0.1 g"}]},
     "tunable[0].step = 0.0001: no multiple of it lies in design.m3's range here"),  # relative: checked when posed
    ({"design.mu_k": 0.3}, "design.mu_k = 0.3: tunable[4]'s choice with design.mu_s = 0.542 sets it to 0.409"),
])
def test_a_space_that_would_name_an_invalid_or_other_design_is_refused_when_posed(override, needle):
    with pytest.raises(ConfigError) as e:
        DesignSpace(load_config(SMALL, override))
    assert needle in str(e.value) and "\n" not in str(e.value)


STORED = sorted(p for p in (ROOT / "configs").rglob("*.yaml") if p.name != "paper_targets.yaml")


def _searches_a_makers_choices(cfg, where):
    """Every mass a search may choose is set to the 0.1 g of a kitchen scale, every card pair is one of Table 3's,
    and the config's own design is a point of that space (a stored tune's answer included)."""
    from aero_env.config import real_field

    for t in cfg.tunable:
        if real_field(t.name, where).metadata["unit"] == "kg":
            assert t.step is not None and round(t.step * 1e4, 9) == 1.0, (where, t)
        if t.name in ("design.mu_s", "design.mu_k"):
            assert t.choices and {tuple(c) for c in t.choices} <= TABLE_3, (where, t)
    DesignSpace(cfg).action_for(dtype=np.float64)  # refused if off the grid or not a choice


@pytest.mark.parametrize("path", STORED, ids=lambda p: str(p.relative_to(ROOT / "configs")))
def test_every_stored_config_searches_only_a_makers_choices(path):
    _searches_a_makers_choices(load_config(path), str(path))


def test_every_registered_environment_poses_a_makers_choices():
    """What a policy chooses in each registered id (and with no config at all: the defaults) is buildable."""
    import gymnasium as gym

    import aero_env  # noqa: F401  (registers the ids)
    from aero_env.registration import ENVIRONMENTS

    for env_id in ENVIRONMENTS:
        env = gym.make(env_id, **{"sim.fidelity": "reduced"})
        _searches_a_makers_choices(env.unwrapped.config, env_id)
        env.close()
