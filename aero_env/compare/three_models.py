"""The three models on one swing: quasi-static (Eq. 1), two-link (A25/A30) and the pymunk MBD.

All three start from the MBD's held catch state (:mod:`.mbd`) on the chosen swing (swing 1 by default: the
first caught from a flight, the one the paper measures; swing 0 starts from rest) and are
compared up to the MBD's detach angle: the time to reach it, where theta1'' changes sign, and
how much drag changes theta1''. Figs. 40, 42 and 43 are drawn by :func:`plot_comparison`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..config import Config, ConfigError, pymunk_fidelities
from ..files import save_figure
from ..models import quasi_static, two_link
from ..models.two_link import SwingResult
from .mbd import FLIGHT_ENTERED, mbd_swing
from .paper_points import paper_points

def analytical(cfg: Config, start: dict, angle: float, drag: bool = False) -> tuple[SwingResult, SwingResult]:
    """The quasi-static and two-link swings from the MBD's held catch state ``start`` to ``angle``,
    on the MBD's clock (t = 0 at the first touch)."""
    d = cfg.design
    # the two-link model of the machine the world builds (the robot's parts held at alpha_max, the frame's side
    # cards), so the comparison is of models, not of machines; two_link's robot="paper" and inertia="consistent"
    # are the article's own A14 and A13
    tl = two_link.simulate(d, start["theta1"], start["theta2"], start["omega1"], start["omega2"], t_end=3.0,
                           until_theta1=angle, drag=drag, inertia="parts", robot="parts")
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
                          f"pymunk fidelity ({pymunk_fidelities()})")
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
    try:
        save_figure(fig, path, dpi=100)
    finally:
        plt.close(fig)
