"""``aero-env robustness``: does a design survive being built by hand?

    aero-env robustness CONFIG [--draws N] [--seed S] [--tolerances FILE.yaml] [--workers W] [--json] [--no-progress]
                               [--set KEY=VALUE ...]

The tolerance file is read and checked before anything is simulated, so a bad file (or a bad
count) ends with one line and exit status 2 (``file error:``, ``config error:``, or ``error:`` for an option).
"""

from __future__ import annotations

import json
import time

from ..scene_args import add_seed

DEFAULT_DRAWS = 100
DEFAULT_SEED = 0
DEFAULT_WORKERS = 1


def register(sub, scene_command) -> None:
    rp = scene_command(sub, "robustness", "does a design survive being built by hand? random builds within "
                                          "tolerances, single changes, per-parameter effects")
    rp.add_argument("--draws", type=int, default=DEFAULT_DRAWS, help=f"random builds (default {DEFAULT_DRAWS})")
    add_seed(rp, DEFAULT_SEED, f"seed of the draws (default {DEFAULT_SEED})")
    rp.add_argument("--tolerances", metavar="FILE.yaml",
                    help="a list of {name, relative | absolute, [linked: [keys]], [reason]} replacing the default "
                         "table (aero_env/robustness/tolerances.py)")
    rp.add_argument("--workers", type=int, default=DEFAULT_WORKERS,
                    help=f"processes (a spawn pool when > 1; results do not depend on it; default {DEFAULT_WORKERS})")
    rp.add_argument("--no-progress", action="store_true", help="no progress bar")
    rp.set_defaults(func=cmd_robustness)


def cmd_robustness(args) -> int:
    from ..scene_args import load_scene
    from .report import summarize, table
    from ..bench.designs import check_counts
    from .progress import RunProgress
    from .study import assess
    from .tolerances import DEFAULT_TOLERANCES, check_against, load_tolerances

    check_counts(draws=args.draws, workers=args.workers)
    tols = load_tolerances(args.tolerances) if args.tolerances else DEFAULT_TOLERANCES
    cfg = load_scene(args)
    check_against(cfg, tols)
    start = time.perf_counter()
    progress = RunProgress("robustness", enabled=not args.no_progress)
    try:
        study = assess(cfg, tols, draws=args.draws, seed=args.seed, workers=args.workers, progress=progress)
    finally:
        progress.close()  # an interrupted run's bar ends its line before the one that says so
    report = summarize(study, wall_time=time.perf_counter() - start)
    print(json.dumps(report, indent=2) if args.json else table(report))
    return 0
