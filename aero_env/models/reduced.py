"""The ``reduced`` fidelity: a whole run along the row without pymunk, many designs at once.

The cheapest rung of the fidelity ladder. Every design of a batch is a row of numpy arrays and one
fixed-step integrator advances them all together; events (slip, release, catch, stops) are
per-design masks. ``simulate_batch`` / ``simulate_values`` run a batch (``BatchResult``),
``simulate_reduced`` one config as the pymunk runner's ``SimResult``, ``swing_trace`` samples a
first swing. In a batch of 10,000 random designs a design costs ~0.75 ms of one core
(``benchmarks/reduced_speed.py``: ~1,300 designs/s; the pymunk world: ~30 ms for a random design,
~80 ms for the prototype's row). Alone, a design costs more than in pymunk: each step is some
hundreds of numpy calls of ~1 µs whatever the batch size, which also sets the floor of a batch's
time (its slowest designs run ~2,800 steps).

**The swing (hooked).** Coordinates: the frame angle theta1, the arm's direction phi_a (hook ->
axle) and the torso's phi_t (axle -> torso centre), the hook in the handrail's notch. This is the
paper's two-link model (frame + robot jointed at the handrail, A25/A30) with the robot link taken
*from its parts*, as the pymunk robot is built (``arm_length``, ``arm_mass`` a uniform rod,
``torso_com``, and the torso inertia :mod:`aero_env.physics.engine_params` derives so the robot,
fully bent, has the paper's I2 about its centre). While the arm sits on its stop (alpha_max: the
robot's weight holds the leaf spring there on a working design, the prototype all swing long) the
chain *is* the two-link model with Lc = the hook-to-centre distance of the parts at alpha_max
(44.4 mm for the prototype, not the design's 30 mm) and I2 = m2/3·(Ld²+Ld·Lc+Lc²) (the design's
Lc, Ld): the stop is a constraint (the 2x2 two-link system is what is solved), and
``swing_trace`` reproduces ``two_link.simulate`` with that Lc to 0.01 deg. When the spring lifts
the arm off its stop, alpha (interior angle at the axle; spring torque k·(alpha - alpha_min), or
k/2·da² for ``spring_law: stiffening``) is a third coordinate; the arm's stops are inelastic.

Why the parts and not the design's Lc: the pymunk robot is the parts (its centre is 44 mm from
the hook hanging fully bent; Lc and Ld only set I2 there), only the parts give the arm its own
motion, and that motion is a failure a quarter of random designs meet: a stiff spring snaps the
arm off its stop at the catch and the hook pops out (pymunk: 58-72 deg within 90 ms, "spring too
stiff"; this model: the same times, to a few ms). Either rigid link alone misses the prototype's
first swing by the same 2.2 deg RMS (theta1 at 0.1..0.5 s; Lc = 30 mm is 0.8 deg closer in
theta2): what both lack is the friction of the hook's round tip (``hook_radius``) turning in the
notch, mu_s·r·(sum of the faces' normal forces), which slows pymunk's swing by ~2 deg at 0.3 s
(pymunk with a 0.1 mm tip swings as the frictionless chain does). With that torque this model
tracks pymunk's theta1 to 0.05 deg RMS over the prototype's first 0.5 s, and at mu_s 0.2 / 0.54 /
1.5 / 4 to 0.0 / 0.05 / 0.4 / 0.4 deg at 0.3 s (the torque saturates at high friction because
the wedge then carries the load by friction: the normal forces come from
F = sum_i N_i·(n_i + mu·sig·perp(n_i))).

**Slip and detach.** The joint force F (handrail on robot) follows from the accelerations every
step. The notch is two card faces (``design.notch_*``, as :mod:`aero_env.physics.swing_frame`
builds them, turning with the frame); with the hook in the corner it holds while F lies in the
union of the faces' static friction cones (atan(mu_s) about each inward normal). F leaving it
on one face's side, pressing on that face, starts a slide along the face with kinetic friction
(a fourth coordinate s; -mu_k·N·sign(s') with N solved together with the accelerations); the
hook lets go when its centre passes the face's end (length minus the hook/card clearance) or
when N turns tensile; a slide that stops sticks again. F pulling on both faces lets go at once.
pymunk shows this slide: the prototype's hook starts at ~147 deg and leaves ~60 ms later at 162
deg, the frame speeding up as it is relieved (here: 147 deg, 161.7 deg at 0.635 s; pymunk 0.639
s). Impacts are inelastic: at the end stop the robot flies off when the impulse that would stop
it with the frame pulls on the notch (the jolt release pymunk shows at 180 deg), else it holds
(sliding if the impulse leaves the static cone); at the arm's stops a pulling impulse is a
detach only if the hook, free, stays off the handrail for ``sim.contact_hold`` against gravity
and the handrail's motion (shorter lifts are bounces for the runner too); the rest stop always
holds. A hook within one hook/card clearance of the corner meets an impulse with both faces.

**Flight.** The centre of mass is ballistic (closed form); arm and torso turn about it with the
robot's angular momentum conserved and the leaf spring snapping the arm toward alpha_min (a
two-body system in centre-of-mass coordinates, the parts' inertias, inelastic arm stops). The
hook's place is the parts' geometry (``engine_params.robot_mass_layout``), rotated.

**Catch.** Geometric: the hook's centre crosses the mouth of the next notch downward (the segment
between the faces' outer ends, reaching one hook/card clearance past each end: pymunk's catch is
any 10 ms touch, a face's tip included; the frame at its rest angle) with the arm snapped forward
(alpha below mid-range, as the runner reads a snap), then reaches the seat's depth. The robot is
set on the seat and the catch is an inelastic impulse at the hook: the hooked coordinates'
generalised momenta are conserved (the whole system's angular momentum about the new frame's
axis, the robot's about the hook, the torso's about the axle; the frame starts at rest and stays
on its rest stop if pushed into it). Setting the hook on the seat never adds energy (a lift is
taken out of the motion). Misses are named as the runner's ``_classify_miss`` names them.

**Outcomes and times** follow :mod:`aero_env.physics.run` (its thresholds are restated below):
``t_detach`` is when the hook leaves the handrail, ``t_catch`` when it enters the next mouth,
``sim_time`` when the runner would stop (a decided miss: the centre of mass reaching the floor,
in closed form, or the flight timeout; the last catch + ``contact_hold``). Stalls the runner only
ends by its timeouts are ended early (``STALL_WINDOW``: the frame cannot climb ``TURN_BACK_DEG``
with its energy, or lies on its rest stop) and reported at the runner's time.

**Numerics.** RK4 with a fixed step (``STEP``; ``sim.dt`` when the config's ``sim.model`` is
``reduced``), events at step ends, release and catch times interpolated. sin/cos in float32
(``TRIG_DTYPE``). Deterministic, and elementwise: a design gives bit-identical results alone or
in any batch.

**Agreement with pymunk** (``benchmarks/reduced_agreement.py``, uniformly random designs,
configs/paper.yaml). 1,000 held-out designs (seed 2): same traversal count 0.79, same outcome
0.86, Spearman of traversals 0.65, median |error| of the first detach 3 ms and 0.38 deg; the 16%
of designs this model gives at least one traversal hold 25 of the 29 that complete the row in
pymunk (it completes 45, 14 of them pymunk's). The 200 designs used while building it (seed
20240611): 0.825, 0.84, 0.77, 3 ms, 0.36 deg. The main confusions: fell_short vs missed_catch at
the same frame (how far the hook misses hangs on details of the slide and the snap), and
transfers won or lost by a few mm at the mouth, which then shift the traversal count.

Not modelled: air drag (<0.1% in the paper and in the pymunk world), contact bounces and the hook
riding a face's outside, the hook rolling in the corner, the ``hook: pin`` scene (that is
``aero_env.models.two_link``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from .. import results as say
from .. import units
from ..config import Config, ConfigError, real_field
from ..inertia import RobotParts
from ..results import REST_MOVE, STOP_TOLERANCE, TURN_BACK_DEG, SimResult, Swing, held_past_angle

# ---- numerical choices ----
STEP = 4e-3  # s: RK4 step. From 0.5 to 4 ms the prototype's first detach stays within 0.7 ms / 0.25 deg and the
# low-friction one (mu_s 0.1) within 0.1 deg; at 6 ms the latter drifts 1.7 deg (the ~60 ms slide gets too few steps).
TRIG_DTYPE = np.float32  # sin/cos of the angles: numpy's float32 loops are ~16x faster than float64 here; the
# error (~1e-7) is far below the model's own
COMPACT_BELOW = 0.6  # drop finished designs from the working arrays when fewer than this fraction are live
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
# chatters about w = 0 (each stage flips the torque); a stick/slip switch would be one more per-design constraint
# row in every phase (the frame's and the arm's stops already are) for a speed the swing crosses in one or two steps.
# 0.05 rad/s is ~1% of the swing's rates (3 rad/s frame, tens of rad/s arm snap), so the torque is the full Coulomb
# torque wherever it matters; a frame whose other torques stay below T creeps at rate·(torque / T) <= 0.05 rad/s
# instead of standing still (pymunk's capped motor holds it to the solver's slop).
DRY_FRICTION_STEP = 1.0  # the regularised torque's stiffness times the step, T·dt/(I·rate), is kept at most this
# (RK4 is stable to 2.8): a design whose T·dt/(I·DRY_FRICTION_RATE) exceeds it gets a larger rate (I: the smallest
# inertia the coordinate can have, the frame alone for the skewer, the free robot's alpha for the axle)
MOUTH_END_REACH = 1.0  # the catch window reaches this many hook/card clearances past each face's end
ENERGY_BARRIER_MARGIN = 0.02  # of the swing's energy scale: the barrier test's safety margin (grid minima)

OUTCOMES = ("completed", "no_detach", "stalled", "fell_short", "missed_catch")
_C, _ND, _ST, _FS, _MC = range(5)
# phases
_HOOKED, _FLIGHT, _DONE = 0, 1, 2
# reasons (how the outcome's sentence is written)
(_R_COMPLETED, _R_STOP_HOLD, _R_TURN_NEAR_STOP, _R_TURN_BACK, _R_TIMEOUT, _R_BARRIER, _R_STIFF, _R_LOW,
 _R_NEVER_DOWN, _R_WEAK, _R_BEHIND, _R_AHEAD, _R_AT_REST, _R_BARRIER_REST, _R_T_MAX, _R_GRAZE) = range(16)
_REASON_OUTCOME = {_R_COMPLETED: _C, _R_STOP_HOLD: _ND, _R_TURN_NEAR_STOP: _ND, _R_TURN_BACK: _ST, _R_TIMEOUT: _ST,
                   _R_BARRIER: _ST, _R_STIFF: _MC, _R_LOW: _FS, _R_NEVER_DOWN: _MC, _R_WEAK: _MC, _R_BEHIND: _FS,
                   _R_AHEAD: _MC, _R_AT_REST: _ST, _R_BARRIER_REST: _ST,
                   _R_T_MAX: _ST, _R_GRAZE: _MC}  # the runner's "timeout" (sim.t_max: no phase outlasts its own limit) reads stalled


# ============================================================================ parameters

# The config fields the model reads, by dotted key (everything else is ignored).
_DESIGN_KEYS = ("La", "Lb", "Lc", "Ld", "h", "m1", "m2", "m3", "dT", "spring_k", "mu_s", "mu_k", "arm_length",
                "arm_mass", "torso_length", "coin_mass", "coin_radius", "coin_offset", "handrail_mass",
                "pivot_friction", "axle_friction", "alpha_min_deg", "alpha_max_deg", "rest_angle_deg", "stop_angle_deg",
                "notch_angle_deg", "notch_opening_deg", "notch_back_face", "notch_front_face",
                "handrail_thickness", "hook_radius")
_SCENE_KEYS = ("pitch", "rise", "theta2_start_deg", "floor_drop")
_SIM_KEYS = ("contact_hold", "flight_timeout", "swing_timeout", "rest_timeout", "stop_hold", "t_max",
             "min_release_height", "slip_speed", "catch_seat")


class _DesignArrays:
    """The ``design.*`` arrays of a raw batch as attributes, for :class:`aero_env.inertia.RobotParts`."""

    def __init__(self, raw):
        for k, v in raw.items():
            if k.startswith("design."):
                setattr(self, k[7:], v)


class _Arrays:
    """A bag of equal-length 1-D arrays (one row per design) that can be subset or compacted together."""

    def names(self):
        return [k for k, v in vars(self).items() if isinstance(v, np.ndarray)]

    def take(self, idx, names=None) -> "_Arrays":
        out = _Arrays()
        for k in names or self.names():
            setattr(out, k, getattr(self, k)[idx])
        return out

    def compact(self, keep) -> None:
        for k in self.names():
            setattr(self, k, getattr(self, k)[keep])


class _Lazy:
    """The rows ``idx`` of an _Arrays, gathered on first use of each field (event code reads few of many)."""

    def __init__(self, src, idx):
        self.__dict__["_src"], self.__dict__["_idx"] = src, idx

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        v = getattr(self._src, name)[self._idx]
        self.__dict__[name] = v
        return v

    def take(self, idx):
        return _Lazy(self._src, self._idx[idx])


def _raw_from_configs(cfgs: Sequence[Config]) -> dict:
    raw = {}
    for k in _DESIGN_KEYS:
        raw["design." + k] = np.array([getattr(c.design, k) for c in cfgs], dtype=float)
    for k in _SCENE_KEYS:
        raw["scene." + k] = np.array([getattr(c.scene, k) for c in cfgs], dtype=float)
    for k in _SIM_KEYS:
        raw["sim." + k] = np.array([getattr(c.sim, k) for c in cfgs], dtype=float)
    raw["spring_stiffening"] = np.array([c.scene.effects.spring_law == "stiffening" for c in cfgs], dtype=float)
    law = [c.scene.effects.friction for c in cfgs]
    raw["mu_hold"] = np.array([c.design.mu_k if f == "kinetic" else c.design.mu_s for c, f in zip(cfgs, law)])
    raw["mu_slide"] = np.array([c.design.mu_s if f == "static" else c.design.mu_k for c, f in zip(cfgs, law)])
    return raw


def _check_scene(cfgs: Sequence[Config]) -> int:
    if len(cfgs) == 0:
        raise ValueError("simulate_batch: no configs")
    frames = cfgs[0].scene.frames
    for i, c in enumerate(cfgs):
        if c.scene.frames != frames:
            raise ConfigError(f"simulate_batch: config {i} has scene.frames = {c.scene.frames}, config 0 has "
                              f"{frames}: one batch runs one row length")
        if c.scene.effects.hook != "contact":
            raise ConfigError(f"config {i}: scene.effects.hook = {c.scene.effects.hook!r}: the reduced model "
                              f"models the frictional hook only (the pinned hook is aero_env.models.two_link)")
    return frames


def _step_for(cfg: Config) -> float:
    """The integration step: the config's sim.dt when its sim.model names this model, else STEP."""
    return float(cfg.sim.dt) if getattr(cfg.sim, "model", None) == "reduced" else STEP


def _params(raw: Mapping[str, np.ndarray]) -> _Arrays:
    """Per-design constants of the model (SI), from the raw config fields."""
    P = _Arrays()
    d = lambda k: raw["design." + k]  # noqa: E731
    g = units.GRAVITY
    rad = np.radians
    La, Lb, h, m1, m2, m3 = d("La"), d("Lb"), d("h"), d("m1"), d("m2"), d("m3")
    dT = d("dT")
    mh = d("handrail_mass")
    # frame: own inertia (consistent I1), own centre of mass from dT (as engine_params), counterbalance point,
    # and the handrail's card, a point mass at the seat (-Lb, 0) (swing_frame.SwingFrame)
    x_f = -dT / (m1 * g)
    I1 = 2.0 * m1 / 3.0 * (La**2 + Lb**2 - La * Lb)
    P.If = I1 + m1 * x_f**2 + m3 * (La**2 + h**2) + mh * Lb**2
    P.m3gLa, P.m3gh, P.dT = m3 * g * La, m3 * g * h, dT
    # the frame's own, the counterbalance's and the handrail card's moment: cfr·cos(theta1) + m3gh·sin(theta1)
    P.cfr = dT - P.m3gLa + mh * g * Lb
    P.frame_m = m1 + m3 + mh
    # robot from its parts (aero_env.inertia.RobotParts, as the pymunk robot is built); the handrail is the frame's
    design = _DesignArrays(raw)
    parts = RobotParts(design)
    ma, mt, m2 = parts.m_arm, parts.m_torso, parts.mass
    L, dc = parts.arm_length, parts.torso_com
    amin, amax = rad(d("alpha_min_deg")), rad(d("alpha_max_deg"))
    Ia, It = parts.I_arm, parts.I_torso
    P.m, P.ma, P.mt, P.L, P.dc = m2, ma, mt, L, dc
    P.mg = m2 * g
    P.Pa = ma * L / 2.0 + mt * L  # first moments about the hook of the arm direction ...
    P.Pt = mt * dc  # ... and of the torso direction
    P.Ja = Ia + ma * L**2 / 4.0 + mt * L**2  # arm + torso mass about the hook (arm coordinate)
    P.Jt = It + mt * dc**2  # torso about the axle
    P.Pat = mt * L * dc
    # centre-of-mass (flight) coefficients: kinetic energy about the centre of mass
    P.Ka = P.Ja - P.Pa**2 / m2
    P.Kt = P.Jt - P.Pt**2 / m2
    P.Kat = P.Pat - P.Pa * P.Pt / m2
    P.Pag, P.Ptg = P.Pa * g, P.Pt * g
    P.k = d("spring_k")
    P.stiff = raw["spring_stiffening"]
    P.amin, P.amax = amin, amax
    P.alim = np.pi + amin  # the spring is straight at phi_a - phi_t = this
    P.snap = amin + 0.5 * (amax - amin)  # the runner's "snapped" arm angle (half its range)
    P.mu_s, P.mu_k = raw["mu_hold"], raw["mu_slide"]
    P.phi_s = np.arctan(P.mu_s)
    P.r_hook = d("hook_radius")
    # notch (frame-local, as swing_frame.SwingFrame builds it)
    rest, stop = rad(d("rest_angle_deg")), rad(d("stop_angle_deg"))
    P.rest, P.stop = rest, stop
    P.held_past = held_past_angle(design)  # the runner's turn-back rule, the same function
    P.Lb = Lb
    beta = rad(d("notch_angle_deg")) - rest  # bisector, local
    o = rad(d("notch_opening_deg"))
    nb_sf = (np.cos(beta - o / 2), np.sin(beta - o / 2))  # swing_frame's n_back (= the front face's direction)
    nf_sf = (np.cos(beta + o / 2), np.sin(beta + o / 2))  # swing_frame's n_front (= the back face's direction)
    cl = d("handrail_thickness") / 2.0 + d("hook_radius")
    P.clear = cl
    denom = 1.0 + nb_sf[0] * nf_sf[0] + nb_sf[1] * nf_sf[1]
    corner = (-Lb - (nb_sf[0] + nf_sf[0]) * cl / denom, -(nb_sf[1] + nf_sf[1]) * cl / denom)
    P.p0x, P.p0y = -Lb, np.zeros_like(Lb)
    # back face: direction nf_sf, inward normal = direction rotated by -90 deg; front face: nb_sf, +90 deg
    P.ubx, P.uby = nf_sf
    P.nbx, P.nby = nf_sf[1], -nf_sf[0]
    P.ufx, P.ufy = nb_sf
    P.nfx, P.nfy = -nb_sf[1], nb_sf[0]
    sc = (P.p0x - corner[0], P.p0y - corner[1])  # seat relative to the corner
    P.s_end_b = d("notch_back_face") - (sc[0] * P.ubx + sc[1] * P.uby)
    P.s_end_f = d("notch_front_face") - (sc[0] * P.ufx + sc[1] * P.ufy)
    P.beta = beta
    half = 0.5 * np.pi - o / 2  # each face's normal makes this angle with the bisector
    P.cone_half = half + P.phi_s  # the corner's union cone: |angle(F) - beta| <= this
    P.face_off = half  # the back face's normal is at beta - half, the front face's at beta + half
    # the mouth of a notch at rest (world offsets from its frame's axis), its seat, its bisector
    cr, sr = np.cos(rest), np.sin(rest)
    rot = lambda x, y: (cr * x - sr * y, sr * x + cr * y)  # noqa: E731
    ebx, eby = corner[0] + nf_sf[0] * d("notch_back_face"), corner[1] + nf_sf[1] * d("notch_back_face")
    efx, efy = corner[0] + nb_sf[0] * d("notch_front_face"), corner[1] + nb_sf[1] * d("notch_front_face")
    # the hook touches a face's end when its centre comes within the hook/card clearance of it: the window
    # runs that far past each end (pymunk's catch is any 10 ms touch, a face's tip included)
    mx, my = efx - ebx, efy - eby
    ml = np.hypot(mx, my)
    ext = MOUTH_END_REACH * cl / ml
    P.mbx, P.mby = rot(ebx - ext * mx, eby - ext * my)
    P.mfx, P.mfy = rot(efx + ext * mx, efy + ext * my)
    P.seatx, P.seaty = rot(-Lb, 0.0 * Lb)
    P.bisx, P.bisy = np.cos(beta + rest), np.sin(beta + rest)
    # scene
    P.pitch, P.rise, P.floor_drop = raw["scene.pitch"], raw["scene.rise"], raw["scene.floor_drop"]
    P.theta2_start = rad(raw["scene.theta2_start_deg"])
    for k in _SIM_KEYS:
        setattr(P, k, raw["sim." + k])
    # energy barrier (stall test): the robot hanging from a fixed hook, its lowest potential over alpha
    al = amin[None, :] + (amax - amin)[None, :] * np.linspace(0.0, 1.0, 33)[:, None]
    hk, _, _, cm = parts.layout(al)
    dist = np.hypot(hk[0] - cm[0], hk[1] - cm[1])
    P.W_min = np.min(_spring_energy(P.k, P.stiff, al - amin) - m2 * g * dist, axis=0)
    P.pf, P.af = d("pivot_friction"), d("axle_friction")
    # the smallest inertias of theta1 (the frame alone) and of alpha (the free robot, any arm angle): _Run sets the
    # regularisation's rates from them and the step (DRY_FRICTION_STEP)
    P.I_pf = P.If
    P.I_af = (P.Ka * P.Kt - P.Kat**2) / (P.Ka + P.Kt + 2.0 * np.abs(P.Kat))
    hk, _, _, cm = parts.layout(amax)
    P.line_amax = np.arctan2(hk[1] - cm[1], hk[0] - cm[0])  # the centre -> hook line in the torso's frame, bent
    P.e_scale = (m2 + m3) * g * (La + Lb) + _spring_energy(P.k, P.stiff, amax - amin)
    return P


def _spring_energy(k, stiff, da):
    return np.where(stiff > 0, k * np.abs(da) ** 3 / 6.0, 0.5 * k * da * da)


def _spring_torque(k, stiff, da):
    """k·da (linear), or k/2·da·|da| (stiffening): the torque that pushes alpha back toward alpha_min."""
    return k * da * (1.0 - stiff + stiff * 0.5 * np.abs(da))


def _cs(x):
    x32 = x.astype(TRIG_DTYPE)
    return np.cos(x32).astype(np.float64), np.sin(x32).astype(np.float64)


# ============================================================================ hooked dynamics
#
# Coordinates q = (theta1, s, phi_a, phi_t): the frame angle, the hook's distance along the face it slides on
# (0 at the seat; s is held by a constraint row while the hook sticks), the arm's direction hook -> axle and the
# torso's direction axle -> torso centre (world angles). The hook is at H = R(theta1)·(seat + s·u) from the axis;
# alpha = phi_a - phi_t - pi. Each body's position is a sum of fixed lengths times unit vectors, so the mass
# matrix has the double-pendulum form and the velocity terms come from the bodies' centripetal accelerations.


def _mass4(P, th1, s, pa, pt, ux, uy):
    """The hooked mass matrix over (theta1, s, phi_a, phi_t), the joint's place and the angles' cos/sin.

    Each body's centre is a sum of fixed lengths times unit vectors (the joint H = R(theta1)·(seat + s·u), the
    arm's and the torso's directions), so the kinetic energy has the double-pendulum form."""
    c1, s1 = _cs(th1)
    ca, sa = _cs(pa)
    ct, st = _cs(pt)
    m, Pa, Pt = P.m, P.Pa, P.Pt
    px, py = P.p0x + s * ux, P.p0y + s * uy
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    uwx, uwy = c1 * ux - s1 * uy, s1 * ux + c1 * uy
    M01 = m * (px * uy - py * ux)
    M02, M03 = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
    M12, M13 = Pa * (uwy * ca - uwx * sa), Pt * (uwy * ct - uwx * st)
    M23 = P.Pat * (ca * ct + sa * st)
    M = [[P.If + m * (px * px + py * py), M01, M02, M03],
         [M01, m + 0.0 * M01, M12, M13],
         [M02, M12, P.Ja + 0.0 * M01, M23],
         [M03, M13, M23, P.Jt + 0.0 * M01]]
    return M, (Hx, Hy), (c1, s1, ca, sa, ct, st)


def _mass3(P, th1, s, ux, uy, pa, pt):
    """The hooked mass matrix with s held, over (theta1, phi_a, phi_t): (A, B, C, D, E, F) for
    [[A, D, E], [D, B, F], [E, F, C]], and the joint's place H and the cos/sin of the angles."""
    c1, s1 = _cs(th1)
    ca, sa = _cs(pa)
    ct, st = _cs(pt)
    px, py = P.p0x + s * ux, P.p0y + s * uy
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    return (P.If + P.m * (px * px + py * py), P.Ja, P.Jt, P.Pa * (Hx * ca + Hy * sa), P.Pt * (Hx * ct + Hy * st),
            P.Pat * (ca * ct + sa * st), (Hx, Hy), (c1, s1, ca, sa, ct, st))


def _solve3(M, r0, r1, r2, lk1, lkA):
    """Solve the symmetric 3x3 system M x = r with the frame held (lk1 = 1) and/or the arm held (lkA = 1)."""
    A, B, C, D, E, F = M[:6]
    c00, c01, c02 = B * C - F * F, E * F - D * C, D * F - E * B
    c11, c12, c22 = A * C - E * E, D * E - A * F, A * B - D * D
    inv = 1.0 / (A * c00 + D * c01 + E * c02)
    x = [(c00 * r0 + c01 * r1 + c02 * r2) * inv, (c01 * r0 + c11 * r1 + c12 * r2) * inv,
         (c02 * r0 + c12 * r1 + c22 * r2) * inv]
    u = (c00, c01, c02)
    w = (c01 - c02, c11 - c12, c12 - c22)
    lk1 = 0.0 * A if lk1 is None else lk1
    lkA = 0.0 * A if lkA is None else lkA
    both = lk1 * lkA
    k = (lk1 - both) * x[0] / u[0]
    xf = [xi - k * ui for xi, ui in zip(x, u)]
    k = (lkA - both) * (x[1] - x[2]) / (w[1] - w[2])
    xf = [xi - k * wi for xi, wi in zip(xf, w)]
    y = (r1 + r2) / (B + 2.0 * F + C)
    return [xf[0] - both * xf[0], xf[1] + both * (y - xf[1]), xf[2] + both * (y - xf[2])]


def _dry(P, w1, w_alpha):
    """The regularised dry friction (DRY_FRICTION_RATE): the skewer's torque on theta1 (opposing the frame's rate)
    and the axle's on alpha (opposing the arm's rate relative to the torso; + on phi_a, - on phi_t)."""
    return -np.clip(P.pf_c * w1, -P.pf, P.pf), -np.clip(P.af_c * w_alpha, -P.af, P.af)


def _trig3(th1, pa, pt):
    """cos and sin of the frame, arm and torso angles, in one call each (at TRIG_DTYPE precision)."""
    ang = np.empty((3, len(th1)), dtype=TRIG_DTYPE)
    ang[0], ang[1], ang[2] = th1, pa, pt
    return np.cos(ang).astype(np.float64), np.sin(ang).astype(np.float64)


def _stick_eval(P, X, c, th1, pa, pt, w1, wa, wt, extras=False):
    """Accelerations (theta1, phi_a, phi_t) of hooked designs whose hook sticks (s fixed): the 3x3 mass matrix
    inverted by cofactors, the stops' constraints as projections. c: per-step constants (px, py, M00, lock
    weights). With extras: also the joint force, the stops' loads and the frame's cos/sin (stage 1)."""
    px, py, A, wf, wa_, wb, lin = c
    (c1, ca, ct), (s1, sa, st) = _trig3(th1, pa, pt)
    m, Pa, Pt = P.m, P.Pa, P.Pt
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    D = Pa * (Hx * ca + Hy * sa)
    E = Pt * (Hx * ct + Hy * st)
    cat, sat = ca * ct + sa * st, sa * ct - ca * st
    F = P.Pat * cat
    B, C = P.Ja, P.Jt
    w1s, wa2, wt2 = w1 * w1, wa * wa, wt * wt
    Bx = -m * Hx * w1s - Pa * ca * wa2 - Pt * ct * wt2
    By = -m * Hy * w1s - Pa * sa * wa2 - Pt * st * wt2
    da = pa - pt - P.alim
    tau = P.k * da if lin else _spring_torque(P.k, P.stiff, da)
    tp = X.tq0 - X.piv * np.clip((wa - w1) * (1.0 / PIVOT_SLIP_RATE), -1.0, 1.0)
    tf, ta = _dry(P, w1, wa - wt)
    hxh = w1s * (ca * Hy - sa * Hx)  # -(perp(e_a)·b_H)
    hth = w1s * (ct * Hy - st * Hx)
    r0 = -P.mg * Hx + P.cfr * c1 + P.m3gh * s1 - (Hx * By - Hy * Bx) - tp + tf
    r1 = -P.Pag * ca - tau + tp + Pa * hxh - P.Pat * sat * wt2 + ta
    r2 = -P.Ptg * ct + tau + Pt * hth + P.Pat * sat * wa2 - ta
    c00, c01, c02 = B * C - F * F, E * F - D * C, D * F - E * B
    c11, c12, c22 = A * C - E * E, D * E - A * F, A * B - D * D
    inv = 1.0 / (A * c00 + D * c01 + E * c02)
    x0 = (c00 * r0 + c01 * r1 + c02 * r2) * inv
    x1 = (c01 * r0 + c11 * r1 + c12 * r2) * inv
    x2 = (c02 * r0 + c12 * r1 + c22 * r2) * inv
    if wf is not None:  # the frame held at a stop: x - M^-1·e0·x0/(M^-1)_00
        k = wf * x0 / c00
        x1f, x2f = x1 - k * c01, x2 - k * c02
        x0f = x0 - wf * x0
    else:
        x0f, x1f, x2f = x0, x1, x2
    if wa_ is not None:  # the arm held at a stop: J = (0, 1, -1)
        u0, u1, u2 = c01 - c02, c11 - c12, c12 - c22
        k = wa_ * (x1 - x2) / (u1 - u2)
        x0f, x1f, x2f = x0f - k * u0, x1f - k * u1, x2f - k * u2
    if wb is not None:  # both: only the robot's rigid turn about the hook is left
        y = (r1 + r2) / (B + 2.0 * F + C)
        x0f, x1f, x2f = x0f - wb * x0f, x1f + wb * (y - x1f), x2f + wb * (y - x2f)
    acc = (x0f, x1f, x2f)
    if not extras:
        return acc
    Fx = -m * Hy * x0f - Pa * sa * x1f - Pt * st * x2f + Bx
    Fy = m * Hx * x0f + Pa * ca * x1f + Pt * ct * x2f + By + P.mg
    lam1 = A * x0f + D * x1f + E * x2f - r0
    lamA = r2 - (E * x0f + F * x1f + C * x2f)
    return acc, (Fx, Fy, lam1, lamA, c1, s1)


def _stick_consts(P, X):
    """Per-step constants of the stick path: the hook's place on the frame, M00, the stops' weights."""
    px, py = P.p0x + X.s * X.ux, P.p0y + X.s * X.uy
    A = P.If + P.m * (px * px + py * py)
    lk1, lkA = X.lock1, X.lockA
    wf = wa_ = wb = None
    if lk1.any() or lkA.any():
        both = lk1 * lkA
        wf = lk1 - both if (lk1 > lkA).any() else None
        wa_ = lkA - both if (lkA > lk1).any() else None
        wb = both if both.any() else None
    lin = not (P.stiff > 0).any()
    return (px, py, A, wf, wa_, wb, lin)


def _unlocked(X, lam1, lamA, release):
    """Designs whose frame stop (1) or arm stop (A) lets go: a locked stop's multiplier turned to a pull."""
    unlock1 = ~release & (((X.lock1k == 1.0) & (lam1 < 0.0)) | ((X.lock1k == 2.0) & (lam1 > 0.0)))
    unlockA = ~release & (((X.lockAk == 1.0) & (lamA < 0.0)) | ((X.lockAk == 2.0) & (lamA > 0.0)))
    return unlock1, unlockA


def _clear_locks(S, rows1, rowsA):
    """Free the frame stop of ``rows1`` and the arm stop of ``rowsA``."""
    S.lock1[rows1], S.lock1k[rows1] = 0.0, 0.0
    S.lockA[rowsA], S.lockAk[rowsA] = 0.0, 0.0


def _rk4(evaluate, P, X, c, dt, y, v, a1):
    """One classical RK4 step of a second-order system: positions ``y``, rates ``v``, ``a1`` the
    accelerations at the start, ``evaluate(P, X, c, *y, *v)`` the accelerations anywhere."""
    h = 0.5 * dt
    y2 = [yi + h * vi for yi, vi in zip(y, v)]
    v2 = [vi + h * ai for vi, ai in zip(v, a1)]
    a2 = evaluate(P, X, c, *y2, *v2)
    y3 = [yi + h * vi for yi, vi in zip(y, v2)]
    v3 = [vi + h * ai for vi, ai in zip(v, a2)]
    a3 = evaluate(P, X, c, *y3, *v3)
    y4 = [yi + dt * vi for yi, vi in zip(y, v3)]
    v4 = [vi + dt * ai for vi, ai in zip(v, a3)]
    a4 = evaluate(P, X, c, *y4, *v4)
    k6 = dt / 6.0
    y_new = [yi + k6 * (p + 2.0 * (q + r) + u) for yi, p, q, r, u in zip(y, v, v2, v3, v4)]
    v_new = [vi + k6 * (p + 2.0 * (q + r) + u) for vi, p, q, r, u in zip(v, a1, a2, a3, a4)]
    return y_new, v_new


def _stick_step(P, X, c, dt, a1):
    """One RK4 step of sticking designs (theta1, phi_a, phi_t), a1 the accelerations at its start."""
    return _rk4(_stick_eval, P, X, c, dt, (X.th1, X.pa, X.pt), (X.w1, X.wa, X.wt), a1)


def _slide_eval(P, X, c, th1, s, pa, pt, w1, ws, wa, wt, extras=False):
    """Accelerations (theta1, s, phi_a, phi_t) of designs whose hook slides along a face: the s row carries the
    kinetic friction -mu_k·N·sig with N (the face's normal force) linear in the accelerations; s is eliminated
    and the remaining 3x3 solved by Cramer's rule (the stops as substitutions). With extras: also N."""
    ux, uy, nx, ny, musig, lk1, lkA, lin = c
    (c1, ca, ct), (s1, sa, st) = _trig3(th1, pa, pt)
    m, Pa, Pt = P.m, P.Pa, P.Pt
    px, py = P.p0x + s * ux, P.p0y + s * uy
    Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
    uwx, uwy = c1 * ux - s1 * uy, s1 * ux + c1 * uy
    nwx, nwy = c1 * nx - s1 * ny, s1 * nx + c1 * ny
    cat, sat = ca * ct + sa * st, sa * ct - ca * st
    A = P.If + m * (px * px + py * py)
    M01 = m * (px * uy - py * ux)
    D, E = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
    M12, M13 = Pa * (uwy * ca - uwx * sa), Pt * (uwy * ct - uwx * st)
    F = P.Pat * cat
    w1w1, wa2, wt2 = w1 * w1, wa * wa, wt * wt
    w1ws2 = 2.0 * w1 * ws
    bHx, bHy = -Hx * w1w1 - uwy * w1ws2, -Hy * w1w1 + uwx * w1ws2
    Bx = m * bHx - Pa * ca * wa2 - Pt * ct * wt2
    By = m * bHy - Pa * sa * wa2 - Pt * st * wt2
    da = pa - pt - P.alim
    tau = P.k * da if lin else _spring_torque(P.k, P.stiff, da)
    tp = X.tq0
    tf, ta = _dry(P, w1, wa - wt)
    r0 = -P.mg * Hx + P.cfr * c1 + P.m3gh * s1 - (Hx * By - Hy * Bx) - tp + tf
    r1 = -P.mg * uwy - (uwx * Bx + uwy * By)
    r2 = -P.Pag * ca - tau + tp - (Pa * (ca * bHy - sa * bHx) + P.Pat * sat * wt2) + ta
    r3 = -P.Ptg * ct + tau - (Pt * (ct * bHy - st * bHx) - P.Pat * sat * wa2) - ta
    f0 = m * (nwy * Hx - nwx * Hy)
    f2 = Pa * (nwy * ca - nwx * sa)
    f3 = Pt * (nwy * ct - nwx * st)
    N0 = nwx * Bx + nwy * (By + P.mg)
    # the s row with friction, s'' = (q1 - a0 x0 - a2 x2 - a3 x3) / m
    im = 1.0 / m
    a0, a2, a3 = (M01 + musig * f0) * im, (M12 + musig * f2) * im, (M13 + musig * f3) * im
    q1 = (r1 - musig * N0) * im
    # the other rows with s'' substituted: G x = g over (theta1, phi_a, phi_t)
    g00, g01, g02, g0 = A - M01 * a0, D - M01 * a2, E - M01 * a3, r0 - M01 * q1
    g10, g11, g12, g1 = D - M12 * a0, P.Ja - M12 * a2, F - M12 * a3, r2 - M12 * q1
    g20, g21, g22, g2 = E - M13 * a0, F - M13 * a2, P.Jt - M13 * a3, r3 - M13 * q1
    k00, k01, k02 = g11 * g22 - g12 * g21, g12 * g20 - g10 * g22, g10 * g21 - g11 * g20
    inv = 1.0 / (g00 * k00 + g01 * k01 + g02 * k02)
    x0 = (g0 * k00 + g01 * (g12 * g2 - g1 * g22) + g02 * (g1 * g21 - g11 * g2)) * inv
    x1 = (g00 * (g1 * g22 - g12 * g2) + g0 * k01 + g02 * (g10 * g2 - g1 * g20)) * inv
    x2 = (g00 * (g11 * g2 - g1 * g21) + g01 * (g1 * g20 - g10 * g2) + g0 * k02) * inv
    if lk1 is not None:  # the frame held: rows 1, 2 in (phi_a, phi_t)
        inv2 = 1.0 / (g11 * g22 - g12 * g21)
        y1, y2 = (g1 * g22 - g12 * g2) * inv2, (g11 * g2 - g1 * g21) * inv2
        x0, x1, x2 = x0 - lk1 * x0, x1 + lk1 * (y1 - x1), x2 + lk1 * (y2 - x2)
    if lkA is not None:  # the arm held: phi_a'' = phi_t'' = y, rows 0 and 1 + 2
        h0, h1 = g01 + g02, g11 + g12 + g21 + g22
        e1 = g10 + g20
        inv2 = 1.0 / (g00 * h1 - h0 * e1)
        z0, y = (g0 * h1 - h0 * (g1 + g2)) * inv2, (g00 * (g1 + g2) - e1 * g0) * inv2
        if lk1 is not None:  # both: the robot's rigid turn only
            z0, y = z0 - lk1 * z0, y + lk1 * ((g1 + g2) / h1 - y)
        x0, x1, x2 = x0 + lkA * (z0 - x0), x1 + lkA * (y - x1), x2 + lkA * (y - x2)
    xs = q1 - a0 * x0 - a2 * x1 - a3 * x2
    acc = (x0, xs, x1, x2)
    if not extras:
        return acc
    N = f0 * x0 + f2 * x1 + f3 * x2 + N0
    lam1 = A * x0 + M01 * xs + D * x1 + E * x2 - r0
    lamA = r3 - (E * x0 + M13 * xs + F * x1 + P.Jt * x2)
    return acc, (N, lam1, lamA)


def _slide_consts(P, X):
    lk1 = X.lock1 if X.lock1.any() else None
    lkA = X.lockA if X.lockA.any() else None
    return (X.ux, X.uy, X.nx, X.ny, X.mu_sig, lk1, lkA, not (P.stiff > 0).any())


def _slide_step(P, X, c, dt, a1):
    """One RK4 step of sliding designs (theta1, s, phi_a, phi_t)."""
    return _rk4(_slide_eval, P, X, c, dt, (X.th1, X.s, X.pa, X.pt), (X.w1, X.ws, X.wa, X.wt), a1)


# ============================================================================ flight dynamics
#
# The centre of mass is ballistic; the arm and torso angles move about it (kinetic energy
# Ka·wa²/2 + Kt·wt²/2 + Kat·cos(phi_a - phi_t)·wa·wt), driven by the spring only.


def _flight_accel(P, X, pa, pt, wa, wt, lin):
    """Accelerations of (phi_a, phi_t) in flight, and the arm stop's load lam (generalised force on alpha)."""
    c, s = _cs(pa - pt)
    da = pa - pt - P.alim
    tau = P.k * da if lin else _spring_torque(P.k, P.stiff, da)
    kc = P.Kat * c
    ks = P.Kat * s
    ta = -np.clip(P.af_c * (wa - wt), -P.af, P.af)  # the axle's dry friction (DRY_FRICTION_RATE)
    b0 = -ks * wt * wt - tau + ta
    b1 = ks * wa * wa + tau - ta
    inv = 1.0 / (P.Ka * P.Kt - kc * kc)
    x0 = (P.Kt * b0 - kc * b1) * inv
    x1 = (P.Ka * b1 - kc * b0) * inv
    lk = X.lockA
    if lk.any():  # the arm against a stop: the robot turns rigidly
        y = (b0 + b1) / (P.Ka + 2.0 * kc + P.Kt)
        x0, x1 = x0 + lk * (y - x0), x1 + lk * (y - x1)
    return (x0, x1), b1 - kc * x0 - P.Kt * x1


def _flight_step(P, X, dt):
    y = (X.pa, X.pt)
    v = (X.wa, X.wt)
    lin = not (P.stiff > 0).any()
    a1, lam = _flight_accel(P, X, *y, *v, lin)
    h = 0.5 * dt
    y2 = [yi + h * vi for yi, vi in zip(y, v)]
    v2 = [vi + h * ai for vi, ai in zip(v, a1)]
    a2, _ = _flight_accel(P, X, *y2, *v2, lin)
    y3 = [yi + h * vi for yi, vi in zip(y, v2)]
    v3 = [vi + h * ai for vi, ai in zip(v, a2)]
    a3, _ = _flight_accel(P, X, *y3, *v3, lin)
    y4 = [yi + dt * vi for yi, vi in zip(y, v3)]
    v4 = [vi + dt * ai for vi, ai in zip(v, a3)]
    a4, _ = _flight_accel(P, X, *y4, *v4, lin)
    k6 = dt / 6.0
    y_new = [yi + k6 * (p + 2.0 * q + 2.0 * r + u) for yi, p, q, r, u in zip(y, v, v2, v3, v4)]
    v_new = [vi + k6 * (p + 2.0 * q + 2.0 * r + u) for vi, p, q, r, u in zip(v, a1, a2, a3, a4)]
    return y_new, v_new, lam


def _hook_rel_com(P, pa, pt):
    """The hook's position relative to the robot's centre of mass (world), and the centre's offset from the hook."""
    ca, sa = _cs(pa)
    ct, st = _cs(pt)
    ox = (P.Pa * ca + P.Pt * ct) / P.m  # centre of mass - hook
    oy = (P.Pa * sa + P.Pt * st) / P.m
    return -ox, -oy


def _com_velocity_offset(P, pa, pt, wa, wt):
    """d/dt (centre of mass - hook)."""
    ca, sa = _cs(pa)
    ct, st = _cs(pt)
    return (-(P.Pa * sa * wa + P.Pt * st * wt) / P.m, (P.Pa * ca * wa + P.Pt * ct * wt) / P.m)


def _hooked_energy(P, X, oy):
    """Mechanical energy (J) of the hooked frame and robot (kinetic, gravitational, spring); oy: the frame
    axis' height."""
    g = units.GRAVITY
    M, H, trig = _mass4(P, X.th1, X.s, X.pa, X.pt, X.ux, X.uy)
    v = (X.w1, X.ws, X.wa, X.wt)
    kin = 0.0
    for i in range(4):
        for j in range(4):
            kin = kin + 0.5 * M[i][j] * v[i] * v[j]
    c1, s1, ca, sa, ct, st = trig
    pot = (P.frame_m * g * oy - P.cfr * s1 + P.m3gh * c1
           + g * (P.m * (oy + H[1]) + P.Pa * sa + P.Pt * st)
           + _spring_energy(P.k, P.stiff, X.pa - X.pt - P.alim))
    return kin + pot


def _placement(P, theta2):
    """(phi_a, phi_t) of a robot hanging fully bent (alpha_max) with the line from its centre of mass to the hook at
    angle theta2 (the runner's place_hanging)."""
    rot = theta2 - P.line_amax
    return rot + P.amax + 0.5 * np.pi, rot - 0.5 * np.pi


# ============================================================================ the run

_TWO_PI = 2.0 * np.pi


def _wrap(x):
    return (x + np.pi) % _TWO_PI - np.pi


def _cone(Q, X, Fx, Fy, c1, s1):
    """Where the handrail's force (or impulse) (Fx, Fy) on the hook falls against the notch's friction cones.

    Returns (release, slide, face, sig): release where no face can push (tensile); slide where the force leaves
    the static cone with a compressive face (face 0 back, 1 front; sig +1 outward along the face, -1 toward
    the corner). Elsewhere the hook holds."""
    flx, fly = c1 * Fx + s1 * Fy, c1 * Fy - s1 * Fx
    dl = _wrap(np.arctan2(fly, flx) - Q.beta)
    half = 0.5 * np.pi
    corner = X.s <= S_CORNER
    # in the corner: the union of both faces' cones
    out_b = dl < -Q.cone_half
    out_f = dl > Q.cone_half
    comp_b = dl + Q.face_off > -half
    comp_f = dl - Q.face_off < half
    # on one face (mid-face): kappa = -1 back, +1 front
    kappa = 2.0 * X.face - 1.0
    rho = dl - kappa * Q.face_off
    mid_out = np.abs(rho) > Q.phi_s
    mid_tensile = np.abs(rho) > half
    release = np.where(corner, (out_b & ~comp_b) | (out_f & ~comp_f), mid_tensile)
    slide = np.where(corner, (out_b & comp_b) | (out_f & comp_f), mid_out & ~mid_tensile)
    face = np.where(corner, out_f.astype(float), X.face)
    sig = np.where(corner, 1.0, np.where(kappa * rho > 0.0, 1.0, -1.0))
    return release, slide, face, sig


class _Run:
    """The batch's state and its event loop (arrays over the live designs; finished ones are compacted away)."""

    HOOK_STATE = ("th1", "s", "pa", "pt", "w1", "ws", "wa", "wt", "ux", "uy", "nx", "ny", "face", "slide", "sig",
                  "mu_sig", "lock1", "lock1k", "lockA", "lockAk", "piv", "tq0")
    STICK_STATE = ("th1", "s", "pa", "pt", "w1", "wa", "wt", "ux", "uy", "nx", "ny", "face", "lock1", "lock1k",
                   "lockA", "lockAk", "piv", "tq0")
    STICK_PARAMS = ("If", "m", "mg", "Pa", "Pt", "Pag", "Ptg", "Ja", "Jt", "Pat", "cfr", "m3gh", "k", "stiff", "alim",
                    "p0x", "p0y", "beta", "cone_half", "face_off", "phi_s", "mu_s", "mu_k", "r_hook", "nbx", "nby", "nfx", "nfy",
                    "slip_speed", "pf", "pf_c", "af", "af_c")
    SLIDE_STATE = ("th1", "s", "pa", "pt", "w1", "ws", "wa", "wt", "ux", "uy", "nx", "ny", "face", "mu_sig", "lock1",
                   "lock1k", "lockA", "lockAk", "tq0")
    SLIDE_PARAMS = ("If", "m", "mg", "Pa", "Pt", "Pag", "Ptg", "Ja", "Jt", "Pat", "cfr", "m3gh", "k", "stiff", "alim",
                    "p0x", "p0y", "r_hook", "pf", "pf_c", "af", "af_c")
    FLIGHT_STATE = ("pa", "pt", "wa", "wt", "lockA", "lockAk")

    def __init__(self, P: _Arrays, frames: int, dt: float, detail: bool, hold: bool = False):
        self.P, self.frames, self.dt, self.detail = P, frames, dt, detail
        self.hold = hold  # the hook never slips or lets go (swing_trace)
        # dry friction, regularised (DRY_FRICTION_RATE): torque -clip(c·w, -T, T), c = T / rate
        P.pf_c = P.pf / np.maximum(DRY_FRICTION_RATE, P.pf * dt / (P.I_pf * DRY_FRICTION_STEP))
        P.af_c = P.af / np.maximum(DRY_FRICTION_RATE, P.af * dt / (P.I_af * DRY_FRICTION_STEP))
        n = len(P.m)
        self.n = n
        S = _Arrays()
        S.id = np.arange(n)
        S.phase = np.full(n, _HOOKED, dtype=np.int8)
        S.fi = np.zeros(n, dtype=np.int64)
        z = np.zeros(n)
        for k in ("th1", "s", "pa", "pt", "w1", "ws", "wa", "wt", "slide", "mu_sig", "lock1", "lock1k", "lockA",
                  "lockAk", "face", "cx0", "cy0", "vx0", "vy0", "t_rel", "a_rel", "h_rel", "dx_cross", "a_cross",
                  "hx", "hy", "t_mouth", "peak", "t_catch", "barrier", "t0f", "piv", "tq0"):
            setattr(S, k, z.copy())
        S.sig = np.ones(n)
        S.in_notch = np.zeros(n, dtype=bool)
        S.rec = np.zeros(n, dtype=bool)  # the catch state (contact_hold after the catch) has been recorded
        for k in ("t_stop", "t_snap", "t_cross"):
            setattr(S, k, np.full(n, np.nan))
        S.closest = np.full(n, np.inf)
        S.graze = np.full(n, np.inf)  # closest the hook came to the next seat on reaching its depth without seating
        self.S = S
        # results, by design id
        self.reason = np.full(n, -1, dtype=np.int64)
        self.rv = np.full((n, 2), np.nan)
        self.trav = np.zeros(n, dtype=np.int64)
        self.end_time = np.full(n, np.nan)
        self.last_frame = np.zeros(n, dtype=np.int64)
        self.miss = np.full(n, np.nan)
        sh = (n, frames)
        self.sw = {k: np.full(sh, np.nan) for k in ("t_catch", "theta1_catch", "theta2_catch", "t_detach",
                                                    "theta1_detach", "alpha_detach", "theta2_min", "theta2_max",
                                                    "catch_seat")}
        if detail:
            g, j = units.GRAVITY, np.arange(frames)[:, None]
            pe = lambda th: (P.frame_m * g * j * P.rise - P.cfr * np.sin(th) + P.m3gh * np.cos(th))  # noqa: E731
            zero = np.zeros((1, n))
            self._pe = (np.concatenate((zero, np.cumsum(pe(P.stop), axis=0))),
                        np.concatenate((zero, np.cumsum(pe(P.rest), axis=0))))
            self.e_first = np.full(n, np.nan)
            self.e_last = np.full(n, np.nan)
            self.e_min = np.full(n, np.inf)
            self.e_gain = np.zeros(n)
            self.e_rise = np.zeros(n)
        # the start: frame 0 at rest, the robot hanging from its seat at theta2_start, arm fully bent, at rest
        S.th1 = P.rest.copy()
        S.pa, S.pt = _placement(P, P.theta2_start)
        S.ux, S.uy, S.nx, S.ny = P.ubx.copy(), P.uby.copy(), P.nbx.copy(), P.nby.copy()
        S.lockA, S.lockAk = np.ones(n), np.full(n, 2.0)  # against the alpha_max stop
        S.lock1, S.lock1k = np.ones(n), np.ones(n)  # on its rest stop (the first step lifts it if it can)
        S.peak = S.th1.copy()
        self.sw["t_catch"][:, 0] = 0.0
        self.sw["theta1_catch"][:, 0] = np.degrees(P.rest)
        self.sw["theta2_catch"][:, 0] = np.degrees(P.theta2_start)
        self.sw["catch_seat"][:, 0] = 0.0  # the start sets the hook on the seat
        S.rec[:] = True
        all_ = np.arange(n)
        self._start_swing(all_, 0.0)

    # ---------------------------------------------------------------- helpers
    def _finish(self, rows, reason, t_end, v1=None, v2=None):
        """End the runs at working rows ``rows`` with ``reason`` at times t_end."""
        if rows.size == 0:
            return
        S = self.S
        ids = S.id[rows]
        self.reason[ids] = reason
        self.end_time[ids] = t_end
        self.last_frame[ids] = S.fi[rows]
        if v1 is not None:
            self.rv[ids, 0] = v1
        if v2 is not None:
            self.rv[ids, 1] = v2
        self.miss[ids] = S.closest[rows]
        S.phase[rows] = _DONE

    def _start_swing(self, rows, t):
        """Bookkeeping at a catch (or the start): the peak, and whether the frame can climb TURN_BACK_DEG above
        its rest at all with the energy it has (the robot hanging at its lowest; STALL_WINDOW)."""
        S, P = self.S, self.P
        S.t_catch[rows] = t
        S.peak[rows] = S.th1[rows]
        S.t_stop[rows] = np.nan
        S.closest[rows] = np.inf
        Q = _Lazy(P, rows)
        X = S.take(rows, self.HOOK_STATE)
        e = _hooked_energy(Q, X, 0.0)
        g = units.GRAVITY
        th = Q.rest[None, :] + np.radians(TURN_BACK_DEG) * np.linspace(0.0, 1.0, 9)[:, None]
        th = np.maximum(th, X.th1[None, :])
        v_floor = (-Q.cfr * np.sin(th) + Q.m3gh * np.cos(th) - Q.m * g * Q.Lb * np.sin(th)
                   + Q.W_min)
        barrier = np.max(v_floor, axis=0) - e > ENERGY_BARRIER_MARGIN * Q.e_scale
        S.barrier[rows] = barrier

    def _energy_parked(self, rows, fi, left_at_stop):
        """Potential energy of the frames the robot is not on (ahead: at rest; behind: at their stop), from
        per-frame cumulative sums made at the start (by design id)."""
        stop_cum, rest_cum = self._pe
        c = self.S.id[rows]
        upto = fi + (1 if left_at_stop else 0)
        return stop_cum[upto, c] + rest_cum[-1, c] - rest_cum[fi + 1, c]

    def _track_energy(self, rows, e):
        ids = self.S.id[rows]
        first = np.isnan(self.e_first[ids])
        self.e_first[ids[first]] = e[first]
        self.e_last[ids] = e
        self.e_gain[ids] = np.maximum(self.e_gain[ids], e - self.e_first[ids])
        self.e_min[ids] = np.minimum(self.e_min[ids], e)
        self.e_rise[ids] = np.maximum(self.e_rise[ids], e - self.e_min[ids])

    # ---------------------------------------------------------------- the loop
    def run(self) -> None:
        S, P, dt = self.S, self.P, self.dt
        n_max = int(math.ceil(float(np.max(P.t_max)) / dt))
        for k in range(n_max):
            t = k * dt
            rows = np.flatnonzero(S.phase == _HOOKED)
            if rows.size:
                self._hooked(rows, t)
            rows = np.flatnonzero(S.phase == _FLIGHT)
            if rows.size:
                self._flight(rows, t)
            live = S.phase != _DONE
            n_live = int(np.count_nonzero(live))
            if n_live == 0:
                return
            over = np.flatnonzero(live & ((k + 1) * dt >= P.t_max))
            if over.size:
                self._finish(over, _R_T_MAX, (k + 1) * dt)
            if n_live < COMPACT_BELOW * live.size:
                S.compact(live)
                P.compact(live)
        self._finish(np.flatnonzero(S.phase != _DONE), _R_T_MAX, n_max * dt)

    # ---------------------------------------------------------------- hooked
    def _hooked(self, rows, t):
        """One step of the hooked designs: the handrail's force and the stops' loads at t decide the constraints
        (slip, release, unlock), then RK4 under them to t + dt, then the events at t + dt. Designs whose hook
        sticks take the 3x3 path; sliding ones (few at a time) the 4x4 one with the friction row."""
        sl = self.S.slide[rows] > 0.0
        slide_rows = rows[sl]
        if not sl.all():
            started = self._stick_group(rows[~sl], t)
            if started.size:
                slide_rows = np.concatenate((slide_rows, started))
        if slide_rows.size:
            self._slide_group(slide_rows, t)

    def _stick_group(self, rows, t):
        S, P, dt = self.S, self.P, self.dt
        Q = P.take(rows, self.STICK_PARAMS)
        X = S.take(rows, self.STICK_STATE)
        c = _stick_consts(Q, X)
        y0 = (X.th1, X.pa, X.pt, X.w1, X.wa, X.wt)
        a1, (Fx, Fy, lam1, lamA, c1, s1) = _stick_eval(Q, X, c, *y0, extras=True)
        release, start_slide, face, sig = _cone(Q, X, Fx, Fy, c1, s1)
        if self.hold:
            release, start_slide = release & False, start_slide & False
        # the tip turning in the notch: its surface slides over the faces at r·|w_arm - w_frame| (the pymunk switch
        # reads the slip at the contact point): kinetic friction above sim.slip_speed, static below
        mu = np.where(Q.r_hook * np.abs(X.wa - X.w1) > Q.slip_speed, Q.mu_k, Q.mu_s)
        S.piv[rows] = mu * Q.r_hook * self._normal_sum(Q, X, Fx, Fy, c1, s1, mu)
        unlock1, unlockA = _unlocked(X, lam1, lamA, release)
        if release.any():
            self._release(rows[release], t, t)
        if start_slide.any():
            self._start_slide(rows[start_slide], face[start_slide], sig[start_slide])
        keep = ~release & ~start_slide
        changed = keep & (unlock1 | unlockA)
        if changed.any():
            _clear_locks(S, rows[unlock1 & keep], rows[unlockA & keep])
            # the first stage again under the new constraints, for the designs whose constraints changed
            X.lock1, X.lockA = S.lock1[rows], S.lockA[rows]
            Qc, Xc = Q.take(changed), X.take(changed)
            ac = _stick_eval(Qc, Xc, _stick_consts(Qc, Xc), *(v[changed] for v in y0))
            a1 = [a.copy() for a in a1]
            for a, b in zip(a1, ac):
                a[changed] = b
            c = _stick_consts(Q, X)
        if keep.any():
            if not keep.all():
                Q, X, a1 = Q.take(keep), X.take(keep), [a[keep] for a in a1]
                c = _stick_consts(Q, X)
            y, v = _stick_step(Q, X, c, dt, a1)
            kr = rows[keep]
            S.th1[kr], S.pa[kr], S.pt[kr] = y
            S.w1[kr], S.wa[kr], S.wt[kr] = v
            self._hooked_events(kr, t, X.s, np.zeros(len(kr), dtype=bool))
        return rows[start_slide]

    def _slide_group(self, rows, t):
        S, P, dt = self.S, self.P, self.dt
        Q = P.take(rows, self.SLIDE_PARAMS)
        X = S.take(rows, self.SLIDE_STATE)
        c = _slide_consts(Q, X)
        y0 = (X.th1, X.s, X.pa, X.pt, X.w1, X.ws, X.wa, X.wt)
        a1, (N, lam1, lamA) = _slide_eval(Q, X, c, *y0, extras=True)
        # the moment of the sliding friction about the tip's centre, r·mu_k·N·sig·cross(n, u), on the arm
        S.piv[rows] = 0.0
        S.tq0[rows] = Q.r_hook * X.mu_sig * np.maximum(N, 0.0) * (1.0 - 2.0 * X.face)
        release = N < 0.0
        unlock1, unlockA = _unlocked(X, lam1, lamA, release)
        if release.any():
            self._release(rows[release], t, t)
        keep = ~release
        changed = keep & (unlock1 | unlockA)
        if changed.any():
            _clear_locks(S, rows[unlock1 & keep], rows[unlockA & keep])
            X.lock1, X.lockA = S.lock1[rows], S.lockA[rows]
        if changed.any() or not keep.all():
            Q, X = Q.take(keep), X.take(keep)
            c = _slide_consts(Q, X)
            a1 = _slide_eval(Q, X, c, *(v[keep] for v in y0))
        if not keep.any():
            return
        y, v = _slide_step(Q, X, c, dt, a1)
        kr = rows[keep]
        S.th1[kr], S.s[kr], S.pa[kr], S.pt[kr] = y
        S.w1[kr], S.ws[kr], S.wa[kr], S.wt[kr] = v
        self._hooked_events(kr, t, X.s, np.ones(len(kr), dtype=bool))

    def _normal_sum(self, Q, X, Fx, Fy, c1, s1, mu):
        """The sum of the faces' normal forces under the joint force F of a sticking hook, for its turning
        friction. In the corner F = sum_i N_i·(n_i + mu·sig·perp(n_i)): each face's normal force plus the
        friction of the tip turning on it (sig: the sense of the arm's rotation relative to the frame), which is
        what bounds the torque at high friction (mu -> inf: the wedge carries the load by friction alone). On one
        face: that face's normal force."""
        flx, fly = c1 * Fx + s1 * Fy, c1 * Fy - s1 * Fx
        ms = mu * np.where(X.wa >= X.w1, 1.0, -1.0)
        bx, by, fx, fy = Q.nbx, Q.nby, Q.nfx, Q.nfy
        abx, aby = bx - ms * by, by + ms * bx  # n + mu·sig·perp(n)
        afx, afy = fx - ms * fy, fy + ms * fx
        det = abx * afy - aby * afx
        nb = (flx * afy - fly * afx) / det
        nf = (abx * fly - aby * flx) / det
        k = 1.0 / (1.0 + mu * mu)  # one face: F's component along n + mu·sig·perp(n)
        only_b = np.maximum(flx * abx + fly * aby, 0.0) * k
        only_f = np.maximum(flx * afx + fly * afy, 0.0) * k
        corner = np.where(nb < 0.0, only_f, np.where(nf < 0.0, only_b, nb + nf))
        one = np.maximum(flx * X.nx + fly * X.ny, 0.0)
        return np.where(X.s <= S_CORNER, corner, one)

    def _hooked_events(self, rows, t, s_before, was_sliding):
        """After a hooked step to t + dt: impacts at the stops, the slide's end, the runner's swing checks."""
        S, P, dt = self.S, self.P, self.dt
        t1 = t + dt
        # frame stops: inelastic impacts
        th1, w1 = S.th1[rows], S.w1[rows]
        hit = ((th1 >= P.stop[rows]) & (w1 > 0.0) & (S.lock1k[rows] != 2.0)) | \
              ((th1 <= P.rest[rows]) & (w1 < 0.0) & (S.lock1k[rows] != 1.0))
        if hit.any():
            self._impact(rows[hit], t1, frame=True)
        alpha = S.pa[rows] - S.pt[rows] - np.pi
        hitA = (S.phase[rows] == _HOOKED) & (S.lockA[rows] == 0.0) & ((alpha > P.amax[rows]) | (alpha < P.amin[rows]))
        if hitA.any():
            self._impact(rows[hitA], t1, frame=False)
        keep = S.phase[rows] == _HOOKED
        rows, s_before, was_sliding = rows[keep], s_before[keep], was_sliding[keep]
        # the slide's end (a slide an impact has just started waits for its first step)
        sl = was_sliding & (S.slide[rows] > 0.0)
        if sl.any():
            r, sb = rows[sl], s_before[sl]
            s, sig = S.s[r], S.sig[r]
            s_end = np.where(S.face[r] > 0.5, P.s_end_f[r], P.s_end_b[r])
            off = (sig > 0.0) & (s >= s_end)
            if off.any():
                frac = np.clip((s_end[off] - sb[off]) / np.where(s[off] != sb[off], s[off] - sb[off], 1.0), 0.0, 1.0)
                self._release(r[off], t1, t + frac * dt)
            back = ~off & (s <= 0.0)  # back in the corner, where the other face stops it
            stopped = ~off & ~back & (S.ws[r] * sig <= 0.0)  # the slide came to rest
            stick = r[back | stopped]
            S.slide[stick], S.mu_sig[stick], S.ws[stick] = 0.0, 0.0, 0.0
            corner = r[back]
            S.s[corner] = 0.0
            rows = rows[S.phase[rows] == _HOOKED]
        if rows.size == 0:
            return
        self._swing_checks(rows, t1)

    def _swing_checks(self, rows, t1):
        S, P = self.S, self.P
        ids = S.id[rows]
        fi = S.fi[rows]
        th1 = S.th1[rows]
        # the catch state as the runner records it (contact_hold after the first touch)
        rec = ~S.rec[rows] & (t1 - S.t_catch[rows] >= P.contact_hold[rows])
        if rec.any():
            r = rows[rec]
            self.sw["theta1_catch"][S.id[r], S.fi[r]] = np.degrees(S.th1[r])
            self.sw["theta2_catch"][S.id[r], S.fi[r]] = np.degrees(self._theta2(r))
            S.rec[r] = True
        if self.detail:
            th2 = np.degrees(self._theta2(rows))
            lo, hi = self.sw["theta2_min"], self.sw["theta2_max"]
            lo[ids, fi] = np.fmin(lo[ids, fi], th2)
            hi[ids, fi] = np.fmax(hi[ids, fi], th2)
            Q = _Lazy(P, rows)
            e = _hooked_energy(Q, S.take(rows, self.HOOK_STATE), fi * Q.rise) + self._energy_parked(rows, fi, False)
            self._track_energy(rows, e)
        # distance from the hook to the next frame's seat
        c1, s1 = _cs(th1)
        px = P.p0x[rows] + S.s[rows] * S.ux[rows]
        py = P.p0y[rows] + S.s[rows] * S.uy[rows]
        hx = fi * P.pitch[rows] + c1 * px - s1 * py
        hy = fi * P.rise[rows] + s1 * px + c1 * py
        nx = (fi + 1) * P.pitch[rows] + P.seatx[rows]
        ny = (fi + 1) * P.rise[rows] + P.seaty[rows]
        S.closest[rows] = np.minimum(S.closest[rows], np.hypot(hx - nx, hy - ny))
        # the runner's checks
        peak = np.maximum(S.peak[rows], th1)
        S.peak[rows] = peak
        stop = P.stop[rows]
        at_stop = th1 >= stop - STOP_TOLERANCE
        t_stop = np.where(at_stop, np.where(np.isnan(S.t_stop[rows]), t1, S.t_stop[rows]), np.nan)
        S.t_stop[rows] = t_stop
        held = at_stop & (t1 - t_stop >= P.stop_hold[rows])
        turned = ~at_stop & (th1 < peak - np.radians(TURN_BACK_DEG))
        near = peak >= P.held_past[rows]
        since = t1 - S.t_catch[rows]
        timeout = ~held & ~turned & (since > P.swing_timeout[rows])
        rest = P.rest[rows]
        unmoved = peak < rest + REST_MOVE
        at_rest = ~held & ~turned & ~timeout & unmoved & (since > P.rest_timeout[rows])
        # the model's own early end (STALL_WINDOW): the runner would run these to its timeouts
        low = peak < rest + np.radians(TURN_BACK_DEG)
        stuck = ~held & ~turned & ~timeout & ~at_rest & (since >= STALL_WINDOW) & \
            ((S.barrier[rows] > 0.0) | ((S.lock1k[rows] == 1.0) & low))
        self._finish(rows[held], _R_STOP_HOLD, t1)
        self._finish(rows[turned & near], _R_TURN_NEAR_STOP, t1, np.degrees(peak[turned & near]))
        self._finish(rows[turned & ~near], _R_TURN_BACK, t1, np.degrees(peak[turned & ~near]))
        self._finish(rows[timeout], _R_TIMEOUT, t1)
        self._finish(rows[at_rest], _R_AT_REST, t1)
        sr, su = rows[stuck & unmoved], rows[stuck & ~unmoved]
        self._finish(sr, _R_BARRIER_REST, S.t_catch[sr] + np.minimum(P.rest_timeout[sr], P.swing_timeout[sr]))
        self._finish(su, _R_BARRIER, S.t_catch[su] + P.swing_timeout[su])

    def _theta2(self, rows):
        """The runner's theta2: the angle of the line from the robot's centre of mass to the hook."""
        S, P = self.S, self.P
        hx, hy = _hook_rel_com(P.take(rows, ("Pa", "Pt", "m")), S.pa[rows], S.pt[rows])
        return np.arctan2(hy, hx)

    def _impact(self, rows, t1, frame: bool):
        """An inelastic impact at the frame's stops (frame=True) or the arm's: the velocity along the stopped
        coordinate goes to zero with the hook holding (s held: the face takes the impulse), if the handrail can
        take the impulse; else the hook lets go (see below)."""
        S, P = self.S, self.P
        Q = _Lazy(P, rows)
        X = S.take(rows, self.HOOK_STATE)
        ang = np.empty((3, len(rows)), dtype=TRIG_DTYPE)
        ang[0], ang[1], ang[2] = X.th1, X.pa, X.pt
        co, si = np.cos(ang).astype(np.float64), np.sin(ang).astype(np.float64)
        c1, ca, ct = co
        s1, sa, st = si
        m, Pa, Pt = Q.m, Q.Pa, Q.Pt
        px, py = Q.p0x + X.s * X.ux, Q.p0y + X.s * X.uy
        A = Q.If + m * (px * px + py * py)
        Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
        D, E = Pa * (Hx * ca + Hy * sa), Pt * (Hx * ct + Hy * st)
        F = Q.Pat * (ca * ct + sa * st)
        B, C = Q.Ja, Q.Jt
        c00, c01, c02 = B * C - F * F, E * F - D * C, D * F - E * B
        c11, c12, c22 = A * C - E * E, D * E - A * F, A * B - D * D
        u = (c00, c01, c02)  # M^-1·e0 (times det)
        w = (c01 - c02, c11 - c12, c12 - c22)  # M^-1·(0, 1, -1) (times det)
        if frame:
            lim = np.where(X.th1 >= Q.stop, Q.stop, Q.rest)
            err = X.th1 - lim
            k = X.lockA * (u[1] - u[2]) / (w[1] - w[2])  # with the arm held
            x = [ui - k * wi for ui, wi in zip(u, w)]
            jx, jv = x[0], X.w1
        else:
            alpha = X.pa - X.pt - np.pi
            lim = np.where(alpha >= Q.amax, Q.amax, Q.amin)
            err = alpha - lim
            k = X.lock1 * w[0] / u[0]  # with the frame held
            x = [wi - k * ui for ui, wi in zip(u, w)]
            jx, jv = x[1] - x[2], X.wa - X.wt
        into = err * jv > 0.0  # moving further past the stop
        lam = np.where(into, -jv / jx, 0.0)
        dq = [xi * lam for xi in x]
        v = (X.w1, X.wa, X.wt)
        Px = -m * Hy * dq[0] - Pa * sa * dq[1] - Pt * st * dq[2]
        Py = m * Hx * dq[0] + Pa * ca * dq[1] + Pt * ct * dq[2]
        # a hook that has slid less than the hook/card clearance from the corner still has the other face under
        # it: the impulse meets the corner's two faces, and a hold sets it back in the corner
        near = X.s < Q.clear
        Xc = _Arrays()
        Xc.s, Xc.face = np.where(near, 0.0, X.s), X.face
        release, slide, face, sig = _cone(Q, Xc, Px, Py, c1, s1)
        # At the end stop a pull that no face can hold throws the robot off: the frame stays stopped and the robot
        # flies on with the velocities it had (the jolt release). The rest stop never throws the hook (the robot
        # hangs below it). At the arm's stops a pull lifts the hook off the handrail; it is a detach only if the
        # hook stays off for the runner's contact_hold (else the load sets it back in the notch, a bounce).
        if frame:
            at_rest = lim == Q.rest
            go = into & release & ~at_rest
            free = np.zeros(len(rows), dtype=bool)
        else:
            at_rest = np.ones(len(rows), dtype=bool)
            free, fw = self._arm_impact_lifts(Q, X, into & release, jv, err, c1, s1, (Hx, Hy))
            go = free
        hold = ~go
        r = rows[hold]
        back = r[near[hold] & (X.s[hold] > 0.0) & ~(into & slide)[hold]]
        S.s[back], S.ws[back], S.slide[back], S.mu_sig[back] = 0.0, 0.0, 0.0, 0.0
        corr = -err[hold] / jx[hold]
        for name, xi in zip(("th1", "pa", "pt"), x):
            getattr(S, name)[r] += xi[hold] * corr
        for name, vi, di in zip(("w1", "wa", "wt"), v, dq):
            getattr(S, name)[r] = vi[hold] + di[hold]
        kind = np.where(lim == (Q.stop if frame else Q.amax), 2.0, 1.0)
        if frame:
            S.lock1[r], S.lock1k[r] = 1.0, kind[hold]
            S.th1[r] = lim[hold]
        else:
            S.lockA[r], S.lockAk[r] = 1.0, kind[hold]
        # an impulse outside the static cone but pressing on a face starts (or continues) a slide along it
        sl = hold & into & slide & (X.slide == 0.0) & ~at_rest
        if sl.any():
            self._start_slide(rows[sl], face[sl], sig[sl])
        if free.any():  # the arm stops about the robot's own centre: the robot's momentum is unchanged
            rf = rows[free]
            S.pa[rf], S.pt[rf], S.wa[rf], S.wt[rf] = (a[free] for a in fw)
            S.lockA[rf], S.lockAk[rf] = 1.0, kind[free]
        if go.any():
            self._release(rows[go], t1, t1)

    def _arm_impact_lifts(self, Q, X, tensile, jv, err, c1, s1, H):
        """For an arm impact whose held impulse would pull on the handrail: does the hook, free, leave the
        handrail for the runner's contact_hold? It leaves with the velocity the free robot's arm impact gives it
        (about the robot's centre of mass) and falls back under gravity and the handrail's centripetal motion.
        Returns the mask and the free robot's (phi_a, phi_t, w_a, w_t) after the impact."""
        g = units.GRAVITY
        c, _ = _cs(X.pa - X.pt)
        a, b, cc = Q.Ka, Q.Kat * c, Q.Kt
        w = 1.0 / (a + 2.0 * b + cc)
        xa, xt = (cc + b) * w, -(a + b) * w
        dwa, dwt = -xa * jv, -xt * jv
        ca, sa = _cs(X.pa)
        ct, st = _cs(X.pt)
        dvx = (Q.Pa * sa * dwa + Q.Pt * st * dwt) / Q.m
        dvy = -(Q.Pa * ca * dwa + Q.Pt * ct * dwt) / Q.m
        # the way out of the notch: its bisector (in the corner), the face's normal (on a face)
        corner = X.s <= S_CORNER
        bl = Q.beta
        cb, sb = _cs(bl)
        nlx, nly = np.where(corner, cb, X.nx), np.where(corner, sb, X.ny)
        nx, ny = c1 * nlx - s1 * nly, s1 * nlx + c1 * nly
        v_sep = dvx * nx + dvy * ny
        Hx, Hy = H
        a_rel = -g * ny + (Hx * nx + Hy * ny) * X.w1 * X.w1
        T = Q.contact_hold
        lifts = tensile & (v_sep * T + 0.5 * a_rel * T * T > 0.0)
        return lifts, (X.pa - xa * err, X.pt - xt * err, X.wa + dwa, X.wt + dwt)

    def _start_slide(self, rows, face, sig):
        S, P = self.S, self.P
        S.face[rows] = face
        S.sig[rows] = sig
        S.slide[rows] = 1.0
        S.mu_sig[rows] = P.mu_k[rows] * sig
        front = face > 0.5
        S.ux[rows] = np.where(front, P.ufx[rows], P.ubx[rows])
        S.uy[rows] = np.where(front, P.ufy[rows], P.uby[rows])
        S.nx[rows] = np.where(front, P.nfx[rows], P.nbx[rows])
        S.ny[rows] = np.where(front, P.nfy[rows], P.nby[rows])

    # ---------------------------------------------------------------- release and flight
    def _release(self, rows, t_state, t_det):
        """The hook lets go of frame fi: flight from the current state (at time t_state); detach time t_det."""
        S, P = self.S, self.P
        Q = _Lazy(P, rows)
        X = S.take(rows)
        ids, fi = X.id, X.fi
        c1, s1 = _cs(X.th1)
        px, py = Q.p0x + X.s * X.ux, Q.p0y + X.s * X.uy
        Hx, Hy = c1 * px - s1 * py, s1 * px + c1 * py
        uwx, uwy = c1 * X.ux - s1 * X.uy, s1 * X.ux + c1 * X.uy
        vHx, vHy = -Hy * X.w1 + uwx * X.ws, Hx * X.w1 + uwy * X.ws
        hx, hy = _hook_rel_com(Q, X.pa, X.pt)
        dvx, dvy = _com_velocity_offset(Q, X.pa, X.pt, X.wa, X.wt)
        ox, oy = fi * Q.pitch + Hx, fi * Q.rise + Hy  # the hook, world
        S.cx0[rows], S.cy0[rows] = ox - hx, oy - hy
        S.vx0[rows], S.vy0[rows] = vHx + dvx, vHy + dvy
        S.t0f[rows], S.t_rel[rows] = t_state, t_det
        alpha = X.pa - X.pt - np.pi
        S.a_rel[rows] = alpha
        S.h_rel[rows] = oy - ((fi + 1) * Q.rise + Q.seaty)
        S.hx[rows], S.hy[rows] = ox, oy
        S.t_snap[rows], S.t_cross[rows] = np.nan, np.nan
        S.in_notch[rows] = False
        S.graze[rows] = np.inf
        S.slide[rows], S.mu_sig[rows], S.ws[rows], S.lock1[rows], S.lock1k[rows] = 0.0, 0.0, 0.0, 0.0, 0.0
        S.phase[rows] = _FLIGHT
        sw = self.sw
        sw["t_detach"][ids, fi] = t_det
        sw["theta1_detach"][ids, fi] = np.degrees(X.th1)
        sw["alpha_detach"][ids, fi] = np.degrees(alpha)

    def _flight(self, rows, t):
        S, P, dt = self.S, self.P, self.dt
        rows = rows[S.t0f[rows] <= t]  # released at the end of this step's hooked part: from the next step
        if rows.size == 0:
            return
        g = units.GRAVITY
        Q = _Lazy(P, rows)
        X = S.take(rows, self.FLIGHT_STATE)
        (pa, pt), (wa, wt), lamA = _flight_step(Q, X, dt)
        unlock = ((X.lockAk == 1.0) & (lamA < 0.0)) | ((X.lockAk == 2.0) & (lamA > 0.0))
        # the arm's stops: inelastic impacts about the centre of mass
        alpha = pa - pt - np.pi
        beyond = (S.lockA[rows] == 0.0) & ((alpha > Q.amax) | (alpha < Q.amin))
        if beyond.any():
            c, _ = _cs(pa - pt)
            a, b, cc = Q.Ka, Q.Kat * c, Q.Kt
            lim = np.where(alpha > Q.amax, Q.amax, Q.amin)
            err = alpha - lim
            da = wa - wt
            w = 1.0 / (a + 2.0 * b + cc)
            xa, xt = (cc + b) * w, -(a + b) * w  # K^-1 J^T / (J K^-1 J^T), J = (1, -1)
            into = beyond & (err * da > 0.0)
            pa = np.where(beyond, pa - xa * err, pa)
            pt = np.where(beyond, pt - xt * err, pt)
            wa = np.where(into, wa - xa * da, wa)
            wt = np.where(into, wt - xt * da, wt)
            lk = rows[into]
            S.lockA[lk] = 1.0
            S.lockAk[lk] = np.where(lim[into] == Q.amax[into], 2.0, 1.0)
            alpha = pa - pt - np.pi
        un = rows[unlock]
        S.lockA[un], S.lockAk[un] = 0.0, 0.0
        S.pa[rows], S.pt[rows], S.wa[rows], S.wt[rows] = pa, pt, wa, wt
        t1 = t + dt
        tau = t1 - S.t0f[rows]
        cx = S.cx0[rows] + S.vx0[rows] * tau
        cy = S.cy0[rows] + S.vy0[rows] * tau - 0.5 * g * tau * tau
        rx, ry = _hook_rel_com(Q, pa, pt)
        hx, hy = cx + rx, cy + ry
        hx0, hy0 = S.hx[rows], S.hy[rows]
        S.hx[rows], S.hy[rows] = hx, hy
        fi = S.fi[rows]
        nxt = fi + 1
        ox, oy = nxt * Q.pitch, nxt * Q.rise
        seat_x, seat_y = ox + Q.seatx, oy + Q.seaty
        since = t1 - S.t_rel[rows]
        S.closest[rows] = np.minimum(S.closest[rows], np.hypot(hx - seat_x, hy - seat_y))
        if self.detail:
            vy = S.vy0[rows] - g * tau
            c, _ = _cs(pa - pt)
            kin = 0.5 * Q.m * (S.vx0[rows] ** 2 + vy * vy) + 0.5 * (Q.Ka * wa * wa + Q.Kt * wt * wt) + \
                Q.Kat * c * wa * wt
            e = kin + Q.m * g * cy + _spring_energy(Q.k, Q.stiff, alpha - Q.amin) + self._energy_parked(rows, fi, True)
            self._track_energy(rows, e)
        # the runner's watch: the arm's snap, the hook sinking past the next seat
        snapped = alpha < Q.snap
        new_snap = np.isnan(S.t_snap[rows]) & snapped
        S.t_snap[rows[new_snap]] = since[new_snap]
        cross = np.isnan(S.t_cross[rows]) & (hy < seat_y)
        rc = rows[cross]
        S.t_cross[rc] = since[cross]
        S.dx_cross[rc] = hx[cross] - seat_x[cross]
        S.a_cross[rc] = alpha[cross]
        # the notch's mouth: entering it downward with the arm snapped, then reaching the seat's depth
        ax, ay = ox + Q.mbx, oy + Q.mby
        bx, by = ox + Q.mfx - ax, oy + Q.mfy - ay
        side0 = bx * (hy0 - ay) - by * (hx0 - ax)
        side1 = bx * (hy - ay) - by * (hx - ax)
        side_in = bx * (seat_y - ay) - by * (seat_x - ax)
        lam = side0 / np.where(side0 != side1, side0 - side1, 1.0)
        px, py = hx0 + lam * (hx - hx0) - ax, hy0 + lam * (hy - hy0) - ay
        mu = (px * bx + py * by) / (bx * bx + by * by)
        on_mouth = (mu >= 0.0) & (mu <= 1.0)
        enter = on_mouth & (side0 * side_in < 0.0) & (side1 * side_in >= 0.0)
        leave = on_mouth & (side0 * side_in >= 0.0) & (side1 * side_in < 0.0)
        in_notch = S.in_notch[rows]
        ent = enter & ~in_notch & snapped
        S.t_mouth[rows[ent]] = t + lam[ent] * dt
        in_notch = (in_notch | ent) & ~(leave & in_notch)
        S.in_notch[rows] = in_notch
        depth = (hx - seat_x) * Q.bisx + (hy - seat_y) * Q.bisy
        caught = in_notch & (depth <= 0.0)
        if caught.any():
            # the world's catch needs the hook's centre within sim.catch_seat of the seat: here, where the free
            # hook reaches the seat's depth (the model then sets it on the seat); farther is a graze
            d0 = (hx0 - seat_x) * Q.bisx + (hy0 - seat_y) * Q.bisy
            lam_d = np.clip(d0 / np.where(d0 != depth, d0 - depth, 1.0), 0.0, 1.0)
            gap = np.hypot(hx0 + lam_d * (hx - hx0) - seat_x, hy0 + lam_d * (hy - hy0) - seat_y)
            grazed = caught & (gap > Q.catch_seat)
            gz = rows[grazed]
            S.graze[gz] = np.minimum(S.graze[gz], gap[grazed])
            S.in_notch[gz] = False
            in_notch = in_notch & ~grazed
            caught = caught & ~grazed
        if caught.any():
            # the moment the hook reached the seat's depth, inside the step: the state there (the centre of
            # mass in closed form, the arm and torso interpolated)
            c = caught
            d0 = (hx0[c] - seat_x[c]) * Q.bisx[c] + (hy0[c] - seat_y[c]) * Q.bisy[c]
            d1 = depth[c]
            lam_d = np.clip(d0 / np.where(d0 != d1, d0 - d1, 1.0), 0.0, 1.0)
            mid = [x0[c] + lam_d * (x1[c] - x0[c]) for x0, x1 in zip((X.pa, X.pt, X.wa, X.wt), (pa, pt, wa, wt))]
            self._catch(rows[c], t + lam_d * dt, mid, t1, gap[c])
        # the end of a transfer that was not caught
        live = ~caught
        low_mouth = np.minimum(np.minimum(ay, oy + Q.mfy), seat_y) - NOTCH_EXIT_MARGIN
        vy = S.vy0[rows] - g * tau
        floor = cy < cx * Q.rise / Q.pitch - Q.floor_drop
        timeout = since > Q.flight_timeout
        decided = ~np.isnan(S.t_cross[rows]) & ~in_notch & (hy < low_mouth) & (vy < 0.0)
        end = live & (floor | timeout | decided)
        if end.any():
            r = rows[end]
            t_end = np.where((floor | timeout)[end], t1, self._fall_end(r))
            self._classify(r, t_end)

    def _fall_end(self, rows):
        """When the runner would end a decided transfer: the centre of mass below the floor, or the flight timeout."""
        S, P = self.S, self.P
        g = units.GRAVITY
        r = P.rise[rows] / P.pitch[rows]
        # cy0 + vy0·tau - g·tau²/2 = (cx0 + vx0·tau)·r - floor_drop
        a, b, c = -0.5 * g, S.vy0[rows] - S.vx0[rows] * r, S.cy0[rows] - S.cx0[rows] * r + P.floor_drop[rows]
        tau = (-b - np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
        return np.minimum(S.t0f[rows] + tau, S.t_rel[rows] + P.flight_timeout[rows])

    def _classify(self, rows, t_end):
        """The runner's _classify_miss, in its order."""
        S, P = self.S, self.P
        half = 0.5 * (P.amax[rows] - P.amin[rows])
        stiff = S.a_rel[rows] - P.amin[rows] < half
        low = ~stiff & (S.h_rel[rows] < P.min_release_height[rows])
        graze = ~stiff & ~low & np.isfinite(S.graze[rows])
        rest = ~stiff & ~low & ~graze
        never = rest & np.isnan(S.t_cross[rows])
        rest &= ~never
        t_snap, t_cross = S.t_snap[rows], S.t_cross[rows]
        weak = rest & (np.isnan(t_snap) | (t_snap > t_cross))
        rest &= ~weak
        dx = S.dx_cross[rows]
        behind = rest & (dx < 0.0)
        ahead = rest & ~behind
        self._finish(rows[stiff], _R_STIFF, t_end[stiff], np.degrees(S.a_rel[rows[stiff]]))
        self._finish(rows[low], _R_LOW, t_end[low], S.h_rel[rows[low]])
        self._finish(rows[graze], _R_GRAZE, t_end[graze], S.graze[rows[graze]])
        self._finish(rows[never], _R_NEVER_DOWN, t_end[never])
        self._finish(rows[weak], _R_WEAK, t_end[weak], np.degrees(S.a_rel[rows[weak]] - S.a_cross[rows[weak]]))
        self._finish(rows[behind], _R_BEHIND, t_end[behind], -dx[behind])
        self._finish(rows[ahead], _R_AHEAD, t_end[ahead], dx[ahead])

    # ---------------------------------------------------------------- catch
    def _catch(self, rows, t_c, mid, t1, gap):
        """The hook reached the seat of frame fi + 1 at t_c (robot angles and rates ``mid`` then): the inelastic
        catch, then the hooked motion to t1 (or the end of the row)."""
        S, P = self.S, self.P
        g = units.GRAVITY
        j = S.fi[rows] + 1
        ids = S.id[rows]
        t_m = S.t_mouth[rows]
        S.fi[rows] = j
        self.trav[ids] = j
        self.sw["t_catch"][ids, j] = t_m
        self.sw["catch_seat"][ids, j] = gap  # the model then sets the hook on the seat: 0 for the rest of the swing
        last = j == self.frames - 1
        S.pa[rows], S.pt[rows], S.wa[rows], S.wt[rows] = mid
        if last.any():
            r = rows[last]
            self.sw["theta1_catch"][S.id[r], j[last]] = np.degrees(P.rest[r])
            self.sw["theta2_catch"][S.id[r], j[last]] = np.degrees(self._theta2(r))
            self._finish(r, _R_COMPLETED, t_m[last] + P.contact_hold[r])
        rows, t_c, t_m = rows[~last], t_c[~last], t_m[~last]
        if rows.size == 0:
            return
        Q = _Lazy(P, rows)
        X = S.take(rows)
        tau = t_c - X.t0f
        vcx, vcy = X.vx0, X.vy0 - g * tau
        dvx, dvy = _com_velocity_offset(Q, X.pa, X.pt, X.wa, X.wt)
        vHx, vHy = vcx - dvx, vcy - dvy
        ca, sa = _cs(X.pa)
        ct, st = _cs(X.pt)
        cat = ca * ct + sa * st
        Hx, Hy = Q.seatx, Q.seaty  # the hook on the seat, from the new frame's axis
        zero = 0.0 * Hx
        p = [Q.m * (Hx * vcy - Hy * vcx), zero,
             Q.Pa * (ca * vHy - sa * vHx) + Q.Ja * X.wa + Q.Pat * cat * X.wt,
             Q.Pt * (ct * vHy - st * vHx) + Q.Pat * cat * X.wa + Q.Jt * X.wt]
        X.th1, X.s = Q.rest.copy(), zero.copy()
        X.ux, X.uy, X.nx, X.ny = Q.ubx, Q.uby, Q.nbx, Q.nby
        M = _mass3(Q, X.th1, zero, X.ux, X.uy, X.pa, X.pt)
        q = _solve3(M, p[0], p[2], p[3], None, X.lockA)
        back = q[0] < 0.0  # pushed into the rest stop: the frame stays there
        if back.any():
            q2 = _solve3(M, p[0], p[2], p[3], back.astype(float), X.lockA)
            q = [np.where(back, b, a) for a, b in zip(q, q2)]
        # The hook is set on the seat. Where that lifts the robot (a hook that reached the seat's depth beside it,
        # that a face would have guided in), the lift's energy comes out of the motion after the catch: the
        # catch never adds energy.
        cy = X.cy0 + X.vy0 * tau - 0.5 * g * tau * tau
        hy_old = cy + _hook_rel_com(Q, X.pa, X.pt)[1]
        lift = Q.m * g * (j[~last] * Q.rise + Q.seaty - hy_old)
        A, B, C, D, E, F = M[:6]
        kin = 0.5 * (A * q[0] * q[0] + B * q[1] * q[1] + C * q[2] * q[2]) + \
            D * q[0] * q[1] + E * q[0] * q[2] + F * q[1] * q[2]
        scale = np.sqrt(np.clip(1.0 - np.maximum(lift, 0.0) / np.maximum(kin, 1e-300), 0.0, 1.0))
        q = [qi * scale for qi in q]
        S.th1[rows], S.s[rows] = X.th1, X.s
        S.w1[rows], S.ws[rows], S.wa[rows], S.wt[rows] = q[0], zero, q[1], q[2]
        S.ux[rows], S.uy[rows], S.nx[rows], S.ny[rows] = Q.ubx, Q.uby, Q.nbx, Q.nby
        S.face[rows], S.sig[rows], S.slide[rows], S.mu_sig[rows] = 0.0, 1.0, 0.0, 0.0
        S.lock1[rows], S.lock1k[rows] = back.astype(float), back.astype(float)
        S.piv[rows], S.tq0[rows] = 0.0, 0.0
        S.rec[rows] = False
        S.phase[rows] = _HOOKED
        # the rest of the step, hooked
        Qh = P.take(rows, self.STICK_PARAMS)
        Xh = S.take(rows, self.STICK_STATE)
        c = _stick_consts(Qh, Xh)
        a1 = _stick_eval(Qh, Xh, c, Xh.th1, Xh.pa, Xh.pt, Xh.w1, Xh.wa, Xh.wt)
        y, v = _stick_step(Qh, Xh, c, t1 - t_c, a1)
        S.th1[rows], S.pa[rows], S.pt[rows] = y
        S.w1[rows], S.wa[rows], S.wt[rows] = v
        S.th1[rows] = np.maximum(S.th1[rows], Q.rest)
        self._start_swing(rows, t_m)


# ============================================================================ public interface


@dataclass
class BatchResult:
    """What :func:`simulate_batch` returns: one entry per design (arrays of length n)."""

    traversals: np.ndarray  # int: consecutive successful transfers
    outcome: np.ndarray  # str: completed, no_detach, stalled, fell_short, missed_catch
    t_detach: np.ndarray  # s: the first swing's detach time (NaN if the hook never let go of frame 0)
    theta1_detach_deg: np.ndarray  # deg: frame 0's angle at that detach (NaN likewise)
    sim_time: np.ndarray  # s: simulated time at the run's end (the runner's rules: see the module docstring)
    miss_distance: np.ndarray  # m: closest the hook came to the next seat after the last catch (NaN if completed);
    # the hanging is included, so only a run that ``flew`` (the property below) missed by it in flight
    frames: int
    swings: dict = field(repr=False, default_factory=dict)  # per-frame arrays (n, frames), NaN where not reached
    reason_code: np.ndarray = field(repr=False, default=None)
    reason_values: np.ndarray = field(repr=False, default=None)
    last_frame: np.ndarray = field(repr=False, default=None)
    energy: dict | None = field(repr=False, default=None)
    wall_time: float = 0.0
    _text: dict = field(repr=False, default_factory=dict)

    def __len__(self) -> int:
        return len(self.traversals)

    @property
    def flew(self) -> np.ndarray:
        """bool: the run ended in a flight, as :attr:`aero_env.results.SimResult.flew`: the hook let go of the
        last frame that caught it (that frame's ``t_detach`` is recorded) and the next frame did not catch it."""
        t_detach = self.swings["t_detach"][np.arange(len(self)), self.last_frame]
        return (self.outcome != "completed") & np.isfinite(t_detach)

    def reason(self, i: int) -> str:
        """Design i's outcome as a sentence with numbers (the runner's wording)."""
        P = _Arrays()
        for k, v in self._text.items():
            setattr(P, k, v)
        return _reason_text(int(self.reason_code[i]), *self.reason_values[i], int(self.last_frame[i]), P, i)


def simulate_batch(cfgs: Sequence[Config], dt: float | None = None) -> BatchResult:
    """Run every config of ``cfgs`` (all with the same ``scene.frames``) through the reduced model at once.

    ``dt``: the integration step; default: ``sim.dt`` of the configs when their ``sim.model`` is ``reduced``,
    else :data:`STEP`."""
    frames = _check_scene(cfgs)
    if dt is None:
        steps = {_step_for(c) for c in cfgs}
        if len(steps) != 1:
            raise ConfigError(f"simulate_batch: the configs ask for different steps {sorted(steps)}: one batch "
                              f"runs one step (pass dt=)")
        dt = steps.pop()
    return _simulate_raw(_raw_from_configs(cfgs), frames, dt)


def simulate_values(base: Config, values: Mapping[str, np.ndarray], dt: float | None = None) -> BatchResult:
    """The fast path: the designs ``base`` with ``values`` (dotted ``design.*``/``scene.*`` keys -> arrays of
    one length, or scalars) set, without building a Config per design. Each value is checked against its
    field's range and the design's cross-checks, as ``Config.with_values`` does, vectorised."""
    raw = _raw_from_configs([base])
    n = None
    for key, v in values.items():
        a = np.atleast_1d(np.asarray(v, dtype=float))
        if a.ndim != 1 or (n is not None and len(a) not in (1, n)):
            raise ConfigError(f"simulate_values: {key} has shape {np.shape(v)}: every value must be a scalar or a "
                              f"1-D array of one common length")
        if len(a) > 1:
            n = len(a) if n is None else n
    n = n or 1
    raw = {k: np.broadcast_to(v, (n,)).copy() for k, v in raw.items()}
    for key, v in values.items():
        f = real_field(key, "key")
        if key not in raw:
            raise ConfigError(f"simulate_values: {key} is not read by the reduced model (it reads "
                              f"{', '.join(sorted(k for k in raw if '.' in k))})")
        a = np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy()
        meta = f.metadata
        lo, hi = meta["lo"], meta["hi"]
        bad = ~np.isfinite(a)
        if lo is not None:
            bad |= (a < lo) | ((a == lo) if meta["lo_open"] else False)
        if hi is not None:
            bad |= a > hi
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ConfigError(f"{key}[{i}] = {a[i]!r}: out of range, allowed "
                              f"{'(' if meta['lo_open'] else '['}{lo}, {hi}]")
        raw[key] = a
    law = base.scene.effects.friction
    if "design.mu_s" in values or "design.mu_k" in values:
        raw["mu_hold"] = raw["design.mu_k"] if law == "kinetic" else raw["design.mu_s"]
        raw["mu_slide"] = raw["design.mu_s"] if law == "static" else raw["design.mu_k"]
    _check_raw(raw)
    return _simulate_raw(raw, base.scene.frames, _step_for(base) if dt is None else dt)


def _check_raw(raw) -> None:
    """config._check_design's cross-checks, vectorised."""
    d = lambda k: raw["design." + k]  # noqa: E731
    checks = [
        (d("mu_k") > d("mu_s"), "design.mu_k must not exceed design.mu_s"),
        (~(d("alpha_min_deg") < d("alpha_max_deg")), "design.alpha_max_deg must exceed design.alpha_min_deg"),
        (~((d("stop_angle_deg") - d("rest_angle_deg") >= 10.0) & (d("stop_angle_deg") - d("rest_angle_deg") <= 270.0)),
         "the frame must be able to turn from rest_angle_deg to stop_angle_deg by 10 to 270 deg"),
        (np.abs(d("dT")) > d("m1") * units.GRAVITY * np.maximum(d("La"), d("Lb")),
         "design.dT would put the frame's centre of mass beyond its ends"),
        (d("arm_mass") + d("coin_mass") + d("handrail_mass") >= d("m2"),
         "design.m2 must exceed its listed parts arm_mass + coin_mass + handrail_mass"),
        (d("coin_offset") > d("torso_length"), "design.coin_offset must not exceed design.torso_length"),
    ]
    for bad, what in checks:
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ConfigError(f"design {i}: {what}")


def _simulate_raw(raw, frames: int, dt: float) -> BatchResult:
    wall0 = time.perf_counter()
    P = _params(raw)
    text = {k: getattr(P, k).copy() for k in _TEXT_KEYS}
    run = _Run(P, frames, dt, detail=False)
    run.run()
    res = _batch_result(run, time.perf_counter() - wall0)
    res._text = text
    return res


_TEXT_KEYS = ("stop_hold", "stop", "held_past", "swing_timeout", "rest_timeout", "t_max")


def _batch_result(run: _Run, wall: float) -> BatchResult:
    codes = np.array([_REASON_OUTCOME[r] for r in range(len(_REASON_OUTCOME))])
    outcome = np.array(OUTCOMES, dtype=object)[codes[run.reason]].astype(str)
    sw = run.sw
    miss = np.where(outcome == "completed", np.nan, run.miss)
    miss = np.where(np.isfinite(miss), miss, np.nan)
    energy = None
    if run.detail:
        energy = dict(initial=run.e_first, final=run.e_last, max_gain=run.e_gain, max_rise=run.e_rise)
    return BatchResult(traversals=run.trav.copy(), outcome=outcome, t_detach=sw["t_detach"][:, 0].copy(),
                       theta1_detach_deg=sw["theta1_detach"][:, 0].copy(), sim_time=run.end_time.copy(),
                       miss_distance=miss, frames=run.frames, swings=sw, reason_code=run.reason.copy(),
                       reason_values=run.rv.copy(), last_frame=run.last_frame.copy(), energy=energy, wall_time=wall)


def _reason_text(code: int, v1: float, v2: float, origin: int, P, i: int) -> str:
    """The sentence for a reason code, in the words the pymunk runner uses (:mod:`aero_env.results`);
    the energy-barrier stalls are this model's own."""
    if code == _R_COMPLETED:
        return say.completed(origin)
    if code == _R_STOP_HOLD:
        return say.held_at_stop(origin, P.stop_hold[i], math.degrees(P.stop[i]))
    if code == _R_TURN_NEAR_STOP:
        return say.turned_back_holding(origin, v1, math.degrees(P.held_past[i]))
    if code == _R_TURN_BACK:
        return say.turned_back(origin, v1)
    if code == _R_TIMEOUT:
        return say.swing_too_long(origin, P.swing_timeout[i])
    if code == _R_BARRIER:
        return (f"swing on frame {origin} would last over {P.swing_timeout[i]} s: the frame cannot climb "
                f"{TURN_BACK_DEG:.0f} deg above its rest with the energy it has, or fell back to its rest stop "
                f"(too little moment imbalance)")
    if code == _R_AT_REST:
        return say.never_left_rest(origin, P.rest_timeout[i])
    if code == _R_BARRIER_REST:
        return (f"frame {origin} would never leave its rest angle in {P.rest_timeout[i]} s with the robot hooked "
                f"(it cannot climb with the energy it has): the counterbalance outweighs the robot")
    if code == _R_STIFF:
        return say.spring_too_stiff(origin, v1)
    if code == _R_LOW:
        return say.released_low(origin, v1)
    if code == _R_GRAZE:
        return say.grazed(origin, v1)
    if code == _R_NEVER_DOWN:
        return say.never_came_down(origin)
    if code == _R_WEAK:
        return say.spring_too_weak(origin, v1)
    if code == _R_BEHIND:
        return say.passed_behind(origin, v1)
    if code == _R_AHEAD:
        return say.passed_ahead(origin, v1)
    return say.reached_t_max(P.t_max[i])


def swing_trace(cfg: Config, t_end: float, dt: float | None = None, detach: bool = False) -> dict:
    """The first swing of ``cfg`` sampled every step, for comparisons: t, theta1, theta2, alpha (rad), omega1
    (rad/s), energy (J, the hooked frame and robot). With ``detach=False`` the hook holds whatever the force
    (it never slips or lets go), so the swing runs on to ``t_end`` against the stops."""
    frames = _check_scene([cfg])
    dt = _step_for(cfg) if dt is None else dt
    P = _params(_raw_from_configs([cfg]))
    run = _Run(P, frames, dt, detail=False, hold=not detach)
    S = run.S
    rows = np.array([0])
    out = {k: [] for k in ("t", "theta1", "theta2", "alpha", "omega1", "energy")}

    def sample(t):
        out["t"].append(t)
        out["theta1"].append(float(S.th1[0]))
        out["theta2"].append(float(run._theta2(rows)[0]))
        out["alpha"].append(float(S.pa[0] - S.pt[0] - np.pi))
        out["omega1"].append(float(S.w1[0]))
        out["energy"].append(float(_hooked_energy(_Lazy(P, rows), S.take(rows, run.HOOK_STATE), 0.0)[0]))

    sample(0.0)
    for k in range(int(math.ceil(t_end / dt - 1e-9))):
        if S.phase[0] != _HOOKED:
            break
        run._hooked(rows, k * dt)
        if S.phase[0] == _HOOKED:
            sample((k + 1) * dt)
    return {k: np.array(v) for k, v in out.items()}


def simulate_reduced(cfg: Config, dt: float | None = None):
    """One config through the reduced model, as a :class:`~aero_env.results.SimResult` (the pymunk
    runner's fields; the energy is the model's: frames, robot parts and spring; health is all zeros)."""

    wall0 = time.perf_counter()
    frames = _check_scene([cfg])
    dt = _step_for(cfg) if dt is None else dt
    P = _params(_raw_from_configs([cfg]))
    run = _Run(P, frames, dt, detail=True)
    run.run()
    P = _params(_raw_from_configs([cfg]))  # the run compacts its copy
    code = int(run.reason[0])
    sw = run.sw
    swings = []
    for j in range(frames):
        tc = sw["t_catch"][0, j]
        if np.isnan(tc):
            break
        td = sw["t_detach"][0, j]
        opt = lambda x: None if np.isnan(x) else float(x)  # noqa: E731
        swings.append(Swing(j, float(tc), float(sw["theta1_catch"][0, j]), float(sw["theta2_catch"][0, j]),
                            t_detach=opt(td), theta1_detach_deg=opt(sw["theta1_detach"][0, j]),
                            swing_duration=None if np.isnan(td) else float(td - tc),
                            alpha_detach_deg=opt(sw["alpha_detach"][0, j]),
                            theta2_min_deg=opt(sw["theta2_min"][0, j]), theta2_max_deg=opt(sw["theta2_max"][0, j]),
                            catch_seat_mm=opt(sw["catch_seat"][0, j] * 1e3)))
    origin = int(run.last_frame[0])
    reason = _reason_text(code, run.rv[0, 0], run.rv[0, 1], origin, P, 0)
    outcome = OUTCOMES[_REASON_OUTCOME[code]]
    miss = run.miss[0]
    e = dict(initial=float(run.e_first[0]), final=float(run.e_last[0]), max_gain=float(run.e_gain[0]),
             max_rise=float(run.e_rise[0]))
    return SimResult(traversals=int(run.trav[0]), frames=frames, outcome=outcome, reason=reason, swings=swings,
                     energy=e, sim_time=float(run.end_time[0]), wall_time=time.perf_counter() - wall0,
                     miss_distance=None if outcome == "completed" or not np.isfinite(miss) else float(miss),
                     health=dict(joint_drift=0.0, limit_overshoot_deg=0.0, penetration=0.0),
                     fidelity=cfg.sim.fidelity)
