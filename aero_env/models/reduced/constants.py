"""The reduced model's numerical choices: its step, its thresholds, and why each has its value."""

STEP = 4e-3  # s: RK4 step. From 0.5 to 4 ms the prototype's first detach stays within 0.7 ms / 0.25 deg and the
# low-friction one (mu_s 0.1) within 0.1 deg; at 6 ms the latter drifts 1.7 deg (the ~60 ms slide gets too few steps).
S_CORNER = 1e-9  # m: a hook closer than this to the notch corner (along its face) sits in the corner
NOTCH_EXIT_MARGIN = 0.01  # m: a hook this far below the lowest point of the next notch's mouth, falling,
# can no longer be caught: the transfer's outcome is decided (its time is the runner's: floor or timeout)
STALL_WINDOW = 0.6  # s: a swing whose frame cannot climb TURN_BACK_DEG above rest with its energy (or lies on its
# rest stop having never climbed that far) after this long only ends by the runner's timeouts: stalled. About one
# period of the robot hanging from a still frame (0.6 s for the prototype): a hook that pops out does so earlier.
PIVOT_SLIP_RATE = 0.05  # rad/s: the hook tip's friction torque grows linearly up to this rate of the arm relative
# to the frame, then stays at mu·r·N (a smooth Coulomb law: near-stiction, and stiff enough only to need rate·dt < 1)
DRY_FRICTION_RATE = 0.05  # rad/s: the skewer's (pivot_friction) and the axle's (axle_friction) Coulomb torques are
# regularised: -T·clip(w / rate, -1, 1), linear below this relative rate, T above it. A sign(w) in fixed-step RK4
# chatters about w = 0 (each stage flips the torque); a stick/slip switch would be one more constraint in every
# phase (the frame's and the arm's stops already are) for a speed the swing crosses in one or two steps.
# 0.05 rad/s is ~1% of the swing's rates (3 rad/s frame, tens of rad/s arm snap), so the torque is the full Coulomb
# torque wherever it matters; a frame whose other torques stay below T creeps at rate·(torque / T) <= 0.05 rad/s
# instead of standing still (pymunk's capped motor holds it to the solver's slop). On a stop the hold is exact: a
# stop lets its joint go only once the pull on it exceeds the friction (hooked_dynamics.stop_lets_go).
DRY_FRICTION_STEP = 1.0  # the regularised torque's stiffness times the step, T·dt/(I·rate), is kept at most this
# (RK4 is stable to 2.8): a design whose T·dt/(I·DRY_FRICTION_RATE) exceeds it gets a larger rate (I: the smallest
# inertia the coordinate can have, the frame alone for the skewer, the free robot's alpha for the axle)
MOUTH_END_REACH = 1.0  # the catch window reaches this many hook/card clearances past each face's end
ENERGY_BARRIER_MARGIN = 0.02  # of the swing's energy scale: the barrier test's safety margin (grid minima)
BARRIER_GRID = 9  # points on the frame's first TURN_BACK_DEG above rest where the barrier test looks
CAP_STEP = 5e-4  # s: a slide within reach of its face's end or of the corner is stepped at this (the pymunk world's
# default step) for the rest of the step, and split where it meets them: the roll over the card's rounded end and
# the release take 2-5 ms, and the corner stops a slide in an impact a 4 ms step would overshoot
