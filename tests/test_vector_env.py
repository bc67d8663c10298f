"""The native vector env (``vectorization_mode="vector_entry_point"``): N designs per step equal N single
envs with the same seeds, its info is Gymnasium's dict of arrays, bad input names its field, and SB3 learns
on it through the adapter."""

import functools
import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import aero_env  # noqa: F401  (registers the environments)
from aero_env.config import ConfigError
from aero_env.envs import AerialAcrobatEnv, AerialAcrobatVectorEnv
from aero_env.envs.vector_info import stack_infos

from .conftest import COARSE, PAPER

ENV_ID = "aero_env/AerialAcrobat-v0"
VARIED_ID = "aero_env/AerialAcrobatVaried-v0"  # draws context and tolerances: the seeds matter
REDUCED = {"sim.fidelity": "reduced", "scene.frames": 3}
MBD_FAST = {**COARSE, "scene.frames": 2}  # one transfer: the cheapest pymunk run that scores
BATCH_ONLY_MISSING = {"swings", "energy", "health"}  # what a reduced batch keeps no record of (the class docstring)
SEED = 7


def _vector(env_id=VARIED_ID, num_envs=4, **kw):
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **kw)


def _single_envs(env_id, num_envs, **kw):
    """The oracle: the single env, num_envs times, in Gymnasium's SyncVectorEnv with the same autoreset mode."""
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="sync",
                        vector_kwargs={"autoreset_mode": AutoresetMode.SAME_STEP}, **kw)


def _actions(space_dim, num_envs, seed, centre):
    """Designs scattered about ``centre`` (the prototype's action): a mix of outcomes, not all failures."""
    rng = np.random.default_rng(seed)
    a = np.clip(centre + rng.normal(0.0, 0.3, (num_envs, space_dim)), -1.0, 1.0).astype(np.float32)
    a[0] = centre
    return a


def _same(a, b, path="info"):
    """``a`` equals ``b`` bit for bit: dicts key for key, arrays in shape, dtype and value (NaN equal to NaN)."""
    assert type(a) is type(b), f"{path}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, dict):
        assert list(a) == list(b), f"{path}: keys {list(a)} vs {list(b)}"
        for k in a:
            _same(a[k], b[k], f"{path}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]")
    elif isinstance(a, np.ndarray):
        assert a.shape == b.shape and a.dtype == b.dtype, f"{path}: {a.shape} {a.dtype} vs {b.shape} {b.dtype}"
        if a.dtype == object:
            for i, (x, y) in enumerate(zip(a, b)):
                _same(x, y, f"{path}[{i}]")
        else:
            assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), f"{path}: {a} vs {b}"
    elif isinstance(a, float) and math.isnan(a):
        assert math.isnan(b), path
    else:
        assert a == b, f"{path}: {a!r} vs {b!r}"


def _rollout(envs, actions, steps=2):
    """reset(seed=SEED), then ``steps`` steps: the second one runs the episodes the first one's autoreset drew."""
    out = [envs.reset(seed=SEED)]
    for k in range(steps):
        out.append(envs.step(actions[::-1] if k else actions))
    return out


def _rollouts_of_both(num_envs, seed, workers=None, **over):
    """The vector env and the single envs (on the varied scene, ``over`` set), each rolled out on the same
    actions about the prototype's design."""
    kw = {} if workers is None else {"workers": workers}
    fast, slow = _vector(**over, num_envs=num_envs, **kw), _single_envs(VARIED_ID, num_envs, **over)
    try:
        actions = _actions(5, num_envs, seed, slow.envs[0].unwrapped.action_for())
        return _rollout(fast, actions), _rollout(slow, actions)
    finally:
        fast.close(), slow.close()


def _check_equal_to_single_envs(fast, slow, missing=frozenset()):
    """Every step's observations, rewards, terminations and info of ``fast`` equal the single envs' (``slow``); the
    finished episodes' infos hold every key of the single env's but ``missing``."""
    (obs, info), (slow_obs, slow_info) = fast[0], slow[0]
    _same(obs, slow_obs, "reset obs")
    _same(info, slow_info, "reset info")
    for k, (mine, theirs) in enumerate(zip(fast[1:], slow[1:])):
        for name, x, y in zip(("obs", "reward", "terminated", "truncated"), mine[:4], theirs[:4]):
            _same(x, y, f"step {k} {name}")
        info, slow_info = mine[4], theirs[4]
        assert set(slow_info["final_info"]) - set(info["final_info"]) == {m for m in missing} | {f"_{m}" for m in missing}
        kept = {key: v for key, v in slow_info["final_info"].items() if key in info["final_info"]}
        _same(info["final_info"], kept, f"step {k} final_info")
        _same({key: v for key, v in info.items() if key != "final_info"},
              {key: v for key, v in slow_info.items() if key != "final_info"}, f"step {k} info")


def test_at_reduced_one_batch_equals_single_envs_with_the_same_seeds():
    a, b = _rollouts_of_both(6, 1, **REDUCED)
    _check_equal_to_single_envs(a, b, BATCH_ONLY_MISSING)
    rewards = np.concatenate([a[1][1], a[2][1]])
    outcomes = set(a[1][4]["final_info"]["outcome"]) | set(a[2][4]["final_info"]["outcome"])
    assert len(set(rewards)) > 1 and len(outcomes) > 1, (rewards, outcomes)  # a sample the comparison can fail on
    assert not np.array_equal(a[1][0], a[2][0])  # the autoreset drew new contexts


def test_at_reduced_a_scene_that_draws_nothing_equals_single_envs_with_no_python_per_design(monkeypatch):
    # the prototype's scene draws no context and no tolerance: a step goes from the actions to the model's kernel
    # in arrays (no per-design plan, draw or run dict), and still equals the single envs bit for bit
    from aero_env.design_space import DesignSpace
    from aero_env.envs import aerial_acrobat_vector as vector_module

    fast, slow = _vector(ENV_ID, num_envs=6, **REDUCED), _single_envs(ENV_ID, 6, **REDUCED)
    try:
        actions = _actions(5, 6, 3, slow.envs[0].unwrapped.action_for())
        theirs = _rollout(slow, actions)
        fast.reset(seed=SEED)
        for what, name in ((vector_module, "plan_episode"), (DesignSpace, "values"), (DesignSpace, "draw"),
                           (vector_module, "batch_runs"), (vector_module, "episode_info")):
            monkeypatch.setattr(what, name, lambda *a, **k: (_ for _ in ()).throw(AssertionError("per design")))
        mine = _rollout(fast, actions)
    finally:
        fast.close(), slow.close()
    _check_equal_to_single_envs(mine, theirs, BATCH_ONLY_MISSING)
    outcomes = set(mine[1][4]["final_info"]["outcome"])
    assert len(outcomes) > 1, outcomes  # a sample the comparison can fail on


@pytest.mark.parametrize("case", ["tunable", "context"])
def test_a_signed_zero_reaches_the_model_as_the_single_env_gives_it(case):
    # the reduced model tells design.h = -0.0 from 0.0 (a few designs in a hundred change outcome), so the arrays must
    # clamp a tunable and fix a context as the single env's Python does: max(0.0, -0.0) is 0.0 where
    # np.maximum(0.0, -0.0) is -0.0, and a drawn fixed range low + u*0 turns -0.0 into 0.0
    from aero_env.config import from_dict, read_yaml

    d = read_yaml(str(PAPER), "cfg")
    if case == "tunable":  # the box's lowest h is -0.0, and every design takes it
        next(t for t in d["tunable"] if t["name"] == "design.h")["low"] = -0.0
    else:  # h fixed at -0.0 by a context that draws nothing
        d["context"] = [{"name": "design.h", "low": -0.0, "high": -0.0}, {"name": "scene.rise"}]
        d["tunable"] = [t for t in d["tunable"] if t["name"] != "design.h"]
    cfg = from_dict(d, REDUCED)
    fast, slow = _vector(ENV_ID, num_envs=64, config=cfg), _single_envs(ENV_ID, 64, config=cfg)
    try:
        centre = slow.envs[0].unwrapped.action_for()
        actions = _actions(len(centre), 64, 5, centre)
        if case == "tunable":
            actions[:, 1] = -1.0
        mine, theirs = _rollout(fast, actions), _rollout(slow, actions)
    finally:
        fast.close(), slow.close()
    _check_equal_to_single_envs(mine, theirs, BATCH_ONLY_MISSING)
    section = "design" if case == "tunable" else "context"
    for k in (1, 2):
        h, their_h = (r[k][4]["final_info"][section]["design.h"] for r in (mine, theirs))
        assert np.array_equal(np.signbit(h), np.signbit(their_h)) and not np.signbit(h).any()


@pytest.mark.parametrize("seeds", [[-1, 0], [np.int64(3), 4], [1.5, 2]])
def test_a_bad_seed_is_refused_as_gymnasium_refuses_it_where_nothing_is_drawn(seeds):
    # the prototype's scene draws nothing, so the vector env makes no generator per sub-env; a bad seed is still
    # refused before any sub-env is reset, in Gymnasium's words, as the single envs refuse it
    fast, slow = _vector(ENV_ID, num_envs=2, **REDUCED), _single_envs(ENV_ID, 2, **REDUCED)
    try:
        with pytest.raises(gym.error.Error) as mine:
            fast.reset(seed=seeds)
        with pytest.raises(gym.error.Error) as theirs:
            slow.reset(seed=seeds)
    finally:
        fast.close(), slow.close()
    assert str(mine.value) == str(theirs.value)


def test_at_reduced_a_field_the_model_does_not_read_takes_the_config_path_and_still_equals_single_envs():
    # design.Cd (drag) is not read by the reduced model, so its episodes cannot go in as arrays: they are built
    # as configs (reduced_batch's other path), and every step must still be the single envs'
    over = {**REDUCED, "tolerance": [{"name": "design.Cd", "relative": 0.2}, {"name": "design.m3", "relative": 0.05}]}
    a, b = _rollouts_of_both(5, 2, **over)
    _check_equal_to_single_envs(a, b, BATCH_ONLY_MISSING)
    built = a[1][4]["final_info"]["as_built"]
    assert len(set(built["design.Cd"])) == 5 and len(set(built["design.m3"])) == 5  # the tolerances were drawn


def test_at_reduced_the_episodes_go_to_the_model_without_a_config_each(monkeypatch):
    from aero_env.config import Config

    envs = _vector(**REDUCED, num_envs=3)
    try:
        envs.reset(seed=SEED)
        monkeypatch.setattr(Config, "with_values", lambda *a, **k: (_ for _ in ()).throw(AssertionError("built")))
        _, rewards, *_ = envs.step(_actions(5, 3, 1, np.zeros(5, dtype=np.float32)))
    finally:
        envs.close()
    assert rewards.shape == (3,)


# the varied scene's context with the pitch drawn too (the file observes it at 76 mm), and the shaped reward,
# whose near-miss credit w·(1 - miss / pitch) is the one place the reward reads the pitch
PITCH_DRAWN = {**REDUCED, "env.reward_shaping": 0.9,
               "context": [{"name": "scene.rise", "low": 0.0, "high": 0.004},
                           {"name": "scene.pitch", "low": 0.070, "high": 0.082},
                           {"name": "design.m2", "low": 0.0065, "high": 0.009}]}


@pytest.mark.parametrize("path", ["arrays", "configs", "pymunk"])
def test_each_episode_runs_and_is_scored_at_its_own_drawn_pitch(path):
    from aero_env.simulation import simulate

    over, missing, kw = PITCH_DRAWN, BATCH_ONLY_MISSING, {}
    if path == "configs":  # design.Cd, which the model does not read, sends the episodes down reduced_batch's configs
        over = {**PITCH_DRAWN, "tolerance": [{"name": "design.Cd", "relative": 0.2}]}
    elif path == "pymunk":  # one design per process-pool task (here in this process), scored by the single env's reward
        over, missing, kw = {**PITCH_DRAWN, **MBD_FAST}, frozenset(), {"workers": 1}
    a, b = _rollouts_of_both(8, 3, **kw, **over)
    _check_equal_to_single_envs(a, b, missing)  # the single env builds each episode's config
    single = gym.make(VARIED_ID, **over)
    w, base = over["env.reward_shaping"], single.unwrapped.config
    single.close()
    credited = at_base_pitch_differs = 0
    for _, rewards, _, _, info in a[1:]:
        fi = info["final_info"]
        pitch, miss = fi["context"]["scene.pitch"], fi["miss_distance"]
        assert len(set(pitch)) == len(pitch) and base.scene.pitch not in pitch  # drawn per episode, off the base's
        for i, r in enumerate(rewards):
            credit = r - fi["traversals"][i]
            if credit > 0.0:  # a near miss' credit, by hand with the episode's own pitch
                assert credit == pytest.approx(w * (1.0 - miss[i] / pitch[i]), rel=1e-12), i
                credited += 1
            # the same episode at the base config's pitch (everything else as the episode set it)
            values = {k: float(v[i]) for part in ("context", "design", "as_built") for k, v in fi[part].items()
                      if not k.startswith("_")}  # the as-built values last, as the episode sets them
            there = simulate(base.with_values({**values, "scene.pitch": base.scene.pitch}))
            at_base_pitch_differs += (there.outcome, there.traversals) != (fi["outcome"][i], fi["traversals"][i])
    # a sample the checks can fail on: credits a base-pitch reward would get wrong, runs a base-pitch model would
    assert credited >= 2 and at_base_pitch_differs >= 2, (credited, at_base_pitch_differs)


def test_reduced_batch_takes_the_config_path_for_mixed_or_no_fields_and_words_errors_as_with_values():
    from aero_env.config import Config
    from aero_env.models.reduced.batch import reduced_batch
    from aero_env.models.reduced import simulate_batch, simulate_designs

    base = Config().replace({"scene.frames": 2})
    mixed = [{"design.m2": 0.008}, {"design.m3": 0.009}]
    with pytest.raises(ConfigError, match=r"designs\[1\] sets \['design.m3'\], designs\[0\] sets \['design.m2'\]"):
        simulate_designs(base, mixed)
    batch, rewards = reduced_batch(base, mixed)  # each its own config, as the single env builds it
    alone = simulate_batch([base.with_values(e) for e in mixed])
    assert batch.traversals.tolist() == alone.traversals.tolist() and batch.sim_time.tolist() == alone.sim_time.tolist()
    assert len(reduced_batch(base, [{}, {}, {}])[1]) == 3  # no field set: the base design three times
    assert len(simulate_designs(base, [{}, {}, {}])) == 3
    with pytest.raises(ConfigError, match="no episodes"):
        reduced_batch(base, [])
    with pytest.raises(ConfigError) as exc:  # a bad value: the single env's words (key, value, range with unit)
        reduced_batch(base, [{"design.m2": 0.008}, {"design.m2": 0.5}])
    assert str(exc.value).startswith("design.m2 = 0.5: out of range") and "kg" in str(exc.value)


def test_at_a_pymunk_fidelity_the_vector_env_equals_single_envs_with_the_same_seeds():
    a, b = _rollouts_of_both(3, 2, workers=1, **MBD_FAST)
    _check_equal_to_single_envs(a, b)  # every key, swings, energy and health included
    assert len(set(np.concatenate([a[1][1], a[2][1]]))) > 1


def test_the_process_pool_gives_what_one_process_gives():
    one, pool = _vector(**MBD_FAST, num_envs=3, workers=1), _vector(**MBD_FAST, num_envs=3, workers=2)
    try:
        assert one.unwrapped._pool is None and pool.unwrapped._pool is not None
        actions = _actions(5, 3, 4, AerialAcrobatEnv(overrides=MBD_FAST).action_for())
        a, b = _rollout(one, actions), _rollout(pool, actions)
    finally:
        one.close(), pool.close()
    assert pool.unwrapped._pool is None  # close() stopped the workers
    for k, (x, y) in enumerate(zip(a, b)):
        _same(x, y, f"call {k}")
    assert len(set(a[1][4]["final_info"]["outcome"])) == 3  # three outcomes: their order is the sub-envs' order


def test_info_is_a_dict_of_arrays_with_masks_and_the_mode_is_same_step():
    envs = _vector(**REDUCED, num_envs=3)
    obs, reset_info = envs.reset(seed=0)
    *_, terminated, truncated, info = envs.step(np.zeros((3, 5), np.float32))
    envs.close()
    assert envs.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    assert terminated.all() and not truncated.any()  # every episode ended by itself; the spec sets no time limit

    def leaves(d, path=""):
        for k, v in d.items():
            if not k.startswith("_"):
                assert np.array_equal(d[f"_{k}"], [True] * 3), path + k  # every sub-env has every key
            yield from leaves(v, f"{path}{k}.") if isinstance(v, dict) else [(path + k, v)]

    for name, value in [*leaves(info), *leaves(reset_info)]:
        assert isinstance(value, np.ndarray) and value.shape[0] == 3, name
    assert info["final_info"]["traversals"].dtype == np.int64 and info["final_info"]["outcome"].dtype == object
    assert set(info) == {"final_obs", "_final_obs", "final_info", "_final_info", "context", "_context"}


def test_stack_infos_builds_what_gymnasiums_add_info_builds():
    env = AerialAcrobatEnv(overrides=REDUCED)
    infos = []
    for action in (env.action_for(), -np.ones(5, np.float32)):  # completed first: its miss_distance is None
        env.reset(seed=0)
        infos.append(env.step(action)[4])
    assert infos[0]["miss_distance"] is None and infos[1]["miss_distance"] is not None
    two = AerialAcrobatVectorEnv(2, overrides=REDUCED)
    for order in (infos, infos[::-1]):  # an object array, then a float array with NaN
        folded = {}
        for i, sub in enumerate(order):
            folded = two._add_info(folded, sub, i)
        _same(stack_infos(order), folded)


def test_seeds_give_each_sub_env_seed_plus_its_index():
    envs = _vector(num_envs=3)
    a, _ = envs.reset(seed=SEED)
    b, _ = envs.reset(seed=SEED)
    listed, _ = envs.reset(seed=[SEED + 2, SEED + 1, SEED])
    going_on, _ = envs.reset()
    envs.close()
    single = gym.make(VARIED_ID)
    expected = np.stack([single.reset(seed=SEED + i)[0] for i in range(3)])
    assert np.array_equal(a, expected) and np.array_equal(b, a)
    assert np.array_equal(listed, a[::-1])
    assert not np.array_equal(going_on, listed)  # unseeded: each RNG goes on
    assert len({tuple(row) for row in a}) == 3
    with pytest.raises(ConfigError, match="seed: a list of 3 seeds for num_envs = 2"):
        _vector(num_envs=2).reset(seed=[1, 2, 3])


@pytest.mark.parametrize("make, needle", [
    (lambda: _vector(num_envs=0), "num_envs = 0"),
    (lambda: _vector(num_envs=2.5), "num_envs = 2.5"),
    (lambda: _vector(num_envs=2, workers=0), "workers = 0"),
    (lambda: _vector(num_envs=2, render_mode="rgb_array"), "render_mode = 'rgb_array'"),
    (lambda: _vector(num_envs=2, **{"env.record_trace": True}), "env.record_trace"),
])
def test_bad_construction_is_one_line_naming_the_field(make, needle):
    with pytest.raises(ConfigError) as exc:
        make()
    assert needle in str(exc.value) and "\n" not in str(exc.value)


@pytest.mark.parametrize("actions, needle", [
    (np.zeros((2, 6), np.float32), "actions has shape (2, 6): expected (num_envs, d) = (2, 5)"),
    (np.zeros(5, np.float32), "actions has shape (5,)"),
    (np.array([[0, 0, 0, 0, 0], [0, 0, 1.5, 0, 0]], np.float32), "actions[1]: action[2] (design.La) = 1.5"),
    (np.array([[0, 0, 0, 0, 0], [0, np.nan, 0, 0, 0]], np.float32), "actions[1]: action[1] (design.h)"),
])
def test_a_bad_action_is_one_line_naming_the_row_and_field(actions, needle):
    envs = _vector(**REDUCED, num_envs=2)
    envs.reset(seed=0)
    with pytest.raises(ConfigError) as exc:
        envs.step(actions)
    envs.close()
    assert needle in str(exc.value) and "\n" not in str(exc.value)


def test_make_vec_picks_the_vector_entry_point_by_default():
    envs = gym.make_vec(ENV_ID, num_envs=2, **REDUCED)
    assert isinstance(envs.unwrapped, AerialAcrobatVectorEnv) and envs.num_envs == 2
    assert envs.spec.kwargs["vectorization_mode"] == "vector_entry_point"
    envs.close()


# ---- SB3 on the vector env ----
SB3_ENVS = 64     # designs per step
SB3_ROLLOUT = 4   # steps per PPO rollout: 256 designs per update
SB3_UPDATES = 15  # PPO updates: 3840 designs
SCORE_EPISODES = 256
SHAPED = {**REDUCED, "env.reward_shaping": 0.5}  # credit for near misses: a signal where most designs score 0


def _mean_reward(model, seed):
    """The stochastic policy's mean reward over SCORE_EPISODES fresh episodes (one vector step)."""
    envs = _vector(ENV_ID, num_envs=SCORE_EPISODES, **SHAPED)
    obs, _ = envs.reset(seed=seed)
    model.set_random_seed(seed)
    actions, _ = model.predict(obs, deterministic=False)
    rewards = envs.step(np.clip(actions, -1.0, 1.0))[1]
    envs.close()
    return float(rewards.mean())


def test_sb3_ppo_trains_on_the_vector_env_and_learns():
    pytest.importorskip("stable_baselines3")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    from agents.rl import ALGO_DEFAULTS, _sb3
    from agents.vec_env import GymnasiumVecEnv

    _sb3()  # torch on one thread, as agents.rl trains
    venv = VecMonitor(GymnasiumVecEnv(_vector(ENV_ID, num_envs=SB3_ENVS, **SHAPED)))
    venv.seed(0)
    hp = {**ALGO_DEFAULTS["ppo"], "n_steps": SB3_ROLLOUT, "learning_rate": 1e-3}
    model = PPO("MlpPolicy", venv, seed=0, device="cpu", **hp)
    before = _mean_reward(model, 123)
    model.learn(SB3_ENVS * SB3_ROLLOUT * SB3_UPDATES)
    venv.close()
    after = _mean_reward(model, 123)
    assert model.num_timesteps == SB3_ENVS * SB3_ROLLOUT * SB3_UPDATES
    assert len(model.ep_info_buffer) > 0  # VecMonitor saw the episodes end (dones and infos as SB3 expects)
    assert after > before + 0.2, (before, after)  # measured: 0.44 -> 0.84


def test_the_sb3_adapter_gives_dummy_vec_envs_steps():
    from stable_baselines3.common.vec_env import DummyVecEnv

    from agents.vec_env import GymnasiumVecEnv

    ours = GymnasiumVecEnv(_vector(num_envs=3, **REDUCED))
    theirs = DummyVecEnv([functools.partial(AerialAcrobatEnv, overrides=REDUCED, **_varied_kwargs())] * 3)
    actions = _actions(5, 3, 4, theirs.envs[0].unwrapped.action_for())
    for venv in (ours, theirs):
        venv.seed(SEED)
    results = [(venv.reset(), venv.step(actions), venv.reset_infos) for venv in (ours, theirs)]
    ours.close(), theirs.close()
    (obs0, (obs, rew, done, infos), reset_infos), (obs0_d, (obs_d, rew_d, done_d, infos_d), reset_infos_d) = results
    assert np.array_equal(obs0, obs0_d) and np.array_equal(obs, obs_d)
    assert np.array_equal(rew, rew_d) and rew.dtype == rew_d.dtype and done.all() and done_d.all()
    for mine, theirs_ in zip(infos, infos_d):
        assert np.array_equal(mine.pop("terminal_observation"), theirs_.pop("terminal_observation"))
        if theirs_["miss_distance"] is None:  # a dict of arrays keeps a float column: None comes back as NaN
            theirs_["miss_distance"] = mine["miss_distance"] if mine["miss_distance"] is None else math.nan
        _same(mine, {k: v for k, v in theirs_.items() if k not in BATCH_ONLY_MISSING})
    _same(reset_infos, reset_infos_d)


def _varied_kwargs():
    from aero_env.registration import ENVIRONMENTS

    return ENVIRONMENTS[VARIED_ID]
