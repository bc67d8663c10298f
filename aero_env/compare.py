"""The three models on one scene: quasi-static (Eq. 1), two-link (A25/A30) and the pymunk MBD.

All three start from the MBD's catch state on frame 0 (theta1 at rest, theta2 as placed, at
rest) and are compared up to the MBD's detach angle: the time to reach it, where theta1''
changes sign, and how much drag changes theta1''. :func:`domain_map` computes the paper's
Fig. 29 instead of sketching it: where each analytical model predicts the MBD's swing time
within 10%, over robot mass and the frame's available energy.
"""

from __future__ import annotations

import math

import numpy as np

from .config import Config, ConfigError
from .models import quasi_static, two_link
from .models.two_link import SwingResult
from .physics import simulate

FALLBACK_ANGLE_DEG = 150.0  # compared up to here when the MBD never lets go
MAP_MASSES = (0.004, 0.06, 7)  # robot mass m2 for the domain map: kg, low, high, count (log-spaced)
MAP_RATIOS = (0.6, 0.95, 8)  # moment ratio (m3·La)/(m2·Lb) for the map: low, high, count
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


def mbd_first_swing(cfg: Config, drag: bool = False) -> tuple[SwingResult, float, str]:
    """The pymunk run's first swing (to its detach, or to 150 deg), the compare angle (rad) and the
    outcome of its first transfer."""
    run_cfg = cfg.replace({"scene.frames": 2, "scene.effects.drag": drag, "sim.trace_every": 1})
    r = simulate(run_cfg, trace=True)
    tr = r.trace
    s0 = r.swings[0]
    angle = math.radians(s0.theta1_detach_deg) if s0.theta1_detach_deg is not None else math.radians(FALLBACK_ANGLE_DEG)
    t_end = s0.t_detach if s0.t_detach is not None else tr["t"][-1]
    n = max(1, int(round(SMOOTH_S / cfg.sim.dt)))
    # drop the first and last half-window: a moving average of a derivative is one-sided there
    keep = (tr["t"] >= n * cfg.sim.dt / 2) & (tr["t"] <= t_end - n * cfg.sim.dt / 2) & (tr["frame"] == 0)
    t = tr["t"]
    a1 = _smooth(np.gradient(tr["omega1"], t), n)[keep]
    a2 = _smooth(np.gradient(tr["omega2"], t), n)[keep]
    first = (tr["t"] <= t_end) & (tr["frame"] == 0)
    t_angle = s0.swing_duration if s0.t_detach is not None else _first_time(t[first], tr["theta1"][first], angle)
    run = SwingResult(t[keep], tr["theta1"][keep], tr["theta2"][keep], tr["omega1"][keep], tr["omega2"][keep],
                      a1, a2, t_angle)
    return run, angle, r.outcome


def analytical(cfg: Config, theta2_0: float, angle: float, drag: bool = False) -> tuple[SwingResult, SwingResult]:
    d = cfg.design
    th0 = math.radians(d.rest_angle_deg)
    # the two-link model of the robot the world builds (its parts, held at alpha_max), so the comparison is
    # of models, not of robots; two_link's robot="paper" is the article's own A14 convention
    tl = two_link.simulate(d, th0, theta2_0, t_end=3.0, until_theta1=angle, drag=drag, robot="parts")
    qs = quasi_static.simulate(d, th0, t_end=3.0, until_theta1=angle, drag=drag)
    return qs, tl


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


def compare(cfg: Config) -> tuple[dict, dict]:
    """Run the three models, with and without drag. Returns (JSON summary, runs for plotting)."""
    if cfg.sim.model != "mbd":
        raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r}: compare's MBD model is the pymunk world; choose a "
                          f"pymunk fidelity (mbd-fast, mbd, mbd-fine, reference)")
    mbd, angle, _ = mbd_first_swing(cfg)
    mbd_drag, _, _ = mbd_first_swing(cfg, drag=True)
    theta2_0 = math.radians(cfg.scene.theta2_start_deg)  # the MBD's catch state
    qs, tl = analytical(cfg, theta2_0, angle)
    qs_d, tl_d = analytical(cfg, theta2_0, angle, drag=True)
    runs = {"mbd": (mbd, mbd_drag), "two_link": (tl, tl_d), "quasi_static": (qs, qs_d)}
    summary = dict(
        start=dict(theta1_deg=cfg.design.rest_angle_deg, theta2_deg=cfg.scene.theta2_start_deg),
        detach_angle_deg=math.degrees(angle),
        models={name: dict(time_to_detach_angle=plain.t_until,
                           time_to_detach_angle_with_drag=dragged.t_until,
                           alpha1_sign_changes_deg=sign_changes_deg(plain),
                           drag_alpha1_change=drag_effect(plain, dragged))
                for name, (plain, dragged) in runs.items()},
    )
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
    ax[0, 0].legend(fontsize=7)
    fig.suptitle(title or "quasi-static vs two-link vs MBD, first swing (dashed: with drag)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def moment_ratio(d) -> float:
    """The counterbalance's moment over the robot's, (m3·La)/(m2·Lb): the domain map's second axis."""
    return d.m3 * d.La / (d.m2 * d.Lb)


def available_energy(cfg: Config, to_deg: float = FALLBACK_ANGLE_DEG) -> float:
    """Work (J) the quasi-static moment of Eq. (1) does from the rest angle to ``to_deg``: the energy the
    frame makes available to turn with the robot."""
    th = np.radians(np.linspace(cfg.design.rest_angle_deg, to_deg, 2001))
    m = quasi_static.moment(cfg.design, th)
    return float(np.sum((m[1:] + m[:-1]) / 2 * np.diff(th)))


def domain_map(cfg: Config, masses=None, ratios=None, tolerance: float = 0.10) -> dict:
    """Sweep robot mass m2 and counterbalance ratio m3/(m2·Lb/La) (the frame's available energy).

    The spring and robot inertia scale with m2 (k ∝ m2, so a heavier robot still bends and snaps
    its arm as the prototype does). For each point: the MBD's first transfer (caught by frame 1
    or not), and whether each analytical model's time to the MBD's detach angle lies within
    ``tolerance`` of the MBD's.
    """
    d = cfg.design
    masses = np.geomspace(*MAP_MASSES) if masses is None else np.asarray(masses)
    ratios = np.linspace(*MAP_RATIOS) if ratios is None else np.asarray(ratios)
    points = []
    for m2 in masses:
        for ratio in ratios:
            m3 = ratio * m2 * d.Lb / d.La
            c = cfg.replace({"design.m2": float(m2), "design.m3": float(m3),
                             "design.spring_k": d.spring_k * float(m2) / d.m2})
            mbd, angle, outcome = mbd_first_swing(c)
            qs, tl = analytical(c, math.radians(c.scene.theta2_start_deg), angle)
            t_ref = mbd.t_until
            point = dict(m2=float(m2), m3=float(m3), ratio=float(ratio), energy=available_energy(c),
                         mbd_time=t_ref, detach_angle_deg=math.degrees(angle), mbd_outcome=outcome,
                         mbd_traverses=outcome == "completed")
            for name, run in (("quasi_static", qs), ("two_link", tl)):
                err = (abs(run.t_until - t_ref) / t_ref
                       if t_ref is not None and run.t_until is not None else None)
                point[f"{name}_time"] = run.t_until
                point[f"{name}_error"] = err  # relative to the MBD's time; None if either never gets there
                point[f"{name}_within"] = err is not None and err <= tolerance
            points.append(point)
    return dict(tolerance=tolerance, points=points)


def plot_domain_map(result: dict, path, prototype: tuple[float, float] | None = None) -> None:
    """Two panels (quasi-static, two-link): each point coloured by the model's error in swing time
    against the MBD, ringed where it is within tolerance; stars where the MBD robot traverses."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts = result["points"]
    tol = result["tolerance"]
    x = np.array([p["m2"] * 1e3 for p in pts])
    y = np.array([p["ratio"] for p in pts])
    ok = np.array([p["mbd_traverses"] for p in pts])
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), sharey=True)
    for ax, name, title in zip(axes, ("quasi_static", "two_link"), ("quasi-static Eq. (1)", "two-link")):
        err = np.array([np.nan if p[f"{name}_error"] is None else 100 * p[f"{name}_error"] for p in pts])
        within = np.array([p[f"{name}_within"] for p in pts])
        sc = ax.scatter(x, y, c=np.clip(err, 0, 3 * 100 * tol), cmap="viridis_r", s=140, vmin=0, vmax=3 * 100 * tol)
        ax.scatter(x[np.isnan(err)], y[np.isnan(err)], marker="x", color="gray", s=40,
                   label="a model or the MBD never reaches the angle")
        ax.scatter(x[within], y[within], s=330, facecolors="none", edgecolors="tab:red", lw=1.4,
                   label=f"within {100 * tol:.0f}% of the MBD")
        ax.scatter(x[ok], y[ok], marker="*", s=45, color="white", edgecolors="black", lw=0.5,
                   label="MBD robot traverses", zorder=3)
        if prototype is not None:
            ax.scatter([prototype[0] * 1e3], [prototype[1]], s=520, marker="s", facecolors="none",
                       edgecolors="black", lw=1.2, label="prototype (Table 1)")
        ax.set_xscale("log")
        ax.set_xlabel("robot mass m2 [g]")
        ax.set_title(f"{title}: error in time to the MBD's detach angle")
        ax.grid(alpha=0.3, which="both")
        fig.colorbar(sc, ax=ax, label="error [%]")
    axes[0].set_ylabel("counterbalance / robot moment (m3·La)/(m2·Lb)")
    axes[0].legend(fontsize=7, loc="lower left", framealpha=0.9)
    fig.suptitle("Where each model holds (the paper's Fig. 29, computed; spring stiffness scaled with m2)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
