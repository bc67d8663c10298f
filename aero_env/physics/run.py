"""Run a scene along its row: events (catch, detach, stop, fall) and the run's outcome.

A run starts with the hook caught on frame 0 at its rest angle (t = 0 is that catch; the
paper's measured swing is the next one, entered from a flight). A traversal succeeds when the
robot, having left frame i, is caught by frame i+1 with its hook seated (a touch held
``sim.contact_hold`` within ``sim.catch_seat`` of the seat) *and that catch holds*: the frame,
the hook still on, carries the robot through its lowest point (theta1 reaches
:data:`~aero_env.physics.swing_rules.CARRIED_THETA1_DEG`, the handrail straight below the axis). A hook caught
2.95 mm off its seat can fall out 0.08 s later; counting the catch at once would pay for that. The
last frame completes the row by the same rule, not by reaching its stop: on every frame the
prototype lets go near 160 deg, short of the 180 deg stop, so "until the frame reaches its stop"
would fail the prototype on the last frame. A caught robot that lets go (a committed detach) before
it is carried ends the run as ``missed_catch`` (a catch that did not hold); one that stalls or
holds on (stalled, no_detach) before it is carried ends as that, and the catch is not counted
either. The run ends at the first failure or when the last frame has carried the robot, and names
its outcome:

==============  =====================================================================
``completed``   caught by the last frame of the row, which carried the robot through its lowest point
``no_detach``   the hook still holds ``stop_hold`` after the frame reached its stop, or the frame
                turned back from near its stop with the hook holding, or still holds it past its
                balance angle after ``swing_timeout`` (friction too high)
``stalled``     the frame never left its rest angle (``rest_timeout``), turned back well before its
                stop, or the swing outlasted ``swing_timeout`` short of its balance angle
``fell_short``  the hook slipped off too low (friction too low), or passed behind the next handrail
``missed_catch`` the arm did not swing forward in time (spring too weak or too stiff), the hook
                passed ahead of the next handrail, touched it without seating (a graze), or was
                caught and let go before the frame carried it (a catch that did not hold)
``unstable``    a non-finite or exploding state, mechanical energy rose above tolerance, a constraint
                gave past its limit, or the hook went through a handrail card between two steps
                (:class:`~.monitors.TunnelWatch`: the step is too large for the contact)
``timeout``     the run reached ``sim.t_max`` (should not happen: every phase has a limit)
==============  =====================================================================

The loop is a small state machine (:mod:`.phases`: hanging, letting go, flight, catching) with
the monitors and the recording beside it (:mod:`.monitors`) and the naming of misses in
:mod:`.miss`.
"""

from __future__ import annotations

import math
import time

from .. import reasons as say
from .. import units
from ..config import Config
from ..results import SimResult, Swing
from .kernels import load_kernels
from .monitors import TRACE_COLUMNS, Monitors, Recorder
from .phases import Hanging, Run
from .world import World

__all__ = ["simulate", "SimResult", "Swing", "TRACE_COLUMNS"]


def simulate(cfg: Config, trace: bool = False, poses_every: float | None = None,
             world: World | None = None) -> SimResult:
    """Simulate ``cfg`` in the pymunk world until the robot completes the row or fails.
    Deterministic for a config. ``world``: a fresh ``World(cfg)`` the caller keeps, to read after the
    run (``bench overhead`` replays its ``inputs``).

    Per runner step the loop does only what must be per step: the current phase's contact
    bookkeeping. The phase's own limits (the frame's peak and stop, the floor, time limits),
    the energy and the health monitors are read every ``sim.check_interval`` (5 ms), far finer
    than the thresholds they test (a 20 deg turn-back, a 0.3 s stop hold, a 1 s rest timeout),
    and on every step of a catch and of the run's first check interval.
    """
    load_kernels()  # the compiled parts' one-time load, before the clock
    wall0 = time.perf_counter()
    world = World(cfg) if world is None else world
    sim = cfg.sim
    run = Run(world, sim)
    frames, robot = world.frames, world.robot
    step_s = sim.dt * sim.substeps  # one runner step
    check_every = max(1, round(sim.check_interval / step_s))
    recorder = Recorder(world, trace, sim.trace_every, max(1, round(poses_every / step_s)) if poses_every else 0)
    monitors = Monitors(world, sim)

    th2 = math.degrees(robot.theta2())
    run.swings.append(Swing(0, 0.0, math.degrees(frames[0].theta), th2, theta2_min_deg=th2, theta2_max_deg=th2,
                            catch_seat_mm=run.seat_distance(frames[0])))
    phase = Hanging(run, frames[0], 0.0)
    ending: tuple[str, str] = ("timeout", say.reached_t_max(sim.t_max))
    # the frame the transfer aims at: its seat is read where it is at each check (a touch moves the frame)
    origin, target = 0, frames[1]

    world_step, recording = world.step, recorder.recording
    for n in range(1, int(math.ceil(sim.t_max / step_s)) + 1):
        world_step()
        t = world.t
        phase = phase.step(t)
        if run.ending:
            ending = run.ending
            break
        if run.traversals != origin:  # a catch that carried the robot moved it on: the miss distance starts again
            origin, target, run.closest = run.traversals, frames[min(run.traversals + 1, len(frames) - 1)], math.inf
        sample = None
        # every step of a catch, and of the run's first check interval: the robot is placed hanging at alpha_max,
        # and a spring too stiff to stay bent snaps the arm at once, its stop's impulse spiking the energy for a
        # few ms, between the 5 ms checks
        if phase.every_step or n % check_every == 0 or n < check_every:
            stop = phase.check(t)
            if stop:
                ending = stop
                break
            sample = world.sample()
            bad = monitors.check(sample)
            if bad:
                ending = ("unstable", bad)
                break
            st = sample.frames.get(target.index)
            sx, sy = target.hook_seat_world() if st is None else target.hook_seat_at(st)
            run.closest = min(run.closest, math.hypot(sample.hook[0] - sx, sample.hook[1] - sy))
            phase.observe(sample)
        if recording:
            recorder.after_step(n, t, sample)

    if run.tunnel is not None and run.tunnel.crossed:
        monitors.went_through(run.tunnel.depth())  # the health record says how deep it went
    recorder.finish()
    return _result(cfg, world, run, monitors, recorder, ending, run.closest, wall0, bool(poses_every))


def _result(cfg, world, run, monitors, recorder, ending, closest, wall0, posed) -> SimResult:
    """The run in SI: the one place the runner's engine values are converted back."""
    for sw in run.swings:
        if sw.catch_seat_mm is not None:
            sw.catch_seat_mm = units.length_to_si(sw.catch_seat_mm) * 1e3
    outcome, reason = ending
    return SimResult(
        traversals=run.traversals, frames=len(world.frames), outcome=outcome, reason=reason, swings=run.swings,
        energy=monitors.energy(world.energy()), sim_time=world.t, wall_time=time.perf_counter() - wall0,
        miss_distance=None if outcome == "completed" or not math.isfinite(closest) else units.length_to_si(closest),
        health=monitors.health(), trace=recorder.trace_dict(), poses=recorder.poses if posed else None,
        geometry=world.geometry() if posed else None, fidelity=cfg.sim.fidelity,
    )
