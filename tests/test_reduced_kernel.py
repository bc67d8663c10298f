"""The reduced model's compiled kernel: the same bits as the plain-Python path of the same code, in any
process, on any number of threads, and its compiled code cached on disk where the package says."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from aero_env.config import Config
from aero_env.models import reduced

ROOT = Path(__file__).resolve().parents[1]

# Run in a fresh interpreter: a sample of designs spanning the model's branches (the prototype, the five failure
# modes, random designs of the env's action space), every number printed exactly (float.hex).
_SAMPLE = r"""
import json, sys
import numpy as np
from aero_env.config import load_config
from aero_env.design_space import DesignSpace
from aero_env.models.reduced import simulate_batch
sys.path.insert(0, {root!r})
from tests.test_reduced import _varied

n_random = {n_random}
cfgs = _varied()
space = DesignSpace(cfgs[0])
cfgs += [cfgs[0].with_values(space.values(a)) for a in np.random.default_rng(7).uniform(-1, 1, (n_random, space.dim))]
r = simulate_batch(cfgs)
hexed = lambda a: [float(v).hex() for v in np.ravel(a)]
print(json.dumps(dict(outcome=r.outcome.tolist(), traversals=r.traversals.tolist(), reasons=[r.reason(i) for i in
                      range(len(r))], sim_time=hexed(r.sim_time), swings={{k: hexed(v) for k, v in r.swings.items()}},
                      miss=hexed(r.miss_distance))))
"""


def _sample(n_random: int, **env) -> dict:
    code = _SAMPLE.format(root=str(ROOT), n_random=n_random)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                         env={**os.environ, **env}, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout)


def test_the_compiled_kernel_gives_the_plain_python_paths_bits():
    """The same source with numba's compiler switched off (NUMBA_DISABLE_JIT=1: every kernel function runs as
    the Python it is written in, math.sin from Python's libm, Python's float arithmetic) against the compiled
    kernel in another process: a compiler that reordered or fused the arithmetic would show here."""
    plain = _sample(4, NUMBA_DISABLE_JIT="1")
    compiled = _sample(4)
    assert len(plain["outcome"]) == 15
    assert set(plain["outcome"]) >= {"stalled", "no_detach", "fell_short", "missed_catch"}
    assert any("a catch that did not hold" in r for r in plain["reasons"])  # the let-go branch ran in both
    assert plain == compiled


@pytest.mark.slow
def test_a_batch_gives_the_same_bits_in_any_process_on_any_number_of_threads():
    one_thread = _sample(40, NUMBA_NUM_THREADS="1")
    here = _sample(40, NUMBA_NUM_THREADS="2")
    assert one_thread == here
    # and in this process, through the in-process API
    import tests.test_reduced as t

    cfgs = t._varied()
    r = reduced.simulate_batch(cfgs)
    assert [float(v).hex() for v in r.sim_time] == one_thread["sim_time"][:len(cfgs)]
    assert r.outcome.tolist() == one_thread["outcome"][:len(cfgs)]


def test_the_compiled_code_is_cached_on_disk_in_a_folder_keyed_on_its_source(tmp_path, monkeypatch):
    reduced.simulate_batch([Config()])
    cache = reduced.kernel_cache_dir()
    indexes = list(cache.rglob("*.nbi"))
    # one index per kernel file that holds a cached function (run, phases, dynamics ...)
    assert {p.name.split("-")[0].split(".")[0] for p in indexes} >= {"run", "hooked_phase", "flight", "catch"}
    # another root gives another folder, and an edited kernel file another key
    monkeypatch.setenv("AERO_ENV_CACHE", str(tmp_path))
    assert reduced.kernel_cache_dir().parent == tmp_path / "numba"
    assert reduced.kernel_cache_dir().name == cache.name
    copy = tmp_path / "source"  # a copy of the kernel files, one edited: the source tree is never touched
    shutil.copytree(Path(reduced.__file__).parent, copy)
    assert reduced.kernel_cache_dir(copy).name == cache.name
    (copy / "constants.py").write_text((copy / "constants.py").read_text() + "\n")
    assert reduced.kernel_cache_dir(copy).name != cache.name


def test_compile_kernels_reports_its_time():
    seconds = reduced.compile_kernels()
    assert isinstance(seconds, float) and 0.0 < seconds < 600.0
    assert np.isfinite(reduced.simulate_reduced(Config()).sim_time)
