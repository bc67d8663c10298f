"""A map's hold-out share against its training budget: is a map's shortfall its form or its budget?

    python benchmarks/map_budgets.py [--task hard] [--kinds linear,mlp] [--budgets 4096,16384,40960,163840]
                                     [--seeds 0-9] [--holdout 200] [--holdout-seed 0] [--json]

Each map is fitted as ``benchmarks/rl_policies.py`` fits the shipped ones (:func:`agents.context_maps.fit_map`:
CMA-ES at ``reduced`` from the task's start, 64 fresh contexts a generation), once per seed, up to the largest
budget; the map after the last generation within each smaller budget is the map a fit with that budget returns
(the same seed and the same contexts), so one fit gives every budget's map. Seed k's generations draw episode seeds
:data:`BUDGET_BASE` ``+ 20,000·k`` onward: above every shipped method's training contexts (below 10^5), below the
watch and hold-out sets, so no seed shares a context with another or with the scores. Every map is scored at ``mbd``
on the hold-out contexts of ``--holdout-seed`` (as ``benchmarks/rl_vs_tuning.py`` scores), with the mean whole-row
share and its interval from a bootstrap over seeds, then contexts; the wall column is the fit's own time at that
budget (median over seeds).
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from aero_env.intervals import seeds_then_contexts

from rl_holdout import TASKS, holdout_seeds, single_action
from rl_policies import parse_seeds
from rl_vs_tuning import pct_ci

BUDGET_BASE = 200_000  # the budget study's training contexts: 200,000-399,999 (seed k: 20,000 of them from here)
BUDGET_BLOCK = 20_000
BUDGET_SEEDS = 10  # seeds 0-9, a block each
KINDS = ("linear", "mlp")


def has_a_generation(kind: str, space, budget: int) -> bool:
    """Whether ``budget`` episodes hold one CMA-ES generation of a ``kind`` map (64 contexts x its population)."""
    from agents.context_maps import map_seed_span

    first, last = map_seed_span(kind, space.dim, space.obs_dim, 0, budget)
    return last >= first


def check_seeds(prog: str, seeds: list[int]) -> None:
    """Seeds 0-9 only: each draws its own block of the budget study's contexts; refused in one line."""
    if max(seeds) > BUDGET_SEEDS - 1:
        top = BUDGET_BASE + BUDGET_SEEDS * BUDGET_BLOCK - 1
        sys.exit(f"{prog}: --seeds {max(seeds)}: at most {BUDGET_SEEDS - 1} (each seed's contexts are its own block "
                 f"of {BUDGET_BLOCK:,} in the budget study's {BUDGET_BASE:,}-{top:,})")


def check_block(prog: str, option: str, kind: str, space, budget: int) -> None:
    """A ``kind`` fit of ``budget`` episodes must draw its contexts within a seed's block; refused in one line."""
    from agents.context_maps import map_seed_span

    first, last = map_seed_span(kind, space.dim, space.obs_dim, 0, budget)
    if last - first + 1 > BUDGET_BLOCK:
        sys.exit(f"{prog}: {option} {budget}: a {kind} fit would draw {last - first + 1} contexts, past a seed's "
                 f"block of {BUDGET_BLOCK}")


def map_at_budgets(runner, kind: str, seed: int, budgets: list[int], start,
                   sigma: float | None = None) -> dict[int, tuple[np.ndarray, float, int]]:
    """Each budget's map (its parameters), the fit's wall time up to it and the episodes it spent, from one fit to
    the largest budget; a budget below one generation has none. ``sigma``: CMA-ES's first step (default the
    shipped maps')."""
    from agents.context_maps import MAP_STEP, fit_map

    budgets = [b for b in budgets if has_a_generation(kind, runner.space, b)]
    got: dict[int, tuple[np.ndarray, float, int]] = {}
    if not budgets:
        return got
    t0 = time.perf_counter()
    per_generation: list[int] = []

    def seen(used: int, params: np.ndarray) -> None:
        per_generation.append(used)
        for b in budgets:
            if used <= b < used + per_generation[0]:  # the last generation within budget b
                got[b] = (params.copy(), time.perf_counter() - t0, used)

    fit_map(runner, kind, seed, max(budgets), start=start, first_context=BUDGET_BASE + BUDGET_BLOCK * seed,
            on_generation=seen, sigma=MAP_STEP if sigma is None else sigma)
    return got


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--task", default="hard", choices=tuple(TASKS))
    ap.add_argument("--kinds", default=",".join(KINDS), help=f"comma-separated, of {', '.join(KINDS)}")
    ap.add_argument("--budgets", default="4096,16384,40960,163840", help="training episodes, comma-separated")
    ap.add_argument("--seeds", default="0-9", help="fitting seeds, 0-9 or 0,2,5")
    ap.add_argument("--holdout", type=int, default=200)
    ap.add_argument("--holdout-seed", type=int, default=0)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    kinds = args.kinds.split(",")
    if any(k not in KINDS for k in kinds):
        sys.exit(f"map_budgets: --kinds {args.kinds!r}: allowed {', '.join(KINDS)}")
    try:
        budgets = sorted({int(b) for b in args.budgets.split(",")})
        seeds = parse_seeds(args.seeds)
    except ValueError:
        sys.exit(f"map_budgets: --budgets {args.budgets!r} / --seeds {args.seeds!r}: give whole numbers, e.g. "
                 f"4096,40960 and 0-9")
    check_seeds("map_budgets", seeds)
    if args.holdout < 1 or args.holdout_seed < 0:
        sys.exit(f"map_budgets: --holdout {args.holdout} / --holdout-seed {args.holdout_seed}: at least 1 and 0")
    from aero_env.config import load_config
    from agents.context_maps import ParamMap
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    task = TASKS[args.task]
    fast = EpisodeRunner(load_config(task.config, {"sim.fidelity": "reduced"}))
    for kind in kinds:  # every fit's contexts inside its seed's block
        if not has_a_generation(kind, fast.space, budgets[0]):
            sys.exit(f"map_budgets: --budgets {budgets[0]}: too few for one CMA-ES generation of a {kind} map (64 "
                     f"contexts x its population)")
        check_block("map_budgets", "--budgets", kind, fast.space, budgets[-1])
    runner = EpisodeRunner(load_config(task.config))
    rows = []
    try:
        draws = draws_for_seeds(runner.space, holdout_seeds(args.holdout_seed, args.holdout))
        obs = runner.observations(draws)
        start = single_action(fast.space, task)
        for kind in kinds:
            fits = [map_at_budgets(fast, kind, seed, budgets, start) for seed in seeds]
            for b in budgets:
                whole = []
                for fit in fits:
                    m = ParamMap(kind, runner.space.obs_dim, runner.space.dim, params=fit[b][0])
                    whole.append(runner.whole_rows(draws, m.act(obs)))
                whole = np.array(whole)
                mean, ci = seeds_then_contexts(whole)
                rows.append(dict(kind=kind, budget=b, seeds=len(seeds), mean=mean, ci=ci,
                                 per_seed=[float(w.mean()) for w in whole],
                                 fit_wall_s=float(np.median([fit[b][1] for fit in fits])),
                                 outcomes=whole.astype(int).tolist()))
    finally:
        runner.close()
        fast.close()
    rep = dict(task=task.name, config=task.config, holdout=args.holdout, holdout_seed=args.holdout_seed, rows=rows)
    if args.json:
        print(json.dumps(rep, indent=1))
        return
    print(f"{task.config}: maps fitted at reduced from {task.single or 'the box centre'}, scored at mbd on "
          f"{args.holdout} hold-out contexts (--holdout-seed {args.holdout_seed}), {len(seeds)} seeds")
    print("| map | training episodes | fit wall (median) | whole row: mean [95 % CI] | seeds: lowest-highest |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['kind']} | {r['budget']} | {r['fit_wall_s']:.0f} s | {pct_ci(r['mean'], r['ci'])} | "
              f"{100 * min(r['per_seed']):.1f}-{100 * max(r['per_seed']):.1f} % |")


if __name__ == "__main__":
    main()
