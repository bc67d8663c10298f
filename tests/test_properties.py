"""Property tests (hypothesis): random in-box designs keep the run's invariants; random malformed
configs and actions get a clear ConfigError naming the field, never a traceback from inside
pymunk or numpy."""

import math
import re

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import aero_env  # noqa: F401
from aero_env import quantities
from aero_env.config import ConfigError, load_config, schema_rows

from .conftest import PAPER
from .invariants import check_run, observing

ENV = gym.make("aero_env/AerialAcrobat-v0", **{"scene.frames": 2})
IN_BOX = st.lists(st.floats(-1.0, 1.0, width=32), min_size=5, max_size=5)


@pytest.mark.slow
@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(action=IN_BOX, seed=st.integers(0, 2**31 - 1))
def test_random_in_box_designs_keep_the_invariants(action, seed):
    obs, _ = ENV.reset(seed=seed)
    with observing(keep_rows=False) as seen:  # the run measured from pymunk's bodies (tests/invariants.py)
        obs, reward, terminated, truncated, info = ENV.step(np.array(action, np.float32))
    # an episode ends by itself: nothing truncates it (the env's Episode End)
    assert np.all(np.isfinite(obs)) and math.isfinite(reward) and terminated and not truncated
    env = ENV.unwrapped
    cfg, _ = env.space.episode_config(info["design"], env._draw)
    assert len(seen) == 1 and seen[0].world.cfg == cfg  # the episode ran the design the info names
    check_run(env.last_run, seen[0], cfg)
    assert reward == (0.0 if info["outcome"] == "unstable" else info["traversals"])


# Every scalar key of the schema, and values that are wrong in every way a file or a tuner can be wrong.
SCHEMA = {row[0]: row for row in schema_rows() if "[]" not in row[0]}
SCALAR_KEYS = list(SCHEMA)
BAD_VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**12, 10**12), st.booleans(), st.none(),
    st.text(max_size=8), st.lists(st.integers(), max_size=2), st.dictionaries(st.text(max_size=3), st.integers(),
                                                                              max_size=2))
# A range as the config writes it: "[0.0, 0.1]", "(0.0, 1.0]" (the interval's ends are numbers).
_NUMBER = r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?"
RANGE = re.compile(rf"[\[(]{_NUMBER}, {_NUMBER}\]")


def _as_shown(value) -> set[str]:
    """How a value given for a key can appear after "key = " in an error: as given, or as the number it
    was read as (an int for a float field, a numeric string, a float for a whole-number field)."""
    out = {repr(value)}
    number = value
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            return out
    if isinstance(number, (int, float)) and not isinstance(number, bool):
        out.add(repr(float(number)))
        if math.isfinite(number) and float(number).is_integer():
            out.add(repr(int(number)))
    return out


def _allowance(key: str, message: str) -> bool:
    """The error says what ``key`` allows: its choices, true/false, its unit spellings (a string naming
    a unit the key does not take; "a plain number" for a key without one), or a numeric range: the schema's own (with its unit), or one a
    rule between fields computed (mu_k within [0, mu_s], contact_hold at least 5 steps)."""
    _, _, unit, allowed, _ = SCHEMA[key]
    if allowed.startswith("one of "):
        return f"must be one of {allowed[len('one of '):].split(', ')}" in message
    if allowed == "true/false":
        return "must be true or false" in message
    if "is not one this key takes: " in message:  # the number is fine, its unit is not: the units it takes
        return f"is not one this key takes: {', '.join(quantities.units_for(unit))} " in message
    if "given, but the key has no unit" in message:
        return not quantities.units_for(unit) and "write a plain number" in message
    return allowed in message or bool(RANGE.search(message.split("allowed ")[-1]))


def names_key_value_and_range(message: str, overrides: dict) -> bool:
    """One line naming one of the overrides by its full dotted key with its value ("design.m2 = 5.0"), and
    what is allowed; another field's range (mu_k's, when mu_s is set too low) counts for a rule between them."""
    if "\n" in message:
        return False
    for key, value in overrides.items():
        named = [m.start() for m in re.finditer(rf"(?<![\w.]){re.escape(key)} = ", message)]
        shown = any(message.startswith(s, i + len(key) + 3) for i in named for s in _as_shown(value))
        if shown and (_allowance(key, message) or any(_allowance(k, message) for k in SCHEMA
                                                      if f"{k} = " in message and k != key)):
            return True
    return False


def test_the_message_check_refuses_what_the_old_escape_accepted():
    # the old check passed any message with "design." in it, or a key's last part ("h") anywhere
    assert not names_key_value_and_range("design.m3: something went wrong", {"design.h": 1.0})
    assert not names_key_value_and_range("design.h = 2.0: out of range, allowed [-0.1, 0.1] m", {"design.h": 1.0})
    assert not names_key_value_and_range("design.h = 1.0: out of range", {"design.h": 1.0})
    assert not names_key_value_and_range("design.h = 1.0:\nout of range, allowed [-0.1, 0.1] m", {"design.h": 1.0})
    assert not names_key_value_and_range("h = 1.0: out of range, allowed [-0.1, 0.1] m", {"design.h": 1.0})
    assert names_key_value_and_range("design.h = 1.0: out of range, allowed [-0.1, 0.1] m", {"design.h": 1})
    # and what the config really says
    for overrides in ({"design.h": 1}, {"design.mu_s": 0.1}, {"scene.effects.hook": "nail"}, {"sim.dt": "1 parsec"},
                      {"env.record_trace": 3}, {"scene.frames": 2.5}, {"design.m2": float("nan")}):
        try:
            load_config(PAPER, overrides)
        except ConfigError as exc:
            assert names_key_value_and_range(str(exc), overrides), str(exc)
        else:
            raise AssertionError(f"{overrides} loaded")


@pytest.mark.slow
@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(overrides=st.dictionaries(st.sampled_from(SCALAR_KEYS), BAD_VALUES, min_size=1, max_size=3))
def test_random_config_values_load_or_get_a_config_error_naming_the_key(overrides):
    try:
        cfg = load_config(PAPER, overrides)
    except ConfigError as exc:
        assert names_key_value_and_range(str(exc), overrides), str(exc)
        return
    for key, wanted in overrides.items():  # accepted: then it is the value given, valid and finite
        value = cfg.value(key) if key.count(".") == 1 else None
        if isinstance(value, float):
            assert math.isfinite(value)
            if isinstance(wanted, (int, float)) and not isinstance(wanted, bool):
                assert value == float(wanted), (key, wanted, value)


LIST_ENTRY = st.dictionaries(
    st.sampled_from(["name", "low", "high", "scale", "linked", "relative", "absolute", "bogus"]),
    st.one_of(st.sampled_from(["design.m3", "design.h", "scene.rise", "scene.frames", "design.mu_k", "nope",
                               "log", "linear"]), BAD_VALUES), max_size=5)


@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(section=st.sampled_from(["tunable", "context", "tolerance"]),
       entries=st.one_of(st.lists(LIST_ENTRY, max_size=3), BAD_VALUES))
def test_random_design_problem_sections_load_or_get_a_config_error(section, entries):
    try:
        cfg = load_config(PAPER, {section: entries})
        env = gym.make("aero_env/AerialAcrobat-v0", config=cfg)
    except ConfigError as exc:
        assert names_the_entry(str(exc), section, entries), str(exc)
        return
    assert env.action_space.shape[0] >= 1 and env.observation_space.shape[0] >= 1


_ENTRY = re.compile(r"(?P<section>\w+)(?:\[(?P<i>\d+)\])?(?:\.(?P<key>\w+))?(?: \([^()]*\))?(?P<rest>: | = )")


def names_the_entry(message: str, section: str, entries) -> bool:
    """One line that starts with the path of what is wrong, and the path points at what was given:
    ``tunable: ...`` (the section), ``tunable[1]: ...`` (an entry that exists), ``tunable[1].low = 0.5: ...``
    (a key that entry has, with the value it has), ``tunable[1].low: missing`` (a key it lacks),
    ``tunable[1].bogus: unknown key`` (a key it has); or the design space's corner that breaks a field,
    naming the corner's values of the section's own fields."""
    if "\n" in message:
        return False
    if message.startswith("the design space reaches an invalid design at the corner ("):
        names = [e.get("name") for e in entries if isinstance(e, dict)] if isinstance(entries, list) else []
        return any(isinstance(n, str) and f"{n}=" in message for n in names)
    m = _ENTRY.match(message)
    if not m or m["section"] != section:
        return False
    if m["i"] is None:
        return m["key"] is None
    i = int(m["i"])
    if not isinstance(entries, list) or i >= len(entries):
        return False
    entry, key, rest = entries[i], m["key"], message[m.end():]
    if key is None:
        return True
    if not isinstance(entry, dict):
        return False
    if rest.startswith("missing"):
        return key not in entry
    if key not in entry:
        return False
    return m["rest"] == ": " or message[m.end():].startswith(repr(entry[key]))


def test_the_entry_check_refuses_a_wrong_path():
    entries = [{"name": "design.m3", "low": 0.5}]
    assert names_the_entry("tunable[0].high: missing; the value of design.m3 at action +1", "tunable", entries)
    assert names_the_entry("tunable[0].low = 0.5: must be ...", "tunable", entries)
    assert names_the_entry("tunable[0].low (a value of design.m3) = 0.5: must be ...", "tunable", entries)
    assert not names_the_entry("tunable[0].low: missing", "tunable", entries)  # it is there
    assert not names_the_entry("tunable[1]: must be a mapping", "tunable", entries)  # there is no entry 1
    assert not names_the_entry("tunable[0].low = 0.7: must be ...", "tunable", entries)  # not what was given
    assert not names_the_entry("context[0].low = 0.5: must be ...", "tunable", entries)  # another section
    assert not names_the_entry("design.m3 = 0.5: out of range", "tunable", entries)  # the old escape


BAD_ACTIONS = st.one_of(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=7),
    st.lists(st.one_of(st.text(max_size=3), st.none(), st.booleans()), min_size=1, max_size=5),
    st.floats(allow_nan=True), st.text(max_size=5), st.none(),
    st.lists(st.lists(st.floats(-1, 1), min_size=5, max_size=5), min_size=1, max_size=2),
)


@settings(deadline=None)  # max_examples from the profile: 300 in CI, 3000 with --hypothesis-profile=deep
@given(action=BAD_ACTIONS)
def test_random_actions_step_or_get_a_config_error(action):
    env = ENV.unwrapped
    try:
        design = env.design_for(action)
    except ConfigError as exc:
        assert "action" in str(exc), str(exc)
        return
    # accepted: five finite numbers in the box, mapped inside every declared range
    assert np.all(np.abs(np.asarray(action, dtype=float)) <= 1.0)
    for t in env.config.tunable:
        base = 1.0 if t.relative_to is None else env.config.value(t.relative_to)  # relative: multiples of it
        assert t.low * base <= design[t.name] <= t.high * base
