"""From configs to the kernel's table of per-design constants (SI), vectorised over the designs.

``raw_from_configs`` reads the fields the model uses (dotted keys -> arrays), ``check_raw`` applies
the config's cross-checks to arrays, and ``param_table`` derives every constant the phases read,
one row per design, one column per name of :data:`.layout.P`.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ... import units
from ...config import Config, ConfigError, check_design
from ...parts.bodies import RobotParts, frame_body, frame_card, spring_damping_coefficient
from ...physics.swing_rules import held_past_angle
from .constants import DRY_FRICTION_RATE, DRY_FRICTION_STEP, MOUTH_END_REACH, STEP
from .layout import P

# The config fields the model reads, by dotted key (everything else is ignored).
DESIGN_KEYS = ("La", "Lb", "Lc", "Ld", "h", "m1", "m2", "m3", "dT", "spring_k", "mu_s", "mu_k", "arm_length",
               "arm_mass", "coin_mass", "coin_radius", "handrail_mass",
               "pivot_friction", "axle_friction", "spring_damping", "alpha_min_deg", "alpha_max_deg", "rest_angle_deg", "stop_angle_deg",
               "notch_angle_deg", "notch_opening_deg", "notch_back_face", "notch_front_face",
               "handrail_thickness", "hook_radius")
SCENE_KEYS = ("pitch", "rise", "theta2_start_deg", "floor_drop")
SIM_KEYS = ("contact_hold", "flight_timeout", "swing_timeout", "rest_timeout", "stop_hold", "t_max",
            "min_release_height", "slip_speed", "catch_seat")
ALPHA_GRID = 33  # arm angles between the stops where the stall test looks for the robot's lowest potential


class _DesignArrays:
    """The ``design.*`` arrays of a raw batch as attributes, for :mod:`aero_env.parts.bodies`."""

    def __init__(self, raw):
        for k, v in raw.items():
            if k.startswith("design."):
                setattr(self, k[7:], v)


def raw_from_configs(cfgs: Sequence[Config]) -> dict:
    raw = {}
    for k in DESIGN_KEYS:
        raw["design." + k] = np.array([getattr(c.design, k) for c in cfgs], dtype=float)
    for k in SCENE_KEYS:
        raw["scene." + k] = np.array([getattr(c.scene, k) for c in cfgs], dtype=float)
    for k in SIM_KEYS:
        raw["sim." + k] = np.array([getattr(c.sim, k) for c in cfgs], dtype=float)
    raw["spring_stiffening"] = np.array([c.scene.effects.spring_law == "stiffening" for c in cfgs], dtype=float)
    set_friction_law(raw, [c.scene.effects.friction for c in cfgs])
    return raw


def set_friction_law(raw: dict, laws) -> None:
    """The coefficients a hook holds with and slides with, under ``scene.effects.friction``: the static/kinetic
    switch (``static_kinetic``), or one coefficient throughout (``static``, ``kinetic``)."""
    laws = np.broadcast_to(np.asarray(laws, dtype=object), raw["design.mu_s"].shape)
    mu_s, mu_k = raw["design.mu_s"], raw["design.mu_k"]
    raw["mu_hold"] = np.where(laws == "kinetic", mu_k, mu_s)
    raw["mu_slide"] = np.where(laws == "static", mu_s, mu_k)


def check_scene(cfgs: Sequence[Config]) -> int:
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


def step_for(cfg: Config) -> float:
    """The integration step: the config's sim.dt when its sim.model names this model, else STEP."""
    return float(cfg.sim.dt) if getattr(cfg.sim, "model", None) == "reduced" else STEP


def check_raw(raw) -> None:
    """The config's design cross-checks (:func:`aero_env.config.check_design`) on the designs' arrays."""
    check_design(_DesignArrays(raw))


def spring_energy(k, stiff, da):
    """The leaf spring's energy at da past alpha_min: k·da²/2 (linear), k·|da|³/6 (stiffening)."""
    return np.where(stiff > 0, k * np.abs(da) ** 3 / 6.0, 0.5 * k * da * da)


def param_table(raw: Mapping[str, np.ndarray], dt: float) -> np.ndarray:
    """Every per-design constant of the model, (n, len(P)) float64, from the raw config fields and the step."""
    d = lambda k: raw["design." + k]  # noqa: E731
    g = units.GRAVITY
    rad = np.radians
    c = {}
    La, Lb, h, m1, m3 = d("La"), d("Lb"), d("h"), d("m1"), d("m3")
    dT = d("dT")
    mh = d("handrail_mass")
    # the frame as the world swings it (aero_env/parts/bodies.py): its side cards, the counterbalance at (La, h) and
    # the handrail's card at the seat, one body about the axis (dT moves the card's centre, not its inertia there)
    _, x_f, I1 = frame_card(_DesignArrays(raw))
    c["frame_m"], _, c["If"] = frame_body(m1, x_f, I1, m3, La, h, mh, Lb)
    c["m3gh"] = m3 * g * h
    # the frame's own, the counterbalance's and the handrail card's moment: cfr·cos(theta1) + m3gh·sin(theta1)
    c["cfr"] = dT - m3 * g * La + mh * g * Lb
    # the robot from its parts (aero_env.parts.bodies.RobotParts, as the pymunk robot is built)
    parts = RobotParts(_DesignArrays(raw))
    ma, mt, m2 = parts.m_arm, parts.m_torso, parts.mass
    L, dc = parts.arm_length, parts.torso_com
    amin, amax = rad(d("alpha_min_deg")), rad(d("alpha_max_deg"))
    c["m"], c["mg"] = m2, m2 * g
    xa = L - parts.arm_com  # the arm's centre from the hook
    Pa = c["Pa"] = ma * xa + mt * L  # first moments about the hook of the arm direction ...
    Pt = c["Pt"] = mt * dc  # ... and of the torso direction
    Ja = c["Ja"] = parts.I_arm + ma * xa**2 + mt * L**2  # arm + torso about the hook (arm coordinate)
    Jt = c["Jt"] = parts.I_torso + mt * dc**2  # torso about the axle
    Pat = c["Pat"] = mt * L * dc
    # about the centre of mass (flight): kinetic energy Ka·wa²/2 + Kt·wt²/2 + Kat·cos(pa - pt)·wa·wt
    Ka, Kt, Kat = c["Ka"], c["Kt"], c["Kat"] = Ja - Pa**2 / m2, Jt - Pt**2 / m2, Pat - Pa * Pt / m2
    c["Pag"], c["Ptg"] = Pa * g, Pt * g
    k, stiff = c["k"], c["stiff"] = d("spring_k"), raw["spring_stiffening"]
    c["spring_c"] = spring_damping_coefficient(k, d("spring_damping"), d("arm_mass"), d("arm_length"))
    c["amin"], c["amax"] = amin, amax
    c["alim"] = np.pi + amin  # the spring is straight at phi_a - phi_t = this
    c["snap"] = amin + 0.5 * (amax - amin)  # the runner's "snapped" arm angle (half its range)
    hk, _, _, cm = parts.layout(amax)
    c["line_amax"] = np.arctan2(hk[1] - cm[1], hk[0] - cm[0])  # the centre -> hook line in the torso's frame, bent
    c["mu_s"], c["mu_k"] = raw["mu_hold"], raw["mu_slide"]
    c["phi_s"], c["phi_k"] = np.arctan(raw["mu_hold"]), np.arctan(raw["mu_slide"])  # the cones' half-angles
    c["r_hook"] = d("hook_radius")
    # the notch (frame-local, as swing_frame.SwingFrame builds it)
    rest, stop = rad(d("rest_angle_deg")), rad(d("stop_angle_deg"))
    c["rest"], c["stop"], c["Lb"] = rest, stop, Lb
    c["held_past"] = held_past_angle(_DesignArrays(raw))  # the runner's turn-back rule, the same function
    beta = rad(d("notch_angle_deg")) - rest  # bisector, local
    o = rad(d("notch_opening_deg"))
    nb_sf = (np.cos(beta - o / 2), np.sin(beta - o / 2))  # swing_frame's n_back (= the front face's direction)
    nf_sf = (np.cos(beta + o / 2), np.sin(beta + o / 2))  # swing_frame's n_front (= the back face's direction)
    cl = c["clear"] = d("handrail_thickness") / 2.0 + d("hook_radius")
    denom = 1.0 + nb_sf[0] * nf_sf[0] + nb_sf[1] * nf_sf[1]
    corner = (-Lb - (nb_sf[0] + nf_sf[0]) * cl / denom, -(nb_sf[1] + nf_sf[1]) * cl / denom)
    c["p0x"], c["p0y"] = -Lb, np.zeros_like(Lb)
    # back face: direction nf_sf, inward normal = direction rotated by -90 deg; front face: nb_sf, +90 deg
    c["ubx"], c["uby"] = nf_sf
    c["nbx"], c["nby"] = nf_sf[1], -nf_sf[0]
    c["ufx"], c["ufy"] = nb_sf
    c["nfx"], c["nfy"] = -nb_sf[1], nb_sf[0]
    sc = (-Lb - corner[0], -corner[1])  # the seat relative to the corner
    c["s_end_b"] = d("notch_back_face") - (sc[0] * nf_sf[0] + sc[1] * nf_sf[1])
    c["s_end_f"] = d("notch_front_face") - (sc[0] * nb_sf[0] + sc[1] * nb_sf[1])
    c["beta"] = beta
    half = 0.5 * np.pi - o / 2  # each face's normal makes this angle with the bisector
    c["face_off"] = half  # the back face's normal is at beta - half, the front face's at beta + half;
    # the corner's union cone: |angle(F) - beta| <= face_off + phi
    # the mouth of a notch at rest (offsets from its frame's axis), its seat, its bisector
    cr, sr = np.cos(rest), np.sin(rest)
    rot = lambda x, y: (cr * x - sr * y, sr * x + cr * y)  # noqa: E731
    ebx, eby = corner[0] + nf_sf[0] * d("notch_back_face"), corner[1] + nf_sf[1] * d("notch_back_face")
    efx, efy = corner[0] + nb_sf[0] * d("notch_front_face"), corner[1] + nb_sf[1] * d("notch_front_face")
    # the hook touches a face's end when its centre comes within the hook/card clearance of it: the window
    # runs that far past each end (pymunk's catch is any 10 ms touch, a face's tip included)
    mx, my = efx - ebx, efy - eby
    ext = MOUTH_END_REACH * cl / np.hypot(mx, my)
    c["mbx"], c["mby"] = rot(ebx - ext * mx, eby - ext * my)
    c["mfx"], c["mfy"] = rot(efx + ext * mx, efy + ext * my)
    c["seatx"], c["seaty"] = rot(-Lb, 0.0 * Lb)
    c["bisx"], c["bisy"] = np.cos(beta + rest), np.sin(beta + rest)
    for face in "bf":
        c[f"r{face}ux"], c[f"r{face}uy"] = rot(c[f"u{face}x"], c[f"u{face}y"])
        c[f"r{face}nx"], c[f"r{face}ny"] = rot(c[f"n{face}x"], c[f"n{face}y"])
    # the scene and the runner's limits
    c["pitch"], c["rise"], c["floor_drop"] = raw["scene.pitch"], raw["scene.rise"], raw["scene.floor_drop"]
    c["next_card"] = next_card_reach(c, rest, stop)
    c["theta2_start"] = rad(raw["scene.theta2_start_deg"])
    for key in SIM_KEYS:
        c[key] = raw["sim." + key]
    # the stall test: the robot hanging from a fixed hook, its lowest potential over alpha, and the energy scale
    al = amin[None, :] + (amax - amin)[None, :] * np.linspace(0.0, 1.0, ALPHA_GRID)[:, None]
    hk, _, _, cm = parts.layout(al)
    dist = np.hypot(hk[0] - cm[0], hk[1] - cm[1])
    c["W_min"] = np.min(spring_energy(k, stiff, al - amin) - m2 * g * dist, axis=0)
    c["e_scale"] = (m2 + m3) * g * (La + Lb) + spring_energy(k, stiff, amax - amin)
    # dry friction, regularised (DRY_FRICTION_RATE): torque -clip(c·w, -T, T), c = T / rate, the rate raised where
    # the step needs it (DRY_FRICTION_STEP) against the coordinate's smallest inertia: the frame alone for the
    # skewer, the free robot's alpha for the axle
    pf, af = c["pf"], c["af"] = d("pivot_friction"), d("axle_friction")
    I_af = (Ka * Kt - Kat**2) / (Ka + Kt + 2.0 * np.abs(Kat))
    c["pf_c"] = pf / np.maximum(DRY_FRICTION_RATE, pf * dt / (c["If"] * DRY_FRICTION_STEP))
    c["af_c"] = af / np.maximum(DRY_FRICTION_RATE, af * dt / (I_af * DRY_FRICTION_STEP))
    n = len(La)
    table = np.empty((n, len(P)))
    for name in P:
        table[:, name] = np.broadcast_to(np.asarray(c[name.name], dtype=float), (n,))
    return table


def next_card_reach(c: dict, rest: np.ndarray, stop: np.ndarray, samples: int = 33) -> np.ndarray:
    """1.0 for each design whose hook, hooked on a frame, can come within the hook/card clearance of the next
    frame's cards (at rest) at all; 0.0 where it cannot, and next_card skips its test (a capsule test every
    hooked step: 9 % of the model's time; only a steep row needs it). Conservative: the hook's centre stays in
    the annular sector its notch sweeps from the rest stop to the end stop (its radii and polar angles over
    both faces, widened by the card's rounded end, the clearance and the sampling), and a card is out of reach
    when none of its centre line's points lies in that sector widened by the clearance."""
    cl = c["clear"]
    s = np.linspace(0.0, 1.0, samples)[:, None]
    # the hook's centre on each face, frame coordinates (p0 + s·u), and its radius and angle about the axis
    rad_, ang_ = [], []
    for f in "bf":
        qx = c["p0x"] + s * c[f"s_end_{f}"] * c[f"u{f}x"]
        qy = c["p0y"] + s * c[f"s_end_{f}"] * c[f"u{f}y"]
        rad_.append(np.hypot(qx, qy))
        ang_.append(np.arctan2(qy, qx))
    r = np.concatenate(rad_)
    ref = ang_[0][0]  # angles taken from the seat's (p0's): the notch spans far less than a turn
    a = np.angle(np.exp(1j * (np.concatenate(ang_) - ref)))
    widen = 3.0 * cl  # the rounded end (one clearance), the clearance itself, the card's sampling (< one)
    r_lo, r_hi = r.min(axis=0) - widen, r.max(axis=0) + widen
    da = np.arcsin(np.minimum(1.0, widen / np.maximum(r_lo, widen)))
    a_lo = rest + ref + a.min(axis=0) - da  # the sector's first angle and its span
    span = (stop - rest) + (a.max(axis=0) - a.min(axis=0)) + 2.0 * da
    reach = np.zeros_like(r_lo, dtype=bool)
    for f in "bf":  # the next frame's card: its centre line from the seat, seat + s·u - cl·n, at rest
        px = c["pitch"] + c["seatx"] + s * c[f"s_end_{f}"] * c[f"r{f}ux"] - cl * c[f"r{f}nx"]
        py = c["rise"] + c["seaty"] + s * c[f"s_end_{f}"] * c[f"r{f}uy"] - cl * c[f"r{f}ny"]
        pr = np.hypot(px, py)
        pa = np.mod(np.arctan2(py, px) - a_lo, 2.0 * np.pi)
        reach |= np.any((pr >= r_lo) & (pr <= r_hi) & (pa <= span), axis=0)
    return reach.astype(float)
