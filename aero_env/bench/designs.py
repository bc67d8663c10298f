"""The designs a benchmark measures, and the timing helper every benchmark shares."""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..config import Config, ConfigError
from ..design_space import DesignSpace


@dataclass(frozen=True)
class DesignSample:
    """``n`` designs drawn uniformly from a config's action box (and its context, if varied)."""

    actions: np.ndarray  # (n, dim)
    configs: tuple  # the episode config of each design, at the config's own fidelity
    seed: int


def draw_designs(cfg: Config, n: int, seed: int, near: Config | None = None, spread: float = 0.1) -> DesignSample:
    """``n`` random actions of ``cfg``'s design space, with their episode configs: uniform over the whole
    action box, or, with ``near``, uniform in a box of ±``spread`` (a fraction of each action range, which
    is 2 wide) around the action of ``near``'s design (its tunable values), clipped to the box. That is
    where a tuner spends its time once it has found a working design."""
    if n < 1:
        raise ConfigError(f"--designs {n}: must be at least 1")
    space = DesignSpace(cfg)
    rng = np.random.default_rng(seed)
    if near is None:
        actions = rng.uniform(-1.0, 1.0, (n, space.dim))
    else:
        if not 0.0 < spread <= 1.0:
            raise ConfigError(f"--spread {spread!r}: a fraction of each action range, allowed (0, 1]")
        try:
            centre = space.action_for({t.name: near.value(t.name) for t in space.tunables}).astype(float)
        except ConfigError as exc:
            raise ConfigError(f"--near: that config's design is not in this scene's design space: {exc}") from None
        actions = np.clip(centre + rng.uniform(-2.0 * spread, 2.0 * spread, (n, space.dim)), -1.0, 1.0)
    configs = tuple(space.episode_config(space.values(a), space.draw(rng))[0] for a in actions)
    return DesignSample(actions, configs, seed)


def median_time(fn: Callable[[], object], repeats: int) -> tuple[float, object]:
    """The median wall time of ``repeats`` calls of ``fn``, and the last call's result."""
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def check_counts(**counts: int) -> None:
    """Each named count is a whole number >= 1, or a ConfigError naming the option."""
    for name, value in counts.items():
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ConfigError(f"--{name.replace('_', '-')} {value!r}: must be a whole number >= 1")
