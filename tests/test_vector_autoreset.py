"""The native vector env's ``autoreset_mode`` (issue 35 §5): NEXT_STEP and DISABLED step as Gymnasium's
``SyncVectorEnv`` over the single env steps in that mode, the reduced array path carries every mode, Gymnasium's
vector observation wrappers take the env only with such a mode, and a bad mode is refused in one line."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode
from gymnasium.wrappers import vector as vector_wrappers

import aero_env  # noqa: F401  (registers the environments)
from aero_env.config import ConfigError
from aero_env.envs import AerialAcrobatVectorEnv
from aero_env.envs import aerial_acrobat_vector as vector_module

from .test_vector_env import BATCH_ONLY_MISSING, _actions, _same

VARIED_ID = "aero_env/AerialAcrobatVaried-v0"  # draws context and tolerances: the seeds matter
CONTEXTS_ID = "aero_env/AerialAcrobatContexts-v0"
REDUCED = {"sim.fidelity": "reduced", "scene.frames": 3}
# design.Cd, which the reduced model does not read: the episodes go to the model as configs, one each
CONFIGS = {**REDUCED, "tolerance": [{"name": "design.Cd", "relative": 0.2}, {"name": "design.m3", "relative": 0.05}]}
N = 6
SEED = 7


def _native(env_id, mode, num_envs=N, **over):
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", autoreset_mode=mode,
                        **over)


def _sync(env_id, mode, num_envs=N, **over):
    """The oracle: ``gym.make(env_id, **over)`` num_envs times in Gymnasium's SyncVectorEnv, in the same mode."""
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="sync", vector_kwargs={"autoreset_mode": mode},
                        **over)


def _script(mode):
    """The calls of a rollout: ("reset", kwargs) or ("step", k), k indexing the actions. NEXT_STEP: scored and
    reset-only steps in turn, then a masked reset that leaves sub-envs 1, 3, 5 ended, so the next step both runs
    designs and resets; DISABLED: every step after a reset, whole or masked (every sub-env ended, so all True)."""
    mask = np.array([True, False] * (N // 2))
    if mode == AutoresetMode.NEXT_STEP:
        return [("reset", dict(seed=SEED)), ("step", 0), ("step", 1), ("step", 2), ("reset", dict(options={
            "reset_mask": mask})), ("step", 3), ("step", 4), ("step", 0)]
    return [("reset", dict(seed=SEED)), ("step", 0), ("reset", dict(options={"reset_mask": np.ones(N, bool)})),
            ("step", 1), ("reset", dict()), ("step", 2), ("reset", dict(seed=[SEED + 10 + i for i in range(N)])),
            ("step", 3)]


def _rollout(envs, script, actions):
    out = []
    for call, arg in script:
        if call == "reset":
            kwargs = {k: ({"reset_mask": v["reset_mask"].copy()} if k == "options" else v) for k, v in arg.items()}
            out.append(("reset", envs.reset(**kwargs)))  # a copy: SyncVectorEnv pops the mask from the options
        else:
            out.append(("step", envs.step(actions[arg])))
    return out


def _without(info, keys):
    return {k: v for k, v in info.items() if k not in keys and k[1:] not in keys}


@pytest.mark.parametrize("scene", ["arrays", "configs"])
@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.DISABLED])
def test_the_mode_steps_as_sync_vector_env_over_the_single_env(mode, scene, monkeypatch):
    over = REDUCED if scene == "arrays" else CONFIGS
    fast, slow = _native(VARIED_ID, mode, **over), _sync(VARIED_ID, mode, **over)
    try:
        centre = slow.envs[0].unwrapped.action_for()
        actions = [_actions(5, N, seed, centre) for seed in range(5)]
        theirs = _rollout(slow, _script(mode), actions)
        if scene == "arrays":  # every step from the actions to the model's kernel in arrays, in this mode too
            for name in ("plan_episode", "batch_runs", "episode_info"):
                monkeypatch.setattr(vector_module, name,
                                    lambda *a, **k: (_ for _ in ()).throw(AssertionError("per design")))
        mine = _rollout(fast, _script(mode), actions)
    finally:
        fast.close(), slow.close()
    assert fast.metadata["autoreset_mode"] == mode and slow.metadata["autoreset_mode"] == mode
    for k, ((call, a), (_, b)) in enumerate(zip(mine, theirs)):
        if call == "reset":
            _same(a, b, f"call {k} reset")
            continue
        for name, x, y in zip(("obs", "reward", "terminated", "truncated"), a[:4], b[:4]):
            _same(x, y, f"call {k} {name}")
        assert "final_info" not in b[4] and "final_obs" not in b[4]  # the step info is the info itself
        _same(a[4], _without(b[4], BATCH_ONLY_MISSING), f"call {k} info")  # a reduced batch keeps no swings
    steps = [r for call, r in mine if call == "step"]
    rewards = np.concatenate([r[1] for r in steps])
    assert len(set(rewards[rewards > 0])) > 1, rewards  # scored designs with more than one outcome
    assert not any(r[3].any() for r in steps)  # nothing truncates an episode that ends by itself (no limit registered)
    if mode == AutoresetMode.NEXT_STEP:
        terminated = [r[2].tolist() for r in steps]
        assert terminated[1] == [False] * N and [True] * N in terminated  # a reset-only step and a scored one
        mixed = steps[3]  # after the masked reset: 0, 2, 4 run their designs, 1, 3, 5 are reset
        assert mixed[2].tolist() == [True, False] * (N // 2) and not mixed[1][1::2].any()
        assert mixed[4]["_traversals"].tolist() == [True, False] * (N // 2) and mixed[4]["_context"].all()


def test_disabled_refuses_a_step_of_an_ended_sub_env_until_it_is_reset():
    fast, slow = (_native(VARIED_ID, AutoresetMode.DISABLED, num_envs=3, **REDUCED),
                  _sync(VARIED_ID, AutoresetMode.DISABLED, num_envs=3, **REDUCED))
    actions = np.zeros((3, 5), np.float32)
    try:
        for envs in (fast, slow):
            envs.reset(seed=SEED)
            envs.step(actions)
        with pytest.raises(AssertionError):  # SyncVectorEnv: assert not self._autoreset_envs[i]
            slow.step(actions)
        with pytest.raises(ConfigError) as exc:
            fast.step(actions)
        assert "sub-envs [0, 1, 2] ended" in str(exc.value) and "reset_mask" in str(exc.value)
        fast.reset(options={"reset_mask": np.array([True, False, True])})
        with pytest.raises(ConfigError, match=r"sub-envs \[1\] ended"):  # the one not reset
            fast.step(actions)
        fast.reset(options={"reset_mask": np.array([False, True, False])})
        assert fast.step(actions)[2].all()
    finally:
        fast.close(), slow.close()


@pytest.mark.parametrize("limit, truncated", [(1, True), (2, False), (-1, False), (None, False)])
def test_max_episode_steps_truncates_as_time_limit_does_on_the_single_envs(limit, truncated):
    # every episode is one step, so TimeLimit(limit) truncates it only where limit is 1; -1: no TimeLimit
    flags = []
    for make in (_native, _sync):
        envs = make(VARIED_ID, AutoresetMode.NEXT_STEP, num_envs=2, max_episode_steps=limit, **REDUCED)
        envs.reset(seed=SEED)
        flags.append([envs.step(np.zeros((2, 5), np.float32))[3].tolist() for _ in range(2)])
        envs.close()
    assert flags[0] == flags[1] == [[truncated] * 2, [False] * 2]  # the second step only resets
    with pytest.raises(ConfigError, match=r"max_episode_steps = 0: must be a whole number >= 1"):
        AerialAcrobatVectorEnv(2, max_episode_steps=0)


# ---- Gymnasium's vector observation wrappers ----
def _normalize(envs):
    return vector_wrappers.NormalizeObservation(envs)


def _flatten(envs):
    return vector_wrappers.FlattenObservation(envs)


def _dtype(envs):
    with warnings.catch_warnings():  # Box's float32 -> float64 bounds check warns of an overflow that is not one
        warnings.simplefilter("ignore", RuntimeWarning)
        return vector_wrappers.DtypeObservation(envs, np.float64)


def _transform(envs):
    return vector_wrappers.TransformObservation(envs, lambda obs: 2.0 * obs + 1.0)


def _effect_seen(name, wrapped, obs, raw, calls):
    """What each wrapper does, seen on its last observations (``raw``: the same ``calls`` calls' unwrapped)."""
    if name == "NormalizeObservation":  # the statistics take 8 observations at each reset and step
        rms = wrapped.obs_rms
        assert rms.count == pytest.approx(1e-4 + 8 * calls) and np.abs(rms.mean).max() > 0.05
        assert np.allclose(obs, (raw - rms.mean) / np.sqrt(rms.var + wrapped.epsilon), atol=1e-5)
        assert not np.allclose(obs, raw)
    elif name == "FlattenObservation":
        flat = gym.spaces.flatten_space(wrapped.env.single_observation_space)
        assert wrapped.single_observation_space == flat and obs.shape == (8, flat.shape[0])
        assert np.array_equal(obs, np.stack([gym.spaces.flatten(wrapped.env.single_observation_space, r)
                                             for r in raw]))  # a flat Box flattens to its own values
    elif name == "DtypeObservation":
        assert obs.dtype == np.float64 and raw.dtype == np.float32 and np.array_equal(obs, raw.astype(np.float64))
    else:
        assert np.array_equal(obs, 2.0 * raw + 1.0) and not np.array_equal(obs, raw)


WRAPPERS = {"NormalizeObservation": _normalize, "FlattenObservation": _flatten, "DtypeObservation": _dtype,
            "TransformObservation": _transform}
# Gymnasium 1.4: every VectorObservationWrapper takes NEXT_STEP or DISABLED; NormalizeObservation NEXT_STEP only
TAKES = {AutoresetMode.NEXT_STEP: set(WRAPPERS), AutoresetMode.DISABLED: set(WRAPPERS) - {"NormalizeObservation"},
         AutoresetMode.SAME_STEP: set()}


@pytest.mark.parametrize("mode", list(AutoresetMode))
@pytest.mark.parametrize("name", list(WRAPPERS))
def test_make_vec_runs_under_gymnasiums_vector_observation_wrappers_with_the_option(name, mode):
    envs = _native(CONTEXTS_ID, mode, num_envs=8, **REDUCED)
    if name not in TAKES[mode]:  # SAME_STEP, the default: why the option is needed
        with pytest.raises(ValueError, match="autoreset_mode"):
            WRAPPERS[name](envs)
        envs.close()
        return
    wrapped, raw_envs = WRAPPERS[name](envs), _native(CONTEXTS_ID, mode, num_envs=8, **REDUCED)
    try:
        calls = [("reset", dict(seed=SEED))] + [("step", k) for k in range(4)]
        if mode == AutoresetMode.DISABLED:  # a reset before every step
            calls = [("reset", dict(seed=SEED))] + [c for k in range(4) for c in (("step", k), ("reset", {}))][:-1]
        actions = [np.random.default_rng(k).uniform(-0.5, 0.5, (8, 5)).astype(np.float32) for k in range(4)]
        for call, arg in calls:
            if call == "reset":
                obs, raw = wrapped.reset(**arg)[0], raw_envs.reset(**arg)[0]
            else:
                obs, raw = wrapped.step(actions[arg])[0], raw_envs.step(actions[arg])[0]
        _effect_seen(name, wrapped, obs, raw, len(calls))
    finally:
        wrapped.close(), raw_envs.close()


# ---- the argument ----
@pytest.mark.parametrize("value", ["next", "SameSteps", 1, None, gym.envs.registration.VectorizeMode.SYNC])
def test_a_bad_autoreset_mode_is_one_line_naming_the_argument_the_value_and_the_allowed_values(value):
    with pytest.raises(ConfigError) as exc:
        gym.make_vec(CONTEXTS_ID, num_envs=2, vectorization_mode="vector_entry_point", autoreset_mode=value)
    message = str(exc.value)
    assert message.startswith(f"autoreset_mode = {value!r}: must be one of") and "\n" not in message
    for mode in AutoresetMode:
        assert f"AutoresetMode.{mode.name} ({mode.value!r})" in message


def test_each_instance_carries_its_own_mode_given_as_the_member_its_value_or_its_name():
    modes = {}
    for given in (AutoresetMode.NEXT_STEP, "Disabled", "SAME_STEP"):
        envs = AerialAcrobatVectorEnv(2, overrides=REDUCED, autoreset_mode=given)
        modes[given] = envs.metadata["autoreset_mode"]
        envs.close()
    assert modes == {AutoresetMode.NEXT_STEP: AutoresetMode.NEXT_STEP, "Disabled": AutoresetMode.DISABLED,
                     "SAME_STEP": AutoresetMode.SAME_STEP}
    assert AerialAcrobatVectorEnv.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP  # the class's is untouched
    assert AerialAcrobatVectorEnv(2, overrides=REDUCED).metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
