"""The run of one design along the row, and the compiled kernels that run many.

``run_design`` is the event loop of one design: at every fixed step a hooked design steps its swing
(:mod:`.hooked_phase`), a flying one its flight (:mod:`.flight`, which catches), until the runner's
rules end the run or ``sim.t_max`` does. ``run_batch`` runs a table of designs, spread over the
cores with ``prange``; each design's result depends on its own row only, so a design gives the same
bits alone or in any batch, on any number of threads. ``trace_first_swing`` samples a first swing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ... import units
from .flight import flight_stage
from .hooked_dynamics import hooked_energy, theta2
from .hooked_phase import hooked_step
from .jit import allocating
from .layout import DONE, FLIGHT, HOOKED, N_OUT, N_STATE, N_SWING, R_T_MAX, O, P, W, X
from .transitions import finish, set_face, start_swing

G = units.GRAVITY


@allocating
def parked_sums(p, frames):
    """The potential energy of each frame parked at its stop (row 0) and at rest (row 1), summed up to each frame."""
    sums = np.zeros((2, frames + 1))
    for row, th in enumerate((p[P.stop], p[P.rest])):
        for j in range(frames):
            e = p[P.frame_m] * G * j * p[P.rise] - p[P.cfr] * math.sin(th) + p[P.m3gh] * math.cos(th)
            sums[row, j + 1] = sums[row, j] + e
    return sums


@allocating
def start_state(p, x, out, sw):
    """Frame 0 at rest on its stop, the robot hanging from its seat at theta2_start, arm fully bent, at rest."""
    x[:] = 0.0
    out[:] = math.nan
    sw[:, :] = math.nan
    out[O.reason], out[O.traversals], out[O.last_frame] = -1.0, 0.0, 0.0
    out[O.v3] = math.nan
    out[O.e_min], out[O.e_gain], out[O.e_rise] = math.inf, 0.0, 0.0
    x[X.phase] = HOOKED
    x[X.carried] = 1.0  # the start is no catch: the transfer it begins is to frame 1
    x[X.th1] = p[P.rest]
    # the robot hanging fully bent (alpha_max) with the line from its centre of mass to the hook at theta2_start
    # (the runner's place_hanging)
    rot = p[P.theta2_start] - p[P.line_amax]
    x[X.pa], x[X.pt] = rot + p[P.amax] + 0.5 * math.pi, rot - 0.5 * math.pi
    set_face(p, x, 0.0)
    x[X.sig] = 1.0
    x[X.lockA], x[X.lockAk] = 1.0, 2.0  # against the alpha_max stop
    x[X.lock1], x[X.lock1k] = 1.0, 1.0  # on its rest stop (the first step lifts it if it can)
    x[X.t_stop], x[X.t_snap], x[X.t_cross] = math.nan, math.nan, math.nan
    x[X.closest], x[X.graze] = math.inf, math.inf
    sw[W.t_catch, 0] = 0.0
    sw[W.theta1_catch, 0] = math.degrees(p[P.rest])
    sw[W.theta2_catch, 0] = math.degrees(p[P.theta2_start])
    sw[W.catch_seat, 0] = 0.0  # the start sets the hook on the seat
    x[X.rec] = 1.0
    start_swing(p, x, 0.0)


@allocating
def run_design(p, frames, dt, detail, x, out, sw):
    """Run one design (``p`` its row of constants) to its end; ``out`` and ``sw`` receive its results, ``x`` is
    its working state. ``detail``: also the energy and theta2's range (a single run's SimResult)."""
    start_state(p, x, out, sw)
    parked = parked_sums(p, frames) if detail else np.zeros((2, 1))
    n_max = int(math.ceil(p[P.t_max] / dt))
    for k in range(n_max):
        t = k * dt
        if x[X.phase] == HOOKED:
            hooked_step(p, x, out, sw, t, dt, False, detail, parked)
        if x[X.phase] == FLIGHT:
            flight_stage(p, x, out, sw, t, dt, detail, parked)
        if x[X.phase] == DONE:
            return
        if (k + 1) * dt >= p[P.t_max]:
            finish(x, out, R_T_MAX, (k + 1) * dt, math.nan, math.nan)
            return
    finish(x, out, R_T_MAX, n_max * dt, math.nan, math.nan)


@njit(cache=True, parallel=True, error_model="numpy")
def run_batch(table, frames, dt, detail, out, sw):
    """Run every design of ``table`` (n, len(P)): ``out`` (n, len(O)) and ``sw`` (n, len(W), frames) receive them."""
    for i in prange(table.shape[0]):
        x = np.empty(N_STATE)
        run_design(table[i], frames, dt, detail, x, out[i], sw[i])


@allocating
def run_one(table, frames, dt, detail, out, sw):
    """``run_batch`` on one thread (a single design: no thread pool to wake)."""
    for i in range(table.shape[0]):
        x = np.empty(N_STATE)
        run_design(table[i], frames, dt, detail, x, out[i], sw[i])


@allocating
def trace_first_swing(p, frames, dt, hold, n_steps, samples):
    """Sample the first swing every step into ``samples`` (n_steps + 1, 6): t, theta1, theta2, alpha, omega1,
    energy. With ``hold`` the hook never slips or lets go. Returns how many rows were filled."""
    x = np.empty(N_STATE)
    out = np.empty(N_OUT)
    sw = np.empty((N_SWING, frames))
    start_state(p, x, out, sw)
    parked = np.zeros((2, 1))
    filled = 0
    for k in range(n_steps + 1):
        if k > 0:
            if x[X.phase] != HOOKED:
                break
            hooked_step(p, x, out, sw, (k - 1) * dt, dt, hold, False, parked)
            if x[X.phase] != HOOKED:
                break
        row = samples[filled]
        row[0] = k * dt
        row[1] = x[X.th1]
        row[2] = theta2(p, x[X.pa], x[X.pt])
        row[3] = x[X.pa] - x[X.pt] - math.pi
        row[4] = x[X.w1]
        row[5] = hooked_energy(p, x, 0.0)
        filled += 1
    return filled
