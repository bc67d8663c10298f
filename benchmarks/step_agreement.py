"""Which step and solver iterations the default rung would need to agree with the reference.

``aero-env bench accuracy`` measures the ladder's named rungs; this asks the question behind the
default one: over uniformly random designs (the env's whole action box), how often does a given
step ``dt`` and solver ``iterations`` give the reference's traversal count, and at what cost? Each
design runs at ``reference`` and ``reference/2`` (half the step, twice the iterations): the
designs whose count those two agree on are the *converged* ones, and each setting's agreement is
taken over them, as ``bench accuracy``'s ``conv.`` column. Every setting runs the same designs;
the designs run in ``--jobs`` processes (each run is a function of its config alone, so the jobs
change only the time).

Each agreement comes with its 95 % Wilson interval (:mod:`aero_env.intervals`): the agreements the
sample cannot rule out, which is what decides whether a setting meets a target such as 99 %.

Beside the table, each converged design that some setting gets wrong is listed with its count at
every setting: a design whose count jumps back and forth as the step shrinks is chaotic there (a
catch decided by a hair), one that is wrong at 30 iterations and right at 120 at every step is
limited by the solver's iterations, one that turns right below some step by the step.

``--near CONFIG --spread S`` draws the designs around that config's design instead, as ``bench
accuracy --near`` does (the same sample for the same seed): there a setting meets the close calls a
tuner meets.

    python benchmarks/step_agreement.py --designs 200 --seed 11 --jobs 2
    python benchmarks/step_agreement.py --settings 0.5/30,0.5/120,0.25/60 --json
    python benchmarks/step_agreement.py --designs 100 --seed 4 --near configs/paper.yaml --spread 0.15 --settings 1/30,0.5/30
    python benchmarks/step_agreement.py --designs 300 --seed 21 --near configs/paper.yaml --spread 0.15 --only 28,42 --settings 0.5/120
    python benchmarks/step_agreement.py --designs 300 --seed 21 --near configs/paper.yaml --spread 0.15 --builds 8

``--builds K`` asks where the misses fall: each design is also built K times within the maker's tolerances (the
builds ``aero-env robustness --draws K --seed S`` draws for it, ``S`` from ``--builds-seed``, robustness's own default
unless given) at the config's own fidelity, and each
setting's agreement is split into the converged designs whose count every build keeps (*robust*: a maker who cuts
it gets that count) and the rest (*fragile*: the card's tolerances already decide its count, whatever the step).
``--builds-at FIDELITY`` runs the builds at another rung, e.g. the reference, so that which designs count as robust
does not rest on the rung being judged.

A setting named ``reduced`` is the reduced model's rung (its preset), on the same designs and builds; ``reduced/DT_MS``
is the same model at another step (``reduced/0.5``: 0.5 ms, an eighth of its preset's 4 ms), which asks whether its
misses are its step's. Every setting is
timed one design per call; the reduced model's batch (``bench accuracy``, ``bench throughput``) is several times
cheaper per design than that.

``--only I,J`` runs only those designs of the sample (their indices in a whole run's list), to look at a few of
them at more settings than a whole sample can afford.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from aero_env.bench.accuracy import REFERENCE, REFINED, fidelity_overrides  # noqa: E402
from aero_env.bench.designs import draw_designs  # noqa: E402
from aero_env.config import FIDELITY_PRESETS, ConfigError, load_config  # noqa: E402
from aero_env.intervals import interval_text, wilson_interval  # noqa: E402
from aero_env.models import reduced  # noqa: E402
from aero_env.physics.kernels import load_kernels  # noqa: E402
from aero_env.robustness.command import DEFAULT_SEED  # noqa: E402
from aero_env.robustness.study import draw_builds  # noqa: E402
from aero_env.robustness.tolerances import DEFAULT_TOLERANCES, check_against  # noqa: E402
from aero_env.simulation import simulate  # noqa: E402

DEFAULT_SETTINGS = "0.5/30,0.5/60,0.5/120,0.25/30,0.25/60,0.125/30,0.125/120"


def parse_settings(text: str) -> list:
    """``"0.5/30,0.25/60"`` -> [(0.0005 s, 30), (0.00025 s, 60)]; ``reduced`` -> ("reduced", None), that rung (the
    compiled reduced model at its preset), ``reduced/0.5`` -> ("reduced", 0.0005 s), that model at another step; a
    bad entry is one line naming it."""
    out = []
    for item in text.split(","):
        if item == "reduced":
            out.append(("reduced", None))
            continue
        if item.startswith("reduced/"):
            try:
                dt = float(item[len("reduced/"):]) / 1e3
            except ValueError:
                dt = math.nan
            if not 1e-5 <= dt <= 0.004:  # (NaN fails it too) down to 10 us, up to the preset's 4 ms
                raise ConfigError(f"--settings: {item!r}: the reduced model's step must be in [0.01, 4] ms, e.g. "
                                  f"reduced/0.5")
            out.append(("reduced", dt))
            continue
        try:
            dt_ms, iterations = item.split("/")
            dt, it = float(dt_ms) / 1e3, int(iterations)
        except ValueError:
            raise ConfigError(f"--settings: {item!r} must be DT_MS/ITERATIONS (e.g. 0.5/30), reduced or "
                              f"reduced/DT_MS") from None
        if not (0.0 < dt <= 0.002 and 1 <= it <= 1000):
            raise ConfigError(f"--settings: {item!r}: the step must be in (0, 2] ms and the iterations in [1, 1000]")
        out.append((dt, it))
    return out


def setting_name(setting) -> str:
    """A setting's column name: ``reduced``, ``reduced/DT_MS`` or ``DT_MS/ITERATIONS``."""
    if setting[0] == "reduced":
        return "reduced" if setting[1] is None else f"reduced/{setting[1] * 1e3:g}"
    return f"{setting[0] * 1e3:g}/{setting[1]}"


def setting_overrides(setting) -> dict:
    """What a setting sets in each design's config: the reduced rung's preset, or the pymunk world's step and
    iterations with one pymunk step per runner step."""
    if setting[0] == "reduced":
        step = {} if setting[1] is None else {"sim.dt": setting[1]}
        return {**fidelity_overrides("reduced"), **step}
    dt, iterations = setting
    return {"sim.dt": dt, "sim.iterations": iterations, "sim.substeps": 1}


BUILD = "build"  # the work items of --builds: (i, "build", k)


def _run(job) -> tuple[int, str, int | None, float]:
    """One design at one setting: its traversal count (None: a build the world cannot assemble) and wall time."""
    i, name, cfg = job
    load_kernels()  # once per process, untimed
    if cfg is not None and cfg.sim.model == "reduced":
        reduced.compile_kernels()  # likewise: loaded from numba's cache once per process, untimed
    t0 = time.perf_counter()
    try:
        traversals = None if cfg is None else simulate(cfg).traversals
    except ConfigError:  # an invalid build, as aero-env robustness counts it: never one that keeps the count
        traversals = None
    return i, name, traversals, time.perf_counter() - t0


def tolerance_builds(sample, indices, builds: int, seed: int, fidelity: str | None = None) -> list:
    """The work of --builds: each design's nominal run and the ``builds`` builds ``aero-env robustness --draws builds
    --seed seed`` draws for it (its default table), all at ``fidelity`` (None: the config's own). A build the config
    rejects has no config (an invalid build)."""
    work = []
    for i in indices:
        cfg = sample.configs[i] if fidelity is None else sample.configs[i].replace(fidelity_overrides(fidelity))
        check_against(cfg, DEFAULT_TOLERANCES)
        work.append((i, "nominal", cfg))
        work += [(i, f"{BUILD} {k}", b.config) for k, b in enumerate(draw_builds(cfg, DEFAULT_TOLERANCES, builds,
                                                                                    seed)[1])]
    return work


def step_agreement(config: str, designs: int, seed: int, settings: list, jobs: int,
                   near: str | None = None, spread: float = 0.1, only: list[int] | None = None,
                   builds: int = 0, builds_at: str | None = None, builds_seed: int = DEFAULT_SEED) -> dict:
    base = load_config(config)
    sample = draw_designs(base, designs, seed, near=None if near is None else load_config(near), spread=spread)
    names = {setting_name(setting): setting_overrides(setting) for setting in settings}
    rungs = {REFERENCE: fidelity_overrides(REFERENCE), REFINED: fidelity_overrides(REFINED), **names}
    # --only: these designs of the sample, by their index in it (the same designs a whole run lists)
    indices = range(designs) if only is None else only
    work = [(i, name, sample.configs[i].replace(over)) for name, over in rungs.items() for i in indices]
    if builds:
        work += tolerance_builds(sample, indices, builds, builds_seed, builds_at)
    counts: dict[str, list] = {name: [None] * designs for name in rungs}
    walls: dict[str, float] = {name: 0.0 for name in rungs}
    built: dict[int, dict] = {i: {} for i in indices}  # --builds: design -> {"nominal" or "build k": count}
    with ProcessPoolExecutor(jobs) as pool:
        for i, name, traversals, wall in pool.map(_run, work, chunksize=8):
            if name in counts:
                counts[name][i] = traversals
                walls[name] += wall
            else:
                built[i][name] = traversals
    ref = counts[REFERENCE]
    converged = [i for i in indices if ref[i] == counts[REFINED][i]]
    if not converged:
        raise ConfigError(f"no converged design: reference and reference/2 disagree on all {len(indices)} run; "
                          f"draw more designs")
    # --builds: a converged design is robust when every build keeps its nominal count (an invalid build, None, never
    # does; nor does anything, when the nominal run itself is invalid)
    robust = [i for i in converged if builds and built[i]["nominal"] is not None and
              all(c == built[i]["nominal"] for c in built[i].values())]
    groups = {"converged": converged} | ({"robust": robust, "fragile": [i for i in converged if i not in robust]}
                                         if builds else {})
    rows = []
    for name in rungs:
        row = dict(setting=name)
        for group, members in groups.items():
            right = sum(counts[name][i] == ref[i] for i in members)
            row[f"agreement_{group}"] = right / len(members) if members else None
            row[f"agreement_{group}_interval_95"] = (None if name in (REFERENCE, REFINED) or not members else
                                                     list(wilson_interval(right, len(members))))
        rows.append(row | dict(wall_per_design=walls[name] / len(indices),
                               speedup_vs_reference=walls[REFERENCE] / walls[name],
                               wrong=[i for i in converged if counts[name][i] != ref[i]]))
    missed = sorted({i for r in rows for i in r["wrong"]})
    return dict(config=config, designs=designs, seed=seed, jobs=jobs, only=only, converged_designs=len(converged),
                builds=builds, builds_at=(builds_at or base.sim.fidelity) if builds else None,
                builds_seed=builds_seed if builds else None, robust_designs=robust if builds else None,
                rows=rows,
                sample="uniform" if near is None else f"near {near} ±{spread:g}", reference_counts=ref,
                missed={i: {name: counts[name][i] for name in rungs} for i in missed})


def table(rep: dict) -> str:
    which = f"{rep['designs']} designs" if rep["only"] is None else f"designs {_indices(rep['only'])} of {rep['designs']}"
    groups = ("converged", "robust", "fragile") if rep["builds"] else ("converged",)
    lines = [f"{which} of {rep['config']} ({rep['sample']}, seed {rep['seed']}); agreement with the reference "
             f"over the {rep['converged_designs']} whose count reference/2 confirms"]
    if rep["builds"]:
        lines.append(f"robust: the {len(rep['robust_designs'])} of them that keep their count in all {rep['builds']} "
                     f"builds within the maker's tolerances (aero-env robustness's table, seed {rep['builds_seed']}) at "
                     f"{rep['builds_at']}; "
                     f"fragile: the other {rep['converged_designs'] - len(rep['robust_designs'])}")
    head = {"converged": "agree", "robust": "robust", "fragile": "fragile"}
    lines.append(f"{'dt ms/iter':>12}" + "".join(f" {head[g]:>7} {'95% CI':>11}" for g in groups) +
                 f" {'s/design':>9} {'x ref':>6}")
    for r in rep["rows"]:
        lines.append(f"{r['setting']:>12}" + "".join(
            f" {_percent(r[f'agreement_{g}'])} {interval_text(r[f'agreement_{g}_interval_95']):>11}" for g in groups) +
            f" {r['wall_per_design']:9.4f} {r['speedup_vs_reference']:6.1f}")
    if rep["missed"]:
        names = list(next(iter(rep["missed"].values())))
        lines += ["", "converged designs some setting gets wrong: the traversal count at each", "design " +
                  " ".join(f"{n:>11}" for n in names)]
        for i, row in rep["missed"].items():
            lines.append(f"{i:>6} " + " ".join(f"{row[n]:>11}" for n in names))
    return "\n".join(lines)


def _percent(x: float | None) -> str:
    return f"{'-':>7}" if x is None else f"{100 * x:6.1f}%"


def _indices(only: list[int]) -> str:
    return ",".join(str(i) for i in only)


def parse_only(text: str | None, designs: int) -> list[int] | None:
    """``"28,42"`` -> [28, 42]: designs of the drawn sample by index; a bad one is one line naming it."""
    if text is None:
        return None
    try:
        only = [int(x) for x in text.split(",")]
    except ValueError:
        raise ConfigError(f"--only {text!r}: design indices separated by commas, e.g. 28,42") from None
    bad = [i for i in only if not 0 <= i < designs]
    if bad or len(set(only)) != len(only):
        raise ConfigError(f"--only {text!r}: each index once, in [0, {designs - 1}] for --designs {designs}")
    return only


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("config", nargs="?", default="configs/paper.yaml")
    ap.add_argument("--designs", type=int, default=200, help="designs, uniform from the action box unless --near "
                    "(default: 200)")
    ap.add_argument("--seed", type=int, default=11, help="seed of the design draw (default: 11)")
    ap.add_argument("--settings", default=DEFAULT_SETTINGS, help=f"DT_MS/ITERATIONS,..., reduced (the reduced "
                    f"model's rung) or reduced/DT_MS (that model at another step) (default: {DEFAULT_SETTINGS})")
    ap.add_argument("--jobs", type=int, default=1, help="processes (default: 1)")
    ap.add_argument("--near", metavar="CONFIG", help="draw the designs around this config's design")
    ap.add_argument("--spread", type=float, default=0.1, help="with --near: ± this fraction of each action range "
                    "(default: 0.1)")
    ap.add_argument("--only", metavar="I,J,...", help="run only these designs of the sample (their indices in a "
                    "whole run's list), e.g. to see a few of them at more settings")
    ap.add_argument("--builds", type=int, default=0, metavar="K", help="also build each design K times within the "
                    "maker's tolerances (aero-env robustness's default table) at the config's fidelity, and split the "
                    "agreement into the designs whose count every build keeps (robust) and the rest (default: 0, off)")
    ap.add_argument("--builds-seed", type=int, default=DEFAULT_SEED, help="seed of the builds' draws, as aero-env "
                    f"robustness --seed (default: {DEFAULT_SEED}, robustness's own; must differ from --seed)")
    ap.add_argument("--builds-at", metavar="FIDELITY", help="run the builds at this rung (default: the config's "
                    "fidelity, which is what aero-env robustness runs)")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of the table")
    args = ap.parse_args(argv)
    try:
        for option, value in (("--designs", args.designs), ("--jobs", args.jobs)):
            if value < 1:
                raise ConfigError(f"{option} = {value}: must be at least 1")
        if not 0 <= args.builds <= 1000:
            raise ConfigError(f"--builds {args.builds}: allowed 0 (off) to 1000")
        if args.near is None and args.spread != 0.1:
            raise ConfigError(f"--spread {args.spread!r}: only with --near")
        settings = parse_settings(args.settings)
        only = parse_only(args.only, args.designs)
        if args.builds and args.builds_seed == args.seed:
            raise ConfigError(f"--builds-seed {args.builds_seed} equals --seed: the builds would reuse the random numbers "
                              f"that drew the designs; choose another")
        if args.builds_at is not None:
            if not args.builds:
                raise ConfigError(f"--builds-at {args.builds_at}: only with --builds")
            if args.builds_at not in FIDELITY_PRESETS:
                raise ConfigError(f"--builds-at {args.builds_at!r}: not a fidelity; allowed {list(FIDELITY_PRESETS)}")
        rep = step_agreement(args.config, args.designs, args.seed, settings, args.jobs, args.near, args.spread, only,
                             args.builds, args.builds_at, args.builds_seed)
    except ConfigError as exc:
        print(f"step_agreement: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(rep, indent=1) if args.json else table(rep))
    return 0


if __name__ == "__main__":
    sys.exit(main())
