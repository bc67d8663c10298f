"""The analytical models: Eq. (1), the two-link model, their agreement, and the pymunk pinned-hook check."""

import math

import numpy as np
import pytest

from aero_env.models import quasi_static, two_link
from aero_env.physics import simulate

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


def test_accelerations_have_opposite_signs_over_part_of_the_swing(paper_cfg):
    res = two_link.simulate(paper_cfg.design, R(55), R(81), until_theta1=R(165))
    opposite = np.sign(res.alpha1) * np.sign(res.alpha2) < 0
    assert 0.1 < opposite.mean() < 0.9  # the paper's key finding: the links work against each other


def test_drag_changes_alpha1_by_a_few_percent_at_most(paper_cfg):
    d = paper_cfg.design
    a = two_link.simulate(d, R(55), R(81), until_theta1=R(165))
    b = two_link.simulate(d, R(55), R(81), until_theta1=R(165), drag=True)
    grid = np.radians(np.linspace(56, 164, 300))
    diff = np.interp(grid, b.theta1, b.alpha1) - np.interp(grid, a.theta1, a.alpha1)
    assert np.abs(diff).max() / np.abs(a.alpha1).max() < 0.05


def test_batch_fast_path_matches_the_integrator(paper_cfg):
    designs = [paper_cfg.replace({"design.m2": m2}).design for m2 in (0.00771, 0.0085, 0.009, 0.0095)]
    batch = two_link.time_to_angle_batch(designs, R(55), R(81), R(150))
    for d, tb in zip(designs, batch):
        assert tb == pytest.approx(two_link.simulate(d, R(55), R(81), until_theta1=R(150)).t_until, abs=1e-5)
    stuck = paper_cfg.replace({"design.m2": 0.0055}).design  # robot lighter than the counterbalance's moment
    assert np.isnan(two_link.time_to_angle_batch([stuck], R(55), R(81), R(150), t_end=1.0)[0])


def test_pymunk_pinned_hook_scene_agrees_with_two_link(paper_cfg):
    # The article's Appendix B: with the hook a pin and no spring the MBD reduces to the two-link model.
    cfg = paper_cfg.replace({"scene.effects.hook": "pin", "sim.trace_every": 1, "scene.frames": 2})
    r = simulate(cfg, trace=True)
    assert r.outcome == "no_detach" and "pinned" in r.reason
    t, th1, th2 = r.trace["t"], r.trace["theta1"], r.trace["theta2"]
    i = int(np.argmax(th1 >= R(165)))
    t165 = t[i - 1] + (R(165) - th1[i - 1]) / (th1[i] - th1[i - 1]) * (t[i] - t[i - 1])
    ref = two_link.simulate(cfg.design, R(55), R(81), until_theta1=R(165))
    assert t165 == pytest.approx(ref.t_until, rel=0.01)  # measured: 0.07% at dt = 0.5 ms
    rms = np.sqrt(np.mean((th2[:i] - np.interp(t[:i], ref.t, ref.theta2)) ** 2))
    assert math.degrees(rms) < 1.0  # measured: 0.011 deg
