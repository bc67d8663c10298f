"""Names for the compiled kernel's arrays: one row of numbers per design, a name for every column.

numba compiles scalar code over float arrays; these IntEnums give each column a name the physics reads
by (``p[P.If]``, ``x[X.th1]``) and are constants to the compiler. ``P``: a design's constants
(:mod:`.params` fills them, SI). ``X``: its run's state, which the phases change. ``O``: what the run
returns. ``W``: the per-frame swing records.
"""

from __future__ import annotations

from enum import IntEnum

P = IntEnum("P", [
    # the frame: inertia about its axis, its weight's moments, mass
    "If", "m3gh", "cfr", "frame_m",
    # the robot from its parts: mass, arm and torso geometry, first and second moments about hook and axle
    "m", "mg", "Pa", "Pt", "Pag", "Ptg", "Ja", "Jt", "Pat", "Ka", "Kt", "Kat",
    # the leaf spring and the arm's stops
    "k", "stiff", "spring_c", "amin", "amax", "alim", "snap", "line_amax",
    # the hook in the notch: friction, tip radius, the faces (directions u, inward normals n), their ends
    "mu_s", "mu_k", "phi_s", "phi_k", "r_hook", "clear", "p0x", "p0y",
    "ubx", "uby", "nbx", "nby", "ufx", "ufy", "nfx", "nfy", "s_end_b", "s_end_f",
    "beta", "face_off",
    # the frame's stops and the runner's turn-back angle
    "rest", "stop", "held_past", "Lb",
    # the next notch at rest, from its frame's axis: the mouth's ends, the seat, the bisector
    "mbx", "mby", "mfx", "mfy", "seatx", "seaty", "bisx", "bisy",
    # ... and its faces there (world): the hook centre's lines from the seat, directions and inward normals
    "rbux", "rbuy", "rbnx", "rbny", "rfux", "rfuy", "rfnx", "rfny",
    # whether a hook hooked on a frame can come near the next frame's cards at all (next_card: 1 on a steep row)
    "next_card",
    # the scene
    "pitch", "rise", "floor_drop", "theta2_start",
    # the runner's limits (sim.*)
    "contact_hold", "flight_timeout", "swing_timeout", "rest_timeout", "stop_hold", "t_max",
    "min_release_height", "slip_speed", "catch_seat",
    # the stall test's energy floor and scale
    "W_min", "e_scale",
    # dry friction at the skewer (pf) and the axle (af), regularised: torque -clip(c·w, -T, T)
    "pf", "pf_c", "af", "af_c",
], start=0)

X = IntEnum("X", [
    # hooked coordinates and rates: frame angle, slide along a face, arm and torso directions
    "th1", "s", "pa", "pt", "w1", "ws", "wa", "wt",
    # the face the hook is on (0 back, 1 front), its direction and inward normal, the slide
    "face", "ux", "uy", "nx", "ny", "slide", "sig", "mu_sig",
    # the hook on the card's rounded end past its face (1), or on the face's line (0): set per slide step
    "cap",
    # stops: held (1) or free (0); which one (1 the lower: rest / alpha_min, 2 the upper: stop / alpha_max)
    "lock1", "lock1k", "lockA", "lockAk",
    # the tip's turning friction (its magnitude, and the sliding friction's moment)
    "piv", "tq0",
    # where the run is: phase, the frame the robot is on, whether that frame has carried the robot through its
    # lowest point (swing_rules.CARRIED_THETA1_DEG: its catch is a traversal; 1 from the start on frame 0, no catch)
    "phase", "fi", "carried",
    # the swing's bookkeeping
    "t_catch", "peak", "t_stop", "closest", "barrier", "rec",
    # flight: the centre of mass' start and velocity, release time and state, the hook's place
    "t0f", "t_rel", "cx0", "cy0", "vx0", "vy0", "a_rel", "h_rel", "hx", "hy",
    # the runner's watch over a flight: the arm's snap, the hook crossing the seat's height, the mouth
    "t_snap", "t_cross", "dx_cross", "a_cross", "in_notch", "t_mouth", "graze",
    # a touch of the next frame not yet a catch (the hook landed on a face): since when, its closest to the seat
    "touch", "t_touch", "touch_gap",
    # the next frame, kicked by a touch that grazed: moving (1) or at rest (0), its angle and rate
    "nmov", "nth", "nw",
    # the hook, hooked, inside the clearance of the next frame's card at the last step's end (next_card): 1, else 0
    "card",
], start=0)

O = IntEnum("O", [  # noqa: E741 (the run's Outputs)
    "reason", "v1", "v2", "v3", "traversals", "end_time", "last_frame", "miss",
    "e_first", "e_last", "e_min", "e_gain", "e_rise",
], start=0)

W = IntEnum("W", [
    "t_catch", "theta1_catch", "theta2_catch", "t_detach", "theta1_detach", "alpha_detach",
    "theta2_min", "theta2_max", "catch_seat", "t_carried",
], start=0)

# phases
HOOKED, FLIGHT, DONE = 0.0, 1.0, 2.0

OUTCOMES = ("completed", "no_detach", "stalled", "fell_short", "missed_catch")
_C, _ND, _ST, _FS, _MC = range(5)
# reasons: how the outcome's sentence is written (outputs.reason_text)
(R_COMPLETED, R_STOP_HOLD, R_TURN_NEAR_STOP, R_TURN_BACK, R_TIMEOUT, R_BARRIER, R_STIFF, R_LOW,
 R_NEVER_DOWN, R_WEAK, R_BEHIND, R_AHEAD, R_AT_REST, R_BARRIER_REST, R_T_MAX, R_GRAZE, R_HELD_LONG,
 R_LET_GO) = range(18)
REASON_OUTCOME = {R_COMPLETED: _C, R_STOP_HOLD: _ND, R_TURN_NEAR_STOP: _ND, R_TURN_BACK: _ST, R_TIMEOUT: _ST,
                  R_BARRIER: _ST, R_STIFF: _MC, R_LOW: _FS, R_NEVER_DOWN: _MC, R_WEAK: _MC, R_BEHIND: _FS,
                  R_AHEAD: _MC, R_AT_REST: _ST, R_BARRIER_REST: _ST,
                  R_T_MAX: _ST,  # the runner's "timeout" (sim.t_max: no phase outlasts its own limit) reads stalled
                  R_GRAZE: _MC, R_HELD_LONG: _ND,
                  R_LET_GO: _MC}  # caught, let go before the frame carried the robot: a catch that did not hold

# the arrays' widths, as constants the compiled code can read
N_PARAMS, N_STATE, N_OUT, N_SWING = len(P), len(X), len(O), len(W)
