"""The runner's phases: what a run is doing between two events, and what ends each phase.

==============  ==========================================================================
``Hanging``     the hook on frame i: the frame turns; checks its peak, its stop and its time, and
                when it has carried the robot through its lowest point (``CARRIED_THETA1_DEG``):
                from then the catch counts as a traversal, and on the last frame the row is complete
``LettingGo``   contact lost, for less than ``sim.contact_hold``: a bounce returns to Hanging,
                a lasting loss commits the detach (the state at the first step without contact);
                a caught frame that had not carried the robot ends the run (a catch that did not hold)
``Flight``      the robot free: watches the arm's snap and the hook's fall past the next seat;
                the floor or ``sim.flight_timeout`` ends the run as a named miss
``Catching``    the hook touches frame i+1: a touch held ``sim.contact_hold`` with the hook's
                centre within ``sim.catch_seat`` of the seat is a catch (and Hanging follows); a
                touch that never seats is a graze, and the flight goes on
==============  ==========================================================================

"Carried" is an event, step-exact like the catch and the detach: read every runner step while the hook
touches the frame and the frame has not yet carried it, and at the detach from the state at the first
step without contact (a frame at ``CARRIED_THETA1_DEG`` or past it there carried the robot).

Each phase's :meth:`step` runs every runner step (contact bookkeeping, so catch and detach times
are step-exact) and returns the phase that follows; :meth:`check` runs on the check cadence and
returns an ending ``(outcome, reason)`` or None; :meth:`observe` takes the check's world sample.
"""

from __future__ import annotations

import math

from .. import reasons as say
from .. import units
from ..results import Swing
from .swing_rules import CARRIED_THETA1_DEG, REST_MOVE, STOP_TOLERANCE, TURN_BACK_DEG
from .body_state import angle, handle
from .miss import FlightRecord, classify_miss
from .monitors import TunnelWatch


class Run:
    """What the phases share: the world, the config's thresholds and the swings so far."""

    def __init__(self, world, sim):
        self.world, self.sim, self.p = world, sim, world.p
        self.frames, self.robot = world.frames, world.robot
        self.touches = world.contact.touches
        # frame index -> touching faces, kept current by the contact's callbacks: the per-step test
        # of the phases is one lookup in it
        self.touching = world.contact.touching
        self.holding_note = world.contact.holding_note
        p = self.p
        self.snapped_alpha = p.alpha_min + 0.5 * (p.alpha_max - p.alpha_min)  # the arm swung half its range
        self.near_stop = p.stop_angle - STOP_TOLERANCE
        self.turn_back = math.radians(TURN_BACK_DEG)
        self.carried_angle = math.radians(CARRIED_THETA1_DEG)
        self.swings: list[Swing] = []
        self.tunnel: TunnelWatch | None = None  # the flight's watch on the next frame's card (monitors.TunnelWatch)
        self.traversals = 0  # catches that carried the robot: frames 1..traversals
        # engine units: the hook's closest approach to the seat of frame traversals + 1 since the last traversal
        # (the runner samples it on the check cadence; a catch adds its touch's every step)
        self.closest = math.inf
        self.ending: tuple[str, str] | None = None

    def next_seat(self, origin: int):
        return self.frames[origin + 1].hook_seat_world() if origin + 1 < len(self.frames) else None

    def seat_distance(self, frame) -> float:
        return (self.robot.hook_world() - frame.hook_seat_world()).length

    def carried(self, swing: Swing, t: float) -> tuple[str, str] | None:
        """The frame of ``swing`` has carried the robot through its lowest point at ``t``: its catch counts
        (the start's swing on frame 0 counts nothing). Returns the ending when that completes the row."""
        swing.t_carried = t
        if swing.frame > 0:
            self.traversals = swing.frame
            if swing.frame == len(self.frames) - 1:
                return "completed", say.completed(swing.frame)
        return None


class Hanging:
    """The hook on ``frame``, caught at ``t``."""

    name = "hanging"
    every_step = False

    def __init__(self, run: Run, frame, t: float):
        self.run, self.frame = run, frame
        self.index, self.touching = frame.index, run.touching
        self.frame_c = handle(frame.body)  # its angle is read every step (body_state)
        self.t_touch = t  # the last runner step at which the hook touched the frame
        self.peak = frame.theta
        self.t_stop: float | None = None
        self.swing = run.swings[-1]

    def step(self, t: float):
        if self.index in self.touching:
            self.t_touch = t
            if self.swing.t_carried is None and angle(self.frame_c) >= self.run.carried_angle:
                self.run.ending = self.run.carried(self.swing, t)
            return self
        return LettingGo(self).step(t)

    def check(self, t: float):
        run, frame, sim, p = self.run, self.frame, self.run.sim, self.run.p
        theta1 = frame.theta
        self.peak = max(self.peak, theta1)
        if theta1 >= run.near_stop:
            self.t_stop = t if self.t_stop is None else self.t_stop
            if t - self.t_stop >= sim.stop_hold:
                return "no_detach", say.held_at_stop(frame.index, sim.stop_hold, math.degrees(p.stop_angle),
                                                     run.holding_note)
        else:
            self.t_stop = None
            if theta1 < self.peak - run.turn_back:
                peak = math.degrees(self.peak)
                if self.peak >= p.held_past:  # swing_rules.held_past_angle: friction held the hook
                    return "no_detach", say.turned_back_holding(frame.index, peak, math.degrees(p.held_past),
                                                                run.holding_note)
                return "stalled", say.turned_back(frame.index, peak)
        since_catch = t - self.swing.t_catch
        if self.peak < p.rest_angle + REST_MOVE and since_catch > sim.rest_timeout:
            return "stalled", say.never_left_rest(frame.index, sim.rest_timeout)
        if since_catch > sim.swing_timeout:
            if self.peak >= p.held_past:  # past the balance angle and still hooked: friction holds it
                return "no_detach", say.held_past_balance(frame.index, math.degrees(self.peak),
                                                          math.degrees(p.held_past), sim.swing_timeout,
                                                          run.holding_note)
            return "stalled", say.swing_too_long(frame.index, sim.swing_timeout)
        return None

    def observe(self, sample) -> None:
        sw = self.swing
        th2 = math.degrees(sample.theta2)
        sw.theta2_min_deg, sw.theta2_max_deg = min(sw.theta2_min_deg, th2), max(sw.theta2_max_deg, th2)
        sx, sy = self.frame.hook_seat_at(sample.frames[self.index])  # the hanging frame is live
        gap = math.hypot(sample.hook[0] - sx, sample.hook[1] - sy)
        sw.catch_seat_mm = min(sw.catch_seat_mm, gap)  # engine units (mm) until the result is built


class LettingGo:
    """Contact with the hanging frame lost at the step after ``hanging.t_touch``."""

    name = "letting_go"
    every_step = False

    def __init__(self, hanging: Hanging):
        self.hanging = hanging
        run, frame = hanging.run, hanging.frame
        # the state at the detach: the first step without contact
        self.record = FlightRecord(frame.index, hanging.t_touch, frame.theta, run.robot.alpha,
                                   run.robot.hook_world().y, run.next_seat(frame.index), run.snapped_alpha)

    def step(self, t: float):
        h, run = self.hanging, self.hanging.run
        if run.touches(h.frame.index):  # a brief loss of contact was a bounce, not a detach
            h.t_touch = t
            return h
        self.record.observe(t, run.robot)
        if t - h.t_touch >= run.sim.contact_hold:
            sw, rec = h.swing, self.record
            sw.t_detach, sw.theta1_detach_deg = h.t_touch, math.degrees(rec.theta1_detach)
            sw.swing_duration = h.t_touch - sw.t_catch
            sw.alpha_detach_deg = math.degrees(rec.alpha_detach)
            if sw.t_carried is None and rec.theta1_detach >= run.carried_angle:  # it got there as the contact was lost
                run.ending = run.carried(sw, h.t_touch)
            if sw.t_carried is None and sw.frame > 0:  # caught, let go before it was carried: no traversal
                run.ending = ("missed_catch", say.catch_did_not_hold(
                    sw.frame - 1, units.length_to_si(sw.catch_seat_mm), sw.swing_duration, sw.theta1_detach_deg))
            if run.ending:
                return self
            return Flight(run, rec)
        return self

    def check(self, t: float):
        return self.hanging.check(t)

    def observe(self, sample) -> None:
        self.hanging.observe(sample)


class Flight:
    """The robot free after letting go of frame ``record.origin``."""

    name = "flight"
    every_step = False

    def __init__(self, run: Run, record: FlightRecord):
        self.run, self.record = run, record
        self.next = run.frames[record.origin + 1]
        run.tunnel = self.tunnel = TunnelWatch(run.world, self.next)
        self.tunnel.step()

    def step(self, t: float):
        run = self.run
        through = self.tunnel.step()
        if through:
            run.ending = ("unstable", through)
            return self
        if run.touches(self.next.index):
            return Catching(self, t).step(t)
        self.record.observe(t, run.robot)
        # The hook (the robot's one collision shape) reaching the floor is the fall's end: read every step, so
        # the run ends at the touch, before the floor's impact, which the solver answers by giving energy back
        if run.world.on_floor(*self.tunnel.hook, run.p.hook_radius):  # the hook as the watch read it this step
            run.ending = classify_miss(self.record, run.p)
        return self

    def check(self, t: float, touching_gap: float | None = None):
        """The floor (the robot's centre below it; the hook on it ends the run in :meth:`step`) or the flight
        timeout ends the run as a named miss; ``touching_gap``: the hook still touches the next handrail, this
        far from its seat at best (a graze)."""
        run = self.run
        com = run.robot.com_world()
        if com.y < run.world.floor_y(com.x) or t - self.record.t_detach > run.sim.flight_timeout:
            if touching_gap is not None:
                self.record.note_graze(touching_gap)
            return classify_miss(self.record, run.p)
        return None

    def observe(self, sample) -> None:
        pass


class Catching:
    """The hook touching the next frame since ``t_first``: every step is checked, because the
    hook's landing is where it sinks deepest into the card."""

    name = "catching"
    every_step = True

    def __init__(self, flight: Flight, t_first: float):
        self.flight, self.t_first = flight, t_first
        self.closest = math.inf  # the hook centre's closest approach to the seat during this touch

    def step(self, t: float):
        fl = self.flight
        run, frame = fl.run, fl.next
        through = fl.tunnel.step()
        if through:
            run.ending = ("unstable", through)
            return self
        if not run.touches(frame.index):
            fl.record.note_graze(self.closest)  # the touch ended without a catch: a graze, unless a later one seats
            return fl
        fl.record.observe(t, run.robot)
        self.closest = min(self.closest, run.seat_distance(frame))
        if t - self.t_first >= run.sim.contact_hold and self.closest <= run.p.catch_seat:
            return self._caught(t)
        return self

    def _caught(self, t: float):
        run, frame = self.flight.run, self.flight.next
        run.closest = min(run.closest, self.closest)  # the transfer goes on until the frame carries the robot
        run.world.set_active(frame.index)
        th2 = math.degrees(run.robot.theta2())
        hook = frame.body.world_to_local(run.robot.hook_world()) - frame.hook_seat_local  # engine units (mm)
        run.swings.append(Swing(frame.index, self.t_first, math.degrees(frame.theta), th2,
                                theta2_min_deg=th2, theta2_max_deg=th2, catch_seat_mm=self.closest,
                                omega1_catch=frame.omega,
                                robot_speed_catch=units.velocity_to_si(run.robot.com_velocity().length),
                                hook_along_catch_mm=units.length_to_si(hook.x) * 1e3,
                                hook_across_catch_mm=units.length_to_si(hook.y) * 1e3))
        return Hanging(run, frame, t)  # a traversal (or, on the last frame, the row) once the frame carries it

    def check(self, t: float):
        return self.flight.check(t, self.closest)  # ending while still touching unseated is a graze

    def observe(self, sample) -> None:
        pass
