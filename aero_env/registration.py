"""The registered environments: ids and the config overrides that make each variant."""

from __future__ import annotations

import gymnasium as gym

ENTRY_POINT = "aero_env.envs.aerial_acrobat:AerialAcrobatEnv"
# gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point", **overrides): N designs per step in one
# call (aero_env/envs/aerial_acrobat_vector.py). make_vec with no vectorization_mode picks it too.
VECTOR_ENTRY_POINT = "aero_env.envs.aerial_acrobat_vector:AerialAcrobatVectorEnv"

ENVIRONMENTS: dict[str, dict] = {
    # The prototype's scene: Table 1 masses and lengths on the 8-frame row of configs/paper.yaml.
    "aero_env/AerialAcrobat-v0": {},
    # The same row for a maker who knows the scene only roughly: every reset draws the row's rise
    # (0-4 mm per frame) and the robot's mass (6.5-9 g: how many coins), both observed, and the
    # cutting error of the build (counterbalance mass ±2 %, its arm La ±0.3 mm), not observed.
    # The best design depends on the draw, so a policy must map the context to a design.
    "aero_env/AerialAcrobatVaried-v0": {
        "context": [{"name": "scene.rise", "low": 0.0, "high": 0.004}, {"name": "scene.pitch"},
                    {"name": "design.m2", "low": 0.0065, "high": 0.009}],
        "tolerance": [{"name": "design.m3", "relative": 0.02}, {"name": "design.La", "absolute": 0.0003}],
    },
}


def register_environments() -> None:
    for env_id, kwargs in ENVIRONMENTS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point=ENTRY_POINT, vector_entry_point=VECTOR_ENTRY_POINT,
                         kwargs=dict(kwargs))
