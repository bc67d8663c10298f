"""The :class:`Config` and how one is made: from a mapping, a YAML file or ``--set`` overrides.

Also the schema table (``aero-env schema``, docs/configuration.md) read from the declarations.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping

import yaml

from ..files import read_text
from .design_problem import (DEFAULT_CONTEXT, DEFAULT_TUNABLES, LIST_SECTIONS, ContextRange, Tolerance, Tunable,
                             build_list)
from .sections import (DEFAULT_FIDELITY, FIDELITY_PRESETS, REMOVED_FIDELITIES, SECTIONS, Design, EnvOptions, Scene,
                       Sim, check_design, check_sim, real_field)
from .plausible import warn_unit_slips
from .validation import ConfigError, build_section, check_value, did_you_mean, range_text, shown


@dataclass(frozen=True)
class Config:
    design: Design = field(default_factory=Design)
    scene: Scene = field(default_factory=Scene)
    sim: Sim = field(default_factory=Sim)
    tunable: tuple[Tunable, ...] = DEFAULT_TUNABLES
    context: tuple[ContextRange, ...] = DEFAULT_CONTEXT
    tolerance: tuple[Tolerance, ...] = ()
    env: EnvOptions = field(default_factory=EnvOptions)

    def tunable_range(self, t: Tunable) -> tuple[float, float]:
        """``t``'s ``(low, high)`` in its field's unit: as written, or times ``t.relative_to``'s value here.

        A relative range is checked here, when the design problem is posed (the environment, a tuner),
        not when the config is read: ``aero-env simulate`` ignores the tunables, so a scene scaled past
        where its relative ranges fit the fields' ranges still simulates."""
        if t.relative_to is None:
            return t.low, t.high
        i = self.tunable.index(t)
        low, high = self._relative_range(t, i)
        if t.step is not None and math.ceil(low / t.step - 1e-9) * t.step > high * (1 + 1e-12):
            raise ConfigError(f"tunable[{i}].step = {t.step!r}: no multiple of it lies in {t.name}'s range here, "
                              f"[{low:.6g}, {high:.6g}] ({t.low:g} to {t.high:g} x {t.relative_to}); allowed (0, "
                              f"{high - low:.6g}]")
        return low, high

    def _relative_range(self, t: Tunable, i: int) -> tuple[float, float]:
        """A relative tunable's range in its field's unit, each bound checked against the field's range."""
        base = float(self.value(t.relative_to))
        if not base > 0:
            raise ConfigError(f"tunable[{i}].relative_to = {t.relative_to!r}: its value in this config is {base!r}; a "
                              f"range relative to it needs a value > 0 (or give {t.name}'s low and high in its unit)")
        low, high = t.low * base, t.high * base
        f = real_field(t.name, f"tunable[{i}].name")
        for key, v in (("low", low), ("high", high)):
            check_value(f"tunable[{i}].{key} ({getattr(t, key):g} x {t.relative_to} = {v:.6g}, a value of {t.name})",
                         f, v)
        return low, high

    def to_dict(self) -> dict:
        """Plain dicts and lists (YAML-ready); ``from_dict(cfg.to_dict())`` gives ``cfg`` back.

        Sim fields equal to their fidelity preset's value are left out, so that the dict names the
        fidelity and only what departs from it: ``replace({"sim.fidelity": ...})`` on it moves the
        preset's fields with the fidelity."""
        out = _plain(dataclasses.asdict(self))
        preset = FIDELITY_PRESETS[self.sim.fidelity]
        for key, value in preset.items():
            if out["sim"][key] == value:
                del out["sim"][key]
        return out

    def to_yaml(self) -> str:
        """The whole config as YAML that :func:`load_config` reads back to an equal config."""
        return yaml.safe_dump(self.to_dict(), sort_keys=False)

    def value(self, key: str) -> Any:
        """A field by dotted key, e.g. ``cfg.value("design.m3")`` or ``cfg.value("scene.effects.drag")``."""
        node: Any = self
        for name in key.split("."):
            node = getattr(node, name)
        return node

    def with_values(self, values: Mapping[str, float]) -> "Config":
        """A new config with real-valued ``design.*``/``scene.*`` fields set, each checked against its
        range and the design's cross-checks (the fast path ``replace`` takes for numbers only)."""
        changes: dict[str, dict[str, float]] = {"design": {}, "scene": {}}
        for key, v in values.items():
            f = real_field(key, "key")
            sec, name = key.split(".", 1)
            changes[sec][name] = check_value(key, f, v)
        cfg = dataclasses.replace(self, design=dataclasses.replace(self.design, **changes["design"]),
                                  scene=dataclasses.replace(self.scene, **changes["scene"]))
        check_design(cfg.design)
        return cfg

    def replace(self, overrides: Mapping[str, Any]) -> "Config":
        """A new validated config with dotted-key overrides applied."""
        return from_dict(self.to_dict(), overrides)


def _plain(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    return x


def _set_dotted(tree: dict, key: str, value: Any) -> None:
    if key in LIST_SECTIONS:  # a list section is replaced whole
        tree[key] = value
        return
    parts = key.split(".")
    if len(parts) < 2 or parts[0] not in SECTIONS:
        hint = did_you_mean(key, [r[0] for r in schema_rows() if "[]" not in r[0]] + list(LIST_SECTIONS))
        raise ConfigError(f"override key {key!r}: must start with one of {sorted(SECTIONS)} (e.g. design.m2), "
                          f"or be one of {sorted(LIST_SECTIONS)}{hint}")
    node = tree
    for p in parts[:-1]:
        child = node.setdefault(p, {})
        if not isinstance(child, dict):
            raise ConfigError(f"override key {key!r}: {p!r} is a value, not a section")
        node = child
    node[parts[-1]] = value


def from_dict(data: Mapping[str, Any] | None, overrides: Mapping[str, Any] | None = None) -> Config:
    """Validate a plain mapping (as read from YAML) plus dotted overrides into a Config."""
    tree = _deep_copy(data or {})
    if not isinstance(tree, dict):
        raise ConfigError(f"config: must be a mapping with sections {sorted(SECTIONS)}, got {shown(data)}")
    for key, value in (overrides or {}).items():
        _set_dotted(tree, key, value)
    _apply_fidelity(tree, overrides or {})
    unknown = sorted(map(str, set(tree) - set(SECTIONS) - set(LIST_SECTIONS)))
    if unknown:
        hint = did_you_mean(unknown[0], SECTIONS | LIST_SECTIONS)
        raise ConfigError(f"{unknown[0]}: unknown section{hint}; allowed sections are "
                          f"{sorted(SECTIONS | LIST_SECTIONS)}")
    sections = {name: build_section(cls, tree.get(name), name) for name, cls in SECTIONS.items()}
    lists = {name: build_list(name, tree[name]) for name in LIST_SECTIONS if name in tree}
    cfg = Config(**sections, **lists)
    check_design(cfg.design)
    check_sim(cfg.sim)
    _check_design_problem(cfg)
    return cfg


def _apply_fidelity(tree: dict, overrides: Mapping[str, Any]) -> None:
    """Fill the sim fields the fidelity preset names, unless the config names them itself.

    An override of ``sim.fidelity`` chooses that preset's numbers over the file's: the file's
    preset fields are dropped unless the same overrides set them too. So
    ``--set sim.fidelity=reference`` on a file that lists ``sim.dt`` runs at the reference step,
    and ``--set sim.fidelity=mbd-fine --set sim.dt=0.0002`` runs mbd-fine at 0.2 ms.
    """
    sim = tree.get("sim")
    if sim is None:
        sim = tree["sim"] = {}
    if not isinstance(sim, dict):
        return  # build_section names the problem
    name = sim.get("fidelity", DEFAULT_FIDELITY)
    if isinstance(name, str) and name in REMOVED_FIDELITIES:
        raise ConfigError(f"sim.fidelity = {name!r}: {REMOVED_FIDELITIES[name]}; must be one of {list(FIDELITY_PRESETS)}")
    if not isinstance(name, str) or name not in FIDELITY_PRESETS:
        raise ConfigError(f"sim.fidelity = {name!r}: must be one of {list(FIDELITY_PRESETS)} (cheapest first)")
    preset = FIDELITY_PRESETS[name]
    if "sim.fidelity" in overrides:
        for key in preset:
            if f"sim.{key}" not in overrides:
                sim.pop(key, None)
    for key, value in preset.items():
        sim.setdefault(key, value)


def _check_design_problem(cfg: Config) -> None:
    """A field is either chosen (tunable) or given (context), and links only fields that are neither."""
    tuned = {t.name for t in cfg.tunable}
    for i, c in enumerate(cfg.context):
        if c.name in tuned:
            raise ConfigError(f"context[{i}].name = {c.name!r}: also tunable; the designer either chooses a value "
                              f"or is given it, not both")
    given = {c.name for c in cfg.context}
    # where each chosen or given field is named, in reading order (tunable before context): a conflict is reported
    # at the later of the two entries, the one that clashes with what came before (a context naming a field that a
    # tunable already links is the context's error, and the other way round)
    named = {t.name: (0, i, "tunable") for i, t in enumerate(cfg.tunable)}
    named.update({c.name: (1, i, "context") for i, c in enumerate(cfg.context)})
    leader: dict[str, str] = {}
    for rank, (section, entries) in enumerate((("tunable", cfg.tunable), ("context", cfg.context))):
        for i, t in enumerate(entries):
            for key in t.linked:
                if key in tuned or key in given:
                    other_rank, j, other = named[key]
                    if (other_rank, j) > (rank, i):
                        raise ConfigError(f"{other}[{j}].name = {key!r}: {section}[{i}] links it to {t.name}; a "
                                          f"field is chosen, given or linked, only one of them")
                    raise ConfigError(f"{section}[{i}].linked: {key!r} is itself tunable or context; it cannot also "
                                      f"follow {t.name}")
                if key in leader:
                    raise ConfigError(f"{section}[{i}].linked: {key!r} already follows {leader[key]}; a field can "
                                      f"follow one tunable or context only")
                leader[key] = t.name


def _deep_copy(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {k: _deep_copy(v) for k, v in x.items()}
    return x


class DuplicateKey(Exception):
    """A YAML mapping names one key twice (:class:`UniqueKeyLoader`); the reader turns it into a ConfigError
    naming the file or ``--set`` value. Not a ``yaml.YAMLError``, so that no "not YAML" fallback swallows it."""

    def __init__(self, key: Any, mapping: str, first: yaml.Mark, again: yaml.Mark):
        super().__init__(f"key {key!r} appears twice in {mapping!r}" if mapping else f"key {key!r} appears twice")
        self.key, self.mapping, self.first, self.again = key, mapping, first, again


class UniqueKeyLoader(yaml.SafeLoader):
    """``yaml.SafeLoader`` that refuses a mapping naming one key twice with :class:`DuplicateKey`: YAML requires
    keys to be unique, but PyYAML keeps the last value silently (``m3: 0.0072`` then ``m3: 0.009`` would run
    with 0.009). Keys brought in by a merge (``<<: *base``) may still be overridden, as YAML's merge intends."""

    def construct_document(self, node):
        self.mapping_names = _mapping_names(node)
        return super().construct_document(node)

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            first: dict[Any, yaml.Mark] = {}
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    seen = first.setdefault(key, key_node.start_mark)
                except TypeError:  # an unhashable key: SafeLoader's own error names it
                    continue
                if seen is not key_node.start_mark:
                    raise DuplicateKey(key, getattr(self, "mapping_names", {}).get(id(node), ""), seen,
                                       key_node.start_mark)
        return super().construct_mapping(node, deep=deep)


def _mapping_names(root: yaml.Node) -> dict[int, str]:
    """id(node) -> the dotted path of every mapping under ``root`` (``design``, ``scene.effects``, ``tunable[1]``;
    "" for the document's own), for the duplicate key's message."""
    names: dict[int, str] = {}
    stack: list[tuple[yaml.Node, str]] = [(root, "")]
    while stack:
        node, path = stack.pop()
        if id(node) in names:
            continue  # an alias of a node already named (or a recursive one)
        names[id(node)] = path
        if isinstance(node, yaml.MappingNode):
            for key_node, value_node in node.value:
                name = key_node.value if isinstance(key_node, yaml.ScalarNode) else "?"
                stack.append((value_node, f"{path}.{name}" if path else str(name)))
        elif isinstance(node, yaml.SequenceNode):
            stack.extend((item, f"{path}[{i}]") for i, item in enumerate(node.value))
    return names


# What a YAML document may hold, once every alias is expanded. The stored configs nest at most 5 mappings and
# sequences deep (the document, tunable, an entry, its choices, a choice) and hold at most 292 values (configs/);
# a 300-byte "billion laughs" alias bomb expands to gigabytes, and a document nested thousands deep overflows
# Python's stack, both before any check runs.
MAX_YAML_DEPTH = 32
MAX_YAML_NODES = 100_000


class YamlTooBig(Exception):
    """A YAML document nests too deep, its aliases expand it too far, or an alias holds itself
    (:func:`check_yaml_shape`); the reader turns it into a ConfigError naming the file or ``--set`` value."""

    def __init__(self, why: str, mark: yaml.Mark | None):
        super().__init__(why)
        self.why, self.mark = why, mark


def check_yaml_shape(text: str) -> None:
    """Raise :class:`YamlTooBig` where the document in ``text`` nests deeper than ``MAX_YAML_DEPTH`` or holds more
    than ``MAX_YAML_NODES`` nodes with its aliases expanded, or has an alias inside the node it names (a recursive
    structure). Read from the parser's events, which build nothing and recurse nowhere: the document is measured
    before PyYAML builds it (which recurses once per level) or anything copies or prints it (once per alias)."""
    anchored: dict[str, tuple[int, int]] = {}  # anchor -> (nodes, depth) of the node it names, aliases expanded
    stack: list[list] = []  # each open mapping or sequence: [anchor, its nodes so far, its depth so far]
    total = 0
    for event in yaml.parse(text, Loader=yaml.SafeLoader):
        if isinstance(event, yaml.CollectionStartEvent):
            total += 1
            stack.append([event.anchor, 1, 1])
            if len(stack) > MAX_YAML_DEPTH:
                raise YamlTooBig(f"nested more than {MAX_YAML_DEPTH} levels deep (a config nests 5)", event.start_mark)
            continue
        if isinstance(event, yaml.CollectionEndEvent):
            anchor, nodes, depth = stack.pop()
            if anchor is not None:
                anchored[anchor] = (nodes, depth)
        elif isinstance(event, yaml.ScalarEvent):
            nodes, depth = 1, 0  # depth: how many mappings and sequences nest in a node, itself included
            if event.anchor is not None:
                anchored[event.anchor] = (1, 0)
            total += 1
        elif isinstance(event, yaml.AliasEvent):
            if any(entry[0] == event.anchor for entry in stack):
                raise YamlTooBig(f"the alias *{event.anchor} lies inside the node &{event.anchor} names: a structure "
                                 f"that holds itself", event.start_mark)
            nodes, depth = anchored.get(event.anchor, (0, 0))  # an unknown anchor: PyYAML's own error names it
            total += nodes
        else:
            continue
        if total > MAX_YAML_NODES:
            raise YamlTooBig(f"its aliases expand it to more than {MAX_YAML_NODES:,} values (a config holds a few "
                             f"hundred)", event.start_mark)
        if stack:  # the node just finished belongs to the innermost open one
            parent = stack[-1]
            parent[1] += nodes
            parent[2] = max(parent[2], depth + 1)
            if len(stack) - 1 + parent[2] > MAX_YAML_DEPTH:
                raise YamlTooBig(f"nested more than {MAX_YAML_DEPTH} levels deep once its aliases are expanded (a "
                                 f"config nests 5)", event.start_mark)


def read_yaml(path: str | Path, what: str) -> Any:
    """The YAML document in ``path`` (None for an empty file); a one-line ConfigError naming ``what`` (e.g.
    "config file") and the file when it is missing, a folder, unreadable or not YAML (with the line), or when a
    mapping in it names a key twice (both lines)."""
    p = Path(path)
    text = read_text(p, what, "a YAML file (e.g. configs/paper.yaml)")
    try:
        check_yaml_shape(text)
        return yaml.load(text, Loader=UniqueKeyLoader)
    except YamlTooBig as big:
        where = f", line {big.mark.line + 1}" if big.mark is not None else ""
        raise ConfigError(f"{what} {str(p)!r}{where}: {big.why}") from None
    except DuplicateKey as dup:
        where = f"in {dup.mapping!r}" if dup.mapping else "at the top level"
        raise ConfigError(f"{what} {str(p)!r}, line {dup.again.line + 1}: key {dup.key!r} appears twice {where} "
                          f"(first at line {dup.first.line + 1}); a key takes one value") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        why = getattr(exc, "problem", None) or str(exc)
        context, start = getattr(exc, "context", None), getattr(exc, "context_mark", None)
        if context:
            since = f" from line {start.line + 1}" if start is not None and mark is not None and \
                start.line != mark.line else ""
            why = f"{why} ({context}{since})"
        raise ConfigError(f"{what} {str(p)!r}{where}: not valid YAML: {' '.join(str(why).split())}") from None


def load_config(path: str | Path | None = None, overrides: Mapping[str, Any] | None = None) -> Config:
    """Load a YAML scene config (or the defaults when ``path`` is None) and apply overrides.

    A value given here (in the file or an override) that lies orders of magnitude from anything that can swing
    gets one :class:`~aero_env.config.UnitSlipWarning` naming the likely unit slip, and runs as given."""
    if path is None:
        cfg = from_dict({}, overrides)
        warn_unit_slips(dict(overrides or {}))
        return cfg
    data = read_yaml(path, "config file")
    if data is None:
        raise ConfigError(f"config file {str(path)!r}: empty; a config is a YAML mapping of sections "
                          f"({', '.join([*SECTIONS, *LIST_SECTIONS])}), e.g. configs/paper.yaml")
    if not isinstance(data, Mapping):
        raise ConfigError(f"config file {str(path)!r}: must be a YAML mapping of sections "
                          f"({', '.join([*SECTIONS, *LIST_SECTIONS])}), got a {type(data).__name__}")
    cfg = from_dict(data, overrides)
    warn_unit_slips({**_given_values(data), **(overrides or {})})
    return cfg


def _given_values(data: Mapping[str, Any]) -> dict[str, Any]:
    """The ``design`` and ``scene`` values a config file gives, by dotted key, as written."""
    given = {}
    for section in ("design", "scene"):
        values = data.get(section)
        if isinstance(values, Mapping):
            given.update({f"{section}.{name}": value for name, value in values.items()})
    return given


def parse_override(text: str) -> tuple[str, Any]:
    """Parse a CLI ``KEY=VALUE`` override; the value is read as YAML (numbers, true/false, words). A mapping in it
    that names a key twice (``scene.effects={drag: true, drag: false}``) is refused."""
    if "=" not in text:
        raise ConfigError(f"--set {text!r}: expected KEY=VALUE, e.g. design.m2=0.008")
    key, raw = text.split("=", 1)
    try:
        check_yaml_shape(raw)
        value = yaml.load(raw, Loader=UniqueKeyLoader)
    except YamlTooBig as big:
        raise ConfigError(f"--set {shown(text)}: {big.why}") from None
    except DuplicateKey as dup:
        inner = dup.mapping if dup.mapping.startswith("[") or not dup.mapping else f".{dup.mapping}"
        raise ConfigError(f"--set {text!r}: key {dup.key!r} appears twice in {key.strip() + inner!r} (at "
                          f"{_in_value(dup.first, dup.again)} of the value); a key takes one value") from None
    except yaml.YAMLError:
        value = raw
    return key.strip(), value


def _in_value(first: yaml.Mark, again: yaml.Mark) -> str:
    """Where two marks are in a ``--set`` value: "columns 2 and 14", with lines where the value has several."""
    if first.line == again.line == 0:
        return f"columns {first.column + 1} and {again.column + 1}"
    return f"line {first.line + 1} column {first.column + 1} and line {again.line + 1} column {again.column + 1}"


def schema_rows() -> list[tuple[str, str, str, str, str]]:
    """(key, default, unit, allowed, meaning) for every field, for docs and ``aero-env schema``."""
    rows = []

    def walk(cls, prefix):
        for f in fields(cls):
            sub = f.default_factory if f.default_factory is not dataclasses.MISSING else None
            if sub is not None and dataclasses.is_dataclass(sub):
                walk(sub, f"{prefix}.{f.name}")
                continue
            m = f.metadata
            allowed = ("one of " + ", ".join(m["choices"])) if m["choices"] else (
                "true/false" if f.type in (bool, "bool") else range_text(m))
            rows.append((f"{prefix}.{f.name}", repr(f.default), m["unit"], allowed, m["doc"]))

    for name, cls in SECTIONS.items():
        walk(cls, name)
    for name, cls in LIST_SECTIONS.items():
        for f in fields(cls):
            m = f.metadata
            default = "required" if f.name == "name" or (cls is Tunable and f.name in ("low", "high")) else repr(f.default)
            rows.append((f"{name}[].{f.name}", default, m["unit"], "", m["doc"]))
    return rows
