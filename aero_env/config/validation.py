"""Checking one config value against its declaration, and the error messages that name it.

:class:`ConfigError` is what every bad config raises; ``check_value`` reads a value (with or
without its unit) and checks its type and range, ``check_values`` an array of numbers the same way (the
reduced model's fast path); ``build_section`` checks a mapping into a section.
"""

from __future__ import annotations

import dataclasses
import difflib
import itertools
import math
import reprlib
from dataclasses import fields
from typing import Any, Mapping

import numpy as np

from .. import quantities


class _ShortRepr(reprlib.Repr):
    """``repr`` cut short: a handful of items per list or mapping, a few levels deep, 60 characters of a string;
    a mapping in its own order (reprlib sorts one). What a short value prints is ``repr``'s own text."""

    def __init__(self):
        super().__init__()
        self.maxlevel, self.maxlist, self.maxtuple, self.maxdict, self.maxset = 3, 8, 8, 6, 6
        self.maxstring, self.maxother, self.maxlong = 60, 60, 40

    def repr_dict(self, x, level):
        if not x:
            return "{}"
        if level <= 0:
            return "{...}"
        items = [f"{self.repr1(k, level - 1)}: {self.repr1(v, level - 1)}"
                 for k, v in itertools.islice(x.items(), self.maxdict)]
        return "{" + ", ".join(items) + (", ..." if len(x) > self.maxdict else "") + "}"


_SHORT = _ShortRepr()
SHOWN_MAX = 120  # characters of a value a message prints at most


def shown(value: Any) -> str:
    """``repr(value)`` for a message, never longer than about ``SHOWN_MAX``: a value as big as a YAML alias bomb
    makes it (or a megabyte string) would make a message of gigabytes. A value cut short says its size."""
    text = _SHORT.repr(value)
    if len(text) > SHOWN_MAX:
        text = text[:SHOWN_MAX - 3] + "..."
    most = {str: _SHORT.maxstring, list: _SHORT.maxlist, tuple: _SHORT.maxtuple, dict: _SHORT.maxdict}.get(type(value))
    if most is not None and len(value) > most:
        text += f" ({len(value):,} {'characters' if isinstance(value, str) else 'items'})"
    return text


class ConfigError(ValueError):
    """A config value is missing, unknown, of the wrong type or out of range."""


ConfigError.__module__ = "aero_env.config"  # tracebacks (and the docs quoting them) name it where it is imported from


class MissingExtra(ConfigError):
    """A command needs packages of an extra that this install left out (the README's first command installs
    the core only): not a slip in the config, so the command line calls it ``missing package``."""

    def __init__(self, what: str, packages: str, extra: str):
        super().__init__(f"{what} needs {packages}, which the core install (pip install -e .) leaves out: "
                         f"pip install -e '.[{extra}]'")


MissingExtra.__module__ = "aero_env.config"


def check_value(path: str, f: dataclasses.Field, value: Any) -> Any:
    """``value`` (a number, or a string with its unit) read and checked against the field ``f`` declares; a bad one
    raises one line naming ``path``, the value and the allowed range."""
    meta = f.metadata
    typ = f.type if isinstance(f.type, type) else {"float": float, "int": int, "bool": bool, "str": str}.get(f.type)
    if typ is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{path} = {shown(value)}: must be true or false")
        return value
    if typ is str:
        if not isinstance(value, str) or (meta["choices"] and value not in meta["choices"]):
            raise ConfigError(f"{path} = {shown(value)}: must be one of {list(meta['choices'])}")
        return value
    raw = value
    value, plain = with_unit(path, value, meta["unit"])
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        units = quantities.units_for(meta["unit"])
        with_units = f", optionally with a unit ({', '.join(units)})" if len(units) > 1 else ""
        raise ConfigError(f"{path} = {shown(value)}: must be a number ({typ.__name__}) in "
                          f"{range_text(meta)}{with_units}")
    text = repr(value) if plain else f"{shown(raw)} (= {value:.6g} {meta['unit']})"
    if typ is int:
        if isinstance(value, float) and not value.is_integer():
            raise ConfigError(f"{path} = {text}: must be a whole number in {range_text(meta)}")
        value = int(value)
    else:
        value = float(value)
    if plain:
        text = repr(value)
    if not math.isfinite(value):
        raise ConfigError(f"{path} = {text}: must be finite, in {range_text(meta)}")
    if not in_range(meta, value):
        hint = quantities.smaller_unit_hint(value, meta["unit"], lambda v: in_range(meta, v)) if plain else ""
        raise ConfigError(f"{path} = {text}: out of range, allowed {range_text(meta)}{hint}")
    return value


def in_range(meta: Mapping[str, Any], value):
    """Whether ``value`` lies in the range ``meta`` declares: a bool for a number, elementwise for an array."""
    lo, hi = meta["lo"], meta["hi"]
    ok = np.ones(np.shape(value), dtype=bool)
    if lo is not None:
        ok &= (value > lo) if meta["lo_open"] else (value >= lo)
    if hi is not None:
        ok &= value <= hi
    return ok if ok.ndim else bool(ok)


def check_values(path: str, f: dataclasses.Field, values: np.ndarray) -> None:
    """:func:`check_value` of every entry of a 1-D array of numbers, vectorised: the first bad entry is refused
    as ``check_value`` refuses it, its index after the key (``design.m3[1] = -1.0: out of range, allowed ...``)."""
    bad = ~(np.isfinite(values) & in_range(f.metadata, values))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        check_value(f"{path}[{i}]", f, float(values[i]))
        raise AssertionError(f"{path}[{i}] = {values[i]!r}: refused by in_range, accepted by check_value")


def with_unit(path: str, value: Any, unit: str) -> tuple[Any, bool]:
    """``value`` as a number in ``unit`` when it is a string that spells one (``"7.71 g"``, or ``"1e-9"``,
    which YAML 1.1 reads as a string), and whether it was a plain number (no unit named)."""
    if not isinstance(value, str):
        return value, True
    try:
        number = quantities.parse(value, unit)
    except quantities.UnitError as exc:
        raise ConfigError(f"{path} = {shown(value)}: {exc}") from None
    if number is None:
        return value, True
    try:
        float(value)
        return number, True
    except ValueError:
        return number, False


def range_text(meta: Mapping[str, Any]) -> str:
    lo, hi, unit = meta["lo"], meta["hi"], meta["unit"]
    left = "(" if meta["lo_open"] else "["
    u = f" {unit}" if unit and unit != "-" else ""
    return f"{left}{lo}, {hi}]{u}"


def did_you_mean(name: Any, candidates, prefix: str = "") -> str:
    """"; did you mean PREFIXkey?" naming the candidate closest to ``name`` (difflib; case ignored), or ""."""
    by_lower: dict[str, str] = {}
    for c in candidates:
        by_lower.setdefault(str(c).lower(), str(c))
    text = str(name).lower()
    if text in by_lower:
        return f"; did you mean {prefix}{by_lower[text]}?"
    close = difflib.get_close_matches(text, list(by_lower), n=1, cutoff=0.6)
    return f"; did you mean {prefix}{by_lower[close[0]]}?" if close else ""


def unknown_key(where: str, name: Any, known, prefix: str = "") -> ConfigError:
    """An unknown key: the closest known one, else the keys themselves when few, else where to find them."""
    known = sorted(map(str, known))
    hint = did_you_mean(name, known, prefix)
    if not hint:
        hint = (f"; allowed keys are {known}" if len(known) <= 8 else
                f"; none is close among its {len(known)} keys (aero-env schema lists them)")
    return ConfigError(f"{where}: unknown key{hint}")


def build_section(cls, data: Any, path: str):
    if data is None:
        data = {}
    if not isinstance(data, Mapping):
        raise ConfigError(f"{path}: must be a mapping of keys to values, got {shown(data)}")
    known = {f.name: f for f in fields(cls)}
    unknown = sorted(map(str, set(data) - set(known)))
    derived = getattr(cls, "DERIVED", {})
    for name in unknown:
        if name in derived:
            raise ConfigError(f"{path}.{name}: derived, not set: {derived[name]}")
    if unknown:
        raise unknown_key(f"{path}.{unknown[0]}", unknown[0], known, f"{path}.")
    kwargs = {}
    for name, f in known.items():
        if name not in data:
            continue
        sub = f.default_factory if f.default_factory is not dataclasses.MISSING else None
        if sub is not None and dataclasses.is_dataclass(sub):
            kwargs[name] = build_section(sub, data[name], f"{path}.{name}")
        else:
            kwargs[name] = check_value(f"{path}.{name}", f, data[name])
    return cls(**kwargs)
