"""``aero-env bench overhead``: what the Python layer costs over the bare ``space.step`` calls.

One scene (the config's own design), at its fidelity. ``bare`` builds the same world and calls
``space.step(dt)`` as many times as the run stepped pymunk, and nothing else: no events, no
checks, no friction switch (the contact callbacks that pymunk itself runs stay). The full run is
then taken apart by switching its per-step work off one piece at a time:

| row                 | what runs                                                           |
|---------------------|---------------------------------------------------------------------|
| ``bare``            | ``space.step`` only                                                  |
| ``loop``            | the runner with one friction coefficient and checks every 1 s        |
| ``loop+friction``   | ... plus the static/kinetic switch, once per runner step            |
| ``full``            | the run as configured (checks every ``sim.check_interval``)          |

Each time is the median of ``repeats`` runs; every ratio is against ``bare`` in the same call.
"""

from __future__ import annotations

from ..config import Config, ConfigError
from ..physics import World
from ..simulation import simulate
from .designs import check_counts, median_time


def _bare(cfg: Config, n: int) -> None:
    world = World(cfg)
    space, dt = world.space, world.p.dt
    for _ in range(n):
        space.step(dt)


def overhead(cfg: Config, repeats: int = 5) -> dict:
    check_counts(repeats=repeats)
    if cfg.sim.model != "mbd":
        raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r}: the overhead benchmark measures the pymunk world; "
                          f"choose a pymunk fidelity (mbd-fast, mbd, mbd-fine, reference)")
    full_wall, run = median_time(lambda: simulate(cfg), repeats)
    n = round(run.sim_time / cfg.sim.dt)  # pymunk steps the run took
    bare_wall, _ = median_time(lambda: World(cfg), repeats)  # building the world is not stepping it
    bare_wall = median_time(lambda: _bare(cfg, n), repeats)[0] - bare_wall
    variants = {
        "loop": {"scene.effects.friction": "kinetic", "sim.check_interval": 1.0},
        "loop+friction": {"sim.check_interval": 1.0},
    }
    rows = [dict(name="bare", wall=bare_wall)]
    for name, over in variants.items():
        c = cfg.replace(over)
        rows.append(dict(name=name, wall=median_time(lambda: simulate(c), repeats)[0]))
    rows.append(dict(name="full", wall=full_wall))
    for r in rows:
        r["per_pymunk_step_us"] = 1e6 * r["wall"] / n
        r["ratio_vs_bare"] = r["wall"] / bare_wall
    return dict(fidelity=cfg.sim.fidelity, pymunk_steps=n, sim_time=run.sim_time, outcome=run.outcome,
                realtime_factor=run.sim_time / full_wall, python_layer_ratio=full_wall / bare_wall,
                repeats=repeats, rows=rows)


def table(report: dict) -> str:
    lines = [f"fidelity {report['fidelity']}: {report['pymunk_steps']} pymunk steps ({report['sim_time']:.3f} s "
             f"simulated, {report['outcome']}), median of {report['repeats']} runs; "
             f"{report['realtime_factor']:.0f}x real time",
             f"{'':>14} {'wall ms':>8} {'us/step':>8} {'x bare':>7}"]
    for r in report["rows"]:
        lines.append(f"{r['name']:>14} {1e3 * r['wall']:8.1f} {r['per_pymunk_step_us']:8.2f} {r['ratio_vs_bare']:7.2f}")
    return "\n".join(lines)
