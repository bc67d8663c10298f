"""Pictures of a run: the angle plot (the paper's Fig. 40) and an animation of the machine.

Reads a :class:`~aero_env.physics.SimResult` (SI units); never touches pymunk.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Iterator

import numpy as np

from .files import save_figure, text_writer, write_atomically
from .physics.run import TRACE_COLUMNS, SimResult


# simulate --trace's columns: each trace column's header, with its unit, and how its SI value is written. Angles in
# degrees, as every table prints them and as `aero-env calibrate --trace` reads a measured swing.
_SI, _DEG = float, math.degrees
TRACE_CSV_COLUMNS = {"t": ("t_s", _SI), "frame": ("frame", int), "theta1": ("theta1_deg", _DEG),
                     "theta2": ("theta2_deg", _DEG), "alpha": ("alpha_deg", _DEG), "omega1": ("omega1_deg_s", _DEG),
                     "omega2": ("omega2_deg_s", _DEG), "alpha_rate": ("alpha_rate_deg_s", _DEG),
                     "contact": ("contact", int), "energy": ("energy_J", _SI)}


def write_trace_csv(result: SimResult, path: str | Path) -> None:
    """Time (s), active frame, theta1, theta2, alpha (deg), their rates (deg/s), contact (frame index or -1), energy
    (J): the headers carry the units (:data:`TRACE_CSV_COLUMNS`)."""
    if result.trace is None:
        raise ValueError("this result has no trace: simulate(..., trace=True)")
    cols = [result.trace[c] for c in TRACE_COLUMNS]
    writes = [TRACE_CSV_COLUMNS[c][1] for c in TRACE_COLUMNS]

    def rows(fh) -> None:
        w = csv.writer(fh)
        w.writerow([TRACE_CSV_COLUMNS[c][0] for c in TRACE_COLUMNS])
        for row in zip(*cols):
            w.writerow([int(v) if f is int else repr(f(float(v))) for f, v in zip(writes, row)])

    write_atomically(path, text_writer(rows), "trace file")


def plot_angles(result: SimResult, path: str | Path, title: str = "") -> None:
    """theta1 and theta2 (and the arm angle alpha) against time, with catches and detaches marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tr = result.trace
    if tr is None:
        raise ValueError("this result has no trace: simulate(..., trace=True)")
    t = tr["t"]
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, gridspec_kw=dict(height_ratios=[3, 1.3]))
    ax.plot(t, np.degrees(tr["theta1"]), label=r"$\theta_1$ (frame the robot is on)", color="tab:blue")
    ax.plot(t, np.degrees(tr["theta2"]), label=r"$\theta_2$ (robot line)", color="tab:orange")
    for s in result.swings:
        ax.axvline(s.t_catch, color="tab:green", lw=0.8, ls=":")
        if s.t_detach is not None:
            ax.axvline(s.t_detach, color="tab:red", lw=0.8, ls="--")
    ax.plot([], [], color="tab:green", ls=":", label="catch")
    ax.plot([], [], color="tab:red", ls="--", label="detach")
    ax.set_ylabel("angle [deg]")
    # the legend sits between the title and the axes, where it covers no curve
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize=8, ncol=4, frameon=False)
    ax.grid(alpha=0.3)
    fig.suptitle(title or f"{result.outcome}: {result.traversals}/{result.frames - 1} traversals")
    ax2.plot(t, np.degrees(tr["alpha"]), color="tab:purple")
    ax2.set_ylabel(r"arm angle $\alpha$ [deg]")
    ax2.set_xlabel("time [s]")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    try:
        save_figure(fig, path, dpi=110)
    finally:
        plt.close(fig)


# 25 fps, not 30: a GIF stores each frame's delay in whole centiseconds, so 30 fps's 33.3 ms became 30 ms and every
# animation played 3.5x slow, not 4x (with the runner's rounding of 1/120 s to 17 steps of 0.5 ms). A 40 ms frame is
# exact, and the default pose interval, 1/(25 x 4) = 10 ms, is a whole number of runner steps at every fidelity.
ANIMATION_FPS = 25


def pose_interval(slowmo: float, fps: float = ANIMATION_FPS) -> float:
    """Simulated seconds between recorded poses for an animation at ``fps`` played ``slowmo`` times slower."""
    return 1.0 / (fps * slowmo)


def _rot(v, a):
    c, s = math.cos(a), math.sin(a)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _add(a, b):
    return (a[0] + b[0], a[1] + b[1])


class Canvas:
    """Draws the machine (SI geometry from :meth:`World.geometry`) into fixed-size RGB images."""

    BACKGROUND = (250, 250, 247)
    MARGIN_PX, CAPTION_PX = 6, 18  # room for the dots drawn around points (radius 5 px); the caption's line on top

    def __init__(self, geometry: dict, width: int = 720, height: int = 300):
        self.g, self.width, self.height = geometry, width, height
        g, axes = geometry, geometry["axes"]
        xmin, xmax = axes[0][0] - 0.09, axes[-1][0] + 0.09
        # The view holds every pose, not only the axes' line: fitting the width alone made a short row (3 frames)
        # so large that the robot hanging from the last frame fell off the bottom edge. A frame reaches `reach`
        # from its axis; the robot hangs at most arm + torso below a hook that a frame holds, and never below the floor.
        reach = max(g["Lb"], math.hypot(g["La"], g["h"]))
        ys = [y for _x, y in axes]
        (fxa, fya), (fxb, fyb) = g["floor"]
        floor_y = min(fya + (x - fxa) * (fyb - fya) / (fxb - fxa) for x in (xmin, xmax))  # under the view's ends
        ymin = min(min(ys) - reach - g["arm_length"] - g["torso_length"], floor_y)
        ymax = max(ys) + reach
        m = self.MARGIN_PX
        self.scale = min((width - 2 * m) / (xmax - xmin), (height - 2 * m - self.CAPTION_PX) / (ymax - ymin))
        # the view's box centred in the image, below the caption
        cx, cy = (xmin + xmax) / 2.0, (ymin + ymax) / 2.0
        self.origin = (cx - width / 2.0 / self.scale, cy + (height + self.CAPTION_PX) / 2.0 / self.scale)

    def px(self, p):
        return ((p[0] - self.origin[0]) * self.scale, (self.origin[1] - p[1]) * self.scale)

    def hook(self, pose) -> tuple:
        _t, _angles, torso_pos, _torso_angle, arm_angle = pose
        return _add(torso_pos, _rot((self.g["arm_length"], 0.0), arm_angle))

    def draw(self, pose, caption: str = "", path: list | None = None, labels: bool = False,
             robot: bool = True) -> np.ndarray:
        """One frame: the row at ``pose`` (t, frame angles, torso position, torso angle, arm angle),
        optionally with the hook's ``path`` (SI points) traced behind it; ``labels`` names the parts of the
        first frame and the robot beside them (a classroom's animation); ``robot=False`` draws the stand and its
        frames alone (an assembly step)."""
        from PIL import Image, ImageDraw

        g, px = self.g, self.px
        t, angles, torso_pos, torso_angle, arm_angle = pose
        img = Image.new("RGB", (self.width, self.height), self.BACKGROUND)
        d = ImageDraw.Draw(img)
        d.line([px(g["floor"][0]), px(g["floor"][1])], fill=(150, 150, 150), width=2)
        La, Lb, h = g["La"], g["Lb"], g["h"]
        for (ax, ay), th in zip(g["axes"], angles):
            def w(v, ax=ax, ay=ay, th=th):
                r = _rot(v, th)
                return px((ax + r[0], ay + r[1]))

            d.line([w((-Lb, 0.0)), w((La, 0.0))], fill=(120, 90, 40), width=3)  # frame
            for a, b in g["faces_local"][0]:  # handrail notch
                d.line([w(a), w(b)], fill=(40, 40, 40), width=2)
            cx, cy = w((La, h))
            d.ellipse([cx - 5, cy - 5, cx + 5, cy + 5], fill=(200, 160, 30))  # counterbalance
            for offset in g["stoppers"]:  # the rest and end stoppers, where the kit's crossbeam holds them
                sx, sy = px(_add((ax, ay), offset))
                d.ellipse([sx - 2, sy - 2, sx + 2, sy + 2], fill=(90, 90, 90))
            ox, oy = px((ax, ay))
            d.ellipse([ox - 3, oy - 3, ox + 3, oy + 3], fill=(0, 0, 0))  # axis skewer
        if path and len(path) > 1:
            d.line([px(q) for q in path], fill=(230, 150, 150), width=1)
        if not robot:
            d.text((8, 6), caption, fill=(0, 0, 0))
            if labels:
                self._labels(d, angles, None, None)
            return np.asarray(img)
        torso_end = _add(torso_pos, _rot((0.0, -g["torso_length"]), torso_angle))
        d.line([px(torso_pos), px(torso_end)], fill=(30, 90, 200), width=6)  # torso card strip
        cx, cy = px(_add(torso_pos, _rot((0.0, -g["coin_offset"]), torso_angle)))  # the coins
        d.ellipse([cx - 5, cy - 5, cx + 5, cy + 5], fill=(190, 190, 200))
        hook = self.hook(pose)
        d.line([px(torso_pos), px(hook)], fill=(200, 40, 40), width=3)  # arm
        hx, hy = px(hook)
        d.ellipse([hx - 3, hy - 3, hx + 3, hy + 3], outline=(200, 40, 40), width=2)
        d.text((8, 6), f"t = {t:5.2f} s" + (f"   {caption}" if caption else ""), fill=(0, 0, 0))
        if labels:
            self._labels(d, angles, torso_pos, torso_end)
        return np.asarray(img)

    def _labels(self, d, angles, torso_pos, torso_end) -> None:
        """The parts' names beside frame 0's parts, and the robot's when it is drawn."""
        g, px = self.g, self.px
        (ax, ay), th = g["axes"][0], angles[0]
        at = lambda v: px(_add((ax, ay), _rot(v, th)))  # noqa: E731  a point of frame 0, drawn
        names = [("swing frame", at((0.5 * g["La"], 0.0)), (6, -16)), ("counterbalance", at((g["La"], g["h"])), (8, -4)),
                 ("handrail", at((-g["Lb"], 0.0)), (-60, -16)), ("axis skewer", px((ax, ay)), (6, 4))]
        if torso_pos is not None:
            names += [("spring (at the axle)", px(torso_pos), (10, -6)), ("robot", px(torso_end), (8, -4))]
        for text, (x, y), (dx, dy) in names:
            d.text((x + dx, y + dy), text, fill=(60, 60, 60))


def _need_poses(result: SimResult) -> None:
    if result.poses is None or result.geometry is None:
        raise ValueError("this result has no poses: simulate(..., poses_every=...)")


def iter_frames(result: SimResult, width: int = 720, height: int = 300, every: int = 1, caption: str = "",
                labels: bool = False) -> Iterator[np.ndarray]:
    """The recorded poses as RGB numpy arrays (height, width, 3), drawn one at a time."""
    _need_poses(result)
    canvas = Canvas(result.geometry, width, height)
    return (canvas.draw(pose, caption, labels=labels) for pose in result.poses[::every])


def draw_frames(result: SimResult, width: int = 720, height: int = 300, every: int = 1, caption: str = "",
                labels: bool = False) -> list[np.ndarray]:
    """Render the recorded poses as a list of RGB numpy arrays (height, width, 3)."""
    return list(iter_frames(result, width, height, every, caption, labels))


def draw_summary(result: SimResult, width: int = 720, height: int = 300) -> np.ndarray:
    """The whole run in one picture: the final pose, the hook's path, and the outcome."""
    _need_poses(result)
    canvas = Canvas(result.geometry, width, height)
    path = [canvas.hook(p) for p in result.poses]
    caption = f"{result.outcome}: {result.traversals}/{result.frames - 1} traversals"
    return canvas.draw(result.poses[-1], caption, path)


def write_gif(result: SimResult, path: str | Path, fps: int = ANIMATION_FPS, labels: bool = False,
              slowmo: float | None = None) -> None:
    """The recorded poses as an animated GIF; ``labels`` names the parts, and ``slowmo`` (the factor the poses were
    recorded for) is then said in the caption."""
    from PIL import Image

    caption = f"slow motion x{slowmo:g}" if labels and slowmo else ""
    rgb = draw_frames(result, caption=caption, labels=labels)
    # One shared palette (the drawing uses a dozen colours): per-frame quantization is 5x slower.
    palette = Image.fromarray(rgb[len(rgb) // 2]).quantize(colors=32, method=Image.Quantize.MEDIANCUT)
    frames = [Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.NONE) for f in rgb]
    # the delay in whole centiseconds, as the GIF stores it (Pillow would truncate the rest silently)
    frame_ms = 10 * round(100 / fps)
    write_atomically(path, lambda f: frames[0].save(f, format="GIF", save_all=True, append_images=frames[1:],
                                                     duration=frame_ms, loop=0), "animation file")
