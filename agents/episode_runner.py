"""Run many episodes of one scene, each a (draw, action) pair, as ``env.step`` would run them.

The benchmarks of a context -> design map score designs on chosen scenes: hold-out contexts, the same
contexts on a fresh build, a per-context search's candidates. :class:`EpisodeRunner` takes the draws
(context + build, :class:`aero_env.design_space.Draw`) and one action per draw, and returns each episode's
traversals: at ``reduced`` in one call of the model's kernel, at a pymunk fidelity over a pool of one
process per core. An action goes through the env's own path (the float32 cast, the clip, the map onto the
design), so a runner's episode and ``env.step`` on the same seed are the same run
(``tests/test_context_maps.py``).
"""

from __future__ import annotations

import os

import numpy as np

from aero_env.config import Config
from aero_env.design_space import DesignSpace, Draw
from aero_env.process_pool import worker_pool
from aero_env.simulation import simulate


def draws_for_seeds(space: DesignSpace, seeds) -> list[Draw]:
    """What ``env.reset(seed=s)`` draws for each seed: the context and the build."""
    return [space.draw_for_seed(int(s)) for s in seeds]


def fresh_builds(space: DesignSpace, draws: list[Draw], seed: int) -> list[Draw]:
    """The same contexts built again by hand: each draw's tolerance factors drawn anew (uniform in [-1, 1), as a
    reset draws them) from ``seed``; the contexts are kept."""
    rng = np.random.default_rng(seed)
    u = 2.0 * rng.random((len(draws), len(space.tolerances))) - 1.0
    return [Draw(dict(d.context), tuple(float(x) for x in row)) for d, row in zip(draws, u)]


def _run(cfg: Config) -> tuple[int, str]:
    r = simulate(cfg)
    return int(r.traversals), str(r.outcome)


class EpisodeRunner:
    """Episodes of ``cfg``'s scene at its fidelity; ``workers`` processes at a pymunk fidelity (default one per
    core; a script that uses them needs ``if __name__ == "__main__":``, as the vector env's pool does)."""

    def __init__(self, cfg: Config, workers: int | None = None):
        self.cfg = cfg
        self.space = DesignSpace(cfg)
        self.reduced = cfg.sim.model == "reduced"
        self.full_row = cfg.scene.frames - 1
        workers = (os.cpu_count() or 1) if workers is None else workers
        self._pool = None
        if not self.reduced and workers > 1:
            self._pool = worker_pool(workers)
        self.episodes = 0  # episodes run so far (a method's budget is counted here)

    def observations(self, draws: list[Draw]) -> np.ndarray:
        return self.space.observations(draws)

    def actions_in_box(self, actions) -> np.ndarray:
        """The actions clipped to the box, float64 (the mapping then reads them as float32, the space's dtype, as
        the env does); a NaN or infinite entry is refused in one line."""
        a = self.space.rows_in_box(np.clip(np.asarray(actions, dtype=np.float64), -1.0, 1.0), clip=True)
        if a is None:
            raise ValueError("actions: a NaN or infinite entry; a map must give finite numbers (clipped to [-1, 1])")
        return a

    def run(self, draws: list[Draw], actions) -> tuple[np.ndarray, list[str]]:
        """Each episode's consecutive traversals and outcome (draw i played with action row i)."""
        a = self.actions_in_box(actions)
        if len(draws) != len(a):
            raise ValueError(f"{len(draws)} draws for {len(a)} actions")
        self.episodes += len(draws)
        design = self.space.values_columns(a)
        if self.reduced:
            from aero_env.models.reduced.batch import reduced_batch, reduced_columns

            values, _ = self.space.episode_columns(design, draws)
            ran = reduced_columns(self.cfg, values)
            if ran is None:  # a value the columns path refuses: the per-episode path (same runs)
                n = len(draws)
                ran = reduced_batch(self.cfg, [{k: float(v[i]) for k, v in values.items()} for i in range(n)])
            return np.asarray(ran[0].traversals, dtype=np.int64), [str(o) for o in ran[0].outcome]
        cfgs = [self.space.episode_config({k: float(v[i]) for k, v in design.items()}, d)[0]
                for i, d in enumerate(draws)]
        runs = list(self._pool.map(_run, cfgs) if self._pool else map(_run, cfgs))
        return np.array([t for t, _ in runs], dtype=np.int64), [o for _, o in runs]

    def traversals(self, draws: list[Draw], actions) -> np.ndarray:
        """Each episode's consecutive traversals (draw i played with action row i)."""
        return self.run(draws, actions)[0]

    def whole_rows(self, draws: list[Draw], actions) -> np.ndarray:
        return self.traversals(draws, actions) >= self.full_row

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
