"""reduced_batch (aero_env.models.reduced.batch): the arrays path, and a fallback to configs seen, not silent."""

import warnings

import numpy as np
import pytest
from gymnasium.utils import seeding

from aero_env.config import Config, ConfigError
from aero_env.design_space import DesignSpace
from aero_env.models.reduced import batch as reduced_batch_module
from aero_env.models.reduced import simulate_batch
from aero_env.models.reduced.batch import FALLBACKS, ReducedFallbackWarning, reduced_batch
from aero_env.reward import batch_reward

BASE = Config().replace({"scene.frames": 2, "sim.fidelity": "reduced"})


def _episodes(n: int, seed: int = 3) -> list[dict]:
    space = DesignSpace(BASE)
    rng = np.random.default_rng(seed)
    return [space.episode_values(space.values(rng.uniform(-1, 1, space.dim)),
                                 space.draw(seeding.np_random(seed + i)[0]))[0] for i in range(n)]


@pytest.fixture
def fresh_count(monkeypatch):
    monkeypatch.setattr(FALLBACKS, "count", 0)
    monkeypatch.setattr(FALLBACKS, "warned", False)
    return FALLBACKS


def test_random_episodes_go_in_as_arrays_with_no_fallback(fresh_count):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ReducedFallbackWarning)
        batch, rewards = reduced_batch(BASE, _episodes(6))
    assert fresh_count.count == 0 and not fresh_count.warned
    assert len(rewards) == 6 and batch.traversals.shape == (6,)


def test_a_refusal_the_configs_accept_is_a_fallback_warned_once_and_counted(fresh_count, monkeypatch):
    def refuse(*_args, **_kwargs):
        raise ConfigError("design.m2[0] = 0.0077: refused by a broken check")

    monkeypatch.setattr(reduced_batch_module, "simulate_designs", refuse)
    episodes = _episodes(3)
    with pytest.warns(ReducedFallbackWarning, match="refused by a broken check") as seen:
        batch, rewards = reduced_batch(BASE, episodes)
        reduced_batch(BASE, episodes)
    assert len(seen) == 1 and fresh_count.count == 2  # warned once per process, every fallback counted
    cfgs = [BASE.with_values(e) for e in episodes]  # the same runs as the configs give
    alone = simulate_batch(cfgs)
    assert batch.sim_time.tolist() == alone.sim_time.tolist()
    assert rewards.tolist() == batch_reward(alone, cfgs).tolist()


def test_a_bug_on_the_arrays_path_is_raised_not_taken_for_a_refusal(fresh_count, monkeypatch):
    def bug(*_args, **_kwargs):
        raise TypeError("a bug")

    monkeypatch.setattr(reduced_batch_module, "simulate_designs", bug)
    with pytest.raises(TypeError, match="a bug"):
        reduced_batch(BASE, _episodes(2))
    assert fresh_count.count == 0


def test_a_bad_value_is_refused_in_with_values_words_and_is_no_fallback(fresh_count):
    with pytest.raises(ConfigError, match=r"^design\.m2 = 0\.5: out of range.* kg"):
        reduced_batch(BASE, [{"design.m2": 0.008}, {"design.m2": 0.5}])
    assert fresh_count.count == 0
