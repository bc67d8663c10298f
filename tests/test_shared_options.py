"""Options every command shares are refused alike, before any work and with nothing written (issue 36).

``--seed`` is defined once (:func:`aero_env.scene_args.add_seed`); a negative seed used to reach numpy in four
commands and end in its traceback, after ``sheet`` had written half its kit.
"""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

from aero_env.cli import build_parser, main

from .conftest import PAPER
from .test_slips import one_line_error


def _commands_with(option: str):
    """(command path, parser) of every subcommand that takes ``option``, found in the parser itself."""
    def walk(parser, path):
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from walk(sub, path + (name,))
        if any(option in a.option_strings for a in parser._actions):
            yield path, parser

    return list(walk(build_parser(), ()))


def _argv(path, parser, tmp_path) -> list[str]:
    """The command with its required arguments filled in (a config, a run folder, an --out)."""
    argv = list(path)
    for action in parser._actions:
        if not action.option_strings and action.nargs is None:  # a required positional
            argv.append(str(tmp_path / "run") if action.dest == "run_dir" else str(PAPER))
        elif action.required:
            argv += [action.option_strings[0], str(tmp_path / "kit")]
    return argv


SEEDED = _commands_with("--seed")


def test_every_command_that_draws_takes_the_one_seed_option():
    names = {" ".join(path) for path, _ in SEEDED}
    assert {"robustness", "sheet", "bench accuracy", "scenes", "tune", "train", "evaluate", "calibrate"} <= names
    for path, parser in SEEDED:
        (seed,) = [a for a in parser._actions if "--seed" in a.option_strings]
        assert seed.type(str(2**31 - 1)) == 2**31 - 1, path
        with pytest.raises(argparse.ArgumentTypeError):
            seed.type("-1")


@pytest.mark.parametrize("value", ["-3", "2147483648", "1.5", "x"])
@pytest.mark.parametrize("path, parser", SEEDED, ids=[" ".join(p) for p, _ in SEEDED])
def test_a_bad_seed_is_refused_in_one_line_before_anything_is_written(path, parser, value, tmp_path, monkeypatch,
                                                                      capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main([*_argv(path, parser, tmp_path), "--seed", value])
    line = one_line_error(capsys, stop.value.code, "--seed", repr(value), "[0, 2147483647]")
    assert "usage:" not in line
    assert list(tmp_path.iterdir()) == []


def test_sheet_with_a_negative_seed_writes_no_kit(tmp_path):
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "sheet", str(PAPER), "--out", str(tmp_path / "kit"),
                           "--seed", "-3"], capture_output=True, text=True, timeout=120)
    lines = done.stderr.splitlines()
    assert done.returncode == 2 and len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert not (tmp_path / "kit").exists()


def test_a_sheet_stopped_in_its_robustness_builds_writes_neither_file(tmp_path, monkeypatch, capsys):
    import aero_env.sheet.command as sheet

    def stopped(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(sheet, "markdown", stopped)
    kit = tmp_path / "kit"
    assert main(["sheet", str(PAPER), "--out", str(kit), "--draws", "2"]) == 130
    assert not (kit / "template.svg").exists() and not (kit / "sheet.md").exists()


@pytest.mark.parametrize("command", [["tune", "--trials", "1"], ["calibrate", "--fit", "design.pivot_friction=0:2e-4"]])
def test_a_command_never_writes_its_output_config_over_the_config_it_reads(command, tmp_path, monkeypatch, capsys):
    own = tmp_path / "mine.yaml"
    own.write_text(PAPER.read_text().replace("design:", "# my notes, by hand\ndesign:", 1))
    before = own.read_bytes()
    monkeypatch.chdir(tmp_path)
    for out in ("mine.yaml", str(own), "./sub/../mine.yaml"):
        (tmp_path / "sub").mkdir(exist_ok=True)
        code = main([command[0], "mine.yaml", *command[1:], "--out", out])
        one_line_error(capsys, code, "--out", "is the config this command reads")
    assert own.read_bytes() == before


def test_a_missing_extra_is_named_as_a_missing_package_not_a_config_error(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "optuna", None)  # import optuna now raises ImportError
    code = main(["tune", str(PAPER), "--trials", "1", "--out", str(tmp_path / "b.yaml")])
    line = one_line_error(capsys, code, "aero-env: missing package:", "Optuna", "pip install -e '.[tune]'")
    assert "config error" not in line and not (tmp_path / "b.yaml").exists()


def test_a_trace_is_written_only_under_a_csv_name(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("aero_env.simulation.simulate", lambda *a, **k: pytest.fail("ran before the refusal"))
    code = main(["simulate", str(PAPER), "--trace", str(tmp_path / "x.yaml")])
    one_line_error(capsys, code, "--trace", "'.yaml'", ".csv")
    assert list(tmp_path.iterdir()) == []
