"""What ``aero-env calibrate`` gives back: the JSON object, the table, the calibrated config, the plot."""

from __future__ import annotations

from pathlib import Path

from ..config import Config
from ..files import save_figure, write_text_atomically
from .fit import FitResult
from .measured import MeasuredSwing
from .swing_metrics import METRICS, SwingTrace
from .targets import Targets

SCORE_UNITS = {"trace": "deg RMS", "targets": "tolerances RMS"}


def mode_of(reference: MeasuredSwing | Targets) -> str:
    return "trace" if isinstance(reference, MeasuredSwing) else "targets"


def to_json_dict(result: FitResult, reference: MeasuredSwing | Targets, swing: int, seed: int) -> dict:
    """The ``--json`` object (every value but ``wall_time`` is the same for the same command)."""
    best = result.best
    targets = None
    if best.targets is not None:
        targets = {row["metric"]: {k: v for k, v in row.items() if k != "metric"} for row in best.targets}
    return dict(fitted=dict(result.fitted), score=best.score, score_unit=SCORE_UNITS[mode_of(reference)],
                miss=best.miss, rms_theta1_deg=best.rms_theta1_deg, rms_theta2_deg=best.rms_theta2_deg,
                metrics=best.metrics, targets=targets, trials=result.trials, wall_time=result.wall_time, swing=swing,
                method=result.method, seed=seed, ranges={k.key: [k.low, k.high] for k in result.keys},
                reference=reference.path)


def table(doc: dict) -> str:
    """A short human-readable summary of :func:`to_json_dict`'s object."""
    lines = [f"calibrated against {doc['reference']} (swing {doc['swing']}): {doc['trials']} trials, "
             f"{doc['method']}, {doc['wall_time']:.1f} s"]
    for key, value in doc["fitted"].items():
        low, high = doc["ranges"][key]
        lines.append(f"  {key} = {value:.6g}   (searched {low:g} .. {high:g})")
    score = f"score: {doc['score']:.4g} {doc['score_unit']}"
    if doc["rms_theta1_deg"] is not None:
        score += f" (theta1 {doc['rms_theta1_deg']:.3g} deg"
        score += f", theta2 {doc['rms_theta2_deg']:.3g} deg)" if doc["rms_theta2_deg"] is not None else ")"
    lines.append(score)
    if doc["miss"]:
        lines.append(f"miss: no trial produced a usable swing {doc['swing']}: {doc['miss']}")
        return "\n".join(lines)
    targets = doc["targets"]
    if targets is None:  # a measured swing: the fitted swing's metrics alone
        lines.append(f"{'metric':<20} {'simulated':>10}  unit")
        lines += [f"{name:<20} {_num(doc['metrics'][name], 10)}  {unit}" for name, (unit, _) in METRICS.items()]
        return "\n".join(lines)
    lines.append(f"{'metric':<20} {'simulated':>10} {'target':>10} {'tol':>8} {'z':>7}  unit")
    for name, (unit, _) in METRICS.items():
        t = targets.get(name)
        cells = [_num(doc["metrics"][name], 10), _num(t and t["value"], 10), _num(t and t["tolerance"], 8),
                 _num(t and t["z"], 7, ".2f")]
        lines.append(f"{name:<20} {' '.join(cells)}  {unit}")
    return "\n".join(lines)


def _num(v, width: int, spec: str = ".4g") -> str:
    return f"{'-':>{width}}" if v is None else f"{v:>{width}{spec}}"


def write_config(cfg: Config, result: FitResult, doc: dict, path: str | Path) -> None:
    """The whole config with the fitted values, as YAML that ``load_config`` reads back."""
    fitted = cfg.replace(result.fitted)
    header = [f"# aero-env calibrate: fitted against {doc['reference']} (swing {doc['swing']}), "
              f"score {doc['score']:.4g} {doc['score_unit']}, {doc['trials']} trials ({doc['method']})"]
    header += [f"#   {k} = {v!r}" for k, v in result.fitted.items()]
    write_text_atomically(path, "\n".join(header) + "\n" + fitted.to_yaml(), "config file")


# where a target is drawn in the plot: metric -> (axis, where on it)
_POINT_TARGETS = {  # an angle: (axis, at a time metric's target or simulated value, or 0: the catch; colour)
    "theta1_catch_deg": ("theta", 0.0, "tab:blue"),
    "theta2_catch_deg": ("theta", 0.0, "tab:orange"),
    "theta1_detach_deg": ("theta", "swing_duration", "tab:blue"),
    "alpha_at_lowest_deg": ("alpha", "t_lowest", "tab:purple"),
}
_BAND_TARGETS = {"swing_duration": "theta", "t_lowest": "alpha"}  # a time: a vertical band on that axis


def plot_fit(doc: dict, sw: SwingTrace | None, reference: MeasuredSwing | Targets, path: str | Path) -> None:
    """theta1, theta2 (top) and alpha (bottom) of the fitted swing against the measurement or targets."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, gridspec_kw=dict(height_ratios=[3, 1.3]))
    axes = {"theta": ax, "alpha": ax2}
    if sw is not None:
        ax.plot(sw.t, sw.theta1, color="tab:blue", label=r"$\theta_1$ fitted")
        ax.plot(sw.t_robot, sw.theta2, color="tab:orange", label=r"$\theta_2$ fitted")
        ax2.plot(sw.t_robot, sw.alpha, color="tab:purple", label=r"$\alpha$ fitted")
    if isinstance(reference, MeasuredSwing):
        _plot_measured(ax, reference)
    else:
        _plot_targets(axes, doc, reference)
    fitted = ", ".join(f"{k} = {v:.4g}" for k, v in doc["fitted"].items())
    ax.set_title(f"swing {doc['swing']}: {fitted}; score {doc['score']:.3g} {doc['score_unit']}", fontsize=9)
    ax.set_ylabel("angle [deg]")
    ax2.set_ylabel(r"$\alpha$ [deg]")
    ax2.set_xlabel("time from the catch [s]")
    for a in (ax, ax2):
        a.grid(alpha=0.3)
        a.legend(loc="lower right", fontsize=8, ncol=2)
    fig.tight_layout()
    try:
        save_figure(fig, path, dpi=110)
    finally:
        plt.close(fig)


def _plot_measured(ax, m: MeasuredSwing) -> None:
    ax.plot(m.t, m.theta1, "o", ms=3, color="tab:blue", alpha=0.6, label=r"$\theta_1$ measured")
    if m.theta2 is not None:
        ax.plot(m.t, m.theta2, "s", ms=3, color="tab:orange", alpha=0.6, label=r"$\theta_2$ measured")


def _plot_targets(axes: dict, doc: dict, targets: Targets) -> None:
    given = {t.metric: t for t in targets.targets}
    metrics = doc["metrics"] or {}

    def time_of(where):
        if not isinstance(where, str):
            return where
        t = given.get(where)
        return t.value if t is not None else metrics.get(where)

    for name, (axis, where, colour) in _POINT_TARGETS.items():
        t, when = given.get(name), time_of(where)
        if t is not None and when is not None:
            axes[axis].errorbar([when], [t.value], yerr=[t.tolerance], fmt="D", ms=5, color=colour, mec="k",
                                capsize=3, label=f"target {name}")
    for name, axis in _BAND_TARGETS.items():
        t = given.get(name)
        if t is not None:
            axes[axis].axvspan(t.value - t.tolerance, t.value + t.tolerance, color="tab:green", alpha=0.15,
                               label=f"target {name}")
    for name in ("theta2_min_deg", "theta2_max_deg"):
        t = given.get(name)
        if t is not None:
            axes["theta"].axhspan(t.value - t.tolerance, t.value + t.tolerance, color="tab:orange", alpha=0.1,
                                  label=f"target {name}")
