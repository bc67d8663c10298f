"""The maker's contexts as a benchmark: which contexts are held out, and which are watched.

Shared by ``benchmarks/rl_policies.py`` (which trains the shipped policies and watches their learning curves)
and ``benchmarks/rl_vs_tuning.py`` (which scores every method). Three disjoint sets of episode seeds:

* training and tuning draw from seeds below 10^5 (a vector env's sub-envs are seeded ``seed + i``);
* the **watch** set, :data:`WATCH_BASE` onward, is what the learning curves are drawn on, and where a setting
  of a method was chosen (the maps' CMA-ES step);
* the **hold-out** sets, ``10^6·(S+1)`` onward for ``--holdout-seed S``, give the final scores only.

An episode seed fixes the context (observed) and the build's cutting error (not observed), so two methods
scored on the same seeds face the same contexts and the same builds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SCENE = "aero_env/AerialAcrobatContexts-v0"
CONFIG = "configs/contexts.yaml"
SINGLE = "configs/contexts_single.yaml"  # the best single design (its header: the tune that wrote it)


@dataclass(frozen=True)
class Task:
    """A benchmark task: its registered scene, the config file that is that scene, the stored best single design
    (None: none was tuned, and every search starts from the box's centre), and where its policies are shipped."""

    name: str
    scene: str
    config: str
    single: str | None
    policies: str
    oracle_restarts: int = 0  # searches from the box's centre on the contexts the first search left unsolved


TASKS = {
    "contexts": Task("contexts", SCENE, CONFIG, SINGLE, "policies/contexts"),
    # the maker's wider shelves on the 8-frame row (docs/agents.md, "The hard task"): maps fitted from cold
    "hard": Task("hard", "aero_env/AerialAcrobatContexts-Hard-v0", "configs/contexts_hard.yaml", None,
                 "policies/contexts-hard", oracle_restarts=2),
}
HOLDOUT_BASE = 1_000_000
WATCH_BASE = 500_000  # the learning curves' contexts: above every training seed, below every hold-out set


def holdout_seeds(holdout_seed: int, n: int) -> list[int]:
    start = HOLDOUT_BASE * (holdout_seed + 1)
    return list(range(start, start + n))


def watch_seeds(n: int) -> list[int]:
    return list(range(WATCH_BASE, WATCH_BASE + n))


def single_action(space, task: Task = TASKS["contexts"]) -> np.ndarray:
    """The action (float64) of ``task``'s stored best single design in ``space``; the box's centre where the task
    has none (a cold start)."""
    from aero_env.config import load_config

    if task.single is None:
        return np.zeros(space.dim)
    single = load_config(task.single)
    return space.action_for({t.name: single.value(t.name) for t in space.tunables}, dtype=np.float64)
