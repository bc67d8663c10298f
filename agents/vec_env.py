"""stable-baselines3 on a Gymnasium vector env: SB3's own ``VecEnv`` API over a ``gymnasium.vector.VectorEnv``.

SB3 (2.x) steps its own vector envs (``DummyVecEnv``, ``SubprocVecEnv``), which reset a finished
sub-env within the step, return a list of per-env info dicts and put the finished episode's last
observation in ``info["terminal_observation"]``. A Gymnasium vector env with SAME_STEP autoreset
(:class:`aero_env.envs.AerialAcrobatVectorEnv`) does the same reset in its step and returns one
dict of arrays with the finished episodes in ``final_obs`` and ``final_info``; :class:`GymnasiumVecEnv`
translates one into the other, so that ``PPO("MlpPolicy", GymnasiumVecEnv(envs))`` trains on N
designs per step::

    envs = gym.make_vec("aero_env/AerialAcrobat-v0", num_envs=64, vectorization_mode="vector_entry_point",
                        **{"sim.fidelity": "reduced"})
    model = PPO("MlpPolicy", VecMonitor(GymnasiumVecEnv(envs)), seed=0).learn(4096)

What each step's ``infos[i]`` holds, as ``DummyVecEnv`` gives it: the finished episode's info (sub-env
``i`` of ``final_info``), ``terminal_observation`` and ``TimeLimit.truncated``; the next episode's reset
info is in ``reset_infos[i]``. Values are Python scalars or numpy arrays, as the single env returns them.
"""

from __future__ import annotations

from typing import Any, Sequence

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices, VecEnvObs, VecEnvStepReturn

from aero_env.config import ConfigError

__all__ = ["GymnasiumVecEnv", "unbatch_info"]


def unbatch_info(info: dict, i: int) -> dict:
    """Sub-env ``i``'s entries of a Gymnasium vector info (a dict of arrays with ``_key`` masks), as the dict its
    own env returned: keys whose mask is False for ``i`` are left out, numpy scalars become Python ones."""
    out = {}
    for key, value in info.items():
        if key.startswith("_") and key[1:] in info:
            continue  # a mask
        mask = info.get(f"_{key}")
        if mask is not None and not mask[i]:
            continue
        if isinstance(value, dict):
            out[key] = unbatch_info(value, i)
        else:
            item = value[i]
            out[key] = item.item() if isinstance(item, np.generic) else item
    return out


class GymnasiumVecEnv(VecEnv):
    """SB3's ``VecEnv`` over a Gymnasium ``VectorEnv`` whose ``metadata["autoreset_mode"]`` is SAME_STEP.

    Attributes (``get_attr``, ``set_attr``, ``env_method``) are the vector env's own, one value for every
    index: its sub-envs are not separate objects. Rendering is not supported."""

    def __init__(self, envs: gym.vector.VectorEnv):
        mode = envs.metadata.get("autoreset_mode")
        if mode != AutoresetMode.SAME_STEP:
            raise ConfigError(f"autoreset_mode = {mode!r}: GymnasiumVecEnv needs AutoresetMode.SAME_STEP (SB3 resets a "
                              f"finished env within its step), e.g. vectorization_mode='vector_entry_point' with its "
                              f"default autoreset_mode, or vector_kwargs={{'autoreset_mode': AutoresetMode.SAME_STEP}}")
        self.envs = envs  # before VecEnv.__init__, which reads render_mode through get_attr
        super().__init__(envs.num_envs, envs.single_observation_space, envs.single_action_space)
        self._actions: np.ndarray | None = None

    def reset(self) -> VecEnvObs:
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        obs, info = self.envs.reset(seed=seeds)
        self.reset_infos = [unbatch_info(info, i) for i in range(self.num_envs)]
        self._reset_seeds()  # seeds are used once, as in DummyVecEnv
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> VecEnvStepReturn:
        obs, rewards, terminated, truncated, info = self.envs.step(self._actions)
        dones = np.logical_or(terminated, truncated)
        final_info, final_obs = info.get("final_info", {}), info.get("final_obs")
        step_info = {k: v for k, v in info.items() if k not in ("final_info", "_final_info", "final_obs", "_final_obs")}
        infos: list[dict[str, Any]] = []
        for i in range(self.num_envs):
            sub = unbatch_info(final_info if dones[i] else step_info, i)
            sub["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            if dones[i]:  # as DummyVecEnv: the last observation in the info, the reset's info in reset_infos
                sub["terminal_observation"] = final_obs[i]
                self.reset_infos[i] = unbatch_info(step_info, i)
            infos.append(sub)
        return obs, np.asarray(rewards, dtype=np.float32), dones, infos

    def close(self) -> None:
        self.envs.close()

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        value = getattr(self.envs, attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        setattr(self.envs, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list[Any]:
        result = getattr(self.envs, method_name)(*method_args, **method_kwargs)
        return [result for _ in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        return [False for _ in self._get_indices(indices)]

    def get_images(self) -> Sequence[np.ndarray | None]:
        raise ConfigError("GymnasiumVecEnv does not render; render the single env (gym.make(..., render_mode=...))")
