"""The three models on one swing: quasi-static (Eq. 1), two-link (A25/A30) and the pymunk MBD.

All three start from the MBD's held catch state on the chosen swing (swing 1 by default: the
first caught from a flight, the one the paper measures; swing 0 starts from rest) and are
compared up to the MBD's detach angle: the time to reach it, where theta1'' changes sign, and
how much drag changes theta1''. Figs. 40, 42 and 43 are drawn by :func:`plot_comparison`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..config import Config, ConfigError
from ..models import quasi_static, two_link
from ..models.two_link import SwingResult
from ..physics import simulate

FLIGHT_ENTERED = 1  # swing 1: caught from a flight, as in the paper's Sec. 7.3 and Figs. 40-43
FALLBACK_ANGLE_DEG = 150.0  # compared up to here when the MBD never lets go
SMOOTH_S = 0.01  # the MBD's theta1'' is a numerical derivative: averaged over 10 ms


def _first_time(t, theta1, angle) -> float | None:
    idx = np.nonzero(theta1 >= angle)[0]
    if idx.size == 0 or idx[0] == 0:
        return None
    i = idx[0]
    return float(t[i - 1] + (angle - theta1[i - 1]) / (theta1[i] - theta1[i - 1]) * (t[i] - t[i - 1]))


def _smooth(x, n):
    if n <= 1:
        return x
    kernel = np.ones(n) / n
    return np.convolve(np.pad(x, (n // 2, n - 1 - n // 2), mode="edge"), kernel, mode="valid")


@dataclass(frozen=True)
class MbdSwing:
    """One swing of the pymunk run, with the state the analytical models start from."""

    run: SwingResult  # t = 0 at the catch (the paper's Sec. 7.3 origin), up to the detach or 150 deg
    angle: float  # rad: the detach angle the models are compared up to
    outcome: str  # of the run (scene.frames = swing + 2)
    start: dict  # t (s after the catch), theta1, theta2, omega1, omega2 (rad, rad/s) of the first held row
    alpha: np.ndarray  # rad: the arm's angle to the torso at the run's samples (the leaf spring's bend)


def mbd_swing(cfg: Config, swing: int = FLIGHT_ENTERED, drag: bool = False) -> MbdSwing:
    """Swing ``swing`` of the pymunk run (0: the first, from rest; 1: the first entered from a flight,
    the one the paper measures) to its detach, or to 150 deg if it never lets go.

    The trace names a new frame once the catch has held (``sim.contact_hold``); the models start from
    that first row, at its time after the first touch, so every curve shares the paper's t = 0.
    """
    run_cfg = cfg.replace({"scene.frames": swing + 2, "scene.effects.drag": drag, "sim.trace_every": 1})
    r = simulate(run_cfg, trace=True)
    if len(r.swings) <= swing:
        raise ConfigError(f"compare --swing {swing}: the MBD robot never catches frame {swing} "
                          f"({r.outcome}: {r.reason}); choose a swing in 0..{len(r.swings) - 1}")
    tr = r.trace
    s = r.swings[swing]
    angle = math.radians(s.theta1_detach_deg if s.theta1_detach_deg is not None else FALLBACK_ANGLE_DEG)
    on = tr["frame"] == swing
    t = tr["t"] - s.t_catch
    t_end = s.swing_duration if s.t_detach is not None else t[on][-1]
    n = max(1, int(round(SMOOTH_S / cfg.sim.dt)))
    first = on & (t <= t_end + 1e-12)
    i0 = int(np.argmax(first))
    if swing == 0:  # the scene's own start state: at rest, before the world's first step settles it
        start = dict(t=0.0, theta1=math.radians(cfg.design.rest_angle_deg),
                     theta2=math.radians(cfg.scene.theta2_start_deg), omega1=0.0, omega2=0.0)
    else:
        start = dict(t=float(t[i0]), theta1=float(tr["theta1"][i0]), theta2=float(tr["theta2"][i0]),
                     omega1=float(tr["omega1"][i0]), omega2=float(tr["omega2"][i0]))
    # drop the first and last half-window: a moving average of a derivative is one-sided there
    keep = first & (t >= start["t"] + n * cfg.sim.dt / 2) & (t <= t_end - n * cfg.sim.dt / 2)
    a1 = _smooth(np.gradient(tr["omega1"], tr["t"]), n)[keep]
    a2 = _smooth(np.gradient(tr["omega2"], tr["t"]), n)[keep]
    t_angle = s.swing_duration if s.t_detach is not None else _first_time(t[first], tr["theta1"][first], angle)
    run = SwingResult(t[keep], tr["theta1"][keep], tr["theta2"][keep], tr["omega1"][keep], tr["omega2"][keep],
                      a1, a2, t_angle)
    return MbdSwing(run, angle, r.outcome, start, tr["alpha"][keep])


def analytical(cfg: Config, start: dict, angle: float, drag: bool = False) -> tuple[SwingResult, SwingResult]:
    """The quasi-static and two-link swings from the MBD's held catch state ``start`` to ``angle``,
    on the MBD's clock (t = 0 at the first touch)."""
    d = cfg.design
    # the two-link model of the robot the world builds (its parts, held at alpha_max), so the comparison is
    # of models, not of robots; two_link's robot="paper" is the article's own A14 convention
    tl = two_link.simulate(d, start["theta1"], start["theta2"], start["omega1"], start["omega2"], t_end=3.0,
                           until_theta1=angle, drag=drag, robot="parts")
    qs = quasi_static.simulate(d, start["theta1"], start["omega1"], t_end=3.0, until_theta1=angle, drag=drag)
    return _delayed(qs, start["t"]), _delayed(tl, start["t"])


def _delayed(run: SwingResult, t0: float) -> SwingResult:
    return replace(run, t=run.t + t0, t_until=None if run.t_until is None else run.t_until + t0)


def sign_changes_deg(run: SwingResult) -> list[float]:
    """theta1 (deg) where theta1'' changes sign, in order."""
    a, th = run.alpha1, run.theta1
    out = []
    for i in np.nonzero(np.sign(a[:-1]) * np.sign(a[1:]) < 0)[0]:
        out.append(math.degrees(th[i] - a[i] * (th[i + 1] - th[i]) / (a[i + 1] - a[i])))
    return out


def drag_effect(plain: SwingResult, dragged: SwingResult) -> dict:
    """Largest change drag makes to theta1'' at the same theta1, absolute and relative to max|theta1''|."""
    lo = max(plain.theta1.min(), dragged.theta1.min())
    hi = min(plain.theta1.max(), dragged.theta1.max())
    grid = np.linspace(lo, hi, 400)
    diff = np.interp(grid, *_increasing(dragged.theta1, dragged.alpha1)) - np.interp(grid, *_increasing(plain.theta1, plain.alpha1))
    worst = float(np.abs(diff).max())
    return dict(max_change=worst, relative=worst / float(np.abs(plain.alpha1).max()))


def _increasing(x, y):
    """theta1 rises through a swing but may dwell; keep the samples where it strictly increases."""
    keep = np.concatenate([[True], np.diff(np.maximum.accumulate(x)) > 0])
    return x[keep], y[keep]


def compare(cfg: Config, swing: int = FLIGHT_ENTERED) -> tuple[dict, dict]:
    """Run the three models on swing ``swing`` (0: from rest), with and without drag.

    Every model starts from the plain MBD run's held catch state; the MBD's own run with drag
    flies into its catch with drag too. Returns (JSON summary, runs for plotting)."""
    if isinstance(swing, bool) or not isinstance(swing, int) or swing < 0:
        raise ConfigError(f"compare --swing {swing!r}: must be a whole number >= 0 (0: the first swing, from rest)")
    if cfg.sim.model != "mbd":
        raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r}: compare's MBD model is the pymunk world; choose a "
                          f"pymunk fidelity (mbd-fast, mbd, mbd-fine, reference)")
    mbd = mbd_swing(cfg, swing)
    mbd_drag = mbd_swing(cfg, swing, drag=True)
    qs, tl = analytical(cfg, mbd.start, mbd.angle)
    qs_d, tl_d = analytical(cfg, mbd.start, mbd.angle, drag=True)
    runs = {"mbd": (mbd.run, mbd_drag.run), "two_link": (tl, tl_d), "quasi_static": (qs, qs_d)}
    st = mbd.start
    summary = dict(
        swing=swing,
        start=dict(t=st["t"], theta1_deg=math.degrees(st["theta1"]), theta2_deg=math.degrees(st["theta2"]),
                   omega1=st["omega1"], omega2=st["omega2"]),
        detach_angle_deg=math.degrees(mbd.angle),
        models={name: dict(time_to_detach_angle=plain.t_until,
                           time_to_detach_angle_with_drag=dragged.t_until,
                           alpha1_sign_changes_deg=sign_changes_deg(plain),
                           drag_alpha1_change=drag_effect(plain, dragged))
                for name, (plain, dragged) in runs.items()},
    )
    if swing >= 1:  # the paper describes a swing caught from a flight
        from .paper_points import paper_points

        summary["paper_points"] = paper_points(mbd, tl)
    return summary, runs


def plot_comparison(runs: dict, path, title: str = "") -> None:
    """The paper's Figs. 40, 42, 43 for the three models; dashed: with drag."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colors = {"mbd": "black", "two_link": "tab:blue", "quasi_static": "tab:orange"}
    labels = {"mbd": "MBD (pymunk)", "two_link": "two-link", "quasi_static": "quasi-static Eq. (1)"}
    fig, ax = plt.subplots(3, 2, figsize=(11, 10))
    for name, (plain, dragged) in runs.items():
        for run, ls, lw in ((plain, "-", 1.6), (dragged, "--", 0.9)):
            lab = labels[name] + (" + drag" if ls == "--" else "")
            c = colors[name]
            d1, d2 = np.degrees(run.theta1), np.degrees(run.theta2)
            ax[0, 0].plot(run.t, d1, ls, color=c, lw=lw, label=lab)
            ax[1, 0].plot(d1, run.omega1, ls, color=c, lw=lw, label=lab)
            ax[2, 0].plot(d1, run.alpha1, ls, color=c, lw=lw, label=lab)
            if not np.all(np.isnan(run.theta2)):
                ax[0, 1].plot(run.t, d2, ls, color=c, lw=lw, label=lab)
                ax[1, 1].plot(d1, run.omega2, ls, color=c, lw=lw, label=lab)
                ax[2, 1].plot(d1, run.alpha2, ls, color=c, lw=lw, label=lab)
    names = [(r"$\theta_1$ [deg]", r"$\theta_2$ [deg]", "time [s]"),
             (r"$\dot\theta_1$ [rad/s]", r"$\dot\theta_2$ [rad/s]", r"$\theta_1$ [deg]"),
             (r"$\ddot\theta_1$ [rad/s$^2$]", r"$\ddot\theta_2$ [rad/s$^2$]", r"$\theta_1$ [deg]")]
    figs = ("Fig. 40", "Fig. 42", "Fig. 43")
    for row, (y1, y2, x) in enumerate(names):
        for col, y in enumerate((y1, y2)):
            a = ax[row, col]
            a.set_ylabel(y)
            a.set_xlabel(x)
            a.grid(alpha=0.3)
            a.set_title(f"{figs[row]}: {y.split('[')[0].strip()}", fontsize=9)
            if row == 2:
                a.axhline(0.0, color="gray", lw=0.6)
                # scale to the analytical curves: the MBD's contact events spike far beyond them
                ref = np.concatenate([(r.alpha1 if col == 0 else r.alpha2) for name, pair in runs.items()
                                      if name != "mbd" for r in pair])
                ref = ref[np.isfinite(ref)]
                if ref.size:
                    span = ref.max() - ref.min()
                    a.set_ylim(ref.min() - 1.5 * span, ref.max() + 1.5 * span)
    # one legend for all six panels, below them, where it covers no curve
    handles, names = ax[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(title or "quasi-static vs two-link vs MBD (dashed: with drag)")
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(path, dpi=100)
    plt.close(fig)
