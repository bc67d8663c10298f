"""The ``aero-env cycle`` subcommand.

    aero-env cycle CONFIG [--frames N] [--last K] [--json] [--set KEY=VALUE ...]

Runs the scene on a row of N frames (``--frames`` sets ``scene.frames``, default 100) and reports
the spread and drift of the state at each of the last K catches (default 50), with whether the
row was completed and, if not, where and why (:mod:`.report`). ``sim.t_max`` is raised, never
lowered, to N·(``sim.swing_timeout`` + ``sim.flight_timeout``): every swing and flight has its own
limit, so the row cannot run out of time before one of them ends it.

``--frames`` and ``--last`` are checked before anything is simulated (one line naming the option,
the value and what is allowed, exit 2); K must leave out the start from rest and the first catch
from a flight (K < N - 1). Exit 0 when the row was completed and the cycle settled, 1 otherwise.
"""

from __future__ import annotations

import json

from ..config import Config, Scene, Sim
from ..scene_args import whole_number
from .report import cycle_report, table

DEFAULT_FRAMES = 100
DEFAULT_LAST = 50
MIN_LAST = 2


def register(sub, scene_command) -> None:
    cp = scene_command(sub, "cycle", "does the robot settle into a limit cycle? the spread and drift of the state "
                                     "at each of the last K catches on a long row")
    cp.add_argument("--frames", metavar="N", default=str(DEFAULT_FRAMES),
                    help=f"frames in the row: sets scene.frames (default {DEFAULT_FRAMES})")
    cp.add_argument("--last", metavar="K", default=str(DEFAULT_LAST),
                    help=f"the catches the statistics cover, the row's last K (default {DEFAULT_LAST}; "
                         f"{MIN_LAST} <= K < N - 1)")
    cp.set_defaults(func=cmd_cycle)


def cmd_cycle(args) -> int:
    from ..scene_args import load_scene
    from ..simulation import simulate

    frames, last = check_counts(args.frames, args.last)
    cfg = long_row(load_scene(args), frames)
    result = simulate(cfg)
    doc = cycle_report(result, last, config=args.config, t_max=cfg.sim.t_max)
    print(json.dumps(doc, indent=2) if args.json else table(doc))
    return 0 if doc["settled"] else 1


def check_counts(frames_text, last_text) -> tuple[int, int]:
    """(--frames, --last) as whole numbers within their ranges, or a ConfigError naming the option."""
    hi = _field_bounds(Scene, "frames")[1]
    frames = whole_number("--frames", frames_text, MIN_LAST + 2, hi, "scene.frames")
    last = whole_number("--last", last_text, MIN_LAST, frames - 2,
                  f"less than --frames - 1 = {frames - 1}: the window leaves out the start from rest and the first "
                  f"catch from a flight")
    return frames, last


def long_row(cfg: Config, frames: int) -> Config:
    """``cfg`` on a row of ``frames`` frames, with ``sim.t_max`` raised to cover every swing and flight."""
    needed = frames * (cfg.sim.swing_timeout + cfg.sim.flight_timeout)
    t_max = min(max(cfg.sim.t_max, needed), _field_bounds(Sim, "t_max")[1])
    return cfg.replace({"scene.frames": frames, "sim.t_max": t_max})


def _field_bounds(cls, name: str) -> tuple[float | None, float | None]:
    meta = cls.__dataclass_fields__[name].metadata
    return meta["lo"], meta["hi"]
