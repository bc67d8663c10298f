"""Values in range but orders of magnitude from anything that can swing: a likely unit slip, warned of, not refused.

The allowed ranges are wide on purpose (a deliberate experiment may go far from the prototype), so a value
given in the wrong unit can pass them: ``design.m3=7.2e-3g`` (7.2 mg, for 7.2 g) runs and reports
``no_detach``; ``design.rest_angle_deg=0.96`` (55 deg given in radians) reports ``fell_short``. Such a value
gets one :class:`UnitSlipWarning`, one line naming the key, the value and the likely slip, and runs as given.

It is checked where a config is loaded or overridden (:func:`aero_env.config.load_config`, the environments'
overrides), never per episode or per trial: the runs' own ``with_values``/``replace`` calls are not checked.
``warnings.filterwarnings("ignore", category=UnitSlipWarning)`` silences it; ``"error"`` turns it into a
refusal. (Python's ``-W`` option cannot name it: it reads its categories before the package can be imported.)
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any, Mapping

from .. import quantities
from .sections import real_field
from .validation import ConfigError, in_range


class UnitSlipWarning(UserWarning):
    """A config value lies orders of magnitude from anything that can swing: probably a unit slip. It runs as given."""


UnitSlipWarning.__module__ = "aero_env.config"


@dataclass(frozen=True)
class Band:
    """The values of one kind of quantity that a card toy that swings can have: within ``factor`` times the
    prototype's value (the key's default, configs/paper.yaml's) either way."""

    factor: float
    noun: str  # what a value of this kind is, for the message


# How far a value of each kind may sit from the prototype's before it reads as a unit slip, by the unit the key
# declares; keys of other kinds (friction coefficients, air density, the sim's settings) are not checked. Where
# each band comes from:
# * masses (kg): every stored scene and solution moves a mass by at most 2.7x (configs/scenes: m1 x0.375, m3 up to
#   x1.6) and the tuner searches m3 over 0.5-1.6 x m2: the counterbalance must nearly balance the robot, and a
#   mass 30x off the prototype's swings nothing the paper built. A slip of g for kg (or mg for g) is 1000x.
# * lengths (m): the stored scenes move a length by at most 1.7x (small_frames: La x0.6; the solutions' h by 3.7x
#   and the scenes' rise by 5x, both signed and not checked, see below); a 30x longer or shorter frame is another
#   machine than a card toy. A slip of mm for m is 1000x, of cm for m 100x.
# * torques (N·m/rad, N·m): the tuner searches spring_k over 0.22-4.5x the prototype's and the stored solutions
#   move it by at most 2x; the friction torques were fitted to the paper's figures (docs/physics.md). A slip of
#   N·mm for N·m is 1000x.
# Any band from about 10x to 100x separates both: the stored values sit within 3x and a slip is 100x or more
# (tests/test_config_slips.py loads every config in configs/ and configs/scenes/ and sees no warning).
# "Did you mean" names the value moved by the slip's factor (1000 for g and kg) only where that lands within
# SUGGEST_WITHIN times the prototype's, where the stored scenes lie: farther, the guess would be a guess.
PLAUSIBLE_BANDS: dict[str, Band] = {
    "kg": Band(30.0, "mass"),
    "m": Band(30.0, "length"),
    "N·m/rad": Band(30.0, "spring stiffness"),
    "N·m": Band(30.0, "torque"),
}
SUGGEST_WITHIN = 5.0
# Angles (keys in degrees, "_deg"): a plain number whose size is below RADIANS_BELOW reads as radians (pi written
# as 3.14 or 3.1416 included), where the prototype's angle is at least RADIANS_PROTOTYPE_ABOVE, which every _deg
# key's is (55 deg and more): a few degrees is none of their working values, and the same number in radians is.
# A value written with its unit ("0.96 rad", "2 deg") says what was meant and is not checked.
RADIANS_BELOW = 3.2
RADIANS_PROTOTYPE_ABOVE = 10.0
# Not checked: a key whose range is signed (design.h, design.dT, scene.rise) is an offset about zero, where any
# small value is a design, not a slip; and 0, which switches a part off (design.pivot_friction, design.coin_mass).


def unit_slips(given: Mapping[str, Any]) -> list[str]:
    """The one-line warnings for the values ``given`` (dotted key -> the value as written, a number or a string
    with its unit; keys other than real-valued ``design.*``/``scene.*`` fields are skipped), each already accepted
    by its key's range."""
    out = []
    for key, raw in given.items():
        try:
            f = real_field(key, "key")
        except ConfigError:
            continue
        meta = f.metadata
        value, plain = _number(raw, meta["unit"])
        if value is None or value == 0.0 or not math.isfinite(value):
            continue
        if meta["lo"] is not None and meta["lo"] < 0 and meta["unit"] != "deg":
            continue  # a signed offset: no scale to be far from
        message = _slip(key, value, plain, f.default, meta)
        if message:
            out.append(message)
    return out


def warn_unit_slips(given: Mapping[str, Any]) -> None:
    """One :class:`UnitSlipWarning` per value in :func:`unit_slips`, each printed as one line."""
    for message in unit_slips(given):
        _warn(message)


def _number(raw: Any, unit: str) -> tuple[float | None, bool]:
    """``raw`` in the key's unit and whether it was a plain number (no unit written); None if it is no number."""
    if isinstance(raw, bool):
        return None, True
    if isinstance(raw, (int, float)):
        return float(raw), True
    if isinstance(raw, str):
        try:
            return float(raw), True
        except ValueError:
            pass
        try:
            return quantities.parse(raw, unit), False
        except quantities.UnitError:
            return None, False
    return None, True


def _slip(key: str, value: float, plain: bool, prototype: float, meta: Mapping[str, Any]) -> str:
    unit = meta["unit"]
    if unit == "deg":
        return _radians_slip(key, value, prototype, meta) if plain else ""
    band = PLAUSIBLE_BANDS.get(unit)
    if band is None or not prototype:
        return ""
    ratio = abs(value / prototype)
    if 1.0 / band.factor <= ratio <= band.factor:
        return ""
    shown, small = quantities.in_maker_units(value, unit), quantities.in_maker_units(prototype, unit)
    side = "below" if ratio < 1 else "above"
    times = _round2(1 / ratio if ratio < 1 else ratio)
    hint = _meant(value, prototype, unit, meta)
    return (f"{key} = {value!r} {unit} ({shown[0]:g} {shown[1]}): about {times:g}x {side} the prototype's "
            f"{small[0]:g} {small[1]}, beyond the {band.factor:g}x either way of any {band.noun} that can swing "
            f"(run as given){hint}")


def _meant(value: float, prototype: float, unit: str, meta: Mapping[str, Any]) -> str:
    """"; did you mean 7.2 g?": the value moved by the factor between two spellings of its unit (1000 for g and
    kg) that brings it nearest the prototype's, if that is within SUGGEST_WITHIN of it and in the key's range;
    else ""."""
    spellings = quantities.UNITS[unit].values()
    factors = {10.0 ** round(math.log10(a / b)) for a in spellings for b in spellings if a > b}
    best = None
    for factor in factors:
        moved = quantities.to_si(repr(value), factor) if abs(value) < abs(prototype) else value / factor
        ratio = abs(moved / prototype)
        if 1.0 / SUGGEST_WITHIN <= ratio <= SUGGEST_WITHIN and in_range(meta, moved):
            if best is None or abs(math.log(ratio)) < abs(math.log(abs(best / prototype))):
                best = moved
    if best is None:
        return ""
    shown = quantities.in_maker_units(best, unit)
    return f"; did you mean {shown[0]:.6g} {shown[1]}?"


def _radians_slip(key: str, value: float, prototype: float, meta: Mapping[str, Any]) -> str:
    if abs(value) >= RADIANS_BELOW or abs(prototype) < RADIANS_PROTOTYPE_ABOVE:
        return ""
    degrees = math.degrees(value)
    meant = f": did you mean {value:g}rad (or {degrees:.3g})?" if in_range(meta, degrees) else ""
    return (f"{key} = {value:g}: an angle in degrees (the prototype's is {prototype:g} deg), run as given; "
            f"{value:g} rad is {degrees:.3g} deg{meant}")


def _round2(x: float) -> float:
    """``x`` to two significant digits (1000 for 999.99, 36 for 36.4)."""
    return float(f"{x:.2g}")


def _warn(message: str) -> None:
    """Warn with :class:`UnitSlipWarning`, shown as one line (``aero-env: warning: ...``) where Python's default
    format would add the file, line and source of this call. The one-line format is in place only while this
    warning is shown, so other warnings keep theirs; filters (ignore, error, once) apply as to any warning."""
    previous = warnings.formatwarning

    def one_line(msg, category, filename, lineno, line=None):
        if isinstance(category, type) and issubclass(category, UnitSlipWarning):
            return f"aero-env: warning: {msg}\n"
        return previous(msg, category, filename, lineno, line)

    warnings.formatwarning = one_line
    try:
        warnings.warn(message, UnitSlipWarning, stacklevel=2)
    finally:
        warnings.formatwarning = previous
