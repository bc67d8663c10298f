"""Ctrl-C or SIGTERM during ``aero-env train`` leaves a whole run or nothing, and says so in one line (issues 36
and 50; SIGTERM ends with status 143).

The real thing first: ``aero-env train`` with two worker processes, in a session of its own, sent SIGINT the way
a terminal's Ctrl-C and ``timeout -s INT`` send it (to the command, and to its whole process group, so the workers
hear it too), and SIGTERM the way a scheduler sends it (to the workers, the command, its group). Then the pieces,
in this process, each signal sent at a chosen point: :class:`agents.interrupts.SigintOnce`,
:func:`agents.interrupts.children_ignore_sigint`, the atomic write, and the close of a vector env stopped between
a step's send and its replies (a run hung there at its save) or by a dead worker.
"""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import threading
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

from aero_env.files import write_atomically
from aero_env.signals import Terminated
from agents.interrupts import STOP_SIGNALS, SigintOnce, children_ignore_sigint

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


def _ctrl_c(proc, signum: int = signal.SIGINT) -> None:
    """SIGINT as ``timeout -s INT`` sends it: to the command, then to its process group (SIGTERM: as ``timeout`` and
    a scheduler send it)."""
    os.kill(proc.pid, signum)
    os.killpg(proc.pid, signum)


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


def _worker_pids(proc) -> list[int]:
    """The command's spawned worker processes that are running (multiprocessing's own tracker aside)."""
    found = subprocess.run(["pgrep", "-P", str(proc.pid), "-f", "spawn_main"], capture_output=True, text=True)
    return sorted(int(pid) for pid in found.stdout.split())


def _workers(proc) -> int:
    return len(_worker_pids(proc))


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
@pytest.mark.parametrize("signum, said", [(signal.SIGINT, "interrupted"), (signal.SIGTERM, "terminated (SIGTERM)")],
                         ids=["SIGINT", "SIGTERM"])
def test_ctrl_c_before_the_first_step_leaves_nothing(signum, said, tmp_path):
    out = tmp_path / "new" / "run"
    proc = _start(out)
    # the workers launched (the instant of each launch ignores both signals: agents.interrupts) and still importing
    _wait_for(lambda: (out / "config.yaml").is_file() and _workers(proc) >= 2, proc)
    _ctrl_c(proc, signum)
    code, lines = _finish(proc)
    assert code == 128 + signum and len(lines) <= 2, lines  # + the held one
    assert lines[-1] == f"aero-env train: {said} before the first training step; {out} is as it was before"
    assert not (tmp_path / "new").exists()  # the folders it made are gone with what it wrote


def _a_whole_interrupted_run(out, lines) -> None:
    """``out`` holds a stopped run that evaluate reads, and the command's last line said so."""
    run = json.loads((out / "run.json").read_text())
    assert run["interrupted"] and run["timesteps_done"] >= 40
    assert lines[-1].startswith(f"aero-env train: terminated (SIGTERM) at {run['timesteps_done']} of 1000000 "
                                f"timesteps; kept the policy so far") and "--resume" in lines[-1], lines
    with zipfile.ZipFile(out / "model.zip") as z:  # whole: every entry reads back with its CRC
        assert z.testzip() is None and "policy.pth" in z.namelist()
    assert not list(out.glob(".*.part"))
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "evaluate", str(out), "--episodes", "1", "--json"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


@pytest.mark.slow
def test_sigterm_to_the_workers_leaves_them_training_and_to_the_group_keeps_a_whole_run(tmp_path):
    """SLURM sends SIGTERM to every process of the job: the workers leave it to the command, which closes them."""
    out = tmp_path / "run"
    proc = _start(out)
    _wait_for(lambda: (out / "evaluations.npz").is_file() and _trained_episodes(out) >= 40, proc)
    workers = _worker_pids(proc)
    assert len(workers) == 2
    for pid in workers:
        os.kill(pid, signal.SIGTERM)
    episodes = _trained_episodes(out)
    _wait_for(lambda: _trained_episodes(out) >= episodes + 16, proc)  # still training, on the same two workers
    assert _worker_pids(proc) == workers
    os.killpg(proc.pid, signal.SIGTERM)
    code, lines = _finish(proc)
    assert code == 128 + signal.SIGTERM and len(lines) <= 2, lines
    _a_whole_interrupted_run(out, lines)


@pytest.mark.slow
def test_a_second_sigterm_during_the_save_waits_for_it(tmp_path):
    """A scheduler's SIGTERM to the command, then to its process group once the command is saving: the save runs
    to its end (before, the second one cut it and left a run with no policy that only --overwrite could reuse)."""
    out = tmp_path / "run"
    proc = _start(out)
    _wait_for(lambda: (out / "evaluations.npz").is_file() and _trained_episodes(out) >= 40, proc)
    os.kill(proc.pid, signal.SIGTERM)
    _wait_for(lambda: _workers(proc) == 0, proc)  # closed: the command is writing the run's files now (1.5-2.5 s)
    os.killpg(proc.pid, signal.SIGTERM)
    code, lines = _finish(proc)
    assert code == 128 + signal.SIGTERM and len(lines) == 2, lines
    assert lines[0] == f"aero-env train: stopping; it ends once {out} holds a whole run or nothing new"
    _a_whole_interrupted_run(out, lines)


def _terminate_at(monkeypatch, method: str, call: int) -> None:
    """``AerialAcrobatEnv.<method>`` raises Terminated, as SIGTERM does in the main thread, on its call number
    ``call``."""
    from aero_env.envs import AerialAcrobatEnv

    real, calls = getattr(AerialAcrobatEnv, method), [0]

    def wrapped(self, *args, **kwargs):
        calls[0] += 1
        if calls[0] == call:
            raise Terminated
        return real(self, *args, **kwargs)

    monkeypatch.setattr(AerialAcrobatEnv, method, wrapped)


IN_PROCESS = ["train", str(PAPER), "--set", "scene.frames=2", "--timesteps", "64", "--eval-every", "16", "--hp",
              "n_steps=16", "--hp", "batch_size=16", "--hp", "n_epochs=1", "--no-progress"]


def test_sigterm_while_training_keeps_the_run_says_so_and_ends_with_143(tmp_path, monkeypatch, capsys):
    from aero_env.cli import main

    _terminate_at(monkeypatch, "step", 40)
    out = tmp_path / "run"
    assert main([*IN_PROCESS, "--out", str(out)]) == 128 + signal.SIGTERM
    run = json.loads((out / "run.json").read_text())
    assert run["interrupted"] and 16 <= run["timesteps_done"] < 64
    assert capsys.readouterr().err.splitlines() == [
        f"aero-env train: terminated (SIGTERM) at {run['timesteps_done']} of 64 timesteps; kept the policy so far and "
        f"its curves in {out} (aero-env evaluate {out} scores it); resume: rerun the same command with --resume"]


def test_sigterm_before_the_first_step_leaves_nothing_and_ends_with_143(tmp_path, monkeypatch, capsys):
    from aero_env.cli import main

    _terminate_at(monkeypatch, "reset", 1)
    out = tmp_path / "new" / "run"
    assert main([*IN_PROCESS, "--out", str(out)]) == 128 + signal.SIGTERM
    assert capsys.readouterr().err.splitlines() == [
        f"aero-env train: terminated (SIGTERM) before the first training step; {out} is as it was before"]
    assert not (tmp_path / "new").exists()


# ---- SigintOnce, the signal sent at a chosen point (signal.raise_signal runs the handler before it returns) ----
STOPS = [(signal.SIGINT, KeyboardInterrupt), (signal.SIGTERM, Terminated)]
STOP_IDS = ["SIGINT", "SIGTERM"]


@pytest.fixture
def own_handlers():
    """A handler of the test's own for SIGINT and SIGTERM while it runs: what SigintOnce must put back, and what
    takes a signal SigintOnce failed to (SIGTERM's default would end pytest). Yields the signals it took."""
    took: list[int] = []

    def take(signum, _frame):
        took.append(signum)

    before = {signum: signal.signal(signum, take) for signum in STOP_SIGNALS}
    try:
        yield took
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)


def _send(signum: int):
    """``signum`` to this process now: the type of what its handler raised, or None (a raise stays in the test;
    pytest would stop on a KeyboardInterrupt)."""
    try:
        signal.raise_signal(signum)
    except KeyboardInterrupt as stop:
        return type(stop)
    return None


@pytest.mark.parametrize("second", [signal.SIGINT, signal.SIGTERM], ids=["then-SIGINT", "then-SIGTERM"])
@pytest.mark.parametrize("first, raised", STOPS, ids=STOP_IDS)
def test_the_first_stop_raises_and_every_later_one_is_held_with_one_line(first, raised, second, own_handlers):
    said = io.StringIO()
    with SigintOnce("held: saving", said) as sigint:
        assert sigint.came is False
        assert _send(first) is raised and sigint.came  # Terminated for SIGTERM: the command ends with 143
        assert said.getvalue() == ""  # the one that stops the run says nothing here: the command says what it kept
        assert _send(second) is None  # outside a save: held all the same (the survivor)
        with sigint.saving():
            assert _send(second) is None and _send(first) is None
        assert _send(first) is None
    assert said.getvalue() == "held: saving\n"  # once, for four held signals
    assert own_handlers == []  # every one reached SigintOnce


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=STOP_IDS)
def test_a_first_stop_during_a_save_is_held_and_counts_as_the_first(signum, own_handlers):
    said = io.StringIO()
    with SigintOnce("held", said) as sigint:
        with sigint.saving():
            assert _send(signum) is None and sigint.came
            assert said.getvalue() == "held\n"
        # the save was the run's end (a finished run's files, or an interrupted one's): nothing left to stop
        assert _send(signum) is None
    assert said.getvalue() == "held\n" and own_handlers == []


@pytest.mark.parametrize("signum, raised", STOPS, ids=STOP_IDS)
def test_a_save_ended_or_failed_holds_nothing_after_it(signum, raised, own_handlers):
    with SigintOnce("held", io.StringIO()) as sigint:
        with sigint.saving():
            pass
        with pytest.raises(OSError), sigint.saving():
            raise OSError("disk full")
        assert _send(signum) is raised and own_handlers == []


def test_the_held_line_goes_to_stderr_at_once(own_handlers, capsys):
    class Watched(io.StringIO):
        flushed = ""

        def flush(self):
            self.flushed = self.getvalue()
            super().flush()

    watched = Watched()
    with SigintOnce("to the stream", watched) as sigint, sigint.saving():
        _send(signal.SIGTERM)
    assert watched.flushed == "to the stream\n"  # flushed: the save it waits for may take a while
    with SigintOnce("to stderr") as sigint, sigint.saving():
        _send(signal.SIGINT)
    said = capsys.readouterr()
    assert (said.err, said.out) == ("to stderr\n", "")


@pytest.mark.parametrize("how", ["ended", "raised"])
def test_both_handlers_are_put_back(how, own_handlers):
    take = signal.getsignal(signal.SIGINT)
    try:
        with SigintOnce("held", io.StringIO()) as sigint:
            assert sigint is not None
            assert all(signal.getsignal(signum) not in (take, signal.SIG_DFL) for signum in STOP_SIGNALS)
            if how == "raised":
                raise ValueError
    except ValueError:
        pass
    assert [signal.getsignal(signum) for signum in STOP_SIGNALS] == [take, take]
    assert _send(signal.SIGTERM) is None and own_handlers == [signal.SIGTERM]  # the test's own handler has it again


def _in_a_thread(work) -> list[BaseException]:
    """Run ``work`` in another thread (where no signal handler may be set); what it raised, if anything."""
    failed: list[BaseException] = []

    def run():
        try:
            work()
        except BaseException as e:  # noqa: BLE001 - reported to the test
            failed.append(e)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join(30)
    return failed


def test_outside_the_main_thread_sigint_once_sets_no_handler_and_still_saves(own_handlers):
    take = signal.getsignal(signal.SIGINT)
    seen = []

    def work():
        with SigintOnce("held", io.StringIO()) as sigint:
            with sigint.saving():
                seen.append("saved")
            seen.append([signal.getsignal(signum) for signum in STOP_SIGNALS])

    assert _in_a_thread(work) == []
    assert seen == ["saved", [take, take]]
    assert [signal.getsignal(signum) for signum in STOP_SIGNALS] == [take, take]


# ---- children_ignore_sigint: a launch ignores both signals for its instant, so the child does for life ----
def _ignored(pid: int) -> set[int]:
    """The signals process ``pid`` ignores, as the kernel reports them (/proc/PID/status, SigIgn: a hex mask)."""
    line = next(ln for ln in Path(f"/proc/{pid}/status").read_text().splitlines() if ln.startswith("SigIgn:"))
    mask = int(line.split()[1], 16)
    return {signum for signum in range(1, 65) if mask >> (signum - 1) & 1}


def _spawned_ignoring() -> set[int]:
    """Spawn a child (multiprocessing's spawn), and which of SIGINT and SIGTERM it ignores."""
    import multiprocessing

    child = multiprocessing.get_context("spawn").Process(target=time.sleep, args=(60,), daemon=True)
    child.start()
    try:
        return _ignored(child.pid) & set(STOP_SIGNALS)
    finally:
        child.kill()
        child.join()


def test_children_launched_in_the_block_ignore_sigint_and_sigterm_and_this_process_does_not(own_handlers):
    take = signal.getsignal(signal.SIGINT)
    assert _spawned_ignoring() == set()  # the check can tell: a child launched outside the block ignores neither
    with children_ignore_sigint():
        assert _spawned_ignoring() == {signal.SIGINT, signal.SIGTERM}
        assert [signal.getsignal(signum) for signum in STOP_SIGNALS] == [take, take]  # put back after the launch
    assert _spawned_ignoring() == set()
    assert own_handlers == []


def test_the_launch_ignores_both_signals_for_its_instant_and_puts_them_back_if_it_fails(own_handlers, monkeypatch):
    from multiprocessing import popen_spawn_posix

    take = signal.getsignal(signal.SIGINT)
    during = []

    def launch(self, process_obj):
        during.append([signal.getsignal(signum) for signum in STOP_SIGNALS])
        if process_obj == "fails":
            raise OSError("fork failed")
        return ("launched", self, process_obj)

    monkeypatch.setattr(popen_spawn_posix.Popen, "_launch", launch)
    with children_ignore_sigint():
        assert popen_spawn_posix.Popen._launch(1, 2) == ("launched", 1, 2)
        with pytest.raises(OSError):
            popen_spawn_posix.Popen._launch(1, "fails")
        assert [signal.getsignal(signum) for signum in STOP_SIGNALS] == [take, take]
    assert during == [[signal.SIG_IGN, signal.SIG_IGN]] * 2


@pytest.mark.parametrize("how", ["ended", "raised"])
def test_the_launch_wrapper_is_removed_when_the_block_ends(how):
    from multiprocessing import popen_spawn_posix

    launch = popen_spawn_posix.Popen._launch
    try:
        with children_ignore_sigint():
            assert popen_spawn_posix.Popen._launch is not launch
            if how == "raised":
                raise ValueError
    except ValueError:
        pass
    assert popen_spawn_posix.Popen._launch is launch


def test_outside_the_main_thread_children_ignore_sigint_changes_nothing():
    from multiprocessing import popen_spawn_posix

    launch = popen_spawn_posix.Popen._launch
    inside = []

    def work():
        with children_ignore_sigint():
            inside.append(popen_spawn_posix.Popen._launch)

    assert _in_a_thread(work) == [] and inside == [launch]
    assert popen_spawn_posix.Popen._launch is launch


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


def _cartpoles(n: int):
    """SB3's SubprocVecEnv of ``n`` CartPoles (a cheap env: these tests are about the worker processes)."""
    import functools

    import gymnasium as gym
    from stable_baselines3.common.vec_env import SubprocVecEnv

    from agents.rl import _worker_processes

    return _worker_processes(SubprocVecEnv, [functools.partial(gym.make, "CartPole-v1")] * n)


@pytest.mark.slow  # two workers importing torch: about 5 s on 2 cores
def test_a_close_cut_short_by_a_dead_worker_still_ends_the_others():
    """The workers ignore SIGTERM, so SB3's terminate() at exit cannot end one a failed close left waiting."""
    from agents.rl import _close

    venv = _cartpoles(2)
    try:
        venv.processes[0].kill()
        venv.processes[0].join()
        _close(venv)  # its first "close" meets a broken pipe
        assert [p.is_alive() for p in venv.processes] == [False, False]
    finally:
        for p in venv.processes:
            p.kill()


def test_workers_stopped_while_they_start_are_killed():
    """A Ctrl-C or SIGTERM while the workers import: the vector env is never made, so nothing else could close them."""
    import functools
    import multiprocessing

    from stable_baselines3.common.vec_env import SubprocVecEnv

    from agents.rl import _worker_processes

    def stop(_signum, _frame):
        raise Terminated

    before = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, 1.0)  # while the parent waits for the first worker's spaces
    try:
        with pytest.raises(Terminated):
            _worker_processes(SubprocVecEnv, [functools.partial(time.sleep, 60)] * 2)  # never gives its spaces
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, before)
    left = multiprocessing.active_children()
    for p in left:
        p.kill()
    assert left == []

