import importlib
import sys
from pathlib import Path

import pytest
from hypothesis import settings

# Property tests: 300 examples each in CI; `pytest --hypothesis-profile=deep` tries 3000.
settings.register_profile("ci", max_examples=300)
settings.register_profile("deep", max_examples=3000)
settings.load_profile("ci")

from aero_env.config import load_config
from aero_env.physics import simulate

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "configs" / "paper.yaml"


def benchmark_module(name: str):
    """A script of benchmarks/ as a module (it imports its sibling scripts by name, as when it runs there)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
# The default pymunk world at twice its step: the cheapest run the prototype survives (the former mbd-fast rung,
# which left the ladder: docs/fidelity.md). Tests that need many cheap pymunk runs, not the default's accuracy, use it.
COARSE = {"sim.fidelity": "mbd", "sim.dt": 0.001}


@pytest.fixture(scope="session")
def paper_cfg():
    return load_config(PAPER)


@pytest.fixture(scope="session")
def paper_run(paper_cfg):
    """The prototype's whole row, with its trace (simulated once per test session)."""
    return simulate(paper_cfg, trace=True)
