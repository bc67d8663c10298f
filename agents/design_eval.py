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


class DesignEvaluator:
    """Scores actions of ``config``'s design space on the episode seeds ``seeds``."""

    def __init__(self, config: Config, seeds: Sequence[int]):
        seeds = tuple(int(s) for s in seeds)
        if not seeds:
            raise ConfigError("seeds: empty; a design is scored on at least one episode seed")
        self.env = AerialAcrobatEnv(config)
        self.config = self.env.config
        self.space = self.env.space
        self.seeds = seeds
        self.full_row = self.config.scene.frames - 1

    @property
    def param_names(self) -> list[str]:
        """One name per action dimension: the tunable's field."""
        return [t.name for t in self.space.tunables]

    def score(self, action) -> DesignScore:
        runs = []
        for seed in self.seeds if self.space.draws_anything else self.seeds[:1]:
            self.env.reset(seed=seed)
            _, reward, _, _, info = self.env.step(action)
            runs.append((reward, info["traversals"], info["outcome"]))
        if len(runs) < len(self.seeds):  # nothing is drawn: every seed would repeat this run
            runs *= len(self.seeds)
        rewards, traversals, outcomes = zip(*runs)
        return DesignScore(self.env.design_for(action), rewards, traversals, outcomes)

    def close(self) -> None:
        self.env.close()
