"""Energy budget of one transfer, and the catch that the paper's swing duration implies.

Method. :func:`transfer_budget` builds ``World(cfg)`` and steps it with the runner's own phases
(:mod:`.phases`: Hanging, LettingGo, Flight, Catching), so a catch (a touch held
``sim.contact_hold`` with the hook within ``sim.catch_seat`` of the seat, which calls
``world.set_active``) and a detach (contact lost for ``contact_hold``) are the runner's, step for
step. From the catch on frame-1 to the detach from ``frame`` it books, every runner step, the
mechanical energy by part: the robot's kinetic (translation and rotation of torso and arm) and
potential energy, the leaf spring's, and the kinetic and potential energy of the caught frame and
of the previous one (each frame with its counterbalance and handrail is one pymunk body), from the
bodies' masses, moments and centres of gravity as ``World._energy_of`` does. It also sums the work
of the skewer and axle Coulomb friction (the capped motors' impulse times the relative rate; exact
for one substep a runner step). The events are read off the booked steps; between two consecutive
events the budget gives what robot, spring and caught frame lost, the part lost in the event's own
step (an impact: the arm on a stop, the hook on the card), the part taken by skewer and axle friction
(the rest: the hook's friction and contact between events), and what the frame left behind lost (its
skewer and its stopper). Waiting and parked frames do not move, so the booked total changes as
``world.energy()`` does (both are kept).

:func:`implied_catch_keep` reruns the world to the catch confirmation on ``frame``, multiplies every
live body's velocity and angular velocity by sqrt(f) (kinetic energy times f, positions unchanged),
runs on to the detach and takes the runner's swing duration (first touch of the seating touch to
the last step in contact, as ``Swing.swing_duration``); then it bisects f in [0, 1] for a target.
``at="alpha_max"`` scales instead just after the arm's first strike on its alpha_max stop after the
catch, once the robot has dropped onto its fully bent spring (in the steady row the catch is
confirmed with the arm still snapped forward, and that drop comes after it).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import pymunk

from .. import units
from ..config import Config
from ..results import Swing
from .swing_rules import STOP_TOLERANCE
from .phases import Hanging, Run
from .world import World

PARTS = ("robot_ke", "robot_pe", "spring", "frame_ke", "frame_pe", "prev_ke", "prev_pe")
TRANSFER, PREV = slice(0, 5), slice(5, 7)  # robot, spring and caught frame; the frame left behind
# The arm has struck a stop in a step that ends within STRIKE_TOL of it, having come at it faster than
# STRIKE_RATE and leaving at less than half that speed.
STRIKE_TOL, STRIKE_RATE = math.radians(1.0), 0.5  # rad, rad/s
GRID = (0.0, 0.25, 0.5, 0.75, 1.0)
JUMP = 0.01  # s: durations this far apart at the bisection's ends jump across the target (e.g. from no detach)


class Row(NamedTuple):
    """One runner step, engine units."""

    n: int  # runner steps since the start
    parts: tuple  # energies in the order of PARTS
    world_total: float  # world.energy(), J (parked frames included)
    friction: float  # work of the caught frame's skewer and the axle friction since the recording began
    alpha: float
    alpha_rate: float
    theta: float  # the caught frame's theta1
    theta_prev: float
    touching: bool  # the hook touches the caught frame
    caught: bool  # the runner has confirmed the catch on the frame


def run_steps(world: World, cfg: Config):
    """Step ``world`` from its start (hook on frame 0 at rest) with the runner's phases; yield the
    :class:`Run` after each runner step. The phases' checks (which only read the world) run every
    step; the first ending they name is left in ``run.ending`` and ends the stepping."""
    run = Run(world, cfg.sim)
    th2 = math.degrees(world.robot.theta2())
    run.swings.append(Swing(0, 0.0, math.degrees(world.frames[0].theta), th2, theta2_min_deg=th2, theta2_max_deg=th2))
    phase = Hanging(run, world.frames[0], 0.0)
    for _ in range(int(math.ceil(cfg.sim.t_max / world.p.step))):
        world.step()
        phase = phase.step(world.t)
        run.ending = run.ending or phase.check(world.t)
        yield run
        if run.ending:
            return


def body_energy(world: World, b: pymunk.Body) -> tuple[float, float]:
    """(kinetic, potential) of one body, engine units (g·mm²/s²)."""
    cog = b.local_to_world(b.center_of_gravity)
    ke = 0.5 * (b.mass * b.velocity.length_squared + b.moment * b.angular_velocity ** 2)
    return ke, b.mass * world.p.gravity * cog.y


def energy_parts(world: World, frame: int) -> tuple:
    """The energies of PARTS now, engine units: robot, spring, frame ``frame`` and ``frame - 1``."""
    robot = [body_energy(world, b) for b in world.robot.bodies]
    fk, fp = body_energy(world, world.frames[frame].body)
    pk, pp = body_energy(world, world.frames[frame - 1].body)
    return (sum(e[0] for e in robot), sum(e[1] for e in robot), world.spring.energy_for(world.robot.alpha),
            fk, fp, pk, pp)


def _friction_terms(world: World, frame: int):
    """(motor, relative rate) of the Coulomb friction parts on the robot and the caught frame."""
    f, robot = world.frames[frame], world.robot
    terms = [(c, lambda: f.body.angular_velocity) for c in f.constraints if isinstance(c, pymunk.SimpleMotor)]
    return terms + [(c, lambda: robot.alpha_rate) for c in getattr(robot, "joints", ())
                    if isinstance(c, pymunk.SimpleMotor)]


def record_transfer(cfg: Config, frame: int):
    """Run to the detach from ``frame``, booking every step from the catch on ``frame - 1``.
    Returns (rows, run, world)."""
    if not 1 <= frame < cfg.scene.frames - 1:
        raise ValueError(f"frame {frame}: a flight-entered swing with a detach needs 1 <= frame < "
                         f"{cfg.scene.frames - 1}")
    world = World(cfg)
    terms, substeps = _friction_terms(world, frame), world.p.substeps
    rows, work = [], 0.0
    f, prev = world.frames[frame], world.frames[frame - 1]
    for run in run_steps(world, cfg):
        if len(run.swings) < frame:
            continue
        work += substeps * sum(c.impulse * abs(rate()) for c, rate in terms)
        rows.append(Row(world.steps, energy_parts(world, frame), world.energy(), work, world.robot.alpha,
                        world.robot.alpha_rate, f.theta, prev.theta, world.contact.touches(frame),
                        len(run.swings) > frame))
        if run.swings[-1].frame == frame and run.swings[-1].t_detach is not None:
            # the runner commits a detach contact_hold after the last contact: book until then
            return rows, run, world
    raise RuntimeError(f"no detach from frame {frame}: {': '.join(run.ending or ('timeout', 'sim.t_max'))}")


def struck(limit: float, sign: float, alpha: float, rate: float, rate_before: float) -> bool:
    """Whether the arm struck the stop at ``limit`` (sign +1: alpha_max, -1: alpha_min) in this step."""
    towards, before = sign * rate, sign * rate_before
    return abs(alpha - limit) < STRIKE_TOL and before > STRIKE_RATE and towards < 0.5 * before


def find_events(rows, run, frame: int, p) -> list[tuple[str, int]]:
    """(name, row index) of each event of the transfer, in time order."""
    at = {r.n: k for k, r in enumerate(rows)}
    first_free = lambda t: at[round(t / p.step) + 1]  # noqa: E731  the first step without contact
    start, end = first_free(run.swings[frame - 1].t_detach), first_free(run.swings[frame].t_detach)
    events = [(f"detach from frame {frame - 1}", start), (f"detach from frame {frame}", end)]
    span = range(start + 1, end)
    touch = next(k for k in span if rows[k].touching)
    catch = next(k for k in span if rows[k].caught)
    events += [(f"first touch of frame {frame}", touch), (f"catch confirmed on frame {frame}", catch)]
    for k in range(touch + 1, catch):
        if rows[k].touching != rows[k - 1].touching:
            events.append((f"hook {'touches' if rows[k].touching else 'leaves'} frame {frame}", k))
    for k in span:
        for name, limit, sign in (("alpha_min", p.alpha_min, -1.0), ("alpha_max", p.alpha_max, 1.0)):
            if struck(limit, sign, rows[k].alpha, rows[k].alpha_rate, rows[k - 1].alpha_rate):
                events.append((f"arm strikes its {name} stop", k))
    stop = next((k for k in span if rows[k].theta_prev >= p.stop_angle - STOP_TOLERANCE), None)
    if stop is not None:
        events.append((f"frame {frame - 1} reaches its stopper", stop))
    low = next((k for k in range(catch, end) if rows[k].theta >= math.pi / 2), None)
    if low is not None:
        events.append(("lowest point (theta1 = 90 deg)", low))
    return sorted(events, key=lambda e: e[1])


def group_energy(row: Row, part: slice = TRANSFER) -> float:
    """The energy (J) of a group of PARTS at a booked step."""
    return units.energy_to_si(sum(row.parts[part]))


def transfer_budget(cfg: Config, frame: int = 1) -> dict:
    """The energy budget (J, s) of the flight from ``frame - 1`` and the swing on ``frame``.

    ``events``: per event its time, each part of PARTS, their ``total`` and the world's own total
    (``world_total``, parked frames included); since the previous event, the ``loss`` of robot, spring
    and caught frame, the part of it in the event's own step (``loss_in_step``: an impact), the work of
    the caught frame's skewer and the axle friction in it (``friction``), and the loss of the frame
    left behind (``prev_loss``: its skewer and its stopper). ``flight_ke``: the robot's kinetic energy
    in the step before the first touch; ``catch_loss``: what robot and caught frame lose from that
    step to the catch confirmation; ``kept_ke``: their kinetic energy at the catch confirmation;
    ``t_seating_touch``: the first touch of the touch that seats (the runner's ``Swing.t_catch``, later
    than ``t_first_touch`` when a graze came first)."""
    rows, run, world = record_transfer(cfg, frame)
    found = find_events(rows, run, frame, world.p)
    events, prev = [], None
    for k in sorted({k for _, k in found}):  # events of one step share a row
        name = " + ".join(n for n, j in found if j == k)
        r, q = rows[k], rows[k if prev is None else prev]
        events.append({"event": name, "t": r.n * world.p.step,
                       **{part: units.energy_to_si(v) for part, v in zip(PARTS, r.parts)},
                       "total": units.energy_to_si(sum(r.parts)), "world_total": r.world_total,
                       "loss": group_energy(q) - group_energy(r),
                       "loss_in_step": group_energy(rows[k - 1]) - group_energy(r),
                       "friction": units.energy_to_si(r.friction - q.friction),
                       "prev_loss": group_energy(q, PREV) - group_energy(r, PREV)})
        prev = k
    index = {name: k for name, k in reversed(found)}  # the first of each name
    before_touch = rows[index[f"first touch of frame {frame}"] - 1]
    catch = rows[index[f"catch confirmed on frame {frame}"]]
    return {"frame": frame, "events": events, "flight_ke": units.energy_to_si(before_touch.parts[0]),
            "kept_ke": units.energy_to_si(catch.parts[0] + catch.parts[3]),
            "catch_loss": group_energy(before_touch) - group_energy(catch),
            "t_first_touch": (before_touch.n + 1) * world.p.step, "t_seating_touch": run.swings[frame].t_catch,
            "t_catch": catch.n * world.p.step, "swing_duration": run.swings[frame].swing_duration,
            "loss_total": events[0]["total"] - events[-1]["total"]}


def swing_with_keep(cfg: Config, frame: int, f: float, at: str = "catch") -> tuple[float, float]:
    """(duration, kept): the swing's duration on ``frame`` (s, the runner's: from the first touch of
    the seating touch; inf without a detach within ``sim.swing_timeout``) when the kinetic energy of
    every live body is multiplied by ``f`` at the catch confirmation (``at="catch"``) or at the arm's
    first strike on its alpha_max stop after it, or at once if it rests there (``at="alpha_max"``);
    ``kept``: the kinetic energy (J)
    of the robot and the caught frame there, before the scaling."""
    world = World(cfg)
    robot, p, scale, kept, rate_before = world.robot, world.p, math.sqrt(f), None, 0.0
    for run in run_steps(world, cfg):
        caught = len(run.swings) > frame
        resting = robot.alpha > p.alpha_max - STRIKE_TOL and abs(robot.alpha_rate) < STRIKE_RATE
        if caught and kept is None and (at == "catch" or resting
                                        or struck(p.alpha_max, 1.0, robot.alpha, robot.alpha_rate, rate_before)):
            kept = units.energy_to_si(sum(body_energy(world, b)[0] for b in (*robot.bodies, world.frames[frame].body)))
            for b in (*(fr.body for fr in world.live_frames()), *robot.bodies):
                b.velocity, b.angular_velocity = b.velocity * scale, b.angular_velocity * scale
        rate_before = robot.alpha_rate
        sw = run.swings[frame] if caught else None
        if sw and (sw.swing_duration is not None or world.t - sw.t_catch > cfg.sim.swing_timeout):
            break
    if kept is None:
        raise ValueError(f"frame {frame}: no {at} to scale the kinetic energy at before the detach")
    done = run.swings[frame].swing_duration if len(run.swings) > frame else None
    return (math.inf if done is None else done), kept


def implied_catch_keep(cfg: Config, frame: int = 1, target: float = 0.62, at: str = "catch",
                       tol: float = 1e-3) -> dict:
    """The fraction f of the kinetic energy at the catch confirmation (``at="alpha_max"``: once the arm
    is on its alpha_max stop after it, see :func:`swing_with_keep`) for which the swing on ``frame``
    lasts ``target`` s, by bisection (durations fall as f grows). ``f`` is None, with a ``note`` saying
    why, when even f = 0 is shorter than the target, f = 1 longer, or the duration jumps across it.
    ``kept_ke``: what robot and caught frame keep there; ``flight_ke``: the robot's before the touch."""
    from .run import simulate

    durations, kept = {}, 0.0
    for f in GRID:
        durations[f], kept = swing_with_keep(cfg, frame, f, at)
    out = {"frame": frame, "target": target, "at": at, "durations": durations, "kept_ke": kept,
           "flight_ke": transfer_budget(cfg, frame)["flight_ke"],
           "simulated_duration": simulate(cfg).swings[frame].swing_duration,
           "f": None, "duration_at_f": None, "needed_ke": None, "note": ""}
    if durations[0.0] < target:
        out["note"] = f"even f = 0 (no kinetic energy kept at the {at}) swings {durations[0.0]:.3f} s < {target} s"
        return out
    if durations[1.0] > target:
        out["note"] = f"f = 1 already swings {durations[1.0]:.3f} s > {target} s: the catch would need to keep more"
        return out
    lo, hi = 0.0, 1.0
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if swing_with_keep(cfg, frame, mid, at)[0] > target else (lo, mid)
    f = 0.5 * (lo + hi)
    d_lo, d_hi = swing_with_keep(cfg, frame, lo, at)[0], swing_with_keep(cfg, frame, hi, at)[0]
    if d_lo - d_hi > JUMP:  # the duration does not pass through the target: it jumps across it
        out["note"] = (f"the duration jumps from {d_lo:.3f} s to {d_hi:.3f} s across {target} s at f = {f:.4f}: "
                       f"no f gives {target} s")
        return out
    out.update(f=f, duration_at_f=swing_with_keep(cfg, frame, f, at)[0], needed_ke=f * kept)
    return out
