"""A run's files damaged on disk (issue 50): ``aero-env evaluate DIR`` and ``aero-env train --resume`` end in one
line that names the file and says what to do, with exit status 2, and a refused resume leaves the folder exactly as
it found it (most ended in a traceback of 17-35 lines, and a refused resume left a new monitor file behind).

Two small runs are trained once for the module, a finished PPO run with its periodic evaluations and a SAC run
stopped by Ctrl-C (which keeps its replay buffer); each test copies one and damages one file as a copy cut short,
a disk or a hand edit would.
"""

from __future__ import annotations

import json
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest

from aero_env.cli import main

from .conftest import PAPER

SCENE = ["--set", "scene.frames=2", "--no-progress"]
PPO = ["train", str(PAPER), *SCENE, "--eval-every", "16", "--hp", "n_steps=16", "--hp", "batch_size=16", "--hp",
       "n_epochs=1"]
SAC = ["train", str(PAPER), *SCENE, "--algo", "sac", "--eval-every", "0", "--hp", "learning_starts=4", "--hp",
       "batch_size=4"]


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> Path:
    from aero_env.envs import AerialAcrobatEnv

    root = tmp_path_factory.mktemp("runs")
    assert main([*PPO, "--timesteps", "16", "--out", str(root / "ppo")]) == 0
    real, steps = AerialAcrobatEnv.step, [0]

    def step_then_ctrl_c(self, action):
        steps[0] += 1
        if steps[0] == 9:
            raise KeyboardInterrupt
        return real(self, action)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(AerialAcrobatEnv, "step", step_then_ctrl_c)
        assert main([*SAC, "--timesteps", "64", "--out", str(root / "sac")]) == 130
    assert (root / "sac" / "replay_buffer.pkl").is_file() and (root / "ppo" / "evaluations.npz").is_file()
    return root


def _copy(runs: Path, tmp_path: Path, algo: str = "ppo") -> Path:
    run = tmp_path / algo
    shutil.copytree(runs / algo, run)
    return run


# ---- the damage: each a function of the file's path ----
def cut(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def empty(path: Path) -> None:
    path.write_bytes(b"")


def random_bytes(path: Path) -> None:
    path.write_bytes(np.random.default_rng(50).bytes(max(path.stat().st_size, 64)))


def cut_member(name: str):
    """model.zip rewritten whole (a valid zip) with its member ``name`` cut in half."""
    def damage(path: Path) -> None:
        with zipfile.ZipFile(path) as z:
            members = {n: z.read(n) for n in z.namelist()}
        members[name] = members[name][: len(members[name]) // 2]
        with zipfile.ZipFile(path, "w") as z:
            for n, data in members.items():
                z.writestr(n, data)
    damage.__name__ = f"cut_{name.replace('.', '_')}"
    return damage


def edited(**changes):
    """run.json with fields changed (None: removed)."""
    def damage(path: Path) -> None:
        run = json.loads(path.read_text())
        for key, value in changes.items():
            run.pop(key) if value is None else run.__setitem__(key, value)
        path.write_text(json.dumps(run))
    damage.__name__ = "_".join(("without_" if v is None else "edited_") + k for k, v in changes.items())
    return damage


def written(text: str, name: str):
    def damage(path: Path) -> None:
        path.write_text(text)
    damage.__name__ = name
    return damage


def npz_without_results(path: Path) -> None:
    with np.load(path) as old:
        timesteps = old["timesteps"]
    with open(path, "wb") as f:
        np.savez(f, timesteps=timesteps)


def _files(folder: Path) -> dict[str, bytes]:
    """Every file in ``folder`` (hidden ones too) and its bytes."""
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def _refused(capsys, code: int, path: Path, *words: str) -> None:
    """Exit 2 and one line on stderr, no traceback: a file error naming ``path``, holding ``words``, and saying how
    to train the run again (the remedy for every file, the only one for most)."""
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith(f"aero-env: file error: run file {str(path)!r}: ") or \
        lines[0].startswith(f"aero-env: file error: config file {str(path)!r}"), lines[0]
    for w in (*words, f"train the run again (aero-env train ... --out {path.parent} --overwrite)"):
        assert w in lines[0], (w, lines[0])


# (the file, the damage, words its line must hold besides the file's name)
MODEL = [("model.zip", d, ["not a policy that loads"])
         for d in (cut, empty, random_bytes, cut_member("policy.pth"), cut_member("data"))]
RUN_JSON = [("run.json", cut, ["JSONDecodeError"]),
            ("run.json", empty, ["not the run's JSON record"]),
            ("run.json", random_bytes, ["not the run's JSON record"]),
            ("run.json", written("[1, 2]", "a_list"), ["a JSON list, not the run's record"]),
            ("run.json", edited(algo=None), ["no 'algo' field"]),
            ("run.json", edited(algo="dqn"), ["algo = 'dqn': must be one of ppo, sac"]),
            ("run.json", edited(timesteps_done="abc"), ["timesteps_done = 'abc': must be a whole number"]),
            ("run.json", edited(n_envs=True), ["n_envs = True: must be a whole number"]),
            ("run.json", edited(seed=-1), ["seed = -1: must be a whole number >= 0"]),
            ("run.json", edited(hyperparameters=[1]), ["hyperparameters = [1]: must be a JSON object"]),
            ("run.json", edited(wall_time="1 s"), ["wall_time = '1 s': must be a number"]),
            ("run.json", edited(init_from={"fidelity": "reduced"}), ["init_from has no 'dir'"])]
CONFIG = [("config.yaml", d, ["cut or changed since the run was trained"])
          for d in (cut, empty, random_bytes, written("design:\n  m3: 0.0073\n", "edited_by_hand"))]
# a run written before run.json recorded its config's sha256 (the shipped policies): the file's own error
OLD_CONFIG = [("config.yaml", empty, ["config file", "empty"]),
              ("config.yaml", written("design: [1,\n", "not_yaml"), ["not valid YAML"]),
              ("config.yaml", written("design:\n  m3: -5\n", "out_of_range"), ["design.m3 = -5.0: out of range"])]


def _ids(cases):
    return [f"{name}-{damage.__name__}" for name, damage, _ in cases]


def _damage(run: Path, name: str, damage, old: bool = False) -> Path:
    if old:
        edited(config_sha256=None)(run / "run.json")
    damage(run / name)
    return run / name


@pytest.mark.parametrize("name, damage, words", MODEL + RUN_JSON + CONFIG, ids=_ids(MODEL + RUN_JSON + CONFIG))
def test_evaluate_names_the_damaged_file_in_one_line(name, damage, words, runs, tmp_path, capsys):
    path = _damage(_copy(runs, tmp_path), name, damage)
    _refused(capsys, main(["evaluate", str(path.parent), "--episodes", "1"]), path, *words)


@pytest.mark.parametrize("name, damage, words", OLD_CONFIG, ids=_ids(OLD_CONFIG))
def test_evaluate_of_a_run_without_the_configs_sha256_names_its_damaged_config(name, damage, words, runs, tmp_path,
                                                                               capsys):
    path = _damage(_copy(runs, tmp_path), name, damage, old=True)
    _refused(capsys, main(["evaluate", str(path.parent), "--episodes", "1"]), path, *words)
    # with --set, the file's own error, not the override's
    _refused(capsys, main(["evaluate", str(path.parent), "--episodes", "1", "--set", "scene.frames=3"]), path, *words)


def test_evaluate_with_set_names_a_cut_config(runs, tmp_path, capsys):
    path = _damage(_copy(runs, tmp_path), "config.yaml", cut)
    _refused(capsys, main(["evaluate", str(path.parent), "--set", "scene.frames=3"]), path, "cut or changed")


EVALUATIONS = [("evaluations.npz", d, ["not the run's evaluations", "remove it to resume without the evaluations"])
               for d in (cut, random_bytes, npz_without_results)]
RESUMED = MODEL + RUN_JSON + CONFIG + EVALUATIONS


@pytest.mark.parametrize("name, damage, words", RESUMED, ids=_ids(RESUMED))
def test_resume_names_the_damaged_file_and_leaves_the_folder_as_it_was(name, damage, words, runs, tmp_path, capsys):
    path = _damage(_copy(runs, tmp_path), name, damage)
    before = _files(path.parent)
    _refused(capsys, main([*PPO, "--timesteps", "32", "--out", str(path.parent), "--resume"]), path, *words)
    assert _files(path.parent) == before  # no monitor file of the refused segment, nothing rewritten


@pytest.mark.parametrize("name, damage, words", OLD_CONFIG, ids=_ids(OLD_CONFIG))
def test_resume_of_a_run_without_the_configs_sha256_names_its_damaged_config(name, damage, words, runs, tmp_path,
                                                                             capsys):
    path = _damage(_copy(runs, tmp_path), name, damage, old=True)
    before = _files(path.parent)
    _refused(capsys, main([*PPO, "--timesteps", "32", "--out", str(path.parent), "--resume"]), path, *words)
    assert _files(path.parent) == before


@pytest.mark.parametrize("damage", [cut, random_bytes])
def test_resume_names_a_damaged_replay_buffer_and_goes_on_once_it_is_removed(damage, runs, tmp_path, capsys):
    run = _copy(runs, tmp_path, "sac")
    path = _damage(run, "replay_buffer.pkl", damage)
    before = _files(run)
    argv = [*SAC, "--timesteps", "16", "--out", str(run), "--resume"]
    _refused(capsys, main(argv), path, "not a replay buffer that loads", "remove it to resume with an empty buffer")
    assert _files(run) == before
    path.unlink()  # what the line says to do
    assert main(argv) == 0
    assert json.loads((run / "run.json").read_text())["timesteps_done"] >= 16


def test_resume_goes_on_once_damaged_evaluations_are_removed(runs, tmp_path, capsys):
    run = _copy(runs, tmp_path)
    path = _damage(run, "evaluations.npz", cut)
    _refused(capsys, main([*PPO, "--timesteps", "32", "--out", str(run), "--resume"]), path,
             "remove it to resume without the evaluations so far")
    path.unlink()
    assert main([*PPO, "--timesteps", "32", "--out", str(run), "--resume"]) == 0
    with np.load(path) as ev:
        assert list(ev["timesteps"]) == [32]  # the resumed segment's own evaluation only


def test_a_damaged_monitor_file_costs_its_rows_not_the_resume(runs, tmp_path, capsys):
    """The learning curve reads every monitor file; one of random bytes is read for the rows that parse."""
    from agents.rl import _monitor_rewards

    run = _copy(runs, tmp_path)
    rows = len((run / "0.monitor.csv").read_text().splitlines()) - 2  # the JSON head and the header r,l,t
    random_bytes(run / "0.monitor.csv")
    assert main([*PPO, "--timesteps", "32", "--out", str(run), "--resume"]) == 0
    assert rows == 16 and len(_monitor_rewards(run)) == 16  # the resumed segment's 16 episodes (r1-0.monitor.csv)
    assert (run / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_init_from_a_damaged_run_names_its_file(runs, tmp_path, capsys):
    start = _copy(runs, tmp_path)
    edited(hyperparameters=None)(start / "run.json")
    code = main([*PPO, "--timesteps", "16", "--out", str(tmp_path / "new"), "--init-from", str(start)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert f"--init-from {str(start)!r}: run file {str(start / 'run.json')!r}: no 'hyperparameters' field" in err
    assert not (tmp_path / "new").exists()


def test_a_written_runs_config_sha256_is_its_config_yaml(runs):
    import hashlib

    run = json.loads((runs / "ppo" / "run.json").read_text())
    assert run["config_sha256"] == hashlib.sha256((runs / "ppo" / "config.yaml").read_bytes()).hexdigest()


def test_a_long_reason_is_cut_to_keep_one_line():
    from agents.rl import _why

    assert _why(KeyError("algo")) == "KeyError: 'algo'"
    assert _why(ValueError()) == "ValueError"
    assert _why(ValueError("first\nsecond")) == "ValueError: first"
    long = _why(RuntimeError("x" * 150))
    assert long == "RuntimeError: " + "x" * 97 + "..."
    assert _why(RuntimeError("y" * 100)) == "RuntimeError: " + "y" * 100
