"""One robustness study: the nominal run, each tolerance alone at its two ends, and N random builds.

Every run uses ``simulator`` (default :func:`aero_env.simulation.simulate`, at the config's own
fidelity) and they all go through one batch, nominal first, then the single changes in table
order (-end, +end), then the draws in draw order, so a pool of W workers is kept busy and the
order of the results never depends on W.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from ..bench.designs import check_counts
from ..config import Config
from .draws import Build, Run, build, draw_factors, run_builds, single_change
from .tolerances import Tol, check_against

ENDS = (-1.0, 1.0)  # a single change puts one tolerance at its lower, then its upper end


@dataclass(frozen=True)
class SingleChange:
    tol: Tol
    end: float
    build: Build
    run: Run


@dataclass(frozen=True)
class Study:
    """Everything one study simulated; :func:`aero_env.robustness.report.summarize` reads it."""

    cfg: Config
    tols: tuple[Tol, ...]
    seed: int
    factors: np.ndarray  # (draws, tolerances): u in [-1, 1) of each tolerance in each draw
    nominal: Run
    singles: list[SingleChange]
    builds: list[Build]
    runs: list[Run]

    @property
    def full(self) -> int:
        """Traversals of a whole row."""
        return self.cfg.scene.frames - 1


def _default_simulator() -> Callable:
    from .. import simulation  # looked up at call time, so a test can swap it

    return simulation.simulate


def assess(cfg: Config, tols: Sequence[Tol], draws: int, seed: int = 0, workers: int = 1,
           simulator: Callable | None = None, progress: Callable[[int, int], None] | None = None) -> Study:
    """Simulate ``cfg``'s nominal build, its single changes and ``draws`` random builds."""
    tols = tuple(tols)
    check_counts(draws=draws, workers=workers)
    check_against(cfg, tols)
    simulator = simulator or _default_simulator()
    ends = [(i, e) for i, t in enumerate(tols) if not t.zero for e in ENDS]
    singles = [single_change(cfg, tols, i, e) for i, e in ends]
    factors, builds = draw_builds(cfg, tols, draws, seed)
    nominal = Build({}, cfg)
    runs = run_builds([nominal, *singles, *builds], simulator, workers, progress)
    single_runs, draw_runs = runs[1:1 + len(singles)], runs[1 + len(singles):]
    changes = [SingleChange(tols[i], e, b, r) for (i, e), b, r in zip(ends, singles, single_runs)]
    return Study(cfg, tols, seed, factors, runs[0], changes, builds, draw_runs)


def completed_builds(cfg: Config, tols: Sequence[Tol], draws: int, seed: int = 0, workers: int = 1,
                     simulator: Callable | None = None, progress: Callable[[int, int], None] | None = None) -> int:
    """How many of the ``draws`` random builds :func:`assess` draws with ``seed`` complete the row: those builds
    alone, without the nominal run and the single changes, where only the share is wanted (a sheet's line)."""
    tols = tuple(tols)
    check_counts(draws=draws, workers=workers)
    check_against(cfg, tols)
    runs = run_builds(draw_builds(cfg, tols, draws, seed)[1], simulator or _default_simulator(), workers, progress)
    return sum(r.traversals == cfg.scene.frames - 1 for r in runs)


def draw_builds(cfg: Config, tols: tuple[Tol, ...], draws: int, seed: int) -> tuple[np.ndarray, list[Build]]:
    """The factors of ``draws`` random builds drawn with ``seed``, and the builds they make."""
    factors = draw_factors(seed, draws, len(tols))
    return factors, [build(cfg, tols, row) for row in factors]
