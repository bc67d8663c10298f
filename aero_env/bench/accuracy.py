"""``aero-env bench accuracy``: every fidelity on the same designs, against ``reference``.

For each design (drawn from the env's action space with a fixed seed) and each fidelity, the
run is repeated ``repeats`` times and its median wall time kept; ``reduced`` runs the whole
sample as one vectorised batch, and its time per design is the batch's median over
``repeats`` divided by the sample size. Against ``reference`` each fidelity reports:

* ``outcome_agreement``: the fraction of designs whose traversal count equals the reference's
  (what the environment rewards), and ``outcome_label_agreement`` (same outcome name too);
* ``detach_time_error`` / ``detach_angle_error``: median, 95th percentile and largest absolute
  error in the first swing's detach time (s) and frame angle (deg), over designs where both
  detach;
* ``wall_per_design`` (s), ``wall_per_sim_second`` (s of wall time per simulated second),
  ``realtime_factor`` (simulated seconds per wall second) and ``speedup_vs_reference``.

``check_reference=True`` adds ``reference/2``: the reference preset at half its step and twice
its iterations, the test of the claim that refining further no longer changes the outcome or
the first detach time. It also reports, per fidelity, ``outcome_agreement_converged``: the
agreement over the designs whose traversal count ``reference`` and ``reference/2`` agree on
(``converged_designs``). A design on an outcome boundary, where a change of step decides the
count at any step size, has no right answer to agree with; it is left out of that figure.

Each agreement comes with its 95 % interval (``*_interval``, :mod:`.intervals`): on a few dozen
designs one design moves the column by a point or more, and the interval says which targets the
sample can tell apart.

``near`` (``--near CONFIG --spread S``) draws the designs in a box of ±S of each action range
around that config's design instead of over the whole box (:func:`.designs.draw_designs`): where
tuners spend their time once a design works. Random designs over the whole box mostly fail at the
first transfer, so agreement on them alone flatters every rung.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..config import DEFAULT_FIDELITY, FIDELITY_PRESETS, Config, ConfigError
from ..files import save_figure
from ..intervals import interval_text, wilson_interval
from ..physics.kernels import load_kernels
from ..simulation import simulate
from .designs import DesignSample, check_counts, draw_designs, median_time

REFERENCE = "reference"
REFINED = "reference/2"


@dataclass
class FidelityRuns:
    """One fidelity's runs of the sample, in design order."""

    name: str
    model: str
    dt: float
    iterations: int
    substeps: int
    traversals: list = field(default_factory=list)
    outcomes: list = field(default_factory=list)
    t_detach: list = field(default_factory=list)  # first swing, s (NaN: no detach)
    theta1_detach: list = field(default_factory=list)  # deg
    sim_time: list = field(default_factory=list)
    wall: list = field(default_factory=list)  # median wall time per design, s


def fidelity_overrides(name: str) -> dict:
    """Overrides that put a config at fidelity ``name`` (``reference/2`` refines the reference)."""
    if name == REFINED:
        ref = FIDELITY_PRESETS[REFERENCE]
        return {"sim.fidelity": REFERENCE, "sim.dt": ref["dt"] / 2, "sim.iterations": ref["iterations"] * 2}
    if name not in FIDELITY_PRESETS:
        raise ConfigError(f"--fidelities: {name!r} is not a fidelity; allowed {list(FIDELITY_PRESETS)}")
    return {"sim.fidelity": name}


def _first_detach(swings) -> tuple[float, float]:
    s = swings[0] if swings else None
    if s is None or s.t_detach is None:
        return math.nan, math.nan
    return s.t_detach, s.theta1_detach_deg


def run_fidelity(sample: DesignSample, name: str, repeats: int, on_design=None) -> FidelityRuns:
    """Every design of ``sample`` at fidelity ``name``; ``on_design(name, done, total)`` after each design
    (after the whole batch for ``reduced``)."""
    over = fidelity_overrides(name)
    cfgs = [c.replace(over) for c in sample.configs]
    sim = cfgs[0].sim
    runs = FidelityRuns(name, sim.model, sim.dt, sim.iterations, sim.substeps)
    if sim.model == "reduced":
        from ..models.reduced import compile_kernels, simulate_batch

        compile_kernels()  # its one-time compile or load is no rung's cost per design
        wall, res = median_time(lambda: simulate_batch(cfgs), repeats)
        runs.traversals = [int(x) for x in res.traversals]
        runs.outcomes = [str(x) for x in res.outcome]
        runs.t_detach = [float(x) for x in res.t_detach]
        runs.theta1_detach = [float(x) for x in res.theta1_detach_deg]
        runs.sim_time = [float(x) for x in res.sim_time]
        runs.wall = [wall / len(cfgs)] * len(cfgs)
        if on_design:
            on_design(name, len(cfgs), len(cfgs))
        return runs
    load_kernels()  # the pymunk world's compiled parts: their one-time load is no design's cost either
    for i, cfg in enumerate(cfgs):
        wall, r = median_time(lambda: simulate(cfg), repeats)
        t, th = _first_detach(r.swings)
        runs.traversals.append(r.traversals)
        runs.outcomes.append(r.outcome)
        runs.t_detach.append(t)
        runs.theta1_detach.append(th)
        runs.sim_time.append(r.sim_time)
        runs.wall.append(wall)
        if on_design:
            on_design(name, i + 1, len(cfgs))
    return runs


def _errors(a: list, b: list) -> dict:
    x, y = np.asarray(a, float), np.asarray(b, float)
    both = np.isfinite(x) & np.isfinite(y)
    err = np.abs(x[both] - y[both])
    if not err.size:
        return dict(median=None, p95=None, max=None, compared=0)
    return dict(median=float(np.median(err)), p95=float(np.percentile(err, 95)), max=float(err.max()),
                compared=int(both.sum()))


def summarise(runs: FidelityRuns, ref: FidelityRuns, converged: list[int] | None = None) -> dict:
    """One fidelity's row; ``converged``: the designs whose count the refined reference confirms."""
    n = len(runs.traversals)
    wall, sim_time = float(np.sum(runs.wall)), float(np.sum(runs.sim_time))
    ref_wall = float(np.sum(ref.wall))
    same = sum(a == b for a, b in zip(runs.traversals, ref.traversals))
    return dict(
        name=runs.name, model=runs.model, dt=runs.dt, iterations=runs.iterations, substeps=runs.substeps,
        outcome_agreement=same / n, outcome_agreement_interval=list(wilson_interval(same, n)),
        outcome_label_agreement=sum(a == b and c == d for a, b, c, d in
                                    zip(runs.traversals, ref.traversals, runs.outcomes, ref.outcomes)) / n,
        disagreements=[dict(design=i, traversals=a, reference=b, outcome=o, reference_outcome=ro)
                       for i, (a, b, o, ro) in enumerate(zip(runs.traversals, ref.traversals, runs.outcomes,
                                                             ref.outcomes)) if a != b],
        detach_time_error=_errors(runs.t_detach, ref.t_detach),
        detach_angle_error=_errors(runs.theta1_detach, ref.theta1_detach),
        wall_per_design=wall / n,
        wall_per_sim_second=wall / sim_time if sim_time > 0 else None,
        realtime_factor=sim_time / wall if wall > 0 else None,
        speedup_vs_reference=ref_wall / wall if wall > 0 else None,
        mean_traversals=float(np.mean(runs.traversals)),
    ) | ({} if converged is None else _converged_agreement(runs, ref, converged))


def _converged_agreement(runs: FidelityRuns, ref: FidelityRuns, converged: list[int]) -> dict:
    """The agreement over the converged designs, and its 95 % interval (None: no design converged)."""
    if not converged:
        return dict(outcome_agreement_converged=None, outcome_agreement_converged_interval=None)
    same = sum(runs.traversals[i] == ref.traversals[i] for i in converged)
    return dict(outcome_agreement_converged=same / len(converged),
                outcome_agreement_converged_interval=list(wilson_interval(same, len(converged))))


def accuracy(cfg: Config, designs: int = 50, seed: int = 0, repeats: int = 3, fidelities=None,
             check_reference: bool = False, progress=None, on_design=None, near: Config | None = None,
             spread: float = 0.1, near_name: str | None = None) -> dict:
    """The accuracy/time table of ``fidelities`` (default: the whole ladder) on ``designs`` designs (uniform,
    or within ±``spread`` of ``near``'s design); ``progress(name, runs)`` after each fidelity,
    ``on_design(name, done, total)`` after each design."""
    check_counts(designs=designs, repeats=repeats)
    names = list(fidelities or FIDELITY_PRESETS)
    for name in names:
        fidelity_overrides(name)
    if REFERENCE not in names:
        names.append(REFERENCE)
    if check_reference and REFINED not in names:
        names.append(REFINED)
    sample = draw_designs(cfg, designs, seed, near, spread)
    runs = {}
    for name in names:
        runs[name] = run_fidelity(sample, name, repeats, on_design)
        if progress:
            progress(name, runs[name])
    ref = runs[REFERENCE]
    converged = None
    if check_reference:
        converged = [i for i, (a, b) in enumerate(zip(ref.traversals, runs[REFINED].traversals)) if a == b]
    rows = [summarise(runs[n], ref, converged) for n in names]
    out = dict(default=DEFAULT_FIDELITY, designs=designs, seed=seed, repeats=repeats, frames=cfg.scene.frames,
               sample=("uniform" if near is None else f"near {near_name or 'a design'} ±{spread:g}"),
               fidelities=rows,
               reference_outcomes={o: ref.outcomes.count(o) for o in sorted(set(ref.outcomes))})
    if check_reference:
        out["reference_converged"] = reference_convergence(runs[REFERENCE], runs[REFINED])
        out["converged_designs"] = len(converged)
    return out


# The reference counts as converged when refining it (half the step, twice the iterations) keeps
# the traversal count of at least 99 % of the designs and moves the median first detach by at most
# one default step. Not 100 %: about 1 % of random designs sit on an outcome boundary, where a
# 31 µs change of step decides the count at any step size (docs/fidelity.md, "The ladder, measured").
CONVERGED_AGREEMENT = 0.99
CONVERGED_DETACH_S = FIDELITY_PRESETS[DEFAULT_FIDELITY]["dt"]


def reference_convergence(ref: FidelityRuns, refined: FidelityRuns) -> dict:
    agree = sum(a == b for a, b in zip(ref.traversals, refined.traversals)) / len(ref.traversals)
    t_err = _errors(ref.t_detach, refined.t_detach)
    return dict(outcome_agreement=agree, detach_time_error=t_err, tolerance_agreement=CONVERGED_AGREEMENT,
                tolerance_s=CONVERGED_DETACH_S,
                converged=bool(agree >= CONVERGED_AGREEMENT and (t_err["median"] or 0.0) <= CONVERGED_DETACH_S))


def table(report: dict) -> str:
    conv_col = "converged_designs" in report
    # the interval belongs to the headline column: conv. where the reference was checked, agree otherwise
    head = (f"{'fidelity':>12} {'model':>7} {'dt ms':>7} {'iter':>4} {'s/design':>9} {'x real':>7} "
            f"{'x ref':>7} {'agree':>6}" + (f" {'conv.':>6}" if conv_col else "") + f" {'95% CI':>11}"
            f" {'t_det err ms (med/p95)':>23} {'th_det err deg':>15}")
    interval_key = "outcome_agreement_converged_interval" if conv_col else "outcome_agreement_interval"
    lines = [f"{report['designs']} designs ({report.get('sample', 'uniform')}, seed {report['seed']}), "
             f"{report['frames']} frames, median of {report['repeats']} runs each; default fidelity: "
             f"{report['default']}", head]
    for r in report["fidelities"]:
        te, ae = r["detach_time_error"], r["detach_angle_error"]
        terr = "-" if te["median"] is None else f"{te['median'] * 1e3:.2f} / {te['p95'] * 1e3:.2f}"
        aerr = "-" if ae["median"] is None else f"{ae['median']:.2f} / {ae['p95']:.2f}"
        mark = "*" if r["name"] == report["default"] else " "
        lines.append(f"{r['name'] + mark:>12} {r['model']:>7} {r['dt'] * 1e3:7.4f} {r['iterations']:>4} "
                     f"{r['wall_per_design']:9.4f} {r['realtime_factor']:7.1f} {r['speedup_vs_reference']:7.1f} "
                     f"{100 * r['outcome_agreement']:5.1f}%" + (f" {_percent(r['outcome_agreement_converged'])}"
                                                                if conv_col else "") +
                     f" {_interval(None if tautology(r['name'], conv_col) else r[interval_key])}"
                     f" {terr:>23} {aerr:>15}")
    conv = report.get("reference_converged")
    if conv:
        te = conv["detach_time_error"]
        lines.append(f"reference vs reference/2: {100 * conv['outcome_agreement']:.1f}% same traversals (tolerance "
                     f">= {100 * conv['tolerance_agreement']:.0f}%), first detach median {1e3 * (te['median'] or 0):.3f} "
                     f"ms apart (tolerance {1e3 * conv['tolerance_s']:.2f} ms): "
                     f"{'converged' if conv['converged'] else 'NOT converged'}")
        lines.append(f"conv.: agreement over the {report['converged_designs']} of {report['designs']} designs whose "
                     f"traversal count reference and reference/2 agree on")
    lines.append(f"95% CI: the Wilson interval of the {'conv.' if conv_col else 'agree'} column, the agreements this "
                 f"sample cannot rule out (none where a row agrees by construction)")
    return "\n".join(lines)


def _percent(x: float | None) -> str:
    return f"{'-':>6}" if x is None else f"{100 * x:5.1f}%"


def tautology(name: str, conv_col: bool) -> bool:
    """Whether a row's headline agreement is 100 % by construction: the reference against itself, and its
    refinement over the designs chosen for agreeing with it."""
    return name == REFERENCE or (conv_col and name == REFINED)


def _interval(bounds: list | None) -> str:
    return f"{interval_text(bounds):>11}"


def plot_pareto(report: dict, path: str) -> None:
    """Outcome agreement against wall time per design: the accuracy/time Pareto front."""
    import matplotlib.pyplot as plt

    fig = pareto_figure(report)
    try:
        save_figure(fig, path)
    finally:
        plt.close(fig)


def pareto_figure(report: dict):
    """:func:`plot_pareto`'s figure, laid out and labelled, not saved."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = report["fidelities"]
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    xs = [r["wall_per_design"] for r in rows]
    ys = [100 * r["outcome_agreement"] for r in rows]
    front = sorted((x, y) for x, y in zip(xs, ys))
    best, pareto = -1.0, []
    for x, y in front:
        if y > best:
            pareto.append((x, y))
            best = y
    ax.step(*zip(*pareto), where="post", color="0.6", lw=1, zorder=1, label="Pareto front")
    labels = []
    for r, x, y in zip(rows, xs, ys):
        default = r["name"] == report["default"]
        ax.scatter([x], [y], s=60 if default else 30, color="C3" if default else "C0", zorder=2)
        # the 100 % row sits under the top of the axes: its labels go below the points, the others above
        step = -11 if y > 97 else 11
        labels.append((ax.annotate(r["name"] + (" (default)" if default else ""), (x, y), textcoords="offset points",
                                   xytext=(5, -12 if step < 0 else 5), fontsize=8), step))
    ax.set_xscale("log")
    ax.set_xlabel("wall time per design (s, log)")
    ax.set_ylabel("same traversal count as reference (%)")
    ax.set_title(f"Accuracy vs time: {report['designs']} random designs, {report['frames']} frames", fontsize=10)
    ax.set_ylim(min(ys) - 5, 101)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()  # room for the labels first: moving them down and up below keeps their widths
    _separate_labels(fig, labels)
    return fig


def _separate_labels(fig, labels: list) -> None:
    """Move each (annotation, step) ``step`` points further from its point until it overlaps no label before it:
    fidelities a few ms apart (mbd, mbd-fine) printed their names on top of each other. Measured in display
    coordinates, so after the layout."""
    renderer = fig.canvas.get_renderer()
    placed = []
    for ann, step in labels:
        dx, dy = ann.xyann
        # 2n + 1 tries suffice: a label shorter than a step overlaps at most two positions of another point's column
        for k in range(2 * len(labels) + 1):
            ann.xyann = (dx, dy + k * step)
            box = ann.get_window_extent(renderer)
            if not any(box.overlaps(other) for other in placed):
                break
        placed.append(box)
