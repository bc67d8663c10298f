"""The tolerances of a hand-made toy: the default table, a file that replaces it, and how a
tolerance turns a draw into a built value.

A tolerance moves one real-valued ``design.*`` or ``scene.*`` field by

    built = value·(1 + relative·u) + absolute·u,      u ~ U(-1, 1)

(the formula of the config's ``tolerance`` section, :mod:`aero_env.design_space`). Its ``linked``
fields follow it by the same factor ``built / value``, so ``design.mu_k`` keeps its ratio to
``design.mu_s`` and ``mu_k <= mu_s`` holds in every build.

The default table (:data:`DEFAULT_TOLERANCES`) is what a maker with a ruler, scissors, a kitchen
scale and card gets; each entry carries its reason. Lengths are the ones a maker cuts or marks:

* cut or marked (±0.5 mm): ``La``, ``Lb``, ``h`` (where the counterbalance sits on the frame),
  ``arm_length`` and ``Ld`` (card strips: the torso's length follows from ``Ld``, and the coins,
  glued flush with its end, move with it), ``notch_back_face`` and ``notch_front_face`` (the
  handrail notch's cut faces), and the row's skewer holes in the crossbeams: ``scene.pitch`` and
  ``scene.rise``.
* left out: ``Lc`` (the paper's two-link arm; the built arm is ``arm_length``),
  ``handrail_thickness`` and ``hook_radius`` (the card's thickness, set by the mill),
  ``coin_radius`` (minted), the drag widths (drag is off by default and its widths are
  projections, not cuts) and ``scene.floor_drop`` (the table the row stands on).

A file given with ``--tolerances`` replaces the table. It is a YAML list of entries
``{name, relative | absolute, [linked: [keys]], [reason]}`` (both ``relative`` and ``absolute``
may be given, as in the config's ``tolerance`` section), or a mapping whose one key
``tolerance`` holds that list. A bad entry raises :class:`~aero_env.config.ConfigError` with one
line naming the file, the entry, the field, the value and the allowed range.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Mapping


from ..config import Config, ConfigError, linked_keys, read_yaml, real_field

MAX_RELATIVE = 0.5  # the config's tolerance section allows ± up to half the value
LENGTH_MM = 0.0005  # m: a ruler and a craft knife on card
MASS_FRACTION = 0.03  # a kitchen scale and glue: a few percent
SPRING_FRACTION = 0.15  # a paper leaf spring's stiffness varies with the card's grain and the fold
FRICTION_FRACTION = 0.10  # the card pair's friction varies sheet to sheet and with handling
ANGLE_DEG = 2.0  # the stopper skewer's hole, placed by hand


@dataclass(frozen=True)
class Tol:
    """One tolerance: a field, its ± relative and absolute error, the fields that follow it, and why."""

    name: str
    relative: float = 0.0
    absolute: float = 0.0
    linked: tuple[str, ...] = ()
    reason: str = ""

    @property
    def zero(self) -> bool:
        """Whether the tolerance moves nothing (every draw builds the nominal value)."""
        return self.relative == 0.0 and self.absolute == 0.0

    def to_json(self) -> dict:
        d = asdict(self)
        d["linked"] = list(self.linked)
        return d


def _length(name: str, reason: str) -> Tol:
    return Tol(name, absolute=LENGTH_MM, reason=reason)


def _mass(name: str, reason: str) -> Tol:
    return Tol(name, relative=MASS_FRACTION, reason=reason)


DEFAULT_TOLERANCES: tuple[Tol, ...] = (
    _length("design.La", "the counterbalance's arm of the frame, cut with a knife along a ruler"),
    _length("design.Lb", "the handrail's arm of the frame, cut with a knife along a ruler"),
    _length("design.h", "the counterbalance's offset from the frame line, marked and glued by hand"),
    _length("design.arm_length", "the arm strip, axle hole to hook tip, cut by hand"),
    _length("design.Ld", "the torso strip below the axle, cut by hand (its bottom is Ld from the hook; the coins, "
            "glued flush with its end, move with it)"),
    _length("design.notch_back_face", "the handrail notch's back face, cut by hand"),
    _length("design.notch_front_face", "the handrail notch's front face, cut by hand"),
    _length("scene.pitch", "the distance between skewer holes in the crossbeams, marked by hand"),
    _length("scene.rise", "the height step between skewer holes along the tilted crossbeams, marked by hand"),
    _mass("design.m1", "the frame's card: sheet weight varies and the glue adds a little"),
    _mass("design.m2", "the robot: card, glue and coins weighed on a kitchen scale"),
    _mass("design.m3", "the counterbalance: clay or coins trimmed on a kitchen scale"),
    _mass("design.arm_mass", "the arm's card and glue"),
    Tol("design.spring_k", relative=SPRING_FRACTION,
        reason="a folded paper leaf spring: grain, fold and humidity change its stiffness"),
    Tol("design.mu_s", relative=FRICTION_FRACTION, linked=("design.mu_k",),
        reason="the card pair's friction varies sheet to sheet; mu_k follows by the same factor (mu_k <= mu_s)"),
    Tol("design.rest_angle_deg", absolute=ANGLE_DEG,
        reason="the rest angle is set by the stopper skewer's hole, placed by hand"),
)

_KEYS = ("name", "relative", "absolute", "linked", "reason")


def built_values(cfg: Config, tol: Tol, u: float) -> dict[str, float]:
    """The values ``tol`` builds for the factor ``u`` in [-1, 1]: its field and its linked fields."""
    value = float(cfg.value(tol.name))
    built = value * (1.0 + tol.relative * u) + tol.absolute * u
    out = {tol.name: built}
    if tol.linked:
        factor = built / value
        for key in tol.linked:
            out[key] = float(cfg.value(key)) * factor
    return out


def check_against(cfg: Config, tols: tuple[Tol, ...], where: str = "tolerances") -> None:
    """Raise ConfigError if a tolerance cannot be applied to ``cfg`` (a link needs a leader value > 0)."""
    for i, t in enumerate(tols):
        real_field(t.name, f"{where}[{i}].name")
        if t.linked and not cfg.value(t.name) > 0:
            raise ConfigError(f"{where}[{i}].linked: links follow {t.name} by built/value, and its value is "
                              f"{cfg.value(t.name)!r}; allowed only when that value is > 0")


def load_tolerances(path: str | Path) -> tuple[Tol, ...]:
    """Read and validate a tolerance file (see the module docstring); ConfigError on any problem."""
    return parse_tolerances(read_yaml(path, "tolerance file"), str(Path(path)))


def parse_tolerances(data: Any, where: str = "tolerances") -> tuple[Tol, ...]:
    """Validate a list of tolerance entries (or ``{tolerance: [...]}``) into :class:`Tol` objects."""
    if isinstance(data, Mapping) and set(data) == {"tolerance"}:
        data = data["tolerance"]
    if not isinstance(data, list) or not data:
        raise ConfigError(f"{where}: must be a non-empty list of {{name, relative | absolute, [linked], [reason]}} "
                          f"entries (or a mapping with one key 'tolerance' holding it), got {data!r}")
    tols = tuple(_entry(e, f"{where}[{i}]") for i, e in enumerate(data))
    _check_names(tols, where)
    return tols


def _entry(entry: Any, where: str) -> Tol:
    if not isinstance(entry, Mapping):
        raise ConfigError(f"{where}: must be a mapping with keys {list(_KEYS)}, got {entry!r}")
    extra = sorted(map(str, set(entry) - set(_KEYS)))
    if extra:
        raise ConfigError(f"{where}.{extra[0]}: unknown key; allowed keys are {list(_KEYS)}")
    if "name" not in entry:
        raise ConfigError(f"{where}.name: missing; the dotted key of the field, e.g. design.m3")
    name = str(entry["name"])
    real_field(entry["name"], f"{where}.name")
    if "relative" not in entry and "absolute" not in entry:
        raise ConfigError(f"{where} ({name}): give relative (± fraction of the value, in [0, {MAX_RELATIVE}]) "
                          f"or absolute (± in the field's unit, >= 0), or both")
    relative = _number(entry, "relative", where, MAX_RELATIVE)
    absolute = _number(entry, "absolute", where, math.inf)
    reason = entry.get("reason", "")
    if not isinstance(reason, str):
        raise ConfigError(f"{where}.reason = {reason!r}: must be a line of text")
    return Tol(name, relative, absolute, linked_keys(entry.get("linked"), where, name), reason)


def _number(entry: Mapping, key: str, where: str, hi: float) -> float:
    v = entry.get(key, 0.0)
    if isinstance(v, str):  # YAML 1.1 reads 5e-4 (no dot) as a string
        try:
            v = float(v)
        except ValueError:
            pass
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not 0.0 <= v <= hi:
        raise ConfigError(f"{where}.{key} = {v!r}: must be a finite number in [0, {hi}]")
    return float(v)


def _check_names(tols: tuple[Tol, ...], where: str) -> None:
    """Each field is varied by one entry only: its own, or as one entry's link."""
    owner: dict[str, str] = {}
    for i, t in enumerate(tols):
        for key, role in [(t.name, "name")] + [(k, f"linked[{j}]") for j, k in enumerate(t.linked)]:
            if key in owner:
                raise ConfigError(f"{where}[{i}].{role} = {key!r}: already varied by {owner[key]}; a field can be "
                                  f"varied by one entry only")
            owner[key] = f"{where}[{i}]"
