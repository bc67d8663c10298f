"""``aero-env calibrate``: recovery from a noisy video trace, targets, swing metrics, bad input, determinism.

Self-consistent by construction: every reference is made from a run of the current physics
(the prototype at a known counterbalance mass), so the tests hold whatever numbers the physics
gives, as long as the prototype's swing 1 ends in a slip-off.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from aero_env import cli, simulation
from aero_env.calibration import scoring
from aero_env.calibration.fit import GRID_MIN, FitKey, search_1d
from aero_env.calibration.measured import MeasuredSwing
from aero_env.calibration.swing_metrics import (METRICS, SwingMissing, find_swing, rising_crossing, swing_metrics,
                                                swing_trace)
from aero_env.calibration.targets import parse_targets
from aero_env.config import load_config
from aero_env.results import SimResult, Swing

from .conftest import PAPER, ROOT

SWING = 1  # the first swing entered from a flight, the one the paper measures
SCENE = ["--set", "scene.frames=3"]  # frames 0..2: swing 1 and its flight, a third of the full row
SCENE_OVERRIDES = {"scene.frames": 3}
TRUE_M3 = 0.0070  # kg: the "measured" machine, off the prototype's 0.0072
# kg: the box searched. Its centre (7.2 g) is 0.2 g from the truth and its 7-point grid's nearest point 0.2 g, so
# neither the centre nor the grid alone lands within the tolerance; the golden sections must refine between points
FIT_RANGE = (0.0058, 0.0086)
M3_TOLERANCE = 5e-5  # kg: the fit must land within 0.05 g (0.7 %) of the truth; measured 0.006 g off
RECOVERY_TRIALS = 14  # grid of 7 + 7 golden sections
VIDEO_FPS = 30.0  # a phone video
NOISE_DEG = 0.5  # Gaussian noise of a hand-clicked angle
NOISE_SEED = 0
UNIT_TOLERANCE = {"deg": 1.0, "s": 0.01, "rad/s": 0.1}  # per-unit tolerances of the self-made targets


@pytest.fixture(scope="module")
def truth_run():
    run = simulation.simulate(load_config(PAPER, {**SCENE_OVERRIDES, "design.m3": TRUE_M3}), trace=True)
    try:
        find_swing(run, SWING)
    except SwingMissing as exc:
        pytest.fail(f"precondition: the prototype at design.m3 = {TRUE_M3} must slip off swing {SWING} to be filmed: "
                    f"{exc}")
    return run


def video_csv(path, run, with_theta2=True):
    """Swing 1 as a video would give it: 30 fps from the catch to the slip-off, degrees, with noise."""
    sw = swing_trace(run, SWING)
    t = np.arange(0.0, sw.swing.swing_duration, 1.0 / VIDEO_FPS)
    rng = np.random.default_rng(NOISE_SEED)
    columns = {"t": t, "theta1_deg": np.interp(t, sw.t, sw.theta1) + rng.normal(0.0, NOISE_DEG, t.size)}
    if with_theta2:
        columns["theta2_deg"] = np.interp(t, sw.t_robot, sw.theta2) + rng.normal(0.0, NOISE_DEG, t.size)
    lines = [",".join(columns)] + [",".join(f"{v:.4f}" for v in row) for row in zip(*columns.values())]
    path.write_text("\n".join(lines) + "\n")
    return path


def run_cli(capsys, *argv):
    rc = cli.main(["calibrate", str(PAPER), *SCENE, *argv])
    out, err = capsys.readouterr()
    return rc, out, err


# ---- recovery ----

def test_recovers_the_counterbalance_mass_from_a_noisy_video_trace(tmp_path, capsys, truth_run):
    csv_path = video_csv(tmp_path / "video.csv", truth_run)
    rc, out, _ = run_cli(capsys, "--trace", str(csv_path), "--fit", f"design.m3={FIT_RANGE[0]}:{FIT_RANGE[1]}",
                         "--trials", str(RECOVERY_TRIALS), "--json")
    doc = json.loads(out)
    assert rc == 0 and doc["miss"] is None and doc["swing"] == SWING
    assert abs(doc["fitted"]["design.m3"] - TRUE_M3) < M3_TOLERANCE
    assert doc["trials"] <= RECOVERY_TRIALS
    # at the fit what is left is the noise: about NOISE_DEG RMS in each angle
    assert doc["rms_theta1_deg"] < 2 * NOISE_DEG and doc["rms_theta2_deg"] < 2 * NOISE_DEG
    assert doc["metrics"]["swing_duration"] == pytest.approx(find_swing(truth_run, SWING).swing_duration, abs=0.01)


def test_grid_and_golden_section_find_a_minimum_between_grid_points():
    minimum, key = 0.2371, FitKey("design.h", 0.0, 1.0)
    seen = []

    def score(values):
        x = values[key.key]
        seen.append(x)
        return (x - minimum) ** 2 + (1.0 if x > 0.9 else 0.0)  # a penalty plateau at one end, as misses make

    search_1d(score, key, trials=30)
    best = min(seen, key=lambda x: (x - minimum) ** 2)
    assert len(seen) <= 30 and abs(best - minimum) < 1e-3 * (key.high - key.low)
    assert seen[:GRID_MIN] == sorted(seen[:GRID_MIN])  # the grid first, from LOW up


# ---- targets ----

def own_targets(metrics: dict):
    """Targets built from a run's own metrics, each with a per-unit tolerance."""
    return parse_targets({"swing": SWING, "targets": {
        name: {"value": v, "tolerance": UNIT_TOLERANCE[METRICS[name][0]]} for name, v in metrics.items()
        if v is not None}})


def test_targets_from_a_runs_own_metrics_score_zero_there_and_worse_far_off(truth_run):
    targets = own_targets(swing_metrics(truth_run, SWING))
    assert len(targets.targets) >= 6
    cfg = load_config(PAPER, SCENE_OVERRIDES)
    at_truth = scoring.evaluate(cfg.with_values({"design.m3": TRUE_M3}), targets, SWING)
    far = scoring.evaluate(cfg.with_values({"design.m3": FIT_RANGE[0]}), targets, SWING)
    assert at_truth.miss is None and at_truth.score < 1e-9  # the same config simulates the same, bit for bit
    assert all(abs(row["z"]) < 1e-9 for row in at_truth.targets)
    assert far.score > 1.0  # more than a tolerance off on average


def test_a_run_without_swing_n_scores_the_finite_miss_penalty():
    slips_at_once = load_config(PAPER, {**SCENE_OVERRIDES, "design.mu_s": 0.05, "design.mu_k": 0.04})
    targets = parse_targets({"targets": {"swing_duration": {"value": 0.62, "tolerance": 0.06}}})
    ev = scoring.evaluate(slips_at_once, targets, SWING)
    assert ev.miss and "swing 1" in ev.miss
    assert ev.score == scoring.MISS_PENALTY and math.isfinite(ev.score)


# ---- swing metrics and the trace score on synthetic data ----

T_CATCH, DURATION, CONFIRM = 1.0, 0.5, 0.01  # s; the runner confirms a catch CONFIRM after the touch
ROW_DT = 0.001


def synthetic_run():
    """Frame 0 until the catch is confirmed, then frame 1 swinging 55 -> 165 deg as a quarter sine."""
    t = np.arange(2000) * ROW_DT  # exact multiples: a row falls on the catch itself
    tp = t - T_CATCH
    on_1 = t >= T_CATCH + CONFIRM
    theta1 = np.where(on_1, 55.0 + 110.0 * np.sin(np.pi * np.clip(tp, 0, DURATION) / (2 * DURATION)), 175.0)
    theta1 = np.where(tp > DURATION, 170.0, theta1)  # the freed frame turns on: not part of the swing
    omega1 = np.radians(110.0) * np.pi / (2 * DURATION) * np.cos(np.pi * tp / (2 * DURATION))
    theta2 = 80.0 + 15.0 * np.sin(2 * np.pi * tp / DURATION)
    alpha = 60.0 + 120.0 * tp / DURATION
    trace = dict(t=t, frame=np.where(on_1, 1, 0), theta1=np.radians(theta1), theta2=np.radians(theta2),
                 alpha=np.radians(alpha), omega1=omega1, omega2=np.zeros_like(t), alpha_rate=np.zeros_like(t),
                 contact=np.zeros_like(t), energy=np.zeros_like(t))
    swings = [Swing(0, 0.0, 55.0, 81.0, 0.9, 160.0, 0.9),
              Swing(1, T_CATCH, 55.0, 80.0, T_CATCH + DURATION, 165.0, DURATION, 120.0, 65.0, 95.0),
              Swing(2, 1.6, 55.0, 80.0)]
    return SimResult(traversals=2, frames=3, outcome="completed", reason="", swings=swings, energy={}, sim_time=2.0,
                     wall_time=0.0, trace=trace)


def test_swing_metrics_match_an_independent_computation_on_a_synthetic_trace():
    run = synthetic_run()
    sw = swing_trace(run, 1)
    assert CONFIRM - 1e-9 <= sw.t[0] < CONFIRM + 2 * ROW_DT and sw.t[-1] <= DURATION + 1e-9
    assert np.all(sw.theta1 < 166.0)  # neither the old frame (175) nor the freed one (170)
    assert sw.t_robot[0] == pytest.approx(0.0, abs=1e-9) and sw.theta2[0] == pytest.approx(80.0, abs=1e-6)
    m = swing_metrics(run, 1)
    quarter = 2 * DURATION / np.pi  # theta1 = 55 + 110 sin(t / quarter)
    t_lowest = quarter * math.asin(35.0 / 110.0)
    t_80 = quarter * math.asin(25.0 / 110.0)
    assert m["t_lowest"] == pytest.approx(t_lowest, abs=1e-6)
    assert m["alpha_at_lowest_deg"] == pytest.approx(60.0 + 120.0 * t_lowest / DURATION, abs=1e-3)
    assert m["omega1_at_80_deg"] == pytest.approx(math.radians(110.0) / quarter * math.cos(t_80 / quarter), rel=1e-4)
    assert m["mean_omega1"] == pytest.approx(math.radians(110.0) / DURATION)
    assert (m["swing_duration"], m["theta1_catch_deg"], m["theta2_catch_deg"], m["theta1_detach_deg"],
            m["theta2_min_deg"], m["theta2_max_deg"]) == (DURATION, 55.0, 80.0, 165.0, 65.0, 95.0)
    assert rising_crossing(sw.t, sw.theta1, 170.0) is None
    with pytest.raises(SwingMissing, match="never slipped off"):
        swing_trace(run, 2)
    with pytest.raises(SwingMissing, match="never reached swing 5"):
        swing_trace(run, 5)


def test_trace_score_holds_the_detach_angle_past_the_simulated_slip_off():
    sw = swing_trace(synthetic_run(), 1)
    late = DURATION + 0.2
    measured = MeasuredSwing(t=np.array([0.1, 0.2, late]), theta1=np.array([0.0, 0.0, 0.0]), theta2=None)
    held = np.interp(DURATION, sw.t, sw.theta1)
    expected = [np.interp(0.1, sw.t, sw.theta1), np.interp(0.2, sw.t, sw.theta1), held]
    got = scoring.score_measured(sw, measured)
    assert got["score"] == pytest.approx(math.sqrt(np.mean(np.square(expected))))
    assert got["rms_theta2_deg"] is None


# ---- bad input: one line, exit 2, no simulation ----

def _targets_file(tmp_path, body: str):
    p = tmp_path / "t.yaml"
    p.write_text(body)
    return ["--targets", str(p), "--fit", "design.m3=0.006:0.008"]


def _csv_file(tmp_path, header: str):
    p = tmp_path / "m.csv"
    p.write_text(header + "\n0,55\n0.1,70\n0.2,90\n")
    return ["--trace", str(p), "--fit", "design.m3=0.006:0.008"]


GOOD_TARGETS = "targets:\n  swing_duration: {value: 0.62, tolerance: 0.06}\n"
BAD_INPUTS = {
    "unknown metric": (lambda tp: _targets_file(tp, "targets:\n  theta9_deg: {value: 1, tolerance: 1}\n"),
                       ["theta9_deg", "unknown metric", "swing_duration, theta1_catch_deg"]),
    "missing tolerance": (lambda tp: _targets_file(tp, "targets:\n  swing_duration: {value: 0.62}\n"),
                          ["swing_duration.tolerance", "missing"]),
    "tolerance <= 0": (lambda tp: _targets_file(tp, "targets:\n  swing_duration: {value: 0.62, tolerance: 0}\n"),
                       ["tolerance = 0.0", "> 0"]),
    "bad --fit syntax": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--fit", "design.h=0.01"],
                         ["design.h=0.01", "KEY=LOW:HIGH"]),
    "LOW >= HIGH": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--fit", "design.h=0.02:0.01"],
                    ["design.h=0.02:0.01", "must be below"]),
    "key out of range": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--fit", "design.La=-0.1:0.05"],
                         ["design.La", "-0.1", "out of range", "(0.0, 1.0] m"]),
    "not a real field": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--fit", "scene.frames=2:5"],
                         ["scene.frames", "not a real-valued"]),
    "box corner invalid": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--fit", "design.mu_s=0.3:0.6"],
                           ["box corner", "design.mu_s=0.3", "mu_k"]),
    "missing CSV column": (lambda tp: _csv_file(tp, "t,theta2_deg"), ["missing column 'theta1_deg'", "required: t"]),
    "--out folder missing": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--out", str(tp / "no" / "c.yaml")],
                             ["--out", "does not exist"]),
    "--plot folder missing": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--plot", str(tp / "no" / "p.png")],
                              ["--plot", "does not exist"]),
    "swing past the row": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--swing", "2"], ["--swing 2", "[0, 1]"]),
    "trials not a number": (lambda tp: _targets_file(tp, GOOD_TARGETS) + ["--trials", "many"], ["--trials", "many"]),
    "no reference": (lambda tp: ["--fit", "design.m3=0.006:0.008"], ["exactly one of --trace", "--targets"]),
}


@pytest.mark.parametrize("case", list(BAD_INPUTS))
def test_bad_input_is_one_line_exit_2_before_any_simulation(case, tmp_path, capsys, monkeypatch):
    def no_simulation(*a, **k):
        raise AssertionError("simulated despite bad input")

    monkeypatch.setattr(simulation, "simulate", no_simulation)
    argv, words = BAD_INPUTS[case]
    rc, out, err = run_cli(capsys, *argv(tmp_path))
    assert rc == 2 and out == ""
    assert len(err.strip().splitlines()) == 1, err
    for word in words:
        assert word in err, (word, err)


# ---- determinism, the shipped targets file, --out and --plot ----

def _calibrate_json(*extra):
    cmd = [sys.executable, "-m", "aero_env.cli", "calibrate", str(PAPER), *SCENE, "--targets",
           str(ROOT / "configs" / "paper_targets.yaml"), "--fit", "design.m3=0.0064:0.0078",
           "--fit", "design.mu_k=0.35:0.5", "--trials", "6", "--seed", "3", "--json", *extra]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    assert done.returncode in (0, 1), done.stderr  # 1: no trial had a usable swing (a miss), still reported
    doc = json.loads(done.stdout)
    doc.pop("wall_time")
    return doc


@pytest.mark.slow
def test_same_seed_gives_identical_json_in_two_processes(tmp_path):
    out, plot = tmp_path / "calibrated.yaml", tmp_path / "fit.png"
    a = _calibrate_json("--out", str(out), "--plot", str(plot))
    b = _calibrate_json()
    assert a == b  # json round-trips floats exactly: bit for bit
    assert a["method"] == "cmaes" and a["trials"] == 6 and set(a["fitted"]) == {"design.m3", "design.mu_k"}
    assert set(a["targets"]) == {"swing_duration", "theta1_catch_deg", "theta2_catch_deg", "theta2_mid_deg",
                                 "theta1_detach_deg", "t_lowest", "alpha_at_lowest_deg", "omega1_dip",
                                 "theta1_at_dip_deg"}
    if a["miss"] is None:
        back = load_config(out)
        assert {k: back.value(k) for k in a["fitted"]} == a["fitted"]
    else:  # no trial had a usable swing 1: nothing calibrated to write
        assert not out.exists()
    assert plot.stat().st_size > 10_000


def test_calibrate_reads_the_trace_that_simulate_writes(tmp_path, capsys):
    # the whole run simulate --trace writes (t_s from the run's start, degrees, a contact column) is a measured swing
    # to calibrate: the swing's own rows, timed from its catch; at the machine that wrote it the fit is exact
    trace = tmp_path / "run.csv"
    assert cli.main(["simulate", str(PAPER), *SCENE, "--set", f"design.m3={TRUE_M3}", "--trace", str(trace)]) == 0
    capsys.readouterr()
    rc, out, err = run_cli(capsys, "--trace", str(trace), "--swing", str(SWING),
                           "--fit", f"design.m3={FIT_RANGE[0]}:{FIT_RANGE[1]}", "--trials", str(RECOVERY_TRIALS),
                           "--json")
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["miss"] is None and doc["swing"] == SWING
    assert abs(doc["fitted"]["design.m3"] - TRUE_M3) < M3_TOLERANCE
    assert doc["rms_theta1_deg"] < NOISE_DEG and doc["rms_theta2_deg"] < NOISE_DEG  # degrees read as degrees
