"""Config loading, overrides, immutability, and one test per validation rule (each sees its message)."""

import dataclasses

import numpy as np
import pytest

from aero_env.cli import main
from aero_env.config import ConfigError, load_config, parse_override, schema_rows

from .conftest import PAPER


def test_paper_config_is_table_1_and_table_3(paper_cfg):
    d = paper_cfg.design
    assert (d.La, d.Lb, d.Lc, d.Ld, d.h) == (0.0483, 0.0517, 0.03, 0.06, 0.005)
    assert (d.m1, d.m2, d.m3) == (0.004, 0.00771, 0.0072)
    assert (d.mu_s, d.mu_k) == (0.542, 0.409)  # white/gray pair
    assert d.spring_k == pytest.approx(8.77e-4)
    assert (d.alpha_min_deg, d.alpha_max_deg, d.rest_angle_deg, d.stop_angle_deg) == (60, 120, 55, 180)
    assert paper_cfg.scene.frames >= 8 and paper_cfg.scene.rise > 0


def test_overrides_apply_and_config_is_immutable():
    cfg = load_config(PAPER, {"design.m2": 0.008, "scene.effects.drag": True})
    assert cfg.design.m2 == 0.008 and cfg.scene.effects.drag is True
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.design.m2 = 1.0
    # replace() gives a new validated config and leaves the old one alone
    cfg2 = cfg.replace({"design.m2": 0.009})
    assert cfg2.design.m2 == 0.009 and cfg.design.m2 == 0.008


def test_defaults_without_a_file_equal_the_paper_design():
    assert load_config().design == load_config(PAPER).design


def test_cli_override_values_are_parsed_as_yaml():
    assert parse_override("design.m2=0.008") == ("design.m2", 0.008)
    assert parse_override("scene.effects.drag=true") == ("scene.effects.drag", True)
    assert parse_override("scene.effects.friction=kinetic") == ("scene.effects.friction", "kinetic")


@pytest.mark.parametrize("overrides, needles", [
    ({"design.color": 1}, ["design.color", "unknown key", "aero-env schema lists them"]),
    ({"design.m_2": 0.008}, ["design.m_2", "unknown key", "did you mean design.m2?"]),
    ({"scene.effects.wind": True}, ["scene.effects.wind", "unknown key"]),
    ({"design.m2": "heavy"}, ["design.m2", "'heavy'", "must be a number"]),
    ({"scene.frames": 8.5}, ["scene.frames", "8.5", "whole number"]),
    ({"scene.effects.drag": "yes"}, ["scene.effects.drag", "true or false"]),
    ({"scene.effects.friction": "sticky"}, ["scene.effects.friction", "sticky", "static_kinetic"]),
    ({"design.m2": 0.0}, ["design.m2 = 0.0", "out of range", "(0.0, 0.1] kg"]),
    ({"design.m3": -0.001}, ["design.m3 = -0.001", "out of range"]),
    ({"design.Lb": 0.0}, ["design.Lb = 0.0", "out of range", "(0.0, 1.0] m"]),
    ({"design.La": -0.05}, ["design.La = -0.05", "out of range"]),
    ({"design.spring_k": float("nan")}, ["design.spring_k", "finite"]),
    ({"design.mu_k": 0.6}, ["design.mu_k = 0.6", "must not exceed design.mu_s = 0.542", "[0, 0.542]"]),
    ({"design.alpha_max_deg": 50.0}, ["design.alpha_max_deg = 50.0", "must exceed design.alpha_min_deg = 60"]),
    ({"design.stop_angle_deg": 60.0}, ["design.stop_angle_deg = 60.0", "rest_angle_deg = 55", "[65.0, 325.0]"]),
    ({"design.arm_mass": 0.01}, ["design.m2 = 0.00771", "design.arm_mass = 0.01 + design.coin_mass = 0.004",
                                 "= 0.01421 kg", "(0.01421, 0.1] kg"]),
    ({"sim.dt": 0.5}, ["sim.dt = 0.5", "out of range", "(0.0, 0.01] s"]),
    ({"design.Ld": 0.04}, ["design.Ld = 0.04", "hold the coins", "design.coin_radius = 0.01",
                           "design.arm_length = 0.03", "design.alpha_max_deg = 120", "[0.04359, 0.5] m"]),
    ({"design.torso_length": 0.04}, ["design.torso_length: derived, not set", "design.Ld"]),
    ({"design.coin_offset": 0.02}, ["design.coin_offset: derived, not set", "flush with the torso's bottom"]),
    ({"physics.dt": 0.001}, ["physics.dt", "must start with one of"]),
    ({"sim.dt": 0.01}, ["sim.contact_hold = 0.01", "5 runner steps", "[0.05, 1.0] s"]),
        ({"sim.dt": 0.001, "sim.substeps": 4}, ["sim.contact_hold = 0.01", "sim.substeps = 4", "[0.02, 1.0] s"]),
        ({"sim.fidelity": "exact"}, ["sim.fidelity = 'exact'", "reduced", "reference"]),
    ({"design.dT": 0.05}, ["design.dT = 0.05", "beyond its ends", "N·m", "design.m1 = 0.004"]),
])
def test_bad_values_name_key_value_and_range(overrides, needles):
    with pytest.raises(ConfigError) as exc:
        cfg = load_config(PAPER, overrides)
        # Errors that need derived quantities (the robot's inertia) surface when the world is built.
        from aero_env.physics.engine_params import to_engine

        to_engine(cfg)
    for needle in needles:
        assert needle in str(exc.value)


def test_unknown_section_and_bad_yaml(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("design: {m2: 0.008}\nrobot: {}\n")
    with pytest.raises(ConfigError, match="robot: unknown section"):
        load_config(p)
    p.write_text("design: [1, 2\n")
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_config(p)
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "missing.yaml")


def test_cli_reports_config_errors_cleanly(capsys):
    code = main(["simulate", str(PAPER), "--set", "design.m2=-1"])
    err = capsys.readouterr().err
    assert code == 2
    assert "design.m2 = -1.0" in err and "out of range" in err and "Traceback" not in err


def test_schema_covers_every_field_with_unit_and_range():
    rows = schema_rows()
    keys = {r[0] for r in rows}
    assert {"design.m2", "design.mu_s", "scene.pitch", "scene.effects.drag", "sim.dt"} <= keys
    by_key = {r[0]: r for r in rows}
    assert by_key["design.m2"][3] == "(0.0, 0.1] kg" and by_key["design.m2"][2] == "kg"
    assert by_key["scene.effects.friction"][3] == "one of static_kinetic, static, kinetic"
    for key, default, unit, allowed, doc in rows:
        assert unit and doc, key


def test_scientific_notation_without_a_dot_is_a_number(tmp_path):
    # YAML 1.1 reads 8e-4 as a string; the config reads it as the number it means
    assert load_config(PAPER, dict([parse_override("design.spring_k=8e-4")])).design.spring_k == 8e-4
    p = tmp_path / "s.yaml"
    p.write_text("design:\n  spring_k: 9e-4\n")
    assert load_config(p).design.spring_k == 9e-4


def test_mixed_key_types_give_a_config_error(tmp_path):
    p = tmp_path / "m.yaml"
    p.write_text("design: {1: 2, foo: 3}\n")
    with pytest.raises(ConfigError, match="unknown key"):
        load_config(p)


# ---- the design problem: tunable, context, tolerance, env ----
DESIGN_PROBLEM_YAML = """
tunable:
  - {name: design.m3, low: 0.005, high: 0.01}
  - {name: design.mu_s, low: 0.45, high: 1.2, scale: log, linked: [design.mu_k]}
context:
  - {name: scene.rise, low: 0.0, high: 0.004}
  - {name: design.m2}
tolerance:
  - {name: design.La, absolute: 5e-4}
env:
  reward_shaping: 0.25
"""


def test_design_problem_sections_load_and_round_trip(tmp_path):
    path = tmp_path / "problem.yaml"
    path.write_text(PAPER.read_text().split("\ntunable:")[0] + DESIGN_PROBLEM_YAML)  # its own sections, not a second copy
    cfg = load_config(path)
    assert [t.name for t in cfg.tunable] == ["design.m3", "design.mu_s"]
    assert cfg.tunable[1].scale == "log" and cfg.tunable[1].linked == ("design.mu_k",)
    assert cfg.context[0].low == 0.0 and cfg.context[1].low is None
    assert cfg.tolerance[0].absolute == 5e-4 and cfg.tolerance[0].relative == 0.0
    assert cfg.env.reward_shaping == 0.25
    from aero_env.config import from_dict

    assert from_dict(cfg.to_dict()) == cfg
    assert load_config(PAPER, {"tunable": cfg.to_dict()["tunable"]}).tunable == cfg.tunable
    # the YAML a tuner or a training run writes reads back to the same config, every float exact
    (tmp_path / "again.yaml").write_text(cfg.with_values({"design.m3": 0.1 / 3}).to_yaml())
    again = load_config(tmp_path / "again.yaml")
    assert again == cfg.with_values({"design.m3": 0.1 / 3}) and again.design.m3 == 0.1 / 3


@pytest.mark.parametrize("overrides, message", [
    ({"tunable": [{"name": "design.m3", "low": 0.01}]}, "tunable[0].high: missing"),
    ({"tunable": [{"name": "design.m3", "low": 0.01, "high": 0.005}]}, "tunable[0].high = 0.005: must exceed"),
    ({"tunable": [{"name": "design.h", "low": -0.01, "high": 0.01, "scale": "log"}]},
     "tunable[0].low = -0.01: a log scale needs low > 0"),
    ({"tunable": [{"name": "design.m3", "low": -1, "high": 0.01}]}, "tunable[0].low (a value of design.m3) = -1"),
    ({"tunable": [{"name": "design.m3", "low": 0.005, "high": 0.01, "stride": 1}]}, "tunable[0].stride: unknown key"),
    ({"tunable": [{"name": "scene.effects.drag", "low": 0, "high": 1}]}, "not a real-valued design or scene field"),
    ({"tunable": [{"name": "design.m3", "low": 0.005, "high": 0.01}] * 2}, "listed twice"),
    ({"tunable": [{"name": "design.mu_s", "low": 0.5, "high": 1, "linked": ["design.mu_s"]}]}, "linked to itself"),
    # a linked value that is not a list is refused, even an empty-looking one (it once read as no links)
    ({"tunable": [{"name": "design.mu_s", "low": 0.5, "high": 1, "linked": ""}]}, "tunable[0].linked = '': must be a list"),
    ({"context": [{"name": "scene.rise", "low": 0.001, "high": 0.003, "linked": 0}]}, "context[0].linked = 0: must be a list"),
    ({"tunable": "design.m3"}, "tunable: must be a list"),
    ({"context": [{"name": "scene.rise", "low": 0.001}]}, "give both low and high"),
    ({"context": [{"name": "scene.rise", "low": 0.003, "high": 0.001}]}, "must be at least context[0].low"),
    ({"tolerance": [{"name": "design.m3", "relative": -0.1}]}, "tolerance[0].relative = -0.1"),
    ({"env.reward_shaping": 1.5}, "env.reward_shaping = 1.5: out of range, allowed [0.0, 0.99]"),
    ({"env.action_out_of_box": "wrap"}, "env.action_out_of_box = 'wrap': must be one of ['error', 'clip']"),
])
def test_design_problem_errors_name_the_entry(overrides, message):
    with pytest.raises(ConfigError) as exc:
        load_config(PAPER, overrides)
    assert message in str(exc.value)


def test_with_values_checks_ranges_and_cross_checks(paper_cfg):
    cfg = paper_cfg.with_values({"design.m3": 0.008, "scene.rise": 0.001})
    assert (cfg.design.m3, cfg.scene.rise, cfg.design.m2) == (0.008, 0.001, paper_cfg.design.m2)
    with pytest.raises(ConfigError, match="design.m3 = -0.1: out of range"):
        paper_cfg.with_values({"design.m3": -0.1})
    with pytest.raises(ConfigError, match="design.mu_k = 0.409: must not exceed design.mu_s = 0.3"):
        paper_cfg.with_values({"design.mu_s": 0.3})


def test_relative_ranges_follow_the_scene():
    # A 6 cm frame (La = 29 mm) is searched around its own size: 0.75-1.35 x 29 mm, not the prototype's 36-65 mm
    from aero_env.design_space import DesignSpace

    small = DesignSpace(load_config(PAPER, {"design.La": 0.029, "design.m2": 0.009}))
    proto = DesignSpace(load_config(PAPER))
    edges = [small.values(np.full(5, a)) for a in (-1.0, 1.0)]
    ends = {name: [d[name] for d in edges] for name in ("design.La", "design.h", "design.m3")}
    assert ends["design.La"] == [0.75 * 0.029, 1.35 * 0.029]
    assert ends["design.h"] == [-0.2 * 0.029, 0.4 * 0.029]  # the offset scales with the frame's arm
    assert ends["design.m3"] == [0.5 * 0.009, 1.6 * 0.009]  # the counterbalance with the robot it balances
    # the card pair is the card's, whatever the toy's size: Table 3's three measured pairs
    assert small.ranges[4] == proto.ranges[4] == (0.283, 0.542)
    assert small.tunables[4].choices == ((0.283, 0.149), (0.507, 0.337), (0.542, 0.409))
    # La is a fixed fraction of its range on either scene: the action of the config's own La is the same
    assert small.action_for()[2] == proto.action_for()[2]


def test_relative_ranges_round_trip_and_their_errors(tmp_path):
    cfg = load_config(PAPER)
    assert load_config_text(tmp_path, cfg.to_yaml()).tunable == cfg.tunable
    from aero_env.design_space import DesignSpace

    bad = [({"tunable": [{"name": "design.h", "low": 0.5, "high": 2, "relative_to": "design.h"}],
             "design.h": 0.0}, "tunable[0].relative_to = 'design.h': its value in this config is 0.0"),
           ({"tunable": [{"name": "design.m3", "low": 0.5, "high": 20, "relative_to": "design.m2"}]},
            "tunable[0].high (20 x design.m2 = 0.1542, a value of design.m3) = 0.1542: out of range, allowed (0.0, 0.1]"),
           ({"tunable": [{"name": "design.La", "low": "30 mm", "high": 2, "relative_to": "design.La"}]},
            "tunable[0].low = '30 mm': with relative_to design.La, low and high are plain numbers"),
           ({"tunable": [{"name": "design.La", "low": 0.5, "high": 2, "relative_to": "design.Lz"}]},
            "tunable[0].relative_to")]
    for overrides, message in bad:
        with pytest.raises(ConfigError) as err:
            DesignSpace(load_config(PAPER, overrides))
        assert message in str(err.value) and "\n" not in str(err.value), str(err.value)
    # simulate ignores the tunables: a scene scaled past its relative ranges still loads
    assert load_config(PAPER, {"design.m2": 0.09, "design.m3": 0.09}).design.m2 == 0.09


def load_config_text(tmp_path, text):
    p = tmp_path / "round.yaml"
    p.write_text(text)
    return load_config(p)
