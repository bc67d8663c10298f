"""The search: which values of the ``--fit`` keys make the simulated swing closest to its reference.

**One key: a grid, then golden-section refinement.** Half the trial budget (at least
:data:`GRID_MIN` points) samples the range evenly; the rest narrows the bracket around the best
grid point by golden sections until it is :data:`XTOL` of the range. The score against one
number is low-dimensional and cheap to bracket, but not smooth everywhere: runs that miss swing
N sit on a flat penalty plateau and outcomes switch at thresholds, which a local method alone
would get stuck on and which the grid sees. Golden section then converges geometrically
(0.618 per trial) where TPE with the same budget would still be sampling the range at about a
percent; and it needs no seed, so ``--seed`` does not change a one-key fit.

**Several keys: CMA-ES** (Optuna's ``CmaEsSampler``, seeded by ``--seed``, mean at the box's
centre and sigma a sixth of it, on the box normalised to [0, 1] per key). It handles coupled
keys (m3 against h, say) that a coordinate search would zigzag along.

Both are deterministic: the same command gives the same result in any process. Optuna is
imported only for CMA-ES, so the rest of ``aero_env`` works without the ``tune`` extra.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..config import Config, ConfigError, MissingExtra, real_field
from .measured import MeasuredSwing
from .scoring import Evaluation, evaluate, missed
from .targets import Targets

FIT_SYNTAX = "KEY=LOW:HIGH, e.g. design.m3=0.006:0.0085"
GRID_MIN = 5  # fewest grid points before refining: fewer cannot bracket a minimum away from the ends
GRID_SHARE = 0.5  # share of a one-key trial budget spent on the grid; golden section gets the rest
XTOL = 1e-4  # golden section stops when its bracket is this fraction of the range
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0  # the golden-section ratio, 0.618


@dataclass(frozen=True)
class FitKey:
    """One ``--fit KEY=LOW:HIGH``: a real-valued design or scene field and its search range."""

    key: str
    low: float
    high: float


@dataclass
class FitResult:
    fitted: dict[str, float]
    best: Evaluation
    trials: int
    method: str
    wall_time: float
    keys: tuple[FitKey, ...] = field(default_factory=tuple)


def parse_fit(text: str) -> FitKey:
    """Parse and check one ``--fit`` argument against the field's allowed range."""
    key, eq, span = str(text).partition("=")
    low_text, colon, high_text = span.partition(":")
    if not eq or not colon or not key.strip():
        raise ConfigError(f"--fit {text!r}: expected {FIT_SYNTAX}")
    key = key.strip()
    f = real_field(key, "--fit key")
    low, high = _bound(text, "LOW", low_text), _bound(text, "HIGH", high_text)
    if not low < high:
        raise ConfigError(f"--fit {text!r}: LOW = {low!r} must be below HIGH = {high!r}")
    meta = f.metadata
    for name, v in (("LOW", low), ("HIGH", high)):
        if _outside(meta, v):
            raise ConfigError(f"--fit {text!r}: {name} = {v!r} is out of range for {key}, allowed {_allowed(meta)}")
    return FitKey(key, low, high)


def _bound(text: str, name: str, raw: str) -> float:
    try:
        v = float(raw)
    except ValueError:
        v = math.nan
    if not math.isfinite(v):
        raise ConfigError(f"--fit {text!r}: {name} = {raw.strip()!r} must be a finite number ({FIT_SYNTAX})")
    return v


def _outside(meta, v: float) -> bool:
    lo, hi = meta["lo"], meta["hi"]
    return (lo is not None and (v < lo or (meta["lo_open"] and v == lo))) or (hi is not None and v > hi)


def _allowed(meta) -> str:
    unit = f" {meta['unit']}" if meta["unit"] and meta["unit"] != "-" else ""
    return f"{'(' if meta['lo_open'] else '['}{meta['lo']}, {meta['hi']}]{unit}"


def parse_fits(texts: list[str] | None) -> tuple[FitKey, ...]:
    """Every ``--fit``; at least one, each key once."""
    if not texts:
        raise ConfigError(f"--fit: missing; give at least one {FIT_SYNTAX}")
    keys = tuple(parse_fit(t) for t in texts)
    seen: set[str] = set()
    for k in keys:
        if k.key in seen:
            raise ConfigError(f"--fit {k.key}: given twice; fit each key once")
        seen.add(k.key)
    return keys


def check_box(cfg: Config, keys: tuple[FitKey, ...]) -> None:
    """Every corner of the search box must be a valid config (e.g. design.mu_k <= design.mu_s)."""
    for corner in itertools.product(*((k.low, k.high) for k in keys)):
        values = {k.key: v for k, v in zip(keys, corner)}
        try:
            cfg.with_values(values)
        except ConfigError as exc:
            where = ", ".join(f"{k}={v!r}" for k, v in values.items())
            raise ConfigError(f"--fit box corner {where}: {exc}") from None


class Objective:
    """Score a point of the box; remembers the best point and its evaluation (first of equals)."""

    def __init__(self, cfg: Config, reference: MeasuredSwing | Targets, swing: int,
                 progress: Callable[[int, float], None] | None = None):
        self.cfg, self.reference, self.swing, self.progress = cfg, reference, swing, progress
        self.trials = 0
        self.best: Evaluation | None = None
        self.best_values: dict[str, float] = {}

    def __call__(self, values: dict[str, float]) -> float:
        try:
            trial_cfg = self.cfg.with_values(values)
        except ConfigError as exc:  # check_box makes this rare: only a constraint the corners all satisfy
            ev = missed(str(exc), self.reference)
        else:
            ev = evaluate(trial_cfg, self.reference, self.swing)
        self.trials += 1
        if self.best is None or ev.score < self.best.score:
            self.best, self.best_values = ev, {k: float(v) for k, v in values.items()}
        if self.progress:
            self.progress(self.trials, self.best.score)
        return ev.score


def search_1d(objective: Objective, key: FitKey, trials: int) -> None:
    """A grid over the range, then golden sections around its best point (see the module doc)."""
    n_grid = trials if trials <= GRID_MIN else max(GRID_MIN, int(trials * GRID_SHARE))
    xs = [0.5 * (key.low + key.high)] if n_grid == 1 else [float(x) for x in np.linspace(key.low, key.high, n_grid)]
    ys = [objective({key.key: x}) for x in xs]
    if n_grid < 2 or trials == n_grid:
        return
    i = int(np.argmin(ys))
    golden_section(lambda x: objective({key.key: x}), xs[max(i - 1, 0)], xs[min(i + 1, n_grid - 1)],
                   budget=trials - n_grid, xtol=XTOL * (key.high - key.low))


def golden_section(f: Callable[[float], float], a: float, b: float, budget: int, xtol: float) -> None:
    """Narrow [a, b] around a minimum of ``f`` with at most ``budget`` calls, until it is ``xtol`` wide."""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc = f(c)
    budget -= 1
    if budget <= 0:
        return
    fd = f(d)
    budget -= 1
    while budget > 0 and b - a > xtol:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
        budget -= 1


def require_optuna():
    try:
        import optuna
    except ImportError:
        raise MissingExtra("aero-env calibrate with two or more --fit keys", "Optuna", "tune") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    return optuna


def search_cmaes(objective: Objective, keys: tuple[FitKey, ...], trials: int, seed: int) -> None:
    """Optuna's CMA-ES over the box, seeded."""
    optuna = require_optuna()
    sampler = optuna.samplers.CmaEsSampler(seed=seed, warn_independent_sampling=False)
    study = optuna.create_study(direction="minimize", sampler=sampler)
    study.optimize(lambda trial: objective({k.key: trial.suggest_float(k.key, k.low, k.high) for k in keys}),
                   n_trials=trials)


def fit(cfg: Config, keys: tuple[FitKey, ...], reference: MeasuredSwing | Targets, swing: int, trials: int,
        seed: int = 0, progress: Callable[[int, float], None] | None = None) -> FitResult:
    """Search the box of ``keys`` for the values that score best; deterministic for its arguments."""
    t0 = time.perf_counter()
    objective = Objective(cfg, reference, swing, progress)
    if len(keys) == 1:
        method = "grid+golden"
        search_1d(objective, keys[0], trials)
    else:
        method = "cmaes"
        search_cmaes(objective, keys, trials, seed)
    return FitResult(fitted=objective.best_values, best=objective.best, trials=objective.trials, method=method,
                     wall_time=time.perf_counter() - t0, keys=keys)
