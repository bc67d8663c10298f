"""The pymunk world's hook contacts, pymunk step by pymunk step: which card of which frame the hook touches.

For following one design through the world when the reduced model and the world part: each runner step in
the window prints the time, the angles of the robot's frame and the next one, and every contact of the hook's
shape with a card (its frame, back or front card, depth in mm, the step's impulse in N·s along the contact's
normal and across it, the friction's, and "new" on the step a contact first appears). It found the steep
scene's kick: the hook, in frame 0's corner, meeting frame 1's back card at theta1 ~ 145 deg (docs/fidelity.md,
the reduced model).

    python scripts/world_contacts.py configs/scenes/steep.yaml --from 0.4995 --to 0.5012 \\
        --set design.La=0.0465 --set design.h=0.00927 --set design.m3=0.0081 --set design.spring_k=0.00109

The run is the world's own steps (World.step: the friction switch, then the pymunk substeps; a line per step),
without the runner: it never moves on to the next frame, so it reads the first swing (frames 0 and 1).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from aero_env import units  # noqa: E402
from aero_env.config import ConfigError, load_config  # noqa: E402
from aero_env.config.loading import parse_override  # noqa: E402
from aero_env.physics.world import World  # noqa: E402

IMPULSE = units.MASS * units.LENGTH / units.TIME  # engine impulse units per N·s


def contacts(world: World, names: dict) -> list[tuple[str, float, float, float, bool]]:
    """The hook's contacts now: (card, depth mm, normal and tangential impulse N·s, first step of the contact)."""
    hook = world.contact.hook_shape
    found = []

    def read(arb):
        a, b = arb.shapes
        other = b if a is hook else a
        if other not in names:
            return
        depth = -min((p.distance for p in arb.contact_point_set.points), default=0.0)
        impulse, normal = arb.total_impulse, arb.contact_point_set.normal
        found.append((names[other], units.length_to_si(depth) * 1e3, abs(impulse.dot(normal)) / IMPULSE,
                      impulse.cross(normal) / IMPULSE, arb.is_first_contact))

    hook.body.each_arbiter(read)
    return found


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--from", dest="t0", type=float, required=True, help="the window's start, s")
    ap.add_argument("--to", dest="t1", type=float, required=True, help="the window's end, s")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a config override")
    args = ap.parse_args(argv)
    if not 0.0 <= args.t0 < args.t1 <= 30.0:
        print(f"world_contacts: --from {args.t0} --to {args.t1}: need 0 <= from < to <= 30 s", file=sys.stderr)
        return 2
    try:
        cfg = load_config(args.config, dict(parse_override(text) for text in args.set))
    except ConfigError as exc:
        print(f"world_contacts: {exc}", file=sys.stderr)
        return 2
    world = World(cfg)
    names = {shape: f"frame{f.index}.{'back' if k == 0 else 'front'}" for f in world.frames
             for k, shape in enumerate(f.shapes)}
    while world.t < args.t0:
        world.step()
    print("t s      theta1 deg (frames 0, 1)  contacts: card depth_mm normal_N·s tangential_N·s")
    while world.t < args.t1:
        world.step()
        th = [math.degrees(f.body.angle) for f in world.frames[:2]]
        seen = "  ".join(f"{card} {depth:.3f} {jn:.2e} {jt:+.2e}{' new' if new else ''}"
                         for card, depth, jn, jt, new in contacts(world, names))
        print(f"{world.t:.5f}  {th[0]:8.3f} {th[1]:8.3f}   {seen}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
