"""The design environment: one episode builds one design and runs it along the row."""

from __future__ import annotations

import functools
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Mapping

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..config import Config, ConfigError, load_config, pymunk_fidelities, shown, warn_unit_slips
from ..design_space import DesignSpace, Draw
from ..physics import SimResult, World
from ..reward import reward  # the one reward function: the tuner's screen scores with it too
from ..simulation import simulate
from ..render import ANIMATION_FPS, Canvas, draw_frames, draw_summary, iter_frames, pose_interval

__all__ = ["AerialAcrobatEnv", "Episode", "check_reset_options", "chosen_design", "plan_episode", "episode_info",
           "reset_info"]


# ---- the pieces of an episode, shared with the vector env (aerial_acrobat_vector.py) so the two cannot drift ----
@dataclass(frozen=True)
class Episode:
    """What one step simulates: every field the episode sets on the env's config, the design the action chose and
    the fields as built."""

    base: Config  # the env's config
    values: dict  # every field set (context, design, as built; dotted keys, SI)
    design: dict  # the tunable (and linked) values, SI
    as_built: dict  # the fields the tolerances changed, as simulated, SI

    @functools.cached_property
    def config(self) -> Config:
        """The config to simulate, built on first use (the reduced vector env runs ``values`` without one)."""
        return self.base.with_values(self.values)


def chosen_design(space: DesignSpace, action, clip: bool) -> dict[str, float]:
    """The tunable (and linked) values, SI, that ``action`` chooses; a bad action raises ConfigError naming its
    dimension (``clip``: an out-of-box finite action is clipped instead, ``env.action_out_of_box: clip``)."""
    return space.values(space.check_action(action, clip))


def plan_episode(space: DesignSpace, draw: Draw, action, clip: bool) -> Episode:
    """The episode ``action`` asks for in the scene of ``draw``."""
    design = chosen_design(space, action, clip)
    values, built = space.episode_values(design, draw)
    return Episode(space.cfg, values, design, built)


def check_reset_options(options: Any, known: tuple[str, ...] = ()) -> dict:
    """``reset``'s ``options`` as a dict (None: empty), or a ConfigError naming what is wrong: not a mapping, or a
    key this env does not read (``known``), which would otherwise be ignored without a word."""
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise ConfigError(f"reset(options={shown(options)}): must be a dict or None")
    unknown = [k for k in options if k not in known]
    if unknown:
        reads = f"it reads {', '.join(map(repr, known))}" if known else "it reads none"
        raise ConfigError(f"reset(options=...): {shown(unknown[0])} is not an option of this env ({reads})")
    return dict(options)


def reset_info(draw: Draw) -> dict:
    """What ``reset`` returns as info: the drawn context, SI."""
    return {"context": dict(draw.context)}


def episode_info(run: dict, episode: Episode, draw: Draw) -> dict:
    """A step's info from its run's ``to_json_dict()`` (or the fields of it that a batch has): the run less
    ``wall_time`` (the only field that is not a function of config and seed), plus design, context, as built."""
    info = {k: v for k, v in run.items() if k != "wall_time"}
    info.update(design=episode.design, context=dict(draw.context), as_built=episode.as_built)
    return info


# What a step after terminated=True (and before reset) warns, once until the next reset. Gymnasium's own envs
# (CartPole) warn so through gymnasium.logger and go on; its OrderEnforcing wrapper refuses only a step before the
# first reset, and its env checker none after the end. Vector envs and SB3 reset after every episode themselves,
# and a one-step bandit is often stepped on in one scene on purpose (benchmarks/env_step.py), so it warns, not
# refuses.
STEP_AFTER_END = ("step() after the episode ended (terminated=True): call reset() first. This step scored the "
                  "action as a new episode in the last reset's scene (its context and as-built draw); Gymnasium "
                  "leaves a step after the end undefined")


def env_config(config: str | Path | Config | None, overrides: Mapping[str, Any] | None,
               kwargs: Mapping[str, Any]) -> Config:
    """An env's config: a path (or None: the default scene) loaded with its overrides and keyword overrides, or a
    Config with them applied, warned about unit slips as load_config warns about a file's values."""
    extra = {**(overrides or {}), **kwargs}
    if isinstance(config, Config):
        cfg = config.replace(extra) if extra else config
        warn_unit_slips(extra)
        return cfg
    return load_config(config, extra)


def _no_display() -> bool:
    """A Linux machine without a display to open, where no SDL video driver was chosen."""
    return (sys.platform.startswith("linux") and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")
            and not os.environ.get("SDL_VIDEODRIVER"))


class AerialAcrobatEnv(gym.Env):
    """
    ## Description

    The paper-craft aerial acrobat (Shinohara & Nishibori, Appl. Sci. 2026, 16, 921) swings
    with no motor along a rising row of counterweighted swing frames: each frame, pulled
    round by the robot's weight against its counterbalance, lifts the robot until the hook
    slips off the handrail and the spring-loaded arm snaps forward onto the next frame.
    This environment asks for the *design* that makes it work. One episode is one design:
    the action chooses the design parameters, the step simulates the whole row in the
    pymunk world (:func:`aero_env.physics.simulate`), and the reward counts the consecutive
    successful traversals. It is a contextual bandit: with a varied scene the policy must
    map what it observes of the scene to a design.

    ## Action Space

    ``Box(-1, 1, (d,), float32)``, one dimension per entry of the config's ``tunable`` list,
    mapped onto ``[low, high]`` linearly or geometrically (``scale: log``). A range with
    ``relative_to`` is that many times the named field's value in the config, so it follows
    the scene (a toy with La = 29 mm is searched over 22-39 mm). The defaults
    (``aero_env.config.DEFAULT_TUNABLES``), with the prototype's value inside every range:

    | Num | Field            | Low   | High  | relative_to      | Maps as              | On the prototype    | Unit    |
    |-----|------------------|-------|-------|------------------|----------------------|---------------------|---------|
    | 0   | design.m3        | 0.5   | 1.6   | design.m2        | linear, step 0.1 g   | 3.9-12.3 g          | kg      |
    | 1   | design.h         | -0.2  | 0.4   | design.La        | linear               | -9.7-19.3 mm        | m       |
    | 2   | design.La        | 0.75  | 1.35  | design.La        | linear               | 36-65 mm            | m       |
    | 3   | design.spring_k  | 0.22  | 4.5   | design.spring_k  | log                  | 0.19-3.9 N·mm/rad   | N·m/rad |
    | 4   | design.mu_s      |       |       | (absolute)       | 3 choices, thirds    | 0.283, 0.507, 0.542 | -       |

    **A maker's choices.** Every design an action names is one a maker can build, and the action
    stays a ``Box`` (what every Gymnasium algorithm takes) mapped onto the nearest buildable
    choice. ``step`` snaps a value to its nearest multiple in the range (``step: 0.1 g`` on
    ``design.m3``: whole one-yen coins and clay weighed on a kitchen scale, written as the maker
    writes it, 0.0072 kg). ``choices`` cuts ``[-1, 1]`` into equal bins, one per listed choice,
    each setting the field and its ``linked`` keys: action 4 below -1/3 is Table 3's gray/gray
    card (mu_s 0.283, mu_k 0.149), up to +1/3 white/white (0.507, 0.337), above it white/gray
    (0.542, 0.409, the prototype's), least friction first so that neighbouring bins are
    neighbouring frictions. A config may list a pair its maker measured. The lengths print 1:1
    on the template and the spring is a strip the kit plans no narrower than scissors cut, so
    those stay continuous. Why a ``Box`` and not ``MultiDiscrete``: a Gaussian policy (PPO, SAC)
    and CMA-ES move smoothly through it, and one space holds the continuous and the discrete
    dimensions together. ``env.action_for()`` gives the action of the config's own
    design (the prototype's with ``configs/paper.yaml``). An action outside the box, of the
    wrong shape, or with NaN raises ``ConfigError`` naming the dimension, its field and the
    allowed range; with ``env.action_out_of_box: clip`` an out-of-box (finite) action is clipped.

    ## Observation Space

    ``Box(-1, 1, (k,), float32)``: the config's ``context`` list, what a designer knows of the
    scene, each normalised over its range (``-1`` at ``low``, ``+1`` at ``high``; ``0`` where the
    field is fixed). Defaults, all fixed at the config's value: ``scene.rise``, ``scene.pitch``,
    ``design.m2``. The values in SI are in ``info["context"]``. Tolerances are not observed.

    ## Rewards

    | Outcome                                   | Reward                                                   |
    |-------------------------------------------|----------------------------------------------------------|
    | each consecutive traversal (seated catch, then carried through the robot's lowest point) | +1 (the full row of ``n`` frames gives ``n - 1``) |
    | a failed transfer that flew (shaping on): ``fell_short``, ``missed_catch`` (a catch that did not hold included: its miss is its distance to that seat) | ``+ env.reward_shaping · max(0, 1 - miss_distance / pitch)`` |
    | a hook that never let go: ``stalled``, ``no_detach`` | +0, however near the next seat it hung       |
    | ``unstable`` (the engine lost the state)  | 0 in all: its numbers are not physics                    |
    | ``collides`` (``scene.effects.clearance`` on: the kit's parts meet as its frames turn, nothing simulated) | 0 |

    Shaping is off by default (``env.reward_shaping: 0``); its weight is below 1, so partial
    credit never outweighs one more real traversal. Credit is only for how close a real flight
    came to the next seat: the run must have let go of the frame that last caught it
    (``env.unwrapped.last_run.flew``). :func:`aero_env.reward.reward` is the function; the
    tuner's screen (``tune --screen``) scores with it too.

    ## Starting State

    ``reset(seed=...)`` draws each varied ``context`` field uniformly from ``[low, high]`` and
    each ``tolerance`` factor ``u`` uniformly from [-1, 1] with the env's RNG. The run itself
    starts, as in the paper, at the catch on frame 0 with the frame at its rest angle and the
    robot line at ``scene.theta2_start_deg``.

    ## Episode End

    Every step terminates the episode (``terminated=True``): the run ends at
    the first failed transfer or once the last frame has caught the robot and carried it through its
    lowest point, and always within ``sim.t_max``. The episode ends by itself, so nothing truncates it:
    ``truncated`` is always False. The ids are registered without ``max_episode_steps``, as Gymnasium's
    ``Blackjack-v1`` is, so ``gym.make`` adds no ``TimeLimit``; ``check_env(gym.make(id))`` passes, and
    code that bootstraps on ``truncated`` never takes this terminal step for a time-out.
    ``info`` holds the run as ``aero-env simulate --json`` prints it (``outcome``,
    ``reason``, ``traversals``, ``frames``, ``swings``, ``energy``, ``sim_time``,
    ``miss_distance``, ``health``) except ``wall_time``, which would break determinism, plus ``design``
    (the tunable and linked values chosen, SI), ``context`` (SI) and ``as_built`` (the fields the
    tolerances changed, as simulated, SI).

    The spec's ``reward_threshold`` is the whole row of the id's own scene (``frames - 1``: 7 on the
    prototype's 8 frames, 4 on ``AerialAcrobatContexts-v0``'s 5, 7 on the hard task's 8), which only a
    completed run reaches, shaped or not; it is fixed per id, so with ``scene.frames`` (or ``config``) overridden the whole row
    is that scene's ``frames - 1``, not the threshold.

    ``reset()`` starts the next episode. A ``step()`` after ``terminated=True`` without a ``reset()`` warns once
    (until the next reset) through ``gymnasium.logger``, as Gymnasium's own environments do (CartPole: "any
    further steps are undefined behavior"), and scores the action as a new episode in the scene of the last
    reset (the same context and as-built draw, not a fresh one):

    | Call after ``terminated=True``  | What happens                                                          |
    |---------------------------------|-----------------------------------------------------------------------|
    | ``reset()``, then ``step(a)``   | a new episode in a newly drawn scene (what vector envs and SB3 do)     |
    | ``step(a)`` without ``reset()`` | one ``UserWarning`` "step() after the episode ended (terminated=True): call reset() first...", then ``a`` scored in the last reset's scene |

    ``gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")`` steps N designs in one call
    (:class:`aero_env.envs.AerialAcrobatVectorEnv`, SAME_STEP autoreset unless ``autoreset_mode=`` says
    otherwise), equal to N of these envs.

    ``env.unwrapped.last_run`` is the last step's :class:`aero_env.results.SimResult` (None after
    a reset): its ``swings`` (per-frame catch, detach and flight), and with
    ``env.record_trace: true`` its ``trace``, the time series ``aero-env simulate --trace`` writes.

    ## Arguments

    | Argument      | Default | Meaning                                                             |
    |---------------|---------|---------------------------------------------------------------------|
    | ``config``    | None    | a YAML path or a :class:`Config`; None: the prototype (the defaults) |
    | ``overrides`` | None    | dotted-key overrides, as ``--set`` (``{"scene.rise": 0.004}``); a value orders of magnitude from anything that can swing warns once (``UnitSlipWarning``), as ``load_config`` does |
    | ``render_mode`` | None  | ``human`` (pygame window), ``rgb_array``, ``rgb_array_list``        |
    | ``**kwargs``  |         | more dotted-key overrides: ``gym.make(id, **{"design.m2": 0.008})`` |

    The episode runs at the config's ``sim.fidelity`` (default ``mbd``, the pymunk world):
    ``gym.make(id, **{"sim.fidelity": "reduced"})`` scores designs with the reduced model (no
    pymunk, no rendering) for screening, ``"reference"`` with the converged pymunk settings.

    ```python
    import gymnasium as gym
    import aero_env  # registers the environments

    env = gym.make("aero_env/AerialAcrobat-v0", config="configs/paper.yaml", **{"scene.rise": 0.001})
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.unwrapped.action_for())
    ```

    ## Rendering

    ``rgb_array``: after reset, the row at its start; after a step, the last run in one
    picture (its final pose, the hook's path, the outcome). ``rgb_array_list``: every frame of
    the last run's animation. ``human``: plays that animation in a pygame window, during
    ``step``. Frames are ``(env.render_height, env.render_width, 3)`` uint8; animations play
    ``env.render_slowmo`` times slower than real time at ``metadata["render_fps"]``. Only
    ``human`` touches pygame's display; on a Linux machine with no display (neither ``DISPLAY``
    nor ``WAYLAND_DISPLAY``, and no ``SDL_VIDEODRIVER`` chosen) it draws into SDL's ``dummy``
    driver with one warning, instead of SDL's own errors (``XDG_RUNTIME_DIR is invalid``):
    Gymnasium's ``check_env`` opens every declared mode, ``human`` included.

    ## Version History

    The ids have stayed ``-v0`` through these changes, so a result is comparable only with one of
    the same code (``git log``):

    * v0, first: the registered design bandit ``AerialAcrobat-v0`` and ``AerialAcrobatVaried-v0``
      (context and tolerances drawn at reset); one step builds the design and runs the whole row in
      the pymunk world; reward: the consecutive traversals.
    * v0: ``sim.fidelity`` (a ladder of pymunk settings, and ``reduced``, the reduced model: no
      pymunk, no rendering); ``mbd-fast`` later left the ladder.
    * v0: ``env.reward_shaping`` credits only a failed transfer that flew (the hook let go), through
      the one reward function the tuner's screen uses too.
    * v0: tunable ranges ``relative_to`` a field, so they follow the scene; ``env.unwrapped.last_run``.
    * v0: the robot built to the paper's Table 1 (its unknowns refitted), and a catch counts as a
      traversal only once its frame has carried the robot through its lowest point: rewards changed.
    * v0: ``AerialAcrobatContexts-v0`` (the maker's contexts on a 5-frame row); a context entry can
      carry ``linked`` fields (a drawn ``design.mu_s`` moves ``design.mu_k``); the native vector env
      (``vector_entry_point``).
    * v0: a ``step()`` after ``terminated=True`` warns once; a value 1000x from anything that swings
      warns with its likely unit.
    * v0: ``max_episode_steps=1`` and ``reward_threshold`` in the spec (truncated True under
      ``gym.make``, above); the vector env's ``autoreset_mode``.
    * v0: the world swings the parts as the kit builds them (``aero_env.parts``: each part's card,
      coins and clay give its mass and inertia): rewards changed.
    * v0: the default design problem, and every registered id's, is a maker's choices: ``design.m3``
      in 0.1 g steps, the card pair one of Table 3's (was a continuous friction over 0.2-1.5): the
      action's meaning on dimensions 0 and 4 changed.
    * v0: registered without ``max_episode_steps`` (was 1): ``gym.make`` adds no ``TimeLimit``, so a step
      returns ``truncated=False`` (was True beside ``terminated=True``) and ``check_env(gym.make(id))``
      passes; ``reward_threshold`` kept; rewards unchanged. ``reset(options=...)`` refuses an option the
      env does not read.
    * v0: ``AerialAcrobatContexts-Hard-v0`` (``configs/contexts_hard.yaml``: the maker's contexts over a room's
      range, rows that fall or climb, on the 8-frame row); the other ids unchanged.
    * v0: ``scene.effects.clearance`` (off in every registered id): a design whose kit's parts meet ends as
      ``collides`` with reward 0; with it off, every run as before.
    """

    metadata = {"render_modes": ["human", "rgb_array", "rgb_array_list"], "render_fps": ANIMATION_FPS}

    def __init__(self, config: str | Path | Config | None = None, overrides: Mapping[str, Any] | None = None,
                 render_mode: str | None = None, **kwargs: Any):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ConfigError(f"render_mode = {render_mode!r}: must be one of {self.metadata['render_modes']} or None")
        self.config = env_config(config, overrides, kwargs)
        self.space = DesignSpace(self.config)
        if render_mode is not None and self.config.sim.model == "reduced":
            raise ConfigError(f"render_mode = {render_mode!r}: sim.fidelity = {self.config.sim.fidelity!r} never builds "
                              f"the machine's bodies, so there is nothing to draw; render at a pymunk fidelity "
                              f"({pymunk_fidelities()})")
        if self.config.env.record_trace and self.config.sim.model == "reduced":
            raise ConfigError(f"env.record_trace = True: sim.fidelity = {self.config.sim.fidelity!r} has no time series "
                              f"(the reduced model keeps none); record at a pymunk fidelity ({pymunk_fidelities()})")
        self.render_mode = render_mode
        self.action_space = spaces.Box(-1.0, 1.0, (self.space.dim,), np.float32)
        self.observation_space = spaces.Box(-1.0, 1.0, (self.space.obs_dim,), np.float32)
        self._draw: Draw = self.space.nominal_draw()
        self.last_run: SimResult | None = None  # the last step's run (public: see the class docstring)
        self._ended = False  # a step has returned terminated=True since the last reset
        self._warned_after_end = False  # and a step after it has warned (once until the next reset)
        self._window = None
        self._clock = None

    # ---- the design problem ----
    def action_for(self, design: Mapping[str, float] | None = None) -> np.ndarray:
        """The action whose design is ``design`` (dotted keys, SI); missing keys take the config's values."""
        return self.space.action_for(design)

    def design_for(self, action) -> dict[str, float]:
        """The tunable (and linked) values, SI, that ``action`` chooses."""
        return chosen_design(self.space, action, self._clip)

    @property
    def _clip(self) -> bool:
        return self.config.env.action_out_of_box == "clip"

    # ---- Gymnasium API ----
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        check_reset_options(options)
        super().reset(seed=seed)
        self._draw = self.space.draw(self.np_random)
        self.last_run = None
        self._ended = self._warned_after_end = False
        if self.render_mode == "human":
            self._show([self._start_frame()])
        return self.space.observation(self._draw), reset_info(self._draw)

    def step(self, action):
        if self._ended and not self._warned_after_end:
            self._warned_after_end = True
            gym.logger.warn(STEP_AFTER_END)
        episode = plan_episode(self.space, self._draw, action, self._clip)
        cfg = episode.config
        result = simulate(cfg, trace=cfg.env.record_trace,
                          poses_every=pose_interval(cfg.env.render_slowmo) if self.render_mode else None)
        self.last_run = result
        info = episode_info(result.to_json_dict(), episode, self._draw)
        if self.render_mode == "human":
            self.render()
        self._ended = True
        return self.space.observation(self._draw), reward(result, cfg), True, False, info

    # ---- rendering ----
    def _size(self) -> tuple[int, int]:
        return self.config.env.render_width, self.config.env.render_height

    def _start_frame(self) -> np.ndarray:
        cfg, _ = self.space.episode_config({}, self._draw)  # the config's own design in this reset's scene
        world = World(cfg)
        return Canvas(world.geometry(), *self._size()).draw((0.0, *world.pose()), "ready")

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode: gym.make(..., render_mode='rgb_array')")
            return None
        r = self.last_run
        if self.render_mode == "rgb_array":
            return self._start_frame() if r is None else draw_summary(r, *self._size())
        if self.render_mode == "rgb_array_list":
            return [self._start_frame()] if r is None else draw_frames(r, *self._size())
        self._show([self._start_frame()] if r is None else iter_frames(r, *self._size()))  # drawn as shown
        return None

    def _show(self, frames: Iterable[np.ndarray]) -> None:
        import pygame

        if self._window is None:
            if _no_display():
                gym.logger.warn("render_mode='human' with no display (DISPLAY and WAYLAND_DISPLAY unset): nothing is "
                                "shown (SDL's dummy driver); use render_mode='rgb_array' for frames")
                os.environ["SDL_VIDEODRIVER"] = "dummy"  # else SDL tries Wayland and X11 and prints why each failed
            pygame.display.init()  # display only: pygame.init() would also open the sound card
            pygame.display.set_caption("aero-env: aerial acrobat")
            self._window = pygame.display.set_mode(self._size())
            self._clock = pygame.time.Clock()
        for frame in frames:
            pygame.event.pump()
            self._window.blit(pygame.surfarray.make_surface(frame.swapaxes(0, 1)), (0, 0))
            pygame.display.flip()
            self._clock.tick(self.metadata["render_fps"])

    def close(self):
        if self._window is not None:
            import pygame

            pygame.display.quit()
            self._window = None
