"""The three-model comparison on the prototype (from rest, and the flight-entered swing the paper
measures, point by point against its words) and a small domain map."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from aero_env import compare
from aero_env.models import two_link
from aero_env.simulation import simulate

from .conftest import PAPER
from .test_models import signs_in

# The analytical models leave out the skewer's and the axle's dry friction, as the paper's do; the
# models are compared with the world built without them (the fitted friction's effect is tested below).
FRICTIONLESS = {"design.pivot_friction": 0.0, "design.axle_friction": 0.0}


@pytest.fixture(scope="module")
def summary(summary_and_runs):
    return summary_and_runs[0]


def test_the_fitted_skewer_friction_slows_the_mbd_swing(paper_cfg, summary):
    with_friction = compare.compare(paper_cfg, swing=0)[0]["models"]["mbd"]["time_to_detach_angle"]
    assert with_friction > 1.1 * summary["models"]["mbd"]["time_to_detach_angle"]


def test_all_three_models_reach_the_mbd_detach_angle_in_about_the_same_time(summary):
    m = summary["models"]
    mbd = m["mbd"]["time_to_detach_angle"]
    assert 150.0 <= summary["detach_angle_deg"] <= 175.0
    assert m["two_link"]["time_to_detach_angle"] == pytest.approx(mbd, rel=0.03)  # measured 0.7%
    assert m["quasi_static"]["time_to_detach_angle"] == pytest.approx(mbd, rel=0.10)  # measured 5.8%
    # the quasi-static model, without the robot's swing, gets there first
    assert m["quasi_static"]["time_to_detach_angle"] < m["two_link"]["time_to_detach_angle"]


def _turns(crossings: list[float], graze_deg: float = 0.5) -> list[float]:
    """The sign changes less the grazes: a pair of crossings closer than ``graze_deg`` is theta1'' touching zero
    and returning, not a change of sign."""
    out: list[float] = []
    for x in crossings:
        if out and x - out[-1] < graze_deg:
            out.pop()
        else:
            out.append(x)
    return out


def test_theta1_acceleration_sign_changes(summary):
    m = summary["models"]
    assert m["quasi_static"]["alpha1_sign_changes_deg"] == [pytest.approx(125.3, abs=0.5)]
    # The Table 1 robot's own swing makes theta1'' go +, -, + between 55 and 125 deg (the paper's Fig. 43),
    # back to + near 115 deg, in the two-link model of the built robot and in the MBD alike (measured with the
    # kit's parts: 87.3, 116.6 and 89.6, 117.6 deg); the quasi-static model, without the robot's swing, turns
    # once, at 125 deg. In the MBD theta1'' first grazes zero at 87.2 deg (two crossings 0.02 deg apart) before
    # it turns at 89.6 deg: a graze is not a turn.
    tl, mbd = (_turns(m[name]["alpha1_sign_changes_deg"]) for name in ("two_link", "mbd"))
    for turns in (tl, mbd):
        assert len(turns) >= 2 and 55.0 < turns[0] < turns[1] < 125.0 and turns[1] == pytest.approx(115.0, abs=10.0)
    assert tl[:2] == pytest.approx(mbd[:2], abs=3.0)
    assert _turns([87.24, 87.26, 89.64, 117.62]) == [89.64, 117.62]  # the graze rule on the MBD's crossings


@pytest.fixture(scope="module")
def summary_and_runs(paper_cfg):
    return compare.compare(paper_cfg.replace(FRICTIONLESS), swing=0)


def test_drag_slows_every_model_by_what_the_drag_law_gives(summary_and_runs, paper_cfg):
    summary, runs = summary_and_runs
    m = summary["models"]
    delay = {name: x["time_to_detach_angle_with_drag"] - x["time_to_detach_angle"] for name, x in m.items()}
    # drag delays every model's arrival at the detach angle: the two-link model by 0.57 ms, the pymunk world
    # by whole 0.5 ms steps (measured 0: the Table 1 robot is short, its drag small), within a step and a half
    # of the two-link model's delay
    assert 5e-4 < delay["two_link"] < 5e-3 and 0 < delay["quasi_static"] < delay["two_link"]
    assert delay["mbd"] >= 0.0 and abs(delay["mbd"] - delay["two_link"]) <= 1.5 * paper_cfg.sim.dt
    # the quasi-static model feels only the frame's drag: at each theta1 its theta1'' drops by
    # (1/8)·rho·Cd·A·(La^4 + Lb^4)·theta1'^2 / I, here from the config and the dragged run's own speed
    d = paper_cfg.design
    k = d.rho * d.Cd * d.frame_width * (d.La**4 + d.Lb**4) / 8
    inertia = (2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb) + d.m2 / 3 * (d.Ld**2 + d.Ld * d.Lc + d.Lc**2)
               + d.m3 * (d.La**2 + d.h**2))
    dragged = runs["quasi_static"][1]
    expected = k * np.max(dragged.omega1**2) / inertia
    assert m["quasi_static"]["drag_alpha1_change"]["max_change"] == pytest.approx(expected, rel=0.02)
    for name in ("two_link", "quasi_static"):  # a small change (the paper: no noticeable difference)
        assert 1e-4 < m[name]["drag_alpha1_change"]["relative"] < 0.02, name  # measured 0.40 %, 0.075 %


def test_domain_map_marks_where_models_hold(paper_cfg, tmp_path):
    dm = compare.domain_map(paper_cfg.replace(FRICTIONLESS), masses=[0.006, 0.03], ratios=[0.6, 0.9])
    pts = {(round(p["m2"], 3), p["ratio"]): p for p in dm["points"]}
    assert len(pts) == 4
    for m2 in (0.006, 0.03):
        # a counterbalance with too little moment cannot lift the robot: nothing swings to detach
        # (stalled, or swung past its balance angle and back with the hook on: no_detach)
        assert pts[(m2, 0.6)]["mbd_outcome"] in ("stalled", "no_detach") and not pts[(m2, 0.6)]["mbd_traverses"]
        # near balance the MBD robot traverses and the two-link model is within 10%
        heavy_ok = pts[(m2, 0.9)]
        # (the 30 g robot, all its extra mass in the torso card, no longer completes the transfer since the
        # robot is built from parts: missed_catch; the swing the models compare still happens)
        assert heavy_ok["mbd_traverses"] or m2 == 0.03
        assert heavy_ok["two_link_within"]
        assert heavy_ok["two_link_error"] < heavy_ok["quasi_static_error"]
    out = tmp_path / "map.png"
    compare.plot_domain_map(dm, out, prototype=(0.00771, 0.87))
    assert out.stat().st_size > 10_000


def test_compare_cli_json(tmp_path):
    plot = tmp_path / "c.png"
    out = subprocess.run([sys.executable, "-m", "aero_env.cli", "compare", str(PAPER), "--json", "--plot", str(plot)],
                         check=True, capture_output=True, text=True).stdout
    doc = json.loads(out)
    assert set(doc["models"]) == {"mbd", "two_link", "quasi_static"}
    for m in doc["models"].values():
        assert {"time_to_detach_angle", "alpha1_sign_changes_deg", "drag_alpha1_change"} <= set(m)
    assert plot.stat().st_size > 10_000


# Where the built robot's two-link model (robot="parts", from rest, no friction) has theta1'' and theta2'' of
# opposite sign, window by window (measured on the model: + - from 56.5 to 79.5 deg, - + from 86.7 to 114.8,
# + - from 116.2 to 146.2; a share of 0.72 of the swing)
PARTS_SIGN_WINDOWS = [((60, 78), (True, False)), ((90, 112), (False, True)), ((118, 144), (True, False))]


def test_mbd_accelerations_have_opposite_signs_where_the_two_link_models_do(paper_cfg):
    """The paper's finding in the pymunk world (without the skewer's and axle's friction, as the models), window
    by window as in the two-link model of the same robot; the paper's own convention's windows (test_models,
    SIGN_WINDOWS) belong to its A14 line robot, not the one the world builds."""
    d = paper_cfg.design
    model = two_link.simulate(d, math.radians(55), math.radians(81), until_theta1=math.radians(165), robot="parts")
    first = compare.mbd_swing(paper_cfg.replace(FRICTIONLESS), 0)
    assert first.outcome == "completed"
    for (lo, hi), (a1_up, a2_up) in PARTS_SIGN_WINDOWS:
        assert signs_in(model, lo, hi) == (float(a1_up), float(a2_up)), (lo, hi)
        up1, up2 = signs_in(first.run, lo, hi)  # the world's accelerations are differenced from its trace
        assert abs(up1 - a1_up) <= 0.05 and abs(up2 - a2_up) <= 0.05, (lo, hi, up1, up2)  # measured: all samples
    share = np.mean(first.run.alpha1 * first.run.alpha2 < 0)
    assert share == pytest.approx(0.7, abs=0.2)  # the paper's share (measured 0.71)


@pytest.fixture(scope="module")
def flight_entered(paper_cfg):
    return compare.compare(paper_cfg)


def test_the_flight_entered_swing_starts_where_the_catch_has_held(paper_cfg, flight_entered):
    summary, runs = flight_entered
    assert summary["swing"] == 1
    sim = simulate(paper_cfg.replace({"scene.frames": 3}))
    caught = sim.swings[1]
    st = summary["start"]
    # the models start once the catch has held (sim.contact_hold after the touch), on the MBD's clock
    assert st["t"] == pytest.approx(paper_cfg.sim.contact_hold, abs=2 * paper_cfg.sim.dt)
    assert st["theta1_deg"] == pytest.approx(caught.theta1_catch_deg, abs=0.5)
    # caught from a flight: the robot arrives swinging, unlike the start from rest
    assert abs(st["omega2"]) > 0.5
    for name in ("two_link", "quasi_static"):
        run = runs[name][0]
        assert run.t[0] == pytest.approx(st["t"]) and math.degrees(run.theta1[0]) == pytest.approx(st["theta1_deg"])
    assert summary["models"]["mbd"]["time_to_detach_angle"] == pytest.approx(caught.swing_duration, abs=1e-9)


def test_the_paper_points_are_measured_off_the_mbd_swing(flight_entered):
    summary, runs = flight_entered
    points = {p["key"]: p for p in summary["paper_points"]}
    mbd = runs["mbd"][0]
    assert points["swing_duration"]["ours"] == summary["models"]["mbd"]["time_to_detach_angle"]
    assert points["theta2_centre"]["ours"] == pytest.approx(np.degrees((mbd.theta2.min() + mbd.theta2.max()) / 2))
    # the robot is lowest when the frame passes 90 deg: read off the run by hand, between two samples
    th1 = np.degrees(mbd.theta1)
    i = int(np.flatnonzero(th1 >= 90.0)[0])
    assert mbd.t[i - 1] <= points["t_lowest"]["ours"] <= mbd.t[i]
    # the dip is looked for between 65 and 125 deg, not wherever theta1' is lowest (its global minimum
    # falls past 125 deg, where every swing slows against Eq. 1's moment)
    inside = (th1 >= 65.0) & (th1 <= 125.0)
    assert points["theta1_rate_dip"]["ours"] == pytest.approx(mbd.omega1[inside].min())
    assert 65.0 <= points["theta1_rate_dip_at"]["ours"] <= 125.0
    # the catch, the robot's swing about the vertical and the spring's bend agree with the paper's (the
    # duration, the slip-off angle, t_lowest and the dip are measured misses: docs/physics.md)
    assert all(points[k]["holds"] for k in ("theta1_catch", "theta2_catch", "theta2_centre", "alpha_when_lowest"))
    assert points["mean_theta1_rate"]["holds"] is None  # the paper's mean rates contradict its angles: shown only
    for p in points.values():
        if p["tolerance"] is not None:
            assert p["holds"] == (p["ours"] is not None and abs(p["ours"] - p["paper_value"]) <= p["tolerance"])


def test_compare_refuses_a_swing_the_mbd_never_reaches(paper_cfg, capsys):
    from aero_env.cli import main

    assert main(["compare", str(PAPER), "--swing", "1", "--set", "design.m3=0.02"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--swing 1" in err and "never catches frame 1" in err and len(err.splitlines()) == 1
