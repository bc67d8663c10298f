"""Ctrl-C during ``aero-env train`` leaves a whole run or nothing, and says so in one line (issue 36).

The real thing first: ``aero-env train`` with two worker processes, in a session of its own, sent SIGINT the way
a terminal's Ctrl-C and ``timeout -s INT`` send it (to the command, and to its whole process group, so the workers
hear it too). Then the pieces, in this process: :class:`agents.interrupts.SigintOnce`, the atomic write, and the
close of a vector env stopped between a step's send and its replies (a run hung there at its save).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
import zipfile

import numpy as np
import pytest

from aero_env.files import write_atomically
from agents.interrupts import SigintOnce

from .conftest import PAPER

TRAIN = [sys.executable, "-m", "aero_env.cli", "train", str(PAPER), "--set", "scene.frames=2", "--timesteps",
         "1000000", "--n-envs", "2", "--eval-every", "40", "--hp", "n_steps=8", "--hp", "batch_size=16", "--no-progress"]


def _start(out):
    return subprocess.Popen([*TRAIN, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)  # its own process group, as a shell gives a command


def _wait_for(condition, proc, seconds: float = 120.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the run never got there"
        time.sleep(0.05)


def _ctrl_c(proc) -> None:
    """SIGINT as ``timeout -s INT`` sends it: to the command, then to its process group."""
    os.kill(proc.pid, signal.SIGINT)
    os.killpg(proc.pid, signal.SIGINT)


def _finish(proc) -> tuple[int, list[str]]:
    try:
        _, err = proc.communicate(timeout=180)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        raise AssertionError("the interrupted run did not end")
    deadline = time.monotonic() + 15  # no worker outlives the command (multiprocessing's tracker ends just after)
    while True:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        assert time.monotonic() < deadline, "a process of the run outlived it"
        time.sleep(0.1)
    assert "Traceback" not in err and "Exception ignored" not in err, err
    return proc.returncode, [ln for ln in err.splitlines() if ln.strip()]


def _workers(proc) -> int:
    """How many of the command's spawned worker processes are running (multiprocessing's own tracker aside)."""
    found = subprocess.run(["pgrep", "-P", str(proc.pid), "-f", "spawn_main"], capture_output=True, text=True)
    return len(found.stdout.split())


def _trained_episodes(out) -> int:
    return sum(max(0, len(f.read_text().splitlines()) - 2) for f in out.glob("*.monitor.csv"))


@pytest.mark.slow
def test_ctrl_c_while_training_keeps_a_whole_run_that_evaluate_reads(tmp_path):
    out = tmp_path / "run"
    proc = _start(out)
    _wait_for(lambda: (out / "evaluations.npz").is_file() and _trained_episodes(out) >= 40, proc)
    _ctrl_c(proc)
    code, lines = _finish(proc)
    assert code == 130 and len(lines) <= 2, lines  # the interrupt's line, and at most one for the held second one
    assert "interrupted at" in lines[-1] and "--resume" in lines[-1]
    run = json.loads((out / "run.json").read_text())
    assert run["interrupted"] and run["timesteps_done"] >= 40
    with zipfile.ZipFile(out / "model.zip") as z:  # whole: every entry reads back with its CRC
        assert z.testzip() is None and "policy.pth" in z.namelist()
    ev = np.load(out / "evaluations.npz")
    assert len(ev["timesteps"]) >= 1 and not list(out.glob(".*.part"))
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "evaluate", str(out), "--episodes", "1", "--json"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["episodes"] == 1


@pytest.mark.slow
def test_ctrl_c_before_the_first_step_leaves_nothing(tmp_path):
    out = tmp_path / "new" / "run"
    proc = _start(out)
    # the workers launched (the instant of each launch ignores SIGINT: agents.interrupts) and still importing
    _wait_for(lambda: (out / "config.yaml").is_file() and _workers(proc) >= 2, proc)
    _ctrl_c(proc)
    code, lines = _finish(proc)
    assert code == 130 and len(lines) <= 2 and "before the first training step" in lines[-1], lines  # + the held one
    assert not (tmp_path / "new").exists()  # the folders it made are gone with what it wrote


def _sigint_self() -> None:
    os.kill(os.getpid(), signal.SIGINT)
    time.sleep(0.05)  # the handler runs at the next bytecode


def _held(sigint: SigintOnce, times: int) -> bool:
    """Send ``times`` SIGINTs during a save; True when the save ran to its end (a raised one fails the test, not
    the session: pytest stops on a KeyboardInterrupt)."""
    try:
        with sigint.saving():
            for _ in range(times):
                _sigint_self()
            return True
    except KeyboardInterrupt:
        pytest.fail("a SIGINT during a save was raised, not held")


def test_the_first_sigint_interrupts_and_the_rest_are_held_with_one_line(capsys):
    before = signal.getsignal(signal.SIGINT)  # (SIG_IGN where pytest was started with &, without job control)
    with SigintOnce("held: saving") as sigint:
        with pytest.raises(KeyboardInterrupt):
            _sigint_self()
        finished = _held(sigint, 2)
    assert finished and sigint.came
    assert capsys.readouterr().err.splitlines() == ["held: saving"]
    assert signal.getsignal(signal.SIGINT) is before  # put back


def test_a_first_sigint_during_a_save_is_held_not_raised(capsys):
    with SigintOnce("held") as sigint:
        assert _held(sigint, 1) and sigint.came
    assert capsys.readouterr().err.strip() == "held"


def test_an_atomic_write_cut_half_way_keeps_the_old_file(tmp_path):
    path = tmp_path / "model.zip"
    path.write_bytes(b"old and whole")

    def cut(f):
        f.write(b"new but ")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_atomically(path, cut)
    assert path.read_bytes() == b"old and whole" and sorted(p.name for p in tmp_path.iterdir()) == ["model.zip"]
    write_atomically(path, lambda f: f.write(b"new and whole"))
    assert path.read_bytes() == b"new and whole" and len(list(tmp_path.iterdir())) == 1


@pytest.mark.slow
def test_a_vector_env_stopped_between_a_steps_replies_still_closes():
    """Ctrl-C inside ``step_wait`` after the first worker's reply was read: SB3's close would wait for it again."""
    from agents.interrupts import children_ignore_sigint
    from agents.rl import _close, _vec_env
    from aero_env.config import load_config

    cfg = load_config(PAPER, {"scene.frames": 2})
    with children_ignore_sigint():
        venv = _vec_env(cfg, 2, 0, None)
    venv.reset()
    venv.step_async(np.zeros((2, venv.action_space.shape[0]), dtype=np.float32))
    venv.remotes[0].recv()  # step_wait read this reply, then the KeyboardInterrupt came
    closer = threading.Thread(target=_close, args=(venv,), daemon=True)
    closer.start()
    closer.join(60)
    hung = closer.is_alive()
    if hung:  # free the workers so that the suite goes on
        for p in venv.processes:
            p.kill()
    assert not hung, "closing the stopped vector env hung"
    assert venv.closed and not any(p.is_alive() for p in venv.processes)

