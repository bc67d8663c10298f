"""What changes a design's phase: the end of its run, the hook letting go, a slide starting, a swing starting.

Scalar code for one design (``p`` its constants, ``x`` its state, ``out`` its results, ``sw`` its
per-frame swing records), compiled by numba.
"""

from __future__ import annotations

import math

from .jit import kernel

from ... import units
from ...physics.swing_rules import CARRIED_THETA1_DEG, TURN_BACK_DEG
from .constants import BARRIER_GRID, ENERGY_BARRIER_MARGIN
from .hooked_dynamics import com_velocity_from_hook, face_end, hook_from_com, hook_motion, hooked_energy
from .layout import DONE, FLIGHT, R_COMPLETED, R_LET_GO, O, P, W, X

G = units.GRAVITY
CARRIED = math.radians(CARRIED_THETA1_DEG)  # a caught frame at this angle, hook on, has carried the robot


@kernel
def finish(x, out, reason, t_end, v1, v2, v3=math.nan):
    """End the run with ``reason`` at t_end (v1, v2, v3: the numbers its sentence quotes; NaN where it quotes none)."""
    out[O.reason] = reason
    out[O.end_time] = t_end
    out[O.last_frame] = x[X.fi]
    out[O.v1], out[O.v2], out[O.v3] = v1, v2, v3
    out[O.miss] = x[X.closest]
    x[X.phase] = DONE


@kernel
def carried(x, out, sw, t):
    """The frame the robot is on has carried it through its lowest point at t: its catch is a traversal (the start's
    frame 0 counts nothing), and the next transfer's miss distance starts. Returns True if that completed the row."""
    fi = int(x[X.fi])
    sw[W.t_carried, fi] = t
    if fi > 0:
        out[O.traversals] = fi
        x[X.carried] = 1.0
        x[X.closest] = math.inf
        if fi == sw.shape[1] - 1:
            finish(x, out, R_COMPLETED, t, math.nan, math.nan)
            return True
    return False


@kernel
def track_energy(out, e):
    if math.isnan(out[O.e_first]):
        out[O.e_first] = e
    out[O.e_last] = e
    out[O.e_gain] = max(out[O.e_gain], e - out[O.e_first])
    out[O.e_min] = min(out[O.e_min], e)
    out[O.e_rise] = max(out[O.e_rise], e - out[O.e_min])


@kernel
def parked_energy(parked, fi, left_at_stop):
    """Potential energy of the frames the robot is not on (ahead: at rest; behind: at their stop), from the
    per-frame cumulative sums ``parked`` (row 0 at the stop, row 1 at rest) made at the start."""
    upto = fi + 1 if left_at_stop else fi
    return parked[0, upto] + parked[1, parked.shape[1] - 1] - parked[1, fi + 1]


@kernel
def set_face(p, x, face):
    """The hook on a face (0 back, 1 front), on its flat side: its direction and inward normal (frame-local)."""
    x[X.face], x[X.cap] = face, 0.0
    if face > 0.5:
        x[X.ux], x[X.uy], x[X.nx], x[X.ny] = p[P.ufx], p[P.ufy], p[P.nfx], p[P.nfy]
    else:
        x[X.ux], x[X.uy], x[X.nx], x[X.ny] = p[P.ubx], p[P.uby], p[P.nbx], p[P.nby]


@kernel
def start_slide(p, x, face, sig):
    """The hook starts sliding along a face (0 back, 1 front) in the sense sig (+1 outward)."""
    set_face(p, x, face)
    x[X.sig], x[X.slide] = sig, 1.0
    x[X.mu_sig] = p[P.mu_k] * sig


@kernel
def end_slide(x):
    """The hook stops sliding along its face and sticks: no slide, no kinetic friction or its moment, no rate along
    the face."""
    x[X.slide], x[X.mu_sig], x[X.ws], x[X.tq0] = 0.0, 0.0, 0.0, 0.0


@kernel
def hook_flight_start(p, x, t_state):
    """The flight's start from the hooked state at t_state: the centre of mass' place and velocity, the hook's
    place (world)."""
    fi = int(x[X.fi])
    pa, pt = x[X.pa], x[X.pt]
    Hx, Hy, vHx, vHy = hook_motion(p, x)
    hx, hy = hook_from_com(p, pa, pt)
    dvx, dvy = com_velocity_from_hook(p, pa, pt, x[X.wa], x[X.wt])
    ox, oy = fi * p[P.pitch] + Hx, fi * p[P.rise] + Hy  # the hook, world
    x[X.cx0], x[X.cy0] = ox - hx, oy - hy
    x[X.vx0], x[X.vy0] = vHx + dvx, vHy + dvy
    x[X.t0f] = t_state
    x[X.hx], x[X.hy] = ox, oy
    x[X.slide], x[X.mu_sig], x[X.ws], x[X.lock1], x[X.lock1k] = 0.0, 0.0, 0.0, 0.0, 0.0
    x[X.phase] = FLIGHT
    return oy


@kernel
def graze_off(p, x, sw, t_state):
    """A touch that never became a catch ends (the hook left the face it landed on): the runner's graze. The
    flight towards that frame goes on from the current state; the transfer's own records (its detach, the watch
    over its flight) stay, and the frame's records of the touch are wiped."""
    j = int(x[X.fi])
    s_end = face_end(p, x)
    x[X.graze] = min(x[X.graze], x[X.touch_gap])
    x[X.nmov], x[X.nth], x[X.nw] = 1.0, x[X.th1], x[X.w1]  # the frame keeps the motion the touch gave it
    x[X.in_notch] = 1.0 if x[X.s] < s_end else 0.0  # lifted off inside the notch, or slid off the card's end
    hook_flight_start(p, x, t_state)
    x[X.touch] = 0.0
    x[X.fi], x[X.carried] = j - 1, 1.0
    for k in range(sw.shape[0]):
        sw[k, j] = math.nan


@kernel
def release_hook(p, x, out, sw, t_state, t_det):
    """The hook lets go of frame fi: flight from the current state (at time t_state); detach time t_det. A touch
    that was not yet a catch lets go as a graze (:func:`graze_off`)."""
    if x[X.touch] > 0.0:
        graze_off(p, x, sw, t_state)
        return
    fi = int(x[X.fi])
    th1 = x[X.th1]
    oy = hook_flight_start(p, x, t_state)
    x[X.t_rel] = t_det
    alpha = x[X.pa] - x[X.pt] - math.pi
    x[X.a_rel] = alpha
    x[X.h_rel] = oy - ((fi + 1) * p[P.rise] + p[P.seaty])
    x[X.t_snap], x[X.t_cross] = math.nan, math.nan
    x[X.in_notch] = 0.0
    x[X.graze] = math.inf
    x[X.nmov] = 0.0  # the next frame is at rest
    sw[W.t_detach, fi] = t_det
    sw[W.theta1_detach, fi] = math.degrees(th1)
    sw[W.alpha_detach, fi] = math.degrees(alpha)
    if x[X.carried] == 0.0:  # caught, and not yet carried
        if th1 >= CARRIED:  # carried since the last step's check
            carried(x, out, sw, t_det)
        else:  # a catch that did not hold: the run ends when the runner commits the detach
            finish(x, out, R_LET_GO, t_det + p[P.contact_hold], sw[W.catch_seat, fi], t_det - sw[W.t_catch, fi],
                   math.degrees(th1))


@kernel
def start_swing(p, x, t):
    """Bookkeeping at a catch (or the start): the peak, and whether the frame can climb TURN_BACK_DEG above its
    rest at all with the energy it has, the robot hanging at its lowest (the stall test, STALL_WINDOW)."""
    x[X.t_catch] = t
    x[X.peak] = x[X.th1]
    x[X.t_stop] = math.nan
    e = hooked_energy(p, x, 0.0)
    top = -math.inf
    for i in range(BARRIER_GRID):
        th = max(p[P.rest] + math.radians(TURN_BACK_DEG) * i / (BARRIER_GRID - 1), x[X.th1])
        v_floor = (-p[P.cfr] * math.sin(th) + p[P.m3gh] * math.cos(th) - p[P.m] * G * p[P.Lb] * math.sin(th)
                   + p[P.W_min])
        top = max(top, v_floor)
    x[X.barrier] = 1.0 if top - e > ENERGY_BARRIER_MARGIN * p[P.e_scale] else 0.0
