"""An action is read as the action space holds it (float32), whoever proposes it (issue 35 §4).

A tuner proposes float64 points, a policy float32 ones. Read at full precision, the stored best single design of
the maker's contexts and its own action rounded to float32 (a change of ~5e-9) were two designs, and 8 of 200
hold-out outcomes differed. These tests compute the float32 point with numpy themselves, not through the cast the
code applies."""

from __future__ import annotations

import numpy as np

from aero_env.config import load_config
from aero_env.design_space import DesignSpace
from aero_env.envs import AerialAcrobatEnv, AerialAcrobatVectorEnv

from .conftest import PAPER

CONTEXTS = PAPER.parent / "contexts.yaml"
SINGLE = PAPER.parent / "contexts_single.yaml"


def _between_float32s(dim: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """float64 actions that float32 cannot hold: each a float32 value plus a third of its spacing."""
    a32 = np.random.default_rng(seed).uniform(-0.9, 0.9, dim).astype(np.float32)
    a64 = a32.astype(np.float64) + np.spacing(a32).astype(np.float64) / 3.0
    assert (a64.astype(np.float32) == a32).all() and (a64 != a32.astype(np.float64)).all()
    return a64, a32


def test_a_float64_action_names_the_design_of_its_float32_rounding():
    cfg = load_config(CONTEXTS)
    env = AerialAcrobatEnv(cfg)
    for seed in range(3):
        a64, a32 = _between_float32s(env.space.dim, seed)
        assert env.design_for(a64) == env.design_for(a32)
        env.reset(seed=seed)
        info64 = env.step(a64)[4]
        env.reset(seed=seed)
        info32 = env.step(a32)[4]
        assert info64["design"] == info32["design"] and info64["traversals"] == info32["traversals"]
        assert info64["sim_time"] == info32["sim_time"]


def test_the_vector_env_reads_actions_as_the_single_env_does():
    cfg = load_config(CONTEXTS, {"sim.fidelity": "reduced"})
    rows = [_between_float32s(DesignSpace(cfg).dim, s) for s in range(8)]
    a64, a32 = np.array([r[0] for r in rows]), np.array([r[1] for r in rows])
    envs = AerialAcrobatVectorEnv(8, cfg)
    out = []
    for actions in (a64, a32):
        envs.reset(seed=10)
        info = envs.step(actions)[4]["final_info"]
        out.append({k: np.asarray(v).tolist() for k, v in info["design"].items() if not k.startswith("_")})
    assert out[0] == out[1]
    env = AerialAcrobatEnv(cfg)
    assert [env.design_for(a)["design.h"] for a in a64] == out[0]["design.h"]


def test_the_stored_single_design_is_what_its_own_action_names():
    """configs/contexts_single.yaml holds the design its action names: a policy that outputs that action (float32)
    builds exactly the file's design."""
    cfg, single = load_config(CONTEXTS), load_config(SINGLE)
    space = DesignSpace(cfg)
    stored = {t.name: single.value(t.name) for t in space.tunables}
    action = space.action_for(stored)  # float32, as a policy gives it
    assert action.dtype == np.float32
    assert space.values(action) == {k: single.value(k) for k in space.values(action)}
