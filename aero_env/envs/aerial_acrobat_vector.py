"""The design environment batched: N designs per step, in one call (the registered ``vector_entry_point``)."""

from __future__ import annotations

import multiprocessing
import re
import sys
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from multiprocessing import get_context
from pathlib import Path
from typing import Any, Mapping

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from ..config import Config, ConfigError, load_config, warn_unit_slips
from ..design_space import DesignSpace, Draw
from ..reward import reward
from ..simulation import simulate
from .aerial_acrobat import Episode, episode_info, plan_episode, reset_info
from .vector_info import batch_infos, batch_runs, stack_columns, stack_infos

__all__ = ["AerialAcrobatVectorEnv", "MAX_NUM_ENVS", "POOL_START_METHOD"]

MAX_NUM_ENVS = 1_000_000  # designs per step; past this one step's configs alone would fill the memory
# spawn, as AsyncVectorEnv and SB3's SubprocVecEnv are started here: a forked child would inherit the
# parent's threads (torch's, a numba kernel's) mid-state
POOL_START_METHOD = "spawn"
# spawn runs the calling script again in every worker before it takes any work: unguarded, the script's make_vec
# would start a pool inside each worker, and the workers die
GUARD = 'if __name__ == "__main__":'


class AerialAcrobatVectorEnv(gym.vector.VectorEnv):
    """
    ## Description

    ``num_envs`` copies of :class:`~aero_env.envs.AerialAcrobatEnv` stepped together: one ``step``
    runs one design per sub-env. At ``sim.fidelity: reduced`` the designs run in one call of the
    reduced model, and the step goes from the actions to the model's kernel in arrays, a field at a
    time over all sub-envs (:meth:`_run_columns`: no Config or dict per design); at a pymunk
    fidelity (mbd, mbd-fine, reference) the designs run one after another in this process, or, when
    ``workers`` > 1 is asked for, in a persistent pool of ``workers`` processes, one design each,
    gathered in sub-env order. Each run is a function of its config alone, so the pool changes
    only the time: rewards, observations and infos equal those of ``num_envs`` single envs with
    the same seeds, bit for bit (``tests/test_vector_env.py``).

    The pool starts its processes with ``spawn``, which runs the calling script again in each of
    them: a script that asks for ``workers`` must make the env under ``if __name__ == "__main__":``
    (a script without that line is refused with one line saying so; without ``workers`` no
    process is started and no guard is needed).

    ```python
    envs = gym.make_vec("aero_env/AerialAcrobat-v0", num_envs=256, vectorization_mode="vector_entry_point",
                        **{"sim.fidelity": "reduced"})
    ```

    ## Autoreset: SAME_STEP

    Every episode is one step (a contextual bandit), so every step ends every sub-env's episode
    (``terminated`` all True, ``truncated`` all False) and the same step resets it:
    ``metadata["autoreset_mode"]`` is ``AutoresetMode.SAME_STEP``, and every step scores the
    designs it is given (under NEXT_STEP every other step would be a reset that ignores its actions).

    | returned by ``step``   | what                                                                |
    |------------------------|---------------------------------------------------------------------|
    | observations           | the *next* episode's context, normalised, ``(num_envs, k)`` float32 |
    | rewards                | each design's reward, :func:`aero_env.reward.reward`, float64       |
    | terminated / truncated | all True / all False                                                |
    | ``info["final_obs"]``  | object array: the observation each finished episode was stepped on  |
    | ``info["final_info"]`` | the finished episodes' infos (below)                                |
    | ``info["context"]``    | the next episode's context, SI (the reset info)                     |

    ## Info

    A dict of arrays, one entry per sub-env, each key with its ``_key`` mask (all True: every
    sub-env finishes every step), built as ``SyncVectorEnv`` builds it from the single envs'
    infos (Gymnasium's dtypes included). ``final_info`` holds the single env's step info:

    | key                                                                     | reduced | pymunk |
    |-------------------------------------------------------------------------|---------|--------|
    | ``traversals``, ``frames``, ``outcome``, ``reason``, ``sim_time``,      | yes     | yes    |
    | ``miss_distance``, ``fidelity``, ``design``, ``context``, ``as_built``  |         |        |
    | ``swings``, ``energy``, ``health``                                      | no      | yes    |

    At ``reduced`` the batch keeps no per-swing record or energy bookkeeping (and the reduced
    model's health is zero by construction): for those, step the single env. Every key present
    equals the single env's value.

    ## Seeding

    ``reset(seed=s)`` seeds sub-env ``i`` with ``s + i``, a list seeds each sub-env with its own
    entry, None leaves each sub-env's RNG going on, as in ``SyncVectorEnv``. The reset inside a
    step is unseeded: each sub-env's RNG goes on. ``reset(options={"reset_mask": mask})`` redraws only
    the masked sub-envs.

    ## Arguments

    | Argument      | Default          | Meaning                                                          |
    |---------------|------------------|------------------------------------------------------------------|
    | ``num_envs``  | 1                | designs per step, in [1, ``MAX_NUM_ENVS``]                       |
    | ``config``    | None             | a YAML path or a :class:`Config`; None: the prototype            |
    | ``overrides`` | None             | dotted-key overrides (``{"scene.frames": 3}``)                   |
    | ``workers``   | 1                | pymunk fidelities: processes in the pool (``os.cpu_count()``: one per core; needs the ``__main__`` guard); 1: this process, no pool; unused at ``reduced`` |
    | ``**kwargs``  |                  | more dotted-key overrides, as ``gym.make``                       |

    Actions are ``(num_envs, d)`` in the single env's box; a bad row raises ``ConfigError`` naming
    the row, the dimension and its field. There is no rendering and no trace (``env.record_trace``
    is refused): step the single env to watch a design. ``close()`` stops the pool.
    """

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

    def __init__(self, num_envs: int = 1, config: str | Path | Config | None = None,
                 overrides: Mapping[str, Any] | None = None, render_mode: str | None = None,
                 workers: int | None = None, **kwargs: Any):
        self._pool = None  # first, so that close() works whatever below fails
        whole = isinstance(num_envs, (int, np.integer)) and not isinstance(num_envs, bool)
        if not whole or not 1 <= num_envs <= MAX_NUM_ENVS:
            raise ConfigError(f"num_envs = {num_envs!r}: must be a whole number in [1, {MAX_NUM_ENVS}] (designs per "
                              f"step)")
        if render_mode is not None:
            raise ConfigError(f"render_mode = {render_mode!r}: the vector env does not render; render the single env "
                              f"(gym.make(..., render_mode=...))")
        extra = {**(overrides or {}), **kwargs}
        if isinstance(config, Config):
            self.config = config.replace(extra) if extra else config
            warn_unit_slips(extra)  # as load_config does for a file's values and its overrides
        else:
            self.config = load_config(config, extra)
        if self.config.env.record_trace:
            raise ConfigError("env.record_trace = True: the vector env keeps no runs to trace; record with the single "
                              "env (gym.make)")
        self.space = DesignSpace(self.config)
        self.num_envs = int(num_envs)
        self.reduced = self.config.sim.model == "reduced"
        self.workers = self._check_workers(workers)
        self.single_action_space = spaces.Box(-1.0, 1.0, (self.space.dim,), np.float32)
        self.single_observation_space = spaces.Box(-1.0, 1.0, (self.space.obs_dim,), np.float32)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._rngs: list[np.random.Generator | None] = [None] * self.num_envs  # each sub-env's, as gym.Env's
        self._fixed = None if self.space.draws_anything else self.space.fixed_draw()
        self._draws: list[Draw] = [self.space.nominal_draw()] * self.num_envs
        self._observations = self._observe()
        if not self.reduced and self.workers > 1:
            _check_spawn_guard(self.workers)
            self._pool = ProcessPoolExecutor(min(self.workers, self.num_envs), mp_context=get_context(POOL_START_METHOD))

    def _check_workers(self, workers) -> int:
        if workers is None:
            return 1  # no pool unless asked for: a pool needs the script's __main__ guard
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
            raise ConfigError(f"workers = {workers!r}: must be a whole number >= 1 (processes in the pool; 1: none)")
        return int(workers)

    @property
    def _clip(self) -> bool:
        return self.config.env.action_out_of_box == "clip"

    # ---- Gymnasium API ----
    def reset(self, *, seed: int | list | None = None, options: dict | None = None):
        seeds = self._seeds(seed)
        if isinstance(seed, (int, np.integer)):
            super().reset(seed=int(seed))
        mask = self._reset_mask(options)
        for i in np.flatnonzero(mask):  # every seed checked before any sub-env is reset
            if seeds[i] is not None and not (isinstance(seeds[i], int) and seeds[i] >= 0):
                seeding.np_random(seeds[i])  # Gymnasium's own refusal of that seed, as the single env's reset gives
        for i in np.flatnonzero(mask):
            if seeds[i] is not None and self.space.draws_anything:  # nothing drawn: the RNG is never read
                self._rngs[i] = seeding.np_random(seeds[i])[0]
            self._draws[i] = self._draw(i)
        self._observations = self._observe()
        if mask.all():
            info = self._reset_infos()
        else:
            info = self._masked([reset_info(self._draws[i]) for i in np.flatnonzero(mask)], mask)
        return self._observations.copy(), info

    def step(self, actions):
        self._check_shape(actions)
        ran = self._run_columns(actions) if self.reduced else None
        if ran is None:
            rewards, final_info = self._run_episodes(self._plan(actions))
        else:
            rewards, final_info = ran
        final_obs = np.full(self.num_envs, None, dtype=object)
        for i, row in enumerate(self._observations):
            final_obs[i] = row.copy()
        # SAME_STEP: every episode ended with this step, so every sub-env resets now, unseeded (its RNG goes on)
        self._draws = [self._draw(i) for i in range(self.num_envs)]
        self._observations = self._observe()
        every = np.ones(self.num_envs, dtype=np.bool_)
        info = {"final_obs": final_obs, "_final_obs": every, "final_info": final_info,
                "_final_info": every.copy(), **self._reset_infos()}
        return (self._observations.copy(), rewards, np.ones(self.num_envs, dtype=np.bool_),
                np.zeros(self.num_envs, dtype=np.bool_), info)

    def _run_episodes(self, episodes: list[Episode]) -> tuple[np.ndarray, dict]:
        """The step's runs, one :class:`Episode` each: their rewards and the vector info of their step infos."""
        if self.reduced:
            from ..models.reduced.batch import reduced_batch  # numba's import waits for the first reduced step

            batch, rewards = reduced_batch(self.config, [e.values for e in episodes])
            runs = batch_runs(batch, self.config.sim.fidelity)
        else:
            results = self._simulate_each([e.config for e in episodes])
            rewards = np.array([reward(r, e.config) for r, e in zip(results, episodes)], dtype=np.float64)
            runs = [r.to_json_dict() for r in results]
        return rewards, stack_infos([episode_info(run, e, d) for run, e, d in zip(runs, episodes, self._draws)])

    def _run_columns(self, actions) -> tuple[np.ndarray, dict] | None:
        """At ``reduced``: :meth:`_run_episodes` of the step's episodes with one array per field and no Python per
        design between the actions and the model's kernel: the same rewards and infos, bit for bit
        (``tests/test_vector_env.py``). None where a row of ``actions`` is bad or the model refuses an episode: the
        per-episode path then words the refusal as the single env does."""
        from ..models.reduced.batch import reduced_columns

        a = self.space.rows_in_box(actions, self._clip)
        if a is None:
            return None
        design = self.space.values_columns(a)
        values, built = self.space.episode_columns(design, self._draws)
        ran = reduced_columns(self.config, values)
        if ran is None:
            return None
        batch, rewards = ran
        return rewards, batch_infos(batch, self.config.sim.fidelity, design, self._contexts(), built, self.num_envs)

    def close_extras(self, **kwargs: Any) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def __del__(self):
        # an env dropped unclosed must not leave its workers waiting; at interpreter exit the pool may be half gone
        if getattr(self, "_pool", None) is not None:
            try:
                self._pool.shutdown(wait=False, cancel_futures=True)
            except Exception:  # noqa: BLE001 - nothing left to report to
                pass

    # ---- the pieces ----
    def _rng(self, i: int) -> np.random.Generator:
        """Sub-env i's RNG, made unseeded on first use as ``gym.Env.np_random`` is."""
        if self._rngs[i] is None:
            self._rngs[i] = seeding.np_random()[0]
        return self._rngs[i]

    def _draw(self, i: int) -> Draw:
        """Sub-env i's next draw; in a scene that draws nothing, the draw every RNG gives, without the RNG."""
        return self.space.draw(self._rng(i)) if self._fixed is None else self._fixed

    def _observe(self) -> np.ndarray:
        return self.space.observations(self._draws)

    def _contexts(self) -> dict[str, list]:
        """Every sub-env's drawn context, by key: one value per sub-env."""
        return {k: [d.context[k] for d in self._draws] for k in self._draws[0].context}

    def _reset_infos(self) -> dict:
        """``stack_infos`` of every sub-env's reset info (its drawn context), built by key."""
        return stack_columns({"context": self._contexts()}, self.num_envs)

    def _seeds(self, seed) -> list:
        if seed is None:
            return [None] * self.num_envs
        if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            return [int(seed) + i for i in range(self.num_envs)]  # as SyncVectorEnv: sub-env i gets seed + i
        seeds = list(seed)
        if len(seeds) != self.num_envs:
            raise ConfigError(f"seed: a list of {len(seeds)} seeds for num_envs = {self.num_envs}; give one per "
                              f"sub-env, an int (sub-env i gets seed + i) or None")
        return seeds

    def _reset_mask(self, options) -> np.ndarray:
        mask = (options or {}).get("reset_mask")
        if mask is None:
            return np.ones(self.num_envs, dtype=np.bool_)
        mask = np.asarray(mask)
        if mask.dtype != np.bool_ or mask.shape != (self.num_envs,) or not mask.any():
            raise ConfigError(f"options['reset_mask'] has dtype {mask.dtype} and shape {mask.shape}: must be a bool "
                              f"array of shape ({self.num_envs},) with at least one True")
        return mask

    def _masked(self, infos: list[dict], mask: np.ndarray) -> dict:
        """The reset info of the masked sub-envs only (the others' entries False in every ``_key`` mask)."""
        info: dict = {}
        for i, sub in zip(np.flatnonzero(mask), infos):
            info = self._add_info(info, sub, int(i))
        return info

    def _check_shape(self, actions) -> None:
        shape, expected = np.shape(actions), (self.num_envs, self.space.dim)
        if shape != expected:
            raise ConfigError(f"actions has shape {shape}: expected (num_envs, d) = {expected}, one row per "
                              f"sub-env and one value per tunable ({', '.join(t.name for t in self.space.tunables)})")

    def _plan(self, actions) -> list[Episode]:
        a = np.asarray(actions)
        episodes = []
        for i, (row, draw) in enumerate(zip(a, self._draws)):
            try:
                episodes.append(plan_episode(self.space, draw, row, self._clip))
            except ConfigError as exc:
                raise ConfigError(f"actions[{i}]: {exc}") from None
        return episodes

    def _simulate_each(self, cfgs: list[Config]) -> list:
        if self._pool is None:
            return [simulate(c) for c in cfgs]
        try:
            return list(self._pool.map(simulate, cfgs))  # map keeps the sub-envs' order
        except BrokenProcessPool:
            raise RuntimeError(f"the pool's worker processes ended before they returned a run: spawn runs this "
                               f"script again in each worker, so make the env under {GUARD} (or leave out workers= to "
                               f"run in this process); a worker killed for memory ends the same way") from None


def _check_spawn_guard(workers: int) -> None:
    """Refuse a pool that would die: inside a worker still re-running the script (the script made the env outside its
    ``__main__`` guard), or asked for by a script that has no guard at all (spawn re-runs it in each worker)."""
    if getattr(multiprocessing.current_process(), "_inheriting", False):
        # the worker is importing the parent's script: one line on its stderr instead of multiprocessing's traceback
        raise SystemExit(f"aero-env: error: workers = {workers}: this script made a pooled vector env outside "
                         f"{GUARD}; the pool's workers re-run the script, so move that code under the guard")
    script = _unguarded_script()
    if script is not None:
        raise ConfigError(f"workers = {workers}: {script} has no {GUARD} and the pool's workers (spawn) run it "
                          f"again; put its code under that line, or leave out workers= to run in this process")


def _unguarded_script() -> str | None:
    """The main script's path when its source never compares ``__name__`` with ``"__main__"``; None for a guarded
    script, an interactive session or a notebook (no file to re-run)."""
    path = getattr(sys.modules.get("__main__"), "__file__", None)
    if not path:
        return None
    try:
        source = open(path, encoding="utf-8").read()
    except (OSError, UnicodeDecodeError):
        return None
    return None if "__name__" in source and re.search(r"['\"]__main__['\"]", source) else path
