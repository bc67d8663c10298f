"""Values with units in configs and ``--set``: ``7.71g``, ``"48.3 mm"``, ``"0.877 N*mm/rad"``, ``"55 deg"``.

A config value may be a plain number, read in the key's own unit (SI, or degrees where the key
ends in ``_deg``), or a number followed by a unit of the same kind, converted to that unit:
``design.m2: 7.71 g`` is 0.00771 kg. A unit of another kind (``design.m2: 7.7 mm``) is an error
naming the key and the units it takes.

Why a small table and not pint: every key already declares its one unit (``spec(..., unit)`` in
:mod:`aero_env.config`), so the only question a value can raise is "which spellings of this kind
of unit, at what factor" — about thirty rows, all below. pint would answer it too, but would add
a dependency (and its registry's import to every ``aero-env`` start and every worker process),
would accept spellings nobody means on a card toy (``7.7 oz``, ``3 furlong``) and still could not
say which unit is the *usual smaller one* a maker slips into (grams for kilograms, N·mm/rad for
N·m/rad), which is what the "did you mean 7.7 g?" hint needs (:func:`smaller_unit_hint`).
"""

from __future__ import annotations

import math
import re
from decimal import Decimal

# For each SI unit a key can declare: the spellings accepted and their factor to that unit. The
# first spelling is the canonical one; spellings are matched after removing spaces and writing
# "·", "⋅", "×" as "*" and "²", "³" as "^2", "^3".
UNITS: dict[str, dict[str, float]] = {
    "m": {"m": 1.0, "cm": 1e-2, "mm": 1e-3},
    "kg": {"kg": 1.0, "g": 1e-3, "mg": 1e-6},
    "N·m": {"N*m": 1.0, "Nm": 1.0, "N*mm": 1e-3, "Nmm": 1e-3, "mN*m": 1e-3, "mNm": 1e-3},
    "N·m/rad": {"N*m/rad": 1.0, "Nm/rad": 1.0, "N*mm/rad": 1e-3, "Nmm/rad": 1e-3, "mN*m/rad": 1e-3,
                "mNm/rad": 1e-3},
    "deg": {"deg": 1.0, "°": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / math.pi},
    "s": {"s": 1.0, "ms": 1e-3},
    "m/s": {"m/s": 1.0, "cm/s": 1e-2, "mm/s": 1e-3},
    "kg/m^3": {"kg/m^3": 1.0, "kg/m3": 1.0, "g/cm^3": 1e3, "g/cm3": 1e3, "g/l": 1.0, "g/L": 1.0},
    "px": {"px": 1.0},
}

# The unit a maker writes by habit where the key's unit is far too big: a plain number out of
# range that fits the key's range read in this unit gets "did you mean ...?".
SMALLER: dict[str, str] = {"m": "mm", "kg": "g", "N·m": "N*mm", "N·m/rad": "N*mm/rad", "s": "ms", "m/s": "mm/s"}

_NUMBER_UNIT = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")
_SPELLING = str.maketrans({"·": "*", "⋅": "*", "×": "*", "²": "^2", "³": "^3", " ": ""})


class UnitError(ValueError):
    """A value's unit is unknown or of another kind than the key's (the message says which units it takes)."""


def units_for(unit: str) -> tuple[str, ...]:
    """The spellings a key of ``unit`` accepts (empty for dimensionless keys)."""
    return tuple(UNITS.get(unit, {}))


def parse(value: str, unit: str) -> float | None:
    """``value`` (a string) read as a number in ``unit``: ``"7.71 g"`` with unit ``kg`` is 0.00771.

    A bare number (``"8e-4"``, ``"nan"``) is read as one. Returns None when ``value`` does not
    start with a number (the caller says "must be a number"); raises :class:`UnitError` when it
    names a unit that is not a spelling of ``unit``.
    """
    text = value.strip()
    try:
        return float(text)
    except ValueError:
        pass
    m = _NUMBER_UNIT.match(text)
    if m is None:
        return None
    number, spelled = m.group(1), m.group(2)
    key = spelled.translate(_SPELLING)
    table = UNITS.get(unit, {})
    factor = table.get(key)
    if factor is None:
        if not table:
            raise UnitError(f"unit {spelled!r} given, but the key has no unit: write a plain number")
        raise UnitError(f"unit {spelled!r} is not one this key takes: {', '.join(table)} (a plain number is {unit})")
    return to_si(number, factor)


def to_si(number: float | str, factor: float) -> float:
    """``number`` times ``factor``, a power of ten applied in decimal so that 48.3 mm is 0.0483 m to the
    last bit (48.3 * 1e-3 and 48.3 / 1000 are both 0.048299999999999996)."""
    exp = round(math.log10(factor))
    if factor == 10.0 ** exp:
        try:
            return float(Decimal(str(number)) * Decimal(10) ** exp)
        except ArithmeticError:  # beyond Decimal's exponent range: the float product says inf or 0 as well
            pass
    return float(number) * factor


def smaller_unit_hint(value: float, unit: str, fits) -> str:
    """" did you mean 7.7 g?" when ``value`` (a plain number, out of range) read in the usual smaller
    unit than ``unit`` passes ``fits`` (the key's range check); else ""."""
    small = SMALLER.get(unit)
    if small is None or not math.isfinite(value):
        return ""
    si = to_si(repr(value), UNITS[unit][small])
    if not fits(si):
        return ""
    return f"; did you mean {value:g} {small}? (a plain number is {unit}; write {value:g}{small} or {si:g})"


def in_maker_units(value: float, unit: str) -> tuple[float, str]:
    """``value`` (in ``unit``, SI) in the usual smaller unit a maker reads (mm, g, N·mm/rad), for tables."""
    smaller = SMALLER.get(unit)
    if smaller is None:
        return value, "" if unit == "-" else unit
    return value / UNITS[unit][smaller], smaller.replace("*", "·")
