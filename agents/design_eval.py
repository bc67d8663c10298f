"""Scoring one design through the environment, on a fixed set of episode seeds.

Every tuner and every comparison scores designs here, so that "the reward of a design" means
one thing: the mean environment reward over the same seeds (common random numbers). The reward
is :func:`aero_env.reward.reward` (shaping included), which ``tune --screen`` scores with too. A seed
fixes one reset's draws, the observed context and the unobserved build tolerances; on a scene
that draws nothing every seed gives the same run, so the design is simulated once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from aero_env.config import Config, ConfigError
from aero_env.envs import AerialAcrobatEnv
from aero_env.results import COLLIDES
from aero_env.reward import reward
from aero_env.simulation import simulate


@dataclass(frozen=True)
class DesignScore:
    """One design's runs: the reward per seed and what each run did."""

    design: dict            # tunable and linked fields, SI
    rewards: tuple          # env reward per seed
    traversals: tuple       # consecutive traversals per seed
    outcomes: tuple         # outcome per seed

    @property
    def mean_reward(self) -> float:
        return float(np.mean(self.rewards))

    def to_json_dict(self) -> dict:
        return dict(design=dict(self.design), mean_reward=self.mean_reward, rewards=list(self.rewards),
                    traversals=list(self.traversals), outcomes=list(self.outcomes))


def robust_factors(seed: int, builds: int, tols: Sequence | None = None) -> np.ndarray:
    """The (builds, tolerances) factors u in [-1, 1) of ``tune --robust``: drawn once from ``seed`` (as
    ``aero-env robustness`` draws its builds) and applied to every trial's design alike."""
    from aero_env.robustness.draws import draw_factors
    from aero_env.robustness.tolerances import DEFAULT_TOLERANCES

    return draw_factors(seed, builds, len(DEFAULT_TOLERANCES if tols is None else tols))


def start_params(space) -> dict[str, float] | None:
    """The config's own design as a trial's params (a float64 point of the action box, by field), or None where
    a config value lies outside its tunable range (the box cannot hold it)."""
    try:
        action = space.action_for(dtype=np.float64)
    except ConfigError:
        return None
    return {t.name: min(1.0, max(-1.0, float(a))) for t, a in zip(space.tunables, action)}


class DesignEvaluator:
    """Scores actions of ``config``'s design space on the episode seeds ``seeds``.

    With ``factors`` (a (K, P) array, one row per hand-made build, one column per tolerance of ``tols``,
    default :data:`aero_env.robustness.DEFAULT_TOLERANCES`), every episode is built K times, each build moving
    the design's own values by the same factors (:func:`aero_env.robustness.draws.build`), and the design's
    score is the mean reward over every (seed, build) run; a build the config rejects earns 0."""

    def __init__(self, config: Config, seeds: Sequence[int], factors: np.ndarray | None = None,
                 tols: Sequence | None = None):
        seeds = tuple(int(s) for s in seeds)
        if not seeds:
            raise ConfigError("seeds: empty; a design is scored on at least one episode seed")
        self.env = AerialAcrobatEnv(config)
        self.config = self.env.config
        self.space = self.env.space
        self.seeds = seeds
        self.full_row = self.config.scene.frames - 1
        self.factors = None if factors is None else np.asarray(factors, dtype=np.float64)
        if tols is None and factors is not None:
            from aero_env.robustness.tolerances import DEFAULT_TOLERANCES, check_against

            tols = DEFAULT_TOLERANCES
            check_against(self.config, tuple(tols))
        self.tols = tuple(tols or ())

    @property
    def start_params(self) -> dict[str, float] | None:
        return start_params(self.space)

    @property
    def start_design(self) -> dict[str, float]:
        """The config's own design: its values of every tunable and linked field, SI, exactly."""
        out = {}
        for t in self.space.tunables:
            out[t.name] = float(self.config.value(t.name))
            out.update({k: float(self.config.value(k)) for k in t.linked})
        return out

    @property
    def param_names(self) -> list[str]:
        """One name per action dimension: the tunable's field."""
        return [t.name for t in self.space.tunables]

    def score(self, action, design: dict | None = None) -> DesignScore:
        """The score of ``action``; with ``design`` (tunable and linked values, SI), of that design itself (the
        config's own, exactly, where an action would round it: :meth:`score_design`)."""
        if design is not None or self.factors is not None:
            return self.score_design(self.env.design_for(action) if design is None else design)
        runs = []
        for seed in self.seeds if self.space.draws_anything else self.seeds[:1]:
            self.env.reset(seed=seed)
            _, reward, _, _, info = self.env.step(action)
            runs.append((reward, info["traversals"], info["outcome"]))
        if len(runs) < len(self.seeds):  # nothing is drawn: every seed would repeat this run
            runs *= len(self.seeds)
        rewards, traversals, outcomes = zip(*runs)
        return DesignScore(self.env.design_for(action), rewards, traversals, outcomes)

    def score_design(self, design: dict) -> DesignScore:
        """Score the design ``design`` (tunable and linked values, SI) on the seeds (and builds): what
        :meth:`score` does for an action, from the values themselves (the config's own design is scored exactly,
        not through an action's rounding)."""
        from aero_env.robustness.draws import build

        runs = []
        for seed in self.seeds if self.space.draws_anything else self.seeds[:1]:
            cfg = self.space.episode_config(design, self.space.draw_for_seed(seed))[0]
            if self.factors is None:
                runs.append(_run(cfg))
                continue
            for u in self.factors:
                b = build(cfg, self.tols, u)
                runs.append((0.0, 0, "invalid_build") if b.config is None else
                            (0.0, 0, COLLIDES) if b.collides is not None else _run(b.config))
        if not self.space.draws_anything:
            runs *= len(self.seeds)
        rewards, traversals, outcomes = zip(*runs)
        return DesignScore(dict(design), rewards, traversals, outcomes)

    def close(self) -> None:
        self.env.close()


def _run(cfg: Config) -> tuple[float, int, str]:
    """One episode of ``cfg`` as ``env.step`` runs and pays it: (reward, traversals, outcome)."""
    try:
        result = simulate(cfg, trace=cfg.env.record_trace)
    except ConfigError:  # a build the world builder cannot assemble (as aero-env robustness counts it)
        return 0.0, 0, "invalid_build"
    return float(reward(result, cfg)), int(result.traversals), str(result.outcome)
