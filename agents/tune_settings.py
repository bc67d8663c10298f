"""What ``aero-env tune`` was asked to do: :class:`TuneSettings`, read by the tuner, its study storage and its
workers (:mod:`agents.tune`, :mod:`agents.study_storage`, :mod:`agents.tune_workers`), none of which it imports."""

from __future__ import annotations

from dataclasses import dataclass

from aero_env.config import FIDELITY_PRESETS, ConfigError
from aero_env.scene_args import MAX_SEED

from .options import SAMPLERS, check_choice, check_ints
from .study_faults import RECONNECT_S

DEFAULT_FILE_STORAGE = "sqlite:///aero-env-tune.db"  # used when a study must outlive the process


def sqlite_file(url: str) -> str | None:
    """The database file a ``sqlite://`` URL names, as SQLAlchemy reads it ("" for none; None for another scheme):
    ``sqlite:///study.db`` is ``study.db``, ``sqlite:////abs/study.db`` is ``/abs/study.db``."""
    scheme, _, rest = url.partition("://")
    if scheme.split("+")[0] != "sqlite":
        return None
    path = rest.split("?")[0]
    return path[1:] if path.startswith("/") else path


@dataclass(frozen=True)
class TuneSettings:
    """What ``aero-env tune`` was asked to do; every field is checked by :meth:`check`."""

    sampler: str = "cmaes"
    trials: int = 100
    seeds_per_design: int = 1
    seed: int = 0
    storage: str | None = None      # None: memory with one worker and no study name, else DEFAULT_FILE_STORAGE
    study: str | None = None        # None: "<config stem>-<sampler>-s<seed>"
    workers: int = 1
    progress: bool = True
    screen: str | None = None       # a cheaper fidelity to screen random designs with (e.g. reduced)
    screen_designs: int = 20000     # designs the screen scores
    reconnect_s: float = RECONNECT_S  # a lost database is retried this long before the run stops
    robust: int = 0                 # hand-made builds each design is scored on (0: the design as drawn, no builds)

    def check(self) -> "TuneSettings":
        check_choice("sampler", self.sampler, SAMPLERS)
        check_ints(self, (("trials", 1, 10**7), ("seeds_per_design", 1, 10**4), ("workers", 1, 512),
                          ("seed", 0, MAX_SEED), ("screen_designs", 1, 10**8),
                          ("robust", 0, 10**4)))
        if (isinstance(self.reconnect_s, bool) or not isinstance(self.reconnect_s, (int, float))
                or not 0 <= self.reconnect_s <= 86400):
            raise ConfigError(f"--reconnect {self.reconnect_s!r}: seconds in [0, 86400]")
        if self.screen is not None:
            check_choice("screen", self.screen, tuple(FIDELITY_PRESETS))
        if self.storage is not None and self.storage != "memory" and "://" not in self.storage:
            raise ConfigError(f"--storage {self.storage!r}: must be 'memory' or a database URL "
                              f"(sqlite:///FILE.db, postgresql://USER@HOST:PORT/DB)")
        if self.storage == "memory" and self.workers > 1:
            raise ConfigError(f"--storage memory with --workers {self.workers}: processes cannot share an "
                              f"in-memory study; give --storage sqlite:///FILE.db or a postgresql:// URL")
        if self.storage is not None and sqlite_file(self.storage) in ("", ":memory:"):
            # SQLite keeps such a database in memory: the study was gone after the run, and each worker had its own
            raise ConfigError(f"--storage {self.storage!r}: names no file, so SQLite would keep the study in memory "
                              f"and lose it when the run ends; give a file, e.g. --storage sqlite:///study.db")
        return self

    def resolved_storage(self) -> str:
        if self.storage is not None:
            return self.storage
        return "memory" if self.workers == 1 and self.study is None else DEFAULT_FILE_STORAGE

    def study_name(self, config_name: str) -> str:
        return self.study or f"{config_name}-{self.sampler}-s{self.seed}"

    @property
    def eval_seeds(self) -> tuple[int, ...]:
        """The episode seeds every design is scored on (the same for every trial and every tuning seed)."""
        return tuple(range(self.seeds_per_design))

    def build_factors(self):
        """``robust`` > 0: the (robust, tolerances) factors of the hand-made builds every trial is scored on, drawn
        once from ``seed`` (common random numbers: the same builds for every trial and every worker); else None."""
        if not self.robust:
            return None
        from .design_eval import robust_factors

        return robust_factors(self.seed, self.robust)
