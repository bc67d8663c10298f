"""What a newcomer's first script meets, run as that script in its own process (issue 26 §2): a vector env made at
the top of a file with no ``if __name__ == "__main__":`` runs; asking such a script for a process pool ends with a
line naming the guard, not a broken pool."""

from __future__ import annotations

import os
import subprocess
import sys

from aero_env.envs.aerial_acrobat_vector import GUARD

from .conftest import ROOT

VECTOR_SCRIPT = """\
import gymnasium as gym
import numpy as np
import aero_env

envs = gym.make_vec("aero_env/AerialAcrobat-v0", num_envs=4{workers}, **{{"scene.frames": 3, "sim.dt": 0.001}})
obs, info = envs.reset(seed=0)
obs, rewards, terminated, truncated, info = envs.step(np.zeros((4, envs.single_action_space.shape[0]), np.float32))
print("rewards", rewards.tolist())
envs.close()
"""


def _run_script(tmp_path, text: str, env: dict | None = None) -> subprocess.CompletedProcess:
    script = tmp_path / "plain.py"
    script.write_text(text)
    environ = {**os.environ, "PYTHONPATH": str(ROOT), **(env or {})}
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path, env=environ,
                          timeout=300)


def test_make_vec_in_a_script_without_the_main_guard_runs(tmp_path):
    done = _run_script(tmp_path, VECTOR_SCRIPT.format(workers=""))
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("rewards [") and done.stdout.count("\n") == 1, done.stdout
    assert "Traceback" not in done.stderr


def test_a_pool_asked_for_by_a_script_without_the_guard_is_refused_with_one_line_naming_it(tmp_path):
    done = _run_script(tmp_path, VECTOR_SCRIPT.format(workers=", workers=2"))
    assert done.returncode == 1
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("aero_env.config.ConfigError: workers = 2: ") and GUARD in last, done.stderr
    assert "BrokenProcessPool" not in done.stderr and "bootstrapping" not in done.stderr, done.stderr
    assert done.stdout == ""


def test_a_guarded_script_that_makes_the_pool_outside_its_guard_gets_a_line_naming_it(tmp_path):
    text = VECTOR_SCRIPT.format(workers=", workers=2") + '\nif __name__ == "__main__":\n    print("done")\n'
    done = _run_script(tmp_path, text)
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert lines[-1].startswith("RuntimeError: the pool's worker processes ended") and GUARD in lines[-1], done.stderr
    # each worker says why in one line, without multiprocessing's traceback about bootstrapping
    assert any(ln.startswith("aero-env: error: workers = 2: this script made a pooled vector env outside")
               for ln in lines), done.stderr
    assert "bootstrapping" not in done.stderr and "BrokenProcessPool" not in done.stderr, done.stderr


CHECK_ENV_SCRIPT = """\
import sys
import gymnasium as gym
from gymnasium.utils.env_checker import check_env
import aero_env

env = gym.make("aero_env/AerialAcrobat-v0", render_mode="rgb_array", **{"scene.frames": 2})
env.reset(seed=0)
env.step(env.action_space.sample())
print(env.render().shape, "pygame" in sys.modules)
check_env(env.unwrapped)  # makes the env again in every declared mode, human too
print("checked")
"""


def _headless(xdg: str | None) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER",
                                                               "XDG_RUNTIME_DIR")}
    return env if xdg is None else {**env, "XDG_RUNTIME_DIR": xdg}


def test_check_env_on_a_headless_machine_says_nothing_about_the_display_library(tmp_path):
    for xdg in (None, str(tmp_path / "missing")):  # unset, or naming no folder
        script = tmp_path / "check.py"
        script.write_text(CHECK_ENV_SCRIPT)
        done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path,
                              env={**_headless(xdg), "PYTHONPATH": str(ROOT)}, timeout=300)
        assert done.returncode == 0, done.stderr
        # rgb_array never imports pygame; human, on no display, draws into SDL's dummy driver and says so once
        assert done.stdout.splitlines() == ["(300, 720, 3) False", "checked"], done.stdout
        assert "XDG" not in done.stderr and "error" not in done.stderr.lower(), done.stderr
        assert done.stderr.count("WARN: render_mode='human' with no display") == 1, done.stderr


def test_regenerate_docs_only_reruns_the_blocks_whose_command_has_the_text(tmp_path):
    # scripts/regenerate_docs.py --only TEXT: the matching block gets its command's output, the others keep theirs
    page = tmp_path / "page.md"
    page.write_text("<!-- run: echo first -->\n```text\nstale one\n```\n\n"
                    "<!-- run: echo second -->\n```text\nstale two\n```\n")
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "regenerate_docs.py"), str(page), "--only", "second"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert page.read_text() == ("<!-- run: echo first -->\n```text\nstale one\n```\n\n"
                                "<!-- run: echo second -->\n```text\nsecond\n```\n")
