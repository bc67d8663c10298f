"""Property tests (hypothesis): random in-box designs keep the run's invariants; random malformed
configs and actions get a clear ConfigError naming the field, never a traceback from inside
pymunk or numpy."""

import math

import gymnasium as gym
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import aero_env  # noqa: F401
from aero_env.config import ConfigError, load_config, schema_rows

from .conftest import PAPER
from .test_hard_cases import assert_sane

ENV = gym.make("aero_env/AerialAcrobat-v0", **{"scene.frames": 2})
IN_BOX = st.lists(st.floats(-1.0, 1.0, width=32), min_size=5, max_size=5)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(action=IN_BOX, seed=st.integers(0, 2**31 - 1))
def test_random_in_box_designs_keep_the_invariants(action, seed):
    obs, _ = ENV.reset(seed=seed)
    obs, reward, terminated, truncated, info = ENV.step(np.array(action, np.float32))
    assert np.all(np.isfinite(obs)) and math.isfinite(reward) and terminated and not truncated
    env = ENV.unwrapped
    cfg, _ = env.space.episode_config(info["design"], env._draw)
    assert_sane(env._result, cfg)
    assert reward == (0.0 if info["outcome"] == "unstable" else info["traversals"])


# Every scalar key of the schema, and values that are wrong in every way a file or a tuner can be wrong.
SCALAR_KEYS = [row[0] for row in schema_rows() if "[]" not in row[0]]
BAD_VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**12, 10**12), st.booleans(), st.none(),
    st.text(max_size=8), st.lists(st.integers(), max_size=2), st.dictionaries(st.text(max_size=3), st.integers(),
                                                                              max_size=2))


@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(overrides=st.dictionaries(st.sampled_from(SCALAR_KEYS), BAD_VALUES, min_size=1, max_size=3))
def test_random_config_values_load_or_get_a_config_error_naming_the_key(overrides):
    try:
        cfg = load_config(PAPER, overrides)
    except ConfigError as exc:
        assert any(key.split(".")[-1] in str(exc) for key in overrides) or "design." in str(exc), str(exc)
        return
    for key in overrides:  # accepted: then it is a valid, finite value of the declared type
        value = cfg.value(key) if key.count(".") == 1 else None
        if isinstance(value, float):
            assert math.isfinite(value)


LIST_ENTRY = st.dictionaries(
    st.sampled_from(["name", "low", "high", "scale", "linked", "relative", "absolute", "bogus"]),
    st.one_of(st.sampled_from(["design.m3", "design.h", "scene.rise", "scene.frames", "design.mu_k", "nope",
                               "log", "linear"]), BAD_VALUES), max_size=5)


@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(section=st.sampled_from(["tunable", "context", "tolerance"]),
       entries=st.one_of(st.lists(LIST_ENTRY, max_size=3), BAD_VALUES))
def test_random_design_problem_sections_load_or_get_a_config_error(section, entries):
    try:
        cfg = load_config(PAPER, {section: entries})
        env = gym.make("aero_env/AerialAcrobat-v0", config=cfg)
    except ConfigError as exc:
        assert section in str(exc) or "corner" in str(exc) or "design." in str(exc), str(exc)
        return
    assert env.action_space.shape[0] >= 1 and env.observation_space.shape[0] >= 1


BAD_ACTIONS = st.one_of(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=7),
    st.lists(st.one_of(st.text(max_size=3), st.none(), st.booleans()), min_size=1, max_size=5),
    st.floats(allow_nan=True), st.text(max_size=5), st.none(),
    st.lists(st.lists(st.floats(-1, 1), min_size=5, max_size=5), min_size=1, max_size=2),
)


@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(action=BAD_ACTIONS)
def test_random_actions_step_or_get_a_config_error(action):
    env = ENV.unwrapped
    try:
        design = env.design_for(action)
    except ConfigError as exc:
        assert "action" in str(exc), str(exc)
        return
    # accepted: five finite numbers in the box, mapped inside every declared range
    assert np.all(np.abs(np.asarray(action, dtype=float)) <= 1.0)
    for t in env.config.tunable:
        assert t.low <= design[t.name] <= t.high
