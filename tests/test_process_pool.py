"""aero_env.process_pool: a pool's workers end with the process that made them, however it ends."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parent.parent

# a script that makes the vector env's pool at a pymunk fidelity, steps it once (the workers are up), prints the
# workers' pids and then kills itself with SIGKILL, which runs none of Python's cleanup
KILLED_MID_RUN = """
import os, signal
import numpy as np
from aero_env.config import load_config
from aero_env.envs import AerialAcrobatVectorEnv

if __name__ == "__main__":
    env = AerialAcrobatVectorEnv(2, load_config("configs/paper.yaml", {"scene.frames": 2}), workers=2)
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    print(" ".join(str(pid) for pid in env._pool._processes), flush=True)
    os.kill(os.getpid(), signal.SIGKILL)
"""


def running(pid: int) -> bool:
    """Whether ``pid`` is a live process (a zombie nobody has reaped yet has ended)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return False
    return state not in ("Z", "X")


def test_the_vector_envs_workers_end_when_the_process_that_made_them_is_killed(tmp_path):
    # its output goes to files, not pipes: an orphan would hold a pipe open, and the run would never return
    with open(tmp_path / "out", "w") as out, open(tmp_path / "err", "w") as err:
        code = subprocess.run([sys.executable, "-c", KILLED_MID_RUN], cwd=ROOT, stdout=out, stderr=err,
                              timeout=300).returncode
    assert code == -signal.SIGKILL, (tmp_path / "err").read_text()
    workers = [int(pid) for pid in (tmp_path / "out").read_text().split()]
    assert len(workers) == 2
    deadline = time.monotonic() + 10.0
    while any(running(pid) for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    alive = [pid for pid in workers if running(pid)]
    for pid in alive:  # leave no orphan behind, whatever the verdict
        os.kill(pid, signal.SIGKILL)
    assert not alive, f"workers {alive} outlived the process that made them"
