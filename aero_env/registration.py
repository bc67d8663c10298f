"""The registered environments: ids and the config overrides that make each variant."""

from __future__ import annotations

import gymnasium as gym

ENTRY_POINT = "aero_env.envs.aerial_acrobat:AerialAcrobatEnv"
# gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point", **overrides): N designs per step in one
# call (aero_env/envs/aerial_acrobat_vector.py). make_vec with no vectorization_mode picks it too.
VECTOR_ENTRY_POINT = "aero_env.envs.aerial_acrobat_vector:AerialAcrobatVectorEnv"

# Every episode is one step (a design scored on its row) and ends by itself: the step returns terminated=True. The ids
# are registered without max_episode_steps, as Gymnasium's Blackjack-v1 (another episode that ends by itself), so
# gym.make adds no TimeLimit and truncated stays False. With max_episode_steps=1 (as before), TimeLimit set
# truncated=True on that step beside terminated=True (Gymnasium 1.4, wrappers/common.py: it truncates once elapsed >=
# max_episode_steps, whatever terminated says): logs showed 100 % truncation, code that bootstraps on truncated learnt
# wrong targets, and check_env(gym.make(id)) failed ("truncates after 1 step"). Truncation means a limit outside the
# task; this episode has none.

def _maker_choices() -> list[dict]:
    """What the maker chooses on the maker's contexts and on their hard sibling (a fresh list for each id): the
    counterbalance (m3 in 0.1 g, h, La), the spring and the handrail's distance Lb, each relative to the scene."""
    return [{"name": "design.m3", "low": 0.5, "high": 1.6, "relative_to": "design.m2", "step": 1e-4},
            {"name": "design.h", "low": -0.2, "high": 0.4, "relative_to": "design.La"},
            {"name": "design.La", "low": 0.75, "high": 1.35, "relative_to": "design.La"},
            {"name": "design.spring_k", "low": 0.22, "high": 4.5, "scale": "log", "relative_to": "design.spring_k"},
            {"name": "design.Lb", "low": 0.8, "high": 1.3, "relative_to": "design.Lb"}]


def _cutting_error() -> list[dict]:
    """The build's cutting error, drawn at reset and not observed: the counterbalance's mass ±2 %, its arm La ±0.3 mm."""
    return [{"name": "design.m3", "relative": 0.02}, {"name": "design.La", "absolute": 0.0003}]


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
        "tolerance": _cutting_error(),
    },
    # The maker's contexts (configs/contexts.yaml): four things a maker knows before cutting card, each drawn
    # wide enough that the design must follow it. The row's rise (0-10 mm a frame) and pitch (70-86 mm), the
    # robot's mass (6.5-10 g) and the card pair's friction (gray/gray 0.283 to white/gray 0.542, mu_k at the
    # pair's ratio), on a 5-frame row. The maker chooses the counterbalance, the spring and the handrail's
    # distance Lb (which must follow the pitch); the build's cutting error is drawn and not observed. No
    # single design completes the row on most of these contexts (docs/agents.md).
    "aero_env/AerialAcrobatContexts-v0": {
        "scene.frames": 5,
        "context": [{"name": "scene.rise", "low": 0.0, "high": 0.010},
                    {"name": "scene.pitch", "low": 0.070, "high": 0.086},
                    {"name": "design.m2", "low": 0.0065, "high": 0.010},
                    {"name": "design.mu_s", "low": 0.283, "high": 0.542, "linked": ["design.mu_k"]}],
        "tunable": _maker_choices(),
        "tolerance": _cutting_error(),
    },
    # The maker's wider shelves (configs/contexts_hard.yaml): the same four contexts over a room's range, a row that
    # falls 6 mm or climbs 14 mm a frame, frames 64-94 mm apart, four to eight coins, on the paper's 8-frame row
    # (7 traversals in a row). The same five choices and cutting error. At the maps' standard budget a search per
    # context solves what a map fitted on 40,960 episodes does not (docs/agents.md, "The hard task").
    "aero_env/AerialAcrobatContexts-Hard-v0": {
        "scene.frames": 8,
        "context": [{"name": "scene.rise", "low": -0.006, "high": 0.014},
                    {"name": "scene.pitch", "low": 0.064, "high": 0.094},
                    {"name": "design.m2", "low": 0.0065, "high": 0.012},
                    {"name": "design.mu_s", "low": 0.283, "high": 0.542, "linked": ["design.mu_k"]}],
        "tunable": _maker_choices(),
        "tolerance": _cutting_error(),
    },
}


# Each id's reward_threshold: the whole row of its *registered* scene, frames - 1 traversals (the prototype's 8 frames:
# 7; the maker's contexts' 5 frames: 4). A completed run scores exactly frames - 1 and every other run less, with or
# without shaping: the shaping's credit goes only to a failed flight, which has at most frames - 2 traversals, and
# its weight is at most 0.99 (aero_env/reward.py), so a mean reward >= the threshold means every episode completed
# the row. A spec's threshold is fixed per id: gym.make(id, **{"scene.frames": n}) or another config= changes the
# row, not the threshold (for that scene the whole row is n - 1). tests/test_env.py checks these numbers
# against each id's default scene.
REWARD_THRESHOLDS: dict[str, float] = {
    "aero_env/AerialAcrobat-v0": 7.0,
    "aero_env/AerialAcrobatVaried-v0": 7.0,
    "aero_env/AerialAcrobatContexts-v0": 4.0,
    "aero_env/AerialAcrobatContexts-Hard-v0": 7.0,
}


def register_environments() -> None:
    for env_id, kwargs in ENVIRONMENTS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point=ENTRY_POINT, vector_entry_point=VECTOR_ENTRY_POINT,
                         reward_threshold=REWARD_THRESHOLDS[env_id], kwargs=dict(kwargs))
