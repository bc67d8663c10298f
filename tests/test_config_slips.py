"""Two config slips a new user hit (issue 36 §7): a value 1000x too small (a unit slip) runs, with one warning
line naming the likely slip; a YAML mapping naming a key twice, in a file or a ``--set`` value, is refused."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import warnings

import pytest

from aero_env.cli import main
from aero_env.config import (LIST_SECTIONS, SECTIONS, ConfigError, UnitSlipWarning, load_config, parse_override,
                             read_yaml)
from aero_env.envs import AerialAcrobatEnv

from .conftest import PAPER, ROOT

M3_SLIP = ("design.m3 = 7.2e-06 kg (0.0072 g): about 1000x below the prototype's 7.2 g, beyond the 30x either way "
           "of any mass that can swing (run as given); did you mean 7.2 g?")
ANGLE_SLIP = ("design.rest_angle_deg = 0.96: an angle in degrees (the prototype's is 55 deg), run as given; 0.96 rad "
              "is 55 deg: did you mean 0.96rad (or 55)?")
CHEAP = {"scene.frames": 2}


def slip_warnings(caught) -> list[str]:
    return [str(w.message) for w in caught if issubclass(w.category, UnitSlipWarning)]


# ---- 1. a value orders of magnitude from anything that can swing: one warning, and it runs as given ----
@pytest.mark.parametrize("key, raw, si, message", [
    ("design.m3", "7.2e-3g", 7.2e-6, M3_SLIP),  # 7.2 mg written for 7.2 g (issue 36)
    ("design.m3", 7.2e-6, 7.2e-6, M3_SLIP),
    ("design.rest_angle_deg", 0.96, 0.96, ANGLE_SLIP),  # 55 deg given in radians (issue 36)
    ("design.La", "0.0483 mm", 4.83e-5, "design.La = 4.83e-05 m (0.0483 mm): about 1000x below the prototype's "
                                        "48.3 mm, beyond the 30x either way of any length that can swing (run as "
                                        "given); did you mean 48.3 mm?"),
])
def test_a_unit_slip_warns_once_naming_key_value_and_slip_and_still_runs(key, raw, si, message):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cfg = load_config(PAPER, {key: raw})
    assert slip_warnings(caught) == [message]
    assert cfg.value(key) == pytest.approx(si, rel=1e-12)  # not refused: it may be a deliberate experiment


def test_a_slip_in_a_config_file_warns_too(tmp_path):
    text = PAPER.read_text().replace("  m3: 0.00720", "  m3: 7.2e-3g")
    assert text != PAPER.read_text()
    (tmp_path / "slip.yaml").write_text(text)
    with pytest.warns(UnitSlipWarning) as caught:
        load_config(tmp_path / "slip.yaml")
    assert [str(w.message) for w in caught] == [M3_SLIP]


@pytest.mark.parametrize("overrides", [
    {"design.rest_angle_deg": "0.96 rad"},  # a unit written says what was meant
    {"design.rest_angle_deg": "3 deg", "design.stop_angle_deg": 180},
    {"design.m3": 0.0072 / 20, "design.La": 0.0483 * 20},  # far, but within what can swing
    {"design.pivot_friction": 0.0, "design.coin_mass": 0.0},  # 0 switches a part off
    {"design.h": 1e-6, "scene.rise": -1e-5, "design.dT": 1e-9},  # signed offsets: any small value is a design
])
def test_values_that_can_swing_or_say_their_unit_do_not_warn(overrides):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitSlipWarning)
        load_config(PAPER, overrides)


def stored_configs():
    paths = sorted((ROOT / "configs").rglob("*.yaml"))
    return [p for p in paths if set(read_yaml(p, "config file")) <= set(SECTIONS) | set(LIST_SECTIONS)]


def test_every_stored_config_is_a_config_we_check():
    names = {p.relative_to(ROOT).as_posix() for p in stored_configs()}
    assert {"configs/paper.yaml", "configs/small_frames.yaml", "configs/scenes/light_frames.yaml",
            "configs/scenes/solutions/steep.yaml"} <= names and len(names) >= 19


@pytest.mark.parametrize("path", stored_configs(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_stored_config_warns(path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitSlipWarning)
        load_config(path)


def test_the_warning_comes_once_per_value_not_per_episode_or_trial():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # no deduplication by Python: every warn() call is recorded
        for env in (AerialAcrobatEnv(PAPER, {"design.rest_angle_deg": 0.96, **CHEAP}),
                    AerialAcrobatEnv(load_config(PAPER), {"design.rest_angle_deg": 0.96, **CHEAP})):
            for seed in (0, 1):
                env.reset(seed=seed)
                _, _, _, _, info = env.step(env.action_for())
            assert info["outcome"] == "fell_short"  # the slipped value ran, in every episode
        # a tuner's trials and screens build on the loaded config (with_values, replace): not warned again
        cfg = load_config(PAPER, {"design.rest_angle_deg": 0.96})
        for la in (0.045, 0.05, 0.055):
            cfg.with_values({"design.La": la}).replace({"sim.fidelity": "reduced"})
    assert slip_warnings(caught) == [ANGLE_SLIP] * 3  # one per env made and per load, none per episode or trial


def test_the_cli_prints_each_warning_as_one_line_and_runs():
    env = {k: v for k, v in os.environ.items() if k != "PYTHONWARNINGS"}
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "simulate", str(PAPER), "--set", "scene.frames=2",
                           "--set", "design.m3=7.2e-3g", "--set", "design.rest_angle_deg=0.96"],
                          capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    assert done.stderr.splitlines() == [f"aero-env: warning: {M3_SLIP}", f"aero-env: warning: {ANGLE_SLIP}"]
    assert "outcome:" in done.stdout


# ---- 2. a YAML mapping naming a key twice is refused, with both lines ----
def write(tmp_path, text: str):
    path = tmp_path / "x.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, message", [
    ("design:\n  La: 0.0483\n  m3: 0.0072\n  Lb: 0.0517\n  m3: 0.009\n",
     "line 5: key 'm3' appears twice in 'design' (first at line 3)"),
    ("design:\n  m3: 0.0072\nscene:\n  frames: 3\ndesign:\n  m2: 0.008\n",
     "line 5: key 'design' appears twice at the top level (first at line 1)"),
    ("scene:\n  effects:\n    drag: true\n    friction: static\n    drag: false\n",
     "line 5: key 'drag' appears twice in 'scene.effects' (first at line 3)"),
    ("tunable:\n  - name: design.m3\n    low: 0.5\n    high: 1.5\n  - name: design.La\n    low: 0.8\n    high: 1.2\n"
     "    low: 0.9\n", "line 8: key 'low' appears twice in 'tunable[1]' (first at line 6)"),
    ("design: {m3: 0.0072, m3: 0.009}\n", "line 1: key 'm3' appears twice in 'design' (first at line 1)"),
])
def test_a_duplicated_key_in_a_file_is_refused_with_both_lines(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as exc:
        load_config(path)
    assert str(exc.value) == f"config file {str(path)!r}, {message}; a key takes one value"


def test_the_cli_refuses_a_duplicated_key_in_one_line(tmp_path, capsys):
    path = write(tmp_path, "design:\n  m3: 0.0072\n  m3: 0.009\n")
    assert main(["simulate", str(path)]) == 2
    assert capsys.readouterr().err == (f"aero-env: file error: config file {str(path)!r}, line 3: key 'm3' appears "
                                       f"twice in 'design' (first at line 2); a key takes one value\n")


def test_a_merge_may_still_override_a_merged_key(tmp_path):
    # YAML's merge key brings in a mapping whose keys the mapping itself may override: not a duplicate
    merged = write(tmp_path, "x: &x {a: 1, b: 2}\ny:\n  <<: *x\n  b: 3\nz: *x\n")
    assert read_yaml(merged, "file") == {"x": {"a": 1, "b": 2}, "y": {"a": 1, "b": 3}, "z": {"a": 1, "b": 2}}


@pytest.mark.parametrize("text, message", [
    ("scene.effects={drag: true, drag: false}", "key 'drag' appears twice in 'scene.effects' (at columns 2 and 14 "
                                                "of the value)"),
    ("tunable=[{name: design.m3, low: 0.5, high: 1.5}, {name: design.La, low: 0.8, low: 0.9, high: 1.2}]",
     "key 'low' appears twice in 'tunable[1]' (at columns 60 and 70 of the value)"),
])
def test_a_duplicated_key_in_a_set_value_is_refused(text, message):
    with pytest.raises(ConfigError) as exc:
        parse_override(text)
    assert str(exc.value) == f"--set {text!r}: {message}; a key takes one value"


def test_set_values_without_duplicates_read_as_before():
    assert parse_override("scene.effects={drag: true, friction: static}") == (
        "scene.effects", {"drag": True, "friction": "static"})
    assert parse_override("design.m3=7.2e-3g") == ("design.m3", "7.2e-3g")
    assert parse_override("design.m3={oops") == ("design.m3", "{oops")  # not YAML: the text itself, as before


# ---- 3. every band, and the degree rule, on every key it covers ----
# The bands as aero_env/config/plausible.py states them, written out: a mass, a length, a spring stiffness or a
# torque reads as a slip beyond 30x either way of the prototype's; a slip of g for kg, mm for m or N·mm for N·m is
# 1000x. Keyed by the SI unit the keys declare (configs are SI): a band keyed by another spelling ("N·mm/rad")
# would check no key.
BANDS = {"kg": (30.0, "mass"), "m": (30.0, "length"), "N·m/rad": (30.0, "spring stiffness"), "N·m": (30.0, "torque")}


def _keys(select):
    from aero_env.config.sections import real_field, real_keys

    return [k for k in real_keys() if select(real_field(k, "key"))]


def _unsigned(f) -> bool:
    return f.metadata["lo"] is not None and f.metadata["lo"] >= 0


BANDED = _keys(lambda f: f.metadata["unit"] in BANDS and _unsigned(f) and f.default)
SIGNED = _keys(lambda f: f.metadata["unit"] in BANDS and not _unsigned(f))
DEGREES = _keys(lambda f: f.metadata["unit"] == "deg")
UNBANDED = _keys(lambda f: f.metadata["unit"] not in BANDS and f.metadata["unit"] != "deg")


def _allowed(key, value) -> bool:
    from aero_env.config.sections import real_field

    m = real_field(key, "key").metadata
    return (m["lo"] is None or value > m["lo"] or (value == m["lo"] and not m.get("lo_open"))) and (
        m["hi"] is None or value <= m["hi"])


def test_the_bands_are_keyed_by_the_units_the_keys_declare():
    from aero_env.config.plausible import PLAUSIBLE_BANDS

    assert {u: (b.factor, b.noun) for u, b in PLAUSIBLE_BANDS.items()} == BANDS
    assert {u for u in BANDS} == {_field_unit(k) for k in BANDED}  # every band checks keys, every such key a band
    assert {"design.m3", "design.La", "design.spring_k", "design.pivot_friction"} <= set(BANDED)


def _field_unit(key):
    from aero_env.config.sections import real_field

    return real_field(key, "key").metadata["unit"]


@pytest.mark.parametrize("key", BANDED)
def test_every_banded_key_warns_past_its_band_and_not_inside_it(key):
    """1000x (a unit slip) and 31x either way warn, naming the kind of quantity; 29x and 10x do not. Each side
    where the key's range allows the value; every key is checked on at least one side."""
    from aero_env.config.plausible import unit_slips
    from aero_env.config.sections import real_field

    prototype = real_field(key, "key").default
    factor, noun = BANDS[_field_unit(key)]
    warned = 0
    for times in (1000.0, 1 / 1000.0, factor * 1.04, 1 / (factor * 1.04)):
        value = prototype * times
        if _allowed(key, value):
            messages = unit_slips({key: value})
            assert len(messages) == 1, (key, value, messages)
            message = messages[0]
            assert message.startswith(f"{key} = {value!r} ") and f"beyond the {factor:g}x either way of any {noun} " \
                                                                  f"that can swing (run as given)" in message, message
            warned += 1
    assert warned >= 1, key  # every key on one side at least (its range may hold the band's edge and no slip)
    for times in (factor * 0.96, 1 / (factor * 0.96), 10.0, 0.1, 1.0):
        value = prototype * times
        if _allowed(key, value):
            assert unit_slips({key: value}) == [], (key, value)


@pytest.mark.parametrize("key", SIGNED)
def test_a_signed_offset_is_never_a_slip(key):
    from aero_env.config.plausible import unit_slips

    for value in (1e-9, -1e-9, 1e-6, -0.09):
        if _allowed(key, value):
            assert unit_slips({key: value}) == []


@pytest.mark.parametrize("key", DEGREES)
def test_every_angle_in_degrees_warns_when_given_in_radians(key):
    """The degree rule on every _deg key: a plain number below 3.2 reads as radians where the prototype's angle is
    10 deg or more (every key's is); 3.2 and more, or a value with its unit written, does not warn."""
    from aero_env.config.plausible import unit_slips
    from aero_env.config.sections import real_field

    prototype = real_field(key, "key").default
    assert abs(prototype) >= 10.0
    for value in (math.radians(prototype), 3.1416, 0.5, -0.5):
        if _allowed(key, value):
            messages = unit_slips({key: value})
            assert len(messages) == 1, (key, value, messages)
            message = messages[0]
            assert message.startswith(f"{key} = {value:g}: an angle in degrees (the prototype's is {prototype:g} deg)")
            assert f"{value:g} rad is {math.degrees(value):.3g} deg" in message
    for value in (3.2, -3.2, prototype, "0.5 rad", "2 deg"):
        if isinstance(value, str) or _allowed(key, value):
            assert unit_slips({key: value}) == [], (key, value)


@pytest.mark.parametrize("key", UNBANDED)
def test_keys_of_other_kinds_are_not_checked(key):
    """Friction coefficients, air density, the drag coefficient: no band (plausible.py's comment)."""
    from aero_env.config.plausible import unit_slips
    from aero_env.config.sections import real_field

    prototype = real_field(key, "key").default
    for value in (prototype * 1000, prototype / 1000):
        if value and _allowed(key, value):
            assert unit_slips({key: value}) == []
