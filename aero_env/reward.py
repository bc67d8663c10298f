"""The design environment's reward: one function for every scorer.

The environment (:class:`aero_env.envs.AerialAcrobatEnv`), the tuner's evaluator (which scores
designs through the environment) and the tuner's screen (:func:`agents.tune.screen`, which scores
a batch of the reduced model at once) all score a run here, so "the reward of a design" is one
objective at every fidelity:

* each consecutive traversal (a seated catch by the next frame that then carried the robot through its
  lowest point: :data:`aero_env.physics.swing_rules.CARRIED_THETA1_DEG`) pays 1;
* with ``env.reward_shaping = w > 0``, a failed transfer that was a real flight (the hook let go of
  the frame that last caught it: :attr:`aero_env.results.SimResult.flew`) adds
  ``w · max(0, 1 - miss_distance / scene.pitch)``: how close the flight came to the next seat.
  A run whose hook never let go (``stalled``, ``no_detach``) adds nothing, however near its hook
  hung; ``w <= 0.99``, so the credit never reaches one more traversal;
* an ``unstable`` run earns 0: its numbers are not physics.

This module depends only on the result's fields and the config (not on an engine).
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from .config import Config, ConfigError

__all__ = ["reward", "rewards", "batch_reward", "designs_reward"]


def rewards(outcome, traversals, flew, miss_distance, pitch, shaping) -> np.ndarray:
    """The reward of each run, vectorised (arrays of one length, or scalars that broadcast).

    ``outcome``: str; ``traversals``: int; ``flew``: bool, the run ended in a flight; ``miss_distance``
    (m, NaN where none); ``pitch`` (m) and ``shaping`` (``env.reward_shaping``) of each run's config."""
    outcome = np.asarray(outcome, dtype=str)
    traversals = np.asarray(traversals, dtype=float)
    flew = np.asarray(flew, dtype=bool)
    miss = np.asarray(miss_distance, dtype=float)
    pitch, w = np.asarray(pitch, dtype=float), np.asarray(shaping, dtype=float)
    try:
        shape = np.broadcast_shapes(outcome.shape, traversals.shape, flew.shape, miss.shape, pitch.shape, w.shape)
    except ValueError:
        raise ConfigError(f"rewards: outcome, traversals, flew, miss_distance, pitch and shaping must have one length "
                          f"(got shapes {outcome.shape}, {traversals.shape}, {flew.shape}, {miss.shape}, "
                          f"{pitch.shape}, {w.shape})") from None
    shaped = flew & (w > 0) & np.isfinite(miss)
    with np.errstate(invalid="ignore"):
        credit = np.where(shaped, w * np.maximum(0.0, 1.0 - miss / pitch), 0.0)
    return np.broadcast_to(np.where(outcome == "unstable", 0.0, traversals + credit), shape).astype(float)


def reward(result, cfg: Config) -> float:
    """The reward of one run (a :class:`~aero_env.results.SimResult`) of ``cfg``."""
    miss = np.nan if result.miss_distance is None else result.miss_distance
    return float(rewards(result.outcome, result.traversals, result.flew, miss, cfg.scene.pitch,
                         cfg.env.reward_shaping))


def batch_reward(batch, cfgs: Sequence[Config]) -> np.ndarray:
    """The reward of each run of a reduced-model batch (:class:`aero_env.models.reduced.BatchResult`) of
    ``cfgs``, the configs it ran, in order: equal to :func:`reward` of each run alone."""
    if len(cfgs) != len(batch):
        raise ConfigError(f"batch_reward: {len(cfgs)} configs for a batch of {len(batch)} runs; pass the configs "
                          f"the batch ran, in order")
    pitch = np.array([c.scene.pitch for c in cfgs], dtype=float)
    w = np.array([c.env.reward_shaping for c in cfgs], dtype=float)
    return rewards(batch.outcome, batch.traversals, batch.flew, batch.miss_distance, pitch, w)


def designs_reward(batch, base: Config, designs: Sequence[Mapping[str, float]]) -> np.ndarray:
    """The reward of each run of a reduced-model batch of ``designs`` set on ``base``
    (:func:`aero_env.models.reduced.simulate_designs`): :func:`batch_reward` of the configs they would build."""
    if len(designs) != len(batch):
        raise ConfigError(f"designs_reward: {len(designs)} designs for a batch of {len(batch)} runs; pass the designs "
                          f"the batch ran, in order")
    pitch = np.array([d.get("scene.pitch", base.scene.pitch) for d in designs], dtype=float)
    return rewards(batch.outcome, batch.traversals, batch.flew, batch.miss_distance, pitch, base.env.reward_shaping)
