"""The slips a newcomer makes, and what each gets: one line naming the option or key, the value and what
is allowed, no traceback, exit status 2, and nothing lost (issue 16).

Most run ``aero-env`` in this process (``main([...])``) with the work itself replaced by a function that
fails the test, so that "refused before any work starts" is checked, not assumed.
"""

from __future__ import annotations

import io
import json
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

from aero_env.cli import build_parser, main
from aero_env.config import ConfigError, Design, Scene, load_config, parse_override
from aero_env.scene_args import check_output, check_output_dir

from .conftest import PAPER, ROOT

STEEP = ROOT / "configs" / "steep.yaml"


def one_line_error(capsys, code, *words):
    """The command ended with exit 2 and exactly one line on stderr holding every word."""
    err = capsys.readouterr().err
    assert code == 2, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def no_work(*_args, **_kwargs):
    raise AssertionError("the work started before the slip was refused")


# ---- output paths in a folder that does not exist: refused before any work ----
OUTPUTS = [
    (["simulate", str(PAPER), "--plot", "nodir/p.png"], "--plot", "aero_env.simulation.simulate"),
    (["simulate", str(PAPER), "--trace", "nodir/t.csv"], "--trace", "aero_env.simulation.simulate"),
    (["simulate", str(PAPER), "--gif", "nodir/a.gif"], "--gif", "aero_env.simulation.simulate"),
    (["compare", str(PAPER), "--plot", "nodir/c.png"], "--plot", "aero_env.compare.compare"),
    (["compare", str(PAPER), "--domain-map", "nodir/d.png"], "--domain-map", "aero_env.compare.compare"),
    (["bench", "accuracy", str(PAPER), "--plot", "nodir/b.png"], "--plot", "aero_env.bench.accuracy.accuracy"),
    (["tune", str(PAPER), "--out", "nodir/best.yaml"], "--out", "agents.tune.tune"),
    (["tune", str(PAPER), "--plot", "nodir/h.png"], "--plot", "agents.tune.tune"),
    (["calibrate", str(PAPER), "--targets", str(ROOT / "configs" / "paper_targets.yaml"), "--fit",
      "design.pivot_friction=0:2e-4", "--out", "nodir/c.yaml"], "--out", "aero_env.calibration.command.fit"),
]


@pytest.mark.parametrize("argv, option, work", OUTPUTS, ids=[" ".join(a[:1] + a[-2:-1]) for a, _, _ in OUTPUTS])
def test_an_output_in_a_missing_folder_is_refused_before_any_work(argv, option, work, tmp_path, monkeypatch,
                                                                   capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(work, no_work)
    line = one_line_error(capsys, main(argv), option, "nodir", "does not exist")
    assert not (tmp_path / "nodir").exists()
    # the whole line: tune's --plot lies next to --out, so its line names "--out" too ("--plot (next to --out)")
    assert line == (f"aero-env: error: {option} {argv[argv.index(option) + 1]!r}: folder 'nodir' does not exist; "
                    f"create it first or give another path")


def test_an_output_must_be_a_writable_file_of_a_known_kind(tmp_path):
    check_output(tmp_path / "fine.png", "--plot", (".png",))
    check_output(None, "--plot")
    (tmp_path / "file").write_text("")
    (tmp_path / "dir").mkdir()
    for path, words in [(tmp_path / "file" / "p.png", ["is a file, not a folder"]),
                        (tmp_path / "dir", ["is a folder"]),
                        (tmp_path / "p.xyz", ["suffix '.xyz'", ".png"])]:
        with pytest.raises(ConfigError) as exc:
            check_output(path, "--plot", (".png",))
        for w in ["--plot", *words]:
            assert w in str(exc.value)


# ---- units in --set and YAML; ranges of a card toy; "did you mean 7.7 g?" ----
@pytest.mark.parametrize("text, key, value", [
    ("design.m2=7.71g", "design.m2", 0.00771),
    ("design.m2=7.71 g", "design.m2", 0.00771),
    ("design.La=48.3 mm", "design.La", 0.0483),
    ("design.La=4.83cm", "design.La", 0.0483),
    ("design.spring_k=0.877 N*mm/rad", "design.spring_k", 0.000877),
    ("design.spring_k=0.877 N·mm/rad", "design.spring_k", 0.000877),
    ("design.pivot_friction=0.1 N*mm", "design.pivot_friction", 1e-4),
    ("design.rest_angle_deg=55 deg", "design.rest_angle_deg", 55.0),
    ("design.rest_angle_deg=55°", "design.rest_angle_deg", 55.0),
    ("sim.dt=0.5ms", "sim.dt", 0.0005),
    ("design.m2=0.008", "design.m2", 0.008),   # a plain number stays SI
    ("design.m2=8e-3", "design.m2", 0.008),    # YAML 1.1 reads this as a string: still a plain number
])
def test_set_accepts_a_value_with_its_unit(text, key, value):
    assert load_config(PAPER, dict([parse_override(text)])).value(key) == value  # exact: 48.3 mm is 0.0483


def test_map_masses_takes_units_as_set_does(capsys):
    from aero_env.cli import sweep_values

    args = build_parser().parse_args(["compare", str(PAPER), "--map-masses", "4g", "60g", "7"])
    assert sweep_values("--map-masses", args.map_masses, "kg") == (0.004, 0.06, 7.0)
    assert sweep_values("--map-masses", ["0.004", "60 g", "7"], "kg") == (0.004, 0.06, 7.0)  # plain: kg
    assert sweep_values("--map-ratios", ["0.6", "0.95", "8"], "") == (0.6, 0.95, 8.0)
    for texts, words in [(["4oz", "60g", "7"], ["--map-masses 4oz 60g 7: LO = '4oz'", "kg, g, mg"]),
                         (["4g", "60g", "7g"], ["N = '7g'", "no unit"]),
                         (["60g", "4g", "7"], ["needs 0 < LO < HI"])]:
        one_line_error(capsys, main(["compare", str(PAPER), "--domain-map", "d.png", "--map-masses", *texts]),
                       "aero-env: error: --map-masses", *words)


def test_yaml_accepts_values_with_units(tmp_path):
    p = tmp_path / "units.yaml"
    p.write_text("design:\n  m2: 7.71 g\n  La: \"48.3 mm\"\n  spring_k: 0.877 N*mm/rad\n  rest_angle_deg: 55 deg\n"
                 "scene:\n  rise: 2 mm\n  pitch: 82mm\n"
                 "tunable:\n  - {name: design.m3, low: 4 g, high: 12 g}\n"
                 "tolerance:\n  - {name: design.La, absolute: 0.3 mm}\n")
    cfg = load_config(p)
    assert (cfg.design.m2, cfg.design.La, cfg.design.spring_k) == (0.00771, 0.0483, 0.000877)
    assert (cfg.scene.rise, cfg.scene.pitch) == (0.002, 0.082)
    assert (cfg.tunable[0].low, cfg.tunable[0].high) == (0.004, 0.012)
    assert cfg.tolerance[0].absolute == 0.0003
    assert load_config(PAPER).design == load_config(p).design  # the prototype, written in its makers' units


@pytest.mark.parametrize("text, words", [
    ("design.m2=7.7", ["design.m2 = 7.7", "out of range", "(0.0, 0.1] kg", "did you mean 7.7 g?"]),
    ("design.spring_k=0.877", ["design.spring_k = 0.877", "did you mean 0.877 N*mm/rad?"]),
    ("design.La=48.3", ["design.La = 48.3", "(0.0, 1.0] m", "did you mean 48.3 mm?"]),
    ("scene.rise=5", ["scene.rise = 5", "did you mean 5 mm?"]),
    ("design.handrail_mass=0.21", ["design.handrail_mass = 0.21", "did you mean 0.21 g?"]),
])
def test_a_plain_number_in_the_smaller_unit_gets_did_you_mean(text, words, capsys):
    line = one_line_error(capsys, main(["simulate", str(PAPER), "--set", text]), *words)
    assert line.count("did you mean") == 1


@pytest.mark.parametrize("text, words", [
    ("design.m2=7.7 mm", ["design.m2 = '7.7 mm'", "unit 'mm'", "kg, g, mg"]),
    ("design.m2=7.7 oz", ["design.m2 = '7.7 oz'", "unit 'oz'"]),
    ("design.mu_s=0.5 g", ["design.mu_s = '0.5 g'", "no unit"]),
    ("design.m2=700 g", ["design.m2 = '700 g' (= 0.7 kg)", "out of range", "(0.0, 0.1] kg"]),
    ("design.m2=-1", ["design.m2 = -1.0", "out of range"]),
])
def test_a_wrong_unit_or_a_value_out_of_range_names_both(text, words, capsys):
    line = one_line_error(capsys, main(["simulate", str(PAPER), "--set", text]), *words)
    assert "did you mean" not in line  # a unit was given, or no smaller unit fits: no guess


def test_ranges_are_a_card_toys_and_the_prototypes_load():
    for cls in (Design, Scene):
        for f in cls.__dataclass_fields__.values():
            unit, hi = f.metadata.get("unit"), f.metadata.get("hi")
            if unit == "kg":
                assert hi <= 0.1, f.name      # at most 100 g
            if unit == "m":
                assert hi <= 2.0, f.name      # lengths of card (the floor may lie 2 m down)
            if unit in ("N·m/rad", "N·m"):
                assert hi <= 0.1, f.name
    for path in (PAPER, STEEP):
        load_config(path)


# ---- train: a used --out, and --hp checked before training ----
def test_train_refuses_a_used_folder_unless_overwrite(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("agents.rl.train", no_work)
    used = tmp_path / "run"
    used.mkdir()
    (used / "0.monitor.csv").write_text("")
    one_line_error(capsys, main(["train", str(PAPER), "--out", str(used)]), "--out", "not empty", "0.monitor.csv",
                   "--overwrite", "--resume")
    (tmp_path / "afile").write_text("")
    one_line_error(capsys, main(["train", str(PAPER), "--out", str(tmp_path / "afile")]), "--out", "is a file")
    check_output_dir(used, "--out", overwrite=True)  # refused only without --overwrite
    check_output_dir(tmp_path / "new" / "deeper", "--out")  # a new folder is made, parents too


def test_overwrite_removes_the_previous_runs_files(tmp_path):
    from agents.rl import clear_run

    for name in ("model.zip", "run.json", "0.monitor.csv", "3.monitor.csv", "evaluations.npz", "notes.txt"):
        (tmp_path / name).write_text("x")
    clear_run(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]  # a stale 3.monitor.csv would join the curve


@pytest.mark.parametrize("hp, words", [
    (["learning_rate=abc"], ["--hp learning_rate='abc'", "must be a number", "(0.0, 1.0]"]),
    (["n_steps=0"], ["--hp n_steps=0", "out of range", "[1, 10000000]"]),
    (["gamma=2"], ["--hp gamma=2", "out of range", "[0.0, 1.0]"]),
    (["batch_size=1"], ["--hp batch_size=1", "[2, "]),
    (["n_epochs=2.5"], ["--hp n_epochs=2.5", "whole number"]),
    (["policy_kwargs=3"], ["--hp policy_kwargs=3", "mapping"]),
    (["policy_kwargs={net_arch: [0]}"], ["net_arch", "[1, 4096]"]),
    (["n_stepz=8"], ["--hp n_stepz", "did you mean n_steps?"]),
])
def test_hyperparameters_are_checked_before_training(hp, words, monkeypatch, tmp_path, capsys):
    monkeypatch.setattr("agents.rl.train", no_work)
    argv = ["train", str(PAPER), "--out", str(tmp_path / "r")]
    for h in hp:
        argv += ["--hp", h]
    one_line_error(capsys, main(argv), *words)


def test_hyperparameters_are_read_as_their_types():
    from agents.rl import TrainSettings

    hp = dict(parse_override(t) for t in ("learning_rate=3e-4", "n_steps=32.0", "gamma=0"))
    assert isinstance(hp["learning_rate"], str)  # YAML 1.1 reads 3e-4 as a string ...
    checked = TrainSettings(hyperparameters=hp).check().hyperparameters
    assert checked == {"learning_rate": 3e-4, "n_steps": 32, "gamma": 0.0}  # ... SB3 gets the number
    assert type(checked["n_steps"]) is int
    with pytest.raises(ConfigError, match="--hp batch_size=1: out of range"):
        TrainSettings(algo="ppo", hyperparameters={"batch_size": 1}).check()
    TrainSettings(algo="sac", hyperparameters={"batch_size": 1}).check()  # SAC takes it


# ---- Ctrl-C: one line saying what was kept and how to go on ----
def _interrupt_after(monkeypatch, owner, attr: str, calls: int):
    """Replace ``owner.attr`` with itself, raising KeyboardInterrupt on call number ``calls`` (what Ctrl-C does)."""
    real = getattr(owner, attr)
    seen = [0]

    def wrapped(*args, **kwargs):
        seen[0] += 1
        if seen[0] == calls:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(owner, attr, wrapped)
    return seen


def test_ctrl_c_in_tune_keeps_the_best_so_far_and_says_how_to_resume(tmp_path, monkeypatch, capsys):
    from agents.design_eval import DesignEvaluator

    monkeypatch.chdir(tmp_path)
    _interrupt_after(monkeypatch, DesignEvaluator, "score", 4)
    argv = ["tune", str(PAPER), "--set", "scene.frames=3", "--sampler", "random", "--trials", "8", "--no-progress"]
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 130 and len(err.splitlines()) == 1 and "Traceback" not in err
    assert "interrupted after 3 of 8 trials" in err and "best.yaml" in err and "in memory" in err
    assert "--storage sqlite:///" in err
    kept = (tmp_path / "best.yaml").read_text()
    assert "trial" in kept and load_config(tmp_path / "best.yaml").scene.frames == 3
    # in a database the trials are kept, and the same command resumes
    monkeypatch.undo()
    monkeypatch.chdir(tmp_path)
    _interrupt_after(monkeypatch, DesignEvaluator, "score", 3)
    db = ["--storage", f"sqlite:///{tmp_path / 's.db'}", "--study", "s"]
    assert main(argv + db) == 130
    err = capsys.readouterr().err.strip()
    assert "interrupted after 2 of 8 trials" in err and "study 's'" in err and "rerun the same command" in err
    monkeypatch.undo()
    monkeypatch.chdir(tmp_path)
    assert main(argv + db + ["--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["trials"], out["trials_run"]) == (8, 6)  # the 2 kept, 6 more: none redone


def test_real_ctrl_c_in_tune_ends_with_one_line(tmp_path):
    db = tmp_path / "s.db"
    proc = subprocess.Popen([sys.executable, "-m", "aero_env.cli", "tune", str(PAPER), "--set", "scene.frames=3",
                             "--sampler", "random", "--trials", "100000", "--no-progress", "--storage",
                             f"sqlite:///{db}", "--study", "s"], cwd=tmp_path, stderr=subprocess.PIPE, text=True,
                            # a shell without job control starts `pytest &` with SIGINT ignored, which the child
                            # would inherit: give it the default a terminal's process has
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:  # a failed wait must not leave a 100,000-trial study running for the rest of the suite
        deadline = time.time() + 120
        done = 0
        while time.time() < deadline and done < 2:
            time.sleep(0.5)
            if db.exists():
                try:
                    with sqlite3.connect(db) as con:
                        done = con.execute("select count(*) from trials where state = 'COMPLETE'").fetchone()[0]
                except sqlite3.Error:
                    pass
        assert done >= 2, "the study never finished two trials"
        proc.send_signal(signal.SIGINT)
        err = proc.communicate(timeout=120)[1]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 130, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    assert "aero-env tune: interrupted after" in lines[0] and "rerun the same command" in lines[0]
    assert (tmp_path / "best.yaml").is_file()


def test_ctrl_c_in_train_keeps_the_policy_and_resume_goes_on(tmp_path, monkeypatch, capsys):
    from aero_env.envs import AerialAcrobatEnv

    _interrupt_after(monkeypatch, AerialAcrobatEnv, "step", 40)
    out = tmp_path / "run"
    argv = ["train", str(PAPER), "--set", "scene.frames=3", "--timesteps", "64", "--eval-every", "16",
            "--hp", "n_steps=16", "--hp", "batch_size=16", "--hp", "n_epochs=1", "--out", str(out), "--no-progress"]
    assert main(argv) == 130
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert "interrupted at" in err and "of 64 timesteps" in err and "--resume" in err
    run = json.loads((out / "run.json").read_text())
    assert run["interrupted"] and 16 <= run["timesteps_done"] < 64 and (out / "model.zip").is_file()
    # the same command again is refused (the folder holds a run) ...
    one_line_error(capsys, main(argv), "--out", "not empty", "--resume")
    # ... and with --resume goes on to the 64 timesteps, its evaluations kept
    monkeypatch.undo()
    assert main(argv + ["--resume", "--json"]) == 0
    done = json.loads(capsys.readouterr().out)
    assert 64 <= done["timesteps_done"] < 64 + 16 and not done.get("interrupted")  # PPO's rollouts: 16 steps
    import numpy as np

    ev = np.load(out / "evaluations.npz")
    assert ev["timesteps"][0] == 16 and len(ev["timesteps"]) >= 3  # the first run's evaluation, then the resumed
    assert list(ev["timesteps"]) == sorted(ev["timesteps"])
    assert (out / "r1-0.monitor.csv").is_file() and (out / "0.monitor.csv").is_file()
    # a resume with other settings is refused
    one_line_error(capsys, main(argv + ["--resume", "--seed", "3", "--timesteps", "96"]), "--seed 3", "resume it")


def test_ctrl_c_elsewhere_is_one_line(monkeypatch, capsys):
    def interrupted(*_a, **_k):
        raise KeyboardInterrupt

    monkeypatch.setattr("aero_env.simulation.simulate", interrupted)
    try:
        code = main(["simulate", str(PAPER)])
    except KeyboardInterrupt:
        pytest.fail("Ctrl-C came out of main() as a traceback")
    assert code == 130
    assert capsys.readouterr().err.strip() == "aero-env simulate: interrupted"


# ---- config files: malformed, empty, a folder ----
@pytest.mark.parametrize("content, words", [
    ("design:\n  m2: 0.008\n  m3: [1, 2\n", ["bad.yaml", "line 4", "not valid YAML", "from line 3"]),
    ("design:\n  m2: 0.008\n\tm3: 0.007\n", ["bad.yaml", "line 3", "not valid YAML"]),
    ("", ["bad.yaml", "empty"]),
    ("# only a comment\n", ["bad.yaml", "empty"]),
    ("- design\n", ["bad.yaml", "must be a YAML mapping", "got a list"]),
    (b"\xff\xfe\x00binary", ["bad.yaml", "not a text file"]),
])
def test_a_bad_config_file_is_named_with_its_line(content, words, tmp_path, capsys):
    p = tmp_path / "bad.yaml"
    p.write_bytes(content) if isinstance(content, bytes) else p.write_text(content)
    one_line_error(capsys, main(["simulate", str(p)]), *words)


@pytest.mark.parametrize("argv, start", [
    (["simulate", str(PAPER), "--set", "design.Lb=5"], "aero-env: config error: design.Lb = 5.0: out of range"),
    (["simulate", "missing.yaml"], "aero-env: file error: config file 'missing.yaml': not found"),
    (["simulate", str(PAPER), "--plot", "p.xyz"], "aero-env: error: --plot 'p.xyz': suffix '.xyz'"),
    (["simulate", str(PAPER), "--set", "design.Lb"], "aero-env: error: --set 'design.Lb': expected KEY=VALUE"),
])
def test_a_refusal_names_its_kind_an_option_a_file_or_a_config_value(argv, start, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("aero_env.simulation.simulate", no_work)
    assert one_line_error(capsys, main(argv)).startswith(start)


def test_a_folder_given_as_config_is_named(capsys):
    one_line_error(capsys, main(["simulate", str(ROOT / "configs")]), "configs", "is a folder")


# ---- unknown keys: did you mean ...? ----
@pytest.mark.parametrize("overrides, words", [
    ({"design.m_2": 0.008}, ["design.m_2: unknown key", "did you mean design.m2?"]),
    ({"design.spring": 0.001}, ["did you mean design.spring_k?"]),
    ({"scene.effects.dragg": True}, ["did you mean scene.effects.drag?"]),
    ({"desing.m2": 0.008}, ["'desing.m2'", "did you mean design.m2?"]),
    ({"tunable": [{"name": "design.m4", "low": 0.004, "high": 0.01}]}, ["'design.m4'", "did you mean design.m3?"]),
    ({"tunable": [{"name": "design.m3", "lo": 0.004, "high": 0.01}]}, ["tunable[0].lo", "did you mean low?"]),
])
def test_an_unknown_key_gets_the_closest_one(overrides, words):
    with pytest.raises(ConfigError) as exc:
        load_config(PAPER, overrides)
    text = str(exc.value)
    for w in words:
        assert w in text
    assert "design.Cd" not in text  # not the whole list of keys


def test_an_unknown_section_in_a_file_gets_the_closest_one(tmp_path):
    p = tmp_path / "typo.yaml"
    p.write_text("desing:\n  m2: 0.008\n")
    with pytest.raises(ConfigError, match="desing: unknown section; did you mean design?"):
        load_config(p)


# ---- resuming a study with another sampler ----
def test_resuming_a_study_with_another_sampler_is_refused(tmp_path, capsys):
    base = ["tune", str(PAPER), "--set", "scene.frames=3", "--trials", "2", "--no-progress", "--storage",
            f"sqlite:///{tmp_path / 's.db'}", "--study", "s", "--out", str(tmp_path / "b.yaml")]
    assert main(base + ["--sampler", "random"]) == 0
    capsys.readouterr()
    one_line_error(capsys, main(base + ["--sampler", "tpe", "--trials", "4"]), "--sampler tpe", "study 's'",
                   "--sampler random")


# ---- the command line ----
def test_version():
    from importlib.metadata import version

    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "--version"], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.strip() == f"aero-env {version('aero-env')}"


def _parsers(parser, path=("aero-env",)):
    import argparse

    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _parsers(sub, path + (name,))


def test_every_option_has_help_and_shows_its_default():
    import argparse

    checked = 0
    for path, parser in _parsers(build_parser()):
        formatter = parser._get_formatter()
        for action in parser._actions:
            if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
                continue
            where = " ".join(path) + " " + (action.option_strings or [action.dest])[0]
            assert action.help, f"{where}: no help"
            text = formatter._expand_help(action)
            if action.option_strings and action.default is not None and action.default is not False \
                    and action.default != argparse.SUPPRESS:
                assert "default" in text, f"{where}: default {action.default!r} not shown"
            checked += 1
    assert checked > 80


@pytest.mark.parametrize("argv, option, choices", [
    (["tune", str(PAPER), "--sampler", "grid"], "--sampler", ["cmaes", "tpe", "random"]),
    (["tune", str(PAPER), "--screen", "exact"], "--screen", ["reduced", "reference"]),
    (["train", str(PAPER), "--algo", "dqn"], "--algo", ["ppo", "sac"]),
])
def test_fixed_choices_are_argparse_choices_and_errors_are_one_line(argv, option, choices, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    line = one_line_error(capsys, stop.value.code, option, "invalid choice", *choices)
    assert "usage:" not in line


def test_bench_accuracy_shows_progress_on_stderr_and_keeps_json_on_stdout(tmp_path):
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "bench", "accuracy", str(PAPER), "--set",
                           "scene.frames=2", "--designs", "2", "--repeats", "1", "--fidelities", "reduced", "--json"],
                          capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["designs"] == 2
    assert "reduced: " in done.stderr and "reference: " in done.stderr and "for 2 designs" in done.stderr


def test_bench_accuracy_draws_a_bar_over_the_designs_on_a_terminal():
    from aero_env.bench.commands import DesignProgress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    term = Terminal()
    bar = DesignProgress(term)
    for i in range(1, 4):
        bar.design("mbd", i, 4)
    assert "\r" in term.getvalue() and "3/4 designs" in term.getvalue() and "[" in term.getvalue()
    plain = io.StringIO()
    DesignProgress(plain).design("mbd", 1, 4)
    assert plain.getvalue() == ""  # a log file gets the one line per fidelity only


def test_simulate_gif_says_it_is_encoding(tmp_path):
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "simulate", str(PAPER), "--set", "scene.frames=2",
                           "--gif", "a.gif"], capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "encoding" in done.stderr and "a.gif" in done.stderr
    assert (tmp_path / "a.gif").stat().st_size > 0


def test_the_commands_do_not_import_the_command_line():
    code = ("import sys, aero_env.bench.commands, agents.commands, aero_env.calibration.command, "
            "aero_env.robustness.command, aero_env.limit_cycle.command; "
            "assert 'aero_env.cli' not in sys.modules, 'a command module imports aero_env.cli'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    for path in ["aero_env/bench/commands.py", "agents/commands.py", "aero_env/calibration/command.py",
                 "aero_env/robustness/command.py", "aero_env/limit_cycle/command.py"]:
        text = (ROOT / path).read_text()
        assert "..cli import" not in text and "aero_env.cli import" not in text, path
