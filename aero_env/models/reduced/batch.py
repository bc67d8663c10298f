"""The reduced model run on a batch of environment episodes, and their rewards: :func:`reduced_batch`.

What the vector env's reduced step and the tuner's screen call. Episodes come as the fields each sets on a base
config (:meth:`aero_env.design_space.DesignSpace.episode_values`). Where every episode sets the same fields, the
model reads all of them and each value is a number, the values go in as arrays (no Config per design; the same
runs, bit for bit). Otherwise the episodes take the configs they build, as the single env does.

A refusal on the arrays path is refused again through ``Config.with_values``, so that a bad value is worded as
the single env words it (the key, the value with its unit, the range). Should the configs accept what the arrays
refused, the two checks disagree: the configs run the batch (the same runs, only slower), the first such
*fallback* in a process warns (:class:`ReducedFallbackWarning`), and :data:`FALLBACKS` counts them all
(``aero-env bench throughput --json`` reports them as ``reduced_fallbacks``).
"""

from __future__ import annotations

import numbers
import warnings
from typing import Mapping, Sequence

import numpy as np

from ...config import Config, ConfigError
from ...reward import batch_reward, designs_reward, rewards
from . import READ_KEYS, simulate_batch, simulate_designs, simulate_values

__all__ = ["FALLBACKS", "FallbackCount", "ReducedFallbackWarning", "reduced_batch", "reduced_columns"]


class ReducedFallbackWarning(RuntimeWarning):
    """The arrays path refused a batch the configs accept: the runs are the same, only slower."""


class FallbackCount:
    """How many :func:`reduced_batch` calls in this process fell back from the arrays to the configs; the first
    warns."""

    def __init__(self):
        self.count = 0
        self.warned = False

    def record(self, refusal: ConfigError) -> None:
        self.count += 1
        if not self.warned:
            self.warned = True
            warnings.warn(f"reduced_batch: the values path refused a batch the configs accept ({refusal}); it ran "
                          f"as configs, slower (aero_env.models.reduced.batch.FALLBACKS counts these; the two checks "
                          f"should agree)", ReducedFallbackWarning, stacklevel=3)


FALLBACKS = FallbackCount()


def _as_arrays(episodes: Sequence[Mapping[str, float]]) -> bool:
    """Whether the episodes can go in as arrays: the same fields in each, all read by the model, all numbers."""
    keys = episodes[0].keys()
    return (set(keys) <= READ_KEYS and all(e.keys() == keys for e in episodes)
            and all(isinstance(v, numbers.Real) and not isinstance(v, bool) for e in episodes for v in e.values()))


def reduced_batch(base: Config, episodes: Sequence[Mapping[str, float]]):
    """One call of the reduced model for episodes given as the fields each sets on ``base``
    (:meth:`DesignSpace.episode_values`), and their rewards. Where every episode sets the same fields and the model
    reads all of them, the values go in as arrays (no Config per design; the same runs); otherwise, and to word
    a bad value as ``Config.with_values`` does (the key, the value with its unit, the range), as the configs they
    build."""
    if not episodes:
        raise ConfigError("reduced_batch: no episodes; pass at least one dict of the fields an episode sets")
    refusal = None
    if _as_arrays(episodes):
        try:
            batch = simulate_designs(base, episodes)
        except ConfigError as exc:  # a value refused: the configs below refuse it in with_values' words
            refusal = exc
        else:
            mark_collisions(batch, base, episodes)
            return batch, designs_reward(batch, base, episodes).astype(np.float64)
    cfgs = [base.with_values(e) for e in episodes]
    if refusal is not None:  # ... they did not: the two checks disagree
        FALLBACKS.record(refusal)
    batch = simulate_batch(cfgs)
    mark_collisions(batch, base, episodes, cfgs)
    return batch, batch_reward(batch, cfgs).astype(np.float64)


def mark_collisions(batch, base: Config, episodes: Sequence[Mapping[str, float]], cfgs=None) -> None:
    """With ``scene.effects.clearance`` on, each episode whose kit's parts meet becomes ``collides``
    (:func:`aero_env.simulation.collides`, as the single env runs it); off, nothing (and no cost)."""
    if not base.scene.effects.clearance:
        return
    from ...parts.clearance import kit_clearance

    for i, e in enumerate(episodes):
        verdict = kit_clearance(base.with_values(e) if cfgs is None else cfgs[i])
        if not verdict.clears:
            batch.collide(i, verdict.reason())


def reduced_columns(base: Config, columns: Mapping[str, np.ndarray]):
    """:func:`reduced_batch` of episodes given as one float64 array per field (the vector env's step:
    :meth:`DesignSpace.episode_columns`), with no dict per episode: the batch and its rewards, the same runs and
    rewards bit for bit. None where the arrays cannot go in as they are (a field the model does not read, no
    field at all) or the model refuses a value: the caller then runs the episodes' dicts through
    :func:`reduced_batch`, which words a refusal as the single env does."""
    if not columns or not set(columns) <= READ_KEYS or base.scene.effects.clearance:  # clearance: per design
        return None
    try:
        batch = simulate_values(base, columns)
    except ConfigError:
        return None
    pitch = columns["scene.pitch"] if "scene.pitch" in columns else base.scene.pitch  # designs_reward's pitch
    return batch, rewards(batch.outcome, batch.traversals, batch.flew, batch.miss_distance, pitch,
                          base.env.reward_shaping).astype(np.float64)
