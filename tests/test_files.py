"""Files are written whole or not at all, a failed write is one line, and SIGTERM stops a command as Ctrl-C does
(aero_env.files, aero_env.signals)."""

from __future__ import annotations

import errno
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from aero_env import files
from aero_env.files import WriteFailed, temporary_path, write_atomically, write_text_atomically
from aero_env.signals import Terminated, sigterm_as_interrupt

ROOT = Path(__file__).resolve().parent.parent
AERO_ENV = [sys.executable, "-m", "aero_env.cli"]


def test_the_data_reaches_the_disk_before_the_rename_makes_it_the_file(tmp_path, monkeypatch):
    calls = []
    real_fsync, real_replace = os.fsync, os.replace
    monkeypatch.setattr(files.os, "fsync", lambda fd: (calls.append("fsync"), real_fsync(fd))[1])
    monkeypatch.setattr(files.os, "replace", lambda a, b: (calls.append("replace"), real_replace(a, b))[1])
    write_text_atomically(tmp_path / "a.txt", "whole")
    assert calls == ["fsync", "replace"]
    assert (tmp_path / "a.txt").read_text() == "whole"


def test_a_write_cut_by_an_error_keeps_the_old_file_and_leaves_nothing_beside_it(tmp_path):
    path = tmp_path / "best.yaml"
    path.write_text("old and whole")

    def disk_full(f):
        f.write(b"half of the new")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(WriteFailed) as err:
        write_atomically(path, disk_full, "config file")
    assert str(err.value) == (f"config file {str(path)!r}: cannot be written (No space left on device); it was left "
                              f"as it was")
    assert path.read_text() == "old and whole"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["best.yaml"]


def test_an_interrupt_during_a_write_passes_through_and_leaves_no_part_file(tmp_path):
    def interrupted(f):
        f.write(b"half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_atomically(tmp_path / "new.png", interrupted)
    assert list(tmp_path.iterdir()) == []
    assert temporary_path(tmp_path / "new.png").name == ".new.png.part"


def _small_files():
    """A child whose files may grow to 20 kB: a write past it fails with EFBIG, as a full disk fails with ENOSPC."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))


@pytest.mark.parametrize("option,name", [("--plot", "swing.png"), ("--trace", "trace.csv"), ("--gif", "run.gif")])
def test_simulate_on_a_disk_that_cannot_take_its_output_says_so_in_one_line(tmp_path, option, name):
    r = subprocess.run([*AERO_ENV, "simulate", str(ROOT / "configs/paper.yaml"), option, name], cwd=tmp_path,
                       preexec_fn=_small_files, capture_output=True, text=True, timeout=300)
    kind = {"--plot": "plot", "--trace": "trace", "--gif": "animation"}[option]
    lines = [line for line in r.stderr.splitlines() if not line.startswith("aero-env simulate: encoding")]
    assert r.returncode == 2, r.stderr
    assert lines == [f"aero-env: file error: {kind} file {name!r}: cannot be written (File too large); nothing was "
                     f"written"]
    assert list(tmp_path.iterdir()) == []


def test_sigterm_raises_terminated_inside_the_block_and_its_old_handler_comes_back():
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated):
        with sigterm_as_interrupt():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)  # the handler runs at the next bytecode; this never ends
    assert signal.getsignal(signal.SIGTERM) is before
    assert issubclass(Terminated, KeyboardInterrupt)  # every Ctrl-C path keeps a terminated run whole too


def test_a_sigterm_handler_set_before_is_kept():
    seen = []
    old = signal.signal(signal.SIGTERM, lambda s, f: seen.append(s))
    try:
        with sigterm_as_interrupt():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.01)
        assert seen == [signal.SIGTERM]
    finally:
        signal.signal(signal.SIGTERM, old)


@pytest.mark.slow
def test_sigterm_ends_a_command_with_one_line_and_status_143(tmp_path):
    # a long run (1000 frames at the reference step), stopped two seconds in, as a scheduler stops a job
    p = subprocess.Popen([*AERO_ENV, "simulate", str(ROOT / "configs/paper.yaml"), "--set", "scene.frames=1000",
                          "--set", "sim.fidelity=reference"], cwd=tmp_path, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    time.sleep(4.0)
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 143, err
    assert err.strip().splitlines() == ["aero-env simulate: terminated (SIGTERM)"]
