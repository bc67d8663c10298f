"""The analytical models: Eq. (1), the two-link model, their agreement, and the pymunk pinned-hook check."""

import math

import numpy as np
import pytest

from aero_env.models import quasi_static, two_link
from aero_env.physics import simulate
from aero_env.units import GRAVITY

R = math.radians


def test_quasi_static_moment_changes_sign_near_125_deg(paper_cfg):
    d = paper_cfg.design
    assert d.dT == 0.0
    zero = math.degrees(quasi_static.zero_crossing(d))
    assert zero == pytest.approx(125.0, abs=2.0)  # the paper: positive up to ~125 deg, negative beyond
    th = np.radians(np.linspace(56, 179, 200))
    acc = quasi_static.angular_acceleration(d, th)  # vectorised
    assert acc.shape == th.shape
    assert np.all(acc[th < R(zero) - 1e-3] > 0) and np.all(acc[th > R(zero) + 1e-3] < 0)


def test_dT_adds_to_the_quasi_static_moment(paper_cfg):
    d0, d1 = paper_cfg.design, paper_cfg.replace({"design.dT": 0.001}).design
    th = np.radians([10.0, 80.0])
    assert quasi_static.moment(d1, th) - quasi_static.moment(d0, th) == pytest.approx(0.001 * np.cos(th))


def test_two_link_without_robot_swing_is_equation_1(paper_cfg):
    d = paper_cfg.replace({"design.Lc": 0.0}).design
    c = two_link.coefficients(d)
    tl = two_link.simulate(d, R(55), R(81), t_end=0.8)
    qs = quasi_static.simulate(d, R(55), t_end=0.8, I=c.eta1)
    assert np.max(np.abs(tl.theta1 - qs.theta1)) < 1e-8
    assert np.ptp(tl.theta2) == 0.0  # with Lc = 0 the robot line does not move


def test_two_link_reference_times_from_the_brief(paper_cfg):
    d = paper_cfg.design
    consistent = two_link.simulate(d, R(55), R(81), until_theta1=R(165)).t_until
    paper = two_link.simulate(d, R(55), R(81), until_theta1=R(165), inertia="paper").t_until
    assert consistent == pytest.approx(0.64, abs=0.01)  # brief: ~0.64 s
    assert paper == pytest.approx(0.75, abs=0.01)  # brief: ~0.75 s with A13's double-counted I3


def test_time_to_angle_is_accurate_to_a_microsecond(paper_cfg):
    d = paper_cfg.design
    default = two_link.simulate(d, R(55), R(81), until_theta1=R(165)).t_until
    tight = two_link.simulate(d, R(55), R(81), until_theta1=R(165), rtol=1e-13, atol=1e-15).t_until
    assert abs(default - tight) < 1e-6


def test_two_link_conserves_energy_and_drag_only_removes_it(paper_cfg):
    d = paper_cfg.design
    c = two_link.coefficients(d)
    res = two_link.simulate(d, R(55), R(81), until_theta1=R(165))
    e = two_link.energy(c, res.theta1, res.theta2, res.omega1, res.omega2)
    assert np.ptp(e) / np.abs(e).max() < 1e-8
    dragged = two_link.simulate(d, R(55), R(81), until_theta1=R(165), drag=True)
    ed = two_link.energy(c, dragged.theta1, dragged.theta2, dragged.omega1, dragged.omega2)
    assert np.all(np.diff(ed) <= 1e-15) and ed[-1] < ed[0]


def signs_in(run, lo_deg, hi_deg):
    """(share of theta1'' > 0, share of theta2'' > 0) over the samples with theta1 in [lo, hi) deg."""
    sel = (run.theta1 >= R(lo_deg)) & (run.theta1 < R(hi_deg))
    assert sel.sum() >= 10, (lo_deg, hi_deg, sel.sum())
    return float(np.mean(run.alpha1[sel] > 0)), float(np.mean(run.alpha2[sel] > 0))


# Where the two links' accelerations have opposite signs (the paper: "for much of the swing", 0.7 of it, loose).
# Measured on the prototype in the two-link model and in the pymunk world alike: just after release both
# accelerate (55-58 deg); from 62 to 90 deg the frame speeds up while the robot's line swings back
# (theta1'' > 0 > theta2''); from 118 to 140 deg the roles swap (theta1'' < 0 < theta2''). Share of the swing
# with opposite signs: two-link 0.65, world 0.60.
SIGN_WINDOWS = [((55, 58), (True, True)), ((62, 90), (True, False)), ((118, 140), (False, True))]


def test_accelerations_have_opposite_signs_over_part_of_the_swing(paper_cfg):
    d = paper_cfg.design
    res = two_link.simulate(d, R(55), R(81), until_theta1=R(165))
    for (lo, hi), (a1_up, a2_up) in SIGN_WINDOWS:
        assert signs_in(res, lo, hi) == (float(a1_up), float(a2_up)), (lo, hi)
    # the accelerations are the brief's equations' (A25, A30) on the model's own states: same signs everywhere
    by_hand = np.array([_eta_by_hand(d, *y) for y in zip(res.theta1, res.theta2, res.omega1, res.omega2)])
    assert np.array_equal(np.sign(by_hand[:, 0] * by_hand[:, 1]), np.sign(res.alpha1 * res.alpha2))
    share = np.mean(res.alpha1 * res.alpha2 < 0)  # samples are equally spaced in time
    assert share == pytest.approx(0.7, abs=0.2)  # the paper's share (measured 0.65)


def drag_power_by_hand(d, th1, th2, w1, w2):
    """W: the power the brief's quadratic drag takes out, integrated along each strip by hand (401 points),
    from the config's rho, Cd and widths. The frame: both arms, normal speed r·theta1' at radius r. The
    robot: the line from the joint (the seat, at Lb) to its centre (Lc), normal speed
    Lb·theta1'·cos(theta1 - theta2) + l·theta2' at l from the joint."""
    r = np.linspace(0.0, 1.0, 401)
    frame = sum(np.trapezoid(np.abs(np.outer(w1, r * L)) ** 3, r * L, axis=1) for L in (d.La, d.Lb))
    l = r * d.Lc
    vn = np.outer(d.Lb * w1 * np.cos(th1 - th2), np.ones_like(l)) + np.outer(w2, l)
    robot = np.trapezoid(np.abs(vn) ** 3, l, axis=1)
    return 0.5 * d.rho * d.Cd * (d.frame_width * frame + d.robot_width * robot)


def test_drag_takes_out_exactly_its_work_and_slows_the_frame_a_little(paper_cfg):
    d = paper_cfg.design
    c = two_link.coefficients(d)
    a = two_link.simulate(d, R(55), R(81), until_theta1=R(165))
    b = two_link.simulate(d, R(55), R(81), until_theta1=R(165), drag=True)
    # the energy the dragged swing loses is the drag's work, computed here from the drag law (measured 1.5e-6 J,
    # agreeing to 6e-7 of it); a drag that did nothing, or twice too much, fails here
    e = two_link.energy(c, b.theta1, b.theta2, b.omega1, b.omega2)
    p = drag_power_by_hand(d, b.theta1, b.theta2, b.omega1, b.omega2)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(b.t))])
    assert work[-1] > 1e-6
    assert np.abs((e[0] - e) - work).max() < 1e-4 * work[-1]
    # at every angle the dragged frame accelerates less, by 0.05-1 % of the swing's largest theta1''
    # (measured 0.23 %: the paper's "no noticeable difference"), and reaches 165 deg later (measured +0.5 ms)
    grid = np.radians(np.linspace(56, 164, 300))
    diff = np.interp(grid, b.theta1, b.alpha1) - np.interp(grid, a.theta1, a.alpha1)
    assert np.all(diff < 0)
    assert 5e-4 < np.abs(diff).max() / np.abs(a.alpha1).max() < 0.01
    assert 1e-4 < b.t_until - a.t_until < 5e-3


def test_batch_fast_path_matches_the_integrator(paper_cfg):
    designs = [paper_cfg.replace({"design.m2": m2}).design for m2 in (0.00771, 0.0085, 0.009, 0.0095)]
    batch = two_link.time_to_angle_batch(designs, R(55), R(81), R(150))
    for d, tb in zip(designs, batch):
        assert tb == pytest.approx(two_link.simulate(d, R(55), R(81), until_theta1=R(150)).t_until, abs=1e-5)
    # a counterbalance (the tunable's heaviest) whose moment outweighs the robot's: the frame turns back
    stuck = paper_cfg.replace({"design.m3": 0.012}).design
    assert np.isnan(two_link.time_to_angle_batch([stuck], R(55), R(81), R(150), t_end=1.0)[0])


def test_pymunk_pinned_hook_scene_agrees_with_two_link(paper_cfg):
    # The article's Appendix B: with the hook a pin and no spring the MBD reduces to the two-link model.
    # The pinned robot is the parts held rigid at alpha_max (robot="parts"), and the frame carries
    # its own moment dT (its centre of mass moved, I1 kept about the axis); the world's frame is the kit's
    # two side cards, so the model's I1 is theirs (inertia="parts").
    cfg = paper_cfg.replace({"scene.effects.hook": "pin", "sim.trace_every": 1, "scene.frames": 2,
                             "design.dT": 3e-4, "design.pivot_friction": 0.0, "design.axle_friction": 0.0})
    r = simulate(cfg, trace=True)
    assert r.outcome == "no_detach" and "pinned" in r.reason
    t, th1, th2 = r.trace["t"], r.trace["theta1"], r.trace["theta2"]
    i = int(np.argmax(th1 >= R(165)))
    t165 = t[i - 1] + (R(165) - th1[i - 1]) / (th1[i] - th1[i - 1]) * (t[i] - t[i - 1])
    ref = two_link.simulate(cfg.design, R(55), R(81), until_theta1=R(165), robot="parts", inertia="parts")
    assert t165 == pytest.approx(ref.t_until, rel=0.01)  # measured: 0.07% at dt = 0.5 ms
    rms = np.sqrt(np.mean((th2[:i] - np.interp(t[:i], ref.t, ref.theta2)) ** 2))
    assert math.degrees(rms) < 1.0  # measured: 0.020 deg


# ---- dT (the frame's own moment) and the robot conventions ----
DT = 3e-4  # N·m: a frame moment of the size the issue measured (~5 % on the swing time)
STATES = [  # (theta1, theta2, theta1', theta2'), rad and rad/s: rest, mid-swing, late swing
    (R(55), R(81), 0.0, 0.0),
    (R(100), R(120), 3.0, -2.0),
    (R(160), R(150), 1.5, 4.0),
]


def _eta_by_hand(d, th1, th2, w1, w2):
    """theta1'', theta2'' solved from the brief's eta equations (A25, A30) with dT in eta3, written
    out from the design's fields: consistent I1, A14's I2, no drag."""
    g = GRAVITY
    I1 = 2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb)
    I2 = d.m2 / 3 * (d.Ld**2 + d.Ld * d.Lc + d.Lc**2)
    eta1 = d.m2 * d.Lb**2 + d.m3 * (d.La**2 + d.h**2) + I1
    eta2 = d.m2 * d.Lb * d.Lc * math.cos(th1 - th2)
    eta3 = (d.m2 * d.Lb * d.Lc * w2**2 * math.sin(th1 - th2) - d.m2 * g * d.Lb * math.cos(th1)
            - d.dT * math.cos(th1) + d.m3 * g * d.La * math.cos(th1) - d.m3 * g * d.h * math.sin(th1))
    eta5 = d.m2 * d.Lc**2 + I2
    eta6 = -d.m2 * d.Lb * d.Lc * w1**2 * math.sin(th1 - th2) - d.m2 * g * d.Lc * math.cos(th2)
    return np.linalg.solve([[eta1, eta2], [eta2, eta5]], [-eta3, -eta6])


def test_two_link_with_dT_solves_the_briefs_equations(paper_cfg):
    d = paper_cfg.replace({"design.dT": DT}).design
    c = two_link.coefficients(d)
    for state in STATES:
        assert two_link.accelerations(c, *state) == pytest.approx(_eta_by_hand(d, *state), rel=1e-12)


def test_two_link_with_dT_conserves_energy(paper_cfg):
    d = paper_cfg.replace({"design.dT": DT}).design
    c = two_link.coefficients(d)
    res = two_link.simulate(d, R(55), R(81), until_theta1=R(165))
    e = two_link.energy(c, res.theta1, res.theta2, res.omega1, res.omega2)
    kinetic = e - two_link.energy(c, res.theta1, res.theta2, 0.0, 0.0)
    # relative to the energy the swing exchanges (its largest kinetic energy), not to the arbitrary zero
    assert np.ptp(e) / kinetic.max() < 1e-9


def test_two_link_without_robot_swing_is_equation_1_with_dT(paper_cfg):
    d = paper_cfg.replace({"design.Lc": 0.0, "design.dT": DT}).design
    c = two_link.coefficients(d)
    for th1, th2, w1, w2 in STATES:  # with Lc = 0 the theta1 equation is Eq. (1) with I = eta1, whatever theta2 does
        a1, _ = two_link.accelerations(c, th1, th2, w1, w2)
        assert a1 == pytest.approx(quasi_static.angular_acceleration(d, th1, I=c.eta1), rel=1e-12)
    tl = two_link.simulate(d, R(55), R(81), t_end=0.8)
    qs = quasi_static.simulate(d, R(55), t_end=0.8, I=c.eta1)
    assert np.max(np.abs(tl.theta1 - qs.theta1)) < 1e-8


def _parts_inertia_about_hook(d):
    """The robot's parts' inertia about the hook, arm fully bent (alpha_max), summed part by part.

    The parts are the kit's (docs/make-your-own.md): 310 g/m² card laminated in the fewest layers at most 26 mm
    wide, each layer less a 2.4 mm axle hole. The arm, a plate across the plane (a rod), runs from 4 mm behind the
    axle to the hook, its 3 mm lip folded at the hook; the torso, a plate in the plane, runs from 4 mm above the
    axle down to torso_length; the coins are discs on it. The axle is arm_length from the hook; the torso runs from
    the axle at the interior angle alpha to the arm, so a point s down the torso (s < 0 above the axle) lies at
    arm_length² + s² - 2·arm_length·s·cos(alpha) (squared) from the hook (law of cosines)."""
    L, a = d.arm_length, R(d.alpha_max_deg)
    T = d.torso_length
    grammage, end, lip, widest, hole = 0.310, 4e-3, 3e-3, 26e-3, math.pi * 1.2e-3**2  # kg/m², m, m, m, m²
    m_card = d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass  # the handrail rides on the frame

    def plate(mass, length):  # (kg per m of its length, holes filled in; a hole's card, kg; its width, m)
        card = mass / grammage
        layers = math.ceil(card / (length * widest))
        width = (card / layers + hole) / length
        return grammage * layers * width, grammage * layers * hole, width

    def dist2(s):
        return L**2 + s**2 - 2 * L * s * math.cos(a)

    per_m, hole_arm, _ = plate(d.arm_mass, end + L + lip)
    # the plate from the hook back to END behind the axle, a rod about its end; the lip's card at the hook (0); the
    # hole's card a point at the axle, L from the hook
    arm = per_m * (L + end) * (L + end) ** 2 / 3 - hole_arm * L**2
    per_m, hole_torso, width = plate(m_card, end + T)
    # dist2 averaged over s in [-END, T]: <s> = (T - END)/2, <s²> = (T² - T·END + END²)/3; the plate's width in the
    # plane adds width²/12; the hole's card is a disc at the axle (s = 0)
    card = (per_m * (T + end) * (L**2 + (T**2 - T * end + end**2) / 3 - L * (T - end) * math.cos(a) + width**2 / 12)
            - hole_torso * (dist2(0.0) + 1.2e-3**2 / 2))
    coins = d.coin_mass * (d.coin_radius**2 / 2 + dist2(d.coin_offset))  # discs, parallel axis
    return arm + card + coins


def robot_about_hook_paper(d):
    """A14: a uniform line from Lc to Ld measured from the hook, m2/3·(Ld² + Ld·Lc + Lc²)."""
    return d.m2 / 3 * (d.Ld**2 + d.Ld * d.Lc + d.Lc**2)


def test_parts_convention_builds_the_robot_from_its_parts(paper_cfg):
    d = paper_cfg.design
    paper, parts = two_link.coefficients(d, robot="paper"), two_link.coefficients(d, robot="parts")
    assert parts.eta5 == pytest.approx(_parts_inertia_about_hook(d), rel=1e-12)
    assert paper.eta5 == pytest.approx(d.m2 * d.Lc**2 + d.m2 / 3 * (d.Ld**2 + d.Ld * d.Lc + d.Lc**2), rel=1e-12)
    # A14's I2 is already about the hook, so the paper's eta5 counts the distance twice (its own m2·Lc² on top)
    assert paper.eta5 == pytest.approx(d.m2 * d.Lc**2 + robot_about_hook_paper(d), rel=1e-12)
    assert abs(paper.eta5 - parts.eta5) > 0.1 * parts.eta5  # two different robots
    # the handrail moves from the robot to the frame's seat: the same mass at Lb, so eta1 and the drive agree
    assert parts.eta1 == pytest.approx(paper.eta1, rel=1e-12) and parts.drive == pytest.approx(paper.drive, rel=1e-12)
    t_paper = two_link.simulate(d, R(55), R(81), until_theta1=R(165)).t_until
    t_parts = two_link.simulate(d, R(55), R(81), until_theta1=R(165), robot="parts").t_until
    assert abs(t_parts - t_paper) > 1e-3  # measured: 0.641 s (paper), 0.657 s (parts)
    with pytest.raises(ValueError):
        two_link.coefficients(d, robot="toy")


def test_parts_convention_puts_the_handrail_on_the_frame(paper_cfg):
    heavier_handrail = 0.0005  # kg, more than twice the prototype's 0.21 g
    light, heavy = paper_cfg.design, paper_cfg.replace({"design.handrail_mass": heavier_handrail}).design
    a, b = two_link.coefficients(light, robot="parts"), two_link.coefficients(heavy, robot="parts")
    moved = heavy.handrail_mass - light.handrail_mass  # taken from the torso card, put on the seat
    assert b.eta1 == pytest.approx(a.eta1, rel=1e-12)  # still at Lb, on the frame instead of the robot
    assert b.m2gLc < a.m2gLc  # the robot that swings is lighter
    assert (a.m2gLc / a.Lc - b.m2gLc / b.Lc) / GRAVITY == pytest.approx(moved, rel=1e-9)


def test_dT_speeds_the_swing_by_a_few_percent(paper_cfg):
    plain, driven = paper_cfg.design, paper_cfg.replace({"design.dT": DT}).design
    t0 = two_link.simulate(plain, R(55), R(81), until_theta1=R(150)).t_until
    t1 = two_link.simulate(driven, R(55), R(81), until_theta1=R(150)).t_until
    assert t1 < t0 and (t0 - t1) / t0 > 0.01  # measured: 0.570 -> 0.540 s, 5.2 %
    batch = two_link.time_to_angle_batch([plain, driven], R(55), R(81), R(150))
    assert batch == pytest.approx([t0, t1], abs=1e-5)  # the fast path carries dT too
