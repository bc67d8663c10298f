"""A step after the episode ended (issue 36 §7): ``env.step()`` after ``terminated=True`` without ``reset()``
warns once, as Gymnasium's own envs do, instead of silently running a new episode; resetting envs (Gymnasium's
vector envs, the native one, SB3's) never see the warning."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest

import aero_env  # noqa: F401  (registers the environments)

ENV_ID = "aero_env/AerialAcrobat-v0"
CHEAP = {"scene.frames": 2}
AFTER_END = "step() after the episode ended (terminated=True): call reset() first"


def after_end_warnings(caught) -> list[str]:
    return [str(w.message) for w in caught if AFTER_END in str(w.message)]


def test_a_step_after_the_end_warns_once_until_the_next_reset():
    env = gym.make(ENV_ID, **CHEAP)
    action = env.unwrapped.action_for()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # every warn() call recorded: "once" is the env's, not Python's registry
        env.reset(seed=0)
        first = env.step(action)
        assert first[2] is True and after_end_warnings(caught) == []
        again = env.step(action)  # no reset: warned, and still a valid, scored step
        assert len(after_end_warnings(caught)) == 1
        assert again[2] is True and again[1] == first[1] and again[4]["outcome"] == first[4]["outcome"]
        env.step(action)
        assert len(after_end_warnings(caught)) == 1  # once until the next reset
        env.reset(seed=1)
        env.step(action)
        assert len(after_end_warnings(caught)) == 1  # reset, step: the usual loop is silent
        env.step(action)
        assert len(after_end_warnings(caught)) == 2  # warned again after this episode's end
    (message,) = set(after_end_warnings(caught))
    assert "call reset() first" in message and "last reset's scene" in message


@pytest.mark.parametrize("mode", [gym.vector.AutoresetMode.NEXT_STEP, gym.vector.AutoresetMode.SAME_STEP])
def test_gymnasium_vector_envs_reset_and_never_warn(mode):
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="sync", vector_kwargs={"autoreset_mode": mode},
                        **CHEAP)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        envs.reset(seed=0)
        for _ in range(3):
            envs.step(np.zeros((2, 5), np.float32))
    envs.close()
    assert after_end_warnings(caught) == []


def test_the_native_vector_env_and_sb3_reset_and_never_warn():
    from stable_baselines3.common.vec_env import DummyVecEnv

    native = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", **CHEAP)
    sb3 = DummyVecEnv([lambda: gym.make(ENV_ID, **CHEAP)])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        native.reset(seed=0)
        sb3.reset()
        for _ in range(3):
            native.step(np.zeros((2, 5), np.float32))
            _, _, dones, _ = sb3.step(np.zeros((1, 5), np.float32))
            assert dones.all()
    native.close()
    sb3.close()
    assert after_end_warnings(caught) == []
