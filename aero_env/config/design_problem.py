"""The design problem's list sections: ``tunable``, ``context`` and ``tolerance``.

Their entry types, the default design problem, and the checks that build each entry.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field, fields
from typing import Any, Mapping

from .sections import real_field
from .validation import ConfigError, check_value, shown, unknown_key, with_unit


def _item(doc: str, unit: str = "-", default: Any = None):
    return field(default=default, metadata=dict(unit=unit, doc=doc, lo=None, hi=None, lo_open=False, choices=None))


@dataclass(frozen=True)
class Tunable:
    """One action dimension: a design or scene number and the range the action maps onto."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. design.m3")
    low: float = _item("value at action -1 (with relative_to: a multiple of that field's value)", "field's")
    high: float = _item("value at action +1, above low (with relative_to: a multiple)", "field's")
    scale: str = _item("linear, or log (geometric; low > 0)", default="linear")
    linked: tuple = _item("keys scaled by the same factor as this one, keeping their ratio to it "
                          "(design.mu_k with design.mu_s keeps the friction pair's ratio)", default=())
    relative_to: str | None = _item("a dotted key: low and high are then multiples of that field's value in the "
                                    "config, so the range follows the scene (absent: low and high are in the "
                                    "field's own unit)", default=None)
    step: float | None = _item("a maker's resolution: the value snaps to the nearest multiple of step inside [low, "
                               "high] (design.m3: 0.1 g, what a kitchen scale reads, so whole coins plus clay); "
                               "absent: continuous", "field's", default=None)
    choices: tuple = _item("the values a maker can choose from, each a list: this field's value, then each linked "
                           "key's (design.mu_s with linked [design.mu_k]: the measured card pairs of Table 3, "
                           "[[0.507, 0.337], [0.542, 0.409], [0.283, 0.149]]); the action's [-1, 1] is cut into "
                           "equal bins, one per choice, in the order listed; low and high may then be left out",
                           default=())


@dataclass(frozen=True)
class ContextRange:
    """One observed scene number, drawn uniformly from [low, high] at reset (fixed when both are absent)."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. scene.rise")
    low: float | None = _item("lowest value drawn (absent: the config's value)", "field's")
    high: float | None = _item("highest value drawn (absent: the config's value)", "field's")
    linked: tuple = _item("keys scaled by the same factor as this one, keeping their ratio to it "
                          "(design.mu_k with a drawn design.mu_s: the card is drawn, not one coefficient)",
                          default=())


@dataclass(frozen=True)
class Tolerance:
    """Manufacturing error on one number: value·(1 + relative·u) + absolute·u, u ~ U(-1, 1) at reset."""

    name: str = _item("dotted key of a real-valued design or scene field, e.g. design.m3")
    relative: float = _item("± fraction of the value, in [0, 0.5]", default=0.0)
    absolute: float = _item("± in the field's unit, >= 0", "field's", default=0.0)


# Shinohara & Nishibori 2026, Table 3: JIS K7125 friction (mu_s, mu_k) of the 0.4 mm, 310 g/m² card (a white
# coated face and a gray uncoated back). The arm is card too: which faces touch is the maker's choice. Least
# friction first, so that neighbouring bins of the default action are neighbouring frictions. The sheet names
# a design's pair from this table.
CARD_PAIRS = (
    ("gray arm on gray handrail", 0.283, 0.149),
    ("white arm on white handrail", 0.507, 0.337),
    ("white arm on gray handrail (the paper's prototype)", 0.542, 0.409),
)
TABLE3_CARD_PAIRS = tuple((mu_s, mu_k) for _name, mu_s, mu_k in CARD_PAIRS)

# The default design problem: the frame's counterbalance (m3, h, La), the leaf spring, and the
# card pair of the hook. Each is a maker's choice: m3 in the 0.1 g a kitchen scale reads (whole
# coins plus clay), the card pair one of Table 3's measured pairs (a config may list a pair its
# maker measured), the lengths printed 1:1 on the template, the spring a strip the kit plans no
# narrower than scissors cut. The robot's mass, the row's rise and pitch are what the designer is
# given. The ranges follow the scene: the counterbalance's mass scales with the robot it
# balances, its place with the frame's arm La, and the spring with its own value, so a smaller
# toy (``--set design.La=0.029``) is searched around its own size. On the prototype they span
# 3.9-12.3 g, -9.7-19.3 mm, 36-65 mm and 0.19-3.9 N·mm/rad, and the prototype lies inside every
# range. The card pair is a property of the card, not of the toy's size, so it is absolute.
DEFAULT_TUNABLES = (
    Tunable("design.m3", 0.5, 1.6, relative_to="design.m2", step=1e-4),
    Tunable("design.h", -0.2, 0.4, relative_to="design.La"),
    Tunable("design.La", 0.75, 1.35, relative_to="design.La"),
    Tunable("design.spring_k", 0.22, 4.5, "log", relative_to="design.spring_k"),
    Tunable("design.mu_s", 0.283, 0.542, linked=("design.mu_k",), choices=TABLE3_CARD_PAIRS),
)
DEFAULT_CONTEXT = (ContextRange("scene.rise"), ContextRange("scene.pitch"), ContextRange("design.m2"))


LIST_SECTIONS = {"tunable": Tunable, "context": ContextRange, "tolerance": Tolerance}


def build_list(section: str, data: Any) -> tuple:
    """Validate one list section (tunable, context or tolerance) entry by entry."""
    cls = LIST_SECTIONS[section]
    if not isinstance(data, (list, tuple)):
        raise ConfigError(f"{section}: must be a list of mappings with keys {[f.name for f in fields(cls)]}, "
                          f"got {shown(data)}")
    items, seen = [], set()
    for i, entry in enumerate(data):
        where = f"{section}[{i}]"
        if not isinstance(entry, Mapping):
            raise ConfigError(f"{where}: must be a mapping with keys {[f.name for f in fields(cls)]}, "
                              f"got {shown(entry)}")
        allowed = {f.name for f in fields(cls)}
        extra = sorted(map(str, set(entry) - allowed))
        if extra:
            raise unknown_key(f"{where}.{extra[0]}", extra[0], allowed)
        if "name" not in entry:
            raise ConfigError(f"{where}.name: missing; the dotted key of the field, e.g. design.m3")
        f = real_field(entry["name"], f"{where}.name")
        name = str(entry["name"])
        if name in seen:
            raise ConfigError(f"{where}.name = {name!r}: listed twice in {section}")
        seen.add(name)
        items.append(_ITEM_BUILDERS[section](entry, where, name, f))
    return tuple(items)


def _bound(entry: Mapping, key: str, where: str, name: str, f: dataclasses.Field) -> float:
    """``entry[key]`` checked against the range of the field it sets."""
    return check_value(f"{where}.{key} (a value of {name})", f, entry[key])


def _tunable(entry, where, name, f) -> Tunable:
    if entry.get("choices"):  # an empty list (a config written back without choices) is none
        return _chosen(entry, where, name, f)
    for key in ("low", "high"):
        if key not in entry:
            raise ConfigError(f"{where}.{key}: missing; the value of {name} at action {'-1' if key == 'low' else '+1'}")
    relative_to = entry.get("relative_to")
    if relative_to is not None:
        real_field(relative_to, f"{where}.relative_to")
        low, high = (_factor(entry[key], f"{where}.{key}", relative_to) for key in ("low", "high"))
    else:
        low, high = _bound(entry, "low", where, name, f), _bound(entry, "high", where, name, f)
    if not low < high:
        if relative_to is not None:
            raise ConfigError(f"{where}.high = {high!r}: must exceed {where}.low = {low!r} (both multiples of "
                              f"{relative_to}'s value)")
        raise ConfigError(f"{where}.high = {high!r}: must exceed {where}.low = {low!r}, allowed ({low}, "
                          f"{f.metadata['hi']}]")
    scale = entry.get("scale", "linear")
    if scale not in ("linear", "log"):
        raise ConfigError(f"{where}.scale = {shown(scale)}: must be one of ['linear', 'log']")
    if scale == "log" and low <= 0:
        raise ConfigError(f"{where}.low = {low!r}: a log scale needs low > 0, allowed (0, {high})")
    step = _step(entry, where, name, f, low, high, relative_to)
    return Tunable(name, low, high, scale, linked_keys(entry.get("linked"), where, name),
                   None if relative_to is None else str(relative_to), step)


def _step(entry, where, name, f, low, high, relative_to) -> float | None:
    """A tunable's ``step``, in its field's unit, with at least one multiple of it inside an absolute range."""
    if entry.get("step") is None:
        return None
    step, _ = with_unit(f"{where}.step (a step of {name})", entry["step"], f.metadata["unit"])
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not math.isfinite(step) or not step > 0:
        raise ConfigError(f"{where}.step = {shown(step)}: must be a finite number > 0 in {name}'s unit "
                          f"({f.metadata['unit']}), e.g. 0.1 g")
    if relative_to is None and math.ceil(low / step - 1e-9) * step > high * (1 + 1e-12):
        raise ConfigError(f"{where}.step = {shown(step)}: no multiple of it lies in [{low}, {high}]; allowed (0, "
                          f"{high - low}]")
    return float(step)


def _chosen(entry, where, name, f) -> Tunable:
    """A tunable whose values are a list of a maker's choices (a card pair: mu_s with its mu_k)."""
    for key in ("relative_to", "step", "scale"):
        if entry.get(key) not in (None, "linear" if key == "scale" else None):
            raise ConfigError(f"{where}.{key}: not allowed with choices (each choice is a value, not a range)")
    linked = linked_keys(entry.get("linked"), where, name)
    rows = entry["choices"]
    if isinstance(rows, (str, bytes)) or not isinstance(rows, (list, tuple)) or len(rows) < 2:
        raise ConfigError(f"{where}.choices = {shown(rows)}: must be a list of at least 2 choices, each a list of "
                          f"{1 + len(linked)} numbers ({', '.join((name, *linked))})")
    keys = (name, *linked)
    out = []
    for j, row in enumerate(rows):
        if not isinstance(row, (list, tuple)) or len(row) != len(keys):
            raise ConfigError(f"{where}.choices[{j}] = {shown(row)}: must be a list of {len(keys)} numbers, the "
                              f"values of {', '.join(keys)}")
        out.append(tuple(check_value(f"{where}.choices[{j}][{k}] (a value of {key})", real_field(key, where), v)
                         for k, (key, v) in enumerate(zip(keys, row))))
    leaders = [row[0] for row in out]
    if len(set(leaders)) != len(leaders):
        raise ConfigError(f"{where}.choices: two choices give {name} the same value; each must differ in it")
    low, high = min(leaders), max(leaders)
    for key in ("low", "high"):
        if entry.get(key) is not None and _bound(entry, key, where, name, f) != (low if key == "low" else high):
            raise ConfigError(f"{where}.{key} = {shown(entry[key])}: with choices it is the choices' "
                              f"{'least' if key == 'low' else 'greatest'} {name}, {low if key == 'low' else high!r} "
                              f"(or leave it out)")
    return Tunable(name, low, high, "linear", linked, None, None, tuple(out))


def linked_keys(linked: Any, where: str, name: str) -> tuple[str, ...]:
    """An entry's ``linked`` keys (a tunable's, a context's, a tolerance's): real fields other than its own; absent
    (None) is none."""
    if linked is None:
        return ()
    if isinstance(linked, str) or not isinstance(linked, (list, tuple)):
        raise ConfigError(f"{where}.linked = {shown(linked)}: must be a list of dotted keys, e.g. [design.mu_k]")
    for j, key in enumerate(linked):
        real_field(key, f"{where}.linked[{j}]")
        if key == name:
            raise ConfigError(f"{where}.linked[{j}] = {key!r}: a field cannot be linked to itself")
    return tuple(str(k) for k in linked)


def _factor(value: Any, where: str, relative_to: str) -> float:
    """A bound of a relative range: a plain finite number, a multiple of ``relative_to``'s value."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"{where} = {shown(value)}: with relative_to {relative_to}, low and high are plain numbers "
                          f"(multiples of {relative_to}'s value in the config, e.g. 0.75 and 1.35), not quantities")
    return float(value)


def _context(entry, where, name, f) -> ContextRange:
    has_low, has_high = entry.get("low") is not None, entry.get("high") is not None
    if has_low != has_high:
        raise ConfigError(f"{where}: give both low and high (drawn uniformly at reset), or neither (fixed)")
    linked = linked_keys(entry.get("linked"), where, name)
    if not has_low:
        return ContextRange(name, linked=linked)
    low, high = _bound(entry, "low", where, name, f), _bound(entry, "high", where, name, f)
    if low > high:
        raise ConfigError(f"{where}.high = {high!r}: must be at least {where}.low = {low!r}")
    return ContextRange(name, low, high, linked)


def _tolerance(entry, where, name, f) -> Tolerance:
    out = {}
    unit = f.metadata["unit"]
    for key, hi, u in (("relative", 0.5, "-"), ("absolute", math.inf, unit)):
        v, _ = with_unit(f"{where}.{key} (a tolerance of {name})", entry.get(key, 0.0), u)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0.0 <= v <= hi) or not math.isfinite(v):
            in_unit = f" {u}" if u != "-" else ""
            raise ConfigError(f"{where}.{key} = {shown(v)}: must be a finite number in [0, {hi}]{in_unit}")
        out[key] = float(v)
    return Tolerance(name, **out)


_ITEM_BUILDERS = {"tunable": _tunable, "context": _context, "tolerance": _tolerance}
