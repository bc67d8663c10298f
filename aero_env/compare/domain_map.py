"""Where each model holds: the paper's Fig. 29, computed instead of sketched.

Over robot mass m2 and the counterbalance's moment ratio (the frame's available energy), each
point runs the MBD's first swing (from rest, so every design has one) and both analytical models
from the same state, and marks where a model's time to the MBD's detach angle is within 10 %.
"""

from __future__ import annotations

import math

import numpy as np

from ..config import Config
from ..files import save_figure
from ..models import quasi_static
from .mbd import FALLBACK_ANGLE_DEG, mbd_swing
from .three_models import analytical

MAP_MASSES = (0.004, 0.06, 7)  # robot mass m2 for the domain map: kg, low, high, count (log-spaced)
MAP_RATIOS = (0.6, 0.95, 8)  # moment ratio (m3·La)/(m2·Lb) for the map: low, high, count


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

    The robot's parts (arm, coins, the handrail it is weighed with) and the spring scale with m2
    (k ∝ m2, so a heavier robot still bends and snaps its arm as the prototype does). For each point: the MBD's first transfer (caught by frame 1
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
            f = float(m2) / d.m2  # the robot's parts, spring and handrail scale with it: the same toy, heavier
            c = cfg.replace({"design.m2": float(m2), "design.m3": float(m3), "design.spring_k": d.spring_k * f,
                             "design.arm_mass": d.arm_mass * f, "design.coin_mass": d.coin_mass * f,
                             "design.handrail_mass": d.handrail_mass * f})
            mbd = mbd_swing(c, 0)
            angle, outcome = mbd.angle, mbd.outcome
            qs, tl = analytical(c, mbd.start, angle)
            t_ref = mbd.run.t_until
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
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator

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
        # plain grams at the sampled masses, not 4x10^0
        ax.xaxis.set_major_locator(FixedLocator(np.unique(x)))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:.3g}"))
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel("robot mass m2 [g]")
        ax.set_title(f"{title}: error in time to the MBD's detach angle")
        ax.grid(alpha=0.3, which="both")
        fig.colorbar(sc, ax=ax, label="error [%]")
    axes[0].set_ylabel("counterbalance / robot moment (m3·La)/(m2·Lb)")
    # one legend below both panels, where it covers no point
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle("Where each model holds (the paper's Fig. 29, computed; the robot's parts and spring scaled with m2)")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    try:
        save_figure(fig, path, dpi=100)
    finally:
        plt.close(fig)
