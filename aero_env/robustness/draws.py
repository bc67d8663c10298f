"""Draw builds within the tolerances, build their configs, and simulate them (in order, 1 or W processes).

The factors come from ``numpy.random.default_rng(seed)``: one ``u ~ U(-1, 1)`` per draw and
tolerance, drawn as an (N, P) array in one call, so the same seed gives the same builds in any
process. A build whose values leave a field's allowed range or break a design cross-check (the
config raises :class:`~aero_env.config.ConfigError`) is not clipped: it is an **invalid build**
(outcome :data:`INVALID`, counted as not completing the row). Clipping would pile draws onto the
range's edge and report a machine the tolerances never described; a table that can reach an
impossible machine is something the maker should see. A ConfigError raised by the simulator
while it builds the world (a part the physics cannot assemble) counts the same way.

With ``workers > 1`` the runs go to a ``spawn`` process pool (``concurrent.futures``) and come
back in submission order, so the results do not depend on the number of workers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from ..config import Config, ConfigError
from ..process_pool import worker_pool
from ..results import COLLIDES
from .tolerances import Tol, built_values

INVALID = "invalid_build"  # the outcome of a build the config (or the world builder) rejects


@dataclass(frozen=True)
class Build:
    """One machine to simulate: the values the tolerances built, and its config (None when invalid)."""

    values: dict
    config: Config | None
    error: str | None = None
    collides: str | None = None  # why the kit it is built from does not clear (scene.effects.clearance)


@dataclass(frozen=True)
class Run:
    """What the robustness report keeps of one simulation."""

    traversals: int
    outcome: str
    reason: str


def draw_factors(seed: int, draws: int, count: int) -> np.ndarray:
    """The (draws, count) tolerance factors u in [-1, 1), row by row: draw i is row i."""
    rng = np.random.default_rng(seed)
    return 2.0 * rng.random((draws, count)) - 1.0


def build(cfg: Config, tols: Sequence[Tol], u: Sequence[float]) -> Build:
    """The machine that the factors ``u`` (one per tolerance) build from ``cfg``."""
    values: dict[str, float] = {}
    for t, ui in zip(tols, u):
        values.update(built_values(cfg, t, float(ui)))
    try:
        built = cfg.with_values(values)
    except ConfigError as exc:
        return Build(values, None, str(exc))
    if not cfg.scene.effects.clearance:
        return Build(values, built)
    # the kit is drawn, and its cards cut, for the design: a hand-made build of it is judged by that kit (its
    # small errors are not swept again), so it collides where the design's kit does and clears where it clears
    from ..parts.clearance import kit_clearance

    verdict = kit_clearance(cfg)
    return Build(values, built.replace({"scene.effects.clearance": False}),
                 collides=None if verdict.clears else verdict.reason())


def single_change(cfg: Config, tols: Sequence[Tol], index: int, end: float) -> Build:
    """The machine with tolerance ``index`` alone at its ``end`` (-1 or +1), every other field nominal."""
    return build(cfg, [tols[index]], [end])


def _run_one(job: tuple[Callable, Build]) -> Run:
    simulator, b = job
    if b.config is None:
        return Run(0, INVALID, b.error or "")
    if b.collides is not None:
        return Run(0, COLLIDES, b.collides)
    try:
        r = simulator(b.config)
    except ConfigError as exc:
        return Run(0, INVALID, str(exc))
    return Run(int(r.traversals), str(r.outcome), str(r.reason))


def run_builds(builds: Sequence[Build], simulator: Callable, workers: int = 1,
               progress: Callable[[int, int], None] | None = None) -> list[Run]:
    """Simulate every build with ``simulator`` (a module-level function, so a worker can import it),
    returning the runs in the order of ``builds``."""
    jobs = [(simulator, b) for b in builds]
    if workers <= 1:
        return _collect(map(_run_one, jobs), len(jobs), progress)
    with worker_pool(workers) as pool:
        return _collect(pool.map(_run_one, jobs), len(jobs), progress)


def _collect(results, total: int, progress) -> list[Run]:
    runs = []
    for r in results:
        runs.append(r)
        if progress:
            progress(len(runs), total)
    return runs
