import importlib
import os
import sys
import types
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


def per_test_under_mutmut(fixture_name, config) -> str:
    """A fixture's scope: the module's, but each test's own under mutmut (scripts/mutation.py). mutmut runs, for a
    mutant, only the tests it saw reach the function it changed; a module's fixture reaches the kit once, in the
    first test that asks for it, and the other tests that read what it made would never run on a mutant."""
    return "function" if "MUTANT_UNDER_TEST" in os.environ else "module"


@pytest.fixture(scope="session")
def paper_cfg():
    return load_config(PAPER)


@pytest.fixture(scope="session")
def paper_run(paper_cfg):
    """The prototype's whole row, with its trace (simulated once per test session)."""
    return simulate(paper_cfg, trace=True)


@pytest.fixture
def flat_side_cards(monkeypatch):
    """Build every frame with flat side cards (aero_env/parts/build.py's own build for a design no hollow card fits)
    instead of the article's hollow ones: the world, the reduced model and the kit alike. For scenarios found on the
    flat-card machine (before the hollow frame), whose contacts depend on that machine's swing."""
    import numpy as np

    from aero_env.parts import build

    def flat(d):
        shape = np.shape(build.side_card_length(d))
        none = dict(hollow=np.zeros(shape, bool), layers=np.ones(shape), half_depth=np.full(shape, np.nan),
                    end=np.full(shape, np.nan), half_length=build.side_card_length(d) / 2.0)
        return {k: v.item() for k, v in none.items()} if shape == () else none

    monkeypatch.setattr(build, "fit_ring", flat)
    monkeypatch.setattr(build, "_fit_ring_one",
                        lambda La, Lb, m1, h, rest, stop: flat(types.SimpleNamespace(La=La, Lb=Lb)))
