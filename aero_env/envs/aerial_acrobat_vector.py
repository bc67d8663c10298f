"""The design environment batched: N designs per step, in one call (the registered ``vector_entry_point``)."""

from __future__ import annotations

import multiprocessing
import re
import sys
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any, Mapping

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from ..config import Config, ConfigError
from ..design_space import DesignSpace, Draw
from ..process_pool import worker_pool
from ..reward import reward
from ..simulation import simulate
from .aerial_acrobat import Episode, check_reset_options, env_config, episode_info, plan_episode, reset_info
from .vector_info import batch_infos, batch_runs, scatter_infos, stack_columns, stack_infos

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

    ## Autoreset: SAME_STEP by default

    Every episode is one step (a contextual bandit), so every step ends the episode of every
    sub-env it runs. ``autoreset_mode`` (an :class:`AutoresetMode`, its value ``"SameStep"`` or its
    name ``"SAME_STEP"``) says what happens next, as in ``SyncVectorEnv`` with that mode, and
    ``metadata["autoreset_mode"]`` holds it per instance (Gymnasium's vector wrappers read it):

    | mode                  | a step                                                                  |
    |-----------------------|-------------------------------------------------------------------------|
    | ``SAME_STEP`` (default) | scores every sub-env's design and resets it in the same call: every step scores ``num_envs`` designs |
    | ``NEXT_STEP``         | a sub-env whose episode the last step ended is only reset (its action ignored, reward 0, terminated and truncated False, its reset info); every other sub-env runs its design. Without masked resets every other step only resets |
    | ``DISABLED``          | every sub-env runs its design, none is reset; a step while any sub-env's episode has ended (after every step, here) is refused with a ``ConfigError`` naming them: call ``reset()`` or ``reset(options={"reset_mask": mask})`` first (``SyncVectorEnv`` refuses with an ``AssertionError``) |

    SAME_STEP is what SB3 and ``aero-env train --vector`` need (``agents.vec_env``). Gymnasium's vector
    observation wrappers (``gymnasium.wrappers.vector``: ``NormalizeObservation``, ``FlattenObservation``,
    ``DtypeObservation``, ``TransformObservation``, ...) refuse SAME_STEP; they take NEXT_STEP, and all
    but ``NormalizeObservation`` take DISABLED:

    ```python
    envs = gym.make_vec("aero_env/AerialAcrobatContexts-v0", num_envs=8, vectorization_mode="vector_entry_point",
                        autoreset_mode=gym.vector.AutoresetMode.NEXT_STEP)
    envs = gym.wrappers.vector.NormalizeObservation(envs)
    ```

    | returned by ``step``   | SAME_STEP                                                | NEXT_STEP, DISABLED                          |
    |------------------------|----------------------------------------------------------|----------------------------------------------|
    | observations           | the *next* episode's context, normalised, ``(num_envs, k)`` float32 | the stepped episode's own (a reset sub-env: its new episode's) |
    | rewards                | each design's reward, :func:`aero_env.reward.reward`, float64 | the same; 0 for a sub-env that was reset |
    | terminated             | all True                                                 | True where a design ran                      |
    | truncated              | all False (unless ``max_episode_steps=1``, below)        | the same where a design ran; False where reset |
    | ``info["final_obs"]``  | object array: the observation each finished episode was stepped on | absent                      |
    | ``info["final_info"]`` | the finished episodes' infos (below)                     | absent: their keys are in ``info`` itself, masked to the sub-envs that ran |
    | ``info["context"]``    | the next episode's context, SI (the reset info)          | the stepped episode's context (a reset sub-env: its new one) |

    ``truncated`` follows Gymnasium's ``TimeLimit``: the registered ids have no ``max_episode_steps``
    (an episode ends by itself: the single env's "Episode End" section), so it is False, as in
    ``SyncVectorEnv`` of ``gym.make`` envs. Given ``max_episode_steps=1`` (``gym.make_vec(id,
    max_episode_steps=1)`` passes it on), each scored step returns truncated True beside terminated True,
    as ``TimeLimit(env, 1)`` gives the single env.

    ## Info

    A dict of arrays, one entry per sub-env, each key with its ``_key`` mask, built as
    ``SyncVectorEnv`` builds it from the single envs' infos (Gymnasium's dtypes included). Under
    SAME_STEP every mask is all True (every sub-env finishes every step) and ``final_info`` holds the
    single env's step info; under NEXT_STEP and DISABLED ``info`` itself holds it, each key's mask
    True on the sub-envs that ran a design (``context``'s on every sub-env: a reset sub-env's is its
    reset info). The step info's keys:

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
    | ``autoreset_mode`` | ``SAME_STEP`` | ``SAME_STEP``, ``NEXT_STEP`` or ``DISABLED`` (above); anything else is refused with a one-line ``ConfigError`` |
    | ``max_episode_steps`` | None      | TimeLimit's limit per sub-env, as ``gym.make_vec`` passes one given it; None (the spec's) or -1: none (truncated False) |
    | ``**kwargs``  |                  | more dotted-key overrides, as ``gym.make``                       |

    Actions are ``(num_envs, d)`` in the single env's box; a bad row raises ``ConfigError`` naming
    the row, the dimension and its field. There is no rendering and no trace (``env.record_trace``
    is refused): step the single env to watch a design. ``close()`` stops the pool.

    ## Version History

    The ids have stayed ``-v0``; what changed for the vector entry point (the single env's history
    holds the rest):

    * v0, first: ``num_envs`` designs per step through ``vector_entry_point``, SAME_STEP autoreset
      only; a reduced step is one call of the model, pymunk designs run in a process pool.
    * v0: pymunk designs run in this process unless ``workers`` asks for a pool; at ``reduced`` the step
      goes from the actions to the model's kernel in arrays (the same rewards and infos, bit for bit).
    * v0: ``autoreset_mode`` (NEXT_STEP, DISABLED beside SAME_STEP) and ``max_episode_steps`` (from
      the spec through ``gym.make_vec``: truncated True on each scored step, as TimeLimit gives the
      single envs).
    * v0: the registered ids have no ``max_episode_steps`` (was 1): truncated False on every step.
    """

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}  # each instance: its own mode

    def __init__(self, num_envs: int = 1, config: str | Path | Config | None = None,
                 overrides: Mapping[str, Any] | None = None, render_mode: str | None = None,
                 workers: int | None = None, autoreset_mode: AutoresetMode | str = AutoresetMode.SAME_STEP,
                 max_episode_steps: int | None = None, **kwargs: Any):
        self._pool = None  # first, so that close() works whatever below fails
        self.autoreset_mode = _autoreset_mode(autoreset_mode)
        self.metadata = {**type(self).metadata, "autoreset_mode": self.autoreset_mode}  # Gymnasium's wrappers read it
        self.max_episode_steps = _max_episode_steps(max_episode_steps)
        # each episode is one step, so TimeLimit(max_episode_steps) truncates it (beside terminated) exactly when
        # the limit is 1: elapsed = 1 >= max_episode_steps
        self._truncates = self.max_episode_steps == 1
        whole = isinstance(num_envs, (int, np.integer)) and not isinstance(num_envs, bool)
        if not whole or not 1 <= num_envs <= MAX_NUM_ENVS:
            raise ConfigError(f"num_envs = {num_envs!r}: must be a whole number in [1, {MAX_NUM_ENVS}] (designs per "
                              f"step)")
        if render_mode is not None:
            raise ConfigError(f"render_mode = {render_mode!r}: the vector env does not render; render the single env "
                              f"(gym.make(..., render_mode=...))")
        self.config = env_config(config, overrides, kwargs)
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
        # NEXT_STEP and DISABLED: the sub-envs whose episode ended at the last step, not reset since (SyncVectorEnv's
        # _autoreset_envs): NEXT_STEP resets them at the next step, DISABLED refuses to step them
        self._ended = np.zeros(self.num_envs, dtype=np.bool_)
        if not self.reduced and self.workers > 1:
            _check_spawn_guard(self.workers)
            self._pool = worker_pool(min(self.workers, self.num_envs), POOL_START_METHOD)

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
        self._ended[mask] = False
        self._observations = self._observe()
        if mask.all():
            info = self._reset_infos()
        else:
            info = self._masked([reset_info(self._draws[i]) for i in np.flatnonzero(mask)], mask)
        return self._observations.copy(), info

    def step(self, actions):
        self._check_shape(actions)
        if self.autoreset_mode != AutoresetMode.SAME_STEP:
            return self._step_apart(actions)
        rewards, final_info = self._run(actions, np.arange(self.num_envs))
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
                np.full(self.num_envs, self._truncates, dtype=np.bool_), info)

    def _step_apart(self, actions):
        """A step under NEXT_STEP or DISABLED, as ``SyncVectorEnv`` steps its sub-envs in that mode: a sub-env whose
        episode ended at the last step is reset (NEXT_STEP: its action ignored, reward 0, terminated and truncated
        False, its reset info) or refused (DISABLED); every other sub-env runs its design and returns the episode's
        own observation and its step info, with no ``final_obs`` or ``final_info``."""
        if self.autoreset_mode == AutoresetMode.DISABLED and self._ended.any():
            ended = np.flatnonzero(self._ended).tolist()
            raise ConfigError(f"step(): sub-envs {ended} ended at the last step and autoreset_mode = DISABLED resets "
                              f"none itself; call reset(options={{'reset_mask': mask}}) with those True, or reset(), "
                              f"first")
        resetting = self._ended.copy()
        stepped = np.flatnonzero(~resetting)
        rewards = np.zeros(self.num_envs, dtype=np.float64)
        parts = []
        if len(stepped):
            ran, info = self._run(actions, stepped)
            rewards[stepped] = ran
            parts.append((stepped, info))
        if resetting.any():
            for i in np.flatnonzero(resetting):  # unseeded, as SyncVectorEnv's env.reset(): each RNG goes on
                self._draws[i] = self._draw(i)
            self._observations = self._observe()
            parts.append((np.flatnonzero(resetting), self._reset_infos(np.flatnonzero(resetting))))
        # one part: its info is already every sub-env's; two: folded in sub-env order, as SyncVectorEnv's _add_info
        info = parts[0][1] if len(parts) == 1 else scatter_infos(sorted(parts, key=lambda p: p[0][0]), self.num_envs)
        terminated = ~resetting
        truncated = terminated & self._truncates
        self._ended = terminated | truncated
        return self._observations.copy(), rewards, terminated, truncated, info

    def _run(self, actions, rows: np.ndarray) -> tuple[np.ndarray, dict]:
        """The episodes of sub-envs ``rows`` (ascending) on their rows of ``actions``: their rewards and the vector
        info of their step infos, one entry per row in that order (all of them: every ``_key`` mask all True)."""
        if len(rows) == self.num_envs:  # every sub-env (SAME_STEP, DISABLED, a NEXT_STEP step that resets none)
            ran = self._run_columns(actions) if self.reduced else None
            return ran if ran is not None else self._run_episodes(self._plan(actions))
        draws = [self._draws[i] for i in rows]
        actions = np.asarray(actions)[rows]
        ran = self._run_columns(actions, draws) if self.reduced else None
        return ran if ran is not None else self._run_episodes(self._plan(actions, rows, draws), draws)

    def _run_episodes(self, episodes: list[Episode], draws: list[Draw] | None = None) -> tuple[np.ndarray, dict]:
        """The step's runs, one :class:`Episode` each (in the scenes of ``draws``, default every sub-env's): their
        rewards and the vector info of their step infos."""
        draws = self._draws if draws is None else draws
        if self.reduced:
            from ..models.reduced.batch import reduced_batch  # numba's import waits for the first reduced step

            batch, rewards = reduced_batch(self.config, [e.values for e in episodes])
            runs = batch_runs(batch, self.config.sim.fidelity)
        else:
            results = self._simulate_each([e.config for e in episodes])
            rewards = np.array([reward(r, e.config) for r, e in zip(results, episodes)], dtype=np.float64)
            runs = [r.to_json_dict() for r in results]
        return rewards, stack_infos([episode_info(run, e, d) for run, e, d in zip(runs, episodes, draws)])

    def _run_columns(self, actions, draws: list[Draw] | None = None) -> tuple[np.ndarray, dict] | None:
        """At ``reduced``: :meth:`_run_episodes` of the step's episodes (``actions`` one row per draw of ``draws``,
        default every sub-env's) with one array per field and no Python per design between the actions and the
        model's kernel: the same rewards and infos, bit for bit (``tests/test_vector_env.py``). None where a row of
        ``actions`` is bad or the model refuses an episode: the per-episode path then words the refusal as the single
        env does."""
        from ..models.reduced.batch import reduced_columns

        draws = self._draws if draws is None else draws
        a = self.space.rows_in_box(actions, self._clip)
        if a is None:
            return None
        design = self.space.values_columns(a)
        values, built = self.space.episode_columns(design, draws)
        ran = reduced_columns(self.config, values)
        if ran is None:
            return None
        batch, rewards = ran
        return rewards, batch_infos(batch, self.config.sim.fidelity, design, self._contexts(draws), built, len(draws))

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

    def _contexts(self, draws: list[Draw] | None = None) -> dict[str, list]:
        """Each draw's context (every sub-env's by default), by key: one value per draw."""
        draws = self._draws if draws is None else draws
        return {k: [d.context[k] for d in draws] for k in draws[0].context}

    def _reset_infos(self, rows=None) -> dict:
        """``stack_infos`` of the reset infos (the drawn contexts) of sub-envs ``rows`` (default every one), built by
        key: one entry per row."""
        draws = self._draws if rows is None else [self._draws[i] for i in rows]
        return stack_columns({"context": self._contexts(draws)}, len(draws))

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
        mask = check_reset_options(options, ("reset_mask",)).get("reset_mask")
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

    def _plan(self, actions, rows=None, draws: list[Draw] | None = None) -> list[Episode]:
        """The episodes of sub-envs ``rows`` (default every one): ``actions`` holds their rows, in order, in the
        scenes of ``draws``."""
        rows = range(self.num_envs) if rows is None else rows
        draws = self._draws if draws is None else draws
        a = np.asarray(actions)
        episodes = []
        for i, row, draw in zip(rows, a, draws):
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


def _autoreset_mode(value) -> AutoresetMode:
    """``value`` as an :class:`AutoresetMode`: the member, its value (``"NextStep"``, as Gymnasium's vector envs take
    it) or its name (``"NEXT_STEP"``); anything else raises a one-line ``ConfigError`` naming the allowed values."""
    if isinstance(value, AutoresetMode):
        return value
    if isinstance(value, str):
        for mode in AutoresetMode:
            if value in (mode.value, mode.name):
                return mode
    allowed = ", ".join(f"AutoresetMode.{m.name} ({m.value!r})" for m in AutoresetMode)
    raise ConfigError(f"autoreset_mode = {value!r}: must be one of {allowed}, or the member's name as a string")


def _max_episode_steps(value) -> int | None:
    """The limit TimeLimit would put on each sub-env (``gym.make_vec`` passes the spec's); None or -1: none, as
    ``gym.make(..., max_episode_steps=-1)``."""
    if value is None or (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value == -1):
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ConfigError(f"max_episode_steps = {value!r}: must be a whole number >= 1 (TimeLimit's steps per "
                          f"episode; every episode here is 1 step), or None or -1 for no limit")
    return int(value)


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
