"""The design space (aero_env/design_space.py): actions to designs, the drawn context and the tolerances, and the
checks on both. Each mapping is worked out here from the config's numbers (a range's ends, a step, a bin), not
read back from the code that maps; every error is one line naming what is wrong."""

from __future__ import annotations

import math

import numpy as np
import pytest

from aero_env.config import ConfigError, load_config
from aero_env.design_space import DesignSpace, Draw, changes_outside_tunables, in_action_dtype

from .conftest import PAPER, ROOT, per_test_under_mutmut

CONTEXTS = ROOT / "configs" / "contexts.yaml"
F32 = lambda a: float(np.float32(a))  # noqa: E731  (an action as the env's float32 box holds it)




@pytest.fixture(scope=per_test_under_mutmut)
def paper():
    return DesignSpace(load_config(PAPER))


@pytest.fixture(scope=per_test_under_mutmut)
def contexts():
    return DesignSpace(load_config(CONTEXTS))


def _ranges(cfg):
    """paper.yaml's tunables, worked out from its values (relative_to: multiples of that field's value)."""
    d = cfg.design
    return {"design.m3": (0.5 * d.m2, 1.6 * d.m2), "design.h": (-0.2 * d.La, 0.4 * d.La),
            "design.La": (0.75 * d.La, 1.35 * d.La), "design.spring_k": (0.22 * d.spring_k, 4.5 * d.spring_k)}


# ---- actions to designs ----
def test_the_box_edges_are_the_ranges_ends_and_its_middle_their_middle(paper):
    cfg = paper.cfg
    r = _ranges(cfg)
    low, high = paper.values(-np.ones(paper.dim)), paper.values(np.ones(paper.dim))
    for key in ("design.h", "design.La", "design.spring_k"):
        assert (low[key], high[key]) == pytest.approx(r[key], rel=1e-15), key
    # m3 snaps to 0.1 g: the ends of 3.855-12.336 g on the grid are 3.9 and 12.3 g
    assert (low["design.m3"], high["design.m3"]) == (0.0039, 0.0123)
    mid = paper.values(np.zeros(paper.dim))
    assert mid["design.La"] == pytest.approx(sum(r["design.La"]) / 2, rel=1e-15)  # linear: the arithmetic middle
    assert mid["design.h"] == pytest.approx(sum(r["design.h"]) / 2, abs=1e-18)
    assert mid["design.spring_k"] == pytest.approx(math.sqrt(r["design.spring_k"][0] * r["design.spring_k"][1]),
                                                   rel=1e-12)  # log: the geometric middle
    assert mid["design.m3"] == round(sum(r["design.m3"]) / 2 / 1e-4) * 1e-4 == pytest.approx(0.0081)


@pytest.mark.parametrize("a", [-0.9, -0.5, -0.1, 0.3, 0.77])
def test_a_linear_and_a_log_range_are_mapped_as_stated(paper, a):
    r = _ranges(paper.cfg)
    action = np.full(paper.dim, a)
    v = paper.values(action)
    x = (F32(a) + 1) / 2
    lo, hi = r["design.La"]
    assert v["design.La"] == pytest.approx(lo + x * (hi - lo), rel=1e-14)
    lo, hi = r["design.spring_k"]
    assert v["design.spring_k"] == pytest.approx(lo * (hi / lo) ** x, rel=1e-14)
    lo, hi = r["design.m3"]
    assert v["design.m3"] == pytest.approx(round((lo + x * (hi - lo)) / 1e-4) * 1e-4, abs=1e-15)


def test_a_step_gives_the_multiple_as_a_maker_writes_it(paper):
    # 72 steps of 0.1 g is 0.0072 kg, not 72·1e-4 = 0.007200000000000001
    assert 72 * 1e-4 != 0.0072
    a = paper.action_for({"design.m3": 0.0072}, dtype=np.float64)
    assert paper.values(a)["design.m3"] == 0.0072
    every = {paper.values(np.r_[x, np.zeros(paper.dim - 1)])["design.m3"] for x in np.linspace(-1, 1, 301)}
    assert all(v == float(f"{round(v / 1e-4) * 1e-4:.12g}") for v in every)
    assert min(every) == 0.0039 and max(every) == 0.0123 and len(every) == 85  # 3.9 to 12.3 g, every 0.1 g


@pytest.mark.parametrize("a, pair", [(-1.0, (0.283, 0.149)), (-0.34, (0.283, 0.149)), (-0.33, (0.507, 0.337)),
                                     (0.0, (0.507, 0.337)), (0.33, (0.507, 0.337)), (0.34, (0.542, 0.409)),
                                     (1.0, (0.542, 0.409))])
def test_choices_cut_the_box_into_equal_bins_in_the_order_listed(paper, a, pair):
    action = np.zeros(paper.dim)
    action[-1] = a  # design.mu_s: three pairs, bins [-1, -1/3), [-1/3, 1/3), [1/3, 1]
    v = paper.values(action)
    assert (v["design.mu_s"], v["design.mu_k"]) == pair
    cols = paper.values_columns(action[None, :])
    assert (cols["design.mu_s"][0], cols["design.mu_k"][0]) == pair


def test_a_linked_field_follows_by_the_same_factor(contexts):
    # contexts.yaml draws mu_s over 0.283-0.542 with mu_k linked: mu_k keeps the prototype's ratio 0.409/0.542
    cfg = contexts.cfg
    draw = Draw({**{c.name: cfg.value(c.name) for c in contexts.context}, "design.mu_s": 0.283}, (0.0, 0.0))
    values, built = contexts.episode_values({}, draw)
    assert values["design.mu_k"] == pytest.approx(0.283 * 0.409 / 0.542, rel=1e-15)
    assert built == {"design.m3": cfg.design.m3, "design.La": cfg.design.La}  # u = 0: as designed


def test_values_columns_are_values_row_by_row_to_the_bit(paper, contexts):
    rng = np.random.default_rng(5)
    for space in (paper, contexts):
        actions = rng.uniform(-1, 1, (64, space.dim))
        actions[0], actions[1] = -1.0, 1.0
        cols = space.values_columns(actions)
        for i, a in enumerate(actions):
            row = space.values(a)
            assert set(cols) == set(row)
            for key, v in row.items():
                assert cols[key][i] == v, (key, i)


def test_action_for_is_the_inverse_of_values(paper):
    cfg = paper.cfg
    a = paper.action_for()
    assert a.dtype == np.float32
    back = paper.values(a)
    for key in ("design.h", "design.La", "design.spring_k"):
        assert back[key] == pytest.approx(cfg.value(key), rel=1e-6)  # through float32
    assert back["design.m3"] == cfg.design.m3 and back["design.mu_s"] == cfg.design.mu_s
    r = _ranges(cfg)
    a = paper.action_for({"design.La": r["design.La"][1], "design.h": r["design.h"][0],
                          "design.spring_k": r["design.spring_k"][0], "design.m3": 0.0123, "design.mu_s": 0.283},
                         dtype=np.float64)
    assert a.dtype == np.float64
    assert a[1] == pytest.approx(-1.0, abs=1e-12) and a[2] == pytest.approx(1.0, abs=1e-12)
    assert a[3] == pytest.approx(-1.0, abs=1e-12)
    assert a[0] == pytest.approx(2 * (0.0123 - r["design.m3"][0]) / (r["design.m3"][1] - r["design.m3"][0]) - 1,
                                 rel=1e-12)
    assert a[4] == pytest.approx(-2 / 3, rel=1e-12)  # the middle of the first of three bins
    a = paper.action_for({"design.spring_k": math.sqrt(r["design.spring_k"][0] * r["design.spring_k"][1])},
                         dtype=np.float64)
    assert a[3] == pytest.approx(0.0, abs=1e-12)  # log: the geometric middle is the box's middle


@pytest.mark.parametrize("values, message", [
    ({"design.mu_k": 0.3}, "action_for: 'design.mu_k' cannot be chosen, it follows design.mu_s (linked); tunable "
                           "fields: ['design.La', 'design.h', 'design.m3', 'design.mu_s', 'design.spring_k']"),
    ({"design.Lb": 0.05}, "action_for: 'design.Lb' cannot be chosen, it is not tunable; tunable fields: "),
    ({"design.mu_s": 0.3}, "design.mu_s = 0.3: not one of tunable[4]'s choices [0.283, 0.507, 0.542] (a maker's "
                           "measured values)"),
    ({"design.m3": 0.00725}, "design.m3 = 0.00725: not a multiple of tunable[0].step = 0.0001 (what a maker can "
                             "set); the nearest is 0.0072"),
    ({"design.La": 0.1}, "design.La = 0.1: outside tunable[2]'s range [0.036225, 0.065205]"),
    ({"design.La": 0.03}, "design.La = 0.03: outside tunable[2]'s range [0.036225, 0.065205]"),
])
def test_action_for_refuses_what_no_action_names(paper, values, message):
    with pytest.raises(ConfigError) as exc:
        paper.action_for(values)
    assert str(exc.value).startswith(message), str(exc.value)


def test_a_config_whose_pair_is_not_a_listed_choice_is_refused():
    cfg = load_config(PAPER, {"design.mu_k": 0.4})
    with pytest.raises(ConfigError, match=r"design.mu_k = 0.4: tunable\[4\]'s choice with design.mu_s = 0.542 sets it "
                                          r"to 0.409; give the pair as listed"):
        DesignSpace(cfg)


def test_naming_a_choices_leader_chooses_its_whole_pair(paper):
    assert paper.action_for({"design.mu_s": 0.283})[4] == np.float32(-2 / 3)
    assert paper.action_for({"design.mu_s": 0.542})[4] == np.float32(2 / 3)


# ---- what an action may be ----
@pytest.mark.parametrize("action, message", [
    ("abc", "action = 'abc': must be 5 numbers in [-1, 1] (an integer or float array), got dtype <U3"),
    ([None] * 5, "got non-numbers"),
    ([True] * 5, "got dtype bool"),
    (np.zeros(4), "action has shape (4,): expected (5,), one value per tunable (design.m3, design.h, design.La, "
                  "design.spring_k, design.mu_s)"),
    (np.zeros((1, 5)), "action has shape (1, 5): expected (5,)"),
    ([0, 0, float("nan"), 0, 0], "action[2] (design.La) = nan: must be a finite number in [-1, 1]"),
    ([0, 0, 0, float("-inf"), 0], "action[3] (design.spring_k) = -inf: must be a finite number in [-1, 1]"),
    ([0, 1.5, 0, 0, 0], "action[1] (design.h) = 1.5: out of the action box, allowed [-1, 1] (or set "
                        "env.action_out_of_box: clip)"),
    ([0, 0, 0, 0, -1.0001], "action[4] (design.mu_s) = -1.0001: out of the action box"),
])
def test_a_bad_action_is_refused_naming_the_dimension(paper, action, message):
    with pytest.raises(ConfigError) as exc:
        paper.check_action(action, clip=False)
    assert message in str(exc.value) and str(exc.value).startswith("action"), str(exc.value)


def test_check_action_clips_where_asked_and_keeps_a_boxed_action(paper):
    a = paper.check_action([0, 1.5, -3, 0.25, 1], clip=True)
    assert a.dtype == np.float64 and a.tolist() == [0.0, 1.0, -1.0, 0.25, 1.0]
    assert paper.check_action(np.array([1, -1, 0, 0, 1], dtype=np.int64), clip=False).tolist() == [1, -1, 0, 0, 1]
    with pytest.raises(ConfigError, match="must be a finite number"):
        paper.check_action([0, 0, float("inf"), 0, 0], clip=True)  # clipping does not make inf a position


def test_rows_in_box_is_check_action_of_every_row(paper):
    rows = np.array([[0, 0.5, -1, 1, 0.2], [1, 1, 1, 1, 1]])
    assert paper.rows_in_box(rows, clip=False).tolist() == rows.tolist()
    assert paper.rows_in_box(rows * 2, clip=False) is None
    assert paper.rows_in_box(rows * 2, clip=True).tolist() == np.clip(rows * 2, -1, 1).tolist()
    assert paper.rows_in_box(rows.astype(np.float32), clip=False).dtype == np.float64
    bad = rows.astype(float)
    bad[1, 3] = np.nan
    assert paper.rows_in_box(bad, clip=True) is None and paper.rows_in_box(rows.astype(str), clip=True) is None
    assert paper.rows_in_box(np.full((2, 5), np.inf), clip=True) is None


def test_in_action_dtype_reads_through_float32():
    a = np.array([0.1, -1 / 3, 1.0])
    got = in_action_dtype(a)
    assert got.dtype == np.float64 and got.tolist() == [F32(0.1), F32(-1 / 3), 1.0] and got[0] != 0.1


# ---- the context and the tolerances ----
def test_the_draw_is_uniform_over_each_context_range_and_the_tolerances_over_minus_one_to_one(contexts):
    cfg = contexts.cfg
    rng = np.random.default_rng(11)
    u = np.random.default_rng(11).random(len(contexts.context) + len(contexts.tolerances))
    draw = contexts.draw(rng)
    for c, ui in zip(contexts.context, u):
        assert draw.context[c.name] == pytest.approx(c.low + ui * (c.high - c.low), rel=1e-15)
    assert draw.tolerance_u == pytest.approx(tuple(2 * x - 1 for x in u[len(contexts.context):]), rel=1e-15)
    assert contexts.draws_anything and len(draw.tolerance_u) == 2
    values, built = contexts.episode_values(contexts.values(np.zeros(contexts.dim)), draw)
    # the tolerances as built: value·(1 + relative·u) + absolute·u; m3 ±2 %, La ±0.3 mm
    m3 = contexts.values(np.zeros(contexts.dim))["design.m3"]
    assert built["design.m3"] == pytest.approx(m3 * (1 + 0.02 * draw.tolerance_u[0]), rel=1e-15)
    la = contexts.values(np.zeros(contexts.dim))["design.La"]
    assert built["design.La"] == pytest.approx(la + 0.0003 * draw.tolerance_u[1], rel=1e-15)
    assert values["scene.rise"] == draw.context["scene.rise"]
    assert values["design.mu_k"] == pytest.approx(draw.context["design.mu_s"] * cfg.design.mu_k / cfg.design.mu_s)
    obs = contexts.observation(draw)
    assert obs.dtype == np.float32
    for i, c in enumerate(contexts.context):
        assert obs[i] == np.float32(2 * (draw.context[c.name] - c.low) / (c.high - c.low) - 1)


def test_draw_for_seed_is_the_draw_of_gymnasiums_generator_for_that_seed(contexts):
    from gymnasium.utils import seeding

    assert contexts.draw_for_seed(7) == contexts.draw(seeding.np_random(7)[0])
    assert contexts.draw_for_seed(7) != contexts.draw_for_seed(8)


def test_a_space_that_draws_nothing_has_one_fixed_draw(paper, contexts):
    cfg = paper.cfg
    assert not paper.draws_anything and paper.varied_context == ()
    fixed = paper.fixed_draw()
    assert fixed == Draw({c.name: cfg.value(c.name) for c in paper.context}, ())
    assert fixed == paper.draw(np.random.default_rng(3)) == paper.nominal_draw()
    assert paper.observation(fixed).tolist() == [0.0] * paper.obs_dim
    with pytest.raises(ValueError, match="this space draws a context or a tolerance; use draw"):
        contexts.fixed_draw()
    nominal = contexts.nominal_draw()
    assert nominal.tolerance_u == (0.0, 0.0)
    assert nominal.context == {c.name: (c.low + c.high) / 2 for c in contexts.context}
    assert contexts.observation(nominal).tolist() == pytest.approx([0.0] * contexts.obs_dim, abs=1e-7)


def test_a_fixed_range_draws_low_plus_nothing():
    # a context whose range is one value draws low + u·0, which turns a -0.0 into 0.0
    cfg = load_config(PAPER, {"scene.rise": -0.0, "context": [{"name": "scene.rise", "low": -0.0, "high": -0.0}]})
    space = DesignSpace(cfg)
    assert not space.draws_anything
    rise = space.fixed_draw().context["scene.rise"]
    assert rise == 0.0 and math.copysign(1, rise) == 1.0
    assert space.draw(np.random.default_rng(0)).context["scene.rise"] == rise


def test_episode_columns_are_episode_values_of_each_episode(contexts, paper):
    for space in (contexts, paper):
        rng = np.random.default_rng(2)
        actions = rng.uniform(-1, 1, (12, space.dim))
        draws = [space.draw(rng) for _ in actions]
        cols, built_cols = space.episode_columns(space.values_columns(actions), draws)
        for i, (a, d) in enumerate(zip(actions, draws)):
            values, built = space.episode_values(space.values(a), d)
            assert set(cols) == set(values) and set(built_cols) == set(built)
            for key, v in values.items():
                assert cols[key][i] == v, key
            for key, v in built.items():
                assert built_cols[key][i] == v, key
        obs = space.observations(draws)
        assert obs.shape == (12, space.obs_dim) and obs.dtype == np.float32
        assert obs.tolist() == [space.observation(d).tolist() for d in draws]


def test_the_episode_config_is_the_config_with_the_episodes_values(contexts):
    draw = contexts.draw(np.random.default_rng(4))
    design = contexts.values(np.full(contexts.dim, 0.5))
    cfg, built = contexts.episode_config(design, draw)
    values, built2 = contexts.episode_values(design, draw)
    assert built == built2
    for key, v in values.items():
        assert cfg.value(key) == v, key


# ---- the space's own checks ----
@pytest.mark.parametrize("overrides, message", [
    ({"tunable": []}, "tunable: empty; the action space needs at least one tunable field"),
    ({"context": []}, "context: empty; the observation needs at least one field (e.g. scene.rise)"),
    ({"design.spring_damping": 0.0, "tunable": [{"name": "design.spring_damping", "low": 0.0, "high": 0.5,
                                                  "linked": ["design.Cd"]}]},
     "tunable[0].linked: the links scale by design.spring_damping / its config value, which is 0.0; allowed only "
     "when that value is > 0"),
    ({"context": [{"name": "design.dT", "low": -1e-4, "high": 1e-4, "linked": ["design.Lc"]}]},
     "context[0].linked: the links scale by design.dT / its config value, which is 0.0; allowed only when that value "
     "is > 0"),
])
def test_a_space_that_cannot_be_built_is_refused_in_one_line(overrides, message):
    with pytest.raises(ConfigError) as exc:
        DesignSpace(load_config(PAPER, overrides))
    assert str(exc.value).startswith(message) and "\n" not in str(exc.value), str(exc.value)


def test_a_corner_that_is_no_design_is_named():
    # the arm up to 3x its 1.5 g: at that corner the robot's 7.71 g no longer holds the arm, the coins and the
    # handrail (the config's check says so after the corner)
    cfg = load_config(PAPER, {"tunable": [{"name": "design.arm_mass", "low": 0.5, "high": 3.0,
                                           "relative_to": "design.arm_mass"}]})
    with pytest.raises(ConfigError) as exc:
        DesignSpace(cfg)
    text = str(exc.value)
    assert text.startswith("the design space reaches an invalid design at the corner (design.arm_mass=0.0045, "
                           "scene.rise=0.002, scene.pitch=0.076, design.m2=0.00771): design.m2 = 0.00771"), text


def test_a_corner_with_a_tolerance_names_it():
    # up to 2.3x the arm fits (3.45 + 4 + 0.21 < 7.71 g); built 2 % heavier it does not
    over = {"tunable": [{"name": "design.arm_mass", "low": 0.5, "high": 2.3, "relative_to": "design.arm_mass"}]}
    DesignSpace(load_config(PAPER, over))
    cfg = load_config(PAPER, {**over, "tolerance": [{"name": "design.arm_mass", "relative": 0.02}]})
    with pytest.raises(ConfigError) as exc:
        DesignSpace(cfg)
    assert str(exc.value).startswith("the design space reaches an invalid design at the corner (design.arm_mass="
                                     "0.00345, scene.rise=0.002, scene.pitch=0.076, design.m2=0.00771, tolerances "
                                     "(1.0,)): "), str(exc.value)


def test_a_choice_that_is_no_design_is_named():
    cfg = load_config(PAPER, {"tunable": [{"name": "design.mu_s", "linked": ["design.mu_k"],
                                           "choices": [[0.542, 0.409], [0.3, 0.5]]}]})
    with pytest.raises(ConfigError, match=r"tunable\[0\].choices\[1\] = \[0.3, 0.5\]: not a valid design with the "
                                          r"config's other values: "):
        DesignSpace(cfg)


def test_a_wide_space_checks_a_sample_of_its_corners(monkeypatch):
    """Beyond EXHAUSTIVE_CORNERS varied dimensions a fixed sample of 4096 corners is checked, not all of them."""
    import aero_env.design_space as ds

    cfg = load_config(CONTEXTS)
    seen = []
    real = DesignSpace.episode_config
    monkeypatch.setattr(DesignSpace, "episode_config", lambda self, *a: (seen.append(1), real(self, *a))[1])
    DesignSpace(cfg)  # 5 tunables + 4 varied contexts + 2 tolerances: 11 dimensions, 2048 corners
    assert len(seen) == 2**11
    seen.clear()
    monkeypatch.setattr(ds, "EXHAUSTIVE_CORNERS", 10)
    DesignSpace(cfg)
    assert len(seen) == 2**10


# ---- another design for the same scene ----
def test_changes_outside_tunables_lists_what_is_not_a_design_change(paper):
    cfg = paper.cfg
    assert changes_outside_tunables(cfg, cfg) == []
    # tunables and the key linked to one are a design; anything else is another scene or robot
    assert changes_outside_tunables(cfg, cfg.replace({"design.m3": 0.008, "design.mu_s": 0.283,
                                                      "design.mu_k": 0.149})) == []
    other = cfg.replace({"design.m2": 0.009, "scene.frames": 3, "scene.effects.drag": True, "design.La": 0.05})
    assert changes_outside_tunables(cfg, other) == ["design.m2", "scene.effects.drag", "scene.frames"]


# ---- the column path on every kind of tunable, and the range's ends to the bit ----
def _columns_match_rows(space, actions):
    cols = space.values_columns(actions)
    for i, a in enumerate(actions):
        row = space.values(a)
        assert set(cols) == set(row)
        for key, v in row.items():
            assert cols[key][i] == v and cols[key].dtype == np.float64, (key, i)
    return cols


def test_a_choice_listed_before_other_tunables_leaves_them_mapped():
    cfg = load_config(PAPER, {"tunable": [
        {"name": "design.mu_s", "linked": ["design.mu_k"], "choices": [[0.283, 0.149], [0.542, 0.409]]},
        {"name": "design.La", "low": 0.9, "high": 1.1, "relative_to": "design.La"}]})
    space = DesignSpace(cfg)
    cols = _columns_match_rows(space, np.array([[-0.5, -1.0], [0.5, 1.0], [0.0, 0.0]]))
    assert cols["design.La"].tolist() == pytest.approx([0.9 * 0.0483, 1.1 * 0.0483, 0.0483], rel=1e-14)
    assert cols["design.mu_k"].tolist() == [0.149, 0.409, 0.409]


def test_a_linked_tunable_carries_its_links_by_the_same_factor():
    # mu_s searched over 0.3-0.6 with mu_k linked: mu_k = 0.409 · mu_s / 0.542 for every action, both paths
    cfg = load_config(PAPER, {"tunable": [{"name": "design.mu_s", "low": 0.3, "high": 0.6,
                                           "linked": ["design.mu_k"]}]})
    space = DesignSpace(cfg)
    actions = np.linspace(-1, 1, 7)[:, None]
    cols = _columns_match_rows(space, actions)
    assert cols["design.mu_k"].tolist() == pytest.approx((cols["design.mu_s"] * 0.409 / 0.542).tolist(), rel=1e-15)
    assert space.values(np.array([1.0]))["design.mu_k"] == pytest.approx(0.6 * 0.409 / 0.542, rel=1e-15)


def test_a_log_range_ends_at_its_high_to_the_bit_where_the_power_rounds_past_it():
    # 0.004 · (0.009 / 0.004) rounds above 0.009: the value at +1 is the range's end, as at -1
    assert 0.004 * (0.009 / 0.004) ** 1.0 > 0.009
    cfg = load_config(PAPER, {"tunable": [{"name": "design.m3", "low": 0.004, "high": 0.009, "scale": "log"}]})
    space = DesignSpace(cfg)
    assert space.values(np.array([1.0]))["design.m3"] == 0.009 and space.values(np.array([-1.0]))["design.m3"] == 0.004
    cols = _columns_match_rows(space, np.array([[-1.0], [1.0], [0.0]]))
    assert cols["design.m3"].tolist()[:2] == [0.004, 0.009]


def test_a_tolerance_on_a_field_the_design_does_not_set_is_built_from_the_configs_value():
    # Lb is neither tunable nor drawn: built as 51.7 mm · (1 + 0.02·u) + 0.1 mm · u
    cfg = load_config(PAPER, {"tolerance": [{"name": "design.Lb", "relative": 0.02, "absolute": 0.0001}]})
    space = DesignSpace(cfg)
    rng = np.random.default_rng(9)
    draws = [space.draw(rng) for _ in range(5)]
    actions = rng.uniform(-1, 1, (5, space.dim))
    cols, built_cols = space.episode_columns(space.values_columns(actions), draws)
    for i, (a, d) in enumerate(zip(actions, draws)):
        values, built = space.episode_values(space.values(a), d)
        u = d.tolerance_u[0]
        assert built == {"design.Lb": pytest.approx(0.0517 * (1 + 0.02 * u) + 0.0001 * u, rel=1e-15)}
        assert built_cols["design.Lb"][i] == built["design.Lb"] and cols["design.Lb"][i] == values["design.Lb"]
    assert built_cols["design.Lb"].dtype == np.float64


def test_a_ragged_action_is_refused_as_non_numbers(paper):
    with pytest.raises(ConfigError) as exc:
        paper.check_action([[0, 0], [0]], clip=True)
    assert str(exc.value) == ("action = [[0, 0], [0]]: must be 5 numbers in [-1, 1] (an integer or float array), got "
                              "non-numbers")


def test_fixed_draw_refuses_a_space_that_draws_in_one_line(contexts):
    with pytest.raises(ValueError) as exc:
        contexts.fixed_draw()
    assert str(exc.value) == "fixed_draw: this space draws a context or a tolerance; use draw(rng)"


def test_a_context_fixed_to_one_value_is_observed_as_0():
    cfg = load_config(PAPER, {"context": [{"name": "scene.rise", "low": 0.002, "high": 0.002},
                                          {"name": "scene.pitch", "low": 0.07, "high": 0.08}]})
    space = DesignSpace(cfg)
    draws = [space.draw(np.random.default_rng(s)) for s in range(3)]
    obs = space.observations(draws)
    assert obs[:, 0].tolist() == [0.0, 0.0, 0.0]  # not 0/0
    assert obs[:, 1].tolist() == [np.float32(2 * (d.context["scene.pitch"] - 0.07) / 0.01 - 1) for d in draws]


def test_the_corners_are_the_ends_of_each_range_not_beyond():
    # m3 built ±50 %: at the corner u = -1 it is half the design's, still a counterbalance; twice that error is none
    cfg = load_config(PAPER, {"tolerance": [{"name": "design.m3", "relative": 0.5}]})
    DesignSpace(cfg)


def test_the_lower_corner_is_checked_too():
    # Ld down to a tenth of its 60 mm: the torso then cannot hold the coins, at the range's low end only
    cfg = load_config(PAPER, {"tunable": [{"name": "design.Ld", "low": 0.1, "high": 1.0, "relative_to": "design.Ld"}]})
    with pytest.raises(ConfigError) as exc:
        DesignSpace(cfg)
    assert str(exc.value).startswith("the design space reaches an invalid design at the corner (design.Ld=0.006, "
                                      "scene.rise=0.002, scene.pitch=0.076, design.m2=0.00771): design.Ld = 0.006"), \
        str(exc.value)


def test_up_to_exhaustive_corners_every_corner_is_checked_once_and_beyond_a_fixed_sample(monkeypatch):
    import aero_env.design_space as ds

    cfg = load_config(CONTEXTS)  # 11 varied dimensions
    seen = []
    real = DesignSpace.episode_config
    monkeypatch.setattr(DesignSpace, "episode_config",
                        lambda self, design, draw: (seen.append((tuple(design.values()), tuple(draw.context.values()),
                                                                 draw.tolerance_u)), real(self, design, draw))[1])
    monkeypatch.setattr(ds, "EXHAUSTIVE_CORNERS", 11)
    space = DesignSpace(cfg)
    assert len(seen) == len(set(seen)) == 2**11  # all of them, each once

    def ends(corners):
        """Each dimension's values over ``corners``: (tunables' values, contexts' values, tolerances' u)."""
        designs, contexts, tols = zip(*corners)
        assert {len(t) for t in tols} == {len(space.tolerances)}
        return ([set(col) for col in zip(*designs)], [set(col) for col in zip(*contexts)], [set(col) for col in zip(*tols)])

    designs, contexts, tols = ends(seen)
    lows, highs = space.values(-np.ones(space.dim)), space.values(np.ones(space.dim))
    assert designs == [{lows[k], highs[k]} for k in space.values(np.zeros(space.dim))]
    assert contexts == [{c.low, c.high} if c.low is not None else {cfg.value(c.name)} for c in space.context]
    assert tols == [{-1.0, 1.0}] * len(space.tolerances)
    monkeypatch.setattr(ds, "EXHAUSTIVE_CORNERS", 10)
    samples = []
    for _ in range(2):
        seen.clear()
        DesignSpace(cfg)
        samples.append(list(seen))
    assert len(samples[0]) == 2**10 and samples[0] == samples[1]  # a fixed sample: the same every time
    assert len(set(samples[0])) < 2**10  # drawn with replacement
    assert ends(samples[0]) == (designs, contexts, tols)  # reaching both ends of every dimension


def test_action_for_reads_a_value_as_the_config_reads_one(paper):
    # a unit written is read (7.2 g is 0.0072 kg); a value that is no number is refused naming the field
    assert paper.action_for({"design.m3": "7.2 g"}).tolist() == paper.action_for({"design.m3": 0.0072}).tolist()
    for bad in (float("nan"), None):
        with pytest.raises(ConfigError) as exc:
            paper.action_for({"design.m3": bad})
        assert str(exc.value).startswith(f"design.m3 = {bad}: "), str(exc.value)


@pytest.mark.parametrize("low, high, at_low, at_high", [
    (0.00382, 0.01238, 0.0039, 0.0123),  # off the grid: the nearest multiple inside the range (3.8 and 12.4 g are not)
    (0.0039 * (1 + 1e-12), 0.0123 * (1 - 1e-12), 0.0039 * (1 + 1e-12), 0.0123 * (1 - 1e-12)),  # a hair off: the bound
])
def test_a_stepped_range_keeps_its_values_on_the_grid_and_inside_the_range(low, high, at_low, at_high):
    """m3 in 0.1 g steps over a range whose ends are not multiples of 0.1 g: the box's ends give the nearest
    multiples inside it; an end within rounding of a multiple (1e-9 of a step) is taken as on the grid and kept to the
    bit."""
    cfg = load_config(PAPER, {"tunable": [{"name": "design.m3", "low": low, "high": high, "step": 1e-4}]})
    space = DesignSpace(cfg)
    assert space.values(np.array([-1.0]))["design.m3"] == at_low
    assert space.values(np.array([1.0]))["design.m3"] == at_high
    cols = _columns_match_rows(space, np.array([[-1.0], [1.0], [0.0]]))
    assert cols["design.m3"].tolist()[:2] == [at_low, at_high]


def test_a_choice_is_not_scaled_so_its_config_value_may_be_zero():
    # a choice sets its linked keys to the choice's values: no factor, so a leader at 0 in the config is fine
    cfg = load_config(PAPER, {"design.h": 0.0, "tunable": [{"name": "design.h", "linked": ["design.Lc"],
                                                            "choices": [[0.0, 0.03], [0.005, 0.03]]}]})
    space = DesignSpace(cfg)
    assert space.values(np.array([1.0])) == {"design.h": 0.005, "design.Lc": 0.03}


def test_a_tolerance_of_nothing_draws_nothing():
    cfg = load_config(PAPER, {"tolerance": [{"name": "design.m3"}, {"name": "design.La", "relative": 0.0,
                                                                    "absolute": 0.0}]})
    space = DesignSpace(cfg)
    assert space.tolerances == () and not space.draws_anything
    cfg = load_config(PAPER, {"tolerance": [{"name": "design.m3", "absolute": 1e-4}, {"name": "design.La",
                                                                                      "relative": 0.01}]})
    assert [t.name for t in DesignSpace(cfg).tolerances] == ["design.m3", "design.La"]
