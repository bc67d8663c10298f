"""Draw the assembly's steps from the world itself: the stand with its frames at rest, the robot hooked on
frame 0, the robot in flight to frame 1, and frame 1 carrying it.

    python scripts/draw_assembly.py CONFIG OUT_PREFIX    # writes OUT_PREFIX_1.png .. OUT_PREFIX_4.png

Each picture is the simulated run's own pose (aero_env.render.Canvas), labelled, so what the maker is shown is
what the world swings: docs/make-your-own.md, "Assembly", shows the prototype's.
"""

from __future__ import annotations

import sys

from PIL import Image

from aero_env.config import load_config
from aero_env.render import Canvas
from aero_env.simulation import simulate


def main(config: str, prefix: str) -> None:
    cfg = load_config(config, {"scene.frames": 3})
    run = simulate(cfg, poses_every=0.005)
    canvas = Canvas(run.geometry, 720, 300)
    detach = run.swings[0].t_detach
    catch = run.swings[1].t_catch
    at = lambda t: min(run.poses, key=lambda p: abs(p[0] - t))  # noqa: E731  the pose nearest time t
    steps = [
        (canvas.draw(run.poses[0], "1. the stand: each frame on its skewer, resting on its stopper", labels=True,
                     robot=False)),
        (canvas.draw(run.poses[0], "2. hook the robot on frame 0's handrail, arm bent; let go", labels=True)),
        (canvas.draw(at(0.5 * (detach + catch)), "3. the hook has slid off: the robot flies to frame 1")),
        (canvas.draw(at(catch + 0.1), "4. frame 1 caught it and turns: the next swing")),
    ]
    for i, img in enumerate(steps, 1):
        Image.fromarray(img).save(f"{prefix}_{i}.png")
        print(f"wrote {prefix}_{i}.png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().splitlines()[2].strip())
    main(sys.argv[1], sys.argv[2])
