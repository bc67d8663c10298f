"""Figures to fit, with tolerances: a targets YAML file, read and checked.

::

    swing: 1      # optional: the default for --swing
    source: "Shinohara & Nishibori, Appl. Sci. 2026, 16, 921, Sec. 7.3"
    targets:
      swing_duration: {value: 0.62, tolerance: 0.06, unit: s, source: "Fig. 40: ..."}
      theta1_detach_deg: {value: 165, tolerance: 5, unit: deg, source: "..."}

Each target names a metric of :data:`~.swing_metrics.METRICS`; ``value`` and ``tolerance``
(> 0) are in the metric's unit, and ``unit``, when given, must be that unit (a guard against
radians where degrees are meant). A run is scored by how many tolerances it is off each target
(:mod:`.scoring`). Bad input raises ``ConfigError`` naming the entry, the value and what is
allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping


from ..config import ConfigError, read_yaml
from .swing_metrics import METRICS

TOP_KEYS = ("swing", "source", "targets")
TARGET_KEYS = ("value", "tolerance", "unit", "source")


@dataclass(frozen=True)
class Target:
    metric: str
    value: float
    tolerance: float
    unit: str
    source: str = ""


@dataclass(frozen=True)
class Targets:
    targets: tuple[Target, ...]
    swing: int | None = None
    source: str = ""
    path: str = ""


def load_targets(path: str | Path) -> Targets:
    """Read and check a targets file."""
    return parse_targets(read_yaml(path, "--targets"), str(Path(path)))


def parse_targets(data: Any, where: str = "targets file") -> Targets:
    """Check a targets mapping as read from YAML."""
    if not isinstance(data, Mapping):
        raise ConfigError(f"{where}: must be a mapping with keys {list(TOP_KEYS)}, got {data!r}")
    _no_unknown_keys(data, TOP_KEYS, where)
    entries = data.get("targets")
    if not isinstance(entries, Mapping) or not entries:
        raise ConfigError(f"{where}: targets: must be a non-empty mapping of metric -> {{value, tolerance}}; "
                          f"metrics: {', '.join(METRICS)}")
    targets = tuple(_target(str(name), entry, where) for name, entry in entries.items())
    return Targets(targets=targets, swing=_swing(data.get("swing"), where), source=str(data.get("source") or ""),
                   path=where)


def _no_unknown_keys(data: Mapping, allowed: tuple[str, ...], where: str) -> None:
    extra = sorted(map(str, set(data) - set(allowed)))
    if extra:
        raise ConfigError(f"{where}: {extra[0]}: unknown key; allowed keys are {list(allowed)}")


def _swing(value: Any, where: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ConfigError(f"{where}: swing = {value!r}: must be a whole number >= 0 (0: the swing from rest, "
                          f"1: the first swing entered from a flight)")
    return value


def _target(name: str, entry: Any, where: str) -> Target:
    at = f"{where}: targets.{name}"
    if name not in METRICS:
        raise ConfigError(f"{at}: unknown metric; allowed: {', '.join(METRICS)}")
    unit = METRICS[name][0]
    if not isinstance(entry, Mapping):
        raise ConfigError(f"{at} = {entry!r}: must be a mapping {{value: ..., tolerance: ...}} in {unit}")
    _no_unknown_keys(entry, TARGET_KEYS, at)
    value = _number(entry, "value", at, unit)
    tolerance = _number(entry, "tolerance", at, unit)
    if tolerance <= 0:
        raise ConfigError(f"{at}.tolerance = {tolerance!r}: must be > 0 {unit} (the score divides by it)")
    given_unit = entry.get("unit", unit)
    if given_unit != unit:
        raise ConfigError(f"{at}.unit = {given_unit!r}: {name} is measured in {unit!r}")
    return Target(metric=name, value=value, tolerance=tolerance, unit=unit, source=str(entry.get("source") or ""))


def _number(entry: Mapping, key: str, at: str, unit: str) -> float:
    if key not in entry:
        raise ConfigError(f"{at}.{key}: missing; a number in {unit}")
    v = entry[key]
    if isinstance(v, str):  # YAML 1.1 reads 1e-3 (no dot) as a string
        try:
            v = float(v)
        except ValueError:
            pass
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ConfigError(f"{at}.{key} = {v!r}: must be a finite number in {unit}")
    return float(v)
