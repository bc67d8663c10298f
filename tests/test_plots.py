"""The pictures, checked by what they show (issue 36): the GIF's pace, the whole robot in a render, the tune
history's legend clear of the trials, the accuracy plot's labels clear of one another."""

from __future__ import annotations

import itertools
import json

import gymnasium as gym
import numpy as np
from PIL import Image

from aero_env.bench.accuracy import pareto_figure
from aero_env.cli import main
from aero_env.config import load_config
from aero_env.render import Canvas
from agents.tune import TuneResult, history_figure

from .conftest import PAPER


def test_gif_plays_env_render_slowmo_times_slower_than_real_time(tmp_path, capsys):
    gif = tmp_path / "t.gif"
    assert main(["simulate", str(PAPER), "--set", "scene.frames=2", "--json", "--gif", str(gif)]) in (0, None)
    sim_time = json.loads(capsys.readouterr().out)["sim_time"]
    slowmo = load_config(PAPER).env.render_slowmo
    anim = Image.open(gif)
    durations = []
    for i in range(anim.n_frames):
        anim.seek(i)
        durations.append(anim.info["duration"])  # ms, as read back from the file's centiseconds
    # each frame stands for one pose interval; the last frame is the run's final moment (its last interval may be
    # shorter), so the playing time up to it is the simulated time x slowmo, to within one frame
    played = sum(durations[:-1]) / 1000.0
    assert abs(played - slowmo * sim_time) <= durations[-1] / 1000.0, (played / sim_time, slowmo)


def test_render_after_a_step_shows_the_whole_robot():
    # the case: a 3-frame row, where fitting the view to the width alone cut the torso off at the bottom
    env = gym.make("aero_env/AerialAcrobat-v0", render_mode="rgb_array", **{"scene.frames": 3})
    for action in (env.unwrapped.action_for(), -np.ones(5, np.float32)):  # a completed row and a failure
        env.reset(seed=0)
        env.step(action)
        run = env.unwrapped.last_run
        img = env.render()
        h, w, _ = img.shape
        # every pose's robot (torso ends, the coins, the hook) maps inside the image, with room for the torso
        # strip's half width and the coins' radius
        canvas = Canvas(run.geometry, w, h)
        g = run.geometry
        for pose in run.poses:
            _t, _angles, top, angle, _arm = pose
            c, s = np.cos(angle), np.sin(angle)
            bottom = (top[0] + s * g["torso_length"], top[1] - c * g["torso_length"])
            for p in (top, bottom, canvas.hook(pose)):
                x, y = canvas.px(p)
                assert 5 <= x <= w - 5 and 5 <= y <= h - 5, (pose[0], x, y)
        # and in the picture: the torso strip is drawn, and none of it on the image's edge rows
        torso = np.all(img == (30, 90, 200), axis=-1)
        assert torso.any() and not torso[-1].any() and not torso[0].any()


def _tune_result(history) -> TuneResult:
    return TuneResult(study="fake", storage="memory", sampler="cmaes", trials=len(history), trials_run=len(history),
                      best_reward=7.0, best_design={}, best_action=[], best_trial=0, best_score={},
                      first_full_row_trial=4, full_row=7, wall_time=1.0, history=history)


def _display_points(artist, per_segment: int = 20) -> np.ndarray:
    """An artist's data as display points: a scatter's markers, a line's vertices and points along its segments."""
    if hasattr(artist, "get_offsets"):
        return artist.get_offset_transform().transform(artist.get_offsets())
    xy = artist.get_transform().transform(artist.get_xydata())
    t = np.linspace(0.0, 1.0, per_segment)[:, None]
    return np.vstack([a + t * (b - a) for a, b in zip(xy[:-1], xy[1:])] + [xy])


def test_tune_history_legend_covers_no_trial():
    # a 40-trial run as in the issue: the whole row at a few trials, 0 to 2 traversals at the rest, the late
    # ones included (where a legend in the lower right sat)
    rewards = [7, 0, 0, 0, 7, 0, 1, 1, 0, 0, 0, 0, 0, 1, 7, 0, 0, 0, 0, 0, 7, 0, 0, 0, 0, 1, 1, 0, 1, 0, 1, 0, 0, 2,
               0, 1, 1, 0, 0, 0]
    fig = history_figure(_tune_result(list(enumerate(map(float, rewards)))))
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent().padded(3)  # and the markers' radius
    artists = [*ax.collections, *ax.lines]
    assert len(artists) == 3  # the trials, the best so far, the whole row
    for artist in artists:
        pts = _display_points(artist)
        inside = (pts[:, 0] >= legend.x0) & (pts[:, 0] <= legend.x1) & (pts[:, 1] >= legend.y0) & (pts[:, 1] <= legend.y1)
        assert not inside.any(), (artist.get_label(), pts[inside][:3])


def test_accuracy_plot_labels_do_not_overlap():
    # docs/accuracy.png's numbers (mbd and mbd-fine a few ms apart on the 100 % row), and a made-up rung near mbd at
    # 99 %, whose label must step past the ones moved down to it
    points = {"reduced": (7.7e-5, 0.925), "mbd": (0.0128, 1.0), "mbd-fine": (0.0215, 1.0),
              "reference": (0.21, 1.0), "reference/2": (0.78, 1.0), "mbd-near": (0.014, 0.99)}
    report = dict(default="mbd", designs=40, frames=8,
                  fidelities=[dict(name=n, wall_per_design=x, outcome_agreement=a) for n, (x, a) in points.items()])
    fig = pareto_figure(report)
    fig.canvas.draw()
    texts = fig.axes[0].texts
    assert sorted(t.get_text() for t in texts) == sorted(["mbd (default)", *(n for n in points if n != "mbd")])
    boxes = {t.get_text(): t.get_window_extent() for t in texts}
    for (a, box_a), (b, box_b) in itertools.combinations(boxes.items(), 2):
        assert not box_a.overlaps(box_b), (a, b)


def test_a_classroom_gif_names_the_parts_beside_them_and_says_its_slow_motion(tmp_path):
    """--labels writes the parts' names next to frame 0's parts and the robot, and the slow-motion factor in the
    caption: the labelled frame differs from the plain one near each part it names and in the caption's line."""
    from aero_env.render import iter_frames, pose_interval
    from aero_env.simulation import simulate

    cfg = load_config(PAPER).replace({"scene.frames": 2})
    run = simulate(cfg, poses_every=pose_interval(cfg.env.render_slowmo))
    pose = run.poses[len(run.poses) // 3]
    canvas = Canvas(run.geometry, 720, 300)
    plain, labelled = canvas.draw(pose), canvas.draw(pose, "slow motion x4", labels=True)
    changed = np.any(plain != labelled, axis=-1)
    _t, angles, torso_pos, torso_angle, _arm = pose
    g = run.geometry
    (ax, ay), th = g["axes"][0], angles[0]
    rot = lambda v: (ax + v[0] * np.cos(th) - v[1] * np.sin(th), ay + v[0] * np.sin(th) + v[1] * np.cos(th))  # noqa
    bottom = (torso_pos[0] + np.sin(torso_angle) * g["torso_length"],
              torso_pos[1] - np.cos(torso_angle) * g["torso_length"])
    parts = [rot((0.5 * g["La"], 0.0)), rot((g["La"], g["h"])), rot((-g["Lb"], 0.0)), (ax, ay), torso_pos, bottom]
    for p in parts:  # some text within 80 px of each named part
        x, y = (int(v) for v in canvas.px(p))
        assert changed[max(0, y - 30):y + 30, max(0, x - 80):x + 120].any(), p
    assert changed[:18].any()  # the caption's line says the slow motion
    assert main(["simulate", str(PAPER), "--set", "scene.frames=2", "--gif", str(tmp_path / "c.gif"), "--labels"]) \
        in (0, None)
    assert len(list(iter_frames(run, labels=True))) == len(run.poses)


def test_the_assembly_pictures_show_the_stand_alone_then_the_robot_on_it(tmp_path):
    """scripts/draw_assembly.py: picture 1 is the stand and its frames with no robot drawn, pictures 2-4 the robot
    (its torso's colour) hooked, flying and caught."""
    import subprocess
    import sys

    from .conftest import ROOT

    subprocess.run([sys.executable, str(ROOT / "scripts/draw_assembly.py"), str(PAPER), str(tmp_path / "a")],
                   check=True, capture_output=True)
    torso = [np.all(np.asarray(Image.open(tmp_path / f"a_{i}.png").convert("RGB")) == (30, 90, 200), axis=-1).any()
             for i in (1, 2, 3, 4)]
    assert torso == [False, True, True, True]
