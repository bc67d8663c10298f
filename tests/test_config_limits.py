"""Inputs in the schema's range, or sized to hurt, end in one line: a design whose parts cannot be cut, a YAML bomb,
a nesting deeper than Python's stack, a value too big to print. None reaches Chipmunk's asserts (which abort the
process), eats the machine's memory or prints a traceback."""

from __future__ import annotations

import math
import resource
import subprocess
import sys

import numpy as np
import pytest

from aero_env.config import ConfigError, load_config, parse_override
from aero_env.config.loading import MAX_YAML_DEPTH, MAX_YAML_NODES
from aero_env.config.validation import SHOWN_MAX

from .conftest import PAPER

GRAMMAGE = 0.310  # kg/m²: the paper's card (JOHOKU WB310g), as the tests read it off the article
HOLE = 2.4e-3  # m: the kit's skewer and axle holes
END, LIP = 4e-3, 3e-3  # m: card past a hole, the hook's folded lip (docs/make-your-own.md)


def _lightest(length: float) -> float:
    """A plate ``length`` long, one layer as wide as its hole, less the hole: the least card that holds it."""
    return GRAMMAGE * (HOLE * length - math.pi * (HOLE / 2) ** 2)


# ---- designs whose parts cannot be cut ----------------------------------------------------------------------------
@pytest.mark.filterwarnings("ignore::aero_env.config.UnitSlipWarning")  # 26 mg is 57x below the prototype's arm
def test_an_arm_lighter_than_its_narrowest_card_is_refused_in_one_line_naming_the_lightest(paper_cfg):
    lightest = _lightest(END + paper_cfg.design.arm_length + LIP)  # 26.1 mg over the prototype's 37 mm net
    with pytest.raises(ConfigError) as err:
        load_config(PAPER, {"design.arm_mass": 1e-6})  # in the schema's (0, 0.1] kg; Chipmunk aborted on it
    assert str(err.value).startswith("design.arm_mass = 1e-06: lighter than an arm of one layer")
    assert f"allowed [{lightest:.4g}, 0.1] kg" in str(err.value) and "\n" not in str(err.value)
    load_config(PAPER, {"design.arm_mass": lightest * (1 + 1e-9)})  # just heavier: a part, and it loads
    with pytest.raises(ConfigError):
        load_config(PAPER, {"design.arm_mass": lightest * (1 - 1e-9)})


def test_side_cards_and_a_torso_lighter_than_their_narrowest_card_are_refused(paper_cfg):
    d = paper_cfg.design
    frame = 2 * _lightest(2 * (max(d.La, d.Lb) + END))  # two side cards, symmetric about the skewer
    with pytest.raises(ConfigError, match=rf"^design.m1 = 0.0001: .* allowed \[{frame:.4g}, 0.1\] kg$"):
        load_config(PAPER, {"design.m1": 1e-4})
    load_config(PAPER, {"design.m1": frame * (1 + 1e-9)})
    # the torso: its bottom Ld = 60 mm from the hook at alpha_max (law of cosines), END above the axle
    a = math.radians(d.alpha_max_deg)
    torso = math.sqrt(d.Ld**2 - (d.arm_length * math.sin(a)) ** 2) + d.arm_length * math.cos(a)  # hook 15 mm up
    least_m2 = d.arm_mass + d.coin_mass + d.handrail_mass + _lightest(END + torso)
    with pytest.raises(ConfigError, match=rf"^design.m2 = 0.00572: leaves 0.01 g of torso card .* allowed \[{least_m2:.6g}, "):
        load_config(PAPER, {"design.m2": 0.00572})
    load_config(PAPER, {"design.m2": least_m2 * (1 + 1e-9)})


def test_a_frame_moment_beyond_the_cards_radius_of_gyration_is_refused(paper_cfg):
    """A body's centre of mass is never farther from an axis than its radius of gyration about it: dT puts the
    frame card's centre at dT/(m1·g), and the side cards' inertia about the skewer is fixed by their shape (the
    article's hollow frame, A13's)."""
    d = paper_cfg.design
    I1 = 2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb)  # A13: the kit's hollow side cards swing so (test_kit)
    limit = 9.81 * math.sqrt(d.m1 * I1)  # 1.60e-3 N·m on the prototype, below m1·g·Lb = 2.03e-3
    assert limit == pytest.approx(1.605e-3, abs=5e-6)
    load_config(PAPER, {"design.dT": limit * (1 - 1e-9)})
    for dT in (limit * (1 + 1e-6), -limit * (1 + 1e-6)):
        with pytest.raises(ConfigError, match=rf"allowed \[{-limit:.3g}, {limit:.3g}\] N·m"):
            load_config(PAPER, {"design.dT": dT})


def test_designs_as_arrays_are_refused_at_the_first_that_cannot_be_cut(paper_cfg):
    from types import SimpleNamespace

    from aero_env.config.sections import check_design

    d = paper_cfg.design
    arrays = SimpleNamespace(**{f: np.full(3, getattr(d, f)) for f in d.__dataclass_fields__})
    arrays.arm_mass = np.array([d.arm_mass, 1e-6, 1e-7])
    with pytest.raises(ConfigError, match=r"^design.arm_mass\[1\] = 1e-06: lighter than an arm"):
        check_design(arrays)


def test_the_world_never_gives_chipmunk_a_body_without_mass_or_inertia(paper_cfg):
    """The last guard: a body that still comes out massless is one line, not SIGABRT (Chipmunk's hard assert)."""
    from aero_env.physics.engine_params import rigid_body

    with pytest.raises(ConfigError, match=r"^design \(design.arm_mass\): the arm comes out with mass 1e-06 kg and "
                                          r"inertia -1e-12 kg·m² about its centre; .*positive and finite$"):
        rigid_body(1e-6 * 1e3, -1e-12 * 1e9, "arm", "design.arm_mass")  # engine units: g and g·mm²
    with pytest.raises(ConfigError, match="inertia nan kg"):
        rigid_body(1.0, math.nan, "arm", "design.arm_mass")
    assert rigid_body(1.5, 2.5, "arm", "design.arm_mass").moment == 2.5


# ---- YAML sized to hurt -------------------------------------------------------------------------------------------
def _alias_bomb(levels: int = 9, width: int = 9) -> str:
    """The "billion laughs": each level a list of ``width`` aliases of the one before; 341 bytes expand to 9**9."""
    text = "a: &a [" + ", ".join(["lol"] * width) + "]\n"
    for prev, name in zip("abcdefghij", "bcdefghijk"[:levels - 1]):
        text += f"{name}: &{name} [" + ", ".join([f"*{prev}"] * width) + "]\n"
    return text + f"design:\n  m2: *{'abcdefghij'[levels - 1]}\n"


def _mapping_bomb() -> str:
    """The same with mappings: a config copies mappings (``_deep_copy``), so each alias became a real copy."""
    text = "a: &a {" + ", ".join(f"k{j}: 1" for j in range(9)) + "}\n"
    for prev, name in zip("abcdefgh", "bcdefghi"):
        text += f"{name}: &{name} {{" + ", ".join(f"k{j}: *{prev}" for j in range(9)) + "}\n"
    return text + "design: *i\n"


def _run_limited(args, cwd, memory_mb: int = 1500):
    """``aero-env ARGS`` in a child that may use ``memory_mb`` of address space: a bomb that expands dies of
    MemoryError with a traceback instead of swapping the machine."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))

    return subprocess.run([sys.executable, "-m", "aero_env.cli", *args], cwd=cwd, preexec_fn=limit,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("name,text,why", [
    ("alias", _alias_bomb(), f"line 6: its aliases expand it to more than {MAX_YAML_NODES:,} values"),
    ("mapping", _mapping_bomb(), f"line 5: its aliases expand it to more than {MAX_YAML_NODES:,} values"),
    ("deep", "design: " + "[" * 5000 + "]" * 5000 + "\n", f"line 1: nested more than {MAX_YAML_DEPTH} levels deep"),
    ("recursive", "design: &a\n  m2: *a\n", "line 2: the alias *a lies inside the node &a names"),
])
def test_a_yaml_bomb_or_a_deep_nesting_is_one_line_within_little_memory(tmp_path, name, text, why):
    (tmp_path / "bomb.yaml").write_text(text)
    r = _run_limited(["simulate", "bomb.yaml"], tmp_path)
    assert r.returncode == 2, r.stderr[-2000:]
    assert r.stderr.startswith(f"aero-env: file error: config file 'bomb.yaml', {why}") and r.stderr.count("\n") == 1


def test_set_values_are_measured_as_files_are():
    assert parse_override("design.m2=[&a 1, *a]") == ("design.m2", [1, 1])  # a small alias is fine
    with pytest.raises(ConfigError) as err:
        parse_override("design.m2=" + "[" * 40 + "1" + "]" * 40)
    message = str(err.value)
    assert message.startswith("--set 'design.m2=[[[[") and message.endswith(
        f"(91 characters): nested more than {MAX_YAML_DEPTH} levels deep (a config nests 5)")
    # the billion laughs in one line: nine lists, each of nine aliases of the one before
    bomb = "[" + ", ".join(f"&x{i} [" + ", ".join([f"*x{i - 1}"] * 9 if i else ["1"] * 9) + "]" for i in range(9)) + "]"
    with pytest.raises(ConfigError, match=f"characters\\): its aliases expand it to more than {MAX_YAML_NODES:,} values"):
        parse_override(f"design.m2={bomb}")


def test_the_node_limit_is_exact():
    # "a" holds k scalars; "b" holds m aliases of it: nodes = document 1 + key a 1 + (1 + k) + key b 1 + b's list 1
    # + m·(1 + k)
    k, m = 99, 999
    nodes = 1 + 1 + (1 + k) + 1 + 1 + m * (1 + k)
    assert nodes == 100_004
    from aero_env.config.loading import YamlTooBig, check_yaml_shape

    def doc(m):
        return "a: &a [" + ", ".join(["1"] * k) + "]\nb: [" + ", ".join(["*a"] * m) + "]\n"

    with pytest.raises(YamlTooBig):
        check_yaml_shape(doc(m))
    check_yaml_shape(doc(m - 1))  # 99,904 nodes
    # and nesting: 32 mappings or sequences deep is read, 33 is not, with aliases expanded too
    check_yaml_shape("[" * 32 + "]" * 32)
    with pytest.raises(YamlTooBig):
        check_yaml_shape("[" * 33 + "]" * 33)
    with pytest.raises(YamlTooBig, match="once its aliases are expanded"):
        check_yaml_shape("a: &a " + "[" * 16 + "]" * 16 + "\nb: " + "[" * 16 + "*a" + "]" * 16)
    check_yaml_shape("a: &a " + "[" * 16 + "]" * 16 + "\nb: " + "[" * 15 + "*a" + "]" * 15)


def test_a_huge_value_is_shown_cut_short_with_its_size():
    with pytest.raises(ConfigError) as err:
        load_config(PAPER, {"design.m2": list(range(1_000_000))})
    assert str(err.value).startswith("design.m2 = [0, 1, 2, 3, 4, 5, 6, 7, ...] (1,000,000 items): must be a number")
    with pytest.raises(ConfigError) as err:
        load_config(PAPER, {"scene.effects.hook": "x" * 10**6})
    assert "(1,000,000 characters): must be one of ['contact', 'pin']" in str(err.value)
    assert len(str(err.value)) < SHOWN_MAX + 100
