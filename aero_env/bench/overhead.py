"""``aero-env bench overhead``: what the Python layer costs over the bare ``space.step`` calls.

One scene (the config's own design), at its fidelity. ``bare`` is pymunk alone stepping through
the same run: the run is made once and records what its Python layer changed in the space
between steps (``World.inputs``: the live window's moves and the friction switch's changes, a few
dozen in all); ``bare`` builds the same world and replays them around plain ``space.step(dt)``
calls, nothing else per step (the callbacks pymunk itself runs, the contact's begin/separate, stay).
The replay ends in the run's final state bit for bit (``bare_replays_run``), so pymunk meets the
same contacts in both and the ratio is the Python layer's alone. The full run is then taken apart
by switching its per-step work off one piece at a time:

| row                 | what runs                                                           |
|---------------------|---------------------------------------------------------------------|
| ``bare``            | ``space.step`` only, through the same run                           |
| ``c_step``          | Chipmunk's ``cpSpaceStep`` only, as the runner calls it (pymunk's   |
|                     | ``Space.step`` is Python around it, which the runner skips)         |
| ``loop``            | the runner with one friction coefficient and checks every 1 s (its  |
|                     | own, slightly different run: kinetic friction throughout)           |
| ``loop+friction``   | ... plus the static/kinetic switch, once per runner step            |
| ``full``            | the run as configured (checks every ``sim.check_interval``)          |

``python_layer_ratio`` is ``full`` against ``bare``: what the runner costs over plain pymunk.
``layer_ratio_vs_c_step`` is ``full`` against ``c_step``, the C engine alone: it counts pymunk's own
wrapper as part of the layer, so it is the stricter of the two.

The rows are timed in turn within each of ``repeats`` rounds, so a machine that gets busier or
quieter during the call moves them alike; each time is the median over the rounds and every ratio
is against ``bare`` in the same call.
"""

from __future__ import annotations

import statistics
import time

from pymunk._chipmunk_cffi import lib as _cp

from ..config import Config, ConfigError, pymunk_fidelities
from ..physics import World
from ..physics.run import simulate as simulate_mbd
from ..simulation import simulate
from .designs import check_counts

# The rows beside ``bare`` and ``full``: what each switches off, as config overrides.
_VARIANTS = {
    "loop": {"scene.effects.friction": "kinetic", "sim.check_interval": 1.0},
    "loop+friction": {"sim.check_interval": 1.0},
}


cpSpaceStep = _cp.cpSpaceStep


def replay(world: World, inputs: list, steps: int, c_step: bool = False) -> None:
    """Step a freshly built ``world`` through a run of ``steps`` runner steps with bare ``space.step``
    calls, applying the run's ``inputs`` (``World.inputs``) where its runner made them. ``c_step``: call
    Chipmunk's ``cpSpaceStep`` instead, as the runner does, except for the first step and the first after
    each input (pymunk's ``Space.step`` then checks the bodies a window move added, as in ``World.step``)."""
    wrapper, dt, substeps = world.space.step, world.p.dt, world.p.substeps
    c, cs = cpSpaceStep, world.space._space

    def steps_to(n: int) -> None:
        if n > 0 and c_step:
            wrapper(dt)
            for _ in range(n - 1):
                c(cs, dt)
        else:
            for _ in range(n):
                wrapper(dt)

    done = 0
    for at, what, value in inputs:
        steps_to((at - done) * substeps)
        done = at
        if what == "active":
            world.set_active(value)
        else:  # "friction"
            world.contact.hook_shape.friction = value
    steps_to((steps - done) * substeps)


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def overhead(cfg: Config, repeats: int = 5) -> dict:
    check_counts(repeats=repeats)
    if cfg.sim.model != "mbd":
        raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r}: the overhead benchmark measures the pymunk world; "
                          f"choose a pymunk fidelity ({pymunk_fidelities()})")
    recorded = World(cfg)
    run = simulate_mbd(cfg, world=recorded)
    inputs, steps = list(recorded.inputs), recorded.steps
    replays = True
    for c_step in (False, True):
        check = World(cfg)
        replay(check, inputs, steps, c_step)
        replays &= check.energy() == run.energy["final"]  # every live body's state enters the energy

    configs = {"full": cfg, **{name: cfg.replace(over) for name, over in _VARIANTS.items()}}
    times: dict[str, list[float]] = {"bare": [], "c_step": [], **{name: [] for name in configs}}
    for _ in range(repeats):
        world = World(cfg)  # building the world is not stepping it
        times["bare"].append(_timed(lambda: replay(world, inputs, steps)))
        world = World(cfg)
        times["c_step"].append(_timed(lambda: replay(world, inputs, steps, c_step=True)))
        for name, c in configs.items():
            times[name].append(_timed(lambda: simulate(c)))
    wall = {name: statistics.median(ts) for name, ts in times.items()}
    n = steps * cfg.sim.substeps  # pymunk steps the run took
    rows = [dict(name=name, wall=wall[name], per_pymunk_step_us=1e6 * wall[name] / n,
                 ratio_vs_bare=wall[name] / wall["bare"]) for name in ("bare", "c_step", *_VARIANTS, "full")]
    return dict(fidelity=cfg.sim.fidelity, pymunk_steps=n, sim_time=run.sim_time, outcome=run.outcome,
                realtime_factor=run.sim_time / wall["full"], python_layer_ratio=wall["full"] / wall["bare"],
                layer_ratio_vs_c_step=wall["full"] / wall["c_step"],
                bare_replays_run=replays, replayed_inputs=len(inputs), repeats=repeats, rows=rows)


def table(report: dict) -> str:
    same = "bit for bit" if report["bare_replays_run"] else "NOT reproduced: the ratio compares different runs"
    lines = [f"fidelity {report['fidelity']}: {report['pymunk_steps']} pymunk steps ({report['sim_time']:.3f} s "
             f"simulated, {report['outcome']}), median of {report['repeats']} runs; "
             f"{report['realtime_factor']:.0f}x real time",
             f"bare replays the run ({report['replayed_inputs']} inputs): {same}",
             f"{'':>14} {'wall ms':>8} {'us/step':>8} {'x bare':>7}"]
    for r in report["rows"]:
        lines.append(f"{r['name']:>14} {1e3 * r['wall']:8.1f} {r['per_pymunk_step_us']:8.2f} {r['ratio_vs_bare']:7.2f}")
    lines.append(f"python layer: {report['python_layer_ratio']:.2f}x bare space.step; "
                 f"{report['layer_ratio_vs_c_step']:.2f}x the C step alone")
    return "\n".join(lines)
