"""Draw docs/env_summary.png: what ``render()`` returns after a step, for two designs.

    python scripts/draw_env_summary.py docs/env_summary.png

Top: the prototype (configs/paper.yaml) completes its row. Bottom: the same with a spring ten
times too weak, whose arm is still swinging forward when the hook reaches the next handrail.
Prints each run's outcome, so the page that shows the figure quotes what it shows.
"""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
from PIL import Image

import aero_env  # noqa: F401  (registers the environments)

DESIGNS = {"the prototype": {}, "a spring ten times too weak": {"design.spring_k": 8.77e-5}}


def main(path: str) -> None:
    frames = []
    for name, overrides in DESIGNS.items():
        env = gym.make("aero_env/AerialAcrobat-v0", config="configs/paper.yaml", render_mode="rgb_array",
                       **overrides)
        env.reset(seed=0)
        _, reward, _, _, info = env.step(env.unwrapped.action_for())
        frames.append(env.render())
        print(f"{name}: {info['outcome']}, reward {reward:g} ({info['reason']})")
        env.close()
    Image.fromarray(np.concatenate(frames, axis=0)).save(path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/env_summary.png")
